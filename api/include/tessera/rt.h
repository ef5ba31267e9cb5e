/* Tessera host API: the OptiX 3 C API (names, types, enum values, RTresult codes).
 * C99-clean. Functions return RTresult; on failure rtContextGetErrorString describes the error and
 * names the object involved. Thread-safety: one thread per context at a time (the OptiX rule);
 * rtContextCreate, rtDeviceGetDeviceCount and rtDeviceGetAttribute may be called from any thread.
 */
#ifndef TESSERA_RT_H_
#define TESSERA_RT_H_

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(__GNUC__)
#define RTAPI __attribute__((visibility("default")))
#else
#define RTAPI
#endif

#define OPTIX_VERSION 3000 /* the OptiX host API level Tessera implements */
#define TESSERA_VERSION 100

typedef size_t RTsize;
typedef int (*RTtimeoutcallback)(void);

typedef struct RTcontext_api* RTcontext;
typedef struct RTbuffer_api* RTbuffer;
typedef struct RTvariable_api* RTvariable;
typedef struct RTprogram_api* RTprogram;
typedef struct RTgeometry_api* RTgeometry;
typedef struct RTgeometrytriangles_api* RTgeometrytriangles; /* OptiX 6 */
typedef struct RTmaterial_api* RTmaterial;
typedef struct RTgeometryinstance_api* RTgeometryinstance;
typedef struct RTgeometrygroup_api* RTgeometrygroup;
typedef struct RTgroup_api* RTgroup;
typedef struct RTselector_api* RTselector;
typedef struct RTtransform_api* RTtransform;
typedef struct RTacceleration_api* RTacceleration;
typedef struct RTtexturesampler_api* RTtexturesampler;
typedef void* RTobject;

typedef enum {
  RT_FORMAT_UNKNOWN = 0x100,
  RT_FORMAT_FLOAT,
  RT_FORMAT_FLOAT2,
  RT_FORMAT_FLOAT3,
  RT_FORMAT_FLOAT4,
  RT_FORMAT_BYTE,
  RT_FORMAT_BYTE2,
  RT_FORMAT_BYTE3,
  RT_FORMAT_BYTE4,
  RT_FORMAT_UNSIGNED_BYTE,
  RT_FORMAT_UNSIGNED_BYTE2,
  RT_FORMAT_UNSIGNED_BYTE3,
  RT_FORMAT_UNSIGNED_BYTE4,
  RT_FORMAT_SHORT,
  RT_FORMAT_SHORT2,
  RT_FORMAT_SHORT3,
  RT_FORMAT_SHORT4,
  RT_FORMAT_UNSIGNED_SHORT,
  RT_FORMAT_UNSIGNED_SHORT2,
  RT_FORMAT_UNSIGNED_SHORT3,
  RT_FORMAT_UNSIGNED_SHORT4,
  RT_FORMAT_INT,
  RT_FORMAT_INT2,
  RT_FORMAT_INT3,
  RT_FORMAT_INT4,
  RT_FORMAT_UNSIGNED_INT,
  RT_FORMAT_UNSIGNED_INT2,
  RT_FORMAT_UNSIGNED_INT3,
  RT_FORMAT_UNSIGNED_INT4,
  RT_FORMAT_USER,
  RT_FORMAT_BUFFER_ID,
  RT_FORMAT_PROGRAM_ID, /* OptiX 3.6+: an int id, as rtProgramGetId returns */
  RT_FORMAT_HALF,       /* OptiX 3.9: IEEE binary16, texture buffers */
  RT_FORMAT_HALF2,
  RT_FORMAT_HALF3,
  RT_FORMAT_HALF4
} RTformat;

typedef enum {
  RT_OBJECTTYPE_UNKNOWN = 0x200,
  RT_OBJECTTYPE_GROUP,
  RT_OBJECTTYPE_GEOMETRY_GROUP,
  RT_OBJECTTYPE_TRANSFORM,
  RT_OBJECTTYPE_SELECTOR,
  RT_OBJECTTYPE_GEOMETRY_INSTANCE,
  RT_OBJECTTYPE_BUFFER,
  RT_OBJECTTYPE_TEXTURE_SAMPLER,
  RT_OBJECTTYPE_OBJECT,
  RT_OBJECTTYPE_MATRIX_FLOAT2x2,
  RT_OBJECTTYPE_MATRIX_FLOAT2x3,
  RT_OBJECTTYPE_MATRIX_FLOAT2x4,
  RT_OBJECTTYPE_MATRIX_FLOAT3x2,
  RT_OBJECTTYPE_MATRIX_FLOAT3x3,
  RT_OBJECTTYPE_MATRIX_FLOAT3x4,
  RT_OBJECTTYPE_MATRIX_FLOAT4x2,
  RT_OBJECTTYPE_MATRIX_FLOAT4x3,
  RT_OBJECTTYPE_MATRIX_FLOAT4x4,
  RT_OBJECTTYPE_FLOAT,
  RT_OBJECTTYPE_FLOAT2,
  RT_OBJECTTYPE_FLOAT3,
  RT_OBJECTTYPE_FLOAT4,
  RT_OBJECTTYPE_INT,
  RT_OBJECTTYPE_INT2,
  RT_OBJECTTYPE_INT3,
  RT_OBJECTTYPE_INT4,
  RT_OBJECTTYPE_UNSIGNED_INT,
  RT_OBJECTTYPE_UNSIGNED_INT2,
  RT_OBJECTTYPE_UNSIGNED_INT3,
  RT_OBJECTTYPE_UNSIGNED_INT4,
  RT_OBJECTTYPE_USER,
  RT_OBJECTTYPE_PROGRAM
} RTobjecttype;

typedef enum {
  RT_WRAP_REPEAT,
  RT_WRAP_CLAMP_TO_EDGE,
  RT_WRAP_MIRROR,
  RT_WRAP_CLAMP_TO_BORDER
} RTwrapmode;

typedef enum { RT_FILTER_NEAREST, RT_FILTER_LINEAR, RT_FILTER_NONE } RTfiltermode;

typedef enum {
  RT_TEXTURE_READ_ELEMENT_TYPE = 0,
  RT_TEXTURE_READ_NORMALIZED_FLOAT = 1,
  /* OptiX 6: sRGB to linear on 8-bit integer formats */
  RT_TEXTURE_READ_ELEMENT_TYPE_SRGB = 2,
  RT_TEXTURE_READ_NORMALIZED_FLOAT_SRGB = 3
} RTtexturereadmode;

typedef enum {
  RT_TEXTURE_INDEX_NORMALIZED_COORDINATES,
  RT_TEXTURE_INDEX_ARRAY_INDEX
} RTtextureindexmode;

