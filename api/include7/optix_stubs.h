/* What the OptiX SDK's optix_stubs.h gives host code: optixInit, which fills the function table,
 * and one inline function per host API function that calls through it. C++ only, like the
 * SDK's stubs in practice (inline functions with C linkage).
 *
 * Where the table comes from: OptiX's optixInit loads the driver's OptiX library (dlopen) and
 * calls its optixQueryFunctionTable. Tessera's is libtessera itself, which the application links
 * (Tessera::optix7), so optixInit calls tesseraOptixQueryFunctionTable directly: no library
 * search, no path to configure.
 *
 * Requires optix_function_table_definition.h in one translation unit of the application. */
#ifndef TESSERA_OPTIX7_OPTIX_STUBS_H_
#define TESSERA_OPTIX7_OPTIX_STUBS_H_

#include "optix.h"
#include "optix_function_table.h"

#ifndef OPTIX_FUNCTION_TABLE_SYMBOL
#define OPTIX_FUNCTION_TABLE_SYMBOL g_optixFunctionTable
#endif

#ifdef __cplusplus
extern "C" {
#endif

extern OptixFunctionTable OPTIX_FUNCTION_TABLE_SYMBOL;

/* libtessera's OptixQueryFunctionTable_t: fills `functionTable` (`sizeOfTable` bytes) for ABI
 * `abiId`; OPTIX_ERROR_UNSUPPORTED_ABI_VERSION for an ABI it does not serve,
 * OPTIX_ERROR_FUNCTION_TABLE_SIZE_MISMATCH when the size is not that ABI's table. The option
 * arguments are unused, as in OptiX (api/optix7/function_table.cc). */
OptixResult tesseraOptixQueryFunctionTable(int abiId, unsigned int numOptions,
                                           OptixQueryFunctionTableOptions* optionKeys,
                                           const void** optionValues, void* functionTable,
                                           size_t sizeOfTable);

/* Fills the function table. The handle of OptiX's variant names the loaded driver library;
 * Tessera loads none, so it is null on success and optixUninitWithHandle(null) is the matching
 * call. */
inline OptixResult optixInitWithHandle(void** handlePtr) {
  if (handlePtr) *handlePtr = 0;
  return tesseraOptixQueryFunctionTable(OPTIX_ABI_VERSION, 0, 0, 0, &OPTIX_FUNCTION_TABLE_SYMBOL,
                                        sizeof(OPTIX_FUNCTION_TABLE_SYMBOL));
}

inline OptixResult optixInit(void) { return optixInitWithHandle(0); }

/* Empties the function table; later optix* calls need a new optixInit. */
inline OptixResult optixUninitWithHandle(void* handle) {
  if (handle) return OPTIX_ERROR_INVALID_VALUE;
  OptixFunctionTable empty = {};
  OPTIX_FUNCTION_TABLE_SYMBOL = empty;
  return OPTIX_SUCCESS;
}

/* ---- Error handling -----------------------------------------------------------------------------
 */
inline const char* optixGetErrorName(OptixResult result) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixGetErrorName(result);
}
inline const char* optixGetErrorString(OptixResult result) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixGetErrorString(result);
}

/* ---- Device context -----------------------------------------------------------------------------
 */
