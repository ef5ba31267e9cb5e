/* OptiX's OpenGL interop (optix_gl_interop.h), declared so that an application that includes it
 * builds unchanged. Tessera's devices are CPU processes, often on other machines, with no OpenGL
 * context to share memory with: every function returns RT_ERROR_NOT_SUPPORTED and says so
 * (rtContextGetErrorString names the function and what to do instead). An application that
 * falls back to plain buffers when interop fails (the SDK samples' `--nopbo`, or a check of the
 * result) runs as it would on a machine without OpenGL. docs/COMPATIBILITY.md lists them. */
#ifndef TESSERA_OPTIX_GL_INTEROP_H_
#define TESSERA_OPTIX_GL_INTEROP_H_

#include "tessera/rt.h"

#ifdef __cplusplus
extern "C" {
#endif

/* OpenGL targets of rtTextureSamplerCreateFromGLImage, with OptiX's values. */
typedef enum {
  RT_TARGET_GL_TEXTURE_2D,
  RT_TARGET_GL_TEXTURE_RECTANGLE,
  RT_TARGET_GL_TEXTURE_3D,
  RT_TARGET_GL_RENDER_BUFFER,
  RT_TARGET_GL_TEXTURE_1D,
  RT_TARGET_GL_TEXTURE_1D_ARRAY,
  RT_TARGET_GL_TEXTURE_2D_ARRAY,
  RT_TARGET_GL_TEXTURE_CUBE_MAP,
  RT_TARGET_GL_TEXTURE_CUBE_MAP_ARRAY
} RTgltarget;

RTAPI RTresult rtBufferCreateFromGLBO(RTcontext context, unsigned int bufferdesc, unsigned int glId,
                                      RTbuffer* buffer);
RTAPI RTresult rtTextureSamplerCreateFromGLImage(RTcontext context, unsigned int glId,
                                                 RTgltarget target,
                                                 RTtexturesampler* textureSampler);
RTAPI RTresult rtBufferGetGLBOId(RTbuffer buffer, unsigned int* glId);
RTAPI RTresult rtTextureSamplerGetGLImageId(RTtexturesampler textureSampler, unsigned int* glId);
RTAPI RTresult rtBufferGLRegister(RTbuffer buffer);
RTAPI RTresult rtBufferGLUnregister(RTbuffer buffer);
RTAPI RTresult rtTextureSamplerGLRegister(RTtexturesampler textureSampler);
RTAPI RTresult rtTextureSamplerGLUnregister(RTtexturesampler textureSampler);

#ifdef __cplusplus
}
#endif

#endif /* TESSERA_OPTIX_GL_INTEROP_H_ */
