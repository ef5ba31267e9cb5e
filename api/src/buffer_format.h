// RTformat facts: which values are formats and how many bytes an element takes.
#ifndef TESSERA_API_SRC_BUFFER_FORMAT_H_
#define TESSERA_API_SRC_BUFFER_FORMAT_H_

#include <cstddef>

#include "tessera/rt.h"

namespace tessera::api {

bool IsValidFormat(int format);
// Element size of a fixed-size format; 0 for RT_FORMAT_USER and RT_FORMAT_UNKNOWN.
size_t FormatElementSize(RTformat format);
const char* FormatName(RTformat format);

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_BUFFER_FORMAT_H_
