// The compile options of OptiX 7 modules and pipelines: their checks (what OptiX refuses, with
// the field named) and the copy a module keeps so that a pipeline can check that its modules
// were compiled with its own options, as OptiX requires.
#ifndef TESSERA_API_OPTIX7_COMPILE_OPTIONS_H_
#define TESSERA_API_OPTIX7_COMPILE_OPTIONS_H_

#include <optional>
#include <string>

#include "absl/status/status.h"
#include "optix_types.h"

namespace tessera::optix7 {

// OptiX 7.7's limits (Programming Guide §6.1).
inline constexpr int kMaxPayloadValues = 32;
inline constexpr int kMaxAttributeValues = 8;
inline constexpr unsigned kMaxTraceDepth = 31;

// OptixPipelineCompileOptions with the launch parameters' name owned.
struct PipelineOptions {
  int uses_motion_blur = 0;
  unsigned traversable_graph_flags = 0;
  int num_payload_values = 0;
  int num_attribute_values = 0;
  unsigned exception_flags = 0;
  std::optional<std::string> params_name;  // pipelineLaunchParamsVariableName
  unsigned primitive_type_flags = 0;       // usesPrimitiveTypeFlags as given (0: the default)
  int allow_opacity_micromaps = 0;
};

// INVALID_ARGUMENT naming the field for what OptiX refuses.
absl::Status CheckPipelineCompileOptions(const OptixPipelineCompileOptions& options);
absl::Status CheckModuleCompileOptions(const OptixModuleCompileOptions& options,
                                       const OptixPipelineCompileOptions& pipeline);

PipelineOptions CopyPipelineOptions(const OptixPipelineCompileOptions& options);

// The first field where `a` and `b` differ, as "numPayloadValues (2 here, 3 there)"; empty when
// they are the same.
std::string PipelineOptionsDifference(const PipelineOptions& here, const PipelineOptions& there);

// usesPrimitiveTypeFlags as OptiX reads it: 0 means custom primitives and triangles.
unsigned EffectivePrimitiveTypeFlags(unsigned flags);

// The OptixPrimitiveTypeFlags bit of a built-in primitive type; 0 for a type that has none.
unsigned PrimitiveTypeFlag(OptixPrimitiveType type);

// The largest payload size the options allow (numPayloadValues, or the largest payload type's).
int PayloadValueCount(const OptixModuleCompileOptions& module,
                      const OptixPipelineCompileOptions& pipeline);

}  // namespace tessera::optix7

#endif  // TESSERA_API_OPTIX7_COMPILE_OPTIONS_H_
