// tessera-soak: faults at random moments of a whole render, counted. Renders the tutorial (or any
// host command that writes one image) once without faults, then again and again while it SIGKILLs
// one worker, SIGKILLs two or three at the same moment, or SIGSTOPs one, each at a uniformly random
// moment from the host's start to the fault-free render's end (a worker not yet spawned at that
// moment is hit as soon as it appears: the spawn and the first state update are moments too). Every
// render must write the fault-free image's bytes, exit 0 and end within twice the fault-free time
// plus the silence deadline plus a margin (a render that ends past that is judged again against a
// fault-free render timed right after it: other work on the machine slows every render alike;
// one still running at three times the limit is killed and counted hung). Prints
// identical/different/failed/hung per fault and exits 1 unless every render was identical
// (docs/devices.md "Faults").
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "process_util.h"  // tests/e2e: children of a process by name
#include "tessera/cli_checks.h"

extern char** environ;

namespace tessera::soak {
namespace {

using Clock = std::chrono::steady_clock;

enum class Fault { kNone, kKill, kDoubleKill, kTripleKill, kStop };

const char* FaultName(Fault f) {
  switch (f) {
    case Fault::kNone:
      return "none";
    case Fault::kKill:
      return "kill";
    case Fault::kDoubleKill:
      return "double-kill";
    case Fault::kTripleKill:
      return "triple-kill";
    case Fault::kStop:
      return "stop";
  }
  return "?";
}

struct Options {
  std::string host = TESSERA_SOAK_TUTORIAL;
  int step = 8;
  int width = 1600;
  int height = 1200;
  std::string spec = "local:3";
  int rounds = 100;
  std::vector<std::string> faults = {"kill", "double-kill", "stop"};
  double worker_timeout = 10;  // TESSERA_WORKER_TIMEOUT for the host
  double margin = 5;      // seconds a render may take beyond the fault-free one and the deadline
  double time_limit = 0;  // seconds; 0: none. Rounds stop once it passed (at least 1 each)
  uint64_t seed = 1;
  std::string dir;  // where images and logs go; default a fresh directory under /tmp
  std::string worker_name = "tessera-worker";  // the workers' command name (/proc/PID/comm)
  bool keep = false;
};

struct Run {
  int exit_status = -1;  // waitpid status; -1: hung (killed by us)
  double seconds = 0;
  bool fault_done = false;  // the signal reached a worker before the host ended
  std::string image;        // bytes written
  std::string log_path;
};

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

std::string Tail(const std::string& text, size_t lines) {
  size_t at = text.size();
  while (lines > 0 && at > 0) {
    at = text.rfind('\n', at - 1);
    if (at == std::string::npos) return text;
    --lines;
  }
  return text.substr(at + 1);
}

class Soak {
 public:
  explicit Soak(Options o) : o_(std::move(o)), rng_(o_.seed) {}

