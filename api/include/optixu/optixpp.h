// OptiXpp under its pre-namespace name: the classes of optixu/optixpp_namespace.h, also reachable
// as optixu::Context, optixu::Buffer etc. (OptiX 3 Programming Guide, "Header Files"). The names
// are using-declarations, so optixu::Context and optix::Context are one type and the two
// spellings mix freely.
#ifndef OPTIXU_OPTIXPP_H_
#define OPTIXU_OPTIXPP_H_

// clang-format off: before every other #include (see there)
#include "../tessera/detail/program_prelude.h"
// clang-format on

#include "optixu/optixpp_namespace.h"

namespace optixu {

using optix::APIObj;
using optix::DestroyableObj;
using optix::Exception;
using optix::Handle;
using optix::ScopedObj;

using optix::AccelerationObj;
using optix::BufferObj;
using optix::ContextObj;
using optix::GeometryGroupObj;
using optix::GeometryInstanceObj;
using optix::GeometryObj;
using optix::GeometryTrianglesObj;
using optix::GroupObj;
using optix::MaterialObj;
using optix::ProgramObj;
using optix::SelectorObj;
using optix::TextureSamplerObj;
using optix::TransformObj;
using optix::VariableObj;

using optix::Acceleration;
using optix::Buffer;
using optix::Context;
using optix::Geometry;
using optix::GeometryGroup;
using optix::GeometryInstance;
using optix::GeometryTriangles;
using optix::Group;
using optix::Material;
using optix::Program;
using optix::Selector;
using optix::TextureSampler;
using optix::Transform;
using optix::Variable;

}  // namespace optixu

#endif  // OPTIXU_OPTIXPP_H_
