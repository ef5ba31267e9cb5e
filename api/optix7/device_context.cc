// optixDeviceContext*: contexts, their log callback, properties and disk cache settings.
#include <unistd.h>

#include <filesystem>
#include <memory>
#include <string>
#include <system_error>

#include "absl/strings/str_cat.h"
#include "accuracy_flags.h"
#include "call.h"
#include "cuda_devices.h"
#include "module_compiler.h"
#include "optix_host.h"
#include "tessera/optix7_ext.h"

namespace tessera::optix7 {
namespace {

// OptiX's limits where Tessera has none of its own that is lower (an application sizes its
// scene to them): those of OptiX 7.7 on current GPUs. Trace depth 31 is OptiX's, which
// optixPipelineCreate checks too. A traversable graph deeper than one instance level is accepted
// as in OptiX; Embree here traces one instance level, and deeper graphs are for the engine's own
// traversal (docs/optix7.md).
constexpr unsigned kMaxTraceDepthProperty = 31;
constexpr unsigned kMaxTraversableGraphDepth = 31;
constexpr unsigned kMaxPrimitivesPerGas = 1u << 29;
constexpr unsigned kMaxInstancesPerIas = 1u << 24;
constexpr unsigned kRtcoreVersion = 0;  // no RT cores: CPUs
constexpr unsigned kMaxInstanceId = (1u << 28) - 1;
constexpr unsigned kInstanceVisibilityMaskBits = 8;
constexpr unsigned kMaxSbtRecordsPerGas = 1u << 24;
constexpr unsigned kMaxSbtOffset = (1u << 28) - 1;

absl::StatusOr<unsigned> PropertyValue(OptixDeviceProperty property) {
  switch (property) {
    case OPTIX_DEVICE_PROPERTY_LIMIT_MAX_TRACE_DEPTH:
      return kMaxTraceDepthProperty;
    case OPTIX_DEVICE_PROPERTY_LIMIT_MAX_TRAVERSABLE_GRAPH_DEPTH:
      return kMaxTraversableGraphDepth;
    case OPTIX_DEVICE_PROPERTY_LIMIT_MAX_PRIMITIVES_PER_GAS:
      return kMaxPrimitivesPerGas;
    case OPTIX_DEVICE_PROPERTY_LIMIT_MAX_INSTANCES_PER_IAS:
      return kMaxInstancesPerIas;
    case OPTIX_DEVICE_PROPERTY_RTCORE_VERSION:
      return kRtcoreVersion;
    case OPTIX_DEVICE_PROPERTY_LIMIT_MAX_INSTANCE_ID:
      return kMaxInstanceId;
    case OPTIX_DEVICE_PROPERTY_LIMIT_NUM_BITS_INSTANCE_VISIBILITY_MASK:
      return kInstanceVisibilityMaskBits;
    case OPTIX_DEVICE_PROPERTY_LIMIT_MAX_SBT_RECORDS_PER_GAS:
      return kMaxSbtRecordsPerGas;
    case OPTIX_DEVICE_PROPERTY_LIMIT_MAX_SBT_OFFSET:
      return kMaxSbtOffset;
  }
  return OptixError(OPTIX_ERROR_INVALID_VALUE,
                    absl::StrCat("property 0x", absl::Hex(static_cast<unsigned>(property)),
                                 " is no OptixDeviceProperty"));
}

// A cache directory OptiX would accept: created if missing, writable.
absl::Status CheckCacheLocation(const std::string& location) {
  if (location.empty()) {
    return OptixError(OPTIX_ERROR_DISK_CACHE_INVALID_PATH, "location is empty");
  }
  std::error_code ec;
  std::filesystem::create_directories(location, ec);
  if (ec || !std::filesystem::is_directory(location, ec)) {
    return OptixError(OPTIX_ERROR_DISK_CACHE_INVALID_PATH,
                      absl::StrCat("cannot create cache directory '", location,
                                   "': ", ec ? ec.message() : "not a directory"));
  }
  if (access(location.c_str(), W_OK | X_OK) != 0) {
    return OptixError(OPTIX_ERROR_DISK_CACHE_PERMISSION_ERROR,
                      absl::StrCat("cache directory '", location, "' is not writable"));
  }
  return absl::OkStatus();
}

}  // namespace
}  // namespace tessera::optix7

