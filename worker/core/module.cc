#include "module.h"

#include <cxxabi.h>
#include <dlfcn.h>
#include <link.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <string_view>
#include <utility>

#include "absl/status/status.h"
#include "absl/strings/escaping.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/strip.h"
#include "float_mode.h"
#include "interrupt.h"
#include "module_store.h"
#include "optix7_module_init.h"
#include "runtime.h"
#include "tessera/scheduler/module_file.h"
#include "tessera/scheduler/module_symbol.h"
#include "tessera/worker/crash_report.h"
#include "tessera/worker/module_cache.h"
#include "tessera/worker/static_tls.h"

namespace tessera::worker {
namespace {

std::string Unquote(std::string s) {
  if (s.size() >= 2 && s.front() == '"' && s.back() == '"') return s.substr(1, s.size() - 2);
  return s;
}

absl::Status ParseSemantic(const std::string& module, ModuleVariable& v, const char* text) {
  std::string s = text ? text : "";
  if (s.empty()) return absl::OkStatus();
  static const std::pair<const char*, Semantic> kBuiltins[] = {
      {"rtLaunchIndex", Semantic::kLaunchIndex},       {"rtLaunchDim", Semantic::kLaunchDim},
      {"rtCurrentRay", Semantic::kCurrentRay},         {"rtPayload", Semantic::kPayload},
      {"rtIntersectionDistance", Semantic::kDistance}, {"rtCallableProgram", Semantic::kCallable},
      {"rtCurrentTime", Semantic::kCurrentTime},
  };
  for (const auto& [name, semantic] : kBuiltins) {
    if (s == name) {
      v.semantic = semantic;
      return absl::OkStatus();
    }
  }
  absl::string_view rest = s;
  if (absl::ConsumePrefix(&rest, "attribute")) {
    rest = absl::StripAsciiWhitespace(rest);
    if (!rest.empty()) {
      v.semantic = Semantic::kAttribute;
      v.attribute = std::string(rest);
      return absl::OkStatus();
    }
  }
  return absl::InvalidArgumentError(
      absl::StrCat("module ", module, ": variable '", v.name, "' has unknown semantic '", s, "'"));
}

// The name of the symbol at `object` with its namespaces, as the host names it ("ns::buf"; rtBuffer
// objects are named by their symbol). Anonymous namespaces are left out.
std::string SymbolName(const void* object) {
  Dl_info info{};
  if (dladdr(object, &info) == 0 || info.dli_sname == nullptr || info.dli_saddr != object) {
    return "";
  }
  std::string name = info.dli_sname;
  int status = 0;
  char* demangled = abi::__cxa_demangle(info.dli_sname, nullptr, nullptr, &status);
  if (status == 0 && demangled != nullptr) name = demangled;
  std::free(demangled);
  constexpr std::string_view kAnonymous = "(anonymous namespace)::";
  for (size_t i = name.find(kAnonymous); i != std::string::npos; i = name.find(kAnonymous)) {
    name.erase(i, kAnonymous.size());
  }
  return name;
}

thread_local std::vector<std::vector<void*>> t_slots;

// Process-wide, not per cache: the index selects a module's per-thread slot tables.
int NextModuleIndex() {
  static std::atomic<int> next_index{0};
  return next_index++;
}

}  // namespace

void* const* Module::Slots() const {
  if (t_slots.size() <= static_cast<size_t>(index_)) t_slots.resize(index_ + 1);
  std::vector<void*>& slots = t_slots[index_];
  if (slots.size() != variables_.size()) {
    slots.resize(variables_.size());
    for (size_t i = 0; i < variables_.size(); ++i) slots[i] = variables_[i].address();
  }
  return slots.data();
}

void* Module::Function(const std::string& name) const {
  std::lock_guard<std::mutex> lock(functions_mu_);
  auto [it, inserted] = functions_.try_emplace(name, nullptr);
  if (inserted) it->second = scheduler::FindModuleFunction(handle_, name.c_str());
  return it->second;
}

void* Module::Data(const std::string& name, size_t* size) const {
  void* symbol = dlsym(handle_, name.c_str());
  if (symbol == nullptr) return nullptr;
  link_map* self = nullptr;
  Dl_info info{};
  void* extra = nullptr;
  // The module's own object, not one a library it links defines.
  if (dlinfo(handle_, RTLD_DI_LINKMAP, &self) != 0 ||
      dladdr1(symbol, &info, &extra, RTLD_DL_LINKMAP) == 0 || extra != self ||
      dladdr1(symbol, &info, &extra, RTLD_DL_SYMENT) == 0 || extra == nullptr) {
    return nullptr;
  }
  const auto* sym = static_cast<const ElfW(Sym)*>(extra);
  if (ELF64_ST_TYPE(sym->st_info) != STT_OBJECT) return nullptr;
  *size = sym->st_size;
  return symbol;
}

ModuleCache& ModuleCache::Get() {
  static ModuleCache* cache = new ModuleCache();
  return *cache;
}

ModuleCache::ModuleCache(std::string directory) : requested_(std::move(directory)) {}

void ModuleCache::SetDirectory(std::string directory) {
  std::lock_guard<std::mutex> lock(mu_);
  requested_ = std::move(directory);
  directory_.clear();
  stored_.clear();
}

std::string ModuleCache::directory() {
  std::lock_guard<std::mutex> lock(mu_);
  return DirectoryLocked();
}

const std::string& ModuleCache::DirectoryLocked() {
  if (directory_.empty()) {
    directory_ = PrepareModuleCacheDir(requested_.empty() ? DefaultModuleCacheDir() : requested_);
  }
  return directory_;
}

absl::Status ModuleCache::Store(const std::string& hash, absl::string_view bytes) {
  // Hashed before anything else: a module must never be stored under a name it does not match.
  if (!IsModuleHash(hash) || ModuleHash(bytes) != hash) {
    return absl::InvalidArgumentError(
        absl::StrCat("program module bytes do not match their hash ", hash));
  }
  std::lock_guard<std::mutex> lock(mu_);
  if (OnDiskLocked(hash)) return absl::OkStatus();
  if (absl::Status s = WriteModuleFile(DirectoryLocked(), hash, bytes); !s.ok()) return s;
  stored_.insert(hash);
  TrimModuleCache(DirectoryLocked(), ModuleCacheLimitBytes(), hash);
  return absl::OkStatus();
}

bool ModuleCache::OnDiskLocked(const std::string& hash) {
  const std::string& dir = DirectoryLocked();
  const bool present = stored_.count(hash) != 0
                           ? access(ModuleFilePath(dir, hash).c_str(), R_OK) == 0
                           : HasModuleFile(dir, hash);
  if (!present) {
    stored_.erase(hash);
    return false;
  }
  stored_.insert(hash);
  TouchModuleFile(dir, hash);  // used now: trimming keeps it longest
  return true;
}

bool ModuleCache::Has(const std::string& hash) {
  if (!IsModuleHash(hash)) return false;
  std::lock_guard<std::mutex> lock(mu_);
  return modules_.count(hash) != 0 || OnDiskLocked(hash);
}

absl::Status ModuleCache::Receive(const v1::StateDelta& delta) {
  absl::StatusOr<std::map<std::string, std::string>> modules = AssembleModules(delta.modules());
  if (!modules.ok()) return modules.status();
  auto describe = [](const v1::Program& p) {
    return absl::StrCat("program #", p.id(), " '", p.function(), "' from ", p.module_path());
  };
  std::map<std::string, const v1::Program*> users;  // by module hash, for messages
  for (const v1::Object& o : delta.objects()) {
    if (!o.has_program()) continue;
    const v1::Program& p = o.program();
    if (!IsModuleHash(p.module_hash())) {
      return absl::InvalidArgumentError(absl::StrCat(
          describe(p), " names no module hash ('", absl::CEscape(p.module_hash().substr(0, 80)),
          "'; expected 64 lowercase hex digits of SHA-256)"));
    }
    users.emplace(p.module_hash(), &p);
    if (modules->count(p.module_hash()) == 0 && !Has(p.module_hash())) {
      return absl::FailedPreconditionError(absl::StrCat(describe(p), " needs program module ",
                                                        p.module_hash(),
                                                        ", which this device has not received"));
    }
  }
  for (const auto& [hash, bytes] : *modules) {
    if (absl::Status s = Store(hash, bytes); !s.ok()) {
      auto user = users.find(hash);
      if (user == users.end()) return s;
      return absl::Status(s.code(), absl::StrCat(describe(*user->second), ": ", s.message()));
    }
  }
  return absl::OkStatus();
}

namespace {

// The initial-exec build a module file carries (scheduler::kInitialExecSection), written beside it
// as <file>.ie; "" when it carries none or it cannot be written. A copy already there is used only
// if it holds the same bytes: the module file was checked against its hash, the copy was not.
std::string InitialExecFile(const std::string& file) {
  std::string bytes;
  if (!ReadWholeFile(file, &bytes)) return "";
  const absl::string_view build = scheduler::FindElfSection(bytes, scheduler::kInitialExecSection);
  if (build.empty()) return "";
  const std::string out = file + ".ie";
  if (std::string existing; ReadWholeFile(out, &existing) && existing == build) return out;
  // Written under a temporary name and renamed: another thread or process may be at it too.
  const std::string temp = absl::StrCat(out, ".", getpid(), ".", gettid(), ".tmp");
  {
    std::ofstream o(temp, std::ios::binary | std::ios::trunc);
    o.write(build.data(), static_cast<std::streamsize>(build.size()));
    o.close();
    if (!o) {
      unlink(temp.c_str());
      return "";
    }
  }
  if (rename(temp.c_str(), out.c_str()) != 0) {
    unlink(temp.c_str());
    return "";
  }
  return out;
}

}  // namespace

absl::StatusOr<const Module*> ModuleCache::Load(const std::string& hash, absl::string_view origin) {
  std::lock_guard<std::mutex> lock(mu_);
  if (auto it = modules_.find(hash); it != modules_.end()) return it->second.get();
  if (!IsModuleHash(hash)) {
    return absl::InvalidArgumentError(
        absl::StrCat("program module ", origin, " has no valid hash ('", hash, "')"));
  }
  const std::string& dir = DirectoryLocked();
  if (!OnDiskLocked(hash)) {
    return absl::NotFoundError(absl::StrCat("program module ", origin, origin.empty() ? "" : " ",
                                            hash, " is not in this device's module cache (", dir,
                                            "): the host has not sent it"));
  }
  const std::string file = ModuleFilePath(dir, hash);
  // Messages name the host's file, which the user knows, and the copy that was loaded.
  const std::string path = origin.empty() ? file : absl::StrCat(origin, " (cached as ", file, ")");

  // Bytes that match their hash may still be a module cut short, which dlopen would map and the
  // process die of at first use.
  if (absl::Status whole = scheduler::CheckModuleFileComplete(file); !whole.ok()) {
    return absl::InvalidArgumentError(
        absl::StrCat("cannot load program module ", path, ": ", whole.message()));
  }
  // A module's static constructors run in dlopen, its registrations in init.
  const std::string loading = absl::StrCat("loading program module ", path);
  CrashContext crash_context(loading.c_str());
  void* handle = nullptr;
  bool initial_exec = false;
  {
    // A module built with -ffast-math has crtfastmath.o's constructor, which sets FTZ/DAZ on the
    // thread that loads it: a launch's programs get the mode their launch asks for, the loading
    // thread (the host's own, for an in-process device) keeps its own.
    PreservedFloatMode float_mode;
    if (ModuleStaticTlsReserved()) {
      // Its initial-exec build in its place; dlopen refuses it once static TLS is used up (each
      // module loaded keeps its share), and the module itself is loaded then.
      const std::string ie = InitialExecFile(file);
      if (!ie.empty()) handle = dlopen(ie.c_str(), RTLD_NOW | RTLD_LOCAL);
      initial_exec = handle != nullptr;
    }
    if (handle == nullptr) handle = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
  }
  if (handle == nullptr) {
    const char* err = dlerror();
    return absl::NotFoundError(
        absl::StrCat("cannot load program module ", path, ": ", err ? err : "unknown error"));
  }
  auto init = reinterpret_cast<TesseraModuleInitFn>(dlsym(handle, TESSERA_MODULE_INIT_SYMBOL));
  if (init == nullptr) {
    // An OptiX 7 module has no registry: its programs and `params` are found by symbol name.
    absl::StatusOr<bool> optix7 = InitOptix7Module(handle, path);
    if (!optix7.ok() || !*optix7) {
      dlclose(handle);
      if (!optix7.ok()) return optix7.status();
      return absl::InvalidArgumentError(
          absl::StrCat("program module ", path, " was built against neither tessera/device.h (no ",
                       TESSERA_MODULE_INIT_SYMBOL, ") nor the OptiX 7 optix_device.h (no ",
                       kOptix7ModuleInitSymbol, ")"));
    }
    RegisterModuleCode(handle);  // a program looping forever in it can be jumped out of
    auto module = std::make_unique<Module>();
    module->index_ = NextModuleIndex();
    module->path_ = file;
    module->handle_ = handle;
    module->optix7_ = true;
    // A module from before the flags has no TESSERA_OPTIX7_MODULE_FLAGS_SYMBOL: flags 0.
    const auto* flags = static_cast<const unsigned*>(dlsym(handle, kOptix7ModuleFlagsSymbol));
    module->fast_math_ = flags != nullptr && (*flags & kOptix7ModuleFlagFastMath) != 0;
    const Module* result = module.get();
    modules_.emplace(hash, std::move(module));
    return result;
  }
  const TesseraModuleInfo* info = init(EngineRuntime(), TESSERA_MODULE_ABI_VERSION);
  if (info == nullptr || info->abi_version != TESSERA_MODULE_ABI_VERSION) {
    dlclose(handle);
    return absl::FailedPreconditionError(
        absl::StrCat("program module ", path,
                     " was built against another version of Tessera's program headers (this "
                     "Tessera's module ABI is ",
                     TESSERA_MODULE_ABI_VERSION,
                     "): rebuild it against this Tessera's headers (docs/install.md)"));
  }
  RegisterModuleCode(handle);  // a program looping forever in it can be jumped out of
  auto module = std::make_unique<Module>();
  module->index_ = NextModuleIndex();
  module->path_ = file;
  module->handle_ = handle;
  module->info_ = info;
  module->initial_exec_ = initial_exec;
  module->fast_math_ = (info->flags & TESSERA_MODULE_FLAG_FAST_MATH) != 0;
  for (unsigned i = 0; i < info->variable_count; ++i) {
    const TesseraVariableDecl& d = info->variables[i];
    ModuleVariable v;
    v.name = d.name;
    v.annotation = Unquote(d.annotation ? d.annotation : "");
    v.type_name = d.type_name ? d.type_name : "";
    v.size = d.size;
    v.address = d.address;
    if (absl::Status s = ParseSemantic(path, v, d.semantic); !s.ok()) return s;
    // This thread's slot still holds the static initializer (or zeros): that is the default.
    const auto* initial = static_cast<const unsigned char*>(d.address());
    v.initial.assign(initial, initial + d.size);
    if (v.semantic == Semantic::kCurrentRay || v.semantic == Semantic::kPayload ||
        v.semantic == Semantic::kDistance || v.semantic == Semantic::kAttribute ||
        v.semantic == Semantic::kCurrentTime) {
      module->per_call_.push_back(static_cast<unsigned>(module->variables_.size()));
      module->per_call_bytes_ += v.size;
    }
    module->variables_.push_back(std::move(v));
  }
  for (unsigned i = 0; i < info->buffer_count; ++i) {
    const TesseraBufferDecl& d = info->buffers[i];
    ModuleBuffer b;
    b.name = SymbolName(d.object);
    b.element_size = d.element_size;
    b.dimensionality = d.dimensionality;
    if (b.name.empty()) {
      return absl::InvalidArgumentError(absl::StrCat(
          "program module ", path, ": rtBuffer #", i,
          " has no exported name (declare rtBuffer objects at namespace scope, not static)"));
    }
    module->buffers_.push_back(std::move(b));
  }
  for (unsigned i = 0; i < info->texture_count; ++i) {
    const TesseraTextureDecl& d = info->textures[i];
    ModuleTexture t;
    t.name = SymbolName(d.object);
    t.element_size = d.element_size;
    t.dimensionality = d.dimensionality;
    t.read_mode = d.read_mode;
    if (t.name.empty()) {
      return absl::InvalidArgumentError(
          absl::StrCat("program module ", path, ": rtTextureSampler #", i,
                       " has no exported name (declare rtTextureSampler objects at namespace "
                       "scope, not static)"));
    }
    module->textures_.push_back(std::move(t));
  }
  const Module* result = module.get();
  modules_.emplace(hash, std::move(module));
  return result;
}

}  // namespace tessera::worker

namespace tessera {

void SetModuleCacheDirectory(const std::string& dir) {
  worker::ModuleCache::Get().SetDirectory(dir);
}

std::string ModuleCacheDirectory() { return worker::ModuleCache::Get().directory(); }

void RemoveTemporaryModuleCaches() { worker::RemoveTemporaryModuleCaches(); }

}  // namespace tessera