typedef enum {
  RT_BUFFER_INPUT = 0x1,
  RT_BUFFER_OUTPUT = 0x2,
  RT_BUFFER_INPUT_OUTPUT = RT_BUFFER_INPUT | RT_BUFFER_OUTPUT
} RTbuffertype;

typedef enum {
  RT_BUFFER_GPU_LOCAL = 0x4,
  RT_BUFFER_COPY_ON_DIRTY = 0x8,
  /* OptiX 3.9, texture buffers: the depth counts layers, or cube faces (+x, -x, +y, -y, +z, -z;
   * width = height, depth 6, or 6 per layer with both flags) */
  RT_BUFFER_LAYERED = 0x200000,
  RT_BUFFER_CUBEMAP = 0x400000
} RTbufferflag;

/* rtBufferMapEx's map_flags (OptiX 3.9). Tessera maps read-write for each of them. */
typedef enum {
  RT_BUFFER_MAP_READ = 0x1,
  RT_BUFFER_MAP_READ_WRITE = 0x2,
  RT_BUFFER_MAP_WRITE = 0x4,
  RT_BUFFER_MAP_WRITE_DISCARD = 0x8
} RTbuffermapflag;

typedef enum {
  RT_EXCEPTION_PROGRAM_ID_INVALID = 0x3EE,
  RT_EXCEPTION_TEXTURE_ID_INVALID = 0x3EF,
  RT_EXCEPTION_BUFFER_ID_INVALID = 0x3FA,
  RT_EXCEPTION_INDEX_OUT_OF_BOUNDS = 0x3FB,
  RT_EXCEPTION_STACK_OVERFLOW = 0x3FC,
  RT_EXCEPTION_BUFFER_INDEX_OUT_OF_BOUNDS = 0x3FD,
  RT_EXCEPTION_INVALID_RAY = 0x3FE,
  RT_EXCEPTION_INTERNAL_ERROR = 0x3FF,
  RT_EXCEPTION_USER = 0x400,
  RT_EXCEPTION_ALL = 0x7FFFFFFF
} RTexception;

/* OptiX 3.5+: the ids no buffer or program has (rtBufferId, rtCallableProgramId). */
typedef enum { RT_BUFFER_ID_NULL = 0 } RTbufferidnull;
typedef enum { RT_PROGRAM_ID_NULL = 0 } RTprogramidnull;

typedef enum {
  RT_SUCCESS = 0,
  RT_TIMEOUT_CALLBACK = 0x100,
  RT_ERROR_INVALID_CONTEXT = 0x500,
  RT_ERROR_INVALID_VALUE = 0x501,
  RT_ERROR_MEMORY_ALLOCATION_FAILED = 0x502,
  RT_ERROR_TYPE_MISMATCH = 0x503,
  RT_ERROR_VARIABLE_NOT_FOUND = 0x504,
  RT_ERROR_VARIABLE_REDECLARED = 0x505,
  RT_ERROR_ILLEGAL_SYMBOL = 0x506,
  RT_ERROR_INVALID_SOURCE = 0x507,
  RT_ERROR_VERSION_MISMATCH = 0x508,
  RT_ERROR_OBJECT_CREATION_FAILED = 0x600,
  RT_ERROR_NO_DEVICE = 0x601,
  RT_ERROR_INVALID_DEVICE = 0x602,
  RT_ERROR_INVALID_IMAGE = 0x603,
  RT_ERROR_FILE_NOT_FOUND = 0x604,
  RT_ERROR_ALREADY_MAPPED = 0x605,
  RT_ERROR_INVALID_DRIVER_VERSION = 0x606,
  RT_ERROR_CONTEXT_CREATION_FAILED = 0x607,
  RT_ERROR_RESOURCE_NOT_REGISTERED = 0x608,
  RT_ERROR_RESOURCE_ALREADY_REGISTERED = 0x609,
  RT_ERROR_LAUNCH_FAILED = 0x900,
  RT_ERROR_NOT_SUPPORTED = 0xA00,
  RT_ERROR_CONNECTION_FAILED = 0xB00,
  RT_ERROR_AUTHENTICATION_FAILED = 0xB01,
  RT_ERROR_CONNECTION_ALREADY_EXISTS = 0xB02,
  RT_ERROR_NETWORK_LOAD_FAILED = 0xB03,
  RT_ERROR_NETWORK_INIT_FAILED = 0xB04,
  RT_ERROR_CLUSTER_NOT_RUNNING = 0xB06,
  RT_ERROR_CLUSTER_ALREADY_RUNNING = 0xB07,
  RT_ERROR_INSUFFICIENT_FREE_NODES = 0xB08,
  RT_ERROR_UNKNOWN = ~0
} RTresult;

typedef enum {
  RT_DEVICE_ATTRIBUTE_MAX_THREADS_PER_BLOCK,
  RT_DEVICE_ATTRIBUTE_CLOCK_RATE,
  RT_DEVICE_ATTRIBUTE_MULTIPROCESSOR_COUNT,
  RT_DEVICE_ATTRIBUTE_EXECUTION_TIMEOUT_ENABLED,
  RT_DEVICE_ATTRIBUTE_MAX_HARDWARE_TEXTURE_COUNT,
  RT_DEVICE_ATTRIBUTE_NAME,
  RT_DEVICE_ATTRIBUTE_COMPUTE_CAPABILITY,
  RT_DEVICE_ATTRIBUTE_TOTAL_MEMORY,
  RT_DEVICE_ATTRIBUTE_TCC_DRIVER,
  RT_DEVICE_ATTRIBUTE_CUDA_DEVICE_ORDINAL
} RTdeviceattribute;

typedef enum {
  RT_CONTEXT_ATTRIBUTE_MAX_TEXTURE_COUNT = 0,
  RT_CONTEXT_ATTRIBUTE_CPU_NUM_THREADS = 1,
  RT_CONTEXT_ATTRIBUTE_USED_HOST_MEMORY = 2,
  RT_CONTEXT_ATTRIBUTE_GPU_PAGING_ACTIVE = 3,
  RT_CONTEXT_ATTRIBUTE_GPU_PAGING_FORCED_OFF = 4,
  RT_CONTEXT_ATTRIBUTE_AVAILABLE_DEVICE_MEMORY = 0x10000000
} RTcontextattribute;

/* Program-side transform kinds; here so host and device agree on the values. */
typedef enum { RT_WORLD_TO_OBJECT = 0xf00, RT_OBJECT_TO_WORLD } RTtransformkind;
typedef enum { RT_INTERNAL_INVERSE_TRANSPOSE = 0x1000 } RTtransformflags;

