// optixProgramGroupCreate, optixProgramGroupGetStackSize, optixProgramGroupDestroy. A program
// group names entry functions of modules by symbol; what devices receive is its wire form
// (v1::Optix7ProgramGroup) with the modules it needs.
#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "call.h"
#include "optix_host.h"

namespace tessera::optix7 {
namespace {

// Continuation stack of each program kind and the direct stack of direct callables, reported
// for the programs a group has (0 for those it has not). Tessera runs programs on worker
// threads' own stacks and sizes nothing by them; these constants only make the
// optix_stack_size.h arithmetic give plausible nonzero sizes, which optixPipelineSetStackSize
// checks and accepts.
constexpr unsigned kCssRaygen = 96;
constexpr unsigned kCssMiss = 32;
constexpr unsigned kCssClosestHit = 64;
constexpr unsigned kCssAnyHit = 16;
constexpr unsigned kCssIntersection = 32;
constexpr unsigned kCssContinuationCallable = 64;
constexpr unsigned kDssDirectCallable = 32;

// One slot of a program group description: a module and an entry function in it.
struct Slot {
  const char* field;  // "raygen", "hitgroup.moduleCH", ... for messages
  OptixModule module;
  const char* name;
  const char* prefix;  // what OptiX requires the name to start with
};

// The entry of `slot` in `group`: false when the slot is empty (module and name both null).
absl::StatusOr<bool> AddEntry(Call& call, const std::string& where, const Slot& slot,
                              bool builtin_allowed, ProgramGroup& group, v1::Optix7Entry* entry,
                              std::shared_ptr<const Module>* found = nullptr) {
  if (slot.module == nullptr) {
    if (slot.name != nullptr) {
      return OptixError(OPTIX_ERROR_INVALID_VALUE,
                        absl::StrCat(where, ".", slot.field, " names entry function '", slot.name,
                                     "' but its module is null"));
    }
    return false;
  }
  std::shared_ptr<Module> module;
  if (absl::Status s =
          call.Lookup(slot.module, absl::StrCat(where, ".", slot.field, " module"), &module);
      !s.ok()) {
    return s;
  }
  if (module->context != group.context) {
    return OptixError(OPTIX_ERROR_INVALID_VALUE,
                      absl::StrCat(where, ".", slot.field, ": module ", module->name,
                                   " belongs to another device context"));
  }
  if (found != nullptr) *found = module;
  if (module->is_builtin()) {
    if (!builtin_allowed) {
      return OptixError(OPTIX_ERROR_INVALID_VALUE,
                        absl::StrCat(where, ".", slot.field, ": ", module->name,
                                     " (optixBuiltinISModuleGet) can only be a hit group's "
                                     "intersection module"));
    }
    if (slot.name != nullptr) {
      return OptixError(OPTIX_ERROR_INVALID_VALUE,
                        absl::StrCat(where, ".", slot.field,
                                     ": the entry function name must be "
                                     "null for ",
                                     module->name, " (it is '", slot.name, "')"));
    }
    return true;
  }
  if (slot.name == nullptr) {
    return OptixError(
        OPTIX_ERROR_INVALID_VALUE,
        absl::StrCat(where, ".", slot.field, ": entry function name is null for ", module->name));
  }
  const std::string name = slot.name;
  if (!absl::StartsWith(name, slot.prefix)) {
    return OptixError(
        OPTIX_ERROR_INVALID_VALUE,
        absl::StrCat(where, ".", slot.field, ": entry function '", name, "' does not start with '",
                     slot.prefix, "', which OptiX requires of this kind of program"));
  }
  auto symbol = module->symbols.find(name);
  if (symbol == module->symbols.end() || symbol->second != SymbolKind::kFunction) {
    return OptixError(OPTIX_ERROR_INVALID_VALUE,
                      absl::StrCat(where, ".", slot.field, ": module ", module->name,
                                   " exports no function '", name,
                                   "' (declare it extern \"C\" __global__, or __device__ for "
                                   "callables)"));
  }
  entry->set_module_hash(module->launch->hash);
  entry->set_module_path(module->launch->path);
  entry->set_function(name);
  if (std::find(group.modules.begin(), group.modules.end(), module) == group.modules.end()) {
    group.modules.push_back(module);
    group.launch.modules.push_back(module->launch.get());
  }
  return true;
}

absl::StatusOr<std::shared_ptr<ProgramGroup>> CreateGroup(Call& call,
                                                          const std::shared_ptr<DeviceContext>& c,
                                                          const OptixProgramGroupDesc& desc,
                                                          const std::string& where) {
  auto group = std::make_shared<ProgramGroup>();
  group->context = c;
  v1::Optix7ProgramGroup& wire = group->launch.wire;
  wire.set_id(NextObjectId());
  wire.set_version(1);
  wire.set_kind(static_cast<uint32_t>(desc.kind));
  if (desc.flags != OPTIX_PROGRAM_GROUP_FLAGS_NONE) {
    return OptixError(OPTIX_ERROR_INVALID_VALUE,
                      absl::StrCat(where, ".flags is 0x", absl::Hex(desc.flags),
                                   "; OptiX 7.7 has no program group flags"));
  }
  OptixStackSizes& stack = group->stack_sizes;
  switch (desc.kind) {
    case OPTIX_PROGRAM_GROUP_KIND_RAYGEN: {
      const Slot slot{"raygen", desc.raygen.module, desc.raygen.entryFunctionName, "__raygen__"};
      absl::StatusOr<bool> has = AddEntry(call, where, slot, false, *group, wire.mutable_entry());
      if (!has.ok()) return has.status();
      if (!*has) {
        return OptixError(OPTIX_ERROR_INVALID_VALUE,
                          absl::StrCat(where,
                                       ": a raygen group needs a module and an entry "
                                       "function"));
      }
      stack.cssRG = kCssRaygen;
      break;
    }
    case OPTIX_PROGRAM_GROUP_KIND_MISS: {
      // A miss group without a program is allowed: rays that miss do nothing.
      const Slot slot{"miss", desc.miss.module, desc.miss.entryFunctionName, "__miss__"};
      absl::StatusOr<bool> has = AddEntry(call, where, slot, false, *group, wire.mutable_entry());
      if (!has.ok()) return has.status();
      if (*has) stack.cssMS = kCssMiss;
      break;
    }
    case OPTIX_PROGRAM_GROUP_KIND_EXCEPTION: {
      const Slot slot{"exception", desc.exception.module, desc.exception.entryFunctionName,
                      "__exception__"};
      absl::StatusOr<bool> has = AddEntry(call, where, slot, false, *group, wire.mutable_entry());
      if (!has.ok()) return has.status();
      break;
    }
    case OPTIX_PROGRAM_GROUP_KIND_HITGROUP: {
      // Any of the three may be absent: no closest hit, no any hit, and without an intersection
      // module the built-in triangle intersection (builtin_primitive 0).
      const OptixProgramGroupHitgroup& h = desc.hitgroup;
      absl::StatusOr<bool> ch =
          AddEntry(call, where,
                   Slot{"hitgroup.moduleCH", h.moduleCH, h.entryFunctionNameCH, "__closesthit__"},
                   false, *group, wire.mutable_closest_hit());
      if (!ch.ok()) return ch.status();
      absl::StatusOr<bool> ah = AddEntry(
          call, where, Slot{"hitgroup.moduleAH", h.moduleAH, h.entryFunctionNameAH, "__anyhit__"},
          false, *group, wire.mutable_any_hit());
      if (!ah.ok()) return ah.status();
      std::shared_ptr<const Module> is_module;
      absl::StatusOr<bool> is =
          AddEntry(call, where,
                   Slot{"hitgroup.moduleIS", h.moduleIS, h.entryFunctionNameIS, "__intersection__"},
                   true, *group, wire.mutable_intersection(), &is_module);
      if (!is.ok()) return is.status();
      if (is_module != nullptr && is_module->is_builtin()) {
        wire.set_builtin_primitive(static_cast<uint32_t>(is_module->builtin));
        group->modules.push_back(is_module);  // its options take part in the pipeline's checks
      }
      if (*ch) stack.cssCH = kCssClosestHit;
      if (*ah) stack.cssAH = kCssAnyHit;
      if (*is && !is_module->is_builtin()) stack.cssIS = kCssIntersection;
      break;
    }
    case OPTIX_PROGRAM_GROUP_KIND_CALLABLES: {
      const OptixProgramGroupCallables& k = desc.callables;
      absl::StatusOr<bool> dc = AddEntry(
          call, where,
          Slot{"callables.moduleDC", k.moduleDC, k.entryFunctionNameDC, "__direct_callable__"},
          false, *group, wire.mutable_entry());
      if (!dc.ok()) return dc.status();
      absl::StatusOr<bool> cc = AddEntry(call, where,
                                         Slot{"callables.moduleCC", k.moduleCC,
                                              k.entryFunctionNameCC, "__continuation_callable__"},
                                         false, *group, wire.mutable_continuation());
      if (!cc.ok()) return cc.status();
      if (!*dc && !*cc) {
        return OptixError(OPTIX_ERROR_INVALID_VALUE,
                          absl::StrCat(where,
                                       ": a callables group needs a direct or a "
                                       "continuation callable"));
      }
      if (*dc) stack.dssDC = kDssDirectCallable;
      if (*cc) stack.cssCC = kCssContinuationCallable;
      break;
    }
    default:
      return OptixError(OPTIX_ERROR_INVALID_VALUE,
                        absl::StrCat(where, ".kind 0x", absl::Hex(static_cast<unsigned>(desc.kind)),
                                     " is no OptixProgramGroupKind"));
  }
  return group;
}

}  // namespace
}  // namespace tessera::optix7

