// Program-side API: what an OptiX 3-6 program written in CUDA C needs to compile as C++ and run on
// Tessera. A program module is a shared library built from such code with
//   g++ -std=c++17 -O2 -shared -fPIC -x c++ -D__CUDACC__ -I<tessera>/api/include
//       -I<tessera>/api/include/optixu prog.cu -o prog.so
// (optix.h includes this header only where __CUDACC__ is defined, as OptiX's includes
// optix_device.h; included by name it works without).
//
// How it works: every rtDeclareVariable is a thread_local object registered (name, semantic,
// size, slot address) with the module's registry; before a program runs the engine copies the
// value resolved through the program's scope chain into the calling thread's slot. rtBuffer
// objects hold a slot index into the running program's table of buffer views, found through a
// thread-local pointer of the engine at a fixed offset from the thread pointer. Everything else
// calls the engine through the TesseraRuntime table handed over when the module is loaded.
//
// Module variables use the local-dynamic TLS model: a program finds the module's thread-local
// block once (one __tls_get_addr call) and reaches every variable at a fixed offset from it,
// where the default model for -fPIC code pays one call per variable access. The module's second
// build (TESSERA_TLS_INITIAL_EXEC, below) makes them initial-exec: no call at all, for processes
// with static TLS to spare.
#ifndef TESSERA_DEVICE_H_
#define TESSERA_DEVICE_H_

// clang-format off: before every other #include (see there)
#include "tessera/detail/program_prelude.h"
// clang-format on

#if __cplusplus < 201703L
#error \
    "Tessera's program-side API (which optix.h includes in C++) needs C++17: compile with -std=c++17, or include <tessera/rt.h> for the host API alone"
#endif

#include <cstdarg>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <deque>
#include <string>
#include <vector>

#include "internal/optix_datatypes.h"
#include "optixu/optixu_vector_functions.h"
#include "optixu/optixu_vector_types.h"
#include "tessera/cuda_compat.h"
#include "tessera/detail/module_abi.h"
#include "tessera/rt.h"

// optix.h in host code defines these two to say that the program-side API needs __CUDACC__.
#undef rtDeclareVariable
#undef rtBuffer

#define RT_PROGRAM extern "C" __attribute__((visibility("default"), used))
// Exported under its own name as well, so that rtProgramCreateFromPTXFile finds it for an
// rtCallableProgram variable; other programs of the module may still call it directly.
#define RT_CALLABLE_PROGRAM extern "C" __attribute__((visibility("default"), used))
#define RT_INTERNAL_CALLABLE_PROGRAM

// A node of the graph (Group, GeometryGroup, Transform, Selector) as programs see it.
struct rtObject {
  unsigned long long handle;
};

