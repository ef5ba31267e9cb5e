#include "launch7.h"

#include <vector>

#include "launch_target.h"

namespace tessera::optix7 {

absl::Status Launch(LaunchTarget& target, const LaunchPipeline& pipeline, CUdeviceptr params,
                    size_t params_size, const OptixShaderBindingTable& sbt, unsigned width,
                    unsigned height, unsigned depth, uint32_t accuracy_flags) {
  if (width == 0 || height == 0 || depth == 0) return absl::OkStatus();  // nothing to run
  v1::Optix7Launch launch;
  launch.set_pipeline(pipeline.wire.id());
  launch.set_params(params);
  launch.set_params_size(params_size);
  launch.set_raygen_record(sbt.raygenRecord);
  launch.set_exception_record(sbt.exceptionRecord);
  launch.set_miss_record_base(sbt.missRecordBase);
  launch.set_miss_record_stride(sbt.missRecordStrideInBytes);
  launch.set_miss_record_count(sbt.missRecordCount);
  launch.set_hitgroup_record_base(sbt.hitgroupRecordBase);
  launch.set_hitgroup_record_stride(sbt.hitgroupRecordStrideInBytes);
  launch.set_hitgroup_record_count(sbt.hitgroupRecordCount);
  launch.set_callables_record_base(sbt.callablesRecordBase);
  launch.set_callables_record_stride(sbt.callablesRecordStrideInBytes);
  launch.set_callables_record_count(sbt.callablesRecordCount);
  launch.set_accuracy_flags(accuracy_flags);
  // Trailing dimensions of 1 are left out: a 2D launch tiles as 2D.
  std::vector<uint64_t> dims{width, height, depth};
  while (dims.size() > 1 && dims.back() == 1) dims.pop_back();
  return LaunchOnTarget(target, pipeline, launch, dims);
}

}  // namespace tessera::optix7