inline OptixResult optixDeviceContextCreate(CUcontext fromContext,
                                            const OptixDeviceContextOptions* options,
                                            OptixDeviceContext* context) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixDeviceContextCreate(fromContext, options, context);
}
inline OptixResult optixDeviceContextDestroy(OptixDeviceContext context) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixDeviceContextDestroy(context);
}
inline OptixResult optixDeviceContextGetProperty(OptixDeviceContext context,
                                                 OptixDeviceProperty property, void* value,
                                                 size_t sizeInBytes) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixDeviceContextGetProperty(context, property, value,
                                                                   sizeInBytes);
}
inline OptixResult optixDeviceContextSetLogCallback(OptixDeviceContext context,
                                                    OptixLogCallback callbackFunction,
                                                    void* callbackData,
                                                    unsigned int callbackLevel) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixDeviceContextSetLogCallback(context, callbackFunction,
                                                                      callbackData, callbackLevel);
}
inline OptixResult optixDeviceContextSetCacheEnabled(OptixDeviceContext context, int enabled) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixDeviceContextSetCacheEnabled(context, enabled);
}
inline OptixResult optixDeviceContextSetCacheLocation(OptixDeviceContext context,
                                                      const char* location) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixDeviceContextSetCacheLocation(context, location);
}
inline OptixResult optixDeviceContextSetCacheDatabaseSizes(OptixDeviceContext context,
                                                           size_t lowWaterMark,
                                                           size_t highWaterMark) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixDeviceContextSetCacheDatabaseSizes(context, lowWaterMark,
                                                                             highWaterMark);
}
inline OptixResult optixDeviceContextGetCacheEnabled(OptixDeviceContext context, int* enabled) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixDeviceContextGetCacheEnabled(context, enabled);
}
inline OptixResult optixDeviceContextGetCacheLocation(OptixDeviceContext context, char* location,
                                                      size_t locationSize) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixDeviceContextGetCacheLocation(context, location,
                                                                        locationSize);
}
inline OptixResult optixDeviceContextGetCacheDatabaseSizes(OptixDeviceContext context,
                                                           size_t* lowWaterMark,
                                                           size_t* highWaterMark) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixDeviceContextGetCacheDatabaseSizes(context, lowWaterMark,
                                                                             highWaterMark);
}

/* ---- Modules ------------------------------------------------------------------------------------
 */
#if OPTIX_VERSION >= 70700
inline OptixResult optixModuleCreate(OptixDeviceContext context,
                                     const OptixModuleCompileOptions* moduleCompileOptions,
                                     const OptixPipelineCompileOptions* pipelineCompileOptions,
                                     const char* input, size_t inputSize, char* logString,
                                     size_t* logStringSize, OptixModule* module) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixModuleCreate(context, moduleCompileOptions,
                                                       pipelineCompileOptions, input, inputSize,
                                                       logString, logStringSize, module);
}
#else
inline OptixResult optixModuleCreateFromPTX(
    OptixDeviceContext context, const OptixModuleCompileOptions* moduleCompileOptions,
    const OptixPipelineCompileOptions* pipelineCompileOptions, const char* input, size_t inputSize,
    char* logString, size_t* logStringSize, OptixModule* module) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixModuleCreate(context, moduleCompileOptions,
                                                       pipelineCompileOptions, input, inputSize,
                                                       logString, logStringSize, module);
}
#endif
#if OPTIX_VERSION >= 70700
inline OptixResult optixModuleCreateWithTasks(
    OptixDeviceContext context, const OptixModuleCompileOptions* moduleCompileOptions,
    const OptixPipelineCompileOptions* pipelineCompileOptions, const char* input, size_t inputSize,
    char* logString, size_t* logStringSize, OptixModule* module, OptixTask* firstTask) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixModuleCreateWithTasks(
      context, moduleCompileOptions, pipelineCompileOptions, input, inputSize, logString,
      logStringSize, module, firstTask);
}
#else
inline OptixResult optixModuleCreateFromPTXWithTasks(
    OptixDeviceContext context, const OptixModuleCompileOptions* moduleCompileOptions,
    const OptixPipelineCompileOptions* pipelineCompileOptions, const char* input, size_t inputSize,
    char* logString, size_t* logStringSize, OptixModule* module, OptixTask* firstTask) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixModuleCreateWithTasks(
      context, moduleCompileOptions, pipelineCompileOptions, input, inputSize, logString,
      logStringSize, module, firstTask);
}
#endif
inline OptixResult optixModuleGetCompilationState(OptixModule module,
                                                  OptixModuleCompileState* state) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixModuleGetCompilationState(module, state);
}
inline OptixResult optixModuleDestroy(OptixModule module) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixModuleDestroy(module);
}
inline OptixResult optixBuiltinISModuleGet(
    OptixDeviceContext context, const OptixModuleCompileOptions* moduleCompileOptions,
    const OptixPipelineCompileOptions* pipelineCompileOptions,
    const OptixBuiltinISOptions* builtinISOptions, OptixModule* builtinModule) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixBuiltinISModuleGet(
      context, moduleCompileOptions, pipelineCompileOptions, builtinISOptions, builtinModule);
}

