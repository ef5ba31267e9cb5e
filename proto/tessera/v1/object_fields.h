// What every kind of v1::Object shares, read without a switch at each use: its id and its kind's
// name, for the worker's replica and the wire's size checks alike.
#ifndef TESSERA_PROTO_TESSERA_V1_OBJECT_FIELDS_H_
#define TESSERA_PROTO_TESSERA_V1_OBJECT_FIELDS_H_

#include <cstdint>
#include <string>

#include "tessera/v1/state.pb.h"

namespace tessera::v1 {

// The id of the object inside `o`'s kind; 0 when no kind is set.
uint64_t ObjectId(const Object& o);

// "geometry_instance" (the kind's field name) for messages; "object" when none is set.
std::string ObjectKindName(Object::KindCase kind);

}  // namespace tessera::v1

#endif  // TESSERA_PROTO_TESSERA_V1_OBJECT_FIELDS_H_
