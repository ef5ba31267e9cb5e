// optixGetErrorName and optixGetErrorString.
#include "optix_host.h"
#include "result.h"

extern "C" {

const char* optixGetErrorName(OptixResult result) { return tessera::optix7::ResultName(result); }

const char* optixGetErrorString(OptixResult result) {
  return tessera::optix7::ResultString(result);
}

}  // extern "C"
