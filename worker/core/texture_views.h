// Texture views: what a program sees of a sampler the replica holds (TesseraTextureView), for
// rtTextureSampler declarations (binding.cc) and bindless ids (plan.cc).
#ifndef TESSERA_WORKER_CORE_TEXTURE_VIEWS_H_
#define TESSERA_WORKER_CORE_TEXTURE_VIEWS_H_

#include <cstdint>

#include "absl/status/statusor.h"
#include "bindless.h"
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

// Every sampler of a plan by id (rtTex*): its view, or why programs cannot read it (no buffer,
// say), said when one tries rather than when the plan is made.
struct TextureById {
  TesseraTextureView view;
  absl::Status problem;
};
struct TextureTable {
  IdIndex index;
  std::vector<TextureById> samplers;
  // The readable views again, as programs read them without a call (TesseraTextureIdTable): by
  // id while `index` is dense, else none.
  std::vector<const TesseraTextureView*> fast_views;
  TesseraTextureIdTable fast{0, nullptr};
};
void PlanTextures(const Replica& replica, TextureTable& table);

// What modules read at fixed offsets from the thread pointer (TesseraRuntime::
// texture_table_offset, texture_id_table_offset): the running program's views, set whenever
// control passes to a program, and the running plan's table, set by UsePlan.
extern __thread const TesseraTextureView* t_texture_table
    __attribute__((tls_model("initial-exec")));
extern __thread const TesseraTextureIdTable* t_texture_ids
    __attribute__((tls_model("initial-exec")));

// TesseraRuntime::texture_by_id (texture_runtime.cc).
const TesseraTextureView* RtTextureById(int id);

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_TEXTURE_VIEWS_H_
