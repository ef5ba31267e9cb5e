// Forwards to the namespaced header: optix::Aabb is only ever spelled with its namespace (or
// after `using namespace optix;`), so there is no global variant to provide.
#ifndef OPTIXU_OPTIXU_AABB_H_
#define OPTIXU_OPTIXU_AABB_H_

// clang-format off: before every other #include (see there)
#include "../tessera/detail/program_prelude.h"
// clang-format on

#include "optixu_aabb_namespace.h"

#endif  // OPTIXU_OPTIXU_AABB_H_