using tessera::optix7::Call;
using tessera::optix7::DeviceContext;
using tessera::optix7::OptixError;

extern "C" {

OptixResult optixDeviceContextCreate(CUcontext fromContext,
                                     const OptixDeviceContextOptions* options,
                                     OptixDeviceContext* context) {
  // fromContext 0 means "the current one" in OptiX: the calling thread's current CUDA device
  // (cudaSetDevice), which with TESSERA_CUDA_DEVICES=each is the one Tessera device the
  // context's launches run on. A context from cuCtxCreate or cuCtxGetCurrent names its device.
  int cuda_device = tessera::optix7::LaunchDeviceForNewContext();
  if (cuda_device != tessera::optix7::kEveryDevice) {
    const int of_context = tessera::optix7::CudaDeviceOfContext(fromContext);
    if (of_context >= 0) cuda_device = of_context;
  }
  return Call("optixDeviceContextCreate").Run([&](Call& call) -> absl::Status {
    if (absl::Status s = call.NotNull(context, "context"); !s.ok()) return s;
    OptixDeviceContextOptions o{};
    if (options != nullptr) o = *options;
    if (o.logCallbackLevel < 0 || o.logCallbackLevel > 4) {
      return OptixError(OPTIX_ERROR_INVALID_VALUE,
                        absl::StrCat("options->logCallbackLevel is ", o.logCallbackLevel,
                                     "; OptiX allows 0 (off) to 4 (print)"));
    }
    if (o.validationMode != OPTIX_DEVICE_CONTEXT_VALIDATION_MODE_OFF &&
        o.validationMode != OPTIX_DEVICE_CONTEXT_VALIDATION_MODE_ALL) {
      return OptixError(OPTIX_ERROR_INVALID_VALUE,
                        absl::StrCat("options->validationMode 0x",
                                     absl::Hex(static_cast<unsigned>(o.validationMode)),
                                     " is neither OFF nor ALL"));
    }
    auto created = std::make_shared<DeviceContext>(o, tessera::api::ModuleCacheDir(), cuda_device);
    tessera::optix7::Register(created, created.get());
    call.set_context(created);
    if (created->validation()) {
      call.Log(tessera::optix7::kLogWarning,
               "validation mode is on: launches and SBTs are checked further (slower)");
    }
    *context = reinterpret_cast<OptixDeviceContext>(created.get());
    return absl::OkStatus();
  });
}

OptixResult optixDeviceContextDestroy(OptixDeviceContext context) {
  return Call("optixDeviceContextDestroy").Run([&](Call& call) -> absl::Status {
    std::shared_ptr<DeviceContext> c;
    if (absl::Status s = call.Lookup(context, "context", &c); !s.ok()) return s;
    // Its modules, program groups and pipelines go with it, as in OptiX.
    tessera::optix7::UnregisterObjectsOf(c.get());
    return absl::OkStatus();
  });
}

OptixResult optixDeviceContextGetProperty(OptixDeviceContext context, OptixDeviceProperty property,
                                          void* value, size_t sizeInBytes) {
  return Call("optixDeviceContextGetProperty").Run([&](Call& call) -> absl::Status {
    std::shared_ptr<DeviceContext> c;
    if (absl::Status s = call.Lookup(context, "context", &c); !s.ok()) return s;
    if (absl::Status s = call.NotNull(value, "value"); !s.ok()) return s;
    absl::StatusOr<unsigned> v = tessera::optix7::PropertyValue(property);
    if (!v.ok()) return v.status();
    if (sizeInBytes != sizeof(unsigned int)) {
      return OptixError(OPTIX_ERROR_INVALID_VALUE,
                        absl::StrCat("sizeInBytes is ", sizeInBytes,
                                     "; every OptixDeviceProperty is an unsigned int (4 bytes)"));
    }
    *static_cast<unsigned int*>(value) = *v;
    return absl::OkStatus();
  });
}

OptixResult optixDeviceContextSetLogCallback(OptixDeviceContext context,
                                             OptixLogCallback callbackFunction, void* callbackData,
                                             unsigned int callbackLevel) {
  return Call("optixDeviceContextSetLogCallback").Run([&](Call& call) -> absl::Status {
    std::shared_ptr<DeviceContext> c;
    if (absl::Status s = call.Lookup(context, "context", &c); !s.ok()) return s;
    if (callbackLevel > 4) {
      return OptixError(
          OPTIX_ERROR_INVALID_VALUE,
          absl::StrCat("callbackLevel is ", callbackLevel, "; OptiX allows 0 (off) to 4 (print)"));
    }
    c->SetLogCallback(callbackFunction, callbackData, callbackLevel);
    return absl::OkStatus();
  });
}

OptixResult optixDeviceContextSetCacheEnabled(OptixDeviceContext context, int enabled) {
  return Call("optixDeviceContextSetCacheEnabled").Run([&](Call& call) -> absl::Status {
    std::shared_ptr<DeviceContext> c;
    if (absl::Status s = call.Lookup(context, "context", &c); !s.ok()) return s;
    if (enabled != 0 && enabled != 1) {
      return OptixError(OPTIX_ERROR_INVALID_VALUE,
                        absl::StrCat("enabled is ", enabled, "; OptiX takes 0 or 1"));
    }
    DeviceContext::Cache cache = c->cache();
    if (enabled == 1) {
      if (absl::Status s = tessera::optix7::CheckCacheLocation(cache.location); !s.ok()) return s;
    } else {
      call.Log(tessera::optix7::kLogPrint,
               "the disk cache stays in use: program modules are files that devices load; "
               "disabling it is remembered only");
    }
    cache.enabled = enabled == 1;
    c->set_cache(cache);
    return absl::OkStatus();
  });
}

OptixResult optixDeviceContextSetCacheLocation(OptixDeviceContext context, const char* location) {
  return Call("optixDeviceContextSetCacheLocation").Run([&](Call& call) -> absl::Status {
    std::shared_ptr<DeviceContext> c;
    if (absl::Status s = call.Lookup(context, "context", &c); !s.ok()) return s;
    if (absl::Status s = call.NotNull(location, "location"); !s.ok()) return s;
    DeviceContext::Cache cache = c->cache();
    if (absl::Status s = tessera::optix7::CheckCacheLocation(location); !s.ok()) {
      cache.enabled = false;  // as OptiX: an unusable location disables the cache
      c->set_cache(cache);
      return s;
    }
    cache.location = location;
    cache.location_chosen = true;
    c->set_cache(cache);
    return absl::OkStatus();
  });
}

OptixResult optixDeviceContextSetCacheDatabaseSizes(OptixDeviceContext context, size_t lowWaterMark,
                                                    size_t highWaterMark) {
  return Call("optixDeviceContextSetCacheDatabaseSizes").Run([&](Call& call) -> absl::Status {
    std::shared_ptr<DeviceContext> c;
    if (absl::Status s = call.Lookup(context, "context", &c); !s.ok()) return s;
    if (lowWaterMark != 0 && highWaterMark != 0 && highWaterMark < lowWaterMark) {
      return OptixError(
          OPTIX_ERROR_INVALID_VALUE,
          absl::StrCat("highWaterMark ", highWaterMark, " is below lowWaterMark ", lowWaterMark));
    }
    // Remembered and reported back; the module cache is trimmed to its own bound
    // (TESSERA_MODULE_CACHE_MAX_BYTES, docs/programs.md).
    DeviceContext::Cache cache = c->cache();
    cache.low_water_mark = lowWaterMark;
    cache.high_water_mark = highWaterMark;
    c->set_cache(cache);
    return absl::OkStatus();
  });
}

OptixResult optixDeviceContextGetCacheEnabled(OptixDeviceContext context, int* enabled) {
  return Call("optixDeviceContextGetCacheEnabled").Run([&](Call& call) -> absl::Status {
    std::shared_ptr<DeviceContext> c;
    if (absl::Status s = call.Lookup(context, "context", &c); !s.ok()) return s;
    if (absl::Status s = call.NotNull(enabled, "enabled"); !s.ok()) return s;
    *enabled = c->cache().enabled ? 1 : 0;
    return absl::OkStatus();
  });
}

OptixResult optixDeviceContextGetCacheLocation(OptixDeviceContext context, char* location,
                                               size_t locationSize) {
  return Call("optixDeviceContextGetCacheLocation").Run([&](Call& call) -> absl::Status {
    std::shared_ptr<DeviceContext> c;
    if (absl::Status s = call.Lookup(context, "context", &c); !s.ok()) return s;
    if (absl::Status s = call.NotNull(location, "location"); !s.ok()) return s;
    const std::string path = c->cache().location;
    if (locationSize < path.size() + 1) {
      return OptixError(OPTIX_ERROR_INVALID_VALUE,
                        absl::StrCat("locationSize is ", locationSize, "; the location needs ",
                                     path.size() + 1, " bytes"));
    }
    path.copy(location, path.size());
    location[path.size()] = '\0';
    return absl::OkStatus();
  });
}

OptixResult optixDeviceContextGetCacheDatabaseSizes(OptixDeviceContext context,
                                                    size_t* lowWaterMark, size_t* highWaterMark) {
  return Call("optixDeviceContextGetCacheDatabaseSizes").Run([&](Call& call) -> absl::Status {
    std::shared_ptr<DeviceContext> c;
    if (absl::Status s = call.Lookup(context, "context", &c); !s.ok()) return s;
    if (absl::Status s = call.NotNull(lowWaterMark, "lowWaterMark"); !s.ok()) return s;
    if (absl::Status s = call.NotNull(highWaterMark, "highWaterMark"); !s.ok()) return s;
    const DeviceContext::Cache cache = c->cache();
    *lowWaterMark = cache.low_water_mark;
    *highWaterMark = cache.high_water_mark;
    return absl::OkStatus();
  });
}

}  // extern "C"

