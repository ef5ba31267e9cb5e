#include "context.h"

#include <pthread.h>
#include <unistd.h>

#include <atomic>
#include <random>

#include "absl/strings/str_cat.h"
#include "accuracy_flags.h"
#include "program.h"
#include "status.h"
#include "system_info.h"

namespace tessera::api {
namespace {

uint64_t RandomSessionId() {
  std::random_device rd;
  uint64_t id = (static_cast<uint64_t>(rd()) << 32) ^ rd();
  return id == 0 ? 1 : id;
}

// getpid() kept current across fork() without a system call per API call.
std::atomic<long> g_pid{0};

void RefreshPid() { g_pid.store(static_cast<long>(getpid()), std::memory_order_relaxed); }

long CurrentPid() {
  static const bool kRegistered = [] {
    RefreshPid();
    pthread_atfork(nullptr, nullptr, &RefreshPid);
    return true;
  }();
  (void)kRegistered;
  return g_pid.load(std::memory_order_relaxed);
}

}  // namespace

bool Context::InForkedChild() const { return creator_pid_ != CurrentPid(); }

Context::Context()
    : Object(Kind::kContext, this, 0),
      variables_(this),
      ray_generation_(this),
      exception_(this),
      miss_(this),
      // OptiX default: only stack overflow is enabled (bit for 0x3FC).
      exception_mask_(1u << (RT_EXCEPTION_STACK_OVERFLOW - RT_EXCEPTION_PROGRAM_ID_INVALID)),
      num_threads_(HardwareThreads()),
      accuracy_flags_(AccuracyFromEnvironment()),
      session_id_(RandomSessionId()) {
  creator_pid_ = CurrentPid();
  Touch();
}

absl::StatusOr<Context*> Context::Create() {
  auto devices = DevicesFromEnvironment();
  if (!devices.ok()) return devices.status();
  for (const DeviceDesc& d : *devices) TS_RETURN_IF_ERROR(CheckInstantiable(d));
  auto* context = new Context;
  context->device_list_ = *std::move(devices);
  for (size_t i = 0; i < context->device_list_.size(); ++i) {
    context->selected_.push_back(static_cast<int>(i));
  }
  context->ResetDeviceSlots();
  HandleRegistry::Get().Add(context);
  return context;
}

void Context::DestroyAll() {
  // Devices go first: they may still be running nothing, but hold no host pointers anyway.
  slots_.clear();
  for (auto& [id, object] : objects_) object->Destroy();
  Destroy();  // drops the context's own links and variables
  absl::flat_hash_map<uint64_t, Object*> objects;
  objects.swap(objects_);
  for (auto& [id, object] : objects) object->Release();
  HandleRegistry::Get().ForgetContext(this);
  Release();
}

void Context::DropLinks() {
  variables_.Clear();
  ray_generation_.Resize(0);
  exception_.Resize(0);
  miss_.Resize(0);
}

void Context::DestroyObject(Object* object) {
  objects_.erase(object->id());
  object->Destroy();
  object->Release();
  Touch();
}

Object* Context::FindById(uint64_t id) const {
  auto it = objects_.find(id);
  return it == objects_.end() ? nullptr : it->second;
}

void Context::SetEntryPointCount(unsigned count) {
  ray_generation_.Resize(count);
  exception_.Resize(count);
  Touch();
}

void Context::SetRayTypeCount(unsigned count) {
  if (count == ray_type_count()) return;
  miss_.Resize(count);
  Touch();
  // A material is lowered with one program per ray type of the context: a new count changes
  // every material's lowering, so each travels again.
  for (const auto& [id, object] : objects_) {
    if (object->kind() == Kind::kMaterial) object->Touch();
  }
}

void Context::SetRayGeneration(unsigned entry, Program* program) {
  ray_generation_.Set(entry, program);
  Touch();
}

void Context::SetExceptionProgram(unsigned entry, Program* program) {
  exception_.Set(entry, program);
  Touch();
}

void Context::SetMiss(unsigned ray_type, Program* program) {
  miss_.Set(ray_type, program);
  Touch();
}

void Context::SetStackSize(uint64_t bytes) {
  stack_size_ = bytes;
  Touch();
}

void Context::SetPrintEnabled(bool enabled) {
  print_enabled_ = enabled;
  Touch();
}

void Context::SetPrintBufferSize(uint64_t bytes) {
  print_buffer_size_ = bytes;
  Touch();
}

void Context::SetPrintLaunchIndex(int x, int y, int z) {
  print_launch_index_ = {x, y, z};
  Touch();
}

void Context::SetTimeoutCallback(RTtimeoutcallback callback, double min_polling_seconds) {
  timeout_callback_ = callback;
  timeout_polling_seconds_ = min_polling_seconds;
}

void Context::VisitEdges(EdgeVisitor visit) const {
  for (size_t i = 0; i < ray_generation_.size(); ++i) {
    if (Object* p = ray_generation_.Get(i)) {
      visit(p, EdgeRole{"ray generation program for entry point", static_cast<int64_t>(i)});
    }
  }
  for (size_t i = 0; i < exception_.size(); ++i) {
    if (Object* p = exception_.Get(i)) {
      visit(p, EdgeRole{"exception program for entry point", static_cast<int64_t>(i)});
    }
  }
  for (size_t i = 0; i < miss_.size(); ++i) {
    if (Object* p = miss_.Get(i)) {
      visit(p, EdgeRole{"miss program for ray type", static_cast<int64_t>(i)});
    }
  }
  variables_.VisitEdges(visit);
  for (uint64_t id : program_ids_) {
    // Destroyed programs are gone from the table; ids are never reused.
    if (Object* p = FindById(id)) visit(p, EdgeRole{"program with an id (rtProgramGetId)", -1});
  }
}

void Context::RecordError(RTresult code, std::string message, uint64_t sequence) {
  std::lock_guard<std::mutex> lock(error_mu_);
  last_errors_[code] = RecordedError{sequence, std::move(message)};
}

const char* Context::LastErrorFor(RTresult code, uint64_t* sequence) const {
  std::lock_guard<std::mutex> lock(error_mu_);
  auto it = last_errors_.find(code);
  if (it == last_errors_.end() || it->second.message.empty()) return nullptr;
  *sequence = it->second.sequence;
  return it->second.message.c_str();
}

}  // namespace tessera::api
