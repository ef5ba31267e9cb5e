#include "testing_hooks.h"

#include "boundary.h"

namespace tessera::api::testing {

RTresult UseDevices(RTcontext context, std::vector<std::unique_ptr<Device>> devices) {
  return Call<Context>(__func__, context, [&](Context& c) -> absl::Status {
    c.UseDevicesForTesting(std::move(devices));
    return absl::OkStatus();
  });
}

}  // namespace tessera::api::testing
