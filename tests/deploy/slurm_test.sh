#!/usr/bin/env bash
# tests/deploy/slurm_test.sh SOURCE_DIR BUILD_DIR
#
# Runs deploy/slurm's batch scripts on a real Slurm cluster of one machine: munged with a key of
# its own, slurmctld and slurmd (as root, each in the background) on free ports with a slurm.conf
# written into a temporary directory, touching nothing of the machine's own Slurm or munge. Then
#   - tessera-farm.sbatch with three worker tasks on the one node (TLS and a token made by the
#     job): the image must exist and be identical to the same render on an inproc device, every
#     worker must have served TLS with a token, and stopped gracefully;
#   - tessera-farm.sbatch whose workers cannot start (a bad flag): the job fails at once, shows
#     the workers' error, and removes its private directory;
#   - tessera-frames.sbatch as an array of three tasks over frames 1-5: every frame is written,
#     each task renders its own chunk, and a frame that exists is skipped.
# Skips (exit 77) only where the machine cannot run the daemons: not root, or slurmd refused by
# the kernel (cgroups, process tracking). A missing package fails: deploy/install-deps.sh has them.
set -euo pipefail
source_dir="$(cd "$1" && pwd)"
build_dir="$(cd "$2" && pwd)"

# The render command under test: `tessera render` on its built-in scene, small and few samples.
RENDER_CMD="$build_dir/tools/tessera/tessera"
FRAMES_RENDER_CMD="$RENDER_CMD render"
WORKER="$build_dir/worker/service/tessera-worker"

skip() {
  echo "SKIP: $*"
  exit 77
}
fail() {
  echo "FAIL: $*" >&2
  exit 1
}

if [ "$(id -u)" -ne 0 ]; then
  skip "a Slurm cluster of one machine needs root here: slurmd starts every job step as the" \
    "job's user, and munged and slurmctld run as SlurmUser=root in this test"
fi
for tool in munged mungekey slurmctld slurmd sbatch srun sbcast squeue scancel scontrol sinfo \
  openssl python3; do
  command -v "$tool" >/dev/null || fail "$tool not found: deploy/install-deps.sh installs it"
done
[ -x "$WORKER" ] || fail "no $WORKER: build tessera-worker"
[ -x "$RENDER_CMD" ] || fail "no $RENDER_CMD: build tessera_cli"

