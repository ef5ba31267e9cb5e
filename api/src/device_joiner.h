// A running worker (HOST:PORT, unix:PATH) that does not answer, brought into its context when it
// comes up: its device is created again in the background, 0.5 s after the last try and twice as
// long each time up to 10 s, until one try connects. Launches meanwhile run on the devices that
// answer and never wait for it (docs/devices.md "Running workers as a service"); the launch after
// it connected takes the device, which gets the whole state under a new session, as a device lost
// and started again does.
#ifndef TESSERA_API_SRC_DEVICE_JOINER_H_
#define TESSERA_API_SRC_DEVICE_JOINER_H_

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/time/time.h"
#include "tessera/scheduler/device.h"

namespace tessera::api {

// How long a joiner waits between tries: `first` after a failed one, twice as long after each
// further one, up to `most`.
struct JoinBackoff {
  absl::Duration first = absl::Milliseconds(500);
  absl::Duration most = absl::Seconds(10);
};

class DeviceJoiner {
 public:
  using Create = std::function<absl::StatusOr<std::unique_ptr<Device>>()>;
  using Backoff = JoinBackoff;

  // Starts trying on a thread of its own: at once, or after `backoff.first` when the caller has
  // just tried itself. `address` names the device in the line said when it connects ("device
  // unix:/run/w1.sock is up; joining"), which is said for a device `lost` before, or one whose
  // first try failed (not for a worker that simply answered at a context's first launch).
  DeviceJoiner(std::string address, Create create, bool try_at_once, bool lost,
               Backoff backoff = Backoff());
  // Returns at once: a try under way (a connection that waits for its timeout) ends on its own
  // thread, and a device it made then is let go.
  ~DeviceJoiner();
  DeviceJoiner(const DeviceJoiner&) = delete;
  DeviceJoiner& operator=(const DeviceJoiner&) = delete;

  // The device, once a try made it (the thread has ended then); null before, and after a Take.
  std::unique_ptr<Device> Take();

  // Tries again now (after the try under way, if one is), with the backoff from its start, and
  // returns the number Wait waits for.
  uint64_t Kick();
  // Waits until `tries` tries ended or a device is ready, or until `deadline`; whether a device
  // is ready.
  bool Wait(uint64_t tries, absl::Time deadline);

  // Why the last try failed (OK before any failed).
  absl::Status last_error() const;
  uint64_t tries() const;  // tries that ended

 private:
  struct State;  // shared with the thread, which may outlive this object
  std::shared_ptr<State> state_;
};

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_DEVICE_JOINER_H_
