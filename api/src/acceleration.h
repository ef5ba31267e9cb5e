// An acceleration structure: builder and traverser names from OptiX 3 Table 2, string properties
// and a build epoch. The device rebuilds when it sees a new epoch. OptiX rebuilds only when the
// application calls rtAccelerationMarkDirty; Tessera also marks it dirty when the structure below
// changes (see dirty.h and docs/COMPATIBILITY.md).
#ifndef TESSERA_API_SRC_ACCELERATION_H_
#define TESSERA_API_SRC_ACCELERATION_H_

#include <map>
#include <memory>
#include <string>

#include "absl/status/status.h"
#include "acceleration_blob.h"
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

  // rtAccelerationSetData (docs/acceleration_data.md): takes the blob's builder, traverser and
  // properties, and a new build epoch that devices build from the blob's bounds; not dirty after,
  // "as if a regular construction had been performed". Changes nothing when the blob names a
  // builder or traverser this Tessera does not know.
  absl::Status Restore(AccelerationBlob blob);
  // What Restore took, until MarkDirty (or a change below the acceleration) drops it. Null if none.
  const AccelerationBlob* restored() const { return restored_.get(); }
  // Whether the launch that first lowers the restored blob found it built over the graph the
  // acceleration is on now (acceleration_data.cc CheckRestoredAccelerations): only then do its
  // bounds ship to devices.
  enum class RestoreCheck { kPending, kMatches, kMismatch };
  RestoreCheck restore_check() const { return restore_check_; }
  void set_restore_check(RestoreCheck check) {
    restore_check_ = check;
    if (check == RestoreCheck::kMatches) Touch();  // ships again, now with the bounds
  }

  // The blob rtAccelerationGetDataSize made, reused by rtAccelerationGetData while the build
  // epoch and version are the same (the two calls must agree on its size).
  struct Extracted {
    uint64_t build_epoch = 0;
    uint64_t version = 0;
    std::string bytes;
  };
  Extracted& extracted() { return extracted_; }

 private:
  std::string builder_;
  std::string traverser_;
  std::map<std::string, std::string> properties_;
  uint64_t build_epoch_ = 1;
  bool dirty_ = true;
  std::unique_ptr<AccelerationBlob> restored_;
  RestoreCheck restore_check_ = RestoreCheck::kPending;
  Extracted extracted_;
};

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_ACCELERATION_H_