#pragma GCC visibility push(hidden)
namespace tessera {
namespace detail {

struct ModuleRegistry {
  std::vector<TesseraVariableDecl> variables;
  std::deque<std::string> names;  // namespace-qualified variable names the declarations point at
  std::vector<TesseraBufferDecl> buffers;
  TesseraModuleInfo info;
};

inline ModuleRegistry& Registry() {
  static ModuleRegistry registry;
  return registry;
}

inline const TesseraRuntime* g_runtime = nullptr;
inline const TesseraRuntime* Rt() { return g_runtime; }

// Built with TESSERA_TLS_INITIAL_EXEC (the second build Tessera's compile cache and
// tessera_add_program_module embed in each module, docs/programs.md "Thread-local storage"),
// variables are initial-exec: one load from the thread pointer, no call, for processes that
// reserve static TLS for modules (Tessera's workers do).
#if defined(TESSERA_TLS_INITIAL_EXEC)
#define TESSERA_TLS __attribute__((tls_model("initial-exec")))
#else
#define TESSERA_TLS __attribute__((tls_model("local-dynamic")))
#endif

inline long long g_buffer_table_offset = 0;
inline long long g_texture_table_offset = 0;
inline long long g_texture_id_table_offset = 0;

// The pointer the engine keeps in static TLS at `offset` from the thread pointer
// (TesseraRuntime::buffer_table_offset and the like): one load, no call.
template <typename T>
inline T* AtThreadPointer(long long offset) {
  T* p;
#if defined(__x86_64__)
  __asm__("movq %%fs:(%1), %0" : "=r"(p) : "r"(offset));
#else
  p = *reinterpret_cast<T* const*>(static_cast<const char*>(__builtin_thread_pointer()) + offset);
#endif
  return p;
}

// The running program's buffer views. Not volatile: the table stays the same for the whole run
// of a program (nested programs restore it before control returns), so the compiler may keep it.
inline const TesseraBufferView* BufferTable() {
  return AtThreadPointer<const TesseraBufferView>(g_buffer_table_offset);
}

// The name of a variable declared inside namespaces, as the host names it (OptiX guide: "ns::v").
// `where` is __PRETTY_FUNCTION__ of a function of a struct `marker` that rtDeclareVariable
// defines beside the variable, so it spells the enclosing namespaces ("static const char*
// ns::inner::marker::Where()"); anonymous namespaces are left out of the name.
inline const char* QualifiedName(const char* where, const char* marker, const char* name) {
  std::string w = where;
  for (const char* anonymous : {"{anonymous}::", "(anonymous namespace)::"}) {  // GCC, Clang
    for (size_t i = w.find(anonymous); i != std::string::npos; i = w.find(anonymous)) {
      w.erase(i, std::strlen(anonymous));
    }
  }
  const size_t at = w.find(std::string(marker) + "::");
  if (at == std::string::npos) return name;
  size_t begin = w.find_last_of(" *&", at);
  begin = begin == std::string::npos ? 0 : begin + 1;
  const std::string scope = w.substr(begin, at - begin);  // "" or "ns::inner::"
  if (scope.empty()) return name;
  return Registry().names.emplace_back(scope + name).c_str();
}

struct VariableRegistration {
  VariableRegistration(const char* name, const char* semantic, const char* annotation,
                       const char* type_name, size_t size, void* (*address)()) {
    Registry().variables.push_back({name, semantic, annotation, type_name, size, address});
  }
};

inline unsigned RegisterBuffer(const void* object, size_t element_size, unsigned dim) {
  auto& buffers = Registry().buffers;
  buffers.push_back({object, element_size, dim});
  return static_cast<unsigned>(buffers.size() - 1);
}

__attribute__((format(printf, 1, 2))) inline void Print(const char* format, ...) {
  if (!Rt()->print_active()) return;
  char text[2048];
  va_list args, again;
  va_start(args, format);
  va_copy(again, args);
  const int n = std::vsnprintf(text, sizeof(text), format, args);
  va_end(args);
  if (n >= static_cast<int>(sizeof(text))) {  // longer than the stack buffer: format it whole
    std::string whole(static_cast<size_t>(n), '\0');
    std::vsnprintf(whole.data(), whole.size() + 1, format, again);
    Rt()->print(whole.c_str());
  } else if (n >= 0) {
    Rt()->print(text);
  }
  va_end(again);
}

inline float3 Transform(RTtransformkind kind, unsigned what, const float3& v) {
  float3 out;
  Rt()->transform(static_cast<unsigned>(kind), what, &v.x, &out.x);
  return out;
}

}  // namespace detail
}  // namespace tessera
#pragma GCC visibility pop

extern "C" __attribute__((weak, visibility("default"))) const TesseraModuleInfo*
tessera_module_init(const TesseraRuntime* runtime, unsigned abi_version) {
  if (abi_version != TESSERA_MODULE_ABI_VERSION || runtime == nullptr) return nullptr;
  auto& r = tessera::detail::Registry();
  tessera::detail::g_runtime = runtime;
  tessera::detail::g_buffer_table_offset = runtime->buffer_table_offset;
  tessera::detail::g_texture_table_offset = runtime->texture_table_offset;
  tessera::detail::g_texture_id_table_offset = runtime->texture_id_table_offset;
  r.info.abi_version = TESSERA_MODULE_ABI_VERSION;
  r.info.variable_count = static_cast<unsigned>(r.variables.size());
  r.info.variables = r.variables.data();
  r.info.buffer_count = static_cast<unsigned>(r.buffers.size());
  r.info.buffers = r.buffers.data();
  // How this translation unit was compiled: tessera_add_program_module(... FAST_MATH) and the
  // host's compile for a context with TESSERA_ACCURACY_FAST_MATH define TESSERA_FAST_MATH; a
  // module built with plain -ffast-math has __FAST_MATH__ (docs/fast_math.md).
#if defined(TESSERA_FAST_MATH) || defined(__FAST_MATH__)
  r.info.flags = TESSERA_MODULE_FLAG_FAST_MATH;
#else
  r.info.flags = 0;
#endif
  return &r.info;
}

