#!/usr/bin/env bash
# Installs this build into a prefix, moves the prefix (an install must not depend on where it was
# first put, nor on this build tree), builds tests/install/consumer against it with find_package,
# and runs it on two worker processes: they must be the installed tessera-worker, and a program
# compiled from source at run time must find the installed headers.
#   install_test.sh <build dir> <consumer source dir> [consumer cmake arguments...]
set -euo pipefail
build=$1
consumer=$2
shift 2
work=$(mktemp -d "${TMPDIR:-/tmp}/tessera-install-test.XXXXXX")
[ -n "${KEEP_WORK:-}" ] || trap "rm -rf \"$work\"" EXIT

cmake --install "$build" --prefix "$work/first" >/dev/null
mv "$work/first" "$work/moved"
prefix="$work/moved"
for f in bin/tessera-worker include/tessera/optix.h include/tessera/tessera/device.h \
         lib/cmake/Tessera/TesseraConfig.cmake; do
  [ -e "$prefix/$f" ] || { echo "missing from the install: $f"; exit 1; }
done
ls "$prefix"/lib*/libtessera.so* >/dev/null

# `tessera render` runs from the moved prefix with the installed path tracer modules.
unset TESSERA_RENDER_MODULE_DIR
err=$(TESSERA_DEVICES=local:2 TESSERA_CACHE_DIR="$work/cache-render" "$prefix/bin/tessera" render \
      builtin:cornell -o "$work/cornell.png" --width 32 --height 24 --spp 1 --log-level debug 2>&1)
grep -q "program modules in $prefix/lib[^ ]*/tessera/render\$" <<<"$err" ||
  { echo "tessera render did not use the installed modules: $err"; exit 1; }
[ -s "$work/cornell.png" ] || { echo "tessera render wrote no image"; exit 1; }
echo "// added by install_test.sh: consumer/fill.cu needs it" \
  >"$prefix/include/tessera/installed_marker.h"

cmake -S "$consumer" -B "$work/consumer-build" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build "$work/consumer-build" -j 2 >/dev/null

unset TESSERA_WORKER TESSERA_INCLUDE_DIR
output=$(TESSERA_DEVICES=local:2 TESSERA_CACHE_DIR="$work/cache" \
         "$work/consumer-build/consumer")
echo "$output"
workers=$(grep -c '^worker ' <<<"$output" || true)
[ "$workers" = 2 ] || { echo "expected 2 workers, saw $workers"; exit 1; }
if grep '^worker ' <<<"$output" | grep -v "^worker $prefix/bin/tessera-worker\$"; then
  echo "a worker above is not the installed one ($prefix/bin/tessera-worker)"
  exit 1
fi
grep -q "both launches wrote what they should" <<<"$output"

# Reached through a symlink in another directory (LD_LIBRARY_PATH comes before the RUNPATH): the
# library still finds the installed worker and headers, not the build tree's.
mkdir "$work/linkdir"
ln -s "$(ls "$prefix"/lib*/libtessera.so.0)" "$work/linkdir/libtessera.so.0"
output=$(LD_LIBRARY_PATH="$work/linkdir" TESSERA_DEVICES=local:2 \
         TESSERA_CACHE_DIR="$work/cache2" "$work/consumer-build/consumer")
echo "$output"
if grep '^worker ' <<<"$output" | grep -v "^worker $prefix/bin/tessera-worker\$"; then
  echo "through a symlink, a worker above is not the installed one"
  exit 1
fi
grep -q "both launches wrote what they should" <<<"$output"

# A damaged install: its worker not executable. The library falls back to the build tree's worker
# but says so, naming both; without a build tree to fall back to, the error says why the
# installed one was passed over.
chmod -x "$prefix/bin/tessera-worker"
err=$(TESSERA_DEVICES=local:2 TESSERA_CACHE_DIR="$work/cache3"       "$work/consumer-build/consumer" 2>&1 >/dev/null || true)
grep -q "no usable tessera-worker at $prefix/bin/tessera-worker" <<<"$err" ||
  { echo "no warning about falling back to the build tree's worker: $err"; exit 1; }
chmod +x "$prefix/bin/tessera-worker"
# An OptiX 7 application against the same install: Tessera::optix7 and tessera_embed_program.
cmake -S "$consumer/../consumer7" -B "$work/consumer7-build" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build "$work/consumer7-build" -j 2 >/dev/null
output=$(TESSERA_DEVICES=local:2 TESSERA_CACHE_DIR="$work/cache7" "$work/consumer7-build/consumer7")
echo "$output"
grep -q "the OptiX 7 launch wrote what it should" <<<"$output"
echo "install test passed"
