#!/usr/bin/env bash
# Builds Tessera with AddressSanitizer (leaks included) and UndefinedBehaviorSanitizer (vptr
# included) and runs every test with ctest (docs/sanitizers.md). Exits non-zero on any failed
# test and on any sanitizer report, including one from a tessera-worker process a test spawned.
#   tools/sanitize.sh [BUILD_DIR] [CTEST_ARGS...]
#     BUILD_DIR   default build-asan (or $TESSERA_SANITIZE_BUILD_DIR), relative to the repository
#     CTEST_ARGS  passed to ctest, e.g. -R e2e_ to run some tests only
#   JOBS=N        build and test jobs (default: the number of cores)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
build="${TESSERA_SANITIZE_BUILD_DIR:-build-asan}"
if [ $# -gt 0 ] && [ "${1#-}" = "$1" ]; then
  build="$1"
  shift
fi
case "$build" in /*) ;; *) build="$root/$build" ;; esac
jobs="${JOBS:-$(nproc)}"
start=$(date +%s)
elapsed() {
  local s=$(($(date +%s) - start))
  printf '%dm%02ds' $((s / 60)) $((s % 60))
}

echo "== configure $build (TESSERA_SANITIZE=ON, RelWithDebInfo)"
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTESSERA_SANITIZE=ON >/dev/null
echo "== build (-j $jobs)"
cmake --build "$build" -j "$jobs"

# A tessera-worker's stderr goes to a log that is removed with the worker, and a worker that ends
# with a report could look to its host like any lost device, whose tiles the other devices render:
# the test could pass. So every process writes its ASan and LeakSanitizer reports to a file here
# (log_path), and the workers' logs are kept (TESSERA_WORKER_LOG_DIR) and read for UBSan's, which
# g++'s separate libubsan writes to stderr whatever log_path says. Any report fails the run.
reports="$build/sanitizer-reports"
worker_logs="$build/sanitizer-worker-logs"
rm -rf "$reports" "$worker_logs"
mkdir -p "$reports" "$worker_logs"
export TESSERA_WORKER_LOG_DIR="$worker_logs"
supp="$root/tools/sanitizers"
# abort_on_error: a process with a finding dies of SIGABRT, which a host reports as a crashed
# worker (a plain exit status reads as a lost device). The crash reporter of tessera-worker
# catches SIGABRT and says so on its stderr before dying of it.
common="halt_on_error=1:abort_on_error=1:log_path=$reports/report:log_exe_name=1"
# use_sigaltstack=0: tessera-worker gives the threads that run programs alternate signal stacks of
# its own size (worker/core/crash_report.cc), and checks that a new thread has none.
# intercept_tls_get_addr=0: g++ 12's runtime takes some dynamic TLS blocks (program modules are
# dlopen'd with thread_local variables) for glibc 2.19's, reads a bogus range from them, and
# LeakSanitizer's tracer dies of SIGSEGV at exit now and then ("Tracer caught signal 11",
# google/sanitizers#1322; fixed after GCC 13). The cost: the leak check does not scan those blocks.
asan="detect_leaks=1:check_initialization_order=1:strict_init_order=1:use_sigaltstack=0"
asan+=":intercept_tls_get_addr=0"
export ASAN_OPTIONS="$common:$asan:${ASAN_OPTIONS:-}"
export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0:${LSAN_OPTIONS:-}"
export UBSAN_OPTIONS="$common:print_stacktrace=1:suppressions=$supp/ubsan.supp:${UBSAN_OPTIONS:-}"

echo "== ctest -j $jobs $*"
status=0
(cd "$build" && ctest -j "$jobs" --output-on-failure "$@") 2>&1 | tee "$build/sanitize-ctest.log" ||
  status=1  # pipefail: ctest's status

# Tests that skipped, each with the reason it gave (GTEST_SKIP() << reason: under the sanitizers,
# or for a reason of the machine), and tests that ctest did not run at all under the sanitizers
# (DISABLED), with the reason their CMakeLists recorded (tessera_sanitizer_skip).
echo
echo "== tests skipped, and why"
last="$build/Testing/Temporary/LastTest.log"
skipped=0
if [ -f "$last" ]; then
  while IFS=$'\t' read -r name reason; do
    printf '  %-70s %s\n' "$name" "$reason"
    skipped=$((skipped + 1))
  done < <(awk '
    /^[0-9]+\/[0-9]+ Testing: / { name = $3; reason = ""; grab = 0; next }
    grab == 1 { reason = $0; grab = 0; next }
    /: Skipped$/ { grab = 1; next }
    /^\[  SKIPPED \]/ && name != "" {
      print name "\t" (reason != "" ? reason : "(no reason given)")
      name = ""
    }' "$last")
fi
if [ -f "$build/sanitizer-disabled-tests.txt" ]; then
  while IFS=$'\t' read -r name reason; do
    printf '  %-70s %s (disabled)\n' "$name" "$reason"
    skipped=$((skipped + 1))
  done <"$build/sanitizer-disabled-tests.txt"
fi
echo "  $skipped skipped"
# Tests that run with one check turned off, and why (each says so on stderr: "sanitize: …").
echo
echo "== tests run with a check turned off, and why"
if [ -f "$last" ]; then
  awk '
    /^[0-9]+\/[0-9]+ Testing: / { name = $3 }
    /^sanitize: / && !((name, $0) in seen) {
      seen[name, $0] = 1
      print "  " name ": " substr($0, 11)
    }' "$last"
fi

# Reports: ASan's and LSan's files; workers' logs that hold one; and the tests whose output holds
# one (UBSan in a test process, or in a process whose stderr the test passed on).
echo
pattern='runtime error: |ERROR: (AddressSanitizer|LeakSanitizer)'
pattern+='|SUMMARY: (AddressSanitizer|LeakSanitizer|UndefinedBehaviorSanitizer)'
found=$( (find "$reports" -type f; grep -rlE "$pattern" "$worker_logs" || true) | sort)
in_tests=""
if [ -f "$last" ]; then
  in_tests=$(awk -v pattern="$pattern" '
    /^[0-9]+\/[0-9]+ Testing: / { name = $3 }
    $0 ~ pattern && !(name in seen) { seen[name] = 1; print name }' "$last")
fi
if [ -n "$found" ] || [ -n "$in_tests" ]; then
  echo "== sanitizer reports"
  if [ -n "$found" ]; then
    while read -r f; do
      echo "---- $f"
      grep -m 1 -nE "$pattern" "$f" | cut -d: -f1 | while read -r line; do
        tail -n +$((line > 5 ? line - 5 : 1)) "$f" | head -n 80
      done
    done <<<"$found"
  fi
  if [ -n "$in_tests" ]; then
    echo "---- tests whose output holds a report ($last):"
    sed 's/^/  /' <<<"$in_tests"
  fi
  status=1
else
  echo "== no sanitizer reports"
fi

echo
grep -E "tests passed|tests failed" "$build/sanitize-ctest.log" | tail -n 1 || true
echo "sanitize: $([ $status -eq 0 ] && echo PASSED || echo FAILED) in $(elapsed)"
exit $status