extern "C" __attribute__((visibility("default"))) OptixResult
tesseraOptixDeviceContextGetTransferStats(OptixDeviceContext context,
                                          unsigned long long* bytes_sent,
                                          unsigned long long* bytes_received) {
  using tessera::optix7::Call;
  using tessera::optix7::DeviceContext;
  return Call(__func__).Run([&](Call& call) -> absl::Status {
    std::shared_ptr<DeviceContext> c;
    if (absl::Status s = call.Lookup(context, "context", &c); !s.ok()) return s;
    if (absl::Status s = call.NotNull(bytes_sent, "bytes_sent"); !s.ok()) return s;
    if (absl::Status s = call.NotNull(bytes_received, "bytes_received"); !s.ok()) return s;
    uint64_t sent = 0, received = 0;
    c->TransferStats(&sent, &received);
    *bytes_sent = sent;
    *bytes_received = received;
    return absl::OkStatus();
  });
}

extern "C" __attribute__((visibility("default"))) OptixResult tesseraOptixDeviceContextSetAccuracy(
    OptixDeviceContext context, unsigned int flags) {
  using tessera::optix7::Call;
  using tessera::optix7::DeviceContext;
  return Call(__func__).Run([&](Call& call) -> absl::Status {
    std::shared_ptr<DeviceContext> c;
    if (absl::Status s = call.Lookup(context, "context", &c); !s.ok()) return s;
    if (!tessera::api::KnownAccuracy(flags)) {
      return OptixError(OPTIX_ERROR_INVALID_VALUE,
                        absl::StrCat("flags 0x", absl::Hex(flags),
                                     " hold bits no TESSERA_ACCURACY_* flag has (known: 0x1F)"));
    }
    c->set_accuracy_flags(flags);
    return absl::OkStatus();
  });
}

extern "C" __attribute__((visibility("default"))) OptixResult tesseraOptixDeviceContextGetAccuracy(
    OptixDeviceContext context, unsigned int* flags) {
  using tessera::optix7::Call;
  using tessera::optix7::DeviceContext;
  return Call(__func__).Run([&](Call& call) -> absl::Status {
    std::shared_ptr<DeviceContext> c;
    if (absl::Status s = call.Lookup(context, "context", &c); !s.ok()) return s;
    if (absl::Status s = call.NotNull(flags, "flags"); !s.ok()) return s;
    *flags = c->accuracy_flags();
    return absl::OkStatus();
  });
}
