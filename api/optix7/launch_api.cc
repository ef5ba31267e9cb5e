// optixSbtRecordPackHeader and optixLaunch: the arguments are checked here, the launch itself is
// optix7::Launch (launch7.h) on the context's devices.
#include <cstring>
#include <memory>
#include <string>

#include "absl/strings/str_cat.h"
#include "call.h"
#include "host_device_memory.h"
#include "optix_host.h"
#include "sbt_header.h"

namespace tessera::optix7 {
namespace {

// OptiX's limit on width * height * depth.
constexpr uint64_t kMaxLaunchSize = uint64_t{1} << 30;

// One section of the SBT: `count` records of `stride` bytes from `base`, all in one allocation.
// Validation mode also checks the base's alignment and that each record was packed by a program
// group of `pipeline`.
absl::Status CheckSection(HostDeviceMemory& memory, const Pipeline& pipeline, bool validate,
                          const char* name, CUdeviceptr base, unsigned stride, unsigned count) {
  if (count == 0) return absl::OkStatus();
  // raygen and exception are one record each, named without "Base".
  const std::string base_field = absl::StrCat(
      "sbt->", name,
      count == 1 && stride == 0 && (name[0] == 'r' || name[0] == 'e') ? "Record" : "RecordBase");
  if (base == 0) {
    return OptixError(OPTIX_ERROR_INVALID_VALUE,
                      absl::StrCat(base_field, " is null with ", name, "RecordCount ", count));
  }
  if (stride % OPTIX_SBT_RECORD_ALIGNMENT != 0) {
    return OptixError(OPTIX_ERROR_INVALID_VALUE,
                      absl::StrCat("sbt->", name, "RecordStrideInBytes is ", stride,
                                   ", not a multiple of OPTIX_SBT_RECORD_ALIGNMENT (16)"));
  }
  const uint64_t bytes = uint64_t{stride} * (count - 1) + OPTIX_SBT_RECORD_HEADER_SIZE;
  if (!memory.IsAllocated(base, bytes)) {
    return OptixError(
        OPTIX_ERROR_INVALID_VALUE,
        absl::StrCat(base_field, " 0x", absl::Hex(base), ": ", count, " records of stride ", stride,
                     " (", bytes, " bytes) are not in one cudaMalloc allocation"));
  }
  if (!validate) return absl::OkStatus();
  if (base % OPTIX_SBT_RECORD_ALIGNMENT != 0) {
    return OptixError(OPTIX_ERROR_VALIDATION_FAILURE,
                      absl::StrCat(base_field, " 0x", absl::Hex(base),
                                   " is not OPTIX_SBT_RECORD_ALIGNMENT (16) aligned"));
  }
  for (unsigned i = 0; i < count; ++i) {
    memory::SbtHeader h;
    std::memcpy(&h, reinterpret_cast<const void*>(base + uint64_t{stride} * i), sizeof(h));
    bool known = false;
    for (const LaunchProgramGroup* g : pipeline.launch.groups)
      known |= g->wire.id() == h.program_group;
    if (h.magic != memory::kSbtHeaderMagic || !known) {
      return OptixError(OPTIX_ERROR_VALIDATION_FAILURE,
                        absl::StrCat("sbt ", name, " record ", i, " at 0x",
                                     absl::Hex(base + uint64_t{stride} * i),
                                     h.magic != memory::kSbtHeaderMagic
                                         ? " has no header packed by optixSbtRecordPackHeader"
                                         : " was packed by a program group not in the pipeline"));
    }
  }
  return absl::OkStatus();
}

absl::Status CheckSbt(HostDeviceMemory& memory, const Pipeline& p, bool validate,
                      const OptixShaderBindingTable& sbt) {
  if (sbt.raygenRecord == 0) {
    return OptixError(OPTIX_ERROR_INVALID_VALUE, "sbt->raygenRecord is null");
  }
  if (!memory.IsAllocated(sbt.raygenRecord, OPTIX_SBT_RECORD_HEADER_SIZE)) {
    return OptixError(OPTIX_ERROR_INVALID_VALUE,
                      absl::StrCat("sbt->raygenRecord 0x", absl::Hex(sbt.raygenRecord),
                                   " is not device memory (a cudaMalloc allocation holding its "
                                   "32-byte header)"));
  }
  if (absl::Status s = CheckSection(memory, p, validate, "raygen", sbt.raygenRecord, 0, 1);
      !s.ok()) {
    return s;
  }
  if (sbt.exceptionRecord != 0) {
    if (absl::Status s = CheckSection(memory, p, validate, "exception", sbt.exceptionRecord, 0, 1);
        !s.ok()) {
      return s;
    }
  }
  if (absl::Status s = CheckSection(memory, p, validate, "miss", sbt.missRecordBase,
                                    sbt.missRecordStrideInBytes, sbt.missRecordCount);
      !s.ok()) {
    return s;
  }
  if (absl::Status s = CheckSection(memory, p, validate, "hitgroup", sbt.hitgroupRecordBase,
                                    sbt.hitgroupRecordStrideInBytes, sbt.hitgroupRecordCount);
      !s.ok()) {
    return s;
  }
  return CheckSection(memory, p, validate, "callables", sbt.callablesRecordBase,
                      sbt.callablesRecordStrideInBytes, sbt.callablesRecordCount);
}

}  // namespace
}  // namespace tessera::optix7

