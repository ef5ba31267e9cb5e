// OptiX's OpenGL interop (optix_gl_interop.h): declared so that applications build, refused with
// RT_ERROR_NOT_SUPPORTED at run time. Devices are CPU processes, often on other machines, with no
// OpenGL context whose memory they could share.
#include <string>

#include "absl/strings/str_cat.h"
#include "boundary.h"
#include "buffer.h"
#include "context.h"
#include "optix_gl_interop.h"
#include "status.h"
#include "texture_sampler.h"

using namespace tessera::api;  // NOLINT: C entry points only

namespace {

absl::Status NoInterop(const char* instead) {
  return RtError(RT_ERROR_NOT_SUPPORTED,
                 absl::StrCat("OpenGL interop is not supported: Tessera's devices are CPU "
                              "processes with no OpenGL context to share memory with; ",
                              instead));
}

constexpr char kCreateBuffer[] =
    "create the buffer with rtBufferCreate and upload its contents to OpenGL after mapping it "
    "(the OptiX SDK samples: --nopbo)";
constexpr char kCreateSampler[] =
    "create the sampler with rtTextureSamplerCreate over a buffer holding the image";
constexpr char kNoGlObject[] = "no Tessera object has an OpenGL name";

}  // namespace

extern "C" {

RTresult rtBufferCreateFromGLBO(RTcontext context, unsigned int, unsigned int, RTbuffer* buffer) {
  if (buffer != nullptr) *buffer = nullptr;
  return Call<Context>(__func__, context,
                       [](Context&) -> absl::Status { return NoInterop(kCreateBuffer); });
}

RTresult rtTextureSamplerCreateFromGLImage(RTcontext context, unsigned int, RTgltarget,
                                           RTtexturesampler* sampler) {
  if (sampler != nullptr) *sampler = nullptr;
  return Call<Context>(__func__, context,
                       [](Context&) -> absl::Status { return NoInterop(kCreateSampler); });
}

RTresult rtBufferGetGLBOId(RTbuffer buffer, unsigned int* gl_id) {
  if (gl_id != nullptr) *gl_id = 0;
  return Call<Buffer>(__func__, buffer,
                      [](Buffer&) -> absl::Status { return NoInterop(kNoGlObject); });
}

RTresult rtTextureSamplerGetGLImageId(RTtexturesampler sampler, unsigned int* gl_id) {
  if (gl_id != nullptr) *gl_id = 0;
  return Call<TextureSampler>(
      __func__, sampler, [](TextureSampler&) -> absl::Status { return NoInterop(kNoGlObject); });
}

RTresult rtBufferGLRegister(RTbuffer buffer) {
  return Call<Buffer>(__func__, buffer,
                      [](Buffer&) -> absl::Status { return NoInterop(kNoGlObject); });
}

RTresult rtBufferGLUnregister(RTbuffer buffer) {
  return Call<Buffer>(__func__, buffer,
                      [](Buffer&) -> absl::Status { return NoInterop(kNoGlObject); });
}

RTresult rtTextureSamplerGLRegister(RTtexturesampler sampler) {
  return Call<TextureSampler>(
      __func__, sampler, [](TextureSampler&) -> absl::Status { return NoInterop(kNoGlObject); });
}

RTresult rtTextureSamplerGLUnregister(RTtexturesampler sampler) {
  return Call<TextureSampler>(
      __func__, sampler, [](TextureSampler&) -> absl::Status { return NoInterop(kNoGlObject); });
}

}  // extern "C"
