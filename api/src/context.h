// The context: global state (entry points, ray types, programs per entry point and ray type,
// stack size, printing, exceptions, attributes), the table of objects it owns, the devices it
// launches on, and the last error message rtContextGetErrorString returns.
#ifndef TESSERA_API_SRC_CONTEXT_H_
#define TESSERA_API_SRC_CONTEXT_H_

#include <array>
#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "absl/base/thread_annotations.h"
#include "absl/container/flat_hash_map.h"
#include "absl/container/flat_hash_set.h"
#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "auto_batching.h"
#include "device_sync.h"
#include "handle_registry.h"
#include "object.h"
#include "tessera/v1/launch.pb.h"
#include "variable_scope.h"

namespace tessera::api {

class ContextExtension;
class Program;

class Context : public Object {
 public:
  static constexpr Kind kKind = Kind::kContext;

  // Uses the devices TESSERA_DEVICES names (default "inproc"); fails with RT_ERROR_NOT_SUPPORTED
  // for worker devices this release cannot create.
  static absl::StatusOr<Context*> Create();
  // rtContextDestroy: destroys every object, then the context.
  void DestroyAll();

  uint64_t NextVersion() { return ++version_clock_; }
  // Moves with every change but those of variables' bytes alone (Object::TouchValue): a launch
  // whose clock a validation or a walk of the graph saw before need not do it again.
  uint64_t structure_clock() const { return structure_clock_; }
  void StructureChanged() { ++structure_clock_; }
  // The objects reachable from the context (validate.h CollectReachable) as of structure_clock.
  const std::vector<Object*>& Reachable();
  // ValidateContext, unless it passed at the current structure_clock already and no buffer is
  // mapped.
  absl::Status ValidateOnce();

  // The process that created the context, and whether this is another one (a child forked
  // without exec, which inherits the context but not its devices' threads and connections).
  long creator_pid() const { return creator_pid_; }
  bool InForkedChild() const;

  // Creates an object owned by this context and registers its handle.
  template <typename T, typename... Args>
  T* Make(Args&&... args) {
    T* object = new T(this, ++last_id_, std::forward<Args>(args)...);
    objects_[object->id()] = object;
    HandleRegistry::Get().Add(object);
    return object;
  }
  void DestroyObject(Object* object);
  // A live object of this context, or null.
  Object* FindById(uint64_t id) const;
  const absl::flat_hash_map<uint64_t, Object*>& objects() const { return objects_; }
  // rtProgramGetId gave out program `id`: the program is an edge of the context from now on
  // (VisitEdges), so it reaches the devices while it lives whether or not a variable names it.
  void NoteProgramIdTaken(uint64_t id) { program_ids_.push_back(id); }
  // Accelerations whose rtAccelerationSetData data a launch has yet to check against their graph
  // (CheckRestoredAccelerations): launches look at these alone, not at every object.
  absl::flat_hash_set<uint64_t>& pending_restores() { return pending_restores_; }

  // ---- Entry points, ray types and their programs.
  unsigned entry_point_count() const { return static_cast<unsigned>(ray_generation_.size()); }
  void SetEntryPointCount(unsigned count);
  unsigned ray_type_count() const { return static_cast<unsigned>(miss_.size()); }
  void SetRayTypeCount(unsigned count);
  // Indices are checked by the caller.
  Object* ray_generation(unsigned entry) const { return ray_generation_.Get(entry); }
  Object* exception_program(unsigned entry) const { return exception_.Get(entry); }
  Object* miss(unsigned ray_type) const { return miss_.Get(ray_type); }
  void SetRayGeneration(unsigned entry, Program* program);
  void SetExceptionProgram(unsigned entry, Program* program);
  void SetMiss(unsigned ray_type, Program* program);

  // ---- Global settings.
  uint64_t stack_size() const { return stack_size_; }
  void SetStackSize(uint64_t bytes);
  bool print_enabled() const { return print_enabled_; }
  void SetPrintEnabled(bool enabled);
  uint64_t print_buffer_size() const { return print_buffer_size_; }
  void SetPrintBufferSize(uint64_t bytes);
  const std::array<int, 3>& print_launch_index() const { return print_launch_index_; }
  void SetPrintLaunchIndex(int x, int y, int z);
  absl::Status SetExceptionEnabled(int exception, bool enabled);
  absl::StatusOr<bool> ExceptionEnabled(int exception) const;
  // Bit i: exception code 0x3EE + i (ContextState.exception_mask).
  uint32_t exception_mask() const { return exception_mask_; }
  bool user_exceptions() const { return user_exceptions_; }
  int num_threads() const { return num_threads_; }
  // Whether the application set CPU_NUM_THREADS. Only then does the count travel to devices, so
  // that worker processes otherwise keep the share of the cores they were started with.
  bool num_threads_set() const { return num_threads_set_; }
  // TESSERA_ACCURACY_* bits: tesseraContextSetAccuracy, initially TESSERA_ACCURACY.
  uint32_t accuracy_flags() const { return accuracy_flags_; }
  absl::Status SetAccuracy(uint32_t flags);

