// The module cache: modules stored and loaded by content hash in a directory, checked against
// their hash, written once.
#include "module_store.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "module.h"
#include "testdata/module_delta.h"

namespace tessera::worker {
namespace {

namespace fs = std::filesystem;

const std::string kModule = std::string(TESSERA_TEST_MODULE_DIR) + "/worker_core_test_programs.so";

// A fresh directory under the system's temporary directory, removed afterwards.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (fs::temp_directory_path() / "tessera-module-test-XXXXXX").string();
    path_ = mkdtemp(pattern.data()) != nullptr ? pattern : "";
  }
  ~TempDir() {
    std::error_code ec;
    if (!path_.empty()) fs::remove_all(path_, ec);
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// Every device of this test binary (inproc_device_test.cc included) stores modules in a private
// directory rather than the user's cache.
class PrivateModuleCache : public ::testing::Environment {
 public:
  void SetUp() override { ModuleCache::Get().SetDirectory(dir_.path()); }

 private:
  TempDir dir_;
};
[[maybe_unused]] const auto* const kPrivateModuleCache =
    ::testing::AddGlobalTestEnvironment(new PrivateModuleCache);

// Sets an environment variable for one scope; restores the previous value after.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    const char* old = std::getenv(name);
    had_ = old != nullptr;
    if (had_) old_ = old;
    if (value != nullptr) {
      setenv(name, value, 1);
    } else {
      unsetenv(name);
    }
  }
  ~ScopedEnv() {
    if (had_) {
      setenv(name_, old_.c_str(), 1);
    } else {
      unsetenv(name_);
    }
  }

 private:
  const char* name_;
  bool had_ = false;
  std::string old_;
};

std::string ReadFile(const std::string& path) { return testing::ReadModuleFile(path); }

