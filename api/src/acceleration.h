// An acceleration structure: builder and traverser names from OptiX 3 Table 2, string properties
// and a build epoch. The device rebuilds when it sees a new epoch. OptiX rebuilds only when the
// application calls rtAccelerationMarkDirty; Tessera also marks it dirty when the structure below
// changes (see dirty.h and docs/COMPATIBILITY.md).
#ifndef TESSERA_API_SRC_ACCELERATION_H_
#define TESSERA_API_SRC_ACCELERATION_H_

#include <map>
#include <string>

#include "absl/status/status.h"
#include "object.h"

namespace tessera::api {

class Acceleration : public Object {
 public:
  static constexpr Kind kKind = Kind::kAcceleration;

  Acceleration(Context* context, uint64_t id) : Object(Kind::kAcceleration, context, id) {
    Touch();
  }

  const std::string& builder() const { return builder_; }
  const std::string& traverser() const { return traverser_; }
  absl::Status SetBuilder(const char* builder);
  absl::Status SetTraverser(const char* traverser);
  void SetProperty(const std::string& name, const std::string& value);
  // Empty when the property is not set.
  const std::string& Property(const std::string& name) const;
  const std::map<std::string, std::string>& properties() const { return properties_; }

  uint64_t build_epoch() const { return build_epoch_; }
  // Newly created accelerations are dirty, as in OptiX.
  bool dirty() const { return dirty_; }
  void MarkDirty();
  // A launch shipped the current epoch to every device.
  void ClearDirty() { dirty_ = false; }

  // Builder and traverser are set and belong together (Table 2).
  absl::Status CheckComplete() const;

 private:
  std::string builder_;
  std::string traverser_;
  std::map<std::string, std::string> properties_;
  uint64_t build_epoch_ = 1;
  bool dirty_ = true;
};

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_ACCELERATION_H_
