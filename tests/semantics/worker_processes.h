// The tessera-worker processes a host spawned (local:N): tests kill, stop and count them.
#ifndef TESSERA_TESTS_SEMANTICS_WORKER_PROCESSES_H_
#define TESSERA_TESTS_SEMANTICS_WORKER_PROCESSES_H_

#include <sys/types.h>

#include <algorithm>
#include <vector>

#include "../e2e/process_util.h"

namespace tessera::testing {

// Live (not zombie) tessera-worker children of `parent`, in pid order.
inline std::vector<pid_t> WorkersOf(pid_t parent) {
  std::vector<pid_t> workers = e2e::ChildrenNamed(parent, "tessera-worker");
  std::sort(workers.begin(), workers.end());
  return workers;
}

}  // namespace tessera::testing

#endif  // TESSERA_TESTS_SEMANTICS_WORKER_PROCESSES_H_
