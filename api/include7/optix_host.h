/* The OptiX 7.7 host API: every function of the OptiX function table, declared with C linkage
 * as OptiX declares them. Host code calls them through optix_stubs.h (inline functions that call
 * through g_optixFunctionTable, which optixInit fills), exactly as with the SDK.
 *
 * libtessera implements them (api/optix7; docs/COMPATIBILITY.md gives each one's status). On
 * Tessera, modules are program modules (shared libraries built from the .cu source by the system
 * C++ compiler) where OptiX takes PTX, and device memory is Tessera's shared address range
 * (cuda_runtime_api.h).
 *
 * Thread-safety: as in OptiX 7 (guide section 3.4): calls on different objects may run
 * concurrently. */
#ifndef TESSERA_OPTIX7_OPTIX_HOST_H_
#define TESSERA_OPTIX7_OPTIX_HOST_H_

#include "optix_types.h"
#if !defined(OPTIX_DONT_INCLUDE_CUDA)
/* CUcontext, CUstream; an application that declares them itself defines OPTIX_DONT_INCLUDE_CUDA,
 * as with OptiX. */
#include "cuda.h"
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* ---- Error handling -----------------------------------------------------------------------------
 */
/* The enumerator's name, e.g. "OPTIX_ERROR_INVALID_VALUE". */
const char* optixGetErrorName(OptixResult result);
/* A sentence describing `result`. */
const char* optixGetErrorString(OptixResult result);

/* ---- Device context -----------------------------------------------------------------------------
 */
/* A context on the CUDA context `fromContext` (0: the current one). */
OptixResult optixDeviceContextCreate(CUcontext fromContext,
                                     const OptixDeviceContextOptions* options,
                                     OptixDeviceContext* context);
/* Destroys the context and every object made from it. */
OptixResult optixDeviceContextDestroy(OptixDeviceContext context);
/* One limit of the device (an unsigned int). */
OptixResult optixDeviceContextGetProperty(OptixDeviceContext context, OptixDeviceProperty property,
                                          void* value, size_t sizeInBytes);
/* Messages up to `callbackLevel` go to `callbackFunction`. */
OptixResult optixDeviceContextSetLogCallback(OptixDeviceContext context,
                                             OptixLogCallback callbackFunction, void* callbackData,
                                             unsigned int callbackLevel);
/* The compilation cache (here: the program module cache). */
OptixResult optixDeviceContextSetCacheEnabled(OptixDeviceContext context, int enabled);
OptixResult optixDeviceContextSetCacheLocation(OptixDeviceContext context, const char* location);
OptixResult optixDeviceContextSetCacheDatabaseSizes(OptixDeviceContext context, size_t lowWaterMark,
                                                    size_t highWaterMark);
OptixResult optixDeviceContextGetCacheEnabled(OptixDeviceContext context, int* enabled);
OptixResult optixDeviceContextGetCacheLocation(OptixDeviceContext context, char* location,
                                               size_t locationSize);
OptixResult optixDeviceContextGetCacheDatabaseSizes(OptixDeviceContext context,
                                                    size_t* lowWaterMark, size_t* highWaterMark);

/* ---- Modules ------------------------------------------------------------------------------------
 */
#if OPTIX_VERSION >= 70700
/* A module from program input: on Tessera a program module (C++ source or a built .so,
 * docs/programs.md) where OptiX takes PTX or OptiX-IR. */
OptixResult optixModuleCreate(OptixDeviceContext context,
                              const OptixModuleCompileOptions* moduleCompileOptions,
                              const OptixPipelineCompileOptions* pipelineCompileOptions,
                              const char* input, size_t inputSize, char* logString,
                              size_t* logStringSize, OptixModule* module);
#else
OptixResult optixModuleCreateFromPTX(OptixDeviceContext context,
                                     const OptixModuleCompileOptions* moduleCompileOptions,
                                     const OptixPipelineCompileOptions* pipelineCompileOptions,
                                     const char* input, size_t inputSize, char* logString,
                                     size_t* logStringSize, OptixModule* module);
#endif
#if OPTIX_VERSION >= 70700
/* As above, compiled through tasks the application runs (optixTaskExecute). */
OptixResult optixModuleCreateWithTasks(OptixDeviceContext context,
                                       const OptixModuleCompileOptions* moduleCompileOptions,
                                       const OptixPipelineCompileOptions* pipelineCompileOptions,
                                       const char* input, size_t inputSize, char* logString,
                                       size_t* logStringSize, OptixModule* module,
                                       OptixTask* firstTask);
