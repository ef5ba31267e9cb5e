/* The C ABI between a program module (a shared library built from OptiX-style C++) and the
 * engine that loads it. The module describes its variables and buffers (TesseraModuleInfo);
 * the engine hands it a function table (TesseraRuntime) for everything a program asks of the
 * ray tracer. Both sides check abi_version. */
#ifndef TESSERA_DETAIL_MODULE_ABI_H_
#define TESSERA_DETAIL_MODULE_ABI_H_

#include <stddef.h>

#include "tessera/detail/texture_view.h"

#ifdef __cplusplus
extern "C" {
#endif

#define TESSERA_MODULE_ABI_VERSION 12u

/* One rtDeclareVariable. `semantic` and `annotation` are the macro arguments as written
 * ("rtLaunchIndex", "attribute normal_vec", ""). `address` returns the calling thread's slot. */
typedef struct {
  const char* name;
  const char* semantic;
  const char* annotation;
  const char* type_name;
  size_t size;
  void* (*address)(void);
} TesseraVariableDecl;

/* One rtBuffer object. The engine learns its name from the module's dynamic symbol table. */
typedef struct {
  const void* object;
  size_t element_size;
  unsigned dimensionality;
} TesseraBufferDecl;

/* What a program sees of a buffer bound to one of its rtBuffer declarations. The engine keeps one
 * table of views per bound program; a thread-local pointer of the engine names the running
 * program's table (TesseraRuntime::buffer_table_offset). */
typedef struct {
  void* data;
  size_t size[3]; /* unused dimensions are 1 */
  size_t element_size;
  unsigned long long id;
  /* One byte per element: the write epoch (below) in which a program last indexed the element,
   * raised but never lowered while a device call runs; null for buffers that never travel back
   * to the host (INPUT, GPU_LOCAL). The engine ships exactly the marked elements, so devices
   * never overwrite each other's results with stale copies. */
  unsigned char* written;
  /* One byte per block of 2^TESSERA_WRITTEN_BLOCK_SHIFT elements, marked with `written`: the
   * engine scans only the blocks programs touched, not the whole buffer. */
  unsigned char* written_blocks;
  /* The device's current write epoch (1, 2, ...), read atomically at every marking access. The
   * engine raises it while programs run and sends the elements of a closed epoch (one no running
   * program can mark any more) while later ones trace. */
  const unsigned char* write_epoch;
} TesseraBufferView;

#define TESSERA_WRITTEN_BLOCK_SHIFT 12

/* A write epoch no device call reaches (they count from 1 to at most 8): views of the buffers a
 * program may write carry it while the engine runs a launch index's ray generation program only
 * up to its first rtTrace, to trace that ray in a packet with its block's (docs/programs.md,
 * "Batched tracing"). An access then goes to buffer_index_error, which ends that run. (Version
 * 12.) */
#define TESSERA_COLLECTING_EPOCH 0xFFu

/* One rtTextureSampler object (version 8), named like rtBuffer objects. `dimensionality` is the
 * declaration's Dim: 1, 2, 3 or a CUDA layered / cube map texture type (tessera/detail/texture.h);
 * `read_mode` its cudaTextureReadMode. */
typedef struct {
  const void* object;
  size_t element_size;
  unsigned dimensionality;
  unsigned read_mode;
} TesseraTextureDecl;
/* The buffers programs reach by id (rtBufferId, version 8): entries[id] for id < count; an entry
 * with a null view is no buffer. `dimensionality` 0: an unsized buffer, which fits any. */
typedef struct {
  const TesseraBufferView* view;
  unsigned dimensionality;
} TesseraBufferIdEntry;
typedef struct {
  unsigned long long count;
  const TesseraBufferIdEntry* entries;
} TesseraBufferIdTable;

/* The samplers programs reach by id (rtTex*, version 9): views[id] for id < count; a null entry
 * is no sampler a program can read. */
typedef struct {
  unsigned long long count;
  const TesseraTextureView* const* views;
} TesseraTextureIdTable;

typedef struct {
  unsigned abi_version;
  unsigned variable_count;
  const TesseraVariableDecl* variables;
  unsigned buffer_count;
  const TesseraBufferDecl* buffers;
  /* Version 8. */
  unsigned texture_count;
  const TesseraTextureDecl* textures;
  /* Version 10: TESSERA_MODULE_FLAG_* bits, how the module was compiled. */
  unsigned flags;
} TesseraModuleInfo;

/* The module was compiled with fast math (tessera/accuracy.h TESSERA_ACCURACY_FAST_MATH): the
 * engine flushes denormals to zero on the threads that run it. */
#define TESSERA_MODULE_FLAG_FAST_MATH 0x1u

/* What the engine keeps on a program's stack while a callable program it called runs: the
 * caller, to make it the running program again, and its module's values if another program of
 * that module may overwrite them (TesseraRuntime::callable_leave). */
typedef struct {
  const void* caller;
  void* caller_module;
  void* suspended;
} TesseraCallFrame;

/* Geometry kinds for TesseraRuntime::transform. */
enum { TESSERA_TRANSFORM_POINT = 0, TESSERA_TRANSFORM_VECTOR = 1, TESSERA_TRANSFORM_NORMAL = 2 };

typedef struct {
  unsigned abi_version;
  /* rtTrace: `ray` points at an optix::Ray; the payload is copied in and out by value. */
  void (*trace)(unsigned long long node, const void* ray, void* payload, size_t payload_size);
  int (*potential_intersection)(float t);
  int (*report_intersection)(unsigned material);
  void (*ignore_intersection)(void);
  void (*terminate_ray)(void);
  void (*throw_exception)(unsigned code);
  unsigned (*exception_code)(void);
  void (*print_exception_details)(void);
  int (*print_active)(void);
  void (*print)(const char* text);
  void (*transform)(unsigned kind, unsigned what, const float* in, float* out);
  void (*get_transform)(unsigned kind, float* matrix16);
  /* An index outside a buffer: raises RT_EXCEPTION_BUFFER_INDEX_OUT_OF_BOUNDS when enabled,
   * otherwise returns zeroed scratch memory so the program cannot corrupt anything. */
  void* (*buffer_index_error)(unsigned slot, unsigned long long x, unsigned long long y,
                              unsigned long long z);
  void (*intersect_child)(unsigned index);
  /* Where the running program's buffer views are: a `const TesseraBufferView*` (indexed by
   * rtBuffer slot) at this offset from the thread pointer. The engine keeps it in static TLS, so
   * the offset is the same on every thread and a module reads it without a call. */
  long long buffer_table_offset;
  /* OptiX 6 (version 5): rtGetPrimitiveIndex; rtIsTriangleHit* (0: not built-in triangles,
   * 1: front face, 2: back face); rtGetTriangleBarycentrics (weights of vertices 1 and 2). */
  unsigned (*primitive_index)(void);
  unsigned (*triangle_hit)(void);
  void (*triangle_barycentrics)(float* uv);
  /* OptiX 3.0 callable programs (version 7). `variable` is the calling thread's slot of an
   * rtCallableProgram variable, which holds the engine's binding of the program it names (null
   * when no scope sets one). callable_enter makes that program the running one, keeping the
   * caller in *frame, and returns the function to call; callable_leave makes the caller run
   * again, also while an exception unwinds the call. */
  void* (*callable_enter)(const void* variable, TesseraCallFrame* frame);
  void (*callable_leave)(TesseraCallFrame* frame);
  /* Texture samplers (version 8). texture_by_id: the view of the sampler rtTextureSamplerGetId
   * gave `id`; any other id raises RT_EXCEPTION_TEXTURE_ID_INVALID (null when that exception is
   * disabled). Views stay valid while the program runs. Programs read views without a call
   * through texture_table_offset and texture_id_table_offset (below). */
  const TesseraTextureView* (*texture_by_id)(int id);
  /* OptiX 3.5+ ids (version 8, tessera/detail/bindless.h). buffer_by_id: the view of the buffer
   * with id `id` (rtBufferGetId) for an rtBufferId of elements of `element_size` bytes and
   * `dimensionality`; an invalid id raises RT_EXCEPTION_BUFFER_ID_INVALID, or when that is
   * disabled gives an empty view, whose every index then reaches buffer_id_index_error. */
  const TesseraBufferView* (*buffer_by_id)(int id, size_t element_size, unsigned dimensionality);
  /* An index outside the buffer of id `id` (or any index of an invalid id's empty view): as
   * buffer_index_error; the scratch memory holds at least `element_size` bytes. */
  void* (*buffer_id_index_error)(int id, size_t element_size, unsigned long long x,
                                 unsigned long long y, unsigned long long z);
  /* A call through an rtCallableProgramId: as callable_enter for the program of id `id`
   * (rtProgramGetId), bound to its own scope and the context's. An invalid id raises
   * RT_EXCEPTION_PROGRAM_ID_INVALID; when that is disabled it returns null (the call is skipped)
   * if `skippable` (the caller can make up a result), else it fails the launch. */
  void* (*callable_id_enter)(int id, int skippable, TesseraCallFrame* frame);
  /* Where the running plan's buffers by id are: a `const TesseraBufferIdTable*` at this offset
   * from the thread pointer (as buffer_table_offset), so that an rtBufferId access whose entry
   * exists and fits its type costs no call; every other access calls buffer_by_id, which says
   * why. The table may be empty (ids too sparse for an array): every access then calls. */
  long long buffer_id_table_offset;
  /* OptiX 6 rtTrace with a visibility mask and RTrayflags (version 8), and the OptiX 5 ray time
   * (version 9: rtCurrentTime of the programs the ray runs; has_time 0 takes the caller's, as
   * `trace` does); `trace` is this with mask 0xFF, no flags and no time. */
  void (*trace_with_flags)(unsigned long long node, const void* ray, void* payload,
                           size_t payload_size, unsigned mask, unsigned flags, int has_time,
                           float time);
  /* Version 9, read as buffer_table_offset: a `const TesseraTextureView*` indexed by
   * rtTextureSampler slot, the running program's views (level_count 0 where no scope binds a
   * sampler), and a `const TesseraTextureIdTable*`, the running plan's samplers by id (never
   * null; empty when ids are too sparse for an array: every rtTex* then calls texture_by_id). */
  long long texture_table_offset;
  long long texture_id_table_offset;
  /* Version 10 (tesseraSpawnPoint): the origin, in world space, for a ray leaving the current hit
   * in world direction `dir`: the hit point moved past its floating-point error bound to the side
   * `dir` points to (tessera/accuracy.h, TESSERA_ACCURACY_OFFSET_RAYS). Closest-hit and any-hit
   * programs. */
  void (*spawn_point)(const float* dir, float* origin);
} TesseraRuntime;

/* Exported by every module (defined weakly by tessera/device.h): stores the runtime table and
 * returns the module's description, or null when the ABI versions differ. */
typedef const TesseraModuleInfo* (*TesseraModuleInitFn)(const TesseraRuntime* runtime,
                                                        unsigned abi_version);
#define TESSERA_MODULE_INIT_SYMBOL "tessera_module_init"

#ifdef __cplusplus
}
#endif

#endif /* TESSERA_DETAIL_MODULE_ABI_H_ */