TEST(ModuleStoreTest, ModuleHashIsLowercaseHexSha256) {
  EXPECT_EQ(ModuleHash("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(ModuleHash(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  const std::string bytes = ReadFile(kModule);
  ASSERT_FALSE(bytes.empty());
  EXPECT_EQ(ModuleHash(bytes), testing::Sha256Hex(bytes));
  EXPECT_TRUE(IsModuleHash(ModuleHash("abc")));
  EXPECT_FALSE(IsModuleHash("BA7816BF8F01CFEA414140DE5DAE2223B00361A396177A9CB410FF61F20015AD"));
  EXPECT_FALSE(IsModuleHash("../../../../etc/passwd"));
  EXPECT_FALSE(IsModuleHash(std::string(16, 'a')));
}

TEST(ModuleStoreTest, DefaultDirectoryFollowsTheEnvironment) {
  ScopedEnv module_cache("TESSERA_MODULE_CACHE", "/srv/modules");
  ScopedEnv cache_dir("TESSERA_CACHE_DIR", "/srv/cache");
  ScopedEnv xdg("XDG_CACHE_HOME", "/srv/xdg");
  ScopedEnv home("HOME", "/home/someone");
  EXPECT_EQ(DefaultModuleCacheDir(), "/srv/modules");
  unsetenv("TESSERA_MODULE_CACHE");
  EXPECT_EQ(DefaultModuleCacheDir(), "/srv/cache");
  unsetenv("TESSERA_CACHE_DIR");
  EXPECT_EQ(DefaultModuleCacheDir(), "/srv/xdg/tessera/modules");
  unsetenv("XDG_CACHE_HOME");
  EXPECT_EQ(DefaultModuleCacheDir(), "/home/someone/.cache/tessera/modules");
}

TEST(ModuleStoreTest, ModuleShippedByBytesLoadsFromTheCacheDirectory) {
  TempDir temp;
  const std::string dir = temp.path() + "/nested/modules";  // created on first use
  ScopedEnv env("TESSERA_MODULE_CACHE", dir.c_str());
  ModuleCache cache;
  EXPECT_EQ(cache.directory(), dir);
  EXPECT_TRUE(fs::is_directory(dir));

  const std::string bytes = ReadFile(kModule);
  const std::string hash = ModuleHash(bytes);
  EXPECT_FALSE(cache.Has(hash));
  absl::StatusOr<const Module*> missing = cache.Load(hash, "/host/programs.so");
  EXPECT_EQ(missing.status().code(), absl::StatusCode::kNotFound);
  EXPECT_NE(missing.status().message().find(hash), std::string::npos) << missing.status();

  ASSERT_TRUE(cache.Store(hash, bytes).ok());
  EXPECT_TRUE(cache.Has(hash));
  const std::string file = dir + "/" + hash + ".so";
  EXPECT_EQ(ReadFile(file), bytes);
  absl::StatusOr<const Module*> module = cache.Load(hash, "/host/programs.so");
  ASSERT_TRUE(module.ok()) << module.status();
  EXPECT_EQ((*module)->path(), file);
  EXPECT_NE((*module)->Function("write_index"), nullptr);
  // Nothing else is left in the directory (no temporary files).
  int entries = 0;
  for (const auto& entry : fs::directory_iterator(dir)) entries += entry.exists() ? 1 : 0;
  EXPECT_EQ(entries, 1);
}

TEST(ModuleStoreTest, StoredModuleIsNotRewritten) {
  TempDir temp;
  const std::string bytes = ReadFile(kModule);
  const std::string hash = ModuleHash(bytes);
  const std::string file = temp.path() + "/" + hash + ".so";
  {
    ModuleCache cache(temp.path());
    ASSERT_TRUE(cache.Store(hash, bytes).ok());
  }
  const auto long_ago = fs::file_time_type::clock::now() - std::chrono::hours(24);
  fs::last_write_time(file, long_ago);
  struct stat before {};
  ASSERT_EQ(stat(file.c_str(), &before), 0);

  // Another process (a fresh cache) that receives the same module finds it stored.
  ModuleCache again(temp.path());
  EXPECT_TRUE(again.Has(hash));
  ASSERT_TRUE(again.Store(hash, bytes).ok());
  struct stat after {};
  ASSERT_EQ(stat(file.c_str(), &after), 0);
  EXPECT_EQ(after.st_ino, before.st_ino);  // the same file, not a new one renamed over it
  // Finding it counts as using it: trimming keeps it longest.
  EXPECT_GT(fs::last_write_time(file), fs::file_time_type::clock::now() - std::chrono::hours(1));
}

// A file of `bytes` bytes last used `age` ago.
void WriteAged(const std::string& path, size_t bytes, std::chrono::seconds age) {
  std::ofstream(path, std::ios::binary) << std::string(bytes, 'x');
  fs::last_write_time(path, fs::file_time_type::clock::now() - age);
}

TEST(ModuleStoreTest, TrimmingRemovesTheLeastRecentlyUsedModulesFirst) {
  TempDir temp;
  using std::chrono::hours;
  const std::string a = ModuleHash("a"), b = ModuleHash("b"), c = ModuleHash("c"),
                    d = ModuleHash("d");
  auto path = [&](const std::string& name) { return temp.path() + "/" + name; };
  WriteAged(path(a + ".so"), 1000, hours(5));  // the oldest, but the one just stored
  WriteAged(path(b + ".so"), 1000, hours(4));
  WriteAged(path(c + ".so"), 1000, hours(3));
  WriteAged(path(d + ".so"), 1000, std::chrono::seconds(0));         // in use
  WriteAged(path("notes.txt"), 5000, hours(9));                      // not a module: left alone
  WriteAged(path(b + ".so.1-2.tmp"), 100, hours(2));                 // a write cut short long ago
  WriteAged(path(c + ".so.3-4.tmp"), 100, std::chrono::seconds(0));  // a write under way
  // The host's compile cache shares the directory: its modules count and go first when older.
  WriteAged(path("0123456789abcdef.so"), 1000, hours(6));
  WriteAged(path("0123456789abcdef.77-88.cpp"), 100, hours(2));  // a compile cut short
  WriteAged(path("0123456789ABCDEF.so"), 1000, hours(9));        // not a name of ours

  EXPECT_EQ(TrimModuleCache(temp.path(), 2500, a), 3u);
  EXPECT_TRUE(fs::exists(path(a + ".so")));
  EXPECT_FALSE(fs::exists(path(b + ".so")));
  EXPECT_FALSE(fs::exists(path(c + ".so")));
  EXPECT_TRUE(fs::exists(path(d + ".so")));
  EXPECT_TRUE(fs::exists(path("notes.txt")));
  EXPECT_FALSE(fs::exists(path(b + ".so.1-2.tmp")));
  EXPECT_TRUE(fs::exists(path(c + ".so.3-4.tmp")));
  EXPECT_FALSE(fs::exists(path("0123456789abcdef.so")));
  EXPECT_FALSE(fs::exists(path("0123456789abcdef.77-88.cpp")));
  EXPECT_TRUE(fs::exists(path("0123456789ABCDEF.so")));

  // Within the limit nothing goes.
  EXPECT_EQ(TrimModuleCache(temp.path(), 1 << 20, ""), 0u);
  EXPECT_TRUE(fs::exists(path(a + ".so")));
}

// The host compile cache's dependency lists and the compiler's temporaries go too: each edit of
// a source leaves a list behind.
TEST(ModuleStoreTest, TrimmingTakesDependencyListsAndCompilerTemporaries) {
  TempDir temp;
  const std::string a = ModuleHash("a");
  auto path = [&](const std::string& name) { return temp.path() + "/" + name; };
  WriteAged(path(a + ".so"), 1000, std::chrono::seconds(0));
  WriteAged(path("0123456789abcdef.deps"), 3000, std::chrono::hours(6));
  WriteAged(path("0123456789abcdef.12-34.tmp.d"), 100, std::chrono::hours(2));
  TrimModuleCache(temp.path(), 2000, a);
  EXPECT_TRUE(fs::exists(path(a + ".so")));
  EXPECT_FALSE(fs::exists(path("0123456789abcdef.deps")));
  EXPECT_FALSE(fs::exists(path("0123456789abcdef.12-34.tmp.d")));
}

// A module's initial-exec build, written out beside it by the device that loaded it
// (<hash>.so.ie), counts and goes like a module; it is written out again when needed.
TEST(ModuleStoreTest, TrimmingTakesInitialExecBuilds) {
  TempDir temp;
  const std::string a = ModuleHash("a"), b = ModuleHash("b");
  auto path = [&](const std::string& name) { return temp.path() + "/" + name; };
  WriteAged(path(a + ".so"), 1000, std::chrono::seconds(0));
  WriteAged(path(a + ".so.ie"), 1000, std::chrono::hours(7));  // the module kept: kept too
  WriteAged(path(b + ".so.ie"), 1000, std::chrono::hours(6));
  WriteAged(path(b + ".so"), 1000, std::chrono::hours(5));
  EXPECT_EQ(TrimModuleCache(temp.path(), 2500, a), 2u);
  EXPECT_TRUE(fs::exists(path(a + ".so")));
  EXPECT_TRUE(fs::exists(path(a + ".so.ie")));
  EXPECT_FALSE(fs::exists(path(b + ".so.ie")));
  EXPECT_FALSE(fs::exists(path(b + ".so")));
}

TEST(ModuleStoreTest, CacheLimitFollowsTheEnvironment) {
  {
    ScopedEnv env("TESSERA_MODULE_CACHE_MAX_MB", nullptr);
    EXPECT_EQ(ModuleCacheLimitBytes(), uint64_t{1} << 30);
  }
  {
    ScopedEnv env("TESSERA_MODULE_CACHE_MAX_MB", "64");
    EXPECT_EQ(ModuleCacheLimitBytes(), uint64_t{64} << 20);
  }
  {
    ScopedEnv env("TESSERA_MODULE_CACHE_MAX_MB", "lots");  // warned about, then the default
    EXPECT_EQ(ModuleCacheLimitBytes(), uint64_t{1} << 30);
  }
  // MiB whose bytes overflow 64 bits, and negative numbers, are junk too: not a limit of 0.
  for (const char* junk : {"17592186044416", "18446744073709551615", "-5"}) {
    ScopedEnv env("TESSERA_MODULE_CACHE_MAX_MB", junk);
    EXPECT_EQ(ModuleCacheLimitBytes(), uint64_t{1} << 30) << junk;
  }
  {
    ScopedEnv env("TESSERA_MODULE_CACHE_MAX_MB", "17592186044415");  // the largest that fits
    EXPECT_EQ(ModuleCacheLimitBytes(), uint64_t{17592186044415} << 20);
  }
}

TEST(ModuleStoreTest, ModuleTrimmedByAnotherProcessIsAskedForAgain) {
  TempDir temp;
  const std::string bytes = ReadFile(kModule);
  const std::string hash = ModuleHash(bytes);
  ModuleCache cache(temp.path());
  ASSERT_TRUE(cache.Store(hash, bytes).ok());
  ASSERT_TRUE(cache.Has(hash));
  fs::remove(temp.path() + "/" + hash + ".so");  // another worker sharing the directory trimmed it
  EXPECT_FALSE(cache.Has(hash));                 // so the host sends it again
  ASSERT_TRUE(cache.Store(hash, bytes).ok());
  EXPECT_TRUE(cache.Has(hash));
  EXPECT_TRUE(cache.Load(hash).ok());
}

TEST(ModuleStoreTest, BytesThatDoNotMatchTheirHashAreRefused) {
  TempDir temp;
  ModuleCache cache(temp.path());
  std::string bytes = ReadFile(kModule);
  const std::string hash = ModuleHash(bytes);
  bytes[bytes.size() / 2] ^= 0x40;
  absl::Status s = cache.Store(hash, bytes);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find(hash), std::string::npos) << s;
  EXPECT_FALSE(cache.Has(hash));
  EXPECT_TRUE(fs::is_empty(temp.path()));
  // The good bytes still go in afterwards.
  ASSERT_TRUE(cache.Store(hash, ReadFile(kModule)).ok());
  EXPECT_TRUE(cache.Has(hash));
}

TEST(ModuleStoreTest, CacheFileThatDoesNotMatchItsNameIsReplaced) {
  TempDir temp;
  const std::string bytes = ReadFile(kModule);
  const std::string hash = ModuleHash(bytes);
  const std::string file = temp.path() + "/" + hash + ".so";
  std::ofstream(file, std::ios::binary) << bytes.substr(0, bytes.size() / 2);  // cut short
  ModuleCache cache(temp.path());
  EXPECT_FALSE(cache.Has(hash));
  EXPECT_EQ(cache.Load(hash).status().code(), absl::StatusCode::kNotFound);
  ASSERT_TRUE(cache.Store(hash, bytes).ok());
  EXPECT_EQ(ReadFile(file), bytes);
}

TEST(ModuleStoreTest, DirectoryUnderAModulesNameIsNotAStoredModule) {
  TempDir temp;
  const std::string bytes = ReadFile(kModule);
  const std::string hash = ModuleHash(bytes);
  fs::create_directory(temp.path() + "/" + hash + ".so");
  ModuleCache cache(temp.path());
  EXPECT_FALSE(cache.Has(hash));  // so the host sends it
  EXPECT_EQ(cache.Load(hash).status().code(), absl::StatusCode::kNotFound);
  absl::Status s = cache.Store(hash, bytes);  // and cannot put it there
  EXPECT_EQ(s.code(), absl::StatusCode::kInternal) << s;
  EXPECT_NE(s.message().find(hash), std::string::npos) << s;
}

TEST(ModuleStoreTest, FifoUnderAModulesNameIsReplacedWithoutBlocking) {
  TempDir temp;
  const std::string bytes = ReadFile(kModule);
  const std::string hash = ModuleHash(bytes);
  const std::string file = temp.path() + "/" + hash + ".so";
  ASSERT_EQ(mkfifo(file.c_str(), 0600), 0);
  // Opening a FIFO to read waits for a writer: after a while this thread opens it to write (which
  // succeeds only while a reader waits) and counts it, so that a blocking cache fails the test
  // instead of hanging it.
  std::atomic<bool> done{false};
  std::atomic<int> unblocked{0};
  std::thread watchdog([&] {
    const auto start = std::chrono::steady_clock::now();
    while (!done) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      if (std::chrono::steady_clock::now() - start < std::chrono::seconds(2)) continue;
      const int fd = open(file.c_str(), O_WRONLY | O_NONBLOCK);
      if (fd >= 0) {
        ++unblocked;
        close(fd);
      }
    }
  });
  ModuleCache cache(temp.path());
  EXPECT_FALSE(cache.Has(hash));
  absl::Status s = cache.Store(hash, bytes);
  done = true;
  watchdog.join();
  EXPECT_EQ(unblocked, 0) << "reading the cache blocked on a FIFO";
  ASSERT_TRUE(s.ok()) << s;
  EXPECT_EQ(ReadFile(file), bytes);
  EXPECT_TRUE(cache.Load(hash).ok());
}

