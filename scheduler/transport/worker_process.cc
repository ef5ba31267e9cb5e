#include "transport/worker_process.h"

#include <dirent.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <filesystem>
#include <functional>
#include <map>
#include <mutex>
#include <set>
#include <thread>

#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "absl/time/clock.h"
#include "tessera/scheduler/install_paths.h"
#include "tessera/scheduler/log.h"
#include "transport/result_arena.h"

#ifndef TESSERA_WORKER_BUILD_PATH
#define TESSERA_WORKER_BUILD_PATH ""
#endif

namespace tessera::transport {
namespace {

// The worker's descriptor of the result arena (--result-arena-fd): the first after stderr.
constexpr int kArenaChildFd = 3;

constexpr char kReadyPrefix[] = "tessera-worker listening on ";
constexpr char kWorkerName[] = "tessera-worker";

std::string Errno(const char* what) { return absl::StrCat(what, ": ", std::strerror(errno)); }

bool IsExecutable(const std::string& path) {
  struct stat st;
  return !path.empty() && stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) &&
         access(path.c_str(), X_OK) == 0;
}

using scheduler::DirName;

// PR_SET_PDEATHSIG fires when the *thread* that forked the child exits, not the process. An
// application may create contexts (and so spawn workers) on short-lived threads; forking from one
// thread that lives as long as the process ties each worker's life to the host process instead.
class ForkThread {
 public:
  static ForkThread& Get() {
    // Never destroyed: outlives every caller. A process forked from the host (without exec)
    // inherits the object but not its thread, and would wait forever for it: it gets its own.
    static std::mutex* mu = new std::mutex;
    static ForkThread* instance = nullptr;
    static pid_t owner = 0;
    std::lock_guard<std::mutex> lock(*mu);
    if (instance == nullptr || owner != getpid()) {
      instance = new ForkThread;  // the inherited one (if any) is left alone: its thread is gone
      owner = getpid();
    }
    return *instance;
  }

  // Runs `job` on the fork thread and waits for it.
  void Run(const std::function<void()>& job) {
    Job entry{&job};
    std::unique_lock<std::mutex> lock(mu_);
    queue_.push_back(&entry);
    cv_.notify_all();
    cv_.wait(lock, [&] { return entry.done; });
  }

 private:
  struct Job {
    const std::function<void()>* run;
    bool done = false;
  };

  ForkThread() {
    std::thread([this] { Loop(); }).detach();
  }

  void Loop() {
    std::unique_lock<std::mutex> lock(mu_);
    while (true) {
      cv_.wait(lock, [&] { return !queue_.empty(); });
      Job* job = queue_.front();
      queue_.pop_front();
      lock.unlock();
      (*job->run)();
      lock.lock();
      job->done = true;
      cv_.notify_all();
    }
  }