using tessera::optix7::Call;
using tessera::optix7::HostDeviceMemory;
using tessera::optix7::OptixError;
using tessera::optix7::Pipeline;
using tessera::optix7::ProgramGroup;

extern "C" {

OptixResult optixSbtRecordPackHeader(OptixProgramGroup programGroup,
                                     void* sbtRecordHeaderHostPointer) {
  return Call("optixSbtRecordPackHeader").Run([&](Call& call) -> absl::Status {
    std::shared_ptr<ProgramGroup> g;
    if (absl::Status s = call.Lookup(programGroup, "programGroup", &g); !s.ok()) return s;
    if (absl::Status s = call.NotNull(sbtRecordHeaderHostPointer, "sbtRecordHeaderHostPointer");
        !s.ok()) {
      return s;
    }
    // A device pointer would be written behind the back of the memory that launches ship (and
    // crashes in OptiX): the header is packed on the host and copied with cudaMemcpy.
    absl::StatusOr<HostDeviceMemory*> memory = HostDeviceMemory::Get();
    if (memory.ok() &&
        (*memory)->InArena(reinterpret_cast<uintptr_t>(sbtRecordHeaderHostPointer))) {
      return OptixError(OPTIX_ERROR_INVALID_VALUE,
                        "sbtRecordHeaderHostPointer is device memory; pack the header into a host "
                        "record and copy it with cudaMemcpy");
    }
    const tessera::memory::SbtHeader header{
        tessera::memory::kSbtHeaderMagic, g->launch.wire.id(), {0, 0}};
    std::memcpy(sbtRecordHeaderHostPointer, &header, sizeof(header));
    return absl::OkStatus();
  });
}

// `stream` is not checked: every call finishes before it returns (cuda_runtime.cc), so streams
// order nothing.
OptixResult optixLaunch(OptixPipeline pipeline, CUstream stream, CUdeviceptr pipelineParams,
                        size_t pipelineParamsSize, const OptixShaderBindingTable* sbt,
                        unsigned int width, unsigned int height, unsigned int depth) {
  (void)stream;
  return Call("optixLaunch")
      .Run(
          [&](Call& call) -> absl::Status {
            std::shared_ptr<Pipeline> p;
            if (absl::Status s = call.Lookup(pipeline, "pipeline", &p); !s.ok()) return s;
            if (absl::Status s = call.NotNull(sbt, "sbt"); !s.ok()) return s;
            absl::StatusOr<HostDeviceMemory*> memory = HostDeviceMemory::Get();
            if (!memory.ok()) {
              return OptixError(OPTIX_ERROR_CUDA_ERROR, memory.status().message());
            }
            if (absl::Status s =
                    tessera::optix7::CheckSbt(**memory, *p, p->context->validation(), *sbt);
                !s.ok()) {
              return s;
            }
            if (pipelineParamsSize > 0 &&
                (pipelineParams == 0 ||
                 !(*memory)->IsAllocated(pipelineParams, pipelineParamsSize))) {
              return OptixError(
                  OPTIX_ERROR_INVALID_VALUE,
                  absl::StrCat("pipelineParams 0x", absl::Hex(pipelineParams), " (",
                               pipelineParamsSize, " bytes) is not in one cudaMalloc allocation"));
            }
            const uint64_t size = uint64_t{width} * height * depth;
            if (size == 0 || size > tessera::optix7::kMaxLaunchSize) {
              return OptixError(
                  OPTIX_ERROR_INVALID_VALUE,
                  absl::StrCat("launch of ", width, " x ", height, " x ", depth,
                               ": each dimension must be at least 1 and their product "
                               "at most 2^30"));
            }
            return p->context->WithLaunchTarget([&](tessera::optix7::LaunchTarget& target) {
              return tessera::optix7::Launch(target, p->launch, pipelineParams, pipelineParamsSize,
                                             *sbt, width, height, depth,
                                             p->context->accuracy_flags());
            });
          },
          OPTIX_ERROR_LAUNCH_FAILURE);
}

}  // extern "C"
