#include "common/embree_viewer.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace tessera::bench {
std::string ShellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'') {
      q += "'\\''";
    } else {
      q += c;
    }
  }
  return q + "'";
}

std::optional<std::string> FindExecutable(const std::string& name) {
  if (name.empty()) return std::nullopt;
  if (name.find('/') != std::string::npos) {
    if (access(name.c_str(), X_OK) == 0) return name;
    return std::nullopt;
  }
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "/usr/local/bin:/usr/bin:/bin");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    std::string candidate = (dir.empty() ? "." : dir) + "/" + name;
    if (access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return std::nullopt;
}

std::optional<double> ParseBenchmarkValue(const std::string& output, const std::string& key) {
  const std::string prefix = key + " ";
  std::stringstream lines(output);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.compare(0, prefix.size(), prefix) != 0) continue;
    char* end = nullptr;
    double value = std::strtod(line.c_str() + prefix.size(), &end);
    if (end != line.c_str() + prefix.size()) return value;
  }
  return std::nullopt;
}

std::optional<double> ParseMraysAverage(const std::string& output) {
  return ParseBenchmarkValue(output, "BENCHMARK_RENDER_MRAYPS_AVG");
}

std::string RunCommand(const std::string& command, const std::string& what) {
  const std::string cmd = command + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr) throw std::runtime_error("cannot run: " + command);
  std::string output;
  char chunk[4096];
  size_t n;
  while ((n = std::fread(chunk, 1, sizeof(chunk), pipe)) > 0) output.append(chunk, n);
  int status = pclose(pipe);
  if (status == -1 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw std::runtime_error(what + " failed (status " + std::to_string(status) + "): " + command +
                             "\n" + output);
  }
  return output;
}

double RunEmbreeViewer(const ViewerRun& run, std::string* command_out) {
  std::string cmd = ShellQuote(run.viewer) + " -i " + ShellQuote(run.model) + " --size " +
                    std::to_string(run.width) + " " + std::to_string(run.height) +
                    " --shader eyelight --benchmark " + std::to_string(run.warmup) + " " +
                    std::to_string(run.runs);
  if (run.threads > 0) cmd += " --threads " + std::to_string(run.threads);
  for (const std::string& flag : run.camera_flags) cmd += " " + ShellQuote(flag);
  if (command_out != nullptr) *command_out = cmd;
  const std::string output = RunCommand(cmd, "Embree viewer");
  std::optional<double> mrays = ParseMraysAverage(output);
  if (!mrays) {
    throw std::runtime_error("Embree viewer printed no BENCHMARK_RENDER_MRAYPS_AVG line:\n" +
                             output);
  }
  return *mrays;
}

}  // namespace tessera::bench