  std::mutex mu_;
  std::condition_variable cv_;
  std::deque<Job*> queue_;
};

// Worker directories still present; removed at exit for hosts that never destroy their contexts
// (their workers die with them through PDEATHSIG, but the sockets and logs would stay).
// Each directory with the process that made it: a child forked from the host (without exec) runs
// the same atexit handler, and must not remove its parent's live workers' sockets and logs.
std::mutex g_directories_mu;
std::map<std::string, pid_t>* g_directories = nullptr;

void RemoveDirectory(const std::string& directory) {
  if (DIR* dir = opendir(directory.c_str())) {
    while (dirent* entry = readdir(dir)) {
      std::string name = entry->d_name;
      if (name != "." && name != "..") unlink(absl::StrCat(directory, "/", name).c_str());
    }
    closedir(dir);
  }
  rmdir(directory.c_str());
}

void RemoveDirectoriesAtExit() {
  std::lock_guard<std::mutex> lock(g_directories_mu);
  for (const auto& [directory, owner] : *g_directories) {
    if (owner == getpid()) RemoveDirectory(directory);
  }
  g_directories->clear();
}

void TrackDirectory(const std::string& directory, bool add) {
  std::lock_guard<std::mutex> lock(g_directories_mu);
  if (g_directories == nullptr) {
    g_directories = new std::map<std::string, pid_t>;
    std::atexit(&RemoveDirectoriesAtExit);
  }
  if (add) {
    g_directories->emplace(directory, getpid());
  } else {
    g_directories->erase(directory);
  }
}

// Names the host that made a worker directory (its pid), for RemoveStaleDirectories.
constexpr char kHostFile[] = "host.pid";

// Removes worker directories of hosts that are gone: a host killed by a signal runs no atexit
// handler, so its directories (a socket and a log each) would stay for good. A directory counts
// as stale when it is ours, names its host in kHostFile and that process no longer exists.
void RemoveStaleDirectories(const std::string& base) {
  DIR* dir = opendir(base.c_str());
  if (dir == nullptr) return;
  while (dirent* entry = readdir(dir)) {
    const std::string name = entry->d_name;
    if (name.rfind("tessera-w-", 0) != 0) continue;
    const std::string path = absl::StrCat(base, "/", name);
    struct stat st {};
    if (lstat(path.c_str(), &st) != 0 || !S_ISDIR(st.st_mode) || st.st_uid != geteuid()) continue;
    FILE* host = std::fopen(absl::StrCat(path, "/", kHostFile).c_str(), "r");
    if (host == nullptr) continue;  // made by an older Tessera, or not yet named: left alone
    long pid = 0;
    const bool named = std::fscanf(host, "%ld", &pid) == 1 && pid > 0;
    std::fclose(host);
    if (named && kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) RemoveDirectory(path);
  }
  closedir(dir);
}

absl::StatusOr<std::string> MakeDirectory() {
  std::string base = "/tmp";
  // Unix socket paths are limited to 108 bytes; a long TMPDIR falls back to /tmp.
  if (const char* tmp = std::getenv("TMPDIR");
      tmp != nullptr && *tmp == '/' && std::strlen(tmp) < 64) {
    base = tmp;
  }
  {  // once per directory and process: a host spawning a thousand workers scans it once
    static std::mutex mu;
    static std::set<std::string>* swept = new std::set<std::string>;
    std::lock_guard<std::mutex> lock(mu);
    if (swept->insert(base).second) RemoveStaleDirectories(base);
  }
  std::string path = absl::StrCat(base, "/tessera-w-XXXXXX");
  if (mkdtemp(path.data()) == nullptr) {
    return absl::UnavailableError(Errno(absl::StrCat("mkdtemp ", path).c_str()));
  }
  // A directory that does not name its host could never be swept after a crash: one that cannot
  // be named (a full disk) is not used.
  const std::string host_file = absl::StrCat(path, "/", kHostFile);
  FILE* host = std::fopen(host_file.c_str(), "w");
  bool named = host != nullptr && std::fprintf(host, "%ld\n", static_cast<long>(getpid())) > 0;
  if (host != nullptr) named = std::fclose(host) == 0 && named;
  if (!named) {
    const std::string message = Errno(absl::StrCat("writing ", host_file).c_str());
    unlink(host_file.c_str());
    rmdir(path.c_str());
    return absl::UnavailableError(message);
  }
  return path;
}

// Moves `fd` above stdin/stdout/stderr, so that the child's dup2 calls cannot clobber it even in
// a host that closed its standard streams.
int AboveStdio(int fd) {
  if (fd < 0 || fd > STDERR_FILENO) return fd;
  int moved = fcntl(fd, F_DUPFD_CLOEXEC, STDERR_FILENO + 1);
  close(fd);
  return moved;
}

// Waits up to `timeout` for `pid`; true once reaped (or no longer our child).
bool WaitFor(pid_t pid, absl::Duration timeout, int* status) {
  const absl::Time deadline = absl::Now() + timeout;
  absl::Duration pause = absl::Milliseconds(1);
  while (true) {
    pid_t r = waitpid(pid, status, WNOHANG);
    if (r == pid) return true;
    if (r < 0 && errno != EINTR) return true;  // ECHILD: someone else reaped it
    if (absl::Now() >= deadline) return false;
    absl::SleepFor(pause);
    pause = std::min(pause * 2, absl::Milliseconds(20));
  }
}

std::string DescribeExit(int status) {
  if (WIFEXITED(status)) return absl::StrCat("exited with status ", WEXITSTATUS(status));
  if (WIFSIGNALED(status)) return absl::StrCat("was killed by signal ", WTERMSIG(status));
  return "stopped";
}

// What RelayStartupLines compares: the line without the names of what each worker made for
// itself (the private module cache it falls back to, tessera-modules-<pid>-XXXXXX). Otherwise a
// line every worker prints differs per worker, and a host that spawns workers for every context
// prints it, and keeps it, once per worker.
std::string StartupLineKey(absl::string_view line) {
  static constexpr absl::string_view kPrivate = "tessera-modules-";
  std::string key;
  while (true) {
    const size_t at = line.find(kPrivate);
    if (at == absl::string_view::npos) break;
    key.append(line.data(), at + kPrivate.size());
    key.push_back('*');
    line.remove_prefix(at + kPrivate.size());
    while (!line.empty() && (absl::ascii_isalnum(line.front()) || line.front() == '-')) {
      line.remove_prefix(1);
    }
  }
  key.append(line.data(), line.size());
  return key;
}

// Passes on what a worker printed while it started: warnings about the environment it shares with
// the host (a module cache it cannot use, a malformed TESSERA_* value) would otherwise stay in a
// log that nobody reads and that goes with the worker. A line that several workers print (they
// all see the same environment) appears once per host process. A worker's warnings and errors
// travel at their own level, without their time and component (the host's line has its own), and
// its info lines (what it serves) stay in its log; anything else it printed is a warning.
void RelayStartupLines(const std::string& printed, int index) {
  static std::mutex mu;
  static auto* seen = new std::set<std::string>;
  std::lock_guard<std::mutex> lock(mu);
  for (absl::string_view line : absl::StrSplit(printed, '\n', absl::SkipWhitespace())) {
    log::Level level = log::Level::kWarn;
    absl::string_view text = line;
    if (!log::ParseLine(line, &level, &text)) text = line;
    if (level < log::Level::kWarn || !log::Enabled(level)) continue;
    if (!seen->emplace(StartupLineKey(text)).second) continue;
    log::Log(log::Component::kScheduler, level, "%s (said by local worker %d at startup)", text,
             index);
  }
}

}  // namespace