/* ---- Tasks --------------------------------------------------------------------------------------
 */
inline OptixResult optixTaskExecute(OptixTask task, OptixTask* additionalTasks,
                                    unsigned int maxNumAdditionalTasks,
                                    unsigned int* numAdditionalTasksCreated) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixTaskExecute(task, additionalTasks, maxNumAdditionalTasks,
                                                      numAdditionalTasksCreated);
}

/* ---- Program groups -----------------------------------------------------------------------------
 */
inline OptixResult optixProgramGroupCreate(OptixDeviceContext context,
                                           const OptixProgramGroupDesc* programDescriptions,
                                           unsigned int numProgramGroups,
                                           const OptixProgramGroupOptions* options, char* logString,
                                           size_t* logStringSize,
                                           OptixProgramGroup* programGroups) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixProgramGroupCreate(context, programDescriptions,
                                                             numProgramGroups, options, logString,
                                                             logStringSize, programGroups);
}
inline OptixResult optixProgramGroupDestroy(OptixProgramGroup programGroup) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixProgramGroupDestroy(programGroup);
}
inline OptixResult optixProgramGroupGetStackSize(OptixProgramGroup programGroup,
                                                 OptixStackSizes* stackSizes,
                                                 OptixPipeline pipeline) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixProgramGroupGetStackSize(programGroup, stackSizes,
                                                                   pipeline);
}

/* ---- Pipelines ----------------------------------------------------------------------------------
 */
inline OptixResult optixPipelineCreate(OptixDeviceContext context,
                                       const OptixPipelineCompileOptions* pipelineCompileOptions,
                                       const OptixPipelineLinkOptions* pipelineLinkOptions,
                                       const OptixProgramGroup* programGroups,
                                       unsigned int numProgramGroups, char* logString,
                                       size_t* logStringSize, OptixPipeline* pipeline) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixPipelineCreate(
      context, pipelineCompileOptions, pipelineLinkOptions, programGroups, numProgramGroups,
      logString, logStringSize, pipeline);
}
inline OptixResult optixPipelineDestroy(OptixPipeline pipeline) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixPipelineDestroy(pipeline);
}
inline OptixResult optixPipelineSetStackSize(OptixPipeline pipeline,
                                             unsigned int directCallableStackSizeFromTraversal,
                                             unsigned int directCallableStackSizeFromState,
                                             unsigned int continuationStackSize,
                                             unsigned int maxTraversableGraphDepth) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixPipelineSetStackSize(
      pipeline, directCallableStackSizeFromTraversal, directCallableStackSizeFromState,
      continuationStackSize, maxTraversableGraphDepth);
}

/* ---- Acceleration structures --------------------------------------------------------------------
 */
