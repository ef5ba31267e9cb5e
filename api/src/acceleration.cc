#include "acceleration.h"

#include <cstring>

#include "absl/strings/str_cat.h"
#include "context.h"
#include "status.h"

namespace tessera::api {
namespace {

// OptiX 3 Table 2 (plus Trbvh from later 3.x releases): builder → traversers it pairs with.
struct BuilderInfo {
  const char* builder;
  const char* traversers[3];
};

constexpr BuilderInfo kBuilders[] = {
    {"Sbvh", {"Bvh", "BvhCompact", nullptr}},      {"Bvh", {"Bvh", "BvhCompact", nullptr}},
    {"MedianBvh", {"Bvh", "BvhCompact", nullptr}}, {"Lbvh", {"Bvh", "BvhCompact", nullptr}},
    {"Trbvh", {"Bvh", "BvhCompact", nullptr}},     {"TriangleKdTree", {"KdTree", nullptr, nullptr}},
    {"NoAccel", {"NoAccel", nullptr, nullptr}},
};

constexpr const char* kTraversers[] = {"Bvh", "BvhCompact", "KdTree", "NoAccel"};

const BuilderInfo* FindBuilder(const std::string& name) {
  for (const BuilderInfo& info : kBuilders) {
    if (name == info.builder) return &info;
  }
  return nullptr;
}

const std::string& EmptyString() {
  static const auto* empty = new std::string;
  return *empty;
}

}  // namespace

absl::Status Acceleration::SetBuilder(const char* builder) {
  if (FindBuilder(builder) == nullptr) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   absl::StrCat("unknown builder '", builder,
                                "' (expected Sbvh, Bvh, MedianBvh, Lbvh, Trbvh, TriangleKdTree or "
                                "NoAccel)"));
  }
  if (builder_ != builder) {
    builder_ = builder;
    MarkDirty();
  }
  return absl::OkStatus();
}

absl::Status Acceleration::SetTraverser(const char* traverser) {
  bool known = false;
  for (const char* t : kTraversers) known = known || std::strcmp(t, traverser) == 0;
  if (!known) {
    return RtError(RT_ERROR_INVALID_VALUE,
                   absl::StrCat("unknown traverser '", traverser,
                                "' (expected Bvh, BvhCompact, KdTree or NoAccel)"));
  }
  if (traverser_ != traverser) {
    traverser_ = traverser;
    MarkDirty();
  }
  return absl::OkStatus();
}

void Acceleration::SetProperty(const std::string& name, const std::string& value) {
  // As in OptiX, a property change takes effect at the next rebuild; it does not mark dirty.
  properties_[name] = value;
  Touch();
}

const std::string& Acceleration::Property(const std::string& name) const {
  auto it = properties_.find(name);
  return it == properties_.end() ? EmptyString() : it->second;
}

void Acceleration::MarkDirty() {
  ++build_epoch_;
  dirty_ = true;
  restored_.reset();  // a rebuild runs the bounding-box programs again
  Touch();
}

absl::Status Acceleration::Restore(AccelerationBlob blob) {
  const BuilderInfo* info = FindBuilder(blob.builder);
  bool paired = false;
  if (info != nullptr) {
    for (const char* t : info->traversers) paired = paired || (t != nullptr && blob.traverser == t);
  }
  if (!paired) {
    return RtError(
        RT_ERROR_INVALID_VALUE,
        absl::StrCat("acceleration data refused: builder '", blob.builder, "' with traverser '",
                     blob.traverser, "' is not a pair Tessera builds"));
  }
  builder_ = blob.builder;
  traverser_ = blob.traverser;
  properties_ = blob.properties;
  ++build_epoch_;  // devices build again, from the blob's bounds
  dirty_ = false;
  restored_ = std::make_unique<AccelerationBlob>(std::move(blob));
  restore_check_ = RestoreCheck::kPending;
  context()->pending_restores().insert(id());
  Touch();
  return absl::OkStatus();
}

absl::Status Acceleration::CheckComplete() const {
  if (builder_.empty()) return RtError(RT_ERROR_INVALID_VALUE, "no builder set");
  if (traverser_.empty()) return RtError(RT_ERROR_INVALID_VALUE, "no traverser set");
  const BuilderInfo* info = FindBuilder(builder_);
  for (const char* t : info->traversers) {
    if (t != nullptr && traverser_ == t) return absl::OkStatus();
  }
  return RtError(
      RT_ERROR_INVALID_VALUE,
      absl::StrCat("builder '", builder_, "' cannot be used with traverser '", traverser_, "'"));
}

}  // namespace tessera::api