/* ---- Global ---------------------------------------------------------------------------- */
RTAPI RTresult rtGetVersion(unsigned int* version);
RTAPI RTresult rtDeviceGetDeviceCount(unsigned int* count);
RTAPI RTresult rtDeviceGetAttribute(int ordinal, RTdeviceattribute attrib, RTsize size, void* p);

/* ---- Context ----------------------------------------------------------------------------- */
RTAPI RTresult rtContextCreate(RTcontext* context);
RTAPI RTresult rtContextDestroy(RTcontext context);
RTAPI RTresult rtContextValidate(RTcontext context);
RTAPI void rtContextGetErrorString(RTcontext context, RTresult code, const char** return_string);
RTAPI RTresult rtContextSetAttribute(RTcontext context, RTcontextattribute attrib, RTsize size,
                                     void* p);
RTAPI RTresult rtContextGetAttribute(RTcontext context, RTcontextattribute attrib, RTsize size,
                                     void* p);
RTAPI RTresult rtContextSetDevices(RTcontext context, unsigned int count, const int* devices);
RTAPI RTresult rtContextGetDevices(RTcontext context, int* devices);
RTAPI RTresult rtContextGetDeviceCount(RTcontext context, unsigned int* count);
RTAPI RTresult rtContextSetStackSize(RTcontext context, RTsize stack_size_bytes);
RTAPI RTresult rtContextGetStackSize(RTcontext context, RTsize* stack_size_bytes);
RTAPI RTresult rtContextSetTimeoutCallback(RTcontext context, RTtimeoutcallback callback,
                                           double min_polling_seconds);
RTAPI RTresult rtContextSetEntryPointCount(RTcontext context, unsigned int num_entry_points);
RTAPI RTresult rtContextGetEntryPointCount(RTcontext context, unsigned int* num_entry_points);
RTAPI RTresult rtContextSetRayGenerationProgram(RTcontext context, unsigned int entry_point_index,
                                                RTprogram program);
RTAPI RTresult rtContextGetRayGenerationProgram(RTcontext context, unsigned int entry_point_index,
                                                RTprogram* program);
RTAPI RTresult rtContextSetExceptionProgram(RTcontext context, unsigned int entry_point_index,
                                            RTprogram program);
RTAPI RTresult rtContextGetExceptionProgram(RTcontext context, unsigned int entry_point_index,
                                            RTprogram* program);
RTAPI RTresult rtContextSetExceptionEnabled(RTcontext context, RTexception exception, int enabled);
RTAPI RTresult rtContextGetExceptionEnabled(RTcontext context, RTexception exception, int* enabled);
RTAPI RTresult rtContextSetRayTypeCount(RTcontext context, unsigned int num_ray_types);
RTAPI RTresult rtContextGetRayTypeCount(RTcontext context, unsigned int* num_ray_types);
RTAPI RTresult rtContextSetMissProgram(RTcontext context, unsigned int ray_type_index,
                                       RTprogram program);
RTAPI RTresult rtContextGetMissProgram(RTcontext context, unsigned int ray_type_index,
                                       RTprogram* program);
RTAPI RTresult rtContextCompile(RTcontext context);
RTAPI RTresult rtContextLaunch1D(RTcontext context, unsigned int entry_point_index,
                                 RTsize image_width);
RTAPI RTresult rtContextLaunch2D(RTcontext context, unsigned int entry_point_index,
                                 RTsize image_width, RTsize image_height);
RTAPI RTresult rtContextLaunch3D(RTcontext context, unsigned int entry_point_index,
                                 RTsize image_width, RTsize image_height, RTsize image_depth);
RTAPI RTresult rtContextGetRunningState(RTcontext context, int* running);
RTAPI RTresult rtContextSetPrintEnabled(RTcontext context, int enabled);
RTAPI RTresult rtContextGetPrintEnabled(RTcontext context, int* enabled);
RTAPI RTresult rtContextSetPrintBufferSize(RTcontext context, RTsize buffer_size_bytes);
RTAPI RTresult rtContextGetPrintBufferSize(RTcontext context, RTsize* buffer_size_bytes);
RTAPI RTresult rtContextSetPrintLaunchIndex(RTcontext context, int x, int y, int z);
RTAPI RTresult rtContextGetPrintLaunchIndex(RTcontext context, int* x, int* y, int* z);
RTAPI RTresult rtContextDeclareVariable(RTcontext context, const char* name, RTvariable* v);
RTAPI RTresult rtContextQueryVariable(RTcontext context, const char* name, RTvariable* v);
RTAPI RTresult rtContextRemoveVariable(RTcontext context, RTvariable v);
RTAPI RTresult rtContextGetVariableCount(RTcontext context, unsigned int* count);
RTAPI RTresult rtContextGetVariable(RTcontext context, unsigned int index, RTvariable* v);
RTAPI RTresult rtContextGetBufferFromId(RTcontext context, int buffer_id, RTbuffer* buffer);
/* The sampler rtTextureSamplerGetId gave `sampler_id` (OptiX 3.0). */
RTAPI RTresult rtContextGetTextureSamplerFromId(RTcontext context, int sampler_id,
                                                RTtexturesampler* sampler);

/* ---- Program ----------------------------------------------------------------------------- */
/* `filename` names a program module (a shared library built from C++, the PTX analogue) or a
 * C++ source file (.cu/.cpp/.cc) that Tessera compiles with the system compiler and caches. */
RTAPI RTresult rtProgramCreateFromPTXFile(RTcontext context, const char* filename,
                                          const char* program_name, RTprogram* program);
/* `ptx` holds C++ source text of a program module. */
RTAPI RTresult rtProgramCreateFromPTXString(RTcontext context, const char* ptx,
                                            const char* program_name, RTprogram* program);
RTAPI RTresult rtProgramDestroy(RTprogram program);
RTAPI RTresult rtProgramValidate(RTprogram program);
RTAPI RTresult rtProgramGetContext(RTprogram program, RTcontext* context);
RTAPI RTresult rtProgramDeclareVariable(RTprogram program, const char* name, RTvariable* v);
RTAPI RTresult rtProgramQueryVariable(RTprogram program, const char* name, RTvariable* v);
RTAPI RTresult rtProgramRemoveVariable(RTprogram program, RTvariable v);
RTAPI RTresult rtProgramGetVariableCount(RTprogram program, unsigned int* count);
RTAPI RTresult rtProgramGetVariable(RTprogram program, unsigned int index, RTvariable* v);
/* OptiX 3.6+: the program's id for rtCallableProgramId (positive, its object id); the program then
 * reaches every device whether or not a variable names it. */
RTAPI RTresult rtProgramGetId(RTprogram program, int* program_id);
/* OptiX 3.6+: the live program of `context` with id `program_id`; RT_ERROR_INVALID_VALUE if none.
 */