#else
OptixResult optixModuleCreateFromPTXWithTasks(
    OptixDeviceContext context, const OptixModuleCompileOptions* moduleCompileOptions,
    const OptixPipelineCompileOptions* pipelineCompileOptions, const char* input, size_t inputSize,
    char* logString, size_t* logStringSize, OptixModule* module, OptixTask* firstTask);
#endif
OptixResult optixModuleGetCompilationState(OptixModule module, OptixModuleCompileState* state);
OptixResult optixModuleDestroy(OptixModule module);
/* The module of a built-in intersection program (curves, spheres). */
OptixResult optixBuiltinISModuleGet(OptixDeviceContext context,
                                    const OptixModuleCompileOptions* moduleCompileOptions,
                                    const OptixPipelineCompileOptions* pipelineCompileOptions,
                                    const OptixBuiltinISOptions* builtinISOptions,
                                    OptixModule* builtinModule);

/* ---- Tasks --------------------------------------------------------------------------------------
 */
OptixResult optixTaskExecute(OptixTask task, OptixTask* additionalTasks,
                             unsigned int maxNumAdditionalTasks,
                             unsigned int* numAdditionalTasksCreated);

/* ---- Program groups -----------------------------------------------------------------------------
 */
OptixResult optixProgramGroupCreate(OptixDeviceContext context,
                                    const OptixProgramGroupDesc* programDescriptions,
                                    unsigned int numProgramGroups,
                                    const OptixProgramGroupOptions* options, char* logString,
                                    size_t* logStringSize, OptixProgramGroup* programGroups);
OptixResult optixProgramGroupDestroy(OptixProgramGroup programGroup);
/* `pipeline` may be 0 (sizes without the pipeline's direct callables' inlining). */
OptixResult optixProgramGroupGetStackSize(OptixProgramGroup programGroup,
                                          OptixStackSizes* stackSizes, OptixPipeline pipeline);

/* ---- Pipelines ----------------------------------------------------------------------------------
 */
OptixResult optixPipelineCreate(OptixDeviceContext context,
                                const OptixPipelineCompileOptions* pipelineCompileOptions,
                                const OptixPipelineLinkOptions* pipelineLinkOptions,
                                const OptixProgramGroup* programGroups,
                                unsigned int numProgramGroups, char* logString,
                                size_t* logStringSize, OptixPipeline* pipeline);
OptixResult optixPipelineDestroy(OptixPipeline pipeline);
OptixResult optixPipelineSetStackSize(OptixPipeline pipeline,
                                      unsigned int directCallableStackSizeFromTraversal,
                                      unsigned int directCallableStackSizeFromState,
                                      unsigned int continuationStackSize,
                                      unsigned int maxTraversableGraphDepth);

/* ---- Acceleration structures --------------------------------------------------------------------
 */
OptixResult optixAccelComputeMemoryUsage(OptixDeviceContext context,
                                         const OptixAccelBuildOptions* accelOptions,
                                         const OptixBuildInput* buildInputs,
                                         unsigned int numBuildInputs,
                                         OptixAccelBufferSizes* bufferSizes);
OptixResult optixAccelBuild(OptixDeviceContext context, CUstream stream,
                            const OptixAccelBuildOptions* accelOptions,
                            const OptixBuildInput* buildInputs, unsigned int numBuildInputs,
                            CUdeviceptr tempBuffer, size_t tempBufferSizeInBytes,
                            CUdeviceptr outputBuffer, size_t outputBufferSizeInBytes,
                            OptixTraversableHandle* outputHandle,
                            const OptixAccelEmitDesc* emittedProperties,
                            unsigned int numEmittedProperties);
OptixResult optixAccelGetRelocationInfo(OptixDeviceContext context, OptixTraversableHandle handle,
                                        OptixRelocationInfo* info);
OptixResult optixCheckRelocationCompatibility(OptixDeviceContext context,
                                              const OptixRelocationInfo* info, int* compatible);
OptixResult optixAccelRelocate(OptixDeviceContext context, CUstream stream,
                               const OptixRelocationInfo* info,
                               const OptixRelocateInput* relocateInputs, size_t numRelocateInputs,
                               CUdeviceptr targetAccel, size_t targetAccelSizeInBytes,
                               OptixTraversableHandle* targetHandle);
OptixResult optixAccelCompact(OptixDeviceContext context, CUstream stream,
                              OptixTraversableHandle inputHandle, CUdeviceptr outputBuffer,
                              size_t outputBufferSizeInBytes, OptixTraversableHandle* outputHandle);
OptixResult optixAccelEmitProperty(OptixDeviceContext context, CUstream stream,
                                   OptixTraversableHandle handle,
                                   const OptixAccelEmitDesc* emittedProperty);
