#include "compile_options.h"

#include <algorithm>

#include "absl/strings/str_cat.h"

namespace tessera::optix7 {
namespace {

constexpr unsigned kExceptionFlags = OPTIX_EXCEPTION_FLAG_STACK_OVERFLOW |
                                     OPTIX_EXCEPTION_FLAG_TRACE_DEPTH | OPTIX_EXCEPTION_FLAG_USER |
                                     OPTIX_EXCEPTION_FLAG_DEBUG;
constexpr unsigned kGraphFlags = OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_SINGLE_GAS |
                                 OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_SINGLE_LEVEL_INSTANCING;
constexpr unsigned kPrimitiveFlags =
    OPTIX_PRIMITIVE_TYPE_FLAGS_CUSTOM | OPTIX_PRIMITIVE_TYPE_FLAGS_ROUND_QUADRATIC_BSPLINE |
    OPTIX_PRIMITIVE_TYPE_FLAGS_ROUND_CUBIC_BSPLINE | OPTIX_PRIMITIVE_TYPE_FLAGS_ROUND_LINEAR |
    OPTIX_PRIMITIVE_TYPE_FLAGS_ROUND_CATMULLROM |
    OPTIX_PRIMITIVE_TYPE_FLAGS_FLAT_QUADRATIC_BSPLINE | OPTIX_PRIMITIVE_TYPE_FLAGS_SPHERE |
    OPTIX_PRIMITIVE_TYPE_FLAGS_ROUND_CUBIC_BEZIER |
    OPTIX_PRIMITIVE_TYPE_FLAGS_DISPLACED_MICROMESH_TRIANGLE |
    static_cast<unsigned>(OPTIX_PRIMITIVE_TYPE_FLAGS_TRIANGLE);

absl::Status Invalid(const std::string& message) { return absl::InvalidArgumentError(message); }

bool ValidOptLevel(OptixCompileOptimizationLevel level) {
  return level == OPTIX_COMPILE_OPTIMIZATION_DEFAULT ||
         (level >= OPTIX_COMPILE_OPTIMIZATION_LEVEL_0 &&
          level <= OPTIX_COMPILE_OPTIMIZATION_LEVEL_3);
}

bool ValidDebugLevel(OptixCompileDebugLevel level) {
  return level == OPTIX_COMPILE_DEBUG_LEVEL_DEFAULT ||
         (level >= OPTIX_COMPILE_DEBUG_LEVEL_NONE && level <= OPTIX_COMPILE_DEBUG_LEVEL_MODERATE);
}

}  // namespace

absl::Status CheckPipelineCompileOptions(const OptixPipelineCompileOptions& o) {
  if (o.numPayloadValues < 0 || o.numPayloadValues > kMaxPayloadValues) {
    return Invalid(absl::StrCat("pipelineCompileOptions.numPayloadValues is ", o.numPayloadValues,
                                "; OptiX allows 0 to ", kMaxPayloadValues));
  }
  if (o.numAttributeValues < 0 || o.numAttributeValues > kMaxAttributeValues) {
    return Invalid(absl::StrCat("pipelineCompileOptions.numAttributeValues is ",
                                o.numAttributeValues, "; OptiX allows 0 to ", kMaxAttributeValues));
  }
  if ((o.exceptionFlags & ~kExceptionFlags) != 0) {
    return Invalid(absl::StrCat("pipelineCompileOptions.exceptionFlags 0x",
                                absl::Hex(o.exceptionFlags),
                                " has bits that are no OptixExceptionFlags"));
  }
  if ((o.traversableGraphFlags & ~kGraphFlags) != 0) {
    return Invalid(absl::StrCat("pipelineCompileOptions.traversableGraphFlags 0x",
                                absl::Hex(o.traversableGraphFlags),
                                " has bits that are no OptixTraversableGraphFlags"));
  }
  if ((o.usesPrimitiveTypeFlags & ~kPrimitiveFlags) != 0) {
    return Invalid(absl::StrCat("pipelineCompileOptions.usesPrimitiveTypeFlags 0x",
                                absl::Hex(o.usesPrimitiveTypeFlags),
                                " has bits that are no OptixPrimitiveTypeFlags"));
  }
  if (o.pipelineLaunchParamsVariableName != nullptr && *o.pipelineLaunchParamsVariableName == 0) {
    return Invalid(
        "pipelineCompileOptions.pipelineLaunchParamsVariableName is empty (null means none)");
  }
  return absl::OkStatus();
}

absl::Status CheckModuleCompileOptions(const OptixModuleCompileOptions& o,
                                       const OptixPipelineCompileOptions& pipeline) {
  if (o.maxRegisterCount < 0) {
    return Invalid(absl::StrCat("moduleCompileOptions.maxRegisterCount is ", o.maxRegisterCount,
                                " (0 is the default)"));
  }
  if (!ValidOptLevel(o.optLevel)) {
    return Invalid(absl::StrCat("moduleCompileOptions.optLevel 0x", absl::Hex(o.optLevel),
                                " is no OptixCompileOptimizationLevel"));
  }
  if (!ValidDebugLevel(o.debugLevel)) {
    return Invalid(absl::StrCat("moduleCompileOptions.debugLevel 0x", absl::Hex(o.debugLevel),
                                " is no OptixCompileDebugLevel"));
  }
  if (o.numBoundValues > 0 && o.boundValues == nullptr) {
    return Invalid(absl::StrCat("moduleCompileOptions.boundValues is null with numBoundValues ",
                                o.numBoundValues));
  }
  for (unsigned i = 0; i < o.numBoundValues; ++i) {
    const OptixModuleCompileBoundValueEntry& b = o.boundValues[i];
    if (b.boundValuePtr == nullptr || b.sizeInBytes == 0) {
      return Invalid(absl::StrCat("moduleCompileOptions.boundValues[", i,
                                  "] has a null boundValuePtr or a size of 0"));
    }
  }
  if (o.numPayloadTypes > OPTIX_COMPILE_DEFAULT_MAX_PAYLOAD_TYPE_COUNT) {
    return Invalid(absl::StrCat("moduleCompileOptions.numPayloadTypes is ", o.numPayloadTypes,
                                "; OptiX allows at most ",
                                OPTIX_COMPILE_DEFAULT_MAX_PAYLOAD_TYPE_COUNT));
  }
  if (o.numPayloadTypes > 0) {
    if (o.payloadTypes == nullptr) {
      return Invalid(absl::StrCat("moduleCompileOptions.payloadTypes is null with numPayloadTypes ",
                                  o.numPayloadTypes));
    }
    if (pipeline.numPayloadValues != 0) {
      return Invalid(absl::StrCat(
          "pipelineCompileOptions.numPayloadValues must be 0 when the module gives payload types "
          "(it is ",
          pipeline.numPayloadValues, ")"));
    }
    for (unsigned i = 0; i < o.numPayloadTypes; ++i) {
      const OptixPayloadType& t = o.payloadTypes[i];
      if (t.numPayloadValues == 0 || t.numPayloadValues > kMaxPayloadValues) {
        return Invalid(absl::StrCat("moduleCompileOptions.payloadTypes[", i,
                                    "].numPayloadValues is ", t.numPayloadValues,
                                    "; OptiX allows 1 to ", kMaxPayloadValues));
      }
      if (t.payloadSemantics == nullptr) {
        return Invalid(
            absl::StrCat("moduleCompileOptions.payloadTypes[", i, "].payloadSemantics is null"));
      }
    }
  }
  return absl::OkStatus();
}

PipelineOptions CopyPipelineOptions(const OptixPipelineCompileOptions& o) {
  PipelineOptions p;
  p.uses_motion_blur = o.usesMotionBlur;
  p.traversable_graph_flags = o.traversableGraphFlags;
  p.num_payload_values = o.numPayloadValues;
  p.num_attribute_values = o.numAttributeValues;
  p.exception_flags = o.exceptionFlags;
  if (o.pipelineLaunchParamsVariableName != nullptr) {
    p.params_name = o.pipelineLaunchParamsVariableName;
  }
  p.primitive_type_flags = o.usesPrimitiveTypeFlags;
  p.allow_opacity_micromaps = o.allowOpacityMicromaps;
  return p;
}

std::string PipelineOptionsDifference(const PipelineOptions& a, const PipelineOptions& b) {
  auto diff = [](const char* field, auto x, auto y) {
    return absl::StrCat(field, " (", x, " here, ", y, " there)");
  };
  if (a.uses_motion_blur != b.uses_motion_blur) {
    return diff("usesMotionBlur", a.uses_motion_blur, b.uses_motion_blur);
  }
  if (a.traversable_graph_flags != b.traversable_graph_flags) {
    return diff("traversableGraphFlags", a.traversable_graph_flags, b.traversable_graph_flags);
  }
  if (a.num_payload_values != b.num_payload_values) {
    return diff("numPayloadValues", a.num_payload_values, b.num_payload_values);
  }
  if (a.num_attribute_values != b.num_attribute_values) {
    return diff("numAttributeValues", a.num_attribute_values, b.num_attribute_values);
  }
  if (a.exception_flags != b.exception_flags) {
    return diff("exceptionFlags", a.exception_flags, b.exception_flags);
  }
  if (a.params_name != b.params_name) {
    return diff("pipelineLaunchParamsVariableName", a.params_name.value_or("(null)"),
                b.params_name.value_or("(null)"));
  }
  if (a.primitive_type_flags != b.primitive_type_flags) {
    return diff("usesPrimitiveTypeFlags", a.primitive_type_flags, b.primitive_type_flags);
  }
  if (a.allow_opacity_micromaps != b.allow_opacity_micromaps) {
    return diff("allowOpacityMicromaps", a.allow_opacity_micromaps, b.allow_opacity_micromaps);
  }
  return "";
}

unsigned EffectivePrimitiveTypeFlags(unsigned flags) {
  return flags != 0 ? flags
                    : OPTIX_PRIMITIVE_TYPE_FLAGS_CUSTOM |
                          static_cast<unsigned>(OPTIX_PRIMITIVE_TYPE_FLAGS_TRIANGLE);
}

unsigned PrimitiveTypeFlag(OptixPrimitiveType type) {
  switch (type) {
    case OPTIX_PRIMITIVE_TYPE_ROUND_QUADRATIC_BSPLINE:
      return OPTIX_PRIMITIVE_TYPE_FLAGS_ROUND_QUADRATIC_BSPLINE;
    case OPTIX_PRIMITIVE_TYPE_ROUND_CUBIC_BSPLINE:
      return OPTIX_PRIMITIVE_TYPE_FLAGS_ROUND_CUBIC_BSPLINE;
    case OPTIX_PRIMITIVE_TYPE_ROUND_LINEAR:
      return OPTIX_PRIMITIVE_TYPE_FLAGS_ROUND_LINEAR;
    case OPTIX_PRIMITIVE_TYPE_ROUND_CATMULLROM:
      return OPTIX_PRIMITIVE_TYPE_FLAGS_ROUND_CATMULLROM;
    case OPTIX_PRIMITIVE_TYPE_FLAT_QUADRATIC_BSPLINE:
      return OPTIX_PRIMITIVE_TYPE_FLAGS_FLAT_QUADRATIC_BSPLINE;
    case OPTIX_PRIMITIVE_TYPE_SPHERE:
      return OPTIX_PRIMITIVE_TYPE_FLAGS_SPHERE;
    case OPTIX_PRIMITIVE_TYPE_ROUND_CUBIC_BEZIER:
      return OPTIX_PRIMITIVE_TYPE_FLAGS_ROUND_CUBIC_BEZIER;
    default:
      return 0;
  }
}

int PayloadValueCount(const OptixModuleCompileOptions& module,
                      const OptixPipelineCompileOptions& pipeline) {
  int count = pipeline.numPayloadValues;
  for (unsigned i = 0; i < module.numPayloadTypes; ++i) {
    count = std::max(count, static_cast<int>(module.payloadTypes[i].numPayloadValues));
  }
  return count;
}

}  // namespace tessera::optix7