RTAPI RTresult rtContextGetProgramFromId(RTcontext context, int program_id, RTprogram* program);

/* ---- Group ------------------------------------------------------------------------------- */
RTAPI RTresult rtGroupCreate(RTcontext context, RTgroup* group);
RTAPI RTresult rtGroupDestroy(RTgroup group);
RTAPI RTresult rtGroupValidate(RTgroup group);
RTAPI RTresult rtGroupGetContext(RTgroup group, RTcontext* context);
RTAPI RTresult rtGroupSetAcceleration(RTgroup group, RTacceleration acceleration);
RTAPI RTresult rtGroupGetAcceleration(RTgroup group, RTacceleration* acceleration);
RTAPI RTresult rtGroupSetChildCount(RTgroup group, unsigned int count);
RTAPI RTresult rtGroupGetChildCount(RTgroup group, unsigned int* count);
RTAPI RTresult rtGroupSetChild(RTgroup group, unsigned int index, RTobject child);
RTAPI RTresult rtGroupGetChild(RTgroup group, unsigned int index, RTobject* child);
RTAPI RTresult rtGroupGetChildType(RTgroup group, unsigned int index, RTobjecttype* type);

/* ---- Selector (visit programs are not run yet; see docs/COMPATIBILITY.md) ------------------ */
RTAPI RTresult rtSelectorCreate(RTcontext context, RTselector* selector);
RTAPI RTresult rtSelectorDestroy(RTselector selector);
RTAPI RTresult rtSelectorValidate(RTselector selector);
RTAPI RTresult rtSelectorGetContext(RTselector selector, RTcontext* context);
RTAPI RTresult rtSelectorSetVisitProgram(RTselector selector, RTprogram program);
RTAPI RTresult rtSelectorGetVisitProgram(RTselector selector, RTprogram* program);
RTAPI RTresult rtSelectorSetChildCount(RTselector selector, unsigned int count);
RTAPI RTresult rtSelectorGetChildCount(RTselector selector, unsigned int* count);
RTAPI RTresult rtSelectorSetChild(RTselector selector, unsigned int index, RTobject child);
RTAPI RTresult rtSelectorGetChild(RTselector selector, unsigned int index, RTobject* child);
RTAPI RTresult rtSelectorGetChildType(RTselector selector, unsigned int index, RTobjecttype* type);
RTAPI RTresult rtSelectorDeclareVariable(RTselector selector, const char* name, RTvariable* v);
RTAPI RTresult rtSelectorQueryVariable(RTselector selector, const char* name, RTvariable* v);
RTAPI RTresult rtSelectorRemoveVariable(RTselector selector, RTvariable v);
RTAPI RTresult rtSelectorGetVariableCount(RTselector selector, unsigned int* count);
RTAPI RTresult rtSelectorGetVariable(RTselector selector, unsigned int index, RTvariable* v);

/* ---- Transform --------------------------------------------------------------------------- */
RTAPI RTresult rtTransformCreate(RTcontext context, RTtransform* transform);
RTAPI RTresult rtTransformDestroy(RTtransform transform);
RTAPI RTresult rtTransformValidate(RTtransform transform);
RTAPI RTresult rtTransformGetContext(RTtransform transform, RTcontext* context);
/* Row-major 4x4 unless `transpose`; a null `inverse_matrix` means Tessera inverts `matrix`. */
RTAPI RTresult rtTransformSetMatrix(RTtransform transform, int transpose, const float* matrix,
                                    const float* inverse_matrix);
RTAPI RTresult rtTransformGetMatrix(RTtransform transform, int transpose, float* matrix,
                                    float* inverse_matrix);
RTAPI RTresult rtTransformSetChild(RTtransform transform, RTobject child);
RTAPI RTresult rtTransformGetChild(RTtransform transform, RTobject* child);
RTAPI RTresult rtTransformGetChildType(RTtransform transform, RTobjecttype* type);

/* ---- GeometryGroup ----------------------------------------------------------------------- */
RTAPI RTresult rtGeometryGroupCreate(RTcontext context, RTgeometrygroup* geometrygroup);
RTAPI RTresult rtGeometryGroupDestroy(RTgeometrygroup geometrygroup);
RTAPI RTresult rtGeometryGroupValidate(RTgeometrygroup geometrygroup);
RTAPI RTresult rtGeometryGroupGetContext(RTgeometrygroup geometrygroup, RTcontext* context);
RTAPI RTresult rtGeometryGroupSetAcceleration(RTgeometrygroup geometrygroup,
                                              RTacceleration acceleration);
RTAPI RTresult rtGeometryGroupGetAcceleration(RTgeometrygroup geometrygroup,
                                              RTacceleration* acceleration);
RTAPI RTresult rtGeometryGroupSetChildCount(RTgeometrygroup geometrygroup, unsigned int count);
RTAPI RTresult rtGeometryGroupGetChildCount(RTgeometrygroup geometrygroup, unsigned int* count);
RTAPI RTresult rtGeometryGroupSetChild(RTgeometrygroup geometrygroup, unsigned int index,
                                       RTgeometryinstance geometryinstance);
RTAPI RTresult rtGeometryGroupGetChild(RTgeometrygroup geometrygroup, unsigned int index,
                                       RTgeometryinstance* geometryinstance);

/* ---- Acceleration ------------------------------------------------------------------------ */
RTAPI RTresult rtAccelerationCreate(RTcontext context, RTacceleration* acceleration);
RTAPI RTresult rtAccelerationDestroy(RTacceleration acceleration);
RTAPI RTresult rtAccelerationValidate(RTacceleration acceleration);
RTAPI RTresult rtAccelerationGetContext(RTacceleration acceleration, RTcontext* context);
RTAPI RTresult rtAccelerationSetBuilder(RTacceleration acceleration, const char* builder);
RTAPI RTresult rtAccelerationGetBuilder(RTacceleration acceleration, const char** return_string);
RTAPI RTresult rtAccelerationSetTraverser(RTacceleration acceleration, const char* traverser);
RTAPI RTresult rtAccelerationGetTraverser(RTacceleration acceleration, const char** return_string);
RTAPI RTresult rtAccelerationSetProperty(RTacceleration acceleration, const char* name,
                                         const char* value);
RTAPI RTresult rtAccelerationGetProperty(RTacceleration acceleration, const char* name,
                                         const char** return_string);
RTAPI RTresult rtAccelerationGetDataSize(RTacceleration acceleration, RTsize* size);
RTAPI RTresult rtAccelerationGetData(RTacceleration acceleration, void* data);
RTAPI RTresult rtAccelerationSetData(RTacceleration acceleration, const void* data, RTsize size);
RTAPI RTresult rtAccelerationMarkDirty(RTacceleration acceleration);
RTAPI RTresult rtAccelerationIsDirty(RTacceleration acceleration, int* dirty);