/* The handle of a transform traversable the application wrote to device memory. */
OptixResult optixConvertPointerToTraversableHandle(OptixDeviceContext onDevice, CUdeviceptr pointer,
                                                   OptixTraversableType traversableType,
                                                   OptixTraversableHandle* traversableHandle);
OptixResult optixOpacityMicromapArrayComputeMemoryUsage(
    OptixDeviceContext context, const OptixOpacityMicromapArrayBuildInput* buildInput,
    OptixMicromapBufferSizes* bufferSizes);
OptixResult optixOpacityMicromapArrayBuild(OptixDeviceContext context, CUstream stream,
                                           const OptixOpacityMicromapArrayBuildInput* buildInput,
                                           const OptixMicromapBuffers* buffers);
OptixResult optixOpacityMicromapArrayGetRelocationInfo(OptixDeviceContext context,
                                                       CUdeviceptr opacityMicromapArray,
                                                       OptixRelocationInfo* info);
OptixResult optixOpacityMicromapArrayRelocate(OptixDeviceContext context, CUstream stream,
                                              const OptixRelocationInfo* info,
                                              CUdeviceptr targetOpacityMicromapArray,
                                              size_t targetOpacityMicromapArraySizeInBytes);
OptixResult optixDisplacementMicromapArrayComputeMemoryUsage(
    OptixDeviceContext context, const OptixDisplacementMicromapArrayBuildInput* buildInput,
    OptixMicromapBufferSizes* bufferSizes);
OptixResult optixDisplacementMicromapArrayBuild(
    OptixDeviceContext context, CUstream stream,
    const OptixDisplacementMicromapArrayBuildInput* buildInput,
    const OptixMicromapBuffers* buffers);

/* ---- Launch -------------------------------------------------------------------------------------
 */
/* Writes the OPTIX_SBT_RECORD_HEADER_SIZE-byte header that selects `programGroup`'s programs. */
OptixResult optixSbtRecordPackHeader(OptixProgramGroup programGroup,
                                     void* sbtRecordHeaderHostPointer);
/* Runs the raygen program width x height x depth times over Tessera's devices; `pipelineParams` is
 * copied into the modules' launch-parameter variable. */
OptixResult optixLaunch(OptixPipeline pipeline, CUstream stream, CUdeviceptr pipelineParams,
                        size_t pipelineParamsSize, const OptixShaderBindingTable* sbt,
                        unsigned int width, unsigned int height, unsigned int depth);

/* ---- Denoiser -----------------------------------------------------------------------------------
 */
OptixResult optixDenoiserCreate(OptixDeviceContext context, OptixDenoiserModelKind modelKind,
                                const OptixDenoiserOptions* options, OptixDenoiser* denoiser);
OptixResult optixDenoiserDestroy(OptixDenoiser denoiser);
OptixResult optixDenoiserComputeMemoryResources(const OptixDenoiser denoiser,
                                                unsigned int maximumInputWidth,
                                                unsigned int maximumInputHeight,
                                                OptixDenoiserSizes* returnSizes);
OptixResult optixDenoiserSetup(OptixDenoiser denoiser, CUstream stream, unsigned int inputWidth,
                               unsigned int inputHeight, CUdeviceptr denoiserState,
                               size_t denoiserStateSizeInBytes, CUdeviceptr scratch,
                               size_t scratchSizeInBytes);
OptixResult optixDenoiserInvoke(OptixDenoiser denoiser, CUstream stream,
                                const OptixDenoiserParams* params, CUdeviceptr denoiserState,
                                size_t denoiserStateSizeInBytes,
                                const OptixDenoiserGuideLayer* guideLayer,
                                const OptixDenoiserLayer* layers, unsigned int numLayers,
                                unsigned int inputOffsetX, unsigned int inputOffsetY,
                                CUdeviceptr scratch, size_t scratchSizeInBytes);
OptixResult optixDenoiserComputeIntensity(OptixDenoiser denoiser, CUstream stream,
                                          const OptixImage2D* inputImage,
                                          CUdeviceptr outputIntensity, CUdeviceptr scratch,
                                          size_t scratchSizeInBytes);
OptixResult optixDenoiserComputeAverageColor(OptixDenoiser denoiser, CUstream stream,
                                             const OptixImage2D* inputImage,
                                             CUdeviceptr outputAverageColor, CUdeviceptr scratch,
                                             size_t scratchSizeInBytes);
OptixResult optixDenoiserCreateWithUserModel(OptixDeviceContext context, const void* data,
                                             size_t dataSizeInBytes, OptixDenoiser* denoiser);

#ifdef __cplusplus
}
#endif

#endif /* TESSERA_OPTIX7_OPTIX_HOST_H_ */
