#include "tessera/scheduler/module_symbol.h"

#include <dlfcn.h>
#include <link.h>

namespace tessera::scheduler {

void* FindModuleFunction(void* handle, const char* name) {
  void* symbol = dlsym(handle, name);
  if (symbol == nullptr) return nullptr;
  link_map* module = nullptr;
  if (dlinfo(handle, RTLD_DI_LINKMAP, &module) != 0) return nullptr;
  Dl_info info{};
  void* extra = nullptr;
  if (dladdr1(symbol, &info, &extra, RTLD_DL_LINKMAP) == 0 || extra != module) return nullptr;
  if (dladdr1(symbol, &info, &extra, RTLD_DL_SYMENT) == 0 || extra == nullptr) return nullptr;
  const unsigned char kind = static_cast<const ElfW(Sym)*>(extra)->st_info;
  return ELF64_ST_TYPE(kind) == STT_FUNC && ELF64_ST_BIND(kind) == STB_GLOBAL ? symbol : nullptr;
}

}  // namespace tessera::scheduler