/* ---- GeometryInstance -------------------------------------------------------------------- */
RTAPI RTresult rtGeometryInstanceCreate(RTcontext context, RTgeometryinstance* geometryinstance);
RTAPI RTresult rtGeometryInstanceDestroy(RTgeometryinstance geometryinstance);
RTAPI RTresult rtGeometryInstanceValidate(RTgeometryinstance geometryinstance);
RTAPI RTresult rtGeometryInstanceGetContext(RTgeometryinstance geometryinstance,
                                            RTcontext* context);
RTAPI RTresult rtGeometryInstanceSetGeometry(RTgeometryinstance geometryinstance,
                                             RTgeometry geometry);
RTAPI RTresult rtGeometryInstanceGetGeometry(RTgeometryinstance geometryinstance,
                                             RTgeometry* geometry);
RTAPI RTresult rtGeometryInstanceSetMaterialCount(RTgeometryinstance geometryinstance,
                                                  unsigned int count);
RTAPI RTresult rtGeometryInstanceGetMaterialCount(RTgeometryinstance geometryinstance,
                                                  unsigned int* count);
RTAPI RTresult rtGeometryInstanceSetMaterial(RTgeometryinstance geometryinstance,
                                             unsigned int index, RTmaterial material);
RTAPI RTresult rtGeometryInstanceGetMaterial(RTgeometryinstance geometryinstance,
                                             unsigned int index, RTmaterial* material);
RTAPI RTresult rtGeometryInstanceDeclareVariable(RTgeometryinstance geometryinstance,
                                                 const char* name, RTvariable* v);
RTAPI RTresult rtGeometryInstanceQueryVariable(RTgeometryinstance geometryinstance,
                                               const char* name, RTvariable* v);
RTAPI RTresult rtGeometryInstanceRemoveVariable(RTgeometryinstance geometryinstance, RTvariable v);
RTAPI RTresult rtGeometryInstanceGetVariableCount(RTgeometryinstance geometryinstance,
                                                  unsigned int* count);
RTAPI RTresult rtGeometryInstanceGetVariable(RTgeometryinstance geometryinstance,
                                             unsigned int index, RTvariable* v);

/* ---- Geometry ---------------------------------------------------------------------------- */
RTAPI RTresult rtGeometryCreate(RTcontext context, RTgeometry* geometry);
RTAPI RTresult rtGeometryDestroy(RTgeometry geometry);
RTAPI RTresult rtGeometryValidate(RTgeometry geometry);
RTAPI RTresult rtGeometryGetContext(RTgeometry geometry, RTcontext* context);
RTAPI RTresult rtGeometrySetPrimitiveCount(RTgeometry geometry, unsigned int num_primitives);
RTAPI RTresult rtGeometryGetPrimitiveCount(RTgeometry geometry, unsigned int* num_primitives);
RTAPI RTresult rtGeometrySetBoundingBoxProgram(RTgeometry geometry, RTprogram program);
RTAPI RTresult rtGeometryGetBoundingBoxProgram(RTgeometry geometry, RTprogram* program);
RTAPI RTresult rtGeometrySetIntersectionProgram(RTgeometry geometry, RTprogram program);
RTAPI RTresult rtGeometryGetIntersectionProgram(RTgeometry geometry, RTprogram* program);
RTAPI RTresult rtGeometryMarkDirty(RTgeometry geometry);
RTAPI RTresult rtGeometryIsDirty(RTgeometry geometry, int* dirty);
RTAPI RTresult rtGeometryDeclareVariable(RTgeometry geometry, const char* name, RTvariable* v);
RTAPI RTresult rtGeometryQueryVariable(RTgeometry geometry, const char* name, RTvariable* v);
RTAPI RTresult rtGeometryRemoveVariable(RTgeometry geometry, RTvariable v);
RTAPI RTresult rtGeometryGetVariableCount(RTgeometry geometry, unsigned int* count);
RTAPI RTresult rtGeometryGetVariable(RTgeometry geometry, unsigned int index, RTvariable* v);

/* GeometryTriangles (OptiX 6): triangles Embree intersects itself; an optional attribute program
 * computes a hit's attributes (docs/COMPATIBILITY.md "Built-in triangles"). */
RTAPI RTresult rtGeometryTrianglesCreate(RTcontext context, RTgeometrytriangles* geometrytriangles);
RTAPI RTresult rtGeometryTrianglesDestroy(RTgeometrytriangles geometrytriangles);
RTAPI RTresult rtGeometryTrianglesValidate(RTgeometrytriangles geometrytriangles);
RTAPI RTresult rtGeometryTrianglesGetContext(RTgeometrytriangles geometrytriangles,
                                             RTcontext* context);
/* OptiX 6 build flags of GeometryTriangles. */
typedef enum {
  RT_GEOMETRY_BUILD_FLAG_NONE = 0x00,
  RT_GEOMETRY_BUILD_FLAG_RELEASE_BUFFERS = 0x10
} RTgeometrybuildflags;
/* RELEASE_BUFFERS lets OptiX free the device copies of the vertex and index buffers after the
 * build; Tessera keeps them (tesseraSpawnPoint and refits read them) and accepts the flag. Other
 * bits: RT_ERROR_INVALID_VALUE. */
RTAPI RTresult rtGeometryTrianglesSetBuildFlags(RTgeometrytriangles geometrytriangles,
                                                RTgeometrybuildflags build_flags);
RTAPI RTresult rtGeometryTrianglesSetPrimitiveIndexOffset(RTgeometrytriangles geometrytriangles,
                                                          unsigned int index_offset);
RTAPI RTresult rtGeometryTrianglesGetPrimitiveIndexOffset(RTgeometrytriangles geometrytriangles,
                                                          unsigned int* index_offset);
RTAPI RTresult rtGeometryTrianglesSetPrimitiveCount(RTgeometrytriangles geometrytriangles,
                                                    unsigned int num_triangles);
RTAPI RTresult rtGeometryTrianglesGetPrimitiveCount(RTgeometrytriangles geometrytriangles,
                                                    unsigned int* num_triangles);
RTAPI RTresult rtGeometryTrianglesSetTriangleIndices(RTgeometrytriangles geometrytriangles,
                                                     RTbuffer index_buffer,
                                                     RTsize index_buffer_byte_offset,
                                                     RTsize tri_indices_byte_stride,
                                                     RTformat tri_indices_format);
RTAPI RTresult rtGeometryTrianglesSetVertices(RTgeometrytriangles geometrytriangles,
                                              unsigned int num_vertices, RTbuffer vertex_buffer,
                                              RTsize vertex_buffer_byte_offset,
                                              RTsize vertex_byte_stride, RTformat position_format);