  // Starts the host; runs `fault` at `at` seconds after its start; waits for it up to `limit`.
  Run RenderOnce(const std::string& name, Fault fault, double at, double limit) {
    Run run;
    const std::string out = o_.dir + "/" + name + ".png";
    run.log_path = o_.dir + "/" + name + ".log";
    std::remove(out.c_str());
    std::vector<std::string> args = {o_.host,
                                     "--step",
                                     std::to_string(o_.step),
                                     "--width",
                                     std::to_string(o_.width),
                                     "--height",
                                     std::to_string(o_.height),
                                     "--out",
                                     out};
    std::vector<std::string> env_strings = {
        "TESSERA_DEVICES=" + o_.spec,
        "TESSERA_WORKER_TIMEOUT=" + std::to_string(o_.worker_timeout)};
    for (char** e = environ; *e != nullptr; ++e) {
      const std::string s = *e;
      if (s.rfind("TESSERA_DEVICES=", 0) != 0 && s.rfind("TESSERA_WORKER_TIMEOUT=", 0) != 0) {
        env_strings.push_back(s);
      }
    }
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    std::vector<char*> envp;
    for (std::string& e : env_strings) envp.push_back(e.data());
    envp.push_back(nullptr);

    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, run.log_path.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
    pid_t host = -1;
    const auto start = Clock::now();
    const int rc = posix_spawn(&host, argv[0], &actions, nullptr, argv.data(), envp.data());
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) {
      std::fprintf(stderr, "tessera-soak: cannot start %s (log %s): %s\n", argv[0],
                   run.log_path.c_str(), std::strerror(rc));
      std::exit(1);
    }
    const auto fault_at =
        start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(at));
    const auto give_up =
        start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(limit));
    const size_t victims = fault == Fault::kDoubleKill ? 2 : fault == Fault::kTripleKill ? 3 : 1;
    bool pending = fault != Fault::kNone;
    while (true) {
      int status = 0;
      const pid_t r = waitpid(host, &status, WNOHANG);
      if (r == host) {
        run.exit_status = status;
        break;
      }
      const auto now = Clock::now();
      if (now >= give_up) {
        kill(host, SIGKILL);  // its workers follow (PR_SET_PDEATHSIG)
        waitpid(host, &status, 0);
        run.exit_status = -1;
        break;
      }
      if (pending && now >= fault_at) {
        std::vector<pid_t> workers = e2e::ChildrenNamed(host, o_.worker_name);
        if (workers.size() >= victims) {
          std::shuffle(workers.begin(), workers.end(), rng_);
          const int sig = fault == Fault::kStop ? SIGSTOP : SIGKILL;
          for (size_t i = 0; i < victims; ++i) kill(workers[i], sig);
          pending = false;
          run.fault_done = true;
        }
      }
      std::this_thread::sleep_for(std::chrono::microseconds(pending ? 200 : 2000));
    }
    run.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    run.image = ReadFile(out);
    if (!o_.keep) std::remove(out.c_str());
    return run;
  }

  int Main() {
    if (o_.dir.empty()) {
      char templ[] = "/tmp/tessera-soak-XXXXXX";
      if (mkdtemp(templ) == nullptr) {
        std::perror("tessera-soak: mkdtemp");
        return 1;
      }
      o_.dir = templ;
    } else if (std::error_code ec; !std::filesystem::is_directory(o_.dir, ec) &&
                                   !std::filesystem::create_directories(o_.dir, ec)) {
      std::fprintf(stderr, "tessera-soak: --dir %s: %s\n", o_.dir.c_str(), ec.message().c_str());
      return 1;
    }
    std::printf("tessera-soak: %s --step %d %dx%d on %s, TESSERA_WORKER_TIMEOUT=%g, seed %llu\n",
                o_.host.c_str(), o_.step, o_.width, o_.height, o_.spec.c_str(), o_.worker_timeout,
                static_cast<unsigned long long>(o_.seed));
    // The fault-free render: the image every other render must write, and how long one takes
    // (the slower of two, so that a noisy first start does not make the moments too early).
    Run reference = RenderOnce("reference", Fault::kNone, 0, 600);
    if (reference.exit_status != 0 || reference.image.empty()) {
      std::fprintf(stderr, "tessera-soak: the fault-free render failed (log %s):\n%s\n",
                   reference.log_path.c_str(), Tail(ReadFile(reference.log_path), 20).c_str());
      return 1;
    }
    Run again = RenderOnce("reference2", Fault::kNone, 0, 600);
    if (again.exit_status != 0 || again.image != reference.image) {
      std::fprintf(stderr, "tessera-soak: two fault-free renders differ or the second failed\n");
      return 1;
    }
    const double span = std::max(reference.seconds, again.seconds);
    // A render that lost a device waits up to the deadline (a stopped worker), then runs what is
    // left on fewer devices, which takes longer than the fault-free render: twice as long covers
    // three workers down to one. A hang is unbounded; this only has to tell it from slowness.
    const double limit = 2 * span + o_.worker_timeout + o_.margin;
    std::printf("fault-free render: %.2f s; moments uniform in [0, %.2f] s; hung after %.1f s\n",
                span, span, limit);
    std::fflush(stdout);

    const auto began = Clock::now();
    std::uniform_real_distribution<double> moment(0.0, span);
    bool all_good = true;
    for (const std::string& f : o_.faults) {
      const Fault fault = f == "kill"          ? Fault::kKill
                          : f == "double-kill" ? Fault::kDoubleKill
                          : f == "triple-kill" ? Fault::kTripleKill
                                               : Fault::kStop;
      int identical = 0, different = 0, failed = 0, hung = 0, missed = 0, rounds = 0;
      double slowest = 0;
      for (int i = 0; i < o_.rounds; ++i) {
        if (i > 0 && o_.time_limit > 0 &&
            std::chrono::duration<double>(Clock::now() - began).count() >
                o_.time_limit * (&f - o_.faults.data() + 1) / o_.faults.size()) {
          break;  // this fault's share of the time is spent
        }
        const double at = moment(rng_);
        const std::string name = std::string(FaultName(fault)) + "-" + std::to_string(i);
        // A render is given three times the limit before it is killed, and one that ended past
        // the limit is judged against what a fault-free render takes now: other work on the
        // machine slows every render alike, and a hang is unbounded, not a little late.
        Run run = RenderOnce(name, fault, at, 3 * limit);
        ++rounds;
        slowest = std::max(slowest, run.seconds);
        if (!run.fault_done) ++missed;
        const char* verdict = nullptr;
        if (run.exit_status != -1 && run.seconds > limit) {
          const Run now = RenderOnce(name + "-fault-free", Fault::kNone, 0, 600);
          const double now_limit = 2 * std::max(span, now.seconds) + o_.worker_timeout + o_.margin;
          std::printf(
              "  %s at %.3f s: ended after %.2f s, past the limit; a fault-free render "
              "now takes %.2f s, so the limit is %.1f s\n",
              name.c_str(), at, run.seconds, now.seconds, now_limit);
          if (run.seconds > now_limit) run.exit_status = -1;
          if (!o_.keep) std::remove(now.log_path.c_str());
        }
        if (run.exit_status == -1) {
          ++hung;
          verdict = "hung";
        } else if (!WIFEXITED(run.exit_status) || WEXITSTATUS(run.exit_status) != 0) {
          ++failed;
          verdict = "failed";
        } else if (run.image != reference.image) {
          ++different;
          verdict = "different";
        } else {
          ++identical;
        }
        if (verdict != nullptr) {
          all_good = false;
          std::printf("  %s at %.3f s: %s after %.2f s (log %s):\n%s\n", name.c_str(), at, verdict,
                      run.seconds, run.log_path.c_str(), Tail(ReadFile(run.log_path), 8).c_str());
        } else if (!o_.keep) {
          std::remove(run.log_path.c_str());
        }
        std::fflush(stdout);
      }
      std::printf(
          "%-12s rounds %3d: identical %3d  different %d  failed %d  hung %d  (slowest "
          "%.2f s; %d ended before the fault)\n",
          FaultName(fault), rounds, identical, different, failed, hung, slowest, missed);
      std::fflush(stdout);
    }
    if (!o_.keep && all_good) {
      std::remove(reference.log_path.c_str());
      std::remove(again.log_path.c_str());
      rmdir(o_.dir.c_str());
    }
    return all_good ? 0 : 1;
  }

 private:
  Options o_;
  std::mt19937_64 rng_;
};

}  // namespace
}  // namespace tessera::soak

