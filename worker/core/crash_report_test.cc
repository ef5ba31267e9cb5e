// The crash reporter of worker processes, each case in a child process (a death test): it
// installs process-wide handlers and an exit hook that would end the test binary itself.
#include "tessera/worker/crash_report.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "binding.h"
#include "thread_state.h"

namespace tessera {
namespace {

// A program as the engine names it; the plan that would hold it outlives every use here.
const worker::BoundProgram& Program(const char* name) {
  static auto* programs = new std::vector<worker::BoundProgram*>;
  auto* p = new worker::BoundProgram;
  p->name = name;
  programs->push_back(p);
  return *p;
}

// The calling thread runs `program` as far as the crash reporter can tell.
void RunAs(const worker::BoundProgram& program) { worker::TS().current = &program; }

// Deeper than any stack, read at run time so that the compiler cannot bound the recursion.
volatile unsigned g_depth_limit = ~0u;

// Recursion that the compiler can neither turn into a loop nor drop: a volatile frame written
// before and read after each call.
__attribute__((noinline)) unsigned Descend(unsigned depth) {
  volatile unsigned char frame[4096];
  frame[depth % sizeof(frame)] = static_cast<unsigned char>(depth);
  if (depth >= g_depth_limit) return frame[0];
  const unsigned below = Descend(depth + 1);
  return below + frame[(depth * 7u) % sizeof(frame)];
}

size_t MappingCount() {
  std::ifstream maps("/proc/self/maps");
  size_t lines = 0;
  for (std::string line; std::getline(maps, line);) ++lines;
  return lines;
}

// Runs after exit() freed the calling thread's state and before the exit report (registered
// after InstallCrashReporter, so called first): takes the freed memory back and fills it, so a
// report that still read the state would print garbage or fault.
void ScribbleOverFreedMemory() {
  for (int i = 0; i < 64; ++i) {
    void* p = std::malloc(sizeof(worker::ThreadState));
    if (p != nullptr) std::memset(p, 0xA5, sizeof(worker::ThreadState));
  }
}

class CrashReportTest : public ::testing::Test {
 protected:
  // Each child runs only its own test: fork()ing this multithreaded test binary is unsafe.
  void SetUp() override { GTEST_FLAG_SET(death_test_style, "threadsafe"); }
};

TEST_F(CrashReportTest, ThreadsThatRunProgramsHaveAnAlternateSignalStackFreedWithThem) {
  EXPECT_EXIT(
      {
        InstallCrashReporter();
        int failures = 0;
        std::thread([&] {
          stack_t ss{};
          sigaltstack(nullptr, &ss);
          if ((ss.ss_flags & SS_DISABLE) == 0) failures |= 1;  // a new thread has none
          worker::TS();
          sigaltstack(nullptr, &ss);
          if ((ss.ss_flags & SS_DISABLE) != 0 || ss.ss_size < kAltSignalStackBytes) failures |= 2;
        }).join();
        // Two mappings each (the stack and its guard page) would stay behind if they leaked.
        const size_t before = MappingCount();
        for (int i = 0; i < 200; ++i) std::thread([] { worker::TS(); }).join();
        if (MappingCount() > before + 40) failures |= 4;
        std::fprintf(stderr, "failures %d\n", failures);
        std::_Exit(failures);
      },
      ::testing::ExitedWithCode(0), "failures 0");
}

TEST_F(CrashReportTest, AProgramThatOverflowsItsStackIsNamed) {
  EXPECT_EXIT(
      {
        InstallCrashReporter();
        std::thread([] {
          RunAs(Program("ray generation program 'deep' in test.so"));
          std::printf("%u\n", Descend(0));
        }).join();
      },
      ::testing::KilledBySignal(SIGSEGV),
      "tessera-worker: crashed: signal 11 \\(SIGSEGV\\) in ray generation program 'deep' in "
      "test\\.so");
}

// exit() destroys the thread's thread_local objects (its ThreadState) before the report runs: the
// report must name the program without reading that freed memory.
TEST_F(CrashReportTest, ExitInAProgramIsNamedWithoutReadingTheFreedThreadState) {
  EXPECT_EXIT(
      {
        InstallCrashReporter();
        std::atexit(&ScribbleOverFreedMemory);
        RunAs(Program("closest hit program 'quit' in test.so"));
        std::exit(3);
      },
      ::testing::KilledBySignal(SIGABRT),
      "tessera-worker: crashed: exit\\(\\) called in closest hit program 'quit' in test\\.so");
}

// quick_exit() destroys no thread_local objects: the state is still there to read.
TEST_F(CrashReportTest, QuickExitInAProgramIsNamed) {
  EXPECT_EXIT(
      {
        InstallCrashReporter();
        RunAs(Program("miss program 'leave' in test.so"));
        std::quick_exit(3);
      },
      ::testing::KilledBySignal(SIGABRT),
      "tessera-worker: crashed: exit\\(\\) called in miss program 'leave' in test\\.so");
}

// The worker's own exit is no crash, also after other threads ran programs and ended.
TEST_F(CrashReportTest, TheWorkersOwnExitIsNoCrash) {
  EXPECT_EXIT(
      {
        InstallCrashReporter();
        std::thread([] { RunAs(Program("ray generation program 'done' in test.so")); }).join();
        std::exit(0);
      },
      ::testing::ExitedWithCode(0), "");
}

}  // namespace
}  // namespace tessera
