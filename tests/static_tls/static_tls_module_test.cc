// Program modules' initial-exec builds (tessera/worker/static_tls.h, docs/programs.md
// "Thread-local storage"): the GLIBC_TUNABLES a worker starts with, the build each module carries,
// and which build a device's module cache loads. ctest runs this binary with and without static
// TLS reserved for modules (TESSERA_TEST_EXPECT_ROOM says which).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "module.h"
#include "tessera/scheduler/module_file.h"
#include "tessera/scheduler/module_hash.h"
#include "tessera/worker/static_tls.h"
#include "testdata/store_and_load.h"

namespace tessera::worker {
namespace {

std::string ModulePath(const char* name) {
  return std::string(TESSERA_TEST_MODULE_DIR) + "/" + name + ".so";
}

// A cache of the build tree for each of ctest's runs (they may run at once).
std::string CacheDir() {
  const char* room = std::getenv("TESSERA_TEST_EXPECT_ROOM");
  return std::string(TESSERA_STATIC_TLS_MODULE_CACHE) + (room != nullptr ? room : "");
}

// The module at `path`, stored in and loaded from that cache.
const Module* Load(const std::string& path) {
  static ModuleCache cache(CacheDir());
  return testing::StoreAndLoad(cache, path);
}

TEST(StaticTlsTest, ReadsTheRoomGlibcIsAskedFor) {
  EXPECT_EQ(RequestedModuleStaticTls(""), 0u);
  EXPECT_EQ(RequestedModuleStaticTls("glibc.malloc.arena_max=2"), 0u);
  EXPECT_EQ(RequestedModuleStaticTls("glibc.rtld.optional_static_tls=65536"), 65536u);
  EXPECT_EQ(
      RequestedModuleStaticTls("glibc.malloc.arena_max=2:glibc.rtld.optional_static_tls=0x10000"),
      65536u);
  // glibc takes the last setting.
  EXPECT_EQ(RequestedModuleStaticTls(
                "glibc.rtld.optional_static_tls=100000:glibc.rtld.optional_static_tls=512"),
            512u);
  EXPECT_EQ(RequestedModuleStaticTls("glibc.rtld.optional_static_tls=lots"), 0u);
  EXPECT_EQ(RequestedModuleStaticTls("glibc.rtld.optional_static_tls"), 0u);
}

TEST(StaticTlsTest, WorkersAddTheRoomToTheirTunables) {
  EXPECT_EQ(RequestedModuleStaticTls(TunablesWithModuleStaticTls(nullptr)), kModuleStaticTlsBytes);
  EXPECT_EQ(RequestedModuleStaticTls(TunablesWithModuleStaticTls("")), kModuleStaticTlsBytes);
  const std::string kept = TunablesWithModuleStaticTls("glibc.malloc.arena_max=2");
  EXPECT_EQ(kept.rfind("glibc.malloc.arena_max=2:", 0), 0u) << kept;
  EXPECT_EQ(RequestedModuleStaticTls(kept), kModuleStaticTlsBytes);
  // A smaller setting of the user's own is overridden (the last one counts).
  EXPECT_EQ(
      RequestedModuleStaticTls(TunablesWithModuleStaticTls("glibc.rtld.optional_static_tls=512")),
      kModuleStaticTlsBytes);
}

TEST(StaticTlsTest, ModulesCarryTheirInitialExecBuild) {
  const std::string bytes = testing::ReadModuleFile(ModulePath("static_tls_programs"));
  ASSERT_FALSE(bytes.empty());
  const absl::string_view build = scheduler::FindElfSection(bytes, scheduler::kInitialExecSection);
  ASSERT_FALSE(build.empty()) << "tessera_add_program_module embedded no initial-exec build";
  // A whole module of its own, with the same programs, and nothing nested in it.
  EXPECT_TRUE(scheduler::CheckModuleBytes(build, "write_values", /*require_init=*/true).ok());
  EXPECT_TRUE(scheduler::FindElfSection(build, scheduler::kInitialExecSection).empty());
  // Whatever the bytes, no section is read from outside them.
  EXPECT_TRUE(scheduler::FindElfSection(bytes.substr(0, 64), ".text").empty());
  EXPECT_TRUE(
      scheduler::FindElfSection(bytes.substr(0, bytes.size() / 2), scheduler::kInitialExecSection)
          .empty());
  EXPECT_TRUE(scheduler::FindElfSection("not an ELF file", ".text").empty());
}

TEST(StaticTlsTest, TheCacheLoadsTheInitialExecBuildWhereThereIsRoom) {
  const char* expect = std::getenv("TESSERA_TEST_EXPECT_ROOM");
  ASSERT_NE(expect, nullptr) << "ctest sets TESSERA_TEST_EXPECT_ROOM";
  const bool room = std::string(expect) == "1";
  ASSERT_EQ(ModuleStaticTlsReserved(), room);
  // A copy already beside the module is not trusted: only bytes taken from the module file, which
  // the cache checks against its hash, are loaded.
  const std::string bytes = testing::ReadModuleFile(ModulePath("static_tls_programs"));
  const std::string copy = CacheDir() + "/" + scheduler::ModuleHash(bytes) + ".so.ie";
  std::filesystem::create_directories(CacheDir());
  std::ofstream(copy, std::ios::binary | std::ios::trunc) << "planted, not a module";
  const Module* m = Load(ModulePath("static_tls_programs"));
  ASSERT_NE(m, nullptr);
  EXPECT_EQ(m->initial_exec(), room);
  if (room) {
    EXPECT_EQ(testing::ReadModuleFile(copy),
              std::string(scheduler::FindElfSection(bytes, scheduler::kInitialExecSection)));
  }
  // 128 KiB of thread-locals do not fit the room: the module itself is loaded.
  const Module* big = Load(ModulePath("static_tls_big"));
  ASSERT_NE(big, nullptr);
  EXPECT_FALSE(big->initial_exec());
  EXPECT_NE(big->Function("write_through_scratch"), nullptr);
}

}  // namespace
}  // namespace tessera::worker
