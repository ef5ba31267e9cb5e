// Texture views: what a program sees of a sampler the replica holds (TesseraTextureView), for
// rtTextureSampler declarations (binding.cc) and bindless ids (plan.cc).
#ifndef TESSERA_WORKER_CORE_TEXTURE_VIEWS_H_
#define TESSERA_WORKER_CORE_TEXTURE_VIEWS_H_

#include <cstdint>

#include "absl/status/statusor.h"
#include "replica.h"
#include "tessera/detail/texture_view.h"

namespace tessera::worker {

// The view of sampler `sampler_id`: its modes and its buffer's levels, pointing into the
// replica's copy of the buffer (valid until the buffer is reallocated, which makes a new plan).
// NOT_FOUND for an unknown sampler or buffer, FAILED_PRECONDITION for a sampler without a buffer
// or a buffer no texture can read.
absl::StatusOr<TesseraTextureView> MakeTextureView(const Replica& replica, uint64_t sampler_id);

// Whether a buffer's shape fits a declaration's Dim (1, 2, 3 or a cudaTextureType* value): null
// when it does, else what the declaration wants ("a 2D buffer").
const char* TextureShapeMismatch(unsigned declared, const TesseraTextureView& view);

// TesseraRuntime::texture_view and texture_by_id (texture_runtime.cc).
const TesseraTextureView* RtTextureView(unsigned slot);
const TesseraTextureView* RtTextureById(int id);

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_TEXTURE_VIEWS_H_
