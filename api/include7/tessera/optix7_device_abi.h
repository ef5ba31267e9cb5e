/* The C ABI between an OptiX 7 program module and the Tessera engine that runs it. A program
 * module is a shared library that the system C++ compiler builds from an OptiX 7 .cu file
 * (g++ -std=c++17 -O2 -shared -fPIC -x c++ -D__CUDACC__ -I<include7>); its entry points
 * (__raygen__*, __miss__*, __closesthit__*, __anyhit__*, __intersection__*, __exception__*,
 * __direct_callable__*, __continuation_callable__*) and its launch-parameter variable ("params")
 * are exported symbols that the engine finds by name (DESIGN.md, "OptiX 7 on the same devices").
 *
 * Every device function of optix_device.h is an inline function that calls through one table of
 * function pointers, TesseraOptix7Runtime, which the engine fills. The module receives the
 * table through tessera_optix7_module_init (below), which optix_device.h defines weakly in every
 * module; the engine calls it right after loading the module, before any program runs.
 *
 * The engine side (filling the table, running programs) is worker/core/optix7_engine.h
 * (docs/optix7_engine.md). Thread-safety: every function in the table answers for the program
 * running on the calling thread (the engine keeps per-thread state). */
#ifndef TESSERA_OPTIX7_DEVICE_ABI_H_
#define TESSERA_OPTIX7_DEVICE_ABI_H_

#include <stddef.h>

#include "optix_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Raised whenever the table or the meaning of a query changes; module and engine must agree. */
#define TESSERA_OPTIX7_MODULE_ABI_VERSION 4u

/* One optixTrace: the ray and traversal arguments as the program passed them. */
typedef struct TesseraOptix7Trace {
  OptixTraversableHandle handle;
  float origin[3];
  float direction[3];
  float tmin;
  float tmax;
  float ray_time;
  OptixVisibilityMask visibility_mask;
  unsigned int ray_flags;
  unsigned int sbt_offset;
  unsigned int sbt_stride;
  unsigned int miss_sbt_index;
  unsigned int payload_type; /* OptixPayloadTypeID; OPTIX_PAYLOAD_TYPE_DEFAULT without one */
} TesseraOptix7Trace;

/* Vectors of the current ray (TesseraOptix7Runtime::ray_vector). */
enum {
  TESSERA_OPTIX7_WORLD_RAY_ORIGIN = 0,
  TESSERA_OPTIX7_WORLD_RAY_DIRECTION = 1,
  TESSERA_OPTIX7_OBJECT_RAY_ORIGIN = 2,
  TESSERA_OPTIX7_OBJECT_RAY_DIRECTION = 3
};

/* Scalars of the current ray (ray_float). */
enum { TESSERA_OPTIX7_RAY_TMIN = 0, TESSERA_OPTIX7_RAY_TMAX = 1, TESSERA_OPTIX7_RAY_TIME = 2 };

/* Unsigned values of the current ray, hit or launch (state_uint). */
enum {
  TESSERA_OPTIX7_RAY_FLAGS = 0,
  TESSERA_OPTIX7_RAY_VISIBILITY_MASK = 1,
  TESSERA_OPTIX7_PRIMITIVE_INDEX = 2,
  TESSERA_OPTIX7_INSTANCE_ID = 3,
  TESSERA_OPTIX7_INSTANCE_INDEX = 4,
  TESSERA_OPTIX7_SBT_GAS_INDEX = 5,
  TESSERA_OPTIX7_HIT_KIND = 6,
  TESSERA_OPTIX7_TRANSFORM_LIST_SIZE = 7
};

/* What hit_kind_query tells of a hit kind. */
enum {
  TESSERA_OPTIX7_HIT_KIND_PRIMITIVE_TYPE = 0, /* an OptixPrimitiveType */
  TESSERA_OPTIX7_HIT_KIND_IS_FRONT_FACE = 1   /* 1 front, 0 back */
};

/* Geometry kinds and directions of TesseraOptix7Runtime::transform. */
enum {
  TESSERA_OPTIX7_TRANSFORM_POINT = 0,
  TESSERA_OPTIX7_TRANSFORM_VECTOR = 1,
  TESSERA_OPTIX7_TRANSFORM_NORMAL = 2
};
enum { TESSERA_OPTIX7_WORLD_TO_OBJECT = 0, TESSERA_OPTIX7_OBJECT_TO_WORLD = 1 };

