/* cudaCreateChannelDesc<T>(), the C++ template of CUDA's channel_descriptor.h: the channel
 * layout of an element type, for cudaMallocArray and texture resources. Each specialization
 * calls the C function cudaCreateChannelDesc (cuda_runtime_api.h) with CUDA's bits and kind. */
#ifndef TESSERA_OPTIX7_CHANNEL_DESCRIPTOR_H_
#define TESSERA_OPTIX7_CHANNEL_DESCRIPTOR_H_

#include "cuda_runtime_api.h"

#ifdef __cplusplus

/* Types without a channel layout get "none", as in CUDA. */
template <class T>
__inline__ __host__ cudaChannelFormatDesc cudaCreateChannelDesc() {
  return cudaCreateChannelDesc(0, 0, 0, 0, cudaChannelFormatKindNone);
}

#define TESSERA_CHANNEL_DESC_(type, x, y, z, w, kind)                       \
  template <>                                                               \
  __inline__ __host__ cudaChannelFormatDesc cudaCreateChannelDesc<type>() { \
    return cudaCreateChannelDesc(x, y, z, w, cudaChannelFormatKind##kind);  \
  }
#define TESSERA_CHANNEL_DESC_FAMILY_(base, scalar, bits, kind) \
  TESSERA_CHANNEL_DESC_(scalar, bits, 0, 0, 0, kind)           \
  TESSERA_CHANNEL_DESC_(base##1, bits, 0, 0, 0, kind)          \
  TESSERA_CHANNEL_DESC_(base##2, bits, bits, 0, 0, kind)       \
  TESSERA_CHANNEL_DESC_(base##4, bits, bits, bits, bits, kind)

TESSERA_CHANNEL_DESC_(char, 8, 0, 0, 0, Signed)
TESSERA_CHANNEL_DESC_FAMILY_(char, signed char, 8, Signed)
TESSERA_CHANNEL_DESC_FAMILY_(uchar, unsigned char, 8, Unsigned)
TESSERA_CHANNEL_DESC_FAMILY_(short, short, 16, Signed)
TESSERA_CHANNEL_DESC_FAMILY_(ushort, unsigned short, 16, Unsigned)
TESSERA_CHANNEL_DESC_FAMILY_(int, int, 32, Signed)
TESSERA_CHANNEL_DESC_FAMILY_(uint, unsigned int, 32, Unsigned)
TESSERA_CHANNEL_DESC_FAMILY_(float, float, 32, Float)

#undef TESSERA_CHANNEL_DESC_FAMILY_
#undef TESSERA_CHANNEL_DESC_

#endif /* __cplusplus */

#endif /* TESSERA_OPTIX7_CHANNEL_DESCRIPTOR_H_ */