absl::StatusOr<std::string> FindWorkerBinary() {
  if (const char* env = std::getenv("TESSERA_WORKER"); env != nullptr && *env != '\0') {
    if (IsExecutable(env)) return std::string(env);
    return absl::NotFoundError(absl::StrCat("TESSERA_WORKER=", env, " is not an executable file"));
  }
  // An installed library's own worker first: a build tree that still exists may be another
  // version. Then one beside the library, then this build's.
  std::vector<std::string> tried;
  const std::string self = scheduler::ThisBinaryPath();
  const std::string candidates[] = {
      scheduler::InstalledWorkerPath(),
      self.empty() ? std::string() : absl::StrCat(DirName(self), "/", kWorkerName),
      TESSERA_WORKER_BUILD_PATH};
  auto normal = [](const std::string& p) { return std::filesystem::path(p).lexically_normal(); };
  for (const std::string& candidate : candidates) {
    if (candidate.empty()) continue;
    const std::string path = normal(candidate);
    if (IsExecutable(path)) {
      if (candidate == candidates[2]) {  // the build tree's
        scheduler::NoteBuildTreeFallback(scheduler::InstalledPart::kWorker, normal(candidates[0]),
                                         path);
      }
      return path;
    }
    std::error_code ec;
    tried.push_back(std::filesystem::exists(path, ec) ? path + " (not executable)" : path);
  }
  return absl::NotFoundError(absl::StrCat("cannot find the ", kWorkerName, " executable (tried ",
                                          absl::StrJoin(tried, ", "),
                                          "); set TESSERA_WORKER to its path"));
}

