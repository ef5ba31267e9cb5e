// A texture view as the fast lookups' tests build them: linear filtering at normalized
// coordinates from one level (mip filtering off), every wrap mode `wrap`.
#ifndef TESSERA_TESTS_TEXTURE_LINEAR_VIEW_H_
#define TESSERA_TESTS_TEXTURE_LINEAR_VIEW_H_

#include "tessera/detail/texture_view.h"
#include "tessera/rt.h"

namespace tessera::testing {

inline TesseraTextureView LinearView(const void* texels, unsigned w, unsigned h, unsigned d,
                                     unsigned dimensionality, RTformat format,
                                     unsigned element_size, RTtexturereadmode read_mode,
                                     RTwrapmode wrap) {
  TesseraTextureView v{};
  v.levels[0] = {texels, w, h, d, 0};
  v.level_count = 1;
  v.dimensionality = dimensionality;
  v.format = format;
  v.element_size = element_size;
  for (unsigned& m : v.wrap) m = wrap;
  v.min_filter = v.mag_filter = RT_FILTER_LINEAR;
  v.mip_filter = RT_FILTER_NONE;
  v.read_mode = read_mode;
  v.index_mode = RT_TEXTURE_INDEX_NORMALIZED_COORDINATES;
  v.max_anisotropy = 1.f;
  v.mip_level_clamp[1] = 1000.f;
  return v;
}

}  // namespace tessera::testing

#endif  // TESSERA_TESTS_TEXTURE_LINEAR_VIEW_H_
