/* CUDA's atomic functions in OptiX 7 programs: atomicAdd (int, unsigned, unsigned long long,
 * float, double), atomicSub, atomicExch, atomicMin/Max, atomicInc/Dec, atomicCAS (int, unsigned,
 * unsigned long long, unsigned short), atomicAnd/Or/Xor and their _block and _system forms, with
 * CUDA's results (tessera/detail/cuda_atomics.h, shared with the OptiX 3 root). nvcc includes
 * CUDA's header of this name in every .cu file; here optix_device.h and cuda_runtime.h include it
 * in programs (__CUDACC__).
 *
 * Across devices (docs/device_memory.md, "Atomics across devices"): a device that holds a copy of
 * device memory notes every atomic (TesseraOptix7Runtime::note_atomic) and sends the host one
 * combined operation per address, which the host applies to its copy: sums, minima, maxima,
 * and/or/xor and atomicInc/Dec end as on one GPU whatever the device count. The values atomics
 * return are unique only within a device. */
#ifndef TESSERA_OPTIX7_DEVICE_ATOMIC_FUNCTIONS_H_
#define TESSERA_OPTIX7_DEVICE_ATOMIC_FUNCTIONS_H_

#if defined(__cplusplus) && defined(__CUDACC__)

#include "tessera/optix7_module.h"

namespace tessera_optix7 {
/* One flag test when nothing is noted (an in-process device, or the only device): the table and
 * the flag stay in cache, and the branch is always predicted. */
inline void NoteAtomic(void* address, unsigned int op, unsigned long long operand,
                       unsigned int limit) {
  const TesseraOptix7Runtime* runtime = tessera_optix7_runtime;
  if (__builtin_expect(*runtime->atomics_noted != 0, 0)) {
    runtime->note_atomic(address, op, operand, limit);
  }
}
}  // namespace tessera_optix7

#define TESSERA_CUDA_ATOMIC_NOTE(address, op, operand, limit) \
  tessera_optix7::NoteAtomic((void*)(address), op, operand, limit)

#include "tessera/detail/cuda_atomics.h"

#endif /* __cplusplus && __CUDACC__ */

#endif /* TESSERA_OPTIX7_DEVICE_ATOMIC_FUNCTIONS_H_ */