absl::StatusOr<std::unique_ptr<WorkerProcess>> WorkerProcess::Spawn(Options options) {
  if (options.binary.empty()) {
    absl::StatusOr<std::string> found = FindWorkerBinary();
    if (!found.ok()) return absl::UnavailableError(found.status().message());
    options.binary = *std::move(found);
  }
  std::unique_ptr<WorkerProcess> process(new WorkerProcess);
  process->stop_grace_ = options.stop_grace;
  process->host_pid_ = getpid();
  absl::StatusOr<std::string> directory = MakeDirectory();
  if (!directory.ok()) return directory.status();
  process->directory_ = *directory;
  TrackDirectory(process->directory_, true);
  process->log_path_ = absl::StrCat(process->directory_, "/w", options.index, ".log");
  if (const char* dir = std::getenv("TESSERA_WORKER_LOG_DIR"); dir != nullptr && *dir != '\0') {
    // Kept after the worker is gone (say, to read TESSERA_LAUNCH_TIMING's per-call lines), one
    // file per spawn: a respawned worker does not overwrite the log of the one that crashed.
    // A directory that cannot take them costs the logs, not the launch: they stay private.
    static std::atomic<int> spawns{0};
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (!ec && access(dir, W_OK | X_OK) == 0) {
      process->log_path_ = absl::StrCat(dir, "/tessera-worker-", getpid(), "-", spawns++, "-w",
                                        options.index, ".log");
    } else if (static std::atomic<bool> warned{false}; !warned.exchange(true)) {
      log::Warn(log::Component::kScheduler,
                "TESSERA_WORKER_LOG_DIR=%s cannot hold worker logs (%s); they stay in each "
                "worker's private directory",
                dir, ec ? ec.message().c_str() : std::strerror(errno));
    }
  }
  std::string listen = options.listen;
  if (listen.empty()) {
    process->socket_path_ = absl::StrCat(process->directory_, "/w", options.index, ".sock");
    listen = absl::StrCat("unix:", process->socket_path_);
  }

  // Shared memory for results; without it (no memfd here, or TESSERA_RESULT_ARENA=0) results
  // take the socket.
  const char* arena_env = std::getenv("TESSERA_RESULT_ARENA");
  if (options.result_arena_slot_bytes > 0 &&
      (arena_env == nullptr || std::string(arena_env) != "0")) {
    absl::StatusOr<std::unique_ptr<ResultArena>> arena =
        ResultArena::Create(options.result_arena_slot_bytes);
    if (arena.ok()) process->arena_ = *std::move(arena);
  }
  const int arena_fd = process->arena_ != nullptr ? process->arena_->fd() : -1;

  std::vector<std::string> args = {options.binary, "--listen", listen};
  if (arena_fd >= 0) {
    args.push_back("--result-arena-fd");
    args.push_back(std::to_string(kArenaChildFd));
  }
  if (options.threads > 0) {
    args.push_back("--threads");
    args.push_back(std::to_string(options.threads));
  }
  for (const std::string& a : options.extra_args) args.push_back(a);
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  // The host's environment, less the token of workers someone starts themselves: a spawned
  // worker listens in a private directory and needs none, and one that took the host's
  // TESSERA_WORKER_TOKEN would refuse the host, which sends TESSERA_TOKEN (docs/security.md).
  std::vector<char*> envp;
  for (char** e = environ; *e != nullptr; ++e) {
    if (std::strncmp(*e, "TESSERA_WORKER_TOKEN=", 21) != 0) envp.push_back(*e);
  }
  envp.push_back(nullptr);

  // Everything the child touches is prepared here: between fork and exec only async-signal-safe
  // calls are allowed in a multithreaded process.
  int out[2];
  if (pipe2(out, O_CLOEXEC) != 0) return absl::UnavailableError(Errno("pipe"));
  out[0] = AboveStdio(out[0]);
  out[1] = AboveStdio(out[1]);
  int log_fd =
      AboveStdio(open(process->log_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600));
  int null_fd = AboveStdio(open("/dev/null", O_RDONLY | O_CLOEXEC));
  auto close_all = [&] {
    for (int fd : {out[0], out[1], log_fd, null_fd}) {
      if (fd >= 0) close(fd);
    }
  };
  if (out[0] < 0 || out[1] < 0 || log_fd < 0 || null_fd < 0) {
    const std::string message =
        Errno(log_fd < 0 ? absl::StrCat("opening the worker's log ", process->log_path_).c_str()
                         : "opening the worker's files");
    close_all();
    return absl::UnavailableError(message);
  }

  const pid_t parent = getpid();
  pid_t pid = -1;
  int fork_errno = 0;
  ForkThread::Get().Run([&] {
    // vfork, not fork: fork() runs the process's atfork handlers (gRPC's stop and restart its
    // threads when its fork support is on, see grpc_device.cc) and copies the page tables of a
    // host that may hold gigabytes. The child borrows this thread's memory and stack until
    // execve, so it only makes system calls, with every signal blocked until the handlers it
    // would otherwise run (the application's, on the host's memory) are reset.
    sigset_t all;
    sigset_t saved;
    sigfillset(&all);
    pthread_sigmask(SIG_SETMASK, &all, &saved);
    pid = vfork();
    if (pid == 0) {
      // A host that dies, however it dies, takes the worker along.
      prctl(PR_SET_PDEATHSIG, SIGKILL);
      if (getppid() != parent) _exit(126);  // the host died before prctl took effect
      // A process group of its own: Ctrl-C at a terminal signals the host, which decides (tessera
      // render writes the image so far), not its workers in the middle of a pass.
      setpgid(0, 0);
      dup2(null_fd, STDIN_FILENO);
      dup2(out[1], STDOUT_FILENO);
      dup2(log_fd, STDERR_FILENO);
      // The host's caught, blocked or ignored signals must not keep the worker from stopping.
      struct sigaction dfl;
      std::memset(&dfl, 0, sizeof(dfl));
      dfl.sa_handler = SIG_DFL;
      for (int sig = 1; sig < NSIG; ++sig) {
        struct sigaction current;
        if (sig == SIGKILL || sig == SIGSTOP || sigaction(sig, nullptr, &current) != 0) continue;
        const bool ignored_stop =
            current.sa_handler == SIG_IGN &&
            (sig == SIGTERM || sig == SIGINT || sig == SIGHUP || sig == SIGPIPE || sig == SIGCHLD);
        if (current.sa_handler != SIG_DFL && (current.sa_handler != SIG_IGN || ignored_stop)) {
          sigaction(sig, &dfl, nullptr);
        }
      }
      sigset_t none;
      sigemptyset(&none);
      sigprocmask(SIG_SETMASK, &none, nullptr);
      // The result arena becomes descriptor 3 (dup2 clears close-on-exec; an arena that is
      // already 3 only needs it cleared). Whatever 3 held is one of the above, duplicated.
      int first_closed = 3;
      if (arena_fd >= 0) {
        if (arena_fd == kArenaChildFd) {
          fcntl(kArenaChildFd, F_SETFD, 0);
        } else {
          dup2(arena_fd, kArenaChildFd);
        }
        first_closed = kArenaChildFd + 1;
      }
      // Descriptors the application left inheritable stay with the application.
      if (syscall(SYS_close_range, static_cast<unsigned>(first_closed), ~0u, 0u) != 0) {
        for (int fd = first_closed; fd < 4096; ++fd) close(fd);
      }
      execve(argv[0], argv.data(), envp.data());
      // Why, in system calls only (this is still the vfork child): the host shows this line.
      const int err = errno;
      const char* why = err == ENOEXEC  ? "it is not a program this machine can run"
                        : err == ENOENT ? "it, or the interpreter it names, does not exist"
                        : err == EACCES ? "permission denied"
                                        : "errno ";
      char digits[16];
      size_t n = 0;
      if (why[0] == 'e') {
        for (int e = err; n == 0 || e > 0; e /= 10) digits[n++] = static_cast<char>('0' + e % 10);
      }
      auto say = [](const char* text, size_t size) {
        ssize_t ignored = write(STDERR_FILENO, text, size);
        (void)ignored;
      };
      say("tessera-worker: exec of ", 24);
      say(argv[0], std::strlen(argv[0]));
      say(" failed: ", 9);
      say(why, std::strlen(why));
      while (n > 0) say(&digits[--n], 1);
      say("\n", 1);
      _exit(127);
    }
    if (pid < 0) fork_errno = errno;
    pthread_sigmask(SIG_SETMASK, &saved, nullptr);
  });
  close(out[1]);
  out[1] = -1;
  close(log_fd);
  log_fd = -1;
  close(null_fd);
  null_fd = -1;
  if (process->arena_ != nullptr) process->arena_->CloseFd();  // the mapping stays
  if (pid < 0) {
    close_all();
    errno = fork_errno;
    return absl::UnavailableError(Errno("fork"));
  }
  process->pid_ = pid;

  // Wait for the one line the worker prints once it listens.
  std::string output;
  std::string failure;
  const absl::Time deadline = absl::Now() + options.start_timeout;
  while (true) {
    size_t newline = output.find('\n');
    if (newline != std::string::npos) {
      std::string line = output.substr(0, newline);
      if (absl::StartsWith(line, kReadyPrefix)) {
        process->address_ = line.substr(std::strlen(kReadyPrefix));
      } else {
        failure = absl::StrCat("printed '", line, "' instead of '", kReadyPrefix, "<address>'");
      }
      break;
    }
    int64_t remaining = absl::ToInt64Milliseconds(deadline - absl::Now());
    if (remaining <= 0) {
      failure = absl::StrCat("did not report listening within ",
                             absl::FormatDuration(options.start_timeout));
      break;
    }
    pollfd p{out[0], POLLIN, 0};
    int ready = poll(&p, 1, static_cast<int>(std::min<int64_t>(remaining, INT_MAX)));
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) continue;  // timeout: the deadline check above reports it
    char buf[512];
    ssize_t n = read(out[0], buf, sizeof(buf));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      // Stdout closed: the worker exited (or is about to).
      int status = 0;
      if (WaitFor(pid, absl::Seconds(2), &status)) {
        process->pid_ = -1;  // reaped
        failure = DescribeExit(status);
      } else {
        failure = "closed its standard output";
      }
      break;
    }
    output.append(buf, static_cast<size_t>(n));
  }
  close(out[0]);
  if (!failure.empty() || process->address_.empty()) {
    if (failure.empty()) failure = "printed an empty address";
    std::string log = process->LogTail();
    std::string message =
        absl::StrCat(kWorkerName, " (", options.binary, " ", listen, ") did not start: ", failure,
                     log.empty() ? std::string("; its stderr was empty")
                                 : absl::StrCat("; its stderr ends with:\n", log));
    return absl::UnavailableError(message);  // the destructor kills and reaps it
  }
  RelayStartupLines(process->LogTail(), options.index);
  return process;
}