/* What transform_data_from_handle returns a device pointer to. */
enum {
  TESSERA_OPTIX7_STATIC_TRANSFORM = 0,        /* const OptixStaticTransform* */
  TESSERA_OPTIX7_MATRIX_MOTION_TRANSFORM = 1, /* const OptixMatrixMotionTransform* */
  TESSERA_OPTIX7_SRT_MOTION_TRANSFORM = 2,    /* const OptixSRTMotionTransform* */
  TESSERA_OPTIX7_INSTANCE_TRANSFORM = 3,      /* const float4[3], object to world */
  TESSERA_OPTIX7_INSTANCE_INVERSE_TRANSFORM = 4
};

/* Details of OPTIX_EXCEPTION_CODE_CALLABLE_PARAMETER_MISMATCH, as optix_device.h returns them. */
typedef struct TesseraOptix7ParameterMismatch {
  unsigned int expected_parameter_count;
  unsigned int passed_argument_count;
  unsigned int sbt_index;
  char* callable_name;
} TesseraOptix7ParameterMismatch;

/* What the engine keeps while a callable program runs: the caller's state, restored by
 * callable_leave (also when a C++ exception unwinds the call). */
typedef struct TesseraOptix7CallFrame {
  void* caller;
  void* reserved[3];
} TesseraOptix7CallFrame;

/* Callable kinds of callable_enter. */
enum { TESSERA_OPTIX7_DIRECT_CALLABLE = 0, TESSERA_OPTIX7_CONTINUATION_CALLABLE = 1 };

