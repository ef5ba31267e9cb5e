#include "tessera/worker/static_tls.h"

#include <sys/auxv.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <vector>

#include "absl/strings/match.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"

namespace tessera::worker {
namespace {

constexpr absl::string_view kTunable = "glibc.rtld.optional_static_tls";

}  // namespace

size_t RequestedModuleStaticTls(absl::string_view tunables) {
  size_t reserved = 0;
  for (absl::string_view pair : absl::StrSplit(tunables, ':')) {
    std::pair<absl::string_view, absl::string_view> kv = absl::StrSplit(pair, '=');
    if (kv.first != kTunable) continue;
    size_t value = 0;
    const bool hex = absl::StartsWithIgnoreCase(kv.second, "0x");
    if (hex ? absl::SimpleHexAtoi(kv.second.substr(2), &value)
            : absl::SimpleAtoi(kv.second, &value)) {
      reserved = value;
    }
  }
  return reserved;
}

bool ModuleStaticTlsReserved() {
  static const bool reserved = [] {
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    return tunables != nullptr && RequestedModuleStaticTls(tunables) >= kModuleStaticTlsBytes;
  }();
  return reserved;
}

std::string TunablesWithModuleStaticTls(const char* current) {
  const std::string setting = absl::StrCat(kTunable, "=", kModuleStaticTlsBytes);
  if (current == nullptr || *current == '\0') return setting;
  return absl::StrCat(current, ":", setting);  // the last setting wins
}

void RestartWithModuleStaticTls(char** argv, const char* restarted) {
  // AT_BASE is where the kernel put the program's interpreter: 0 when the program was started
  // through the dynamic loader (`ld-linux-x86-64.so.2 --library-path DIR tessera-worker ...`),
  // whose executable is the loader, which the program's own arguments would not start again.
  if (ModuleStaticTlsReserved() || std::getenv(restarted) != nullptr || getauxval(AT_BASE) == 0) {
    return;
  }
  std::string tunables =
      absl::StrCat("GLIBC_TUNABLES=", TunablesWithModuleStaticTls(std::getenv("GLIBC_TUNABLES")));
  std::string marker = absl::StrCat(restarted, "=1");
  std::vector<char*> env;
  for (char** e = environ; *e != nullptr; ++e) {
    if (std::strncmp(*e, "GLIBC_TUNABLES=", 15) != 0) env.push_back(*e);
  }
  env.push_back(tunables.data());
  env.push_back(marker.data());
  env.push_back(nullptr);
  // By its own path, not /proc/self/exe: the process's name (ps, pkill) is the file's.
  char self[4096];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof(self) - 1);
  if (n <= 0 || static_cast<size_t>(n) >= sizeof(self) - 1) return;
  self[n] = '\0';
  execve(self, argv, env.data());
}

}  // namespace tessera::worker
