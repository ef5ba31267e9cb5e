// optixModuleCreate (optixModuleCreateFromPTX before 7.7), optixModuleCreateWithTasks,
// optixTaskExecute, optixModuleGetCompilationState, optixModuleDestroy, optixBuiltinISModuleGet.
//
// A module's input is what an OptiX 7 application has where OptiX takes PTX: the C++ source of
// its .cu file (as a string, the SDK's embedded-PTX pattern), a module's bytes (an ELF shared
// object), the text tessera_embed_program embeds (cmake/TesseraEmbedProgram.cmake: a module's
// bytes in hexadecimal behind "TESSERA-MODULE-HEX:", which survives strlen and std::string as
// PTX does), or the path of a .cu or .so file. Source compiles into the module cache
// (api/src/module_compiler.h) against the OptiX 7 headers.
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <system_error>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "call.h"
#include "module_compiler.h"
#include "optix_host.h"
#include "tessera/accuracy.h"

namespace tessera::optix7 {
namespace {

constexpr size_t kMaxPath = 4096;

// The input as a path: one line without NULs that names an existing regular file. Source text of
// one line that happens to name a file is not plausible; a .cu file's text is never a file name.
bool IsPath(absl::string_view input) {
  if (input.empty() || input.size() >= kMaxPath) return false;
  if (input.find('\n') != absl::string_view::npos || input.find('\0') != absl::string_view::npos) {
    return false;
  }
  std::error_code ec;
  return std::filesystem::is_regular_file(std::string(input), ec);
}

constexpr absl::string_view kHexPrefix = "TESSERA-MODULE-HEX:";

// The bytes of an embedded module's hexadecimal text (after kHexPrefix).
absl::StatusOr<std::string> FromHex(absl::string_view hex) {
  auto digit = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  };
  if (hex.size() % 2 != 0) {
    return OptixError(OPTIX_ERROR_INVALID_INPUT,
                      "embedded module text has an odd number of hexadecimal digits");
  }
  std::string bytes(hex.size() / 2, '\0');
  for (size_t i = 0; i < bytes.size(); ++i) {
    const int hi = digit(hex[2 * i]), lo = digit(hex[2 * i + 1]);
    if (hi < 0 || lo < 0) {
      return OptixError(OPTIX_ERROR_INVALID_INPUT,
                        absl::StrCat("embedded module text has a character that is not a "
                                     "hexadecimal digit at offset ",
                                     kHexPrefix.size() + 2 * i));
    }
    bytes[i] = static_cast<char>(hi * 16 + lo);
  }
  return bytes;
}

absl::StatusOr<std::string> ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in && !in.eof()) {
    return OptixError(OPTIX_ERROR_FILE_IO_ERROR, absl::StrCat("cannot read '", path, "'"));
  }
  return bytes;
}

// The module in the cache, whichever form the input has.
absl::StatusOr<api::CompiledModule> ModuleFile(absl::string_view input,
                                               const api::ProgramCompileOptions& options,
                                               std::string* name) {
  absl::StatusOr<api::CompiledModule> module;
  if (IsElf(input)) {
    *name = "<module bytes>";
    module = api::StoreProgramModule(input, options);
    if (!module.ok()) return OptixError(OPTIX_ERROR_INVALID_INPUT, module.status().message());
    return module;
  }
  // Applications pass strlen() or the size with the terminating NUL; both are the same text.
  while (!input.empty() && input.back() == '\0') input.remove_suffix(1);
  if (absl::StartsWith(input, kHexPrefix)) {
    *name = "<embedded module>";
    absl::StatusOr<std::string> bytes = FromHex(input.substr(kHexPrefix.size()));
    if (!bytes.ok()) return bytes.status();
    if (!IsElf(*bytes)) {
      return OptixError(OPTIX_ERROR_INVALID_INPUT, "embedded module text holds no program module");
    }
    module = api::StoreProgramModule(*bytes, options);
  } else if (IsPath(input)) {
    *name = std::string(input);
    absl::StatusOr<std::string> bytes = ReadFile(*name);
    if (!bytes.ok()) return bytes.status();
    module = IsElf(*bytes) ? api::StoreProgramModule(*bytes, options)
                           : api::CompileProgramModule(*bytes, *name, options);
  } else {
    *name = "<string>";
    module = api::CompileProgramModule(input, "", options);
  }
  // Every failure to have a module is an invalid input to OptiX (the compiler's message says why).
  if (!module.ok()) return OptixError(OPTIX_ERROR_INVALID_INPUT, module.status().message());
  return module;
}

absl::Status CheckOptions(Call& call, const OptixModuleCompileOptions* module_options,
                          const OptixPipelineCompileOptions* pipeline_options) {
  if (absl::Status s = call.NotNull(module_options, "moduleCompileOptions"); !s.ok()) return s;
  if (absl::Status s = call.NotNull(pipeline_options, "pipelineCompileOptions"); !s.ok()) return s;
  if (absl::Status s = CheckPipelineCompileOptions(*pipeline_options); !s.ok()) return s;
  return CheckModuleCompileOptions(*module_options, *pipeline_options);
}

