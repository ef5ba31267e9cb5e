/* The OptiX 7 host headers that OptiX declares for C (types, host API, function table) and the
 * CUDA runtime C API compile as C11 with -Wall -Wextra -Werror. Compiled, never linked: nothing
 * is implemented yet (issue 25). */
#include <cuda.h>
#include <cuda_runtime_api.h>
#include <optix_function_table.h>
#include <optix_host.h>
#include <optix_types.h>
#include <vector_functions.h>

OptixResult tessera_optix7_c_compile(OptixDeviceContext context, OptixPipeline pipeline,
                                     const OptixShaderBindingTable* sbt, CUdeviceptr params) {
  float3 v = make_float3(1.0f, 2.0f, 3.0f);
  (void)v;
  if (cudaMemcpy((void*)params, &v, sizeof v, cudaMemcpyHostToDevice) != cudaSuccess)
    return OPTIX_ERROR_CUDA_ERROR;
  (void)context;
  return optixLaunch(pipeline, 0, params, sizeof(float3), sbt, 1, 1, 1);
}