RTAPI RTresult rtGeometryTrianglesSetAttributeProgram(RTgeometrytriangles geometrytriangles,
                                                      RTprogram program);
RTAPI RTresult rtGeometryTrianglesGetAttributeProgram(RTgeometrytriangles geometrytriangles,
                                                      RTprogram* program);
RTAPI RTresult rtGeometryTrianglesSetMaterialCount(RTgeometrytriangles geometrytriangles,
                                                   unsigned int num_materials);
RTAPI RTresult rtGeometryTrianglesGetMaterialCount(RTgeometrytriangles geometrytriangles,
                                                   unsigned int* num_materials);
RTAPI RTresult rtGeometryTrianglesSetMaterialIndices(RTgeometrytriangles geometrytriangles,
                                                     RTbuffer material_index_buffer,
                                                     RTsize material_index_buffer_byte_offset,
                                                     RTsize material_index_byte_stride,
                                                     RTformat material_index_format);
RTAPI RTresult rtGeometryTrianglesDeclareVariable(RTgeometrytriangles geometrytriangles,
                                                  const char* name, RTvariable* v);
RTAPI RTresult rtGeometryTrianglesQueryVariable(RTgeometrytriangles geometrytriangles,
                                                const char* name, RTvariable* v);
RTAPI RTresult rtGeometryTrianglesRemoveVariable(RTgeometrytriangles geometrytriangles,
                                                 RTvariable v);
RTAPI RTresult rtGeometryTrianglesGetVariableCount(RTgeometrytriangles geometrytriangles,
                                                   unsigned int* count);
RTAPI RTresult rtGeometryTrianglesGetVariable(RTgeometrytriangles geometrytriangles,
                                              unsigned int index, RTvariable* v);
RTAPI RTresult rtGeometryInstanceSetGeometryTriangles(RTgeometryinstance geometryinstance,
                                                      RTgeometrytriangles geometrytriangles);
RTAPI RTresult rtGeometryInstanceGetGeometryTriangles(RTgeometryinstance geometryinstance,
                                                      RTgeometrytriangles* geometrytriangles);

/* ---- Material ---------------------------------------------------------------------------- */
RTAPI RTresult rtMaterialCreate(RTcontext context, RTmaterial* material);
RTAPI RTresult rtMaterialDestroy(RTmaterial material);
RTAPI RTresult rtMaterialValidate(RTmaterial material);
RTAPI RTresult rtMaterialGetContext(RTmaterial material, RTcontext* context);
RTAPI RTresult rtMaterialSetClosestHitProgram(RTmaterial material, unsigned int ray_type_index,
                                              RTprogram program);
RTAPI RTresult rtMaterialGetClosestHitProgram(RTmaterial material, unsigned int ray_type_index,
                                              RTprogram* program);
RTAPI RTresult rtMaterialSetAnyHitProgram(RTmaterial material, unsigned int ray_type_index,
                                          RTprogram program);
RTAPI RTresult rtMaterialGetAnyHitProgram(RTmaterial material, unsigned int ray_type_index,
                                          RTprogram* program);
RTAPI RTresult rtMaterialDeclareVariable(RTmaterial material, const char* name, RTvariable* v);
RTAPI RTresult rtMaterialQueryVariable(RTmaterial material, const char* name, RTvariable* v);
RTAPI RTresult rtMaterialRemoveVariable(RTmaterial material, RTvariable v);
RTAPI RTresult rtMaterialGetVariableCount(RTmaterial material, unsigned int* count);
RTAPI RTresult rtMaterialGetVariable(RTmaterial material, unsigned int index, RTvariable* v);

/* ---- Buffer ------------------------------------------------------------------------------ */
/* `bufferdesc` is an RTbuffertype or'ed with RTbufferflag bits. */
RTAPI RTresult rtBufferCreate(RTcontext context, unsigned int bufferdesc, RTbuffer* buffer);
RTAPI RTresult rtBufferDestroy(RTbuffer buffer);
RTAPI RTresult rtBufferValidate(RTbuffer buffer);
RTAPI RTresult rtBufferGetContext(RTbuffer buffer, RTcontext* context);
RTAPI RTresult rtBufferSetFormat(RTbuffer buffer, RTformat format);
RTAPI RTresult rtBufferGetFormat(RTbuffer buffer, RTformat* format);
RTAPI RTresult rtBufferSetElementSize(RTbuffer buffer, RTsize size_of_element);
RTAPI RTresult rtBufferGetElementSize(RTbuffer buffer, RTsize* size_of_element);
RTAPI RTresult rtBufferSetSize1D(RTbuffer buffer, RTsize width);
RTAPI RTresult rtBufferGetSize1D(RTbuffer buffer, RTsize* width);
RTAPI RTresult rtBufferSetSize2D(RTbuffer buffer, RTsize width, RTsize height);
RTAPI RTresult rtBufferGetSize2D(RTbuffer buffer, RTsize* width, RTsize* height);
RTAPI RTresult rtBufferSetSize3D(RTbuffer buffer, RTsize width, RTsize height, RTsize depth);
RTAPI RTresult rtBufferGetSize3D(RTbuffer buffer, RTsize* width, RTsize* height, RTsize* depth);
RTAPI RTresult rtBufferSetSizev(RTbuffer buffer, unsigned int dimensionality, const RTsize* dims);
RTAPI RTresult rtBufferGetSizev(RTbuffer buffer, unsigned int dimensionality, RTsize* dims);
RTAPI RTresult rtBufferGetDimensionality(RTbuffer buffer, unsigned int* dimensionality);
RTAPI RTresult rtBufferMap(RTbuffer buffer, void** user_pointer);
RTAPI RTresult rtBufferUnmap(RTbuffer buffer);
RTAPI RTresult rtBufferGetId(RTbuffer buffer, int* buffer_id);
RTAPI RTresult rtBufferMarkDirty(RTbuffer buffer);

/* Mip levels (OptiX 3.9): level i is max(1, size >> i) in each dimension (a layered or cube map
 * buffer keeps its depth), stored after level i - 1. rtBufferMap maps level 0. */
RTAPI RTresult rtBufferSetMipLevelCount(RTbuffer buffer, unsigned int levels);
RTAPI RTresult rtBufferGetMipLevelCount(RTbuffer buffer, unsigned int* level);
RTAPI RTresult rtBufferGetMipLevelSize1D(RTbuffer buffer, unsigned int level, RTsize* width);
RTAPI RTresult rtBufferGetMipLevelSize2D(RTbuffer buffer, unsigned int level, RTsize* width,
                                         RTsize* height);
RTAPI RTresult rtBufferGetMipLevelSize3D(RTbuffer buffer, unsigned int level, RTsize* width,
                                         RTsize* height, RTsize* depth);
