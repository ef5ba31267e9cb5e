// The tessera-worker processes a host spawned (local:N), found through /proc: tests kill, stop
// and count them.
#ifndef TESSERA_TESTS_SEMANTICS_WORKER_PROCESSES_H_
#define TESSERA_TESTS_SEMANTICS_WORKER_PROCESSES_H_

#include <dirent.h>
#include <sys/types.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

namespace tessera::testing {

// Live (not zombie) tessera-worker children of `parent`, in pid order.
inline std::vector<pid_t> WorkersOf(pid_t parent) {
  std::vector<pid_t> workers;
  DIR* proc = opendir("/proc");
  if (proc == nullptr) return workers;
  while (dirent* entry = readdir(proc)) {
    char* end = nullptr;
    const long pid = std::strtol(entry->d_name, &end, 10);
    if (pid <= 0 || *end != '\0') continue;
    std::ifstream in(std::string("/proc/") + entry->d_name + "/stat");
    std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const size_t open = stat.find('('), close = stat.rfind(')');
    if (open == std::string::npos || close == std::string::npos) continue;
    std::istringstream fields(stat.substr(close + 1));
    std::string state;
    long ppid = 0;
    fields >> state >> ppid;
    if (ppid == parent && state != "Z" &&
        stat.substr(open + 1, close - open - 1) == "tessera-worker") {
      workers.push_back(static_cast<pid_t>(pid));
    }
  }
  closedir(proc);
  std::sort(workers.begin(), workers.end());
  return workers;
}

}  // namespace tessera::testing

#endif  // TESSERA_TESTS_SEMANTICS_WORKER_PROCESSES_H_
