#!/usr/bin/env bash
# Stands in for `tessera render SCENE -o OUT --frames A-B[:STEP] [--skip-existing]` in
# slurm_test.sh until that command exists: renders each frame of the range with the tutorial
# (the frame number picks its step), to OUT with its run of '#' replaced by the zero-padded frame
# number, as `tessera render` does. Only the flags tessera-frames.sbatch passes are understood.
set -euo pipefail
# The renderer behind the stub: tessera-tutorial, from the test (TESSERA_TUTORIAL).
RENDER="${TESSERA_TUTORIAL:?set TESSERA_TUTORIAL to tessera-tutorial}"

out="" frames="" skip_existing=0
scene="${1:?usage: $0 SCENE -o OUT --frames A-B[:STEP] [--skip-existing]}"
shift
while [ $# -gt 0 ]; do
  case "$1" in
    -o | --out) out="$2"; shift 2 ;;
    --frames) frames="$2"; shift 2 ;;
    --skip-existing) skip_existing=1; shift ;;
    *) echo "render_frames_stub: unexpected argument $1" >&2; exit 2 ;;
  esac
done
[[ "$frames" =~ ^([0-9]+)-([0-9]+)(:([0-9]+))?$ ]] || { echo "bad --frames '$frames'" >&2; exit 2; }
first="${BASH_REMATCH[1]}" last="${BASH_REMATCH[2]}" step="${BASH_REMATCH[4]:-1}"
[[ "$out" =~ ^(.*[^#])?(#+)([^#]*)$ ]] || { echo "-o needs a run of #: '$out'" >&2; exit 2; }
prefix="${BASH_REMATCH[1]}" hashes="${BASH_REMATCH[2]}" suffix="${BASH_REMATCH[3]}"
for ((frame = first; frame <= last; frame += step)); do
  file="$(printf '%s%0*d%s' "$prefix" "${#hashes}" "$frame" "$suffix")"
  if [ "$skip_existing" -eq 1 ] && [ -s "$file" ]; then
    echo "render_frames_stub: $scene frame $frame: $file exists, skipped" >&2
    continue
  fi
  "$RENDER" --step "$((frame % 11))" --width 48 --height 32 --out "$file" >/dev/null
  echo "render_frames_stub: $scene frame $frame: $file" >&2
done