/* `map_flags` is one RTbuffermapflag; `user_owned` must be null (as in OptiX 6). */
RTAPI RTresult rtBufferMapEx(RTbuffer buffer, unsigned int map_flags, unsigned int level,
                             void* user_owned, void** optix_owned);
RTAPI RTresult rtBufferUnmapEx(RTbuffer buffer, unsigned int level);

/* ---- Texture sampler (OptiX guide 3.3) ------------------------------------------------------
 * A sampler reads an INPUT (or INPUT_OUTPUT) buffer of a numeric format through rtTextureSampler
 * declarations or, by id, rtTex* calls. Defaults: wrap REPEAT, filters LINEAR/LINEAR/NONE,
 * NORMALIZED_FLOAT, NORMALIZED_COORDINATES, anisotropy 1, mip clamp [0, 0], bias 0. */
RTAPI RTresult rtTextureSamplerCreate(RTcontext context, RTtexturesampler* texturesampler);
RTAPI RTresult rtTextureSamplerDestroy(RTtexturesampler texturesampler);
RTAPI RTresult rtTextureSamplerValidate(RTtexturesampler texturesampler);
RTAPI RTresult rtTextureSamplerGetContext(RTtexturesampler texturesampler, RTcontext* context);
/* Deprecated in OptiX 3.9 (mip levels live in the buffer): the count must be 1. */
RTAPI RTresult rtTextureSamplerSetMipLevelCount(RTtexturesampler texturesampler,
                                                unsigned int num_mip_levels);
RTAPI RTresult rtTextureSamplerGetMipLevelCount(RTtexturesampler texturesampler,
                                                unsigned int* num_mip_levels);
/* Deprecated in OptiX 3.9 (layered buffers replace arrays): the size must be 1. */
RTAPI RTresult rtTextureSamplerSetArraySize(RTtexturesampler texturesampler,
                                            unsigned int num_textures_in_array);
RTAPI RTresult rtTextureSamplerGetArraySize(RTtexturesampler texturesampler,
                                            unsigned int* num_textures_in_array);
/* `dimension` 0, 1 or 2. */
RTAPI RTresult rtTextureSamplerSetWrapMode(RTtexturesampler texturesampler, unsigned int dimension,
                                           RTwrapmode wrapmode);
RTAPI RTresult rtTextureSamplerGetWrapMode(RTtexturesampler texturesampler, unsigned int dimension,
                                           RTwrapmode* wrapmode);
/* minification and magnification NEAREST or LINEAR; mipmapping also NONE (level 0 only). */
RTAPI RTresult rtTextureSamplerSetFilteringModes(RTtexturesampler texturesampler,
                                                 RTfiltermode minification,
                                                 RTfiltermode magnification,
                                                 RTfiltermode mipmapping);
RTAPI RTresult rtTextureSamplerGetFilteringModes(RTtexturesampler texturesampler,
                                                 RTfiltermode* minification,
                                                 RTfiltermode* magnification,
                                                 RTfiltermode* mipmapping);
/* Clamped to [1, 16], as OptiX does. */
RTAPI RTresult rtTextureSamplerSetMaxAnisotropy(RTtexturesampler texturesampler, float value);
RTAPI RTresult rtTextureSamplerGetMaxAnisotropy(RTtexturesampler texturesampler, float* value);
RTAPI RTresult rtTextureSamplerSetMipLevelClamp(RTtexturesampler texturesampler, float min_level,
                                                float max_level);
RTAPI RTresult rtTextureSamplerGetMipLevelClamp(RTtexturesampler texturesampler, float* min_level,
                                                float* max_level);
RTAPI RTresult rtTextureSamplerSetMipLevelBias(RTtexturesampler texturesampler, float value);
RTAPI RTresult rtTextureSamplerGetMipLevelBias(RTtexturesampler texturesampler, float* value);
RTAPI RTresult rtTextureSamplerSetReadMode(RTtexturesampler texturesampler,
                                           RTtexturereadmode readmode);
RTAPI RTresult rtTextureSamplerGetReadMode(RTtexturesampler texturesampler,
                                           RTtexturereadmode* readmode);
RTAPI RTresult rtTextureSamplerSetIndexingMode(RTtexturesampler texturesampler,
                                               RTtextureindexmode indexmode);
RTAPI RTresult rtTextureSamplerGetIndexingMode(RTtexturesampler texturesampler,
                                               RTtextureindexmode* indexmode);
/* `deprecated0` and `deprecated1` (array index and mip level before OptiX 3.9) must be 0. */
RTAPI RTresult rtTextureSamplerSetBuffer(RTtexturesampler texturesampler, unsigned int deprecated0,
                                         unsigned int deprecated1, RTbuffer buffer);
RTAPI RTresult rtTextureSamplerGetBuffer(RTtexturesampler texturesampler, unsigned int deprecated0,
                                         unsigned int deprecated1, RTbuffer* buffer);
/* The id programs pass to rtTex* (never 0, RT_TEXTURE_ID_NULL). */
RTAPI RTresult rtTextureSamplerGetId(RTtexturesampler texturesampler, int* texture_id);

/* ---- CUDA interop (OptiX guide ch. 7) ------------------------------------------------------
 * A device's copy of a buffer lives in its worker process; a "device pointer" is host memory
 * standing for it (see docs/devices.md). `optix_device_number` is the device's ordinal in the
 * device list (rtDeviceGetDeviceCount), and must be one the context runs on. */
RTAPI RTresult rtBufferCreateForCUDA(RTcontext context, unsigned int bufferdesc, RTbuffer* buffer);
RTAPI RTresult rtBufferGetDevicePointer(RTbuffer buffer, unsigned int optix_device_number,
                                        void** device_pointer);
RTAPI RTresult rtBufferSetDevicePointer(RTbuffer buffer, unsigned int optix_device_number,
                                        void* device_pointer);