int main(int argc, char** argv) {
  tessera::soak::Options o;
  CLI::App app{
      "Renders the tutorial again and again while killing or stopping its worker processes at "
      "random moments; every render must match the fault-free one.\n"
      "  tessera-soak --rounds 100                 # 100 each of kill, double-kill, stop\n"
      "  tessera-soak --rounds 5 --faults stop --worker-timeout 1 --width 320 --height 240",
      "tessera-soak"};
  app.add_option("--host", o.host, "the host program (tessera-tutorial's options)")
      ->capture_default_str();
  app.add_option("--step", o.step, "tutorial step")->capture_default_str();
  app.add_option("--width", o.width, "image width")->capture_default_str();
  app.add_option("--height", o.height, "image height")->capture_default_str();
  app.add_option("--devices", o.spec, "TESSERA_DEVICES for the host")->capture_default_str();
  app.add_option("--rounds", o.rounds, "renders per fault")
      ->capture_default_str()
      ->check(tessera::cli::kPositive);
  app.add_option("--faults", o.faults,
                 "which faults: kill, double-kill, triple-kill (one, two or three workers "
                 "SIGKILLed at one moment), stop (one SIGSTOPped)")
      ->delimiter(',')
      ->check(CLI::IsMember({"kill", "double-kill", "triple-kill", "stop"}))
      ->capture_default_str();
  app.add_option("--worker-timeout", o.worker_timeout,
                 "TESSERA_WORKER_TIMEOUT (seconds) for the host: the silence deadline")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 3600.0));
  app.add_option("--margin", o.margin,
                 "seconds beyond twice the fault-free time + deadline before hung")
      ->capture_default_str();
  app.add_option("--time-limit", o.time_limit,
                 "stop starting renders after this many seconds (0: none), shared among faults")
      ->capture_default_str();
  app.add_option("--seed", o.seed, "random seed (moments and victims)")->capture_default_str();
  app.add_option("--dir", o.dir, "directory for images and logs (default: a new one in /tmp)");
  app.add_flag("--keep", o.keep, "keep every image and log");
  app.add_option("--worker-name", o.worker_name,
                 "the command name of the host's worker processes (/proc/PID/comm; with "
                 "tools/bundle-for-device.sh's loader it is ld-linux-x86-64)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  return tessera::soak::Soak(std::move(o)).Main();
}
