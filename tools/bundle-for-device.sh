#!/usr/bin/env bash
# Packs a build for a machine without Tessera's Debian libraries (the 16-core device machine of
# the `run` tool): the given executables, tessera-worker, every program module, and every shared
# library they load, Debian's glibc and loader included, into one compressed tarball.
#
#   tools/bundle-for-device.sh BUILD_DIR OUT.tar.xz EXECUTABLE...
#
# Build outputs keep their absolute paths (program module paths are baked into the benchmarks);
# the libraries land in /opt/tessera-libs. On the other machine:
#   tar xJf OUT.tar.xz -C / && /opt/tessera-libs/run EXECUTABLE ARGS...
# where `run` starts the executable with the packed loader and libraries, and spawned workers
# (TESSERA_WORKER) get the same.
set -euo pipefail
usage() { sed -n '2,12s/^# \{0,1\}//p' "$0"; }
if [[ $# -ge 1 && ( $1 == -h || $1 == --help ) ]]; then usage; exit 0; fi
if [[ $# -lt 2 ]]; then
  echo "bundle-for-device.sh: expected BUILD_DIR OUT.tar.xz [EXECUTABLE...]" >&2
  usage >&2
  exit 2
fi
if [[ ! -x $1/worker/service/tessera-worker ]]; then
  echo "bundle-for-device.sh: $1 is not a Tessera build directory (no worker/service/tessera-worker)" >&2
  exit 2
fi
for f in "${@:3}"; do
  [[ -f $f ]] || { echo "bundle-for-device.sh: executable $f not found" >&2; exit 2; }
done
build="$(cd "$1" && pwd)"
out="$(realpath -m "$2")"
shift 2
stage="$(mktemp -d)"
trap 'rm -rf "$stage"' EXIT
libs="$stage/opt/tessera-libs"
mkdir -p "$libs"

worker="$build/worker/service/tessera-worker"
files=("$worker")
for f in "$@"; do files+=("$(realpath "$f")"); done  # staged under their absolute paths
# libtessera_image is left out unless an executable links it: it pulls in OpenImageIO's whole
# dependency tree (over 300 MB), past what the device tool carries.
mapfile -t modules < <(find "$build" -name '*.so' -path '*modules*' -o -name 'libtessera*.so*' \
  ! -name 'libtessera_image*')
files+=("${modules[@]}")

echo "collecting ${#files[@]} files and the libraries they load" >&2
for f in "${files[@]}"; do
  mkdir -p "$stage$(dirname "$f")"
  cp -L "$f" "$stage$f"
  strip --strip-debug "$stage$f"  # RelWithDebInfo: debug sections are most of a build's bytes
  { ldd "$f" 2>/dev/null || true; } | awk '/=>/ && $3 ~ /^\// {print $3} /^\t\/lib64/ {print $1}' | while read -r lib; do
    cp -Ln "$lib" "$libs/" 2>/dev/null || true
  done
done
cp -L /lib64/ld-linux-x86-64.so.2 "$libs/"
for lib in "$libs"/libtessera*; do strip --strip-debug "$lib"; done

cat >"$libs/run" <<'SCRIPT'
#!/bin/sh
# Runs a packed executable with the packed loader and libraries; workers it spawns do the same.
export TESSERA_WORKER=/opt/tessera-libs/worker
exec /opt/tessera-libs/ld-linux-x86-64.so.2 --library-path /opt/tessera-libs "$@"
SCRIPT
# A worker started through the loader cannot start itself again with static TLS for its modules'
# initial-exec builds (worker_main.cc): it is given the room here.
cat >"$libs/worker" <<SCRIPT
#!/bin/sh
export GLIBC_TUNABLES="\${GLIBC_TUNABLES:+\$GLIBC_TUNABLES:}glibc.rtld.optional_static_tls=65536"
exec /opt/tessera-libs/ld-linux-x86-64.so.2 --library-path /opt/tessera-libs $worker "\$@"
SCRIPT
chmod +x "$libs/run" "$libs/worker"
echo "compressing $(du -sh "$stage" | cut -f1) into $out" >&2
XZ_OPT="${XZ_OPT:--T0 -3}" tar -C "$stage" -cJf "$out" .  # xz on every core
echo "packed $(du -h "$out" | cut -f1) into $out"
