// Runs a command without a shell (no quoting pitfalls) and captures stdout and stderr together.
#ifndef TESSERA_API_SRC_SUBPROCESS_H_
#define TESSERA_API_SRC_SUBPROCESS_H_

#include <string>
#include <vector>

#include "absl/status/statusor.h"

namespace tessera::api {

struct CommandResult {
  int exit_code = -1;  // -1 when killed by a signal
  std::string output;
};

// `argv[0]` is looked up in PATH. Fails only when the command cannot be started.
absl::StatusOr<CommandResult> RunCommand(const std::vector<std::string>& argv);

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_SUBPROCESS_H_