std::string WorkerProcess::WaitForExit(absl::Duration timeout, bool* crashed) {
  // One reaper at a time: a second caller would find the child gone (ECHILD) and describe a
  // status it never saw ("exited with status 0" for a worker killed by signal 9).
  std::lock_guard<std::mutex> lock(exit_mu_);
  if (pid_ > 0) {
    int status = 0;
    if (WaitFor(pid_, timeout, &status)) {
      exit_ = DescribeExit(status);
      crashed_ = WIFSIGNALED(status) && WTERMSIG(status) != SIGKILL && WTERMSIG(status) != SIGTERM;
      pid_ = -1;
    }
  }
  if (crashed != nullptr) *crashed = crashed_;
  return exit_;
}

void WorkerProcess::Kill() {
  if (getpid() != host_pid_) return;  // a forked child's copy: the worker is the parent's
  {
    std::lock_guard<std::mutex> lock(exit_mu_);
    if (pid_ > 0) kill(pid_, SIGKILL);
  }
  bool crashed = false;
  WaitForExit(absl::InfiniteDuration(), &crashed);  // SIGKILL cannot be held off: it ends soon
}

WorkerProcess::~WorkerProcess() {
  // In a process forked from the host the worker and its directory are the parent's: leave them.
  if (getpid() != host_pid_) return;
  if (pid_ > 0) {
    int status = 0;
    kill(pid_, SIGTERM);
    kill(pid_, SIGCONT);  // a stopped worker (one that missed its deadline) must see the SIGTERM
    if (!WaitFor(pid_, stop_grace_, &status)) {
      kill(pid_, SIGKILL);
      WaitFor(pid_, absl::InfiniteDuration(), &status);
    }
  }
  if (!directory_.empty()) {
    RemoveDirectory(directory_);
    TrackDirectory(directory_, false);
  }
}

std::string WorkerProcess::LogTail(size_t max_bytes) const {
  int fd = open(log_path_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return "";
  off_t size = lseek(fd, 0, SEEK_END);
  off_t start = size > static_cast<off_t>(max_bytes) ? size - static_cast<off_t>(max_bytes) : 0;
  std::string tail(static_cast<size_t>(size - start), '\0');
  ssize_t n = pread(fd, tail.data(), tail.size(), start);
  close(fd);
  tail.resize(n > 0 ? static_cast<size_t>(n) : 0);
  return tail;
}

}  // namespace tessera::transport
