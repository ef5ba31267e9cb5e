// The TesseraRuntime entries of texture samplers (module ABI 8): a program's rtTextureSampler
// declarations read the views of its binding, rtTex* calls those of the plan by sampler id.
#include "absl/strings/str_cat.h"
#include "interrupt.h"
#include "tessera/rt.h"
#include "texture_views.h"
#include "thread_state.h"

namespace tessera::worker {

const TesseraTextureView* RtTextureView(unsigned slot) {
  const ThreadState& ts = TS();
  const std::vector<TesseraTextureView>& views = ts.current->textures;
  if (slot >= views.size() || views[slot].level_count == 0) return nullptr;
  return &views[slot];
}

const TesseraTextureView* RtTextureById(int id) {
  InterruptPoint();
  ThreadState& ts = TS();
  const LaunchPlan& plan = *ts.plan;
  if (auto it = plan.textures_by_id.find(id); it != plan.textures_by_id.end()) return &it->second;
  std::string why = "no texture sampler has that id";
  if (auto it = plan.texture_problems.find(id); it != plan.texture_problems.end()) {
    why = std::string(it->second.message());
  }
  Raise(RT_EXCEPTION_TEXTURE_ID_INVALID,
        absl::StrCat("texture id ", id, " in ", ts.current->name, ": ", why));
  return nullptr;  // the exception is disabled: the read gives zeros
}

}  // namespace tessera::worker
