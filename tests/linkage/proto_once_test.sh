#!/usr/bin/env bash
# For every ELF executable under a build directory: the generated protobuf code of each Tessera
# .proto (its descriptor_table_tessera_2fv1_2f*_2eproto symbol, local or global) must be defined
# at most once in the executable and the shared libraries of the same build that it loads
# (ldd). Two copies, one static in the executable and one hidden in libtessera.so say, both
# register the file at start-up, and protobuf aborts: "File already exists in database".
#   proto_once_test.sh <build dir>
set -euo pipefail
build=$(cd "$1" && pwd -P)

# The tables a file defines, one per line (nm reads the full symbol table, hidden symbols too),
# into table_cache[file]: each file is read once, libtessera.so being loaded by most executables.
declare -A table_cache
read_tables() {
  if [ -z "${table_cache[$1]+set}" ]; then
    table_cache[$1]=$(nm "$1" 2>/dev/null |
      awk '$2 ~ /^[A-Za-z]$/ && $3 ~ /^descriptor_table_tessera_2fv1_2f/ {print $3}' | sort -u)
  fi
}

checked=0
with_protos=0
failures=0
while IFS= read -r -d '' exe; do
  [ "$(head -c 4 "$exe" | od -An -c | tr -d ' ')" = '177ELF' ] || continue
  # A program, not a shared library that happens to be executable: it has an interpreter.
  readelf -l "$exe" 2>/dev/null | grep -q 'Requesting program interpreter' || continue
  checked=$((checked + 1))
  files=("$exe")
  while read -r lib; do
    real=$(readlink -f "$lib")
    case "$real" in "$build"/*) files+=("$real") ;; esac
  done < <(ldd "$exe" 2>/dev/null | awk '$2 == "=>" && $3 ~ /^\// {print $3}')
  all=""
  for f in "${files[@]}"; do
    read_tables "$f"
    [ -z "${table_cache[$f]}" ] || all+="${table_cache[$f]}"$'\n'
  done
  all=$(sort <<<"$all" | sed '/^$/d')
  [ -n "$all" ] && with_protos=$((with_protos + 1))
  dups=$(uniq -d <<<"$all")
  if [ -n "$dups" ]; then
    failures=$((failures + 1))
    echo "FAIL ${exe#"$build"/}: generated protobuf code more than once:"
    for table in $dups; do
      echo "  $table in:"
      for f in "${files[@]}"; do
        grep -qx "$table" <<<"${table_cache[$f]}" && echo "    ${f#"$build"/}"
      done
    done
  fi
done < <(find "$build" -type f -perm -u+x -not -name '*.so' -not -name '*.so.*' \
           -not -path '*/CMakeFiles/*' -print0)

echo "$checked executables checked, $with_protos with generated protobuf code," \
  "$failures with two copies"
# Guard against checking nothing (a stripped build, or no symbols found): tessera-worker and the
# tests that link libtessera.so must have been seen holding the code.
if [ "$with_protos" -lt 2 ]; then
  echo "FAIL: found the generated protobuf code in fewer than 2 executables; is the build stripped?"
  exit 1
fi
[ "$failures" -eq 0 ]