/* ---- Variable ---------------------------------------------------------------------------- */
RTAPI RTresult rtVariableSet1f(RTvariable v, float f1);
RTAPI RTresult rtVariableSet2f(RTvariable v, float f1, float f2);
RTAPI RTresult rtVariableSet3f(RTvariable v, float f1, float f2, float f3);
RTAPI RTresult rtVariableSet4f(RTvariable v, float f1, float f2, float f3, float f4);
RTAPI RTresult rtVariableSet1fv(RTvariable v, const float* f);
RTAPI RTresult rtVariableSet2fv(RTvariable v, const float* f);
RTAPI RTresult rtVariableSet3fv(RTvariable v, const float* f);
RTAPI RTresult rtVariableSet4fv(RTvariable v, const float* f);
RTAPI RTresult rtVariableSet1i(RTvariable v, int i1);
RTAPI RTresult rtVariableSet2i(RTvariable v, int i1, int i2);
RTAPI RTresult rtVariableSet3i(RTvariable v, int i1, int i2, int i3);
RTAPI RTresult rtVariableSet4i(RTvariable v, int i1, int i2, int i3, int i4);
RTAPI RTresult rtVariableSet1iv(RTvariable v, const int* i);
RTAPI RTresult rtVariableSet2iv(RTvariable v, const int* i);
RTAPI RTresult rtVariableSet3iv(RTvariable v, const int* i);
RTAPI RTresult rtVariableSet4iv(RTvariable v, const int* i);
RTAPI RTresult rtVariableSet1ui(RTvariable v, unsigned int u1);
RTAPI RTresult rtVariableSet2ui(RTvariable v, unsigned int u1, unsigned int u2);
RTAPI RTresult rtVariableSet3ui(RTvariable v, unsigned int u1, unsigned int u2, unsigned int u3);
RTAPI RTresult rtVariableSet4ui(RTvariable v, unsigned int u1, unsigned int u2, unsigned int u3,
                                unsigned int u4);
RTAPI RTresult rtVariableSet1uiv(RTvariable v, const unsigned int* u);
RTAPI RTresult rtVariableSet2uiv(RTvariable v, const unsigned int* u);
RTAPI RTresult rtVariableSet3uiv(RTvariable v, const unsigned int* u);
RTAPI RTresult rtVariableSet4uiv(RTvariable v, const unsigned int* u);
RTAPI RTresult rtVariableSetMatrix2x2fv(RTvariable v, int transpose, const float* m);
RTAPI RTresult rtVariableSetMatrix2x3fv(RTvariable v, int transpose, const float* m);
RTAPI RTresult rtVariableSetMatrix2x4fv(RTvariable v, int transpose, const float* m);
RTAPI RTresult rtVariableSetMatrix3x2fv(RTvariable v, int transpose, const float* m);
RTAPI RTresult rtVariableSetMatrix3x3fv(RTvariable v, int transpose, const float* m);
RTAPI RTresult rtVariableSetMatrix3x4fv(RTvariable v, int transpose, const float* m);
RTAPI RTresult rtVariableSetMatrix4x2fv(RTvariable v, int transpose, const float* m);
RTAPI RTresult rtVariableSetMatrix4x3fv(RTvariable v, int transpose, const float* m);
RTAPI RTresult rtVariableSetMatrix4x4fv(RTvariable v, int transpose, const float* m);
RTAPI RTresult rtVariableSetObject(RTvariable v, RTobject object);
RTAPI RTresult rtVariableSetUserData(RTvariable v, RTsize size, const void* ptr);

RTAPI RTresult rtVariableGet1f(RTvariable v, float* f1);
RTAPI RTresult rtVariableGet2f(RTvariable v, float* f1, float* f2);
RTAPI RTresult rtVariableGet3f(RTvariable v, float* f1, float* f2, float* f3);
RTAPI RTresult rtVariableGet4f(RTvariable v, float* f1, float* f2, float* f3, float* f4);
RTAPI RTresult rtVariableGet1fv(RTvariable v, float* f);
RTAPI RTresult rtVariableGet2fv(RTvariable v, float* f);
RTAPI RTresult rtVariableGet3fv(RTvariable v, float* f);
RTAPI RTresult rtVariableGet4fv(RTvariable v, float* f);
RTAPI RTresult rtVariableGet1i(RTvariable v, int* i1);
RTAPI RTresult rtVariableGet2i(RTvariable v, int* i1, int* i2);
RTAPI RTresult rtVariableGet3i(RTvariable v, int* i1, int* i2, int* i3);
RTAPI RTresult rtVariableGet4i(RTvariable v, int* i1, int* i2, int* i3, int* i4);
RTAPI RTresult rtVariableGet1iv(RTvariable v, int* i);
RTAPI RTresult rtVariableGet2iv(RTvariable v, int* i);
RTAPI RTresult rtVariableGet3iv(RTvariable v, int* i);
RTAPI RTresult rtVariableGet4iv(RTvariable v, int* i);
RTAPI RTresult rtVariableGet1ui(RTvariable v, unsigned int* u1);
RTAPI RTresult rtVariableGet2ui(RTvariable v, unsigned int* u1, unsigned int* u2);
RTAPI RTresult rtVariableGet3ui(RTvariable v, unsigned int* u1, unsigned int* u2, unsigned int* u3);
RTAPI RTresult rtVariableGet4ui(RTvariable v, unsigned int* u1, unsigned int* u2, unsigned int* u3,
                                unsigned int* u4);
RTAPI RTresult rtVariableGet1uiv(RTvariable v, unsigned int* u);
RTAPI RTresult rtVariableGet2uiv(RTvariable v, unsigned int* u);
RTAPI RTresult rtVariableGet3uiv(RTvariable v, unsigned int* u);
RTAPI RTresult rtVariableGet4uiv(RTvariable v, unsigned int* u);
RTAPI RTresult rtVariableGetMatrix2x2fv(RTvariable v, int transpose, float* m);
RTAPI RTresult rtVariableGetMatrix2x3fv(RTvariable v, int transpose, float* m);
RTAPI RTresult rtVariableGetMatrix2x4fv(RTvariable v, int transpose, float* m);
RTAPI RTresult rtVariableGetMatrix3x2fv(RTvariable v, int transpose, float* m);
RTAPI RTresult rtVariableGetMatrix3x3fv(RTvariable v, int transpose, float* m);
RTAPI RTresult rtVariableGetMatrix3x4fv(RTvariable v, int transpose, float* m);
RTAPI RTresult rtVariableGetMatrix4x2fv(RTvariable v, int transpose, float* m);
RTAPI RTresult rtVariableGetMatrix4x3fv(RTvariable v, int transpose, float* m);
RTAPI RTresult rtVariableGetMatrix4x4fv(RTvariable v, int transpose, float* m);
RTAPI RTresult rtVariableGetObject(RTvariable v, RTobject* object);
RTAPI RTresult rtVariableGetUserData(RTvariable v, RTsize size, void* ptr);
RTAPI RTresult rtVariableGetName(RTvariable v, const char** name_return);
RTAPI RTresult rtVariableGetAnnotation(RTvariable v, const char** annotation_return);
RTAPI RTresult rtVariableGetType(RTvariable v, RTobjecttype* type_return);
RTAPI RTresult rtVariableGetContext(RTvariable v, RTcontext* context);
RTAPI RTresult rtVariableGetSize(RTvariable v, RTsize* size);

#ifdef __cplusplus
}
#endif

#endif /* TESSERA_RT_H_ */
