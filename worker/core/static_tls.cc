#include "tessera/worker/static_tls.h"

#include <cstdlib>

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

}  // namespace tessera::worker