  absl::Status SetAttribute(RTcontextattribute attribute, RTsize size, const void* value);
  absl::Status GetAttribute(RTcontextattribute attribute, RTsize size, void* value) const;

  void SetTimeoutCallback(RTtimeoutcallback callback, double min_polling_seconds);
  RTtimeoutcallback timeout_callback() const { return timeout_callback_; }
  double timeout_polling_seconds() const { return timeout_polling_seconds_; }
  bool running() const { return running_.load(); }
  // Claims the context for a launch or its destruction: false while one is under way, also one
  // that another thread began at the same moment (a context is used by one thread at a time, as in
  // OptiX, but a second thread must get an error, not a second launch over the first one's state).
  bool TryStartRunning() {
    bool idle = false;
    return running_.compare_exchange_strong(idle, true);
  }

  // ---- Devices. Ordinals index the context's device list (TESSERA_DEVICES unless
  // tesseraContextSetDeviceSpec replaced it).
  const std::vector<DeviceDesc>& device_list() const { return device_list_; }
  const std::vector<int>& selected_devices() const { return selected_; }
  absl::Status SetDevices(const std::vector<int>& ordinals);
  absl::Status SetDeviceSpec(const std::string& spec);
  // Lowering and launch state per selected device.
  std::vector<DeviceSlot>& device_slots() { return slots_; }
  // Replaces the devices with the given ones (tests drive the launch path with fakes).
  void UseDevicesForTesting(std::vector<std::unique_ptr<Device>> devices);
  // Creates the selected devices that do not exist yet, including lost ones again (a respawned
  // local worker), and takes running workers (HOST:PORT, unix:PATH) that answered in the
  // background since (DeviceJoiner). A device that cannot be created is left out of the launch
  // with one warning until it is back; a running worker that does not answer is then tried again
  // in the background, never by a launch. With no device left, the running workers get one more
  // try each (within the connection timeout) before it fails: UNAVAILABLE
  // (RT_ERROR_CONNECTION_FAILED) naming every device, or the only device's own reason and code.
  absl::Status EnsureDevices();
  // Forgets a device that was lost during a launch (killed, hung, crashed): the next launch
  // creates it again (a running worker: once it answers in the background) and sends it the
  // whole state under a new session.
  void LoseDevice(DeviceSlot& slot);
  // The tile size launches use: empty = automatic.
  absl::Status SetTileSize(std::vector<uint64_t> size);
  const std::vector<uint64_t>& tile_size() const { return tile_size_; }
  // The launch size and tile size of the last launch with stable ownership on the current device
  // set: a later launch of that size in other tiles moves launch indices to other devices.
  struct StableLayout {
    std::vector<uint64_t> dims, tile;
  };
  StableLayout& last_stable_layout() { return last_stable_layout_; }
  // Buffer bytes shipped to devices and gathered from them (tesseraContextGetTransferStats).
  uint64_t bytes_sent() const { return bytes_sent_; }
  uint64_t bytes_received() const { return bytes_received_; }
  void CountSent(uint64_t bytes) { bytes_sent_ += bytes; }
  // Race checking: tesseraContextSetRaceCheck, or TESSERA_RACE_CHECK=1 in the environment.
  bool race_check() const;
  void set_race_check(bool enabled) { race_check_ = enabled; }
  uint64_t last_race_count() const { return last_race_count_; }
  void set_last_race_count(uint64_t count) { last_race_count_ = count; }
  void CountReceived(uint64_t bytes) { bytes_received_ += bytes; }
  // Tiles of the running (or last) launch finished and in all (tesseraContextGetLaunchProgress);
  // atomic: another thread may ask while the launching thread counts.
  void StartProgress(uint64_t total) {
    tiles_done_.store(0, std::memory_order_relaxed);
    tiles_total_.store(total, std::memory_order_relaxed);
  }
  // What the launch's dispatcher counts finished tiles in.
  std::atomic<uint64_t>* progress_counter() { return &tiles_done_; }
  uint64_t tiles_done() const { return tiles_done_.load(std::memory_order_relaxed); }
  uint64_t tiles_total() const { return tiles_total_.load(std::memory_order_relaxed); }

