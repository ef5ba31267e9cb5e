// Stopping a launch index whose program never returns (an endless loop), when its launch is
// cancelled or has failed elsewhere. Tiles check for a cancel between launch indices; a program
// that never returns never gets there, so the thread gets a signal instead. Landing in program
// code, the handler jumps back to the tile (RunTile's sigsetjmp); landing elsewhere (the engine,
// Embree, libm), it leaves a request that the program's next engine call takes (InterruptPoint),
// or waits for the next signal.
// docs/devices.md "Faults" says what a user sees.
#ifndef TESSERA_WORKER_CORE_INTERRUPT_H_
#define TESSERA_WORKER_CORE_INTERRUPT_H_

#include <setjmp.h>

#include <atomic>
#include <cstddef>

namespace tessera::worker {

// Notes the executable segments of a program module just loaded with dlopen: the code a thread
// may be jumped out of.
void RegisterModuleCode(void* handle);

// Set by the handler when the signal found the thread outside program code; the entry of every
// engine call a program makes, where the engine's state is whole, takes it (InterruptPoint).
// volatile: written by the signal handler on the same thread.
extern __thread volatile bool t_interrupt_requested __attribute__((tls_model("initial-exec")));

// While armed, the calling thread runs a tile that `cancel` or `stop` may end. A thread still
// in the tile kGrace after either became true gets signals (interrupt.cc) until it leaves.
// Construct before the sigsetjmp that `Arm` names and keep it in that frame: its destructor
// disarms on every way out of the tile; after a jump back, call Jumped.
class InterruptibleTile {
 public:
  InterruptibleTile(const std::atomic<bool>& cancel, const std::atomic<bool>& stop);
  ~InterruptibleTile();
  InterruptibleTile(const InterruptibleTile&) = delete;
  InterruptibleTile& operator=(const InterruptibleTile&) = delete;

  void Arm(sigjmp_buf* jump);
  void Disarm();
  // After a jump back to the sigsetjmp: disarms, and forgets the C++ exceptions the abandoned
  // program was handling (a catch block it never left would stay active on the thread).
  void Jumped();

 private:
  volatile bool armed_ = false;  // volatile: read again after a jump back to the sigsetjmp
  // The thread's C++ exception state when armed (Itanium C++ ABI __cxa_eh_globals).
  void* caught_exceptions_ = nullptr;
  unsigned uncaught_exceptions_ = 0;
};

// Jumps to the armed tile's sigsetjmp when its launch is ending; returns otherwise (a request
// left by a signal that came as the tile ended).
void TakeInterruptRequest();

#if defined(__SANITIZE_ADDRESS__)
// A lane's side of each stack switch (lanes.h) says which thread stack it came from, the thread's
// side that it is back; a jump out of the tile from a lane's stack then tells AddressSanitizer
// that it lands on the thread's stack, and the frames it skipped there lose their redzones.
void EnteredLane(const void* thread_stack_bottom, size_t thread_stack_size);
void LeftLane();
#endif

// At the entry of every engine call a program makes (the runtime table), where the engine's state
// is whole: a program looping on engine calls (rtTrace, rtPrintf) spends its time there, and an
// interrupt landing there leaves a request.
inline void InterruptPoint() {
  if (__builtin_expect(t_interrupt_requested, 0)) TakeInterruptRequest();
}

// The signal interrupts use (TESSERA_INTERRUPT_SIGNAL, else SIGRTMIN+6; 0: none). The first call
// in a process says on stderr when the variable holds something unusable; the host calls it
// before starting workers, so that the message reaches the user, not only a worker's log.
int InterruptSignal();

}  // namespace tessera::worker

#endif  // TESSERA_WORKER_CORE_INTERRUPT_H_
