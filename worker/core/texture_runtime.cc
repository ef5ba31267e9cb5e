// TesseraRuntime::texture_by_id: what an rtTex* call on an id the plan's table lacks gets.
#include "absl/strings/str_cat.h"
#include "interrupt.h"
#include "tessera/rt.h"
#include "texture_views.h"
#include "thread_state.h"

namespace tessera::worker {

const TesseraTextureView* RtTextureById(int id) {
  InterruptPoint();
  ThreadState& ts = TS();
  const LaunchPlan& plan = *ts.plan;
  std::string why = "no texture sampler has that id";
  if (const long i = plan.textures.index.Find(id); i >= 0) {
    const TextureById& t = plan.textures.samplers[i];
    if (t.problem.ok()) return &t.view;
    why = std::string(t.problem.message());
  }
  Raise(RT_EXCEPTION_TEXTURE_ID_INVALID,
        absl::StrCat("texture id ", id, " in ", ts.current->name, ": ", why));
  return nullptr;  // the exception is disabled: the read gives zeros
}

}  // namespace tessera::worker