absl::StatusOr<std::shared_ptr<Module>> CreateModule(
    Call& call, OptixDeviceContext context, const OptixModuleCompileOptions* module_options,
    const OptixPipelineCompileOptions* pipeline_options, const char* input, size_t input_size,
    OptixModule* out) {
  std::shared_ptr<DeviceContext> c;
  if (absl::Status s = call.Lookup(context, "context", &c); !s.ok()) return s;
  if (absl::Status s = CheckOptions(call, module_options, pipeline_options); !s.ok()) return s;
  if (absl::Status s = call.NotNull(out, "module"); !s.ok()) return s;
  if (input == nullptr || input_size == 0) {
    return OptixError(OPTIX_ERROR_INVALID_VALUE, "input is null or inputSize is 0");
  }
  api::ProgramCompileOptions compile;
  compile.optix7 = true;
  compile.fast_math = (c->accuracy_flags() & TESSERA_ACCURACY_FAST_MATH) != 0;
  const DeviceContext::Cache cache = c->cache();
  if (cache.location_chosen) compile.cache_dir = cache.location;
  auto module = std::make_shared<Module>();
  module->context = c;
  absl::StatusOr<api::CompiledModule> file =
      ModuleFile(absl::string_view(input, input_size), compile, &module->name);
  if (!file.ok()) return file.status();
  absl::StatusOr<ElfSymbols> symbols = ReadExportedSymbols(file->bytes);
  if (!symbols.ok()) {
    return OptixError(OPTIX_ERROR_INVALID_INPUT,
                      absl::StrCat(module->name, ": ", symbols.status().message()));
  }
  module->symbols = *std::move(symbols);
  module->launch = std::make_shared<LaunchModule>(
      LaunchModule{std::move(file->path), std::move(file->hash), std::move(file->bytes)});
  module->options = CopyPipelineOptions(*pipeline_options);
  module->payload_values = PayloadValueCount(*module_options, *pipeline_options);
  // The launch parameters' variable: a module whose programs do not read them need not declare
  // it (OptiX accepts such modules, e.g. one of intersection programs), so a missing one is a
  // warning; a function of that name is an error.
  if (module->options.params_name) {
    const std::string& params = *module->options.params_name;
    auto it = module->symbols.find(params);
    if (it == module->symbols.end()) {
      call.Log(kLogWarning,
               absl::StrCat(module->name, " exports no variable '", params,
                            "' (pipelineLaunchParamsVariableName): its programs cannot read the "
                            "launch parameters (declare it extern \"C\" __constant__)"));
    } else if (it->second != SymbolKind::kObject) {
      return OptixError(
          OPTIX_ERROR_INVALID_VALUE,
          absl::StrCat("pipelineLaunchParamsVariableName '", params, "' names ",
                       it->second == SymbolKind::kFunction ? "a function" : "no variable", " in ",
                       module->name));
    }
  }
  if (pipeline_options->allowOpacityMicromaps != 0) {
    call.Log(kLogWarning, "allowOpacityMicromaps is ignored: Tessera has no opacity micromaps");
  }
  call.Log(kLogPrint, absl::StrCat("module ", module->launch->hash.substr(0, 16), " from ",
                                   module->name, " (", module->launch->bytes.size(), " bytes, ",
                                   module->symbols.size(), " exported symbols)"));
  Register(module, c.get());
  *out = reinterpret_cast<OptixModule>(module.get());
  return module;
}

}  // namespace
}  // namespace tessera::optix7

using tessera::optix7::Call;
using tessera::optix7::DeviceContext;
using tessera::optix7::Module;
using tessera::optix7::OptixError;
using tessera::optix7::Task;

