#include "buffer_format.h"

namespace tessera::api {
namespace {

struct FormatInfo {
  RTformat format;
  size_t size;
  const char* name;
};

constexpr FormatInfo kFormats[] = {
    {RT_FORMAT_UNKNOWN, 0, "RT_FORMAT_UNKNOWN"},
    {RT_FORMAT_FLOAT, 4, "RT_FORMAT_FLOAT"},
    {RT_FORMAT_FLOAT2, 8, "RT_FORMAT_FLOAT2"},
    {RT_FORMAT_FLOAT3, 12, "RT_FORMAT_FLOAT3"},
    {RT_FORMAT_FLOAT4, 16, "RT_FORMAT_FLOAT4"},
    {RT_FORMAT_BYTE, 1, "RT_FORMAT_BYTE"},
    {RT_FORMAT_BYTE2, 2, "RT_FORMAT_BYTE2"},
    {RT_FORMAT_BYTE3, 3, "RT_FORMAT_BYTE3"},
    {RT_FORMAT_BYTE4, 4, "RT_FORMAT_BYTE4"},
    {RT_FORMAT_UNSIGNED_BYTE, 1, "RT_FORMAT_UNSIGNED_BYTE"},
    {RT_FORMAT_UNSIGNED_BYTE2, 2, "RT_FORMAT_UNSIGNED_BYTE2"},
    {RT_FORMAT_UNSIGNED_BYTE3, 3, "RT_FORMAT_UNSIGNED_BYTE3"},
    {RT_FORMAT_UNSIGNED_BYTE4, 4, "RT_FORMAT_UNSIGNED_BYTE4"},
    {RT_FORMAT_SHORT, 2, "RT_FORMAT_SHORT"},
    {RT_FORMAT_SHORT2, 4, "RT_FORMAT_SHORT2"},
    {RT_FORMAT_SHORT3, 6, "RT_FORMAT_SHORT3"},
    {RT_FORMAT_SHORT4, 8, "RT_FORMAT_SHORT4"},
    {RT_FORMAT_UNSIGNED_SHORT, 2, "RT_FORMAT_UNSIGNED_SHORT"},
    {RT_FORMAT_UNSIGNED_SHORT2, 4, "RT_FORMAT_UNSIGNED_SHORT2"},
    {RT_FORMAT_UNSIGNED_SHORT3, 6, "RT_FORMAT_UNSIGNED_SHORT3"},
    {RT_FORMAT_UNSIGNED_SHORT4, 8, "RT_FORMAT_UNSIGNED_SHORT4"},
    {RT_FORMAT_INT, 4, "RT_FORMAT_INT"},
    {RT_FORMAT_INT2, 8, "RT_FORMAT_INT2"},
    {RT_FORMAT_INT3, 12, "RT_FORMAT_INT3"},
    {RT_FORMAT_INT4, 16, "RT_FORMAT_INT4"},
    {RT_FORMAT_UNSIGNED_INT, 4, "RT_FORMAT_UNSIGNED_INT"},
    {RT_FORMAT_UNSIGNED_INT2, 8, "RT_FORMAT_UNSIGNED_INT2"},
    {RT_FORMAT_UNSIGNED_INT3, 12, "RT_FORMAT_UNSIGNED_INT3"},
    {RT_FORMAT_UNSIGNED_INT4, 16, "RT_FORMAT_UNSIGNED_INT4"},
    {RT_FORMAT_USER, 0, "RT_FORMAT_USER"},
    {RT_FORMAT_BUFFER_ID, 4, "RT_FORMAT_BUFFER_ID"},    // an int id, as rtBufferGetId returns
    {RT_FORMAT_PROGRAM_ID, 4, "RT_FORMAT_PROGRAM_ID"},  // an int id, as rtProgramGetId returns
    {RT_FORMAT_HALF, 2, "RT_FORMAT_HALF"},              // IEEE binary16, for textures
    {RT_FORMAT_HALF2, 4, "RT_FORMAT_HALF2"},
    {RT_FORMAT_HALF3, 6, "RT_FORMAT_HALF3"},
    {RT_FORMAT_HALF4, 8, "RT_FORMAT_HALF4"},
};

const FormatInfo* Find(int format) {
  for (const FormatInfo& info : kFormats) {
    if (info.format == format) return &info;
  }
  return nullptr;
}

}  // namespace

bool IsValidFormat(int format) { return Find(format) != nullptr; }

size_t FormatElementSize(RTformat format) {
  const FormatInfo* info = Find(format);
  return info != nullptr ? info->size : 0;
}

const char* FormatName(RTformat format) {
  const FormatInfo* info = Find(format);
  return info != nullptr ? info->name : "invalid format";
}

}  // namespace tessera::api