// rtDeclareVariable(type, name, semantic, annotation) [= initializer];
// A variable declared inside namespaces registers under its qualified name ("ns::name"), which
// is what the host declares, as in OptiX.
// The semantic of a bound callable program type (rtCallableProgramX) is rtCallableProgram
// (SemanticOf, tessera/detail/bindless.h).
#define rtDeclareVariable(type, name, semantic, annotation)                             \
  extern __attribute__((visibility("hidden"))) thread_local TESSERA_TLS type name;      \
  struct tessera_scope_of_##name {                                                      \
    static const char* Where() { return __PRETTY_FUNCTION__; }                          \
  };                                                                                    \
  static ::tessera::detail::VariableRegistration tessera_variable_##name(               \
      ::tessera::detail::QualifiedName(tessera_scope_of_##name::Where(),                \
                                       "tessera_scope_of_" #name, #name),               \
      ::tessera::detail::SemanticOf<type>(#semantic), #annotation, #type, sizeof(type), \
      []() -> void* { return const_cast<void*>(static_cast<const void*>(&name)); });    \
  __attribute__((visibility("hidden"))) thread_local TESSERA_TLS type name

#define rtDeclareAnnotation(variable, annotation)

// ---- Callable programs (OptiX 3.0) ---------------------------------------------------------
namespace tessera::detail {
template <typename Signature>
class CallableProgram;
// An rtCallableProgram variable: the engine stores in the calling thread's slot its binding of
// the program the variable names through the caller's scopes (OptiX guide, "Callable Programs").
// A call makes that program the running one, with its own variables looked up from its own
// scope and then the caller's, and calls its function directly.
template <typename R, typename... A>
class CallableProgram<R(A...)> {
 public:
  R operator()(A... args) const {
    TesseraCallFrame frame;
    auto* function = reinterpret_cast<R (*)(A...)>(Rt()->callable_enter(this, &frame));
    struct Leave {
      TesseraCallFrame* frame;
      ~Leave() { Rt()->callable_leave(frame); }  // also when rtThrow unwinds the call
    } leave{&frame};
    return function(args...);
  }

 private:
  const void* binding_;
};
}  // namespace tessera::detail

// rtCallableProgram(return_type, name, (parameter types)): `name(args)` calls the
// RT_CALLABLE_PROGRAM the host set on the variable with rtVariableSetObject. Signatures are not
// checked (a module's symbols carry none): the program must take and return what the variable
// says, as in C.
#define rtCallableProgram(return_type, name, parameters)                              \
  rtDeclareVariable(::tessera::detail::CallableProgram<return_type parameters>, name, \
                    rtCallableProgram, )

// Pointers to a program's locals passed to callable programs (OptiX 3.0, for SM 1.x GPUs): on a
// CPU a pointer is a pointer, so pickling keeps it as it is.
struct rtPickledLocalPointer {
  void* pointer;
  // What rtUnpickleLocalPointer gives: converts to a pointer of the type the program wants.
  struct Unpickled {
    void* pointer;
    template <typename T>
    operator T*() const {
      return static_cast<T*>(pointer);
    }
  };
};
template <typename T>
inline rtPickledLocalPointer rtPickleLocalPointer(T* pointer) {
  return {const_cast<void*>(static_cast<const void*>(pointer))};
}
inline rtPickledLocalPointer::Unpickled rtUnpickleLocalPointer(rtPickledLocalPointer p) {
  return {p.pointer};
}

namespace optix {

struct size_t2 {
  size_t x, y;
};
struct size_t3 {
  size_t x, y, z;
};
inline size_t2 make_size_t2(size_t x, size_t y) { return {x, y}; }
inline size_t3 make_size_t3(size_t x, size_t y, size_t z) { return {x, y, z}; }

}  // namespace optix

// Conversions SDK programs apply to buffer sizes, e.g. make_float2(output_buffer.size()).
inline float2 make_float2(const optix::size_t2& s) {
  return make_float2(static_cast<float>(s.x), static_cast<float>(s.y));
}
inline float3 make_float3(const optix::size_t3& s) {
  return make_float3(static_cast<float>(s.x), static_cast<float>(s.y), static_cast<float>(s.z));
}
inline uint2 make_uint2(const optix::size_t2& s) {
  return make_uint2(static_cast<unsigned>(s.x), static_cast<unsigned>(s.y));
}
inline uint3 make_uint3(const optix::size_t3& s) {
  return make_uint3(static_cast<unsigned>(s.x), static_cast<unsigned>(s.y),
                    static_cast<unsigned>(s.z));
}
inline int2 make_int2(const optix::size_t2& s) {
  return make_int2(static_cast<int>(s.x), static_cast<int>(s.y));
}

namespace optix {

template <typename T, int Dim>
struct BufferSize;
template <typename T>
struct BufferSize<T, 1> {
  using type = size_t;
};
template <typename T>
struct BufferSize<T, 2> {
  using type = size_t2;
};
template <typename T>
struct BufferSize<T, 3> {
  using type = size_t3;
};

}  // namespace optix

namespace tessera::detail {

// Raises a mark to `epoch`, never lowers it (a thread still in an older epoch must not hide a
// newer write from the engine). Written only when lower: threads working on one block would
// otherwise take turns owning its cache line with every access.
inline void MarkAtLeast(unsigned char* mark, unsigned char epoch) {
  unsigned char seen = __atomic_load_n(mark, __ATOMIC_RELAXED);
  while (seen < epoch && !__atomic_compare_exchange_n(mark, &seen, epoch, /*weak=*/true,
                                                      __ATOMIC_RELAXED, __ATOMIC_RELAXED)) {
  }
}

// Element access of rtBuffer and rtBufferId (one code for both, write marks included):
// operator[] for every index type OptiX takes and size(). `Derived` gives View(), the buffer's
// view, and OutOfBounds(x, y, z), what an index outside it reaches.
template <typename Derived, typename T, int Dim>
class BufferAccess {
  static_assert(Dim >= 1 && Dim <= 3, "buffer dimensionality must be 1, 2 or 3");

 public:
  typename optix::BufferSize<T, Dim>::type size() const {
    const TesseraBufferView& v = Self().View();
    if constexpr (Dim == 1) {
      return v.size[0];
    } else if constexpr (Dim == 2) {
      return optix::make_size_t2(v.size[0], v.size[1]);
    } else {
      return optix::make_size_t3(v.size[0], v.size[1], v.size[2]);
    }
  }

  T& operator[](unsigned long long i) const { return At<1>(i, 0, 0); }
  T& operator[](long long i) const { return At<1>(static_cast<unsigned long long>(i), 0, 0); }
  T& operator[](unsigned int i) const { return At<1>(i, 0, 0); }
  T& operator[](int i) const { return At<1>(static_cast<unsigned long long>(i), 0, 0); }
  T& operator[](unsigned long i) const { return At<1>(i, 0, 0); }
  T& operator[](long i) const { return At<1>(static_cast<unsigned long long>(i), 0, 0); }
  T& operator[](const uint2& i) const { return At<2>(i.x, i.y, 0); }
  T& operator[](const int2& i) const { return At<2>(Idx(i.x), Idx(i.y), 0); }
  T& operator[](const optix::size_t2& i) const { return At<2>(i.x, i.y, 0); }
  T& operator[](const uint3& i) const { return At<3>(i.x, i.y, i.z); }
  T& operator[](const int3& i) const { return At<3>(Idx(i.x), Idx(i.y), Idx(i.z)); }
  T& operator[](const optix::size_t3& i) const { return At<3>(i.x, i.y, i.z); }

 private:
  const Derived& Self() const { return static_cast<const Derived&>(*this); }
  static unsigned long long Idx(int i) { return static_cast<unsigned long long>(i); }
  // K: how many index components the caller gave; the others are 0. Dimensions past the
  // buffer's own are 1 (the engine gives only buffers of this dimensionality), so a 0 there is
  // always inside and only the first max(K, Dim) components need a check.
  template <int K>
  T& At(unsigned long long x, unsigned long long y, unsigned long long z) const {
    constexpr int kChecked = K > Dim ? K : Dim;
    const TesseraBufferView& v = Self().View();
    if (x >= v.size[0] || (kChecked >= 2 && y >= v.size[1]) || (kChecked >= 3 && z >= v.size[2])) {
      return *static_cast<T*>(Self().OutOfBounds(x, y, z));
    }
    const unsigned long long i = kChecked == 1   ? x
                                 : kChecked == 2 ? y * v.size[0] + x
                                                 : (z * v.size[1] + y) * v.size[0] + x;
    // operator[] cannot tell a read from a write: any access of a gathered buffer marks the
    // element and its block with the device's write epoch.
    if (v.written != nullptr) {
      const unsigned char epoch = __atomic_load_n(v.write_epoch, __ATOMIC_RELAXED);
      // While the engine gathers a block's first rays (TESSERA_COLLECTING_EPOCH), an access to a
      // buffer programs may write ends that; the launch index then runs alone.
      if (__builtin_expect(epoch == TESSERA_COLLECTING_EPOCH, 0)) {
        return *static_cast<T*>(Self().OutOfBounds(x, y, z));
      }
      MarkAtLeast(&v.written[i], epoch);
      MarkAtLeast(&v.written_blocks[i >> TESSERA_WRITTEN_BLOCK_SHIFT], epoch);
    }
    return static_cast<T*>(v.data)[i];
  }
};

}  // namespace tessera::detail

namespace optix {

// rtBuffer<T, Dim>: a view of a buffer bound through the program's scope chain. Indices outside
// the buffer raise RT_EXCEPTION_BUFFER_INDEX_OUT_OF_BOUNDS (or read zeroed scratch when off).
template <typename T, int Dim = 1>
class buffer : public ::tessera::detail::BufferAccess<buffer<T, Dim>, T, Dim> {
 public:
  buffer() : slot_(::tessera::detail::RegisterBuffer(this, sizeof(T), Dim)) {}
  buffer(const buffer&) = delete;
  buffer& operator=(const buffer&) = delete;

 private:
  friend class ::tessera::detail::BufferAccess<buffer<T, Dim>, T, Dim>;
  const TesseraBufferView& View() const { return ::tessera::detail::BufferTable()[slot_]; }
  void* OutOfBounds(unsigned long long x, unsigned long long y, unsigned long long z) const {
    return ::tessera::detail::Rt()->buffer_index_error(slot_, x, y, z);
  }

  unsigned slot_;
};

}  // namespace optix

#define rtBuffer ::optix::buffer

#include "tessera/detail/texture.h"

// rtBufferId, rtCallableProgramId, rtCallableProgramX (OptiX 3.5+).
#include "tessera/detail/bindless.h"

// ---- Tracing ---------------------------------------------------------------------------------
// OptiX 6 ray flags and visibility mask, with OptiX's names and values. The engine honours
// DISABLE_ANYHIT, TERMINATE_ON_FIRST_HIT (the first hit found is the one shaded),
// DISABLE_CLOSESTHIT and the mask (every geometry has the default mask 0xFF: a mask with none of
// those bits misses everything); FORCE_ANYHIT and the CULL_*_ANYHIT flags follow from there being
// no geometry or instance flags. Face culling fails the launch with a message
// (docs/COMPATIBILITY.md).
typedef enum {
  RT_RAY_FLAG_NONE = 0u,
  RT_RAY_FLAG_DISABLE_ANYHIT = 1u << 0,
  RT_RAY_FLAG_FORCE_ANYHIT = 1u << 1,
  RT_RAY_FLAG_TERMINATE_ON_FIRST_HIT = 1u << 2,
  RT_RAY_FLAG_DISABLE_CLOSESTHIT = 1u << 3,
  RT_RAY_FLAG_CULL_BACK_FACING_TRIANGLES = 1u << 4,
  RT_RAY_FLAG_CULL_FRONT_FACING_TRIANGLES = 1u << 5,
  RT_RAY_FLAG_CULL_DISABLED_ANYHIT = 1u << 6,
  RT_RAY_FLAG_CULL_ENABLED_ANYHIT = 1u << 7
} RTrayflags;
typedef unsigned int RTvisibilitymask;
enum { RT_VISIBILITY_ALL = 0xFFu };

// rtTrace(top, ray, payload [, mask, flags]): traces `ray` from `top`, running the programs the
// hit (or miss) selects, which read and write `payload`.
template <typename T>
inline void rtTrace(rtObject top, const optix::Ray& ray, T& payload) {
  ::tessera::detail::Rt()->trace(top.handle, &ray, &payload, sizeof(T));
}
template <typename T>
inline void rtTrace(rtObject top, const optix::Ray& ray, T& payload, RTvisibilitymask mask,
                    RTrayflags flags = RT_RAY_FLAG_NONE) {
  ::tessera::detail::Rt()->trace_with_flags(top.handle, &ray, &payload, sizeof(T), mask, flags, 0,
                                            0.f);
}
// OptiX 5-6: the ray's time for motion blur, which the programs it runs read as rtCurrentTime (a
// ray traced without one takes its caller's). Tessera has no motion transforms or geometry, so
// every time sees the same scene.
template <typename T>
inline void rtTrace(rtObject top, const optix::Ray& ray, float time, T& payload,
                    RTvisibilitymask mask = RT_VISIBILITY_ALL,
                    RTrayflags flags = RT_RAY_FLAG_NONE) {
  ::tessera::detail::Rt()->trace_with_flags(top.handle, &ray, &payload, sizeof(T), mask, flags, 1,
                                            time);
}

inline bool rtPotentialIntersection(float t) {
  return ::tessera::detail::Rt()->potential_intersection(t) != 0;
}
inline bool rtReportIntersection(unsigned int material) {
  return ::tessera::detail::Rt()->report_intersection(material) != 0;
}
// As in OptiX, neither returns in an any-hit program: the engine ends the program there (with
// longjmp, so its automatic objects' destructors do not run). In a miss program rtTerminateRay
// returns and does nothing.
inline void rtIgnoreIntersection() { ::tessera::detail::Rt()->ignore_intersection(); }
inline void rtTerminateRay() { ::tessera::detail::Rt()->terminate_ray(); }
inline void rtIntersectChild(unsigned int index) {
  ::tessera::detail::Rt()->intersect_child(index);
}

// ---- Built-in triangles (OptiX 6 GeometryTriangles) ---------------------------------------------
// The index of the primitive hit (plus the GeometryTriangles' primitive index offset): attribute,
// any hit and closest hit programs, and intersection programs (the primitive being tested).
inline unsigned int rtGetPrimitiveIndex() { return ::tessera::detail::Rt()->primitive_index(); }
// Whether the hit is on built-in triangles, and on which face: the front face winds
// counter-clockwise seen from the ray. Attribute, any hit and closest hit programs.
inline bool rtIsTriangleHit() { return ::tessera::detail::Rt()->triangle_hit() != 0; }
inline bool rtIsTriangleHitFrontFace() { return ::tessera::detail::Rt()->triangle_hit() == 1; }
inline bool rtIsTriangleHitBackFace() { return ::tessera::detail::Rt()->triangle_hit() == 2; }
// The weights of the triangle's second and third vertex at the hit. Attribute programs only; other
// programs declare `attribute rtTriangleBarycentrics` (a float2) when there is no attribute
// program.
inline float2 rtGetTriangleBarycentrics() {
  float2 uv;
  ::tessera::detail::Rt()->triangle_barycentrics(&uv.x);
  return uv;
}

// ---- Transforms --------------------------------------------------------------------------------
inline float3 rtTransformPoint(RTtransformkind kind, const float3& p) {
  return ::tessera::detail::Transform(kind, TESSERA_TRANSFORM_POINT, p);
}
inline float3 rtTransformVector(RTtransformkind kind, const float3& v) {
  return ::tessera::detail::Transform(kind, TESSERA_TRANSFORM_VECTOR, v);
}
inline float3 rtTransformNormal(RTtransformkind kind, const float3& n) {
  return ::tessera::detail::Transform(kind, TESSERA_TRANSFORM_NORMAL, n);
}
inline void rtGetTransform(RTtransformkind kind, float matrix[16]) {
  ::tessera::detail::Rt()->get_transform(static_cast<unsigned>(kind), matrix);
}

// ---- Accuracy (Tessera; tessera/accuracy.h, docs/accuracy.md) -------------------------------
// The origin for a ray that leaves the current hit in world direction `direction`: the hit point
// moved past its floating-point error bound to the side `direction` points to, so that the ray
// cannot hit the surface again and needs no scene_epsilon (trace it with tmin 0). Exact for
// triangles (native or GeometryTriangles); for an intersection program's hit, the point
// ray.origin + t * ray.direction moved along `direction` by its error bound. Closest-hit and
// any-hit programs.
inline float3 tesseraSpawnPoint(const float3& direction) {
  float3 origin;
  ::tessera::detail::Rt()->spawn_point(&direction.x, &origin.x);
  return origin;
}

// ---- Exceptions and printing -------------------------------------------------------------------
inline void rtThrow(unsigned int code) { ::tessera::detail::Rt()->throw_exception(code); }
inline unsigned int rtGetExceptionCode() { return ::tessera::detail::Rt()->exception_code(); }
inline void rtPrintExceptionDetails() { ::tessera::detail::Rt()->print_exception_details(); }

#define rtPrintf(...) ::tessera::detail::Print(__VA_ARGS__)

#endif  // TESSERA_DEVICE_H_
