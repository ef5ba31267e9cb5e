// Process inspection for the end-to-end tests: which processes a parent has, and waiting for one
// to end with a deadline (a test must fail, not hang, when a worker outlives its host).
#ifndef TESSERA_TESTS_E2E_PROCESS_UTIL_H_
#define TESSERA_TESTS_E2E_PROCESS_UTIL_H_

#include <dirent.h>
#include <fcntl.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace tessera::e2e {

// The contents of a file under /proc, empty when it cannot be read. With read(2), not streams: a
// process that ends between open and read makes read fail (ESRCH), which libstdc++'s filebuf
// answers with an exception whatever the stream's exception mask.
inline std::string ReadProcFile(const std::string& path) {
  std::string text;
  const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return text;
  char buf[4096];
  ssize_t n;
  while ((n = read(fd, buf, sizeof(buf))) > 0) text.append(buf, static_cast<size_t>(n));
  close(fd);
  return text;
}

// The command name (/proc/PID/comm), empty once the process is gone.
inline std::string CommandName(pid_t pid) {
  std::string name = ReadProcFile("/proc/" + std::to_string(pid) + "/comm");
  return name.substr(0, name.find('\n'));
}

// Waits until `pid` is stopped (state T in /proc/PID/stat): kill(SIGSTOP) returns before the
// process has stopped, and a worker may still answer a call in between.
inline bool WaitUntilStopped(pid_t pid, std::chrono::milliseconds timeout) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end) {
    const std::string stat = ReadProcFile("/proc/" + std::to_string(pid) + "/stat");
    const size_t close = stat.rfind(')');
    if (close != std::string::npos && close + 2 < stat.size() && stat[close + 2] == 'T') {
      return true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return false;
}

// The value after --listen on the command line of `pid`, empty if none.
inline std::string ListenAddress(pid_t pid) {
  std::istringstream in(ReadProcFile("/proc/" + std::to_string(pid) + "/cmdline"));
  std::string arg;
  bool next = false;
  while (std::getline(in, arg, '\0')) {
    if (next) return arg;
    next = arg == "--listen";
  }
  return "";
}

inline std::string DirName(const std::string& path) {
  size_t slash = path.rfind('/');
  return slash == std::string::npos ? "." : path.substr(0, slash);
}

// TESSERA_WORKER_TIMEOUT, in seconds, for tests of the silence deadline: 1, the shortest the host
// takes. A worker that has not said where it listens within the deadline is dropped, and one built
// with the sanitizers (tools/sanitize.sh) can take most of a second to start, or to take a state
// update, on a loaded machine: there these tests give it 5 s.
#ifdef TESSERA_SANITIZER_BUILD
inline constexpr int kDeadlineSeconds = 5;
#else
inline constexpr int kDeadlineSeconds = 1;
#endif
inline const std::string kDeadline = std::to_string(kDeadlineSeconds);  // for setenv and messages

// Live children of `parent` whose command name is `name` (zombies excluded).
inline std::vector<pid_t> ChildrenNamed(pid_t parent, const std::string& name) {
  std::vector<pid_t> children;
  DIR* proc = opendir("/proc");
  if (proc == nullptr) return children;
  while (dirent* entry = readdir(proc)) {
    char* end = nullptr;
    long pid = std::strtol(entry->d_name, &end, 10);
    if (pid <= 0 || *end != '\0') continue;
    const std::string stat = ReadProcFile(std::string("/proc/") + entry->d_name + "/stat");
    size_t paren = stat.rfind(')');
    if (paren == std::string::npos) continue;
    std::istringstream fields(stat.substr(paren + 1));
    char state = 0;
    long ppid = 0;
    fields >> state >> ppid;
    if (ppid == parent && state != 'Z' && CommandName(static_cast<pid_t>(pid)) == name) {
      children.push_back(static_cast<pid_t>(pid));
    }
  }
  closedir(proc);
  return children;
}

// Waits up to `timeout` for our child `pid` to end; true with its status once reaped.
inline bool WaitForExit(pid_t pid, std::chrono::milliseconds timeout, int* status) {
  auto deadline = std::chrono::steady_clock::now() + timeout;
  while (true) {
    pid_t r = waitpid(pid, status, WNOHANG);
    if (r == pid) return true;
    if (r < 0 && errno != EINTR) return false;
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

}  // namespace tessera::e2e

#endif  // TESSERA_TESTS_E2E_PROCESS_UTIL_H_
