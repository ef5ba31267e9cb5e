// tesseraOptixQueryFunctionTable: what optixInit calls (optix_stubs.h) to fill the application's
// OptixFunctionTable. The optix* functions of this library are not exported (libtessera.map):
// applications reach them only through the table, as they reach OptiX's.
#include <type_traits>

#include "optix_function_table.h"
#include "optix_host.h"

namespace tessera::optix7 {
namespace {

// In OptixFunctionTable's order (optix_function_table.h); the assignments by name make a slot
// that is missing or of another type a compile error.
OptixFunctionTable MakeTable() {
  OptixFunctionTable t{};
  t.optixGetErrorName = &optixGetErrorName;
  t.optixGetErrorString = &optixGetErrorString;
  t.optixDeviceContextCreate = &optixDeviceContextCreate;
  t.optixDeviceContextDestroy = &optixDeviceContextDestroy;
  t.optixDeviceContextGetProperty = &optixDeviceContextGetProperty;
  t.optixDeviceContextSetLogCallback = &optixDeviceContextSetLogCallback;
  t.optixDeviceContextSetCacheEnabled = &optixDeviceContextSetCacheEnabled;
  t.optixDeviceContextSetCacheLocation = &optixDeviceContextSetCacheLocation;
  t.optixDeviceContextSetCacheDatabaseSizes = &optixDeviceContextSetCacheDatabaseSizes;
  t.optixDeviceContextGetCacheEnabled = &optixDeviceContextGetCacheEnabled;
  t.optixDeviceContextGetCacheLocation = &optixDeviceContextGetCacheLocation;
  t.optixDeviceContextGetCacheDatabaseSizes = &optixDeviceContextGetCacheDatabaseSizes;
  t.optixModuleCreate = &optixModuleCreate;
  t.optixModuleCreateWithTasks = &optixModuleCreateWithTasks;
  t.optixModuleGetCompilationState = &optixModuleGetCompilationState;
  t.optixModuleDestroy = &optixModuleDestroy;
  t.optixBuiltinISModuleGet = &optixBuiltinISModuleGet;
  t.optixTaskExecute = &optixTaskExecute;
  t.optixProgramGroupCreate = &optixProgramGroupCreate;
  t.optixProgramGroupDestroy = &optixProgramGroupDestroy;
  t.optixProgramGroupGetStackSize = &optixProgramGroupGetStackSize;
  t.optixPipelineCreate = &optixPipelineCreate;
  t.optixPipelineDestroy = &optixPipelineDestroy;
  t.optixPipelineSetStackSize = &optixPipelineSetStackSize;
  t.optixAccelComputeMemoryUsage = &optixAccelComputeMemoryUsage;
  t.optixAccelBuild = &optixAccelBuild;
  t.optixAccelGetRelocationInfo = &optixAccelGetRelocationInfo;
  t.optixCheckRelocationCompatibility = &optixCheckRelocationCompatibility;
  t.optixAccelRelocate = &optixAccelRelocate;
  t.optixAccelCompact = &optixAccelCompact;
  t.optixAccelEmitProperty = &optixAccelEmitProperty;
  t.optixConvertPointerToTraversableHandle = &optixConvertPointerToTraversableHandle;
  t.optixOpacityMicromapArrayComputeMemoryUsage = &optixOpacityMicromapArrayComputeMemoryUsage;
  t.optixOpacityMicromapArrayBuild = &optixOpacityMicromapArrayBuild;
  t.optixOpacityMicromapArrayGetRelocationInfo = &optixOpacityMicromapArrayGetRelocationInfo;
  t.optixOpacityMicromapArrayRelocate = &optixOpacityMicromapArrayRelocate;
  t.optixDisplacementMicromapArrayComputeMemoryUsage =
      &optixDisplacementMicromapArrayComputeMemoryUsage;
  t.optixDisplacementMicromapArrayBuild = &optixDisplacementMicromapArrayBuild;
  t.optixSbtRecordPackHeader = &optixSbtRecordPackHeader;
  t.optixLaunch = &optixLaunch;
  t.optixDenoiserCreate = &optixDenoiserCreate;
  t.optixDenoiserDestroy = &optixDenoiserDestroy;
  t.optixDenoiserComputeMemoryResources = &optixDenoiserComputeMemoryResources;
  t.optixDenoiserSetup = &optixDenoiserSetup;
  t.optixDenoiserInvoke = &optixDenoiserInvoke;
  t.optixDenoiserComputeIntensity = &optixDenoiserComputeIntensity;
  t.optixDenoiserComputeAverageColor = &optixDenoiserComputeAverageColor;
  t.optixDenoiserCreateWithUserModel = &optixDenoiserCreateWithUserModel;
  return t;
}

// 48 pointers: a slot added to the table without a line above would stay null.
static_assert(sizeof(OptixFunctionTable) == 48 * sizeof(void*), "OptiX 7.7 has 48 host functions");

}  // namespace
}  // namespace tessera::optix7

// optix_stubs.h declares it, but that header's inline optix* functions would collide with this
// library's own; the type check stands in for the declaration.
extern "C" __attribute__((visibility("default"))) OptixResult tesseraOptixQueryFunctionTable(
    int abiId, unsigned int numOptions, OptixQueryFunctionTableOptions* optionKeys,
    const void** optionValues, void* functionTable, size_t sizeOfTable) {
  // OptiX ignores the options; so does Tessera.
  (void)numOptions;
  (void)optionKeys;
  (void)optionValues;
  if (abiId != OPTIX_ABI_VERSION) return OPTIX_ERROR_UNSUPPORTED_ABI_VERSION;
  if (functionTable == nullptr || sizeOfTable != sizeof(OptixFunctionTable)) {
    return OPTIX_ERROR_FUNCTION_TABLE_SIZE_MISMATCH;
  }
  static const OptixFunctionTable table = tessera::optix7::MakeTable();
  *static_cast<OptixFunctionTable*>(functionTable) = table;
  return OPTIX_SUCCESS;
}

static_assert(std::is_same_v<decltype(tesseraOptixQueryFunctionTable), OptixQueryFunctionTable_t>,
              "tesseraOptixQueryFunctionTable is an OptixQueryFunctionTable_t");