inline OptixResult optixAccelComputeMemoryUsage(OptixDeviceContext context,
                                                const OptixAccelBuildOptions* accelOptions,
                                                const OptixBuildInput* buildInputs,
                                                unsigned int numBuildInputs,
                                                OptixAccelBufferSizes* bufferSizes) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixAccelComputeMemoryUsage(
      context, accelOptions, buildInputs, numBuildInputs, bufferSizes);
}
inline OptixResult optixAccelBuild(OptixDeviceContext context, CUstream stream,
                                   const OptixAccelBuildOptions* accelOptions,
                                   const OptixBuildInput* buildInputs, unsigned int numBuildInputs,
                                   CUdeviceptr tempBuffer, size_t tempBufferSizeInBytes,
                                   CUdeviceptr outputBuffer, size_t outputBufferSizeInBytes,
                                   OptixTraversableHandle* outputHandle,
                                   const OptixAccelEmitDesc* emittedProperties,
                                   unsigned int numEmittedProperties) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixAccelBuild(
      context, stream, accelOptions, buildInputs, numBuildInputs, tempBuffer, tempBufferSizeInBytes,
      outputBuffer, outputBufferSizeInBytes, outputHandle, emittedProperties, numEmittedProperties);
}
inline OptixResult optixAccelGetRelocationInfo(OptixDeviceContext context,
                                               OptixTraversableHandle handle,
                                               OptixRelocationInfo* info) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixAccelGetRelocationInfo(context, handle, info);
}
inline OptixResult optixCheckRelocationCompatibility(OptixDeviceContext context,
                                                     const OptixRelocationInfo* info,
                                                     int* compatible) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixCheckRelocationCompatibility(context, info, compatible);
}
inline OptixResult optixAccelRelocate(OptixDeviceContext context, CUstream stream,
                                      const OptixRelocationInfo* info,
                                      const OptixRelocateInput* relocateInputs,
                                      size_t numRelocateInputs, CUdeviceptr targetAccel,
                                      size_t targetAccelSizeInBytes,
                                      OptixTraversableHandle* targetHandle) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixAccelRelocate(context, stream, info, relocateInputs,
                                                        numRelocateInputs, targetAccel,
                                                        targetAccelSizeInBytes, targetHandle);
}
inline OptixResult optixAccelCompact(OptixDeviceContext context, CUstream stream,
                                     OptixTraversableHandle inputHandle, CUdeviceptr outputBuffer,
                                     size_t outputBufferSizeInBytes,
                                     OptixTraversableHandle* outputHandle) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixAccelCompact(context, stream, inputHandle, outputBuffer,
                                                       outputBufferSizeInBytes, outputHandle);
}
inline OptixResult optixAccelEmitProperty(OptixDeviceContext context, CUstream stream,
                                          OptixTraversableHandle handle,
                                          const OptixAccelEmitDesc* emittedProperty) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixAccelEmitProperty(context, stream, handle,
                                                            emittedProperty);
}
inline OptixResult optixConvertPointerToTraversableHandle(
    OptixDeviceContext onDevice, CUdeviceptr pointer, OptixTraversableType traversableType,
    OptixTraversableHandle* traversableHandle) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixConvertPointerToTraversableHandle(
      onDevice, pointer, traversableType, traversableHandle);
}
inline OptixResult optixOpacityMicromapArrayComputeMemoryUsage(
    OptixDeviceContext context, const OptixOpacityMicromapArrayBuildInput* buildInput,
    OptixMicromapBufferSizes* bufferSizes) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixOpacityMicromapArrayComputeMemoryUsage(
      context, buildInput, bufferSizes);
}
inline OptixResult optixOpacityMicromapArrayBuild(
    OptixDeviceContext context, CUstream stream,
    const OptixOpacityMicromapArrayBuildInput* buildInput, const OptixMicromapBuffers* buffers) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixOpacityMicromapArrayBuild(context, stream, buildInput,
                                                                    buffers);
}
inline OptixResult optixOpacityMicromapArrayGetRelocationInfo(OptixDeviceContext context,
                                                              CUdeviceptr opacityMicromapArray,
                                                              OptixRelocationInfo* info) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixOpacityMicromapArrayGetRelocationInfo(
      context, opacityMicromapArray, info);
}
inline OptixResult optixOpacityMicromapArrayRelocate(OptixDeviceContext context, CUstream stream,
                                                     const OptixRelocationInfo* info,
                                                     CUdeviceptr targetOpacityMicromapArray,
                                                     size_t targetOpacityMicromapArraySizeInBytes) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixOpacityMicromapArrayRelocate(
      context, stream, info, targetOpacityMicromapArray, targetOpacityMicromapArraySizeInBytes);
}
inline OptixResult optixDisplacementMicromapArrayComputeMemoryUsage(
    OptixDeviceContext context, const OptixDisplacementMicromapArrayBuildInput* buildInput,
    OptixMicromapBufferSizes* bufferSizes) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixDisplacementMicromapArrayComputeMemoryUsage(
      context, buildInput, bufferSizes);
}
inline OptixResult optixDisplacementMicromapArrayBuild(
    OptixDeviceContext context, CUstream stream,
    const OptixDisplacementMicromapArrayBuildInput* buildInput,
    const OptixMicromapBuffers* buffers) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixDisplacementMicromapArrayBuild(context, stream,
                                                                         buildInput, buffers);
}

/* ---- Launch -------------------------------------------------------------------------------------
 */
