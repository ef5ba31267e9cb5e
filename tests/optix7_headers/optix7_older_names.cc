// An application written against an OptiX 7.0-7.6 SDK, which spells the pre-7.7 names, asks for
// them with OPTIX_VERSION (docs/optix7.md): this translation unit is compiled with
// -DOPTIX_VERSION=70600 and uses optixModuleCreateFromPTX, OPTIX_ERROR_INVALID_PTX and
// OptixPipelineLinkOptions::debugLevel; the 7.7 spellings are absent.
#include <optix.h>
#include <optix_stack_size.h>
#include <optix_stubs.h>

static_assert(OPTIX_VERSION == 70600);
static_assert(OPTIX_ERROR_INVALID_PTX == 7200);
static_assert(sizeof(OptixFunctionTable) == 48 * sizeof(void*), "one table for every 7.x spelling");

OptixResult CreateModuleTheOldWay(OptixDeviceContext context, const char* ptx, size_t size,
                                  OptixModule* module, OptixPipeline* pipeline,
                                  OptixProgramGroup group) {
  OptixModuleCompileOptions module_options = {};
  OptixPipelineCompileOptions pipeline_options = {};
  pipeline_options.pipelineLaunchParamsVariableName = "params";
  char log[256];
  size_t log_size = sizeof(log);
  OptixResult result = optixModuleCreateFromPTX(context, &module_options, &pipeline_options, ptx,
                                                size, log, &log_size, module);
  if (result == OPTIX_ERROR_INVALID_PTX) return result;
  OptixPipelineLinkOptions link_options = {};
  link_options.maxTraceDepth = 2;
  link_options.debugLevel = OPTIX_COMPILE_DEBUG_LEVEL_FULL;
  result = optixPipelineCreate(context, &pipeline_options, &link_options, &group, 1, log, &log_size,
                               pipeline);
  if (result != OPTIX_SUCCESS) return result;
  OptixStackSizes sizes = {};
  return optixUtilAccumulateStackSizes(group, &sizes);  // no pipeline argument before 7.7
}
