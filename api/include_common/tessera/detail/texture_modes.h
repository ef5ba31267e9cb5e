/* The values a TesseraTextureView's fields take (tessera/detail/texture_view.h): those of OptiX
 * 3's RTformat, RTwrapmode, RTfiltermode, RTtexturereadmode and RTtextureindexmode
 * (tessera/rt.h), restated so that the sampler needs no OptiX 3 header and the OptiX 7 layer can
 * describe CUDA texture objects with the same views. worker/core/texture_views.cc checks that
 * they equal OptiX 3's. */
#ifndef TESSERA_DETAIL_TEXTURE_MODES_H_
#define TESSERA_DETAIL_TEXTURE_MODES_H_

namespace tessera::texture {

// TesseraTextureView::format: C channels of one scalar type, packed.
enum FormatValue : unsigned {
  kFormatFloat = 0x101,
  kFormatFloat2,
  kFormatFloat3,
  kFormatFloat4,
  kFormatByte,
  kFormatByte2,
  kFormatByte3,
  kFormatByte4,
  kFormatUnsignedByte,
  kFormatUnsignedByte2,
  kFormatUnsignedByte3,
  kFormatUnsignedByte4,
  kFormatShort,
  kFormatShort2,
  kFormatShort3,
  kFormatShort4,
  kFormatUnsignedShort,
  kFormatUnsignedShort2,
  kFormatUnsignedShort3,
  kFormatUnsignedShort4,
  kFormatInt,
  kFormatInt2,
  kFormatInt3,
  kFormatInt4,
  kFormatUnsignedInt,
  kFormatUnsignedInt2,
  kFormatUnsignedInt3,
  kFormatUnsignedInt4,
  kFormatHalf = 0x120,
  kFormatHalf2,
  kFormatHalf3,
  kFormatHalf4,
};

// TesseraTextureView::wrap[i].
enum WrapValue : unsigned { kWrapRepeat = 0, kWrapClampToEdge, kWrapMirror, kWrapClampToBorder };

// min_filter, mag_filter, mip_filter.
enum FilterValue : unsigned { kFilterNearest = 0, kFilterLinear, kFilterNone };

// read_mode: element type, normalized float, and their sRGB forms.
enum ReadModeValue : unsigned {
  kReadElementType = 0,
  kReadNormalizedFloat = 1,
  kReadElementTypeSrgb = 2,
  kReadNormalizedFloatSrgb = 3,
};

// index_mode.
enum IndexModeValue : unsigned { kIndexNormalizedCoordinates = 0, kIndexArrayIndex };

}  // namespace tessera::texture

#endif  // TESSERA_DETAIL_TEXTURE_MODES_H_
