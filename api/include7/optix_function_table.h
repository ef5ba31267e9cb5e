/* The OptiX 7.7 function table: one pointer per host API function, in OptiX 7.7's order (ABI
 * version 84), so that a table filled for ABI 84 has OptiX's layout. optixInit (optix_stubs.h)
 * asks libtessera to fill it; the inline optix* functions call through it. */
#ifndef TESSERA_OPTIX7_OPTIX_FUNCTION_TABLE_H_
#define TESSERA_OPTIX7_OPTIX_FUNCTION_TABLE_H_

/* The function table ABI of OptiX 7.7. */
#define OPTIX_ABI_VERSION 84

#ifndef OPTIX_DEFINE_ABI_VERSION_ONLY

#include "optix_types.h"
#if !defined(OPTIX_DONT_INCLUDE_CUDA)
#include "cuda.h"
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* Slots keep 7.7's names whatever OPTIX_VERSION says: optixModuleCreate is the slot that
 * optixModuleCreateFromPTX calls when an application asks for the older names. */
typedef struct OptixFunctionTable {
  /* ---- Error handling
   * ----------------------------------------------------------------------------- */
  const char* (*optixGetErrorName)(OptixResult result);
  const char* (*optixGetErrorString)(OptixResult result);

  /* ---- Device context
   * ----------------------------------------------------------------------------- */
  OptixResult (*optixDeviceContextCreate)(CUcontext fromContext,
                                          const OptixDeviceContextOptions* options,
                                          OptixDeviceContext* context);
  OptixResult (*optixDeviceContextDestroy)(OptixDeviceContext context);
  OptixResult (*optixDeviceContextGetProperty)(OptixDeviceContext context,
                                               OptixDeviceProperty property, void* value,
                                               size_t sizeInBytes);
  OptixResult (*optixDeviceContextSetLogCallback)(OptixDeviceContext context,
                                                  OptixLogCallback callbackFunction,
                                                  void* callbackData, unsigned int callbackLevel);
  OptixResult (*optixDeviceContextSetCacheEnabled)(OptixDeviceContext context, int enabled);
  OptixResult (*optixDeviceContextSetCacheLocation)(OptixDeviceContext context,
                                                    const char* location);
  OptixResult (*optixDeviceContextSetCacheDatabaseSizes)(OptixDeviceContext context,
                                                         size_t lowWaterMark, size_t highWaterMark);
  OptixResult (*optixDeviceContextGetCacheEnabled)(OptixDeviceContext context, int* enabled);
  OptixResult (*optixDeviceContextGetCacheLocation)(OptixDeviceContext context, char* location,
                                                    size_t locationSize);
  OptixResult (*optixDeviceContextGetCacheDatabaseSizes)(OptixDeviceContext context,
                                                         size_t* lowWaterMark,
                                                         size_t* highWaterMark);

  /* ---- Modules
   * ------------------------------------------------------------------------------------ */
  OptixResult (*optixModuleCreate)(OptixDeviceContext context,
                                   const OptixModuleCompileOptions* moduleCompileOptions,
                                   const OptixPipelineCompileOptions* pipelineCompileOptions,
                                   const char* input, size_t inputSize, char* logString,
                                   size_t* logStringSize, OptixModule* module);
  OptixResult (*optixModuleCreateWithTasks)(
      OptixDeviceContext context, const OptixModuleCompileOptions* moduleCompileOptions,
      const OptixPipelineCompileOptions* pipelineCompileOptions, const char* input,
      size_t inputSize, char* logString, size_t* logStringSize, OptixModule* module,
      OptixTask* firstTask);
  OptixResult (*optixModuleGetCompilationState)(OptixModule module, OptixModuleCompileState* state);
  OptixResult (*optixModuleDestroy)(OptixModule module);
  OptixResult (*optixBuiltinISModuleGet)(OptixDeviceContext context,
                                         const OptixModuleCompileOptions* moduleCompileOptions,
                                         const OptixPipelineCompileOptions* pipelineCompileOptions,
                                         const OptixBuiltinISOptions* builtinISOptions,
                                         OptixModule* builtinModule);

  /* ---- Tasks
   * -------------------------------------------------------------------------------------- */
  OptixResult (*optixTaskExecute)(OptixTask task, OptixTask* additionalTasks,
                                  unsigned int maxNumAdditionalTasks,
                                  unsigned int* numAdditionalTasksCreated);

  /* ---- Program groups
   * ----------------------------------------------------------------------------- */
  OptixResult (*optixProgramGroupCreate)(OptixDeviceContext context,
                                         const OptixProgramGroupDesc* programDescriptions,
                                         unsigned int numProgramGroups,
                                         const OptixProgramGroupOptions* options, char* logString,
                                         size_t* logStringSize, OptixProgramGroup* programGroups);
  OptixResult (*optixProgramGroupDestroy)(OptixProgramGroup programGroup);
  OptixResult (*optixProgramGroupGetStackSize)(OptixProgramGroup programGroup,
                                               OptixStackSizes* stackSizes, OptixPipeline pipeline);

  /* ---- Pipelines
   * ---------------------------------------------------------------------------------- */
  OptixResult (*optixPipelineCreate)(OptixDeviceContext context,
                                     const OptixPipelineCompileOptions* pipelineCompileOptions,
                                     const OptixPipelineLinkOptions* pipelineLinkOptions,
                                     const OptixProgramGroup* programGroups,
                                     unsigned int numProgramGroups, char* logString,
                                     size_t* logStringSize, OptixPipeline* pipeline);
  OptixResult (*optixPipelineDestroy)(OptixPipeline pipeline);
  OptixResult (*optixPipelineSetStackSize)(OptixPipeline pipeline,
                                           unsigned int directCallableStackSizeFromTraversal,
                                           unsigned int directCallableStackSizeFromState,
                                           unsigned int continuationStackSize,
                                           unsigned int maxTraversableGraphDepth);

  /* ---- Acceleration structures
   * -------------------------------------------------------------------- */
  OptixResult (*optixAccelComputeMemoryUsage)(OptixDeviceContext context,
                                              const OptixAccelBuildOptions* accelOptions,
                                              const OptixBuildInput* buildInputs,
                                              unsigned int numBuildInputs,
                                              OptixAccelBufferSizes* bufferSizes);
  OptixResult (*optixAccelBuild)(OptixDeviceContext context, CUstream stream,
                                 const OptixAccelBuildOptions* accelOptions,
                                 const OptixBuildInput* buildInputs, unsigned int numBuildInputs,
                                 CUdeviceptr tempBuffer, size_t tempBufferSizeInBytes,
                                 CUdeviceptr outputBuffer, size_t outputBufferSizeInBytes,
                                 OptixTraversableHandle* outputHandle,
                                 const OptixAccelEmitDesc* emittedProperties,
                                 unsigned int numEmittedProperties);
  OptixResult (*optixAccelGetRelocationInfo)(OptixDeviceContext context,
                                             OptixTraversableHandle handle,
                                             OptixRelocationInfo* info);
  OptixResult (*optixCheckRelocationCompatibility)(OptixDeviceContext context,
                                                   const OptixRelocationInfo* info,
                                                   int* compatible);
  OptixResult (*optixAccelRelocate)(OptixDeviceContext context, CUstream stream,
                                    const OptixRelocationInfo* info,
                                    const OptixRelocateInput* relocateInputs,
                                    size_t numRelocateInputs, CUdeviceptr targetAccel,
                                    size_t targetAccelSizeInBytes,
                                    OptixTraversableHandle* targetHandle);
  OptixResult (*optixAccelCompact)(OptixDeviceContext context, CUstream stream,
                                   OptixTraversableHandle inputHandle, CUdeviceptr outputBuffer,
                                   size_t outputBufferSizeInBytes,
                                   OptixTraversableHandle* outputHandle);
  OptixResult (*optixAccelEmitProperty)(OptixDeviceContext context, CUstream stream,
                                        OptixTraversableHandle handle,
                                        const OptixAccelEmitDesc* emittedProperty);
  OptixResult (*optixConvertPointerToTraversableHandle)(OptixDeviceContext onDevice,
                                                        CUdeviceptr pointer,
                                                        OptixTraversableType traversableType,
                                                        OptixTraversableHandle* traversableHandle);
  OptixResult (*optixOpacityMicromapArrayComputeMemoryUsage)(
      OptixDeviceContext context, const OptixOpacityMicromapArrayBuildInput* buildInput,
      OptixMicromapBufferSizes* bufferSizes);
  OptixResult (*optixOpacityMicromapArrayBuild)(
      OptixDeviceContext context, CUstream stream,
      const OptixOpacityMicromapArrayBuildInput* buildInput, const OptixMicromapBuffers* buffers);
  OptixResult (*optixOpacityMicromapArrayGetRelocationInfo)(OptixDeviceContext context,
                                                            CUdeviceptr opacityMicromapArray,
                                                            OptixRelocationInfo* info);
  OptixResult (*optixOpacityMicromapArrayRelocate)(OptixDeviceContext context, CUstream stream,
                                                   const OptixRelocationInfo* info,
                                                   CUdeviceptr targetOpacityMicromapArray,
                                                   size_t targetOpacityMicromapArraySizeInBytes);
  OptixResult (*optixDisplacementMicromapArrayComputeMemoryUsage)(
      OptixDeviceContext context, const OptixDisplacementMicromapArrayBuildInput* buildInput,
      OptixMicromapBufferSizes* bufferSizes);
  OptixResult (*optixDisplacementMicromapArrayBuild)(
      OptixDeviceContext context, CUstream stream,
      const OptixDisplacementMicromapArrayBuildInput* buildInput,
      const OptixMicromapBuffers* buffers);

  /* ---- Launch
   * ------------------------------------------------------------------------------------- */
  OptixResult (*optixSbtRecordPackHeader)(OptixProgramGroup programGroup,
                                          void* sbtRecordHeaderHostPointer);
  OptixResult (*optixLaunch)(OptixPipeline pipeline, CUstream stream, CUdeviceptr pipelineParams,
                             size_t pipelineParamsSize, const OptixShaderBindingTable* sbt,
                             unsigned int width, unsigned int height, unsigned int depth);

  /* ---- Denoiser
   * ----------------------------------------------------------------------------------- */
  OptixResult (*optixDenoiserCreate)(OptixDeviceContext context, OptixDenoiserModelKind modelKind,
                                     const OptixDenoiserOptions* options, OptixDenoiser* denoiser);
  OptixResult (*optixDenoiserDestroy)(OptixDenoiser denoiser);
  OptixResult (*optixDenoiserComputeMemoryResources)(const OptixDenoiser denoiser,
                                                     unsigned int maximumInputWidth,
                                                     unsigned int maximumInputHeight,
                                                     OptixDenoiserSizes* returnSizes);
  OptixResult (*optixDenoiserSetup)(OptixDenoiser denoiser, CUstream stream,
                                    unsigned int inputWidth, unsigned int inputHeight,
                                    CUdeviceptr denoiserState, size_t denoiserStateSizeInBytes,
                                    CUdeviceptr scratch, size_t scratchSizeInBytes);
  OptixResult (*optixDenoiserInvoke)(OptixDenoiser denoiser, CUstream stream,
                                     const OptixDenoiserParams* params, CUdeviceptr denoiserState,
                                     size_t denoiserStateSizeInBytes,
                                     const OptixDenoiserGuideLayer* guideLayer,
                                     const OptixDenoiserLayer* layers, unsigned int numLayers,
                                     unsigned int inputOffsetX, unsigned int inputOffsetY,
                                     CUdeviceptr scratch, size_t scratchSizeInBytes);
  OptixResult (*optixDenoiserComputeIntensity)(OptixDenoiser denoiser, CUstream stream,
                                               const OptixImage2D* inputImage,
                                               CUdeviceptr outputIntensity, CUdeviceptr scratch,
                                               size_t scratchSizeInBytes);
  OptixResult (*optixDenoiserComputeAverageColor)(OptixDenoiser denoiser, CUstream stream,
                                                  const OptixImage2D* inputImage,
                                                  CUdeviceptr outputAverageColor,
                                                  CUdeviceptr scratch, size_t scratchSizeInBytes);
  OptixResult (*optixDenoiserCreateWithUserModel)(OptixDeviceContext context, const void* data,
                                                  size_t dataSizeInBytes, OptixDenoiser* denoiser);

} OptixFunctionTable;

#ifdef __cplusplus
}
#endif

#endif /* OPTIX_DEFINE_ABI_VERSION_ONLY */

#endif /* TESSERA_OPTIX7_OPTIX_FUNCTION_TABLE_H_ */
