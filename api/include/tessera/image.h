/* Images for texture samplers: a file OpenImageIO reads (EXR, HDR, PNG, JPEG, TIFF, ...) into a
 * new INPUT buffer, ready for rtTextureSamplerSetBuffer. A separate library, libtessera_image
 * (CMake: Tessera::image), so that applications that never load an image do not link
 * OpenImageIO. C99-clean; calls only the public rt* API. */
#ifndef TESSERA_IMAGE_H_
#define TESSERA_IMAGE_H_

#include "tessera/rt.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Flags of tesseraBufferCreateFromImage. */
enum {
  /* Row 0 of the buffer is the file's first (top) row. Without it row 0 is the bottom row, as
   * the OptiX SDK's loaders store images: texture coordinate v = 0 is the image's bottom edge. */
  TESSERA_IMAGE_TOP_ROW_FIRST = 1u,
  /* Always RT_FORMAT_FLOAT4, whatever the file stores. */
  TESSERA_IMAGE_FLOAT = 2u
};

/* Creates a 2D RT_BUFFER_INPUT buffer of `context` holding the image at `path`, the file's size:
 * RT_FORMAT_UNSIGNED_BYTE4 for a file of 8-bit channels (PNG, JPEG: the bytes as stored, sRGB
 * encoded where the file is; a sampler's RT_TEXTURE_READ_NORMALIZED_FLOAT reads them in [0, 1]),
 * RT_FORMAT_FLOAT4 for any other (EXR, HDR, 16-bit PNG: linear values as OpenImageIO gives them;
 * 16-bit integers become [0, 1]). One channel is grey (R = G = B), two are grey and alpha, three
 * get alpha 1 (255), channels past the fourth are dropped. Errors: RT_ERROR_INVALID_VALUE for a
 * null argument or unknown flags, RT_ERROR_FILE_NOT_FOUND for a file that cannot be opened or
 * read (the message names the file and says why), and whatever rtBufferCreate returns. On error
 * `*buffer` is left alone and no buffer is created. */
RTAPI RTresult tesseraBufferCreateFromImage(RTcontext context, const char* path, unsigned flags,
                                            RTbuffer* buffer);

/* What went wrong in the calling thread's last failed tesseraBufferCreateFromImage ("" when the
 * last call succeeded). Valid until the thread's next call. */
RTAPI const char* tesseraImageGetErrorString(void);

#ifdef __cplusplus
}
#endif

#endif /* TESSERA_IMAGE_H_ */
