#include "tessera/v1/object_fields.h"

namespace tessera::v1 {

uint64_t ObjectId(const Object& o) {
  // A switch, not reflection: the replica reads it for every object of a delta.
  switch (o.kind_case()) {
    case Object::kProgram:
      return o.program().id();
    case Object::kBuffer:
      return o.buffer().id();
    case Object::kGeometry:
      return o.geometry().id();
    case Object::kMaterial:
      return o.material().id();
    case Object::kGeometryInstance:
      return o.geometry_instance().id();
    case Object::kGeometryGroup:
      return o.geometry_group().id();
    case Object::kGroup:
      return o.group().id();
    case Object::kTransform:
      return o.transform().id();
    case Object::kSelector:
      return o.selector().id();
    case Object::kAcceleration:
      return o.acceleration().id();
    case Object::kTextureSampler:
      return o.texture_sampler().id();
    case Object::kOptix7ProgramGroup:
      return o.optix7_program_group().id();
    case Object::kOptix7Pipeline:
      return o.optix7_pipeline().id();
    case Object::KIND_NOT_SET:
      break;
  }
  return 0;
}

std::string ObjectKindName(Object::KindCase kind) {
  const auto* field = Object::descriptor()->FindFieldByNumber(kind);
  return field != nullptr ? field->name() : "object";
}

}  // namespace tessera::v1
