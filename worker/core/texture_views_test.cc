// A device's texture views: samplers and mipmapped buffers as a delta brings them, views that
// point at each level, and samplers a device refuses.
#include "texture_views.h"

#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "replica.h"
#include "tessera/rt.h"

namespace tessera::worker {
namespace {

constexpr uint64_t kBuffer = 5, kSampler = 6;

// A 4x4 float texture with 3 mip levels (16 + 4 + 1 floats, level l holding l + 1) and a
// sampler reading it.
v1::StateDelta Scene(uint64_t sequence = 1) {
  v1::StateDelta d;
  d.set_session_id(1);
  d.set_sequence(sequence);
  v1::Buffer* b = d.add_objects()->mutable_buffer();
  b->set_id(kBuffer);
  b->set_version(1);
  b->set_desc(RT_BUFFER_INPUT);
  b->set_format(RT_FORMAT_FLOAT);
  b->set_element_size(4);
  b->add_dims(4);
  b->add_dims(4);
  b->set_mip_level_count(3);
  std::vector<float> texels;
  for (int level = 0, n = 16; level < 3; ++level, n /= 4) texels.insert(texels.end(), n, level + 1);
  v1::BufferChunk* c = d.add_chunks();
  c->set_buffer_id(kBuffer);
  c->set_data(texels.data(), texels.size() * sizeof(float));
  v1::TextureSampler* t = d.add_objects()->mutable_texture_sampler();
  t->set_id(kSampler);
  t->set_version(1);
  t->set_buffer(kBuffer);
  for (int i = 0; i < 3; ++i) t->add_wrap(RT_WRAP_MIRROR);
  t->set_min_filter(RT_FILTER_LINEAR);
  t->set_mag_filter(RT_FILTER_NEAREST);
  t->set_mip_filter(RT_FILTER_LINEAR);
  t->set_max_anisotropy(2.f);
  t->set_mip_level_clamp_max(2.f);
  t->set_read_mode(RT_TEXTURE_READ_ELEMENT_TYPE);
  return d;
}

TEST(TextureViewsTest, ViewsPointAtEveryLevel) {
  Replica r;
  ASSERT_TRUE(r.Apply(Scene()).ok());
  absl::StatusOr<TesseraTextureView> v = MakeTextureView(r, kSampler);
  ASSERT_TRUE(v.ok()) << v.status();
  ASSERT_EQ(v->level_count, 3u);
  const unsigned sides[3] = {4, 2, 1};
  for (unsigned l = 0; l < 3; ++l) {
    EXPECT_EQ(v->levels[l].width, sides[l]);
    EXPECT_EQ(v->levels[l].height, sides[l]);
    EXPECT_EQ(v->levels[l].depth, 1u);
    const float* texels = static_cast<const float*>(v->levels[l].data);
    for (unsigned i = 0; i < sides[l] * sides[l]; ++i) EXPECT_EQ(texels[i], l + 1.f) << l;
  }
  EXPECT_EQ(v->dimensionality, 2u);
  EXPECT_EQ(v->format, static_cast<unsigned>(RT_FORMAT_FLOAT));
  EXPECT_EQ(v->element_size, 4u);
  EXPECT_EQ(v->wrap[2], static_cast<unsigned>(RT_WRAP_MIRROR));
  EXPECT_EQ(v->mag_filter, static_cast<unsigned>(RT_FILTER_NEAREST));
  EXPECT_EQ(v->mip_filter, static_cast<unsigned>(RT_FILTER_LINEAR));
  EXPECT_EQ(v->max_anisotropy, 2.f);
  EXPECT_EQ(v->mip_level_clamp[1], 2.f);
  EXPECT_EQ(v->id, static_cast<int>(kSampler));
  EXPECT_EQ(TextureShapeMismatch(0x02, *v), nullptr);
  EXPECT_NE(TextureShapeMismatch(0x03, *v), nullptr);
  EXPECT_NE(TextureShapeMismatch(0xF2, *v), nullptr);
}

TEST(TextureViewsTest, ChunksMayFillEveryLevelAndNoMore) {
  Replica r;
  v1::StateDelta d = Scene();
  d.mutable_chunks(0)->set_offset(4);  // 21 floats from byte 4 end past the last level
  const absl::Status s = r.Apply(d);
  EXPECT_EQ(s.code(), absl::StatusCode::kOutOfRange) << s;
}

TEST(TextureViewsTest, SamplersWithValuesNoTextureHasAreRefused) {
  const auto set = [](v1::StateDelta& d) {
    for (v1::Object& o : *d.mutable_objects()) {
      if (o.has_texture_sampler()) return o.mutable_texture_sampler();
    }
    return static_cast<v1::TextureSampler*>(nullptr);
  };
  for (int k = 0; k < 3; ++k) {
    v1::StateDelta d = Scene();
    v1::TextureSampler* t = set(d);
    if (k == 0) t->mutable_wrap()->RemoveLast();
    if (k == 1) t->set_read_mode(9);
    if (k == 2) t->set_min_filter(RT_FILTER_NONE);
    Replica r;
    const absl::Status s = r.Apply(d);
    EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument) << k;
    EXPECT_NE(s.message().find("texture sampler #6"), std::string::npos) << s;
  }
}

TEST(TextureViewsTest, ViewsSayWhyTheyCannotBeMade) {
  Replica r;
  v1::StateDelta d = Scene();
  d.mutable_objects(1)->mutable_texture_sampler()->set_buffer(0);
  ASSERT_TRUE(r.Apply(d).ok());
  EXPECT_NE(MakeTextureView(r, kSampler).status().message().find("has no buffer"),
            std::string::npos);
  EXPECT_EQ(MakeTextureView(r, 99).status().code(), absl::StatusCode::kNotFound);
  v1::StateDelta user = Scene(2);
  user.clear_chunks();
  user.mutable_objects(0)->mutable_buffer()->set_format(RT_FORMAT_USER);
  ASSERT_TRUE(r.Apply(user).ok());
  EXPECT_NE(MakeTextureView(r, kSampler).status().message().find("no texture can read"),
            std::string::npos);
}

}  // namespace
}  // namespace tessera::worker
