// A Device for tests of the launch path: records every delta and launch request, and answers
// launches through a test-provided function (e.g. writing known bytes into output buffers).
#ifndef TESSERA_TESTS_API_FAKE_DEVICE_H_
#define TESSERA_TESTS_API_FAKE_DEVICE_H_

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <new>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "tessera/scheduler/device.h"

namespace tessera::test {

class FakeDevice : public Device {
 public:
  using Answer =
      std::function<absl::Status(const v1::LaunchRequest&, const std::atomic<bool>& cancel,
                                 const std::function<void(v1::TileResult&&)>&)>;

  // What the test sees; shared so it outlives the device the context owns.
  struct Record {
    std::mutex mu;
    std::vector<v1::StateDelta> deltas;
    std::vector<v1::LaunchRequest> launches;
    absl::Status apply_status;  // returned by Apply (deltas are recorded either way)
    bool apply_throws = false;  // Apply throws std::bad_alloc instead
    Answer answer;
    bool destroyed = false;
  };

  explicit FakeDevice(std::shared_ptr<Record> record, std::string name = "fake")
      : record_(std::move(record)), name_(std::move(name)) {}
  ~FakeDevice() override {
    std::lock_guard<std::mutex> lock(record_->mu);
    record_->destroyed = true;
  }

  DeviceInfo Info() const override { return {name_, name_, 1}; }

  absl::Status Apply(const v1::StateDelta& delta) override {
    std::lock_guard<std::mutex> lock(record_->mu);
    record_->deltas.push_back(delta);
    if (record_->apply_throws) throw std::bad_alloc();
    return record_->apply_status;
  }

  absl::Status Launch(const v1::LaunchRequest& request, const std::atomic<bool>& cancel,
                      const std::function<void(v1::TileResult&&)>& on_result) override {
    Answer answer;
    {
      std::lock_guard<std::mutex> lock(record_->mu);
      record_->launches.push_back(request);
      answer = record_->answer;
    }
    return answer ? answer(request, cancel, on_result) : absl::OkStatus();
  }

 private:
  std::shared_ptr<Record> record_;
  std::string name_;
};

}  // namespace tessera::test

#endif  // TESSERA_TESTS_API_FAKE_DEVICE_H_