typedef struct TesseraOptix7Runtime {
  unsigned int abi_version; /* TESSERA_OPTIX7_MODULE_ABI_VERSION */

  /* ---- Launch: optixGetLaunchIndex/Dimensions, optixGetSbtDataPointer. */
  void (*launch_index)(unsigned int out[3]);
  void (*launch_dimensions)(unsigned int out[3]);
  CUdeviceptr (*sbt_data_pointer)(void);

  /* ---- Tracing. `payload` points at the caller's num_payload (0..32) payload variables,
   * which the engine reads when the ray starts and writes when it ends. */
  void (*trace)(const TesseraOptix7Trace* ray, unsigned int num_payload,
                unsigned int* const* payload);
  unsigned int (*get_payload)(unsigned int index);
  void (*set_payload)(unsigned int index, unsigned int value);
  void (*set_payload_types)(unsigned int types);
  unsigned int (*undefined_value)(void);

  /* ---- State of the current ray and hit (enums above). */
  void (*ray_vector)(unsigned int which, float out[3]);
  float (*ray_float)(unsigned int which);
  unsigned int (*state_uint)(unsigned int which);
  unsigned int (*hit_kind_query)(unsigned int hit_kind, unsigned int what);
  void (*triangle_barycentrics)(float out[2]);
  float (*curve_parameter)(void);
  void (*ribbon_parameters)(float out[2]);

  /* ---- Intersection and any-hit programs. attributes: num_attributes values (0..8). Returns
   * whether the hit was accepted. */
  int (*report_intersection)(float hit_t, unsigned int hit_kind, unsigned int num_attributes,
                             const unsigned int* attributes);
  unsigned int (*get_attribute)(unsigned int index);
  void (*ignore_intersection)(void);
  void (*terminate_ray)(void);

  /* ---- Geometry data of a primitive (optixGet*VertexData, optixGetSphereData): `out` gets
   * the primitive's control points as the type has them: triangles 3 x float3 (9 floats),
   * linear curves 2 x float4, quadratic and ribbon curves 3 x float4, cubic, Catmull-Rom and
   * Bezier curves 4 x float4, spheres 1 x float4 (center, radius). */
  void (*primitive_data)(OptixPrimitiveType type, OptixTraversableHandle gas, unsigned int prim_idx,
                         unsigned int sbt_gas_index, float time, float* out);
  void (*ribbon_normal)(OptixTraversableHandle gas, unsigned int prim_idx,
                        unsigned int sbt_gas_index, float time, const float ribbon_parameters[2],
                        float out[3]);
  void (*micro_triangle_vertex_data)(float out[9]);
  void (*micro_triangle_barycentrics_data)(float out[6]);

  /* ---- Traversables and transforms. */
  OptixTraversableHandle (*gas_traversable_handle)(void);
  float (*gas_motion_time)(OptixTraversableHandle gas, int end); /* begin (0) or end (1) */
  unsigned int (*gas_motion_step_count)(OptixTraversableHandle gas);
  OptixTraversableHandle (*transform_list_handle)(unsigned int index);
  OptixTransformType (*transform_type_from_handle)(OptixTraversableHandle handle);
  const void* (*transform_data_from_handle)(OptixTraversableHandle handle, unsigned int what);
  unsigned int (*instance_id_from_handle)(OptixTraversableHandle handle);
  OptixTraversableHandle (*instance_child_from_handle)(OptixTraversableHandle handle);
  OptixTraversableHandle (*instance_traversable_from_ias)(OptixTraversableHandle ias,
                                                          unsigned int instance_index);
  /* The current hit's transform (at the ray's time), 3x4 row-major. */
  void (*current_transform)(unsigned int direction, float out[12]);
  void (*transform)(unsigned int kind, unsigned int direction, const float in[3], float out[3]);

  /* ---- Exceptions. details: num_details values (0..8). */
  void (*throw_exception)(int code, unsigned int num_details, const unsigned int* details);
  int (*exception_code)(void);
  unsigned int (*exception_detail)(unsigned int index);
  OptixTraversableHandle (*exception_invalid_traversable)(void);
  int (*exception_invalid_sbt_offset)(void);
  /* origin[3], direction[3], tmin, tmax, time */
  void (*exception_invalid_ray)(float out[9]);
  void (*exception_parameter_mismatch)(TesseraOptix7ParameterMismatch* out);
  char* (*exception_line_info)(void);

  /* ---- Callables: the function of SBT callable record `sbt_index` (as the entry point's own
   * type), made the running program; callable_leave makes the caller run again. */
  void* (*callable_enter)(unsigned int kind, unsigned int sbt_index, TesseraOptix7CallFrame* frame);
  void (*callable_leave)(TesseraOptix7CallFrame* frame);

  /* ---- Texture footprints (optixTexFootprint2D*): out = the uint4 footprint. */
  void (*tex_footprint_2d)(unsigned long long tex, unsigned int tex_info, float x, float y,
                           unsigned int* single_mip_level, unsigned int out[4]);
  void (*tex_footprint_2d_grad)(unsigned long long tex, unsigned int tex_info, float x, float y,
                                float dpdx_x, float dpdx_y, float dpdy_x, float dpdy_y, int coarse,
                                unsigned int* single_mip_level, unsigned int out[4]);
  void (*tex_footprint_2d_lod)(unsigned long long tex, unsigned int tex_info, float x, float y,
                               float level, int coarse, unsigned int* single_mip_level,
                               unsigned int out[4]);

  /* ---- Atomics across devices (docs/device_memory.md, "Atomics across devices"). While
   * *atomics_noted is not 0 (a device call on a device that holds a copy of device memory), every
   * atomic function calls note_atomic before it operates: `op` its kind
   * (tessera/detail/atomic_ops.h), `operand` the bits of its operand (32-bit ones in the low
   * half), `limit` atomicInc's or atomicDec's. The engine combines them per address for the host.
   * A flag rather than a null function, so that atomics on a device that shares the host's memory
   * cost one predictable branch. */
  const unsigned int* atomics_noted;
  void (*note_atomic)(void* address, unsigned int op, unsigned long long operand,
                      unsigned int limit);
  /* ---- Accuracy (version 3; tessera/optix7_accuracy.h): the world-space origin for a ray that
   * leaves the current hit in world direction `direction` (tesseraOptixGetSpawnPoint). */
  void (*spawn_point)(const float direction[3], float out[3]);
} TesseraOptix7Runtime;

/* Exported by every module (defined weakly by optix_device.h): stores `runtime` for the
 * module's programs and returns 0, or returns the module's ABI version (nonzero) without
 * storing anything when `abi_version` differs from it. */
typedef unsigned int (*TesseraOptix7ModuleInitFn)(const TesseraOptix7Runtime* runtime,
                                                  unsigned int abi_version);
#define TESSERA_OPTIX7_MODULE_INIT_SYMBOL "tessera_optix7_module_init"

/* Exported by every module (defined weakly by optix_device.h, not a part of the table, so a
 * module without it has flags 0): TESSERA_OPTIX7_MODULE_FLAG_* bits, how the module was
 * compiled. */
#define TESSERA_OPTIX7_MODULE_FLAGS_SYMBOL "tessera_optix7_module_flags"
/* The module was compiled with fast math (tessera/accuracy.h TESSERA_ACCURACY_FAST_MATH,
 * docs/fast_math.md): the engine flushes denormals to zero on the threads of launches that run
 * it. */
#define TESSERA_OPTIX7_MODULE_FLAG_FAST_MATH 0x1u

#ifdef __cplusplus
}
#endif

#endif /* TESSERA_OPTIX7_DEVICE_ABI_H_ */