TEST(ModuleStoreTest, AModuleCutShortIsRefusedNotLoaded) {
  // Bytes that match their hash (a host may send anything) but end inside the module's segments:
  // dlopen would map them and the worker die of SIGBUS.
  TempDir temp;
  const std::string bytes = ReadFile(kModule).substr(0, 1024);
  const std::string hash = ModuleHash(bytes);
  ModuleCache cache(temp.path());
  ASSERT_TRUE(cache.Store(hash, bytes).ok());
  absl::StatusOr<const Module*> module = cache.Load(hash, "/host/cut.so");
  EXPECT_EQ(module.status().code(), absl::StatusCode::kInvalidArgument) << module.status();
  EXPECT_NE(module.status().message().find("/host/cut.so"), std::string::npos) << module.status();
  EXPECT_NE(module.status().message().find("cut short"), std::string::npos) << module.status();
}

TEST(ModuleStoreTest, UnusableDirectoryFallsBackToAPrivateTemporaryOne) {
  TempDir temp;
  const std::string file = temp.path() + "/not-a-directory";
  std::ofstream(file) << "x";
  const std::string wanted = file + "/modules";  // cannot be created, even by root
  ::testing::internal::CaptureStderr();
  const std::string dir = PrepareModuleCacheDir(wanted);
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(dir, wanted);
  EXPECT_TRUE(fs::is_directory(dir)) << dir;
  EXPECT_EQ(access(dir.c_str(), W_OK), 0);
  EXPECT_NE(err.find(wanted), std::string::npos) << err;
  EXPECT_NE(err.find(dir), std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  // It holds copies nothing else uses: gone when the process ends.
  RemoveTemporaryModuleCaches();
  EXPECT_FALSE(fs::exists(dir)) << dir;
}

v1::ModuleChunk Slice(const std::string& hash, uint64_t offset, uint64_t total,
                      const std::string& data) {
  v1::ModuleChunk c;
  c.set_module_hash(hash);
  c.set_offset(offset);
  c.set_total_size(total);
  c.set_data(data);
  return c;
}

TEST(ModuleStoreTest, SlicesAreReassembledInOrderOnly) {
  const std::string h1 = ModuleHash("one"), h2 = ModuleHash("two");
  v1::StateDelta d;
  *d.add_modules() = Slice(h1, 0, 6, "abc");
  *d.add_modules() = Slice(h2, 0, 2, "xy");
  *d.add_modules() = Slice(h1, 3, 6, "def");
  absl::StatusOr<std::map<std::string, std::string>> whole = AssembleModules(d.modules());
  ASSERT_TRUE(whole.ok()) << whole.status();
  EXPECT_EQ(whole->at(h1), "abcdef");
  EXPECT_EQ(whole->at(h2), "xy");

  auto rejected = [](std::vector<v1::ModuleChunk> slices, const std::string& words) {
    v1::StateDelta bad;
    for (v1::ModuleChunk& s : slices) *bad.add_modules() = std::move(s);
    absl::Status s = AssembleModules(bad.modules()).status();
    EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument) << words;
    EXPECT_NE(s.message().find(words), std::string::npos) << s;
  };
  rejected({Slice(h1, 3, 6, "def"), Slice(h1, 0, 6, "abc")}, "does not continue");
  rejected({Slice(h1, 0, 6, "abc"), Slice(h1, 3, 7, "defg")}, "disagree on its size");
  rejected({Slice(h1, 0, 6, "abc")}, "only 3 of 6 bytes");
  rejected({Slice(h1, 0, 2, "abc")}, "does not continue");
  rejected({Slice(h1, 0, 0, "")}, "is 0 bytes");
  rejected({Slice("../x", 0, 1, "a")}, "names no module hash");

  // Sizes are claims until the bytes arrive: modules claiming 1 GiB each, with a byte each, are
  // refused for the missing bytes. (Space for every claim used to be reserved up front: enough
  // such claims ran out of address space, and the worker answered "Unexpected error".)
  std::vector<v1::ModuleChunk> claims;
  for (int i = 0; i < 1000; ++i) {
    claims.push_back(Slice(ModuleHash(std::to_string(i)), 0, uint64_t{1} << 30, "a"));
  }
  rejected(std::move(claims), "only 1 of 1073741824 bytes");
}

}  // namespace
}  // namespace tessera::worker
