#!/usr/bin/env python3
"""Where local workers' time went in each launch: tracing, sending, or idle (at the start, between
calls, at the end), from TESSERA_LAUNCH_TIMING=1 lines.

  TESSERA_LAUNCH_TIMING=1 TESSERA_WORKER_LOG_DIR=/tmp/wl APP ... 2> host.txt
  tools/worker-timeline.py host.txt /tmp/wl/*.log

The host prints one line per launch and every worker one line per call, each with the machine's
monotonic clock, so calls can be placed inside their launch. A launch's window runs from the
host's start to its end; a worker's busy time from taking a call (after waiting for the one
before it) to sending that call's last result.
"""
import re
import sys
from collections import defaultdict

HOST = re.compile(r'\[api\] \[info\] launch (\d+):.*monotonic clock ([0-9.]+) to ([0-9.]+)ms')
CALL = re.compile(r'call of launch (\d+) .*waited ([0-9.]+)ms, ran ([0-9.]+)ms, '
                  r'sent the rest in ([0-9.]+)ms.*monotonic clock ([0-9.]+) to ([0-9.]+)ms')


def read_lines(path):
    """The file's lines, or exit with one line naming it (a glob that matched nothing arrives as
    its own pattern, e.g. /tmp/wl/*.log when TESSERA_WORKER_LOG_DIR was not set)."""
    try:
        with open(path, errors='replace') as f:
            return f.readlines()
    except OSError as e:
        sys.exit(f'worker-timeline.py: cannot read {path}: {e.strerror}')


def main(host_file, worker_logs):
    launches = []  # (id, start, end)
    for line in read_lines(host_file):
        m = HOST.search(line)
        if m:
            launches.append((int(m.group(1)), float(m.group(2)), float(m.group(3))))
    calls = defaultdict(lambda: defaultdict(list))  # launch id -> log -> [(busy from, to, ran, sent)]
    for log in worker_logs:
        for line in read_lines(log):
            m = CALL.search(line)
            if not m:
                continue
            arrived, end = float(m.group(5)), float(m.group(6))
            calls[int(m.group(1))][log].append(
                (arrived + float(m.group(2)), end, float(m.group(3)), float(m.group(4))))
    if not launches or not calls:
        sys.exit('no launch or call lines: run with TESSERA_LAUNCH_TIMING=1 and '
                 'TESSERA_WORKER_LOG_DIR set')
    print('launch   window ms  workers  calls   ran   sent  idle: start  between    end')
    for launch_id in sorted(calls):
        workers = calls[launch_id]
        first = min(c[0] for v in workers.values() for c in v)
        # Launch ids count per context: take the host launch whose window holds these calls.
        window = [w for w in launches if w[0] == launch_id and w[1] <= first <= w[2]]
        if not window:
            continue
        _, start, end = window[0]
        total = (end - start) * len(workers)
        ran = sent = idle_start = idle_between = idle_end = 0.0
        count = 0
        for v in workers.values():
            v.sort()
            idle_start += v[0][0] - start
            idle_end += end - v[-1][1]
            idle_between += sum(max(0.0, v[i][0] - v[i - 1][1]) for i in range(1, len(v)))
            ran += sum(c[2] for c in v)
            sent += sum(c[3] for c in v)
            count += len(v)
        print(f'{launch_id:6d} {end - start:11.1f} {len(workers):8d} {count:6d} '
              f'{ran / total:5.1%} {sent / total:6.1%} {idle_start / total:11.1%} '
              f'{idle_between / total:8.1%} {idle_end / total:6.1%}')


if __name__ == '__main__':
    if len(sys.argv) >= 2 and sys.argv[1] in ('-h', '--help'):
        print(__doc__)
        sys.exit(0)
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2:])
