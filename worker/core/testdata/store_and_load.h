// A module file put through a device's module cache in tests: stored under its hash, as the bytes
// a host sends are, and loaded from there.
#ifndef TESSERA_WORKER_CORE_TESTDATA_STORE_AND_LOAD_H_
#define TESSERA_WORKER_CORE_TESTDATA_STORE_AND_LOAD_H_

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>

#include "module.h"
#include "tessera/scheduler/module_hash.h"

namespace tessera::worker::testing {

inline std::string ReadModuleFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The module at `path` loaded through `cache`; null, with the test failed, if that fails.
inline const Module* StoreAndLoad(ModuleCache& cache, const std::string& path) {
  const std::string bytes = ReadModuleFile(path);
  EXPECT_FALSE(bytes.empty()) << path;
  const std::string hash = scheduler::ModuleHash(bytes);
  const absl::Status stored = cache.Store(hash, bytes);
  EXPECT_TRUE(stored.ok()) << stored;
  absl::StatusOr<const Module*> m = cache.Load(hash, path);
  EXPECT_TRUE(m.ok()) << m.status();
  return m.ok() ? *m : nullptr;
}

}  // namespace tessera::worker::testing

#endif  // TESSERA_WORKER_CORE_TESTDATA_STORE_AND_LOAD_H_