# munged wants every directory above its socket searchable by all.
work="$(mktemp -d "${TMPDIR:-/tmp}/tessera-slurm-test.XXXXXX")"
chmod 0755 "$work"
munged_pid="" slurmctld_pid="" slurmd_pid=""
stop() {
  # Jobs first (their steps are slurmd's), then the daemons, by the ids this test started.
  if [ -n "$slurmctld_pid" ]; then
    scancel --user=root 2>/dev/null || true
    for _ in $(seq 50); do
      [ -z "$(squeue --noheader 2>/dev/null)" ] && break
      sleep 0.2
    done
  fi
  for pid in $slurmd_pid $slurmctld_pid $munged_pid; do
    kill -TERM "$pid" 2>/dev/null || true
    wait "$pid" 2>/dev/null || true
  done
  if [ -n "${KEEP_SLURM_TEST_DIR:-}" ]; then
    echo "kept $work"
  else
    rm -rf "$work"
  fi
}
trap stop EXIT
show_logs() {
  for log in "$work"/*.log; do
    echo "---- $log" >&2
    tail -n 30 "$log" >&2
  done
}

# munge: a key of its own and a socket in the test directory.
mkdir -m 0700 "$work/munge"
mungekey --create --keyfile="$work/munge/munge.key" --bits=1024 --force
munged --foreground --socket="$work/munge.socket" --key-file="$work/munge/munge.key" \
  --pid-file="$work/munge/munged.pid" --seed-file="$work/munge/munged.seed" \
  >"$work/munged.log" 2>&1 &
munged_pid=$!
for _ in $(seq 50); do [ -S "$work/munge.socket" ] && break; sleep 0.1; done
[ -S "$work/munge.socket" ] || { show_logs; fail "munged did not start"; }

# Two free TCP ports for slurmctld and slurmd.
read -r ctld_port slurmd_port < <(python3 -c '
import socket
socks = [socket.socket() for _ in range(2)]
for s in socks: s.bind(("127.0.0.1", 0))
print(*(s.getsockname()[1] for s in socks))')
# The node as slurmd sees this machine (CPUs, sockets, cores, memory), named localhost.
node_line="$(slurmd -C | head -n 1 |
  sed 's/^NodeName=[^ ]*/NodeName=localhost NodeAddr=127.0.0.1/')"
mkdir "$work/state" "$work/spool"
cat >"$work/slurm.conf" <<EOF
ClusterName=tessera-test
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$work/munge.socket
CredType=cred/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SwitchType=switch/none
ReturnToService=2
$node_line State=UNKNOWN
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$work/slurm.conf"
slurmctld -D -i -f "$SLURM_CONF" >"$work/slurmctld.out" 2>&1 &
slurmctld_pid=$!
slurmd -D -N localhost -f "$SLURM_CONF" >"$work/slurmd.out" 2>&1 &
slurmd_pid=$!
state=""
for _ in $(seq 150); do
  state="$(sinfo --noheader --format=%T 2>/dev/null || true)"
  [ "$state" = "idle" ] && break
  if ! kill -0 "$slurmctld_pid" 2>/dev/null || ! kill -0 "$slurmd_pid" 2>/dev/null; then break; fi
  sleep 0.2
done
if [ "$state" != "idle" ]; then
  show_logs
  if cat "$work"/slurm*.log "$work"/slurm*.out 2>/dev/null |
    grep -qiE 'cgroup|proctrack|operation not permitted|permission denied'; then
    skip "slurmd or slurmctld could not run on this machine (node state '$state'; logs above)"
  fi
  fail "the one-node cluster did not come up (node state '$state'; logs above)"
fi
echo "cluster up: slurmctld on port $ctld_port, slurmd on $slurmd_port ($node_line)"

export TMPDIR="$work"  # the jobs' private directories go here, so that the test sees them go
export TESSERA_WORKER_BIN="$WORKER"

# ---- tessera-farm.sbatch: three workers on the one node, the render on the first node.
started=$SECONDS
render_args=(render builtin:cornell --spp 2 --width 96 --height 64)
TESSERA_RENDER="$RENDER_CMD" timeout 150 \
  sbatch --wait --export=ALL --nodes=1 --ntasks=3 --overcommit --time=5 \
  --output="$work/farm.out" "$source_dir/deploy/slurm/tessera-farm.sbatch" \
  "${render_args[@]}" --output "$work/farm.png" ||
  { cat "$work/farm.out" >&2 || true; show_logs; fail "tessera-farm.sbatch failed"; }
cat "$work/farm.out"
echo "tessera-farm.sbatch took $((SECONDS - started)) s (sbatch --wait polls)"
[ -s "$work/farm.png" ] || fail "tessera-farm.sbatch wrote no image"
grep -q '^tessera-farm: 3 workers on 1 nodes: localhost:[0-9]*,localhost:[0-9]*,localhost:[0-9]*$' \
  "$work/farm.out" || fail "the job did not start three workers and list them in TESSERA_DEVICES"
grep -q "^tessera-farm: workers stopped (their step's exit status: 0)" "$work/farm.out" ||
  fail "the workers did not stop gracefully (exit 0 on SIGTERM)"
for task in 0 1 2; do
  grep -q "^$task: \[.*\] \[worker\] \[info\] TLS; every call must carry the token$" "$work/farm.out" ||
    fail "worker task $task did not serve TLS with a token"
done
if compgen -G "$work/tessera-job-*" >/dev/null; then
  fail "the job left its private directory behind: $(echo "$work"/tessera-job-*)"
fi
# The same image as on one in-process device: the workers traced it, through TLS and the token.
TESSERA_DEVICES=inproc "$RENDER_CMD" "${render_args[@]}" --output "$work/inproc.png"
cmp "$work/farm.png" "$work/inproc.png" ||
  fail "the farm's image differs from the same render on an inproc device"

# ---- A worker that cannot start fails the job at once, saying why, and leaves nothing behind.
started=$SECONDS
if TESSERA_RENDER="$RENDER_CMD" TESSERA_WORKER_ARGS=--no-such-flag timeout 150 \
  sbatch --wait --export=ALL --nodes=1 --ntasks=2 --overcommit --time=5 \
  --output="$work/farm-fails.out" "$source_dir/deploy/slurm/tessera-farm.sbatch" \
  "${render_args[@]}" --output "$work/never.png"; then
  fail "tessera-farm.sbatch succeeded with workers that cannot start"
fi
cat "$work/farm-fails.out"
echo "the failing tessera-farm.sbatch took $((SECONDS - started)) s"
grep -q '^tessera-farm: not every one of the 2 workers started$' "$work/farm-fails.out" ||
  fail "the job did not say that its workers did not start"
grep -q -- '--no-such-flag' "$work/farm-fails.out" || fail "the job did not show the workers' error"
[ ! -e "$work/never.png" ] || fail "the render ran without workers"
if compgen -G "$work/tessera-job-*" >/dev/null; then
  fail "the failed job left its private directory behind"
fi

# ---- tessera-frames.sbatch: frames 1-5 over an array of three tasks; frame 3 exists already.
started=$SECONDS
mkdir "$work/frames"
echo "rendered before" >"$work/frames/f.0003.png"
TESSERA_FRAMES=1-5 TESSERA_RENDER="$FRAMES_RENDER_CMD" timeout 150 \
  sbatch --wait --export=ALL --array=0-2 --cpus-per-task=1 --time=5 \
  --output="$work/frames-%a.out" "$source_dir/deploy/slurm/tessera-frames.sbatch" \
  builtin:cornell --spp 1 --width 48 --height 32 -o "$work/frames/f.####.png" ||
  { cat "$work"/frames-*.out >&2 || true; show_logs; fail "tessera-frames.sbatch failed"; }
cat "$work"/frames-*.out
echo "tessera-frames.sbatch took $((SECONDS - started)) s"
for frame in 1 2 4 5; do
  [ -s "$work/frames/f.000$frame.png" ] || fail "frame $frame was not rendered"
done
[ "$(cat "$work/frames/f.0003.png")" = "rendered before" ] ||
  fail "frame 3 existed and was rendered again"
for chunk in "0 1-2" "1 3-4" "2 5-5"; do
  read -r task range <<<"$chunk"
  grep -q "^tessera-frames: task $task renders frames $range on local:1$" \
    "$work/frames-$task.out" ||
    fail "array task $task did not render frames $range"
done
echo "PASS"