extern "C" {

OptixResult optixModuleCreate(OptixDeviceContext context,
                              const OptixModuleCompileOptions* moduleCompileOptions,
                              const OptixPipelineCompileOptions* pipelineCompileOptions,
                              const char* input, size_t inputSize, char* logString,
                              size_t* logStringSize, OptixModule* module) {
  return Call("optixModuleCreate", logString, logStringSize).Run([&](Call& call) -> absl::Status {
    return tessera::optix7::CreateModule(call, context, moduleCompileOptions,
                                         pipelineCompileOptions, input, inputSize, module)
        .status();
  });
}

// The module is compiled before this returns, and `firstTask` is one task with nothing left to
// do: applications that execute tasks on their threads work unchanged, and the compiler's
// messages reach the log buffer, which OptiX fills only for what it finds before the tasks run.
OptixResult optixModuleCreateWithTasks(OptixDeviceContext context,
                                       const OptixModuleCompileOptions* moduleCompileOptions,
                                       const OptixPipelineCompileOptions* pipelineCompileOptions,
                                       const char* input, size_t inputSize, char* logString,
                                       size_t* logStringSize, OptixModule* module,
                                       OptixTask* firstTask) {
  return Call("optixModuleCreateWithTasks", logString, logStringSize)
      .Run([&](Call& call) -> absl::Status {
        if (absl::Status s = call.NotNull(firstTask, "firstTask"); !s.ok()) return s;
        absl::StatusOr<std::shared_ptr<Module>> created = tessera::optix7::CreateModule(
            call, context, moduleCompileOptions, pipelineCompileOptions, input, inputSize, module);
        if (!created.ok()) return created.status();
        auto task = std::make_shared<Task>(Task{(*created)->context, *created});
        tessera::optix7::Register(task, task->context.get());
        *firstTask = reinterpret_cast<OptixTask>(task.get());
        return absl::OkStatus();
      });
}

OptixResult optixTaskExecute(OptixTask task, OptixTask* additionalTasks,
                             unsigned int maxNumAdditionalTasks,
                             unsigned int* numAdditionalTasksCreated) {
  return Call("optixTaskExecute").Run([&](Call& call) -> absl::Status {
    std::shared_ptr<Task> t;
    if (absl::Status s = call.Lookup(task, "task", &t); !s.ok()) return s;
    if (maxNumAdditionalTasks > 0 && additionalTasks == nullptr) {
      return OptixError(OPTIX_ERROR_INVALID_VALUE, "additionalTasks is null");
    }
    // A task runs once, as in OptiX; it creates no further tasks.
    tessera::optix7::UnregisterObject(tessera::optix7::ObjectKind::kTask, task);
    if (numAdditionalTasksCreated != nullptr) *numAdditionalTasksCreated = 0;
    return absl::OkStatus();
  });
}

OptixResult optixModuleGetCompilationState(OptixModule module, OptixModuleCompileState* state) {
  return Call("optixModuleGetCompilationState").Run([&](Call& call) -> absl::Status {
    std::shared_ptr<Module> m;
    if (absl::Status s = call.Lookup(module, "module", &m); !s.ok()) return s;
    if (absl::Status s = call.NotNull(state, "state"); !s.ok()) return s;
    *state = OPTIX_MODULE_COMPILE_STATE_COMPLETED;  // a failed compile makes no module
    return absl::OkStatus();
  });
}

OptixResult optixModuleDestroy(OptixModule module) {
  return Call("optixModuleDestroy").Run([&](Call& call) -> absl::Status {
    std::shared_ptr<Module> m;
    if (absl::Status s = call.Lookup(module, "module", &m); !s.ok()) return s;
    tessera::optix7::UnregisterObject(Module::kKind, module);
    return absl::OkStatus();
  });
}

// A module standing for a built-in intersection (spheres, curves): hit groups that name it as
// their intersection module get its primitive type as builtin_primitive. Builds of curves and
// spheres are not supported yet (optixAccelBuild says so), so such hit groups are never hit.
OptixResult optixBuiltinISModuleGet(OptixDeviceContext context,
                                    const OptixModuleCompileOptions* moduleCompileOptions,
                                    const OptixPipelineCompileOptions* pipelineCompileOptions,
                                    const OptixBuiltinISOptions* builtinISOptions,
                                    OptixModule* builtinModule) {
  return Call("optixBuiltinISModuleGet").Run([&](Call& call) -> absl::Status {
    std::shared_ptr<DeviceContext> c;
    if (absl::Status s = call.Lookup(context, "context", &c); !s.ok()) return s;
    if (absl::Status s =
            tessera::optix7::CheckOptions(call, moduleCompileOptions, pipelineCompileOptions);
        !s.ok()) {
      return s;
    }
    if (absl::Status s = call.NotNull(builtinISOptions, "builtinISOptions"); !s.ok()) return s;
    if (absl::Status s = call.NotNull(builtinModule, "builtinModule"); !s.ok()) return s;
    const OptixPrimitiveType type = builtinISOptions->builtinISModuleType;
    const unsigned flag = tessera::optix7::PrimitiveTypeFlag(type);
    if (flag == 0) {
      return OptixError(OPTIX_ERROR_INVALID_VALUE,
                        absl::StrCat("builtinISOptions->builtinISModuleType 0x",
                                     absl::Hex(static_cast<unsigned>(type)),
                                     " is not a curve or sphere type (triangles need no module)"));
    }
    const unsigned uses = tessera::optix7::EffectivePrimitiveTypeFlags(
        pipelineCompileOptions->usesPrimitiveTypeFlags);
    if ((uses & flag) == 0) {
      return OptixError(
          OPTIX_ERROR_INVALID_VALUE,
          absl::StrCat("pipelineCompileOptions->usesPrimitiveTypeFlags 0x", absl::Hex(uses),
                       " lacks the flag 0x", absl::Hex(flag), " of builtinISModuleType"));
    }
    auto module = std::make_shared<Module>();
    module->context = c;
    module->name = absl::StrCat("built-in intersection 0x", absl::Hex(static_cast<unsigned>(type)));
    module->builtin = type;
    module->options = tessera::optix7::CopyPipelineOptions(*pipelineCompileOptions);
    module->payload_values =
        tessera::optix7::PayloadValueCount(*moduleCompileOptions, *pipelineCompileOptions);
    tessera::optix7::Register(module, c.get());
    *builtinModule = reinterpret_cast<OptixModule>(module.get());
    return absl::OkStatus();
  });
}

}  // extern "C"