inline OptixResult optixSbtRecordPackHeader(OptixProgramGroup programGroup,
                                            void* sbtRecordHeaderHostPointer) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixSbtRecordPackHeader(programGroup,
                                                              sbtRecordHeaderHostPointer);
}
inline OptixResult optixLaunch(OptixPipeline pipeline, CUstream stream, CUdeviceptr pipelineParams,
                               size_t pipelineParamsSize, const OptixShaderBindingTable* sbt,
                               unsigned int width, unsigned int height, unsigned int depth) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixLaunch(pipeline, stream, pipelineParams,
                                                 pipelineParamsSize, sbt, width, height, depth);
}

/* ---- Denoiser -----------------------------------------------------------------------------------
 */
inline OptixResult optixDenoiserCreate(OptixDeviceContext context, OptixDenoiserModelKind modelKind,
                                       const OptixDenoiserOptions* options,
                                       OptixDenoiser* denoiser) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixDenoiserCreate(context, modelKind, options, denoiser);
}
inline OptixResult optixDenoiserDestroy(OptixDenoiser denoiser) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixDenoiserDestroy(denoiser);
}
inline OptixResult optixDenoiserComputeMemoryResources(const OptixDenoiser denoiser,
                                                       unsigned int maximumInputWidth,
                                                       unsigned int maximumInputHeight,
                                                       OptixDenoiserSizes* returnSizes) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixDenoiserComputeMemoryResources(
      denoiser, maximumInputWidth, maximumInputHeight, returnSizes);
}
inline OptixResult optixDenoiserSetup(OptixDenoiser denoiser, CUstream stream,
                                      unsigned int inputWidth, unsigned int inputHeight,
                                      CUdeviceptr denoiserState, size_t denoiserStateSizeInBytes,
                                      CUdeviceptr scratch, size_t scratchSizeInBytes) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixDenoiserSetup(denoiser, stream, inputWidth, inputHeight,
                                                        denoiserState, denoiserStateSizeInBytes,
                                                        scratch, scratchSizeInBytes);
}
inline OptixResult optixDenoiserInvoke(OptixDenoiser denoiser, CUstream stream,
                                       const OptixDenoiserParams* params, CUdeviceptr denoiserState,
                                       size_t denoiserStateSizeInBytes,
                                       const OptixDenoiserGuideLayer* guideLayer,
                                       const OptixDenoiserLayer* layers, unsigned int numLayers,
                                       unsigned int inputOffsetX, unsigned int inputOffsetY,
                                       CUdeviceptr scratch, size_t scratchSizeInBytes) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixDenoiserInvoke(
      denoiser, stream, params, denoiserState, denoiserStateSizeInBytes, guideLayer, layers,
      numLayers, inputOffsetX, inputOffsetY, scratch, scratchSizeInBytes);
}
inline OptixResult optixDenoiserComputeIntensity(OptixDenoiser denoiser, CUstream stream,
                                                 const OptixImage2D* inputImage,
                                                 CUdeviceptr outputIntensity, CUdeviceptr scratch,
                                                 size_t scratchSizeInBytes) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixDenoiserComputeIntensity(
      denoiser, stream, inputImage, outputIntensity, scratch, scratchSizeInBytes);
}
inline OptixResult optixDenoiserComputeAverageColor(OptixDenoiser denoiser, CUstream stream,
                                                    const OptixImage2D* inputImage,
                                                    CUdeviceptr outputAverageColor,
                                                    CUdeviceptr scratch,
                                                    size_t scratchSizeInBytes) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixDenoiserComputeAverageColor(
      denoiser, stream, inputImage, outputAverageColor, scratch, scratchSizeInBytes);
}
inline OptixResult optixDenoiserCreateWithUserModel(OptixDeviceContext context, const void* data,
                                                    size_t dataSizeInBytes,
                                                    OptixDenoiser* denoiser) {
  return OPTIX_FUNCTION_TABLE_SYMBOL.optixDenoiserCreateWithUserModel(context, data,
                                                                      dataSizeInBytes, denoiser);
}

#ifdef __cplusplus
}
#endif

#endif /* TESSERA_OPTIX7_OPTIX_STUBS_H_ */
