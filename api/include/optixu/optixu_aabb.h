// Forwards to the namespaced header: optix::Aabb is only ever spelled with its namespace (or
// after `using namespace optix;`), so there is no global variant to provide.
#ifndef OPTIXU_OPTIXU_AABB_H_
#define OPTIXU_OPTIXU_AABB_H_

#include "optixu_aabb_namespace.h"

#endif  // OPTIXU_OPTIXU_AABB_H_
