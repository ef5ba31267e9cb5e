// EmptyProgramCode: which any-hit programs a plan leaves out as doing nothing.
#include "plan.h"

#include <dlfcn.h>
#include <gtest/gtest.h>

#include <string>

namespace tessera::worker {
namespace {

TEST(EmptyProgramCodeTest, BareReturnsInEveryForm) {
  const unsigned char ret[] = {0xc3};
  const unsigned char rep_ret[] = {0xf3, 0xc3};
  const unsigned char endbr_ret[] = {0xf3, 0x0f, 0x1e, 0xfa, 0xc3};
  const unsigned char frame[] = {0x55, 0x48, 0x89, 0xe5, 0x90, 0x5d, 0xc3};
  const unsigned char endbr_frame[] = {0xf3, 0x0f, 0x1e, 0xfa, 0x55, 0x48,
                                       0x89, 0xe5, 0x90, 0x5d, 0xc3};
  for (const unsigned char* code : {ret, rep_ret, endbr_ret, frame, endbr_frame}) {
    EXPECT_TRUE(EmptyProgramCode(code));
  }
  // xor %eax,%eax; ret: returns something. mov %edi,(%rsi); ret: stores. A frame that stores.
  const unsigned char returns_zero[] = {0x31, 0xc0, 0xc3};
  const unsigned char stores[] = {0x89, 0x3e, 0xc3};
  const unsigned char frame_store[] = {0x55, 0x48, 0x89, 0xe5, 0x89, 0x7d, 0xfc, 0x90, 0x5d, 0xc3};
  for (const unsigned char* code : {returns_zero, stores, frame_store}) {
    EXPECT_FALSE(EmptyProgramCode(code));
  }
  EXPECT_FALSE(EmptyProgramCode(nullptr));
}

// What the module build makes of an empty RT_PROGRAM, and of one that is not.
TEST(EmptyProgramCodeTest, ProgramsOfAModule) {
  const std::string path = std::string(TESSERA_TEST_MODULE_DIR) + "/worker_core_test_programs.so";
  void* module = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(module, nullptr) << dlerror();
  void* nothing = dlsym(module, "any_hit_nothing");
  void* miss = dlsym(module, "miss");
  ASSERT_NE(nothing, nullptr);
  ASSERT_NE(miss, nullptr);
  EXPECT_TRUE(EmptyProgramCode(nothing));
  EXPECT_FALSE(EmptyProgramCode(miss));
  dlclose(module);
}

}  // namespace
}  // namespace tessera::worker