using tessera::optix7::Call;
using tessera::optix7::DeviceContext;
using tessera::optix7::OptixError;
using tessera::optix7::Pipeline;
using tessera::optix7::ProgramGroup;

extern "C" {

OptixResult optixProgramGroupCreate(OptixDeviceContext context,
                                    const OptixProgramGroupDesc* programDescriptions,
                                    unsigned int numProgramGroups,
                                    const OptixProgramGroupOptions* options, char* logString,
                                    size_t* logStringSize, OptixProgramGroup* programGroups) {
  return Call("optixProgramGroupCreate", logString, logStringSize)
      .Run([&](Call& call) -> absl::Status {
        std::shared_ptr<DeviceContext> c;
        if (absl::Status s = call.Lookup(context, "context", &c); !s.ok()) return s;
        if (absl::Status s = call.NotNull(programDescriptions, "programDescriptions"); !s.ok()) {
          return s;
        }
        if (absl::Status s = call.NotNull(programGroups, "programGroups"); !s.ok()) return s;
        if (numProgramGroups == 0) {
          return OptixError(OPTIX_ERROR_INVALID_VALUE, "numProgramGroups is 0");
        }
        if (options != nullptr && options->payloadType != nullptr) {
          const OptixPayloadType& t = *options->payloadType;
          if (t.numPayloadValues > tessera::optix7::kMaxPayloadValues ||
              (t.numPayloadValues > 0 && t.payloadSemantics == nullptr)) {
            return OptixError(OPTIX_ERROR_INVALID_VALUE,
                              absl::StrCat("options->payloadType has ", t.numPayloadValues,
                                           " values (at most 32) or null semantics"));
          }
        }
        // All or nothing: groups made before a failing description are not registered.
        std::vector<std::shared_ptr<ProgramGroup>> made;
        for (unsigned i = 0; i < numProgramGroups; ++i) {
          absl::StatusOr<std::shared_ptr<ProgramGroup>> group = tessera::optix7::CreateGroup(
              call, c, programDescriptions[i], absl::StrCat("programDescriptions[", i, "]"));
          if (!group.ok()) return group.status();
          made.push_back(*std::move(group));
        }
        for (unsigned i = 0; i < numProgramGroups; ++i) {
          tessera::optix7::Register(made[i], c.get());
          programGroups[i] = reinterpret_cast<OptixProgramGroup>(made[i].get());
        }
        return absl::OkStatus();
      });
}

OptixResult optixProgramGroupDestroy(OptixProgramGroup programGroup) {
  return Call("optixProgramGroupDestroy").Run([&](Call& call) -> absl::Status {
    std::shared_ptr<ProgramGroup> g;
    if (absl::Status s = call.Lookup(programGroup, "programGroup", &g); !s.ok()) return s;
    tessera::optix7::UnregisterObject(ProgramGroup::kKind, programGroup);
    return absl::OkStatus();
  });
}

OptixResult optixProgramGroupGetStackSize(OptixProgramGroup programGroup,
                                          OptixStackSizes* stackSizes, OptixPipeline pipeline) {
  return Call("optixProgramGroupGetStackSize").Run([&](Call& call) -> absl::Status {
    std::shared_ptr<ProgramGroup> g;
    if (absl::Status s = call.Lookup(programGroup, "programGroup", &g); !s.ok()) return s;
    if (absl::Status s = call.NotNull(stackSizes, "stackSizes"); !s.ok()) return s;
    if (pipeline != nullptr) {  // 7.7: the pipeline the group is linked into, or null
      std::shared_ptr<Pipeline> p;
      if (absl::Status s = call.Lookup(pipeline, "pipeline", &p); !s.ok()) return s;
    }
    *stackSizes = g->stack_sizes;
    return absl::OkStatus();
  });
}

}  // extern "C"