  // ---- Launch (launch.cc).
  // `optix7`: an optixLaunch (api/optix7/launch7.cc) instead of an OptiX 3 entry point, which is
  // then unused.
  absl::Status Launch(unsigned entry_point, const std::vector<uint64_t>& dims,
                      const v1::Optix7Launch* optix7 = nullptr);
  // State that ships beside the object graph (context_extension.h); not owned. Null: none.
  ContextExtension* extension() const { return extension_; }
  void set_extension(ContextExtension* extension) { extension_ = extension; }
  // What the last launch of `entry_point` that finished cost, with its launch and tile sizes:
  // nanoseconds of one device thread per launch index (its devices' time over its launch
  // indices), which sizes the calls of the next launch of that size (the dispatcher's
  // min_indices_per_thread), and each tile's cost, by which the next launch of the same tiles
  // cuts its batches.
  struct TileCosts {
    std::vector<uint64_t> dims, tile_size;
    double ns_per_index = 0;
    std::vector<float> costs;
  };
  TileCosts& tile_costs(unsigned entry_point) {
    if (entry_point >= tile_costs_.size()) tile_costs_.resize(entry_point + 1);
    return tile_costs_[entry_point];
  }
  // Which entry points' OptiX 3 launches trace their first rays as packets (auto_batching.h).
  AutoBatching& auto_batching() { return auto_batching_; }
  uint64_t NextLaunchId() { return ++last_launch_id_; }
  void set_running(bool running) { running_.store(running); }
  // Whether the last launch traced its first rays as packets (tesseraContextGetLastLaunchBatched).
  bool last_launch_batched() const { return last_launch_batched_; }
  void set_last_launch_batched(bool batched) { last_launch_batched_ = batched; }
  // Exceptions of the last launch that reached no exception program.
  uint64_t last_exception_count() const { return last_exception_count_; }
  void set_last_exception_count(uint64_t count) { last_exception_count_ = count; }

  // ---- Errors.
  // `sequence` orders errors across contexts and threads (see ErrorSequence in boundary.h).
  void RecordError(RTresult code, std::string message, uint64_t sequence);
  // The last message, if it was recorded with `code` (else null), and its sequence number.
  const char* LastErrorFor(RTresult code, uint64_t* sequence) const;

  VariableScope* scope() override { return &variables_; }
  const VariableScope& variables() const { return variables_; }
  void VisitEdges(EdgeVisitor visit) const override;

 private:
  Context();
  void DropLinks() override;
  void ResetDeviceSlots();
  // Tries to reach the running worker of `slot` in the background until it answers (the first
  // try at once, or after the backoff's first wait when the caller just tried).
  void StartJoining(DeviceSlot& slot, bool try_at_once);

  uint64_t version_clock_ = 0;
  uint64_t structure_clock_ = 1;
  uint64_t reachable_clock_ = 0, validated_clock_ = 0;  // 0: never
  std::vector<Object*> reachable_;
  uint64_t last_id_ = 0;
  uint64_t last_launch_id_ = 0;
  absl::flat_hash_map<uint64_t, Object*> objects_;  // each holds the creation reference
  std::vector<uint64_t> program_ids_;  // of programs rtProgramGetId gave out, in that order
  absl::flat_hash_set<uint64_t> pending_restores_;

  VariableScope variables_;
  Links ray_generation_;  // per entry point
  Links exception_;       // per entry point
  Links miss_;            // per ray type

  uint64_t stack_size_ = 1024;
  bool print_enabled_ = false;
  uint64_t print_buffer_size_ = 65536;
  std::array<int, 3> print_launch_index_ = {-1, -1, -1};
  uint32_t exception_mask_;
  bool user_exceptions_ = false;
  int num_threads_;
  bool num_threads_set_ = false;
  uint32_t accuracy_flags_;

  RTtimeoutcallback timeout_callback_ = nullptr;
  double timeout_polling_seconds_ = 0.0;
  std::atomic<bool> running_{false};

  std::vector<DeviceDesc> device_list_;
  std::vector<int> selected_;
  std::vector<DeviceSlot> slots_;
  bool injected_devices_ = false;
  uint64_t session_id_;
  uint64_t sessions_ = 0;  // sessions opened after session_id_ (ids session_id_ + n)
  std::vector<uint64_t> tile_size_;
  StableLayout last_stable_layout_;
  uint64_t bytes_sent_ = 0;
  bool race_check_ = false;
  uint64_t last_race_count_ = 0;
  uint64_t bytes_received_ = 0;
  std::vector<TileCosts> tile_costs_;  // by entry point
  AutoBatching auto_batching_;
  std::atomic<uint64_t> tiles_done_{0}, tiles_total_{0};
  uint64_t last_exception_count_ = 0;
  bool last_launch_batched_ = false;
  ContextExtension* extension_ = nullptr;

  mutable std::mutex error_mu_;
  // The newest message of each code (rtContextGetErrorString asks by code): a later error of
  // another code, say a call on a destroyed handle, must not erase a launch's message.
  struct RecordedError {
    uint64_t sequence = 0;
    std::string message;
  };
  // Node-based: a message handed out stays where it is while other codes are recorded.
  std::map<RTresult, RecordedError> last_errors_ ABSL_GUARDED_BY(error_mu_);
  long creator_pid_ = 0;
};

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_CONTEXT_H_
