// Optix7Engine::Prepare: an optixLaunch's pipeline, launch parameters and SBT resolved before any
// tile runs (optix7_launch.h), every error naming the object it is about.
#include <algorithm>
#include <atomic>
#include <cstring>
#include <string_view>

#include "absl/strings/str_cat.h"
#include "module.h"
#include "optix7_engine.h"
#include "optix7_launch.h"
#include "optix7_module_init.h"
#include "optix_types.h"
#include "sbt_header.h"
#include "tessera/accuracy.h"
#include "tessera/optix7_device_abi.h"

namespace tessera::worker {
namespace {

static_assert(kOptix7ModuleFlagFastMath == TESSERA_OPTIX7_MODULE_FLAG_FAST_MATH);
static_assert(std::string_view(kOptix7ModuleFlagsSymbol) == TESSERA_OPTIX7_MODULE_FLAGS_SYMBOL);

std::string Hex(uint64_t v) { return absl::StrCat("0x", absl::Hex(v)); }

const char* GroupKindName(uint32_t kind) {
  switch (kind) {
    case OPTIX_PROGRAM_GROUP_KIND_RAYGEN:
      return "raygen";
    case OPTIX_PROGRAM_GROUP_KIND_MISS:
      return "miss";
    case OPTIX_PROGRAM_GROUP_KIND_EXCEPTION:
      return "exception";
    case OPTIX_PROGRAM_GROUP_KIND_HITGROUP:
      return "hit group";
    case OPTIX_PROGRAM_GROUP_KIND_CALLABLES:
      return "callables";
    default:
      return "unknown";
  }
}

// One entry function: its module loaded (and handed the engine's table) and its symbol found.
// `modules` collects the pipeline's modules, for the launch parameters.
absl::StatusOr<Optix7Entry> Resolve(const v1::Optix7Entry& e, const v1::Optix7ProgramGroup& g,
                                    std::map<std::string, const Module*>& modules) {
  Optix7Entry out;
  if (e.function().empty()) return out;
  const std::string where = absl::StrCat("program group ", g.id(), " (", GroupKindName(g.kind()),
                                         "): ", e.function(), " in ", e.module_path());
  absl::StatusOr<const Module*> m = ModuleCache::Get().Load(e.module_hash(), e.module_path());
  if (!m.ok())
    return absl::Status(m.status().code(), absl::StrCat(where, ": ", m.status().message()));
  if (!(*m)->optix7()) {
    return absl::InvalidArgumentError(
        absl::StrCat(where, ": the module is an OptiX 3 module (tessera/device.h), not OptiX 7"));
  }
  out.function = reinterpret_cast<Optix7Function>((*m)->Function(e.function()));
  if (out.function == nullptr) {
    return absl::NotFoundError(
        absl::StrCat(where, ": the module defines no extern \"C\" function of that name"));
  }
  out.name = absl::StrCat(e.function(), " in ", e.module_path());
  modules.emplace(e.module_hash(), *m);
  return out;
}

absl::StatusOr<Optix7Group> ResolveGroup(const v1::Optix7ProgramGroup& g,
                                         std::map<std::string, const Module*>& modules) {
  Optix7Group out;
  out.id = g.id();
  out.kind = g.kind();
  out.builtin_primitive = g.builtin_primitive();
  struct Slot {
    const v1::Optix7Entry& from;
    Optix7Entry& to;
  };
  const Slot slots[] = {{g.entry(), out.entry},
                        {g.continuation(), out.continuation},
                        {g.closest_hit(), out.closest_hit},
                        {g.any_hit(), out.any_hit},
                        {g.intersection(), out.intersection}};
  for (const Slot& s : slots) {
    absl::StatusOr<Optix7Entry> e = Resolve(s.from, g, modules);
    if (!e.ok()) return e.status();
    s.to = std::move(*e);
  }
  const std::string name = absl::StrCat("program group ", g.id());
  switch (g.kind()) {
    case OPTIX_PROGRAM_GROUP_KIND_RAYGEN:
      if (out.entry.function == nullptr) {
        return absl::InvalidArgumentError(absl::StrCat(name, ": a raygen group without program"));
      }
      break;
    case OPTIX_PROGRAM_GROUP_KIND_MISS:
    case OPTIX_PROGRAM_GROUP_KIND_EXCEPTION:
    case OPTIX_PROGRAM_GROUP_KIND_CALLABLES:
      break;
    case OPTIX_PROGRAM_GROUP_KIND_HITGROUP:
      if (out.intersection.function == nullptr && g.builtin_primitive() != 0 &&
          g.builtin_primitive() != OPTIX_PRIMITIVE_TYPE_TRIANGLE) {
        return absl::UnimplementedError(
            absl::StrCat(name, ": built-in intersection of primitive type ",
                         Hex(g.builtin_primitive()), " (curves and spheres) is not supported yet"));
      }
      break;
    default:
      return absl::InvalidArgumentError(absl::StrCat(name, ": unknown kind ", Hex(g.kind())));
  }
  return out;
}

// One SBT record of `bytes` (header included) at `address`, which must hold a header packed for
// a program group of the pipeline of kind `kind`. `what` names it: "SBT miss record 2".
absl::StatusOr<Optix7Record> ReadRecord(const Optix7Launch& l, uint64_t address, uint64_t bytes,
                                        const std::string& what, uint32_t kind) {
  const std::string at = absl::StrCat(what, " at ", Hex(address), ": ");
  if (address % OPTIX_SBT_RECORD_ALIGNMENT != 0) {
    return absl::InvalidArgumentError(
        absl::StrCat(at, "not aligned to OPTIX_SBT_RECORD_ALIGNMENT (16 bytes)"));
  }
  const uint64_t readable = l.Readable(address);
  if (readable == 0) return absl::InvalidArgumentError(absl::StrCat(at, "not in device memory"));
  if (readable < std::max<uint64_t>(bytes, sizeof(memory::SbtHeader))) {
    return absl::InvalidArgumentError(
        absl::StrCat(at, "its ", bytes, " bytes run past the end of its allocation"));
  }
  memory::SbtHeader header;
  std::memcpy(&header, reinterpret_cast<const void*>(address), sizeof(header));
  if (header.magic != memory::kSbtHeaderMagic) {
    return absl::InvalidArgumentError(
        absl::StrCat(at, "the header was not packed (optixSbtRecordPackHeader never wrote it)"));
  }
  auto it = l.groups.find(header.program_group);
  if (it == l.groups.end()) {
    return absl::InvalidArgumentError(absl::StrCat(at, "packed for program group ",
                                                   header.program_group,
                                                   ", which is not in the launch's pipeline"));
  }
  if (it->second.kind != kind) {
    return absl::InvalidArgumentError(
        absl::StrCat(at, "packed for program group ", header.program_group, ", whose kind is ",
                     GroupKindName(it->second.kind), ", not ", GroupKindName(kind)));
  }
  return Optix7Record{&it->second, address + sizeof(memory::SbtHeader), 0};
}

// An array of SBT records (miss, hit group, callables).
absl::Status ReadSection(const Optix7Launch& l, uint64_t base, uint32_t stride, uint32_t count,
                         const char* name, uint32_t kind, std::vector<Optix7Record>& out) {
  out.clear();
  if (count == 0) return absl::OkStatus();
  const std::string section = absl::StrCat("SBT ", name, " records at ", Hex(base));
  if (base == 0) {
    return absl::InvalidArgumentError(absl::StrCat(section, ": null base for ", count, " records"));
  }
  if (stride % OPTIX_SBT_RECORD_ALIGNMENT != 0 || stride < OPTIX_SBT_RECORD_HEADER_SIZE) {
    return absl::InvalidArgumentError(
        absl::StrCat(section, ": stride ", stride,
                     " is not a multiple of 16 bytes (OPTIX_SBT_RECORD_ALIGNMENT) of at least the "
                     "32-byte header"));
  }
  out.reserve(count);
  for (uint32_t i = 0; i < count; ++i) {
    const uint64_t address = base + uint64_t{i} * stride;
    absl::StatusOr<Optix7Record> r =
        ReadRecord(l, address, stride, absl::StrCat("SBT ", name, " record ", i), kind);
    if (!r.ok()) return r.status();
    r->index = i;
    out.push_back(*r);
  }
  return absl::OkStatus();
}

// Copies the launch parameters into each module's `name` variable (a module's globals are shared
// by every launch in the process: hence Optix7CallMutex).
absl::Status CopyParams(const Optix7Launch& l, const v1::Optix7Launch& launch,
                        const std::string& name,
                        const std::map<std::string, const Module*>& modules) {
  if (name.empty()) return absl::OkStatus();
  const uint64_t size = launch.params_size();
  if (size > 0 && l.Readable(launch.params()) < size) {
    return absl::InvalidArgumentError(absl::StrCat("launch parameters at ", Hex(launch.params()),
                                                   " (", size,
                                                   " bytes): not in one allocation "
                                                   "of device memory"));
  }
  for (const auto& [hash, m] : modules) {
    size_t symbol_size = 0;
    void* symbol = m->Data(name, &symbol_size);
    if (symbol == nullptr) continue;  // a module that does not read the parameters
    if (size > symbol_size) {
      return absl::InvalidArgumentError(absl::StrCat("launch parameters: ", size, " bytes for '",
                                                     name, "' of ", m->path(), ", which is ",
                                                     symbol_size, " bytes"));
    }
    if (size > 0) std::memcpy(symbol, reinterpret_cast<const void*>(launch.params()), size);
    // Bytes the launch does not pass read zeros, not what an earlier launch left.
    std::memset(static_cast<char*>(symbol) + size, 0, symbol_size - size);
  }
  return absl::OkStatus();
}

}  // namespace

absl::Status Optix7Engine::Prepare(const Optix7State& state, const v1::Optix7Launch& launch,
                                   const std::atomic<bool>* cancel) {
  static std::atomic<uint64_t> next_serial{0};
  auto l = std::make_unique<Optix7Launch>();
  l->serial = ++next_serial;
  l->engine = this;
  l->allocations = state.allocations;
  auto p = state.pipelines.find(launch.pipeline());
  if (p == state.pipelines.end()) {
    return absl::FailedPreconditionError(
        absl::StrCat("optixLaunch: pipeline ", launch.pipeline(), " is not on this device"));
  }
  const v1::Optix7Pipeline& pipeline = p->second;
  constexpr uint32_t kMaxTraceDepth = 31;  // guide 10, "Limits"
  l->max_trace_depth = std::min(pipeline.max_trace_depth(), kMaxTraceDepth);
  l->exception_flags = pipeline.exception_flags();
  l->graph_flags = pipeline.traversable_graph_flags();
  l->primitive_flags = pipeline.primitive_type_flags();
  l->motion_blur = pipeline.uses_motion_blur();
  l->batched = launch.batched();
  l->accuracy = launch.accuracy_flags();
  std::map<std::string, const Module*> modules;  // by hash
  for (uint64_t id : pipeline.program_groups()) {
    if (cancel != nullptr && cancel->load(std::memory_order_relaxed)) {
      return absl::CancelledError("optixLaunch cancelled while preparing");
    }
    auto g = state.program_groups.find(id);
    if (g == state.program_groups.end()) {
      return absl::FailedPreconditionError(absl::StrCat(
          "pipeline ", pipeline.id(), ": program group ", id, " is not on this device"));
    }
    absl::StatusOr<Optix7Group> group = ResolveGroup(g->second, modules);
    if (!group.ok()) {
      return absl::Status(group.status().code(),
                          absl::StrCat("pipeline ", pipeline.id(), ": ", group.status().message()));
    }
    l->groups[id] = std::move(*group);
  }
  if (absl::Status s = CopyParams(*l, launch, pipeline.params_name(), modules); !s.ok()) return s;
  // A fast-math module of the pipeline, or a context that asks for fast math, flushes denormals
  // on the launch's threads (docs/fast_math.md).
  l->flush_denormals = (launch.accuracy_flags() & TESSERA_ACCURACY_FAST_MATH) != 0 ||
                       std::any_of(modules.begin(), modules.end(),
                                   [](const auto& m) { return m.second->fast_math(); });

  if (launch.raygen_record() == 0) {
    return absl::InvalidArgumentError("SBT: no raygen record (raygenRecord is 0)");
  }
  absl::StatusOr<Optix7Record> rg = ReadRecord(*l, launch.raygen_record(), 0, "SBT raygen record",
                                               OPTIX_PROGRAM_GROUP_KIND_RAYGEN);
  if (!rg.ok()) return rg.status();
  l->raygen = *rg;
  if (launch.exception_record() != 0) {
    absl::StatusOr<Optix7Record> ex =
        ReadRecord(*l, launch.exception_record(), 0, "SBT exception record",
                   OPTIX_PROGRAM_GROUP_KIND_EXCEPTION);
    if (!ex.ok()) return ex.status();
    l->exception = *ex;
  }
  if (absl::Status s =
          ReadSection(*l, launch.miss_record_base(), launch.miss_record_stride(),
                      launch.miss_record_count(), "miss", OPTIX_PROGRAM_GROUP_KIND_MISS, l->miss);
      !s.ok()) {
    return s;
  }
  if (absl::Status s = ReadSection(*l, launch.hitgroup_record_base(),
                                   launch.hitgroup_record_stride(), launch.hitgroup_record_count(),
                                   "hit group", OPTIX_PROGRAM_GROUP_KIND_HITGROUP, l->hit);
      !s.ok()) {
    return s;
  }
  if (absl::Status s =
          ReadSection(*l, launch.callables_record_base(), launch.callables_record_stride(),
                      launch.callables_record_count(), "callables",
                      OPTIX_PROGRAM_GROUP_KIND_CALLABLES, l->callables);
      !s.ok()) {
    return s;
  }
  l->any_hit = std::any_of(l->hit.begin(), l->hit.end(), [](const Optix7Record& r) {
    return r.group->any_hit.function != nullptr;
  });
  launch_ = std::move(l);
  return absl::OkStatus();
}

}  // namespace tessera::worker
