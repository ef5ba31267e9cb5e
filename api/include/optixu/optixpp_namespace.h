// OptiXpp: the C++ wrapper of the OptiX C API (OptiX 3 Programming Guide, chapter 8), in
// namespace optix. Header-only; it depends only on tessera/rt.h and the vector types.
//
// Lifetime, as in OptiX: a Handle<T> counts references to its wrapper object (the *Obj), and the
// last Handle to go deletes the wrapper. It does not destroy the API object the wrapper stands
// for: call destroy() (or destroy the context, which takes every object of it along). This is what
// makes the usual OptiX idioms work, e.g. `gg->setChild(0, ctx->createGeometryInstance(...))` with
// a temporary handle, and getChild()/getContext() returning fresh handles to existing objects.
//
// Errors: every member that calls the C API throws optix::Exception carrying the call's RTresult
// and the message rtContextGetErrorString gives for it. Destructors never throw.
#ifndef OPTIXU_OPTIXPP_NAMESPACE_H_
#define OPTIXU_OPTIXPP_NAMESPACE_H_

// clang-format off: before every other #include (see there)
#include "../tessera/detail/program_prelude.h"
// clang-format on

#include <atomic>
#include <cstddef>
#include <exception>
#include <functional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "optixu/optixu_vector_types.h"
#include "tessera/rt.h"

namespace optix {

#ifndef TESSERA_DEVICE_H_
#define TESSERA_OPTIXPP_HOST_ID_TYPES_
// Host-side id types (OptiX 3.6), so that host code can fill mapped buffers of RT_FORMAT_BUFFER_ID
// and RT_FORMAT_PROGRAM_ID elements, or structs a program reads, with the types programs declare:
// each is just the int id. A program module gets the usable ones from tessera/device.h (included
// first, they replace these).
template <typename T, int Dim = 1>
class bufferId {
 public:
  bufferId() = default;
  bufferId(int id) : id_(id) {}  // NOLINT: implicit, as OptiX's host version
  int getId() const { return id_; }

 private:
  int id_ = RT_BUFFER_ID_NULL;
};
template <typename Signature>
class callableProgramId {
 public:
  callableProgramId() = default;
  callableProgramId(int id) : id_(id) {}  // NOLINT: implicit, as OptiX's host version
  int getId() const { return id_; }

 private:
  int id_ = RT_PROGRAM_ID_NULL;
};
#endif

class AccelerationObj;
class BufferObj;
class ContextObj;
class GeometryObj;
class GeometryTrianglesObj;
class GeometryGroupObj;
class GeometryInstanceObj;
class GroupObj;
class MaterialObj;
class ProgramObj;
class SelectorObj;
class TextureSamplerObj;
class TransformObj;
class VariableObj;

template <class T>
class Handle;

typedef Handle<AccelerationObj> Acceleration;
typedef Handle<BufferObj> Buffer;
typedef Handle<ContextObj> Context;
typedef Handle<GeometryObj> Geometry;
typedef Handle<GeometryTrianglesObj> GeometryTriangles;
typedef Handle<GeometryGroupObj> GeometryGroup;
typedef Handle<GeometryInstanceObj> GeometryInstance;
typedef Handle<GroupObj> Group;
typedef Handle<MaterialObj> Material;
typedef Handle<ProgramObj> Program;
typedef Handle<SelectorObj> Selector;
typedef Handle<TextureSamplerObj> TextureSampler;
typedef Handle<TransformObj> Transform;
typedef Handle<VariableObj> Variable;

// ---- Exception ------------------------------------------------------------------------------

// An OptiX error: the RTresult and its message. User code may throw it too.
class Exception : public std::exception {
 public:
  explicit Exception(const std::string& message, RTresult error_code = RT_ERROR_UNKNOWN)
      : message_(message), error_code_(error_code) {}
  ~Exception() noexcept override {}

  const std::string& getErrorString() const { return message_; }
  RTresult getErrorCode() const { return error_code_; }
  const char* what() const noexcept override { return message_.c_str(); }

  // The exception for `code` with the message rtContextGetErrorString gives for it on `context`
  // (which may be null: Tessera then reports the calling thread's newest message for the code).
  static Exception makeException(RTresult code, RTcontext context) {
    const char* message = nullptr;
    rtContextGetErrorString(context, code, &message);
    return Exception(message != nullptr ? message : "unknown OptiX error", code);
  }

 private:
  std::string message_;
  RTresult error_code_;
};

namespace optixpp_detail {

// Wrapper objects alive in the process; tests use it to see that the last Handle deletes one.
inline std::atomic<long>& LiveObjectCount() {
  static std::atomic<long> count{0};
  return count;
}

inline void Check(RTresult code, RTcontext context) {
  if (code != RT_SUCCESS) throw Exception::makeException(code, context);
}

// The RTobjecttype that a node wrapper stands for (getChild<T> checks it); only node kinds.
template <class T>
struct NodeType;
template <>
struct NodeType<GroupObj> {
  static constexpr RTobjecttype value = RT_OBJECTTYPE_GROUP;
};
template <>
struct NodeType<GeometryGroupObj> {
  static constexpr RTobjecttype value = RT_OBJECTTYPE_GEOMETRY_GROUP;
};
template <>
struct NodeType<TransformObj> {
  static constexpr RTobjecttype value = RT_OBJECTTYPE_TRANSFORM;
};
template <>
struct NodeType<SelectorObj> {
  static constexpr RTobjecttype value = RT_OBJECTTYPE_SELECTOR;
};

// The name of a node kind, for messages.
inline const char* KindName(RTobjecttype type) {
  switch (type) {
    case RT_OBJECTTYPE_GROUP:
      return "group";
    case RT_OBJECTTYPE_GEOMETRY_GROUP:
      return "geometry group";
    case RT_OBJECTTYPE_TRANSFORM:
      return "transform";
    case RT_OBJECTTYPE_SELECTOR:
      return "selector";
    default:
      return "object of another kind";
  }
}

}  // namespace optixpp_detail

// ---- Handle ---------------------------------------------------------------------------------

// A counted reference to a wrapper object. Handles compare equal when they stand for the same
// API object (or are both null), whichever wrappers they hold.
template <class T>
class Handle {
 public:
  typedef T element_type;

  Handle() : ptr_(nullptr) {}
  Handle(T* ptr) : ptr_(ptr) { Retain(); }  // NOLINT: implicit, so `handle = 0;` resets it
  template <class U, class = typename std::enable_if<std::is_convertible<U*, T*>::value>::type>
  Handle(U* ptr) : ptr_(ptr) {  // NOLINT
    Retain();
  }
  Handle(const Handle& copy) : ptr_(copy.ptr_) { Retain(); }
  template <class U, class = typename std::enable_if<std::is_convertible<U*, T*>::value>::type>
  Handle(const Handle<U>& copy) : ptr_(copy.get()) {  // NOLINT
    Retain();
  }
  Handle(Handle&& other) noexcept : ptr_(other.ptr_) { other.ptr_ = nullptr; }
  ~Handle() { Release(); }

  Handle& operator=(const Handle& copy) {
    Handle(copy).swap(*this);
    return *this;
  }
  Handle& operator=(Handle&& other) noexcept {
    Handle(std::move(other)).swap(*this);
    return *this;
  }
  template <class U, class = typename std::enable_if<std::is_convertible<U*, T*>::value>::type>
  Handle& operator=(const Handle<U>& copy) {
    Handle(copy).swap(*this);
    return *this;
  }

  // A new handle (and wrapper) for an API object made through the C API; null gives a null
  // handle. The API object is not copied or retained: it lives until it is destroyed.
  // (A template so that T may be incomplete where Handle<T> is named.)
  template <class A = T>
  static Handle<T> take(typename A::api_t p) {
    return p ? Handle<T>(new T(p)) : Handle<T>();
  }
  template <class A = T>
  static Handle<T> take(RTobject p) {
    return take<A>(static_cast<typename A::api_t>(p));
  }

  // Context::create(): a new context.
  static Handle<T> create() { return T::create(); }
  // Context::getDeviceCount(): the devices a context may use.
  static unsigned int getDeviceCount() { return T::getDeviceCount(); }

  T* operator->() const {
    if (ptr_ == nullptr) {
      throw Exception("optix::Handle: member access through a null handle", RT_ERROR_INVALID_VALUE);
    }
    return ptr_;
  }
  T& operator*() const { return *operator->(); }
  // The wrapper; `handle->get()` is the API object.
  T* get() const { return ptr_; }
  explicit operator bool() const { return ptr_ != nullptr; }

  // Scoped objects: the variable `name`, declared first if the object has none of that name.
  Handle<VariableObj> operator[](const std::string& name) const { return (*operator->())[name]; }
  Handle<VariableObj> operator[](const char* name) const { return (*operator->())[name]; }

  void swap(Handle& other) noexcept { std::swap(ptr_, other.ptr_); }

  // The API object, or null.
  const void* raw() const {
    return ptr_ != nullptr ? static_cast<const void*>(ptr_->get()) : nullptr;
  }

  friend bool operator==(const Handle& a, const Handle& b) { return a.raw() == b.raw(); }
  friend bool operator!=(const Handle& a, const Handle& b) { return a.raw() != b.raw(); }
  friend bool operator<(const Handle& a, const Handle& b) {
    return std::less<const void*>()(a.raw(), b.raw());
  }

 private:
  void Retain() {
    if (ptr_ != nullptr) ptr_->addReference();
  }
  void Release() {
    if (ptr_ != nullptr && ptr_->removeReference() == 0) delete ptr_;
    ptr_ = nullptr;
  }

  T* ptr_;
};

template <class T, class U>
bool operator==(const Handle<T>& a, const Handle<U>& b) {
  return a.raw() == b.raw();
}
template <class T, class U>
bool operator!=(const Handle<T>& a, const Handle<U>& b) {
  return a.raw() != b.raw();
}

namespace optixpp_detail {
// The API object of `h`, or null: null handles reach the C API, which decides what null means.
template <class T>
typename T::api_t Raw(const Handle<T>& h) {
  return h ? h.get()->get() : nullptr;
}
}  // namespace optixpp_detail

// ---- Attribute classes ----------------------------------------------------------------------

// Every wrapper: reference count, context, error checking.
class APIObj {
 public:
  APIObj(const APIObj&) = delete;
  APIObj& operator=(const APIObj&) = delete;
  virtual ~APIObj() { --optixpp_detail::LiveObjectCount(); }

  void addReference() { ref_count_.fetch_add(1, std::memory_order_relaxed); }
  int removeReference() { return ref_count_.fetch_sub(1, std::memory_order_acq_rel) - 1; }

  // The context this object belongs to (throws for a destroyed object).
  virtual Context getContext() const = 0;

  // Throws the Exception for `code` unless it is RT_SUCCESS.
  void checkError(RTresult code) const { optixpp_detail::Check(code, context_); }
  void checkError(RTresult code, Context context) const;
  void checkErrorNoGetContext(RTresult code, RTcontext context) const {
    optixpp_detail::Check(code, context);
  }
  static Exception makeException(RTresult code, RTcontext context) {
    return Exception::makeException(code, context);
  }

 protected:
  // `context` is kept for error messages: asking a destroyed object for its context would
  // replace the message of the failed call with one about the query.
  explicit APIObj(RTcontext context) : context_(context), ref_count_(0) {
    ++optixpp_detail::LiveObjectCount();
  }

  RTcontext context_;

 private:
  std::atomic<int> ref_count_;
};

// Objects with rt*Destroy and rt*Validate.
class DestroyableObj : public APIObj {
 public:
  virtual void destroy() = 0;
  virtual void validate() = 0;

 protected:
  explicit DestroyableObj(RTcontext context) : APIObj(context) {}
};

// Objects that hold variables.
class ScopedObj : public DestroyableObj {
 public:
  virtual Variable declareVariable(const std::string& name) = 0;
  // A null handle when there is no variable of that name.
  virtual Variable queryVariable(const std::string& name) const = 0;
  virtual void removeVariable(Variable v) = 0;
  virtual unsigned int getVariableCount() const = 0;
  virtual Variable getVariable(unsigned int index) const = 0;

  // The variable `name`, declared first if there is none of that name.
  Variable operator[](const std::string& name);
  Variable operator[](const char* name);

 protected:
  explicit ScopedObj(RTcontext context) : DestroyableObj(context) {}
};

// Declarations of the members every scoped / destroyable wrapper overrides.
#define OPTIXPP_DESTROYABLE_DECLS_()   \
  Context getContext() const override; \
  void destroy() override;             \
  void validate() override;
#define OPTIXPP_SCOPED_DECLS_()                                   \
  OPTIXPP_DESTROYABLE_DECLS_()                                    \
  Variable declareVariable(const std::string& name) override;     \
  Variable queryVariable(const std::string& name) const override; \
  void removeVariable(Variable v) override;                       \
  unsigned int getVariableCount() const override;                 \
  Variable getVariable(unsigned int index) const override;        \
  using ScopedObj::operator[];

// ---- Variable -------------------------------------------------------------------------------

class VariableObj : public APIObj {
 public:
  typedef RTvariable api_t;

  Context getContext() const override;
  RTvariable get() const { return variable_; }

  std::string getName() const;
  std::string getAnnotation() const;
  RTobjecttype getType() const;
  RTsize getSize() const;

  // Scalars and vectors; the first set fixes the variable's type.
  void setFloat(float f1);
  void setFloat(float f1, float f2);
  void setFloat(float f1, float f2, float f3);
  void setFloat(float f1, float f2, float f3, float f4);
  void setFloat(float2 f);
  void setFloat(float3 f);
  void setFloat(float4 f);
  void set1fv(const float* f);
  void set2fv(const float* f);
  void set3fv(const float* f);
  void set4fv(const float* f);

  void setInt(int i1);
  void setInt(int i1, int i2);
  void setInt(int i1, int i2, int i3);
  void setInt(int i1, int i2, int i3, int i4);
  void setInt(int2 i);
  void setInt(int3 i);
  void setInt(int4 i);
  void set1iv(const int* i);
  void set2iv(const int* i);
  void set3iv(const int* i);
  void set4iv(const int* i);

  void setUint(unsigned int u1);
  void setUint(unsigned int u1, unsigned int u2);
  void setUint(unsigned int u1, unsigned int u2, unsigned int u3);
  void setUint(unsigned int u1, unsigned int u2, unsigned int u3, unsigned int u4);
  void setUint(uint2 u);
  void setUint(uint3 u);
  void setUint(uint4 u);
  void set1uiv(const unsigned int* u);
  void set2uiv(const unsigned int* u);
  void set3uiv(const unsigned int* u);
  void set4uiv(const unsigned int* u);

  // Row-major unless `transpose`.
  void setMatrix2x2fv(bool transpose, const float* m);
  void setMatrix2x3fv(bool transpose, const float* m);
  void setMatrix2x4fv(bool transpose, const float* m);
  void setMatrix3x2fv(bool transpose, const float* m);
  void setMatrix3x3fv(bool transpose, const float* m);
  void setMatrix3x4fv(bool transpose, const float* m);
  void setMatrix4x2fv(bool transpose, const float* m);
  void setMatrix4x3fv(bool transpose, const float* m);
  void setMatrix4x4fv(bool transpose, const float* m);

  float getFloat() const;
  float2 getFloat2() const;
  float3 getFloat3() const;
  float4 getFloat4() const;
  void getFloat(float& f1) const;
  void getFloat(float& f1, float& f2) const;
  void getFloat(float& f1, float& f2, float& f3) const;
  void getFloat(float& f1, float& f2, float& f3, float& f4) const;
  void get1fv(float* f) const;
  void get2fv(float* f) const;
  void get3fv(float* f) const;
  void get4fv(float* f) const;

  int getInt() const;
  int2 getInt2() const;
  int3 getInt3() const;
  int4 getInt4() const;
  void getInt(int& i1) const;
  void getInt(int& i1, int& i2) const;
  void getInt(int& i1, int& i2, int& i3) const;
  void getInt(int& i1, int& i2, int& i3, int& i4) const;
  void get1iv(int* i) const;
  void get2iv(int* i) const;
  void get3iv(int* i) const;
  void get4iv(int* i) const;

  unsigned int getUint() const;
  uint2 getUint2() const;
  uint3 getUint3() const;
  uint4 getUint4() const;
  void getUint(unsigned int& u1) const;
  void getUint(unsigned int& u1, unsigned int& u2) const;
  void getUint(unsigned int& u1, unsigned int& u2, unsigned int& u3) const;
  void getUint(unsigned int& u1, unsigned int& u2, unsigned int& u3, unsigned int& u4) const;
  void get1uiv(unsigned int* u) const;
  void get2uiv(unsigned int* u) const;
  void get3uiv(unsigned int* u) const;
  void get4uiv(unsigned int* u) const;

  void getMatrix2x2fv(bool transpose, float* m) const;
  void getMatrix2x3fv(bool transpose, float* m) const;
  void getMatrix2x4fv(bool transpose, float* m) const;
  void getMatrix3x2fv(bool transpose, float* m) const;
  void getMatrix3x3fv(bool transpose, float* m) const;
  void getMatrix3x4fv(bool transpose, float* m) const;
  void getMatrix4x2fv(bool transpose, float* m) const;
  void getMatrix4x3fv(bool transpose, float* m) const;
  void getMatrix4x4fv(bool transpose, float* m) const;
  // The same getters under the names OptiXpp gives them (no "fv").
  void getMatrix2x2(bool transpose, float* m) const { getMatrix2x2fv(transpose, m); }
  void getMatrix2x3(bool transpose, float* m) const { getMatrix2x3fv(transpose, m); }
  void getMatrix2x4(bool transpose, float* m) const { getMatrix2x4fv(transpose, m); }
  void getMatrix3x2(bool transpose, float* m) const { getMatrix3x2fv(transpose, m); }
  void getMatrix3x3(bool transpose, float* m) const { getMatrix3x3fv(transpose, m); }
  void getMatrix3x4(bool transpose, float* m) const { getMatrix3x4fv(transpose, m); }
  void getMatrix4x2(bool transpose, float* m) const { getMatrix4x2fv(transpose, m); }
  void getMatrix4x3(bool transpose, float* m) const { getMatrix4x3fv(transpose, m); }
  void getMatrix4x4(bool transpose, float* m) const { getMatrix4x4fv(transpose, m); }

  // Object references (rtVariableSetObject).
  void set(const Buffer& buffer);
  void set(const TextureSampler& sampler);
  void set(const Program& program);
  void set(const Group& group);
  void set(const GeometryGroup& group);
  void set(const Selector& selector);
  void set(const Transform& transform);
  void setBuffer(const Buffer& buffer);
  void setTextureSampler(const TextureSampler& sampler);
  // OptiX 3.6+: the program's id (rtProgramGetId), for an rtCallableProgramId variable.
  void setProgramId(const Program& program);

  // The object the variable refers to; RT_ERROR_TYPE_MISMATCH if it refers to another kind.
  Buffer getBuffer() const;
  TextureSampler getTextureSampler() const;
  Program getProgram() const;
  Group getGroup() const;
  GeometryGroup getGeometryGroup() const;
  Selector getSelector() const;
  Transform getTransform() const;

  // Bytes of any type (a struct the program declares); getUserData's size must equal the set one.
  void setUserData(RTsize size, const void* ptr);
  void getUserData(RTsize size, void* ptr) const;

 private:
  friend class Handle<VariableObj>;
  explicit VariableObj(RTvariable variable);
  RTobject GetObject(RTobjecttype expected, const char* kind) const;

  RTvariable variable_;
};

// ---- Context --------------------------------------------------------------------------------

class ContextObj : public ScopedObj {
 public:
  typedef RTcontext api_t;

  // A new context on the devices TESSERA_DEVICES names.
  static Context create();
  RTcontext get() const { return context_; }

  OPTIXPP_SCOPED_DECLS_()
  void compile();

  // Devices (ordinals index rtDeviceGetDeviceCount's list).
  static unsigned int getDeviceCount();
  static std::string getDeviceName(int ordinal);
  static void getDeviceAttribute(int ordinal, RTdeviceattribute attrib, RTsize size, void* p);
  template <class Iterator>
  void setDevices(Iterator begin, Iterator end);
  std::vector<int> getEnabledDevices() const;
  unsigned int getEnabledDeviceCount() const;

  // Context attributes.
  void setCPUNumThreads(int num_threads);
  int getCPUNumThreads() const;
  RTsize getUsedHostMemory() const;
  RTsize getAvailableDeviceMemory(int ordinal) const;
  int getMaxTextureCount() const;
  int getGPUPagingActive() const;
  void setGPUPagingForcedOff(int forced_off);
  int getGPUPagingForcedOff() const;

  // The message rtContextGetErrorString gives for `code`.
  std::string getErrorString(RTresult code) const;

  // Object creation: the new objects belong to this context.
  Acceleration createAcceleration(const std::string& builder, const std::string& traverser = "");
  Buffer createBuffer(unsigned int type);
  Buffer createBuffer(unsigned int type, RTformat format);
  Buffer createBuffer(unsigned int type, RTformat format, RTsize width);
  Buffer createBuffer(unsigned int type, RTformat format, RTsize width, RTsize height);
  Buffer createBuffer(unsigned int type, RTformat format, RTsize width, RTsize height,
                      RTsize depth);
  Buffer createBufferForCUDA(unsigned int type);
  Buffer createBufferForCUDA(unsigned int type, RTformat format);
  Buffer createBufferForCUDA(unsigned int type, RTformat format, RTsize width);
  Buffer createBufferForCUDA(unsigned int type, RTformat format, RTsize width, RTsize height);
  Buffer createBufferForCUDA(unsigned int type, RTformat format, RTsize width, RTsize height,
                             RTsize depth);
  Geometry createGeometry();
  GeometryTriangles createGeometryTriangles();
  GeometryInstance createGeometryInstance();
  template <class Iterator>
  GeometryInstance createGeometryInstance(Geometry geometry, Iterator matlbegin, Iterator matlend);
  Group createGroup();
  template <class Iterator>
  Group createGroup(Iterator childbegin, Iterator childend);
  GeometryGroup createGeometryGroup();
  template <class Iterator>
  GeometryGroup createGeometryGroup(Iterator childbegin, Iterator childend);
  Transform createTransform();
  Material createMaterial();
  Program createProgramFromPTXFile(const std::string& filename, const std::string& program_name);
  Program createProgramFromPTXString(const std::string& ptx, const std::string& program_name);
  Selector createSelector();
  TextureSampler createTextureSampler();

  Buffer getBufferFromId(int buffer_id) const;
  // The sampler rtTextureSamplerGetId gave `sampler_id`.
  TextureSampler getTextureSamplerFromId(int sampler_id) const;
  Program getProgramFromId(int program_id) const;

  // Launches.
  void launch(unsigned int entry_point_index, RTsize image_width);
  void launch(unsigned int entry_point_index, RTsize image_width, RTsize image_height);
  void launch(unsigned int entry_point_index, RTsize image_width, RTsize image_height,
              RTsize image_depth);
  // True while a launch runs (from the timeout callback).
  int getRunningState() const;

  void setStackSize(RTsize stack_size_bytes);
  RTsize getStackSize() const;
  void setTimeoutCallback(RTtimeoutcallback callback, double min_polling_seconds);

  void setEntryPointCount(unsigned int num_entry_points);
  unsigned int getEntryPointCount() const;
  void setRayGenerationProgram(unsigned int entry_point_index, Program program);
  Program getRayGenerationProgram(unsigned int entry_point_index) const;
  void setExceptionProgram(unsigned int entry_point_index, Program program);
  Program getExceptionProgram(unsigned int entry_point_index) const;
  void setExceptionEnabled(RTexception exception, bool enabled);
  bool getExceptionEnabled(RTexception exception) const;

  void setRayTypeCount(unsigned int num_ray_types);
  unsigned int getRayTypeCount() const;
  void setMissProgram(unsigned int ray_type_index, Program program);
  Program getMissProgram(unsigned int ray_type_index) const;

  void setPrintEnabled(bool enabled);
  bool getPrintEnabled() const;
  void setPrintBufferSize(RTsize buffer_size_bytes);
  RTsize getPrintBufferSize() const;
  void setPrintLaunchIndex(int x, int y = -1, int z = -1);
  int3 getPrintLaunchIndex() const;

 private:
  friend class Handle<ContextObj>;
  explicit ContextObj(RTcontext context) : ScopedObj(context) {}
  RTsize GetSizeAttribute(RTcontextattribute attrib) const;
  int GetIntAttribute(RTcontextattribute attrib) const;
};

// ---- Program --------------------------------------------------------------------------------

class ProgramObj : public ScopedObj {
 public:
  typedef RTprogram api_t;
  RTprogram get() const { return program_; }
  OPTIXPP_SCOPED_DECLS_()

  // OptiX 3.6+ (rtProgramGetId): the id programs call it by through an rtCallableProgramId.
  int getId() const;

 private:
  friend class Handle<ProgramObj>;
  explicit ProgramObj(RTprogram program);
  RTprogram program_;
};

// ---- Group ----------------------------------------------------------------------------------

class GroupObj : public DestroyableObj {
 public:
  typedef RTgroup api_t;
  RTgroup get() const { return group_; }
  OPTIXPP_DESTROYABLE_DECLS_()

  void setAcceleration(Acceleration acceleration);
  Acceleration getAcceleration() const;

  void setChildCount(unsigned int count);
  unsigned int getChildCount() const;
  // A Group, GeometryGroup, Transform or Selector.
  template <class T>
  void setChild(unsigned int index, T child);
  // The child as `T` (Group, GeometryGroup, Transform or Selector); RT_ERROR_TYPE_MISMATCH if
  // the child is of another kind.
  template <class T>
  T getChild(unsigned int index) const;
  RTobjecttype getChildType(unsigned int index) const;
  // Appends `child`; returns its index.
  template <class T>
  unsigned int addChild(T child);
  // Removes the child at `index`, moving the last child into its place (order is not kept).
  void removeChild(unsigned int index);
  void removeChild(int index) { removeChild(static_cast<unsigned int>(index)); }
  // Removes `child` as above; returns the index it had.
  template <class T>
  unsigned int removeChild(Handle<T> child);
  // The index of `child`; RT_ERROR_INVALID_VALUE if it is not a child.
  template <class T>
  unsigned int getChildIndex(T child) const;

 private:
  friend class Handle<GroupObj>;
  explicit GroupObj(RTgroup group);
  RTgroup group_;
};

// ---- GeometryGroup --------------------------------------------------------------------------

class GeometryGroupObj : public DestroyableObj {
 public:
  typedef RTgeometrygroup api_t;
  RTgeometrygroup get() const { return geometrygroup_; }
  OPTIXPP_DESTROYABLE_DECLS_()

  void setAcceleration(Acceleration acceleration);
  Acceleration getAcceleration() const;

  void setChildCount(unsigned int count);
  unsigned int getChildCount() const;
  void setChild(unsigned int index, GeometryInstance geometryinstance);
  GeometryInstance getChild(unsigned int index) const;
  unsigned int addChild(GeometryInstance geometryinstance);
  // Removes the child at `index`, moving the last child into its place (order is not kept).
  void removeChild(unsigned int index);
  void removeChild(int index) { removeChild(static_cast<unsigned int>(index)); }
  // Removes `geometryinstance` as above; returns the index it had.
  unsigned int removeChild(GeometryInstance geometryinstance);
  unsigned int getChildIndex(GeometryInstance geometryinstance) const;

 private:
  friend class Handle<GeometryGroupObj>;
  explicit GeometryGroupObj(RTgeometrygroup geometrygroup);
  RTgeometrygroup geometrygroup_;
};

// ---- Transform ------------------------------------------------------------------------------

class TransformObj : public DestroyableObj {
 public:
  typedef RTtransform api_t;
  RTtransform get() const { return transform_; }
  OPTIXPP_DESTROYABLE_DECLS_()

  template <class T>
  void setChild(T child);
  template <class T>
  T getChild() const;
  RTobjecttype getChildType() const;

  // Row-major 4x4 unless `transpose`; a null inverse_matrix lets Tessera invert `matrix`.
  void setMatrix(bool transpose, const float* matrix, const float* inverse_matrix);
  // Either pointer may be null.
  void getMatrix(bool transpose, float* matrix, float* inverse_matrix) const;

 private:
  friend class Handle<TransformObj>;
  explicit TransformObj(RTtransform transform);
  RTtransform transform_;
};

// ---- Selector -------------------------------------------------------------------------------

class SelectorObj : public ScopedObj {
 public:
  typedef RTselector api_t;
  RTselector get() const { return selector_; }
  OPTIXPP_SCOPED_DECLS_()

  void setVisitProgram(Program program);
  Program getVisitProgram() const;

  void setChildCount(unsigned int count);
  unsigned int getChildCount() const;
  template <class T>
  void setChild(unsigned int index, T child);
  template <class T>
  T getChild(unsigned int index) const;
  RTobjecttype getChildType(unsigned int index) const;
  template <class T>
  unsigned int addChild(T child);
  // Removes the child at `index`; the later children move down one place (order is kept, as
  // OptiX's Selector does: visit programs choose children by index).
  void removeChild(unsigned int index);
  void removeChild(int index) { removeChild(static_cast<unsigned int>(index)); }
  // Removes `child` as above; returns the index it had.
  template <class T>
  unsigned int removeChild(Handle<T> child);
  template <class T>
  unsigned int getChildIndex(T child) const;

 private:
  friend class Handle<SelectorObj>;
  explicit SelectorObj(RTselector selector);
  RTselector selector_;
};

// ---- Acceleration ---------------------------------------------------------------------------

class AccelerationObj : public DestroyableObj {
 public:
  typedef RTacceleration api_t;
  RTacceleration get() const { return acceleration_; }
  OPTIXPP_DESTROYABLE_DECLS_()

  void markDirty();
  bool isDirty() const;

  void setProperty(const std::string& name, const std::string& value);
  std::string getProperty(const std::string& name) const;
  void setBuilder(const std::string& builder);
  std::string getBuilder() const;
  void setTraverser(const std::string& traverser);
  std::string getTraverser() const;

  RTsize getDataSize() const;
  void getData(void* data) const;
  void setData(const void* data, RTsize size);

 private:
  friend class Handle<AccelerationObj>;
  explicit AccelerationObj(RTacceleration acceleration);
  RTacceleration acceleration_;
};

// ---- GeometryInstance -----------------------------------------------------------------------

class GeometryInstanceObj : public ScopedObj {
 public:
  typedef RTgeometryinstance api_t;
  RTgeometryinstance get() const { return geometryinstance_; }
  OPTIXPP_SCOPED_DECLS_()

  void setGeometry(Geometry geometry);
  Geometry getGeometry() const;
  void setGeometryTriangles(GeometryTriangles geometrytriangles);
  GeometryTriangles getGeometryTriangles() const;

  void setMaterialCount(unsigned int count);
  unsigned int getMaterialCount() const;
  void setMaterial(unsigned int index, Material material);
  Material getMaterial(unsigned int index) const;
  // Appends `material`; returns its index.
  unsigned int addMaterial(Material material);

 private:
  friend class Handle<GeometryInstanceObj>;
  explicit GeometryInstanceObj(RTgeometryinstance geometryinstance);
  RTgeometryinstance geometryinstance_;
};

// ---- Geometry -------------------------------------------------------------------------------

class GeometryObj : public ScopedObj {
 public:
  typedef RTgeometry api_t;
  RTgeometry get() const { return geometry_; }
  OPTIXPP_SCOPED_DECLS_()

  void markDirty();
  bool isDirty() const;

  void setPrimitiveCount(unsigned int num_primitives);
  unsigned int getPrimitiveCount() const;
  void setBoundingBoxProgram(Program program);
  Program getBoundingBoxProgram() const;
  void setIntersectionProgram(Program program);
  Program getIntersectionProgram() const;

 private:
  friend class Handle<GeometryObj>;
  explicit GeometryObj(RTgeometry geometry);
  RTgeometry geometry_;
};

// ---- GeometryTriangles (OptiX 6) ------------------------------------------------------------

class GeometryTrianglesObj : public ScopedObj {
 public:
  typedef RTgeometrytriangles api_t;
  RTgeometrytriangles get() const { return geometrytriangles_; }
  OPTIXPP_SCOPED_DECLS_()

  void setPrimitiveIndexOffset(unsigned int index_offset);
  unsigned int getPrimitiveIndexOffset() const;
  void setPrimitiveCount(unsigned int num_triangles);
  unsigned int getPrimitiveCount() const;

  // Packed indices from the start of the buffer, or from a byte offset, or with a byte stride.
  void setTriangleIndices(Buffer index_buffer, RTformat tri_indices_format);
  void setTriangleIndices(Buffer index_buffer, RTsize index_buffer_byte_offset,
                          RTformat tri_indices_format);
  void setTriangleIndices(Buffer index_buffer, RTsize index_buffer_byte_offset,
                          RTsize tri_indices_byte_stride, RTformat tri_indices_format);
  void setVertices(unsigned int num_vertices, Buffer vertex_buffer, RTformat position_format);
  void setVertices(unsigned int num_vertices, Buffer vertex_buffer,
                   RTsize vertex_buffer_byte_offset, RTsize vertex_byte_stride,
                   RTformat position_format);

  void setAttributeProgram(Program program);
  Program getAttributeProgram() const;

  void setMaterialCount(unsigned int num_materials);
  unsigned int getMaterialCount() const;
  void setMaterialIndices(Buffer material_index_buffer, RTsize material_index_buffer_byte_offset,
                          RTsize material_index_byte_stride, RTformat material_index_format);

 private:
  friend class Handle<GeometryTrianglesObj>;
  explicit GeometryTrianglesObj(RTgeometrytriangles geometrytriangles);
  RTgeometrytriangles geometrytriangles_;
};

// ---- Material -------------------------------------------------------------------------------

class MaterialObj : public ScopedObj {
 public:
  typedef RTmaterial api_t;
  RTmaterial get() const { return material_; }
  OPTIXPP_SCOPED_DECLS_()

  void setClosestHitProgram(unsigned int ray_type_index, Program program);
  Program getClosestHitProgram(unsigned int ray_type_index) const;
  void setAnyHitProgram(unsigned int ray_type_index, Program program);
  Program getAnyHitProgram(unsigned int ray_type_index) const;

 private:
  friend class Handle<MaterialObj>;
  explicit MaterialObj(RTmaterial material);
  RTmaterial material_;
};

// ---- Buffer ---------------------------------------------------------------------------------

class BufferObj : public DestroyableObj {
 public:
  typedef RTbuffer api_t;
  RTbuffer get() const { return buffer_; }
  OPTIXPP_DESTROYABLE_DECLS_()

  void setFormat(RTformat format);
  RTformat getFormat() const;
  // RT_FORMAT_USER buffers only.
  void setElementSize(RTsize size_of_element);
  RTsize getElementSize() const;

  void setSize(RTsize width);
  void getSize(RTsize& width) const;
  void setSize(RTsize width, RTsize height);
  void getSize(RTsize& width, RTsize& height) const;
  void setSize(RTsize width, RTsize height, RTsize depth);
  void getSize(RTsize& width, RTsize& height, RTsize& depth) const;
  void setSize(unsigned int dimensionality, const RTsize* dims);
  void getSize(unsigned int dimensionality, RTsize* dims) const;
  unsigned int getDimensionality() const;

  // Maps mip level `level` (rtBufferMapEx; rtBufferMap for level 0 with the defaults):
  // `map_flags` is one RT_BUFFER_MAP_* value (Tessera always maps read-write, which serves each
  // of them); a user-owned pointer is not supported.
  void* map(unsigned int level = 0, unsigned int map_flags = RT_BUFFER_MAP_READ_WRITE,
            void* user_owned = nullptr);
  void unmap(unsigned int level = 0);
  // Mip levels (OptiX 3.9).
  void setMipLevelCount(unsigned int levels);
  unsigned int getMipLevelCount() const;
  void getMipLevelSize(unsigned int level, RTsize& width) const;
  void getMipLevelSize(unsigned int level, RTsize& width, RTsize& height) const;
  void getMipLevelSize(unsigned int level, RTsize& width, RTsize& height, RTsize& depth) const;
  int getId() const;
  void markDirty();

  // CUDA interop: host memory standing for device `optix_device_number`'s copy (docs/devices.md).
  void* getDevicePointer(int optix_device_number);
  void setDevicePointer(int optix_device_number, void* device_pointer);

 private:
  friend class Handle<BufferObj>;
  explicit BufferObj(RTbuffer buffer);
  RTbuffer buffer_;
};

// ---- TextureSampler -------------------------------------------------------------------------

// A texture sampler (rtTextureSampler*). setMipLevelCount and setArraySize take only 1, and the
// (texture_array_idx, mip_level) forms of setBuffer/getBuffer only (0, 0): OptiX 3.9 moved mip
// levels and layers into the buffer.
class TextureSamplerObj : public DestroyableObj {
 public:
  typedef RTtexturesampler api_t;
  RTtexturesampler get() const { return sampler_; }
  OPTIXPP_DESTROYABLE_DECLS_()

  void setMipLevelCount(unsigned int num_mip_levels);
  unsigned int getMipLevelCount() const;
  void setArraySize(unsigned int num_textures_in_array);
  unsigned int getArraySize() const;
  void setWrapMode(unsigned int dim, RTwrapmode wrapmode);
  RTwrapmode getWrapMode(unsigned int dim) const;
  void setFilteringModes(RTfiltermode minification, RTfiltermode magnification,
                         RTfiltermode mipmapping);
  void getFilteringModes(RTfiltermode& minification, RTfiltermode& magnification,
                         RTfiltermode& mipmapping) const;
  void setMaxAnisotropy(float value);
  float getMaxAnisotropy() const;
  void setMipLevelClamp(float min_level, float max_level);
  void getMipLevelClamp(float& min_level, float& max_level) const;
  void setMipLevelBias(float value);
  float getMipLevelBias() const;
  void setReadMode(RTtexturereadmode readmode);
  RTtexturereadmode getReadMode() const;
  void setIndexingMode(RTtextureindexmode indexmode);
  RTtextureindexmode getIndexingMode() const;
  void setBuffer(unsigned int texture_array_idx, unsigned int mip_level, Buffer buffer);
  Buffer getBuffer(unsigned int texture_array_idx, unsigned int mip_level) const;
  void setBuffer(Buffer buffer);
  Buffer getBuffer() const;
  int getId() const;

 private:
  friend class Handle<TextureSamplerObj>;
  explicit TextureSamplerObj(RTtexturesampler sampler);
  RTtexturesampler sampler_;
};

#undef OPTIXPP_SCOPED_DECLS_
#undef OPTIXPP_DESTROYABLE_DECLS_

// =============================================================================================
// Definitions
// =============================================================================================

namespace optixpp_detail {
// The context of `object` through `get_context`, or null (a destroyed or foreign object).
template <class Api>
RTcontext ContextOf(RTresult (*get_context)(Api, RTcontext*), Api object) {
  RTcontext context = nullptr;
  if (object == nullptr || get_context(object, &context) != RT_SUCCESS) return nullptr;
  return context;
}
}  // namespace optixpp_detail

inline void APIObj::checkError(RTresult code, Context context) const {
  optixpp_detail::Check(code, optixpp_detail::Raw(context));
}

inline Variable ScopedObj::operator[](const std::string& name) {
  Variable v = queryVariable(name);
  return v ? v : declareVariable(name);
}
inline Variable ScopedObj::operator[](const char* name) { return (*this)[std::string(name)]; }

// getContext, destroy and validate of a wrapper whose API object is `member`, for C functions
// named rt<Prefix>GetContext etc.
#define OPTIXPP_DESTROYABLE_DEFS_(Class, Prefix, member)                    \
  inline Context Class::getContext() const {                                \
    RTcontext c = nullptr;                                                  \
    checkError(rt##Prefix##GetContext(member, &c));                         \
    return Context::take(c);                                                \
  }                                                                         \
  inline void Class::destroy() { checkError(rt##Prefix##Destroy(member)); } \
  inline void Class::validate() { checkError(rt##Prefix##Validate(member)); }

#define OPTIXPP_SCOPED_DEFS_(Class, Prefix, member)                         \
  OPTIXPP_DESTROYABLE_DEFS_(Class, Prefix, member)                          \
  inline Variable Class::declareVariable(const std::string& name) {         \
    RTvariable v = nullptr;                                                 \
    checkError(rt##Prefix##DeclareVariable(member, name.c_str(), &v));      \
    return Variable::take(v);                                               \
  }                                                                         \
  inline Variable Class::queryVariable(const std::string& name) const {     \
    RTvariable v = nullptr;                                                 \
    checkError(rt##Prefix##QueryVariable(member, name.c_str(), &v));        \
    return Variable::take(v);                                               \
  }                                                                         \
  inline void Class::removeVariable(Variable v) {                           \
    checkError(rt##Prefix##RemoveVariable(member, optixpp_detail::Raw(v))); \
  }                                                                         \
  inline unsigned int Class::getVariableCount() const {                     \
    unsigned int count = 0;                                                 \
    checkError(rt##Prefix##GetVariableCount(member, &count));               \
    return count;                                                           \
  }                                                                         \
  inline Variable Class::getVariable(unsigned int index) const {            \
    RTvariable v = nullptr;                                                 \
    checkError(rt##Prefix##GetVariable(member, index, &v));                 \
    return Variable::take(v);                                               \
  }

// ---- Variable -------------------------------------------------------------------------------

inline VariableObj::VariableObj(RTvariable variable)
    : APIObj(optixpp_detail::ContextOf(&rtVariableGetContext, variable)), variable_(variable) {}

inline Context VariableObj::getContext() const {
  RTcontext c = nullptr;
  checkError(rtVariableGetContext(variable_, &c));
  return Context::take(c);
}

inline std::string VariableObj::getName() const {
  const char* name = nullptr;
  checkError(rtVariableGetName(variable_, &name));
  return name != nullptr ? name : "";
}
inline std::string VariableObj::getAnnotation() const {
  const char* annotation = nullptr;
  checkError(rtVariableGetAnnotation(variable_, &annotation));
  return annotation != nullptr ? annotation : "";
}
inline RTobjecttype VariableObj::getType() const {
  RTobjecttype type = RT_OBJECTTYPE_UNKNOWN;
  checkError(rtVariableGetType(variable_, &type));
  return type;
}
inline RTsize VariableObj::getSize() const {
  RTsize size = 0;
  checkError(rtVariableGetSize(variable_, &size));
  return size;
}

inline void VariableObj::setFloat(float f1) { checkError(rtVariableSet1f(variable_, f1)); }
inline void VariableObj::setFloat(float f1, float f2) {
  checkError(rtVariableSet2f(variable_, f1, f2));
}
inline void VariableObj::setFloat(float f1, float f2, float f3) {
  checkError(rtVariableSet3f(variable_, f1, f2, f3));
}
inline void VariableObj::setFloat(float f1, float f2, float f3, float f4) {
  checkError(rtVariableSet4f(variable_, f1, f2, f3, f4));
}
inline void VariableObj::setFloat(float2 f) { checkError(rtVariableSet2f(variable_, f.x, f.y)); }
inline void VariableObj::setFloat(float3 f) {
  checkError(rtVariableSet3f(variable_, f.x, f.y, f.z));
}
inline void VariableObj::setFloat(float4 f) {
  checkError(rtVariableSet4f(variable_, f.x, f.y, f.z, f.w));
}
inline void VariableObj::set1fv(const float* f) { checkError(rtVariableSet1fv(variable_, f)); }
inline void VariableObj::set2fv(const float* f) { checkError(rtVariableSet2fv(variable_, f)); }
inline void VariableObj::set3fv(const float* f) { checkError(rtVariableSet3fv(variable_, f)); }
inline void VariableObj::set4fv(const float* f) { checkError(rtVariableSet4fv(variable_, f)); }

inline void VariableObj::setInt(int i1) { checkError(rtVariableSet1i(variable_, i1)); }
inline void VariableObj::setInt(int i1, int i2) { checkError(rtVariableSet2i(variable_, i1, i2)); }
inline void VariableObj::setInt(int i1, int i2, int i3) {
  checkError(rtVariableSet3i(variable_, i1, i2, i3));
}
inline void VariableObj::setInt(int i1, int i2, int i3, int i4) {
  checkError(rtVariableSet4i(variable_, i1, i2, i3, i4));
}
inline void VariableObj::setInt(int2 i) { checkError(rtVariableSet2i(variable_, i.x, i.y)); }
inline void VariableObj::setInt(int3 i) { checkError(rtVariableSet3i(variable_, i.x, i.y, i.z)); }
inline void VariableObj::setInt(int4 i) {
  checkError(rtVariableSet4i(variable_, i.x, i.y, i.z, i.w));
}
inline void VariableObj::set1iv(const int* i) { checkError(rtVariableSet1iv(variable_, i)); }
inline void VariableObj::set2iv(const int* i) { checkError(rtVariableSet2iv(variable_, i)); }
inline void VariableObj::set3iv(const int* i) { checkError(rtVariableSet3iv(variable_, i)); }
inline void VariableObj::set4iv(const int* i) { checkError(rtVariableSet4iv(variable_, i)); }

inline void VariableObj::setUint(unsigned int u1) { checkError(rtVariableSet1ui(variable_, u1)); }
inline void VariableObj::setUint(unsigned int u1, unsigned int u2) {
  checkError(rtVariableSet2ui(variable_, u1, u2));
}
inline void VariableObj::setUint(unsigned int u1, unsigned int u2, unsigned int u3) {
  checkError(rtVariableSet3ui(variable_, u1, u2, u3));
}
inline void VariableObj::setUint(unsigned int u1, unsigned int u2, unsigned int u3,
                                 unsigned int u4) {
  checkError(rtVariableSet4ui(variable_, u1, u2, u3, u4));
}
inline void VariableObj::setUint(uint2 u) { checkError(rtVariableSet2ui(variable_, u.x, u.y)); }
inline void VariableObj::setUint(uint3 u) {
  checkError(rtVariableSet3ui(variable_, u.x, u.y, u.z));
}
inline void VariableObj::setUint(uint4 u) {
  checkError(rtVariableSet4ui(variable_, u.x, u.y, u.z, u.w));
}
inline void VariableObj::set1uiv(const unsigned int* u) {
  checkError(rtVariableSet1uiv(variable_, u));
}
inline void VariableObj::set2uiv(const unsigned int* u) {
  checkError(rtVariableSet2uiv(variable_, u));
}
inline void VariableObj::set3uiv(const unsigned int* u) {
  checkError(rtVariableSet3uiv(variable_, u));
}
inline void VariableObj::set4uiv(const unsigned int* u) {
  checkError(rtVariableSet4uiv(variable_, u));
}

#define OPTIXPP_MATRIX_DEFS_(MxN)                                               \
  inline void VariableObj::setMatrix##MxN##fv(bool transpose, const float* m) { \
    checkError(rtVariableSetMatrix##MxN##fv(variable_, transpose ? 1 : 0, m));  \
  }                                                                             \
  inline void VariableObj::getMatrix##MxN##fv(bool transpose, float* m) const { \
    checkError(rtVariableGetMatrix##MxN##fv(variable_, transpose ? 1 : 0, m));  \
  }
OPTIXPP_MATRIX_DEFS_(2x2)
OPTIXPP_MATRIX_DEFS_(2x3)
OPTIXPP_MATRIX_DEFS_(2x4)
OPTIXPP_MATRIX_DEFS_(3x2)
OPTIXPP_MATRIX_DEFS_(3x3)
OPTIXPP_MATRIX_DEFS_(3x4)
OPTIXPP_MATRIX_DEFS_(4x2)
OPTIXPP_MATRIX_DEFS_(4x3)
OPTIXPP_MATRIX_DEFS_(4x4)
#undef OPTIXPP_MATRIX_DEFS_

inline float VariableObj::getFloat() const {
  float f = 0;
  checkError(rtVariableGet1f(variable_, &f));
  return f;
}
inline float2 VariableObj::getFloat2() const {
  float2 f = {0, 0};
  checkError(rtVariableGet2f(variable_, &f.x, &f.y));
  return f;
}
inline float3 VariableObj::getFloat3() const {
  float3 f = {0, 0, 0};
  checkError(rtVariableGet3f(variable_, &f.x, &f.y, &f.z));
  return f;
}
inline float4 VariableObj::getFloat4() const {
  float4 f = {0, 0, 0, 0};
  checkError(rtVariableGet4f(variable_, &f.x, &f.y, &f.z, &f.w));
  return f;
}
inline void VariableObj::getFloat(float& f1) const { checkError(rtVariableGet1f(variable_, &f1)); }
inline void VariableObj::getFloat(float& f1, float& f2) const {
  checkError(rtVariableGet2f(variable_, &f1, &f2));
}
inline void VariableObj::getFloat(float& f1, float& f2, float& f3) const {
  checkError(rtVariableGet3f(variable_, &f1, &f2, &f3));
}
inline void VariableObj::getFloat(float& f1, float& f2, float& f3, float& f4) const {
  checkError(rtVariableGet4f(variable_, &f1, &f2, &f3, &f4));
}
inline void VariableObj::get1fv(float* f) const { checkError(rtVariableGet1fv(variable_, f)); }
inline void VariableObj::get2fv(float* f) const { checkError(rtVariableGet2fv(variable_, f)); }
inline void VariableObj::get3fv(float* f) const { checkError(rtVariableGet3fv(variable_, f)); }
inline void VariableObj::get4fv(float* f) const { checkError(rtVariableGet4fv(variable_, f)); }

inline int VariableObj::getInt() const {
  int i = 0;
  checkError(rtVariableGet1i(variable_, &i));
  return i;
}
inline int2 VariableObj::getInt2() const {
  int2 i = {0, 0};
  checkError(rtVariableGet2i(variable_, &i.x, &i.y));
  return i;
}
inline int3 VariableObj::getInt3() const {
  int3 i = {0, 0, 0};
  checkError(rtVariableGet3i(variable_, &i.x, &i.y, &i.z));
  return i;
}
inline int4 VariableObj::getInt4() const {
  int4 i = {0, 0, 0, 0};
  checkError(rtVariableGet4i(variable_, &i.x, &i.y, &i.z, &i.w));
  return i;
}
inline void VariableObj::getInt(int& i1) const { checkError(rtVariableGet1i(variable_, &i1)); }
inline void VariableObj::getInt(int& i1, int& i2) const {
  checkError(rtVariableGet2i(variable_, &i1, &i2));
}
inline void VariableObj::getInt(int& i1, int& i2, int& i3) const {
  checkError(rtVariableGet3i(variable_, &i1, &i2, &i3));
}
inline void VariableObj::getInt(int& i1, int& i2, int& i3, int& i4) const {
  checkError(rtVariableGet4i(variable_, &i1, &i2, &i3, &i4));
}
inline void VariableObj::get1iv(int* i) const { checkError(rtVariableGet1iv(variable_, i)); }
inline void VariableObj::get2iv(int* i) const { checkError(rtVariableGet2iv(variable_, i)); }
inline void VariableObj::get3iv(int* i) const { checkError(rtVariableGet3iv(variable_, i)); }
inline void VariableObj::get4iv(int* i) const { checkError(rtVariableGet4iv(variable_, i)); }

inline unsigned int VariableObj::getUint() const {
  unsigned int u = 0;
  checkError(rtVariableGet1ui(variable_, &u));
  return u;
}
inline uint2 VariableObj::getUint2() const {
  uint2 u = {0, 0};
  checkError(rtVariableGet2ui(variable_, &u.x, &u.y));
  return u;
}
inline uint3 VariableObj::getUint3() const {
  uint3 u = {0, 0, 0};
  checkError(rtVariableGet3ui(variable_, &u.x, &u.y, &u.z));
  return u;
}
inline uint4 VariableObj::getUint4() const {
  uint4 u = {0, 0, 0, 0};
  checkError(rtVariableGet4ui(variable_, &u.x, &u.y, &u.z, &u.w));
  return u;
}
inline void VariableObj::getUint(unsigned int& u1) const {
  checkError(rtVariableGet1ui(variable_, &u1));
}
inline void VariableObj::getUint(unsigned int& u1, unsigned int& u2) const {
  checkError(rtVariableGet2ui(variable_, &u1, &u2));
}
inline void VariableObj::getUint(unsigned int& u1, unsigned int& u2, unsigned int& u3) const {
  checkError(rtVariableGet3ui(variable_, &u1, &u2, &u3));
}
inline void VariableObj::getUint(unsigned int& u1, unsigned int& u2, unsigned int& u3,
                                 unsigned int& u4) const {
  checkError(rtVariableGet4ui(variable_, &u1, &u2, &u3, &u4));
}
inline void VariableObj::get1uiv(unsigned int* u) const {
  checkError(rtVariableGet1uiv(variable_, u));
}
inline void VariableObj::get2uiv(unsigned int* u) const {
  checkError(rtVariableGet2uiv(variable_, u));
}
inline void VariableObj::get3uiv(unsigned int* u) const {
  checkError(rtVariableGet3uiv(variable_, u));
}
inline void VariableObj::get4uiv(unsigned int* u) const {
  checkError(rtVariableGet4uiv(variable_, u));
}

inline void VariableObj::set(const Buffer& buffer) {
  checkError(rtVariableSetObject(variable_, optixpp_detail::Raw(buffer)));
}
inline void VariableObj::set(const TextureSampler& sampler) {
  checkError(rtVariableSetObject(variable_, optixpp_detail::Raw(sampler)));
}
inline void VariableObj::set(const Program& program) {
  checkError(rtVariableSetObject(variable_, optixpp_detail::Raw(program)));
}
inline void VariableObj::set(const Group& group) {
  checkError(rtVariableSetObject(variable_, optixpp_detail::Raw(group)));
}
inline void VariableObj::set(const GeometryGroup& group) {
  checkError(rtVariableSetObject(variable_, optixpp_detail::Raw(group)));
}
inline void VariableObj::set(const Selector& selector) {
  checkError(rtVariableSetObject(variable_, optixpp_detail::Raw(selector)));
}
inline void VariableObj::set(const Transform& transform) {
  checkError(rtVariableSetObject(variable_, optixpp_detail::Raw(transform)));
}
inline void VariableObj::setBuffer(const Buffer& buffer) { set(buffer); }
inline void VariableObj::setTextureSampler(const TextureSampler& sampler) { set(sampler); }
inline void VariableObj::setProgramId(const Program& program) {
  checkError(rtVariableSet1i(variable_, program->getId()));
}

inline RTobject VariableObj::GetObject(RTobjecttype expected, const char* kind) const {
  RTobject object = nullptr;
  checkError(rtVariableGetObject(variable_, &object));
  if (getType() != expected) {
    throw Exception("optix::Variable '" + getName() + "' does not refer to a " + kind,
                    RT_ERROR_TYPE_MISMATCH);
  }
  return object;
}
inline Buffer VariableObj::getBuffer() const {
  return Buffer::take(GetObject(RT_OBJECTTYPE_BUFFER, "buffer"));
}
inline TextureSampler VariableObj::getTextureSampler() const {
  return TextureSampler::take(GetObject(RT_OBJECTTYPE_TEXTURE_SAMPLER, "texture sampler"));
}
inline Program VariableObj::getProgram() const {
  return Program::take(GetObject(RT_OBJECTTYPE_PROGRAM, "program"));
}
inline Group VariableObj::getGroup() const {
  return Group::take(GetObject(RT_OBJECTTYPE_GROUP, "group"));
}
inline GeometryGroup VariableObj::getGeometryGroup() const {
  return GeometryGroup::take(GetObject(RT_OBJECTTYPE_GEOMETRY_GROUP, "geometry group"));
}
inline Selector VariableObj::getSelector() const {
  return Selector::take(GetObject(RT_OBJECTTYPE_SELECTOR, "selector"));
}
inline Transform VariableObj::getTransform() const {
  return Transform::take(GetObject(RT_OBJECTTYPE_TRANSFORM, "transform"));
}

inline void VariableObj::setUserData(RTsize size, const void* ptr) {
  checkError(rtVariableSetUserData(variable_, size, ptr));
}
inline void VariableObj::getUserData(RTsize size, void* ptr) const {
  checkError(rtVariableGetUserData(variable_, size, ptr));
}

// ---- Context --------------------------------------------------------------------------------

inline Context ContextObj::create() {
  RTcontext c = nullptr;
  optixpp_detail::Check(rtContextCreate(&c), nullptr);
  return Context::take(c);
}

inline Context ContextObj::getContext() const { return Context::take(context_); }
inline void ContextObj::destroy() { checkError(rtContextDestroy(context_)); }
inline void ContextObj::validate() { checkError(rtContextValidate(context_)); }
inline void ContextObj::compile() { checkError(rtContextCompile(context_)); }

inline Variable ContextObj::declareVariable(const std::string& name) {
  RTvariable v = nullptr;
  checkError(rtContextDeclareVariable(context_, name.c_str(), &v));
  return Variable::take(v);
}
inline Variable ContextObj::queryVariable(const std::string& name) const {
  RTvariable v = nullptr;
  checkError(rtContextQueryVariable(context_, name.c_str(), &v));
  return Variable::take(v);
}
inline void ContextObj::removeVariable(Variable v) {
  checkError(rtContextRemoveVariable(context_, optixpp_detail::Raw(v)));
}
inline unsigned int ContextObj::getVariableCount() const {
  unsigned int count = 0;
  checkError(rtContextGetVariableCount(context_, &count));
  return count;
}
inline Variable ContextObj::getVariable(unsigned int index) const {
  RTvariable v = nullptr;
  checkError(rtContextGetVariable(context_, index, &v));
  return Variable::take(v);
}

inline unsigned int ContextObj::getDeviceCount() {
  unsigned int count = 0;
  optixpp_detail::Check(rtDeviceGetDeviceCount(&count), nullptr);
  return count;
}
inline std::string ContextObj::getDeviceName(int ordinal) {
  char name[256] = {};
  getDeviceAttribute(ordinal, RT_DEVICE_ATTRIBUTE_NAME, sizeof(name), name);
  name[sizeof(name) - 1] = '\0';
  return name;
}
inline void ContextObj::getDeviceAttribute(int ordinal, RTdeviceattribute attrib, RTsize size,
                                           void* p) {
  optixpp_detail::Check(rtDeviceGetAttribute(ordinal, attrib, size, p), nullptr);
}
template <class Iterator>
void ContextObj::setDevices(Iterator begin, Iterator end) {
  std::vector<int> devices(begin, end);
  checkError(
      rtContextSetDevices(context_, static_cast<unsigned int>(devices.size()), devices.data()));
}
inline std::vector<int> ContextObj::getEnabledDevices() const {
  std::vector<int> devices(getEnabledDeviceCount());
  if (!devices.empty()) checkError(rtContextGetDevices(context_, devices.data()));
  return devices;
}
inline unsigned int ContextObj::getEnabledDeviceCount() const {
  unsigned int count = 0;
  checkError(rtContextGetDeviceCount(context_, &count));
  return count;
}

inline RTsize ContextObj::GetSizeAttribute(RTcontextattribute attrib) const {
  RTsize value = 0;
  checkError(rtContextGetAttribute(context_, attrib, sizeof(value), &value));
  return value;
}
inline int ContextObj::GetIntAttribute(RTcontextattribute attrib) const {
  int value = 0;
  checkError(rtContextGetAttribute(context_, attrib, sizeof(value), &value));
  return value;
}
inline void ContextObj::setCPUNumThreads(int num_threads) {
  checkError(rtContextSetAttribute(context_, RT_CONTEXT_ATTRIBUTE_CPU_NUM_THREADS,
                                   sizeof(num_threads), &num_threads));
}
inline int ContextObj::getCPUNumThreads() const {
  return GetIntAttribute(RT_CONTEXT_ATTRIBUTE_CPU_NUM_THREADS);
}
inline RTsize ContextObj::getUsedHostMemory() const {
  return GetSizeAttribute(RT_CONTEXT_ATTRIBUTE_USED_HOST_MEMORY);
}
inline RTsize ContextObj::getAvailableDeviceMemory(int ordinal) const {
  return GetSizeAttribute(
      static_cast<RTcontextattribute>(RT_CONTEXT_ATTRIBUTE_AVAILABLE_DEVICE_MEMORY + ordinal));
}
inline int ContextObj::getMaxTextureCount() const {
  return GetIntAttribute(RT_CONTEXT_ATTRIBUTE_MAX_TEXTURE_COUNT);
}
inline int ContextObj::getGPUPagingActive() const {
  return GetIntAttribute(RT_CONTEXT_ATTRIBUTE_GPU_PAGING_ACTIVE);
}
inline void ContextObj::setGPUPagingForcedOff(int forced_off) {
  checkError(rtContextSetAttribute(context_, RT_CONTEXT_ATTRIBUTE_GPU_PAGING_FORCED_OFF,
                                   sizeof(forced_off), &forced_off));
}
inline int ContextObj::getGPUPagingForcedOff() const {
  return GetIntAttribute(RT_CONTEXT_ATTRIBUTE_GPU_PAGING_FORCED_OFF);
}

inline std::string ContextObj::getErrorString(RTresult code) const {
  const char* message = nullptr;
  rtContextGetErrorString(context_, code, &message);
  return message != nullptr ? message : "";
}

inline Acceleration ContextObj::createAcceleration(const std::string& builder,
                                                   const std::string& traverser) {
  RTacceleration a = nullptr;
  checkError(rtAccelerationCreate(context_, &a));
  Acceleration acceleration = Acceleration::take(a);
  acceleration->setBuilder(builder);
  // OptiX 4 and later ignore the traverser; pick the one Table 2 pairs with the builder.
  if (!traverser.empty()) {
    acceleration->setTraverser(traverser);
  } else if (builder == "TriangleKdTree") {
    acceleration->setTraverser("KdTree");
  } else if (builder == "NoAccel") {
    acceleration->setTraverser("NoAccel");
  } else {
    acceleration->setTraverser("Bvh");
  }
  return acceleration;
}

inline Buffer ContextObj::createBuffer(unsigned int type) {
  RTbuffer b = nullptr;
  checkError(rtBufferCreate(context_, type, &b));
  return Buffer::take(b);
}
inline Buffer ContextObj::createBuffer(unsigned int type, RTformat format) {
  Buffer b = createBuffer(type);
  b->setFormat(format);
  return b;
}
inline Buffer ContextObj::createBuffer(unsigned int type, RTformat format, RTsize width) {
  Buffer b = createBuffer(type, format);
  b->setSize(width);
  return b;
}
inline Buffer ContextObj::createBuffer(unsigned int type, RTformat format, RTsize width,
                                       RTsize height) {
  Buffer b = createBuffer(type, format);
  b->setSize(width, height);
  return b;
}
inline Buffer ContextObj::createBuffer(unsigned int type, RTformat format, RTsize width,
                                       RTsize height, RTsize depth) {
  Buffer b = createBuffer(type, format);
  b->setSize(width, height, depth);
  return b;
}
inline Buffer ContextObj::createBufferForCUDA(unsigned int type) {
  RTbuffer b = nullptr;
  checkError(rtBufferCreateForCUDA(context_, type, &b));
  return Buffer::take(b);
}
inline Buffer ContextObj::createBufferForCUDA(unsigned int type, RTformat format) {
  Buffer b = createBufferForCUDA(type);
  b->setFormat(format);
  return b;
}
inline Buffer ContextObj::createBufferForCUDA(unsigned int type, RTformat format, RTsize width) {
  Buffer b = createBufferForCUDA(type, format);
  b->setSize(width);
  return b;
}
inline Buffer ContextObj::createBufferForCUDA(unsigned int type, RTformat format, RTsize width,
                                              RTsize height) {
  Buffer b = createBufferForCUDA(type, format);
  b->setSize(width, height);
  return b;
}
inline Buffer ContextObj::createBufferForCUDA(unsigned int type, RTformat format, RTsize width,
                                              RTsize height, RTsize depth) {
  Buffer b = createBufferForCUDA(type, format);
  b->setSize(width, height, depth);
  return b;
}

inline Geometry ContextObj::createGeometry() {
  RTgeometry g = nullptr;
  checkError(rtGeometryCreate(context_, &g));
  return Geometry::take(g);
}
inline GeometryTriangles ContextObj::createGeometryTriangles() {
  RTgeometrytriangles g = nullptr;
  checkError(rtGeometryTrianglesCreate(context_, &g));
  return GeometryTriangles::take(g);
}
inline GeometryInstance ContextObj::createGeometryInstance() {
  RTgeometryinstance gi = nullptr;
  checkError(rtGeometryInstanceCreate(context_, &gi));
  return GeometryInstance::take(gi);
}
template <class Iterator>
GeometryInstance ContextObj::createGeometryInstance(Geometry geometry, Iterator matlbegin,
                                                    Iterator matlend) {
  GeometryInstance gi = createGeometryInstance();
  gi->setGeometry(geometry);
  unsigned int count = 0;
  for (Iterator it = matlbegin; it != matlend; ++it) ++count;
  gi->setMaterialCount(count);
  unsigned int index = 0;
  for (Iterator it = matlbegin; it != matlend; ++it) gi->setMaterial(index++, *it);
  return gi;
}
inline Group ContextObj::createGroup() {
  RTgroup g = nullptr;
  checkError(rtGroupCreate(context_, &g));
  return Group::take(g);
}
template <class Iterator>
Group ContextObj::createGroup(Iterator childbegin, Iterator childend) {
  Group group = createGroup();
  unsigned int count = 0;
  for (Iterator it = childbegin; it != childend; ++it) ++count;
  group->setChildCount(count);
  unsigned int index = 0;
  for (Iterator it = childbegin; it != childend; ++it) group->setChild(index++, *it);
  return group;
}
inline GeometryGroup ContextObj::createGeometryGroup() {
  RTgeometrygroup g = nullptr;
  checkError(rtGeometryGroupCreate(context_, &g));
  return GeometryGroup::take(g);
}
template <class Iterator>
GeometryGroup ContextObj::createGeometryGroup(Iterator childbegin, Iterator childend) {
  GeometryGroup group = createGeometryGroup();
  unsigned int count = 0;
  for (Iterator it = childbegin; it != childend; ++it) ++count;
  group->setChildCount(count);
  unsigned int index = 0;
  for (Iterator it = childbegin; it != childend; ++it) group->setChild(index++, *it);
  return group;
}
inline Transform ContextObj::createTransform() {
  RTtransform t = nullptr;
  checkError(rtTransformCreate(context_, &t));
  return Transform::take(t);
}
inline Material ContextObj::createMaterial() {
  RTmaterial m = nullptr;
  checkError(rtMaterialCreate(context_, &m));
  return Material::take(m);
}
inline Program ContextObj::createProgramFromPTXFile(const std::string& filename,
                                                    const std::string& program_name) {
  RTprogram p = nullptr;
  checkError(rtProgramCreateFromPTXFile(context_, filename.c_str(), program_name.c_str(), &p));
  return Program::take(p);
}
inline Program ContextObj::createProgramFromPTXString(const std::string& ptx,
                                                      const std::string& program_name) {
  RTprogram p = nullptr;
  checkError(rtProgramCreateFromPTXString(context_, ptx.c_str(), program_name.c_str(), &p));
  return Program::take(p);
}
inline Selector ContextObj::createSelector() {
  RTselector s = nullptr;
  checkError(rtSelectorCreate(context_, &s));
  return Selector::take(s);
}
inline TextureSampler ContextObj::createTextureSampler() {
  RTtexturesampler s = nullptr;
  checkError(rtTextureSamplerCreate(context_, &s));
  return TextureSampler::take(s);
}
inline TextureSampler ContextObj::getTextureSamplerFromId(int sampler_id) const {
  RTtexturesampler s = nullptr;
  checkError(rtContextGetTextureSamplerFromId(context_, sampler_id, &s));
  return TextureSampler::take(s);
}

inline Buffer ContextObj::getBufferFromId(int buffer_id) const {
  RTbuffer b = nullptr;
  checkError(rtContextGetBufferFromId(context_, buffer_id, &b));
  return Buffer::take(b);
}

inline Program ContextObj::getProgramFromId(int program_id) const {
  RTprogram p = nullptr;
  checkError(rtContextGetProgramFromId(context_, program_id, &p));
  return Program::take(p);
}

inline void ContextObj::launch(unsigned int entry_point_index, RTsize image_width) {
  checkError(rtContextLaunch1D(context_, entry_point_index, image_width));
}
inline void ContextObj::launch(unsigned int entry_point_index, RTsize image_width,
                               RTsize image_height) {
  checkError(rtContextLaunch2D(context_, entry_point_index, image_width, image_height));
}
inline void ContextObj::launch(unsigned int entry_point_index, RTsize image_width,
                               RTsize image_height, RTsize image_depth) {
  checkError(
      rtContextLaunch3D(context_, entry_point_index, image_width, image_height, image_depth));
}
inline int ContextObj::getRunningState() const {
  int running = 0;
  checkError(rtContextGetRunningState(context_, &running));
  return running;
}

inline void ContextObj::setStackSize(RTsize stack_size_bytes) {
  checkError(rtContextSetStackSize(context_, stack_size_bytes));
}
inline RTsize ContextObj::getStackSize() const {
  RTsize size = 0;
  checkError(rtContextGetStackSize(context_, &size));
  return size;
}
inline void ContextObj::setTimeoutCallback(RTtimeoutcallback callback, double min_polling_seconds) {
  checkError(rtContextSetTimeoutCallback(context_, callback, min_polling_seconds));
}

inline void ContextObj::setEntryPointCount(unsigned int num_entry_points) {
  checkError(rtContextSetEntryPointCount(context_, num_entry_points));
}
inline unsigned int ContextObj::getEntryPointCount() const {
  unsigned int count = 0;
  checkError(rtContextGetEntryPointCount(context_, &count));
  return count;
}
inline void ContextObj::setRayGenerationProgram(unsigned int entry_point_index, Program program) {
  checkError(
      rtContextSetRayGenerationProgram(context_, entry_point_index, optixpp_detail::Raw(program)));
}
inline Program ContextObj::getRayGenerationProgram(unsigned int entry_point_index) const {
  RTprogram p = nullptr;
  checkError(rtContextGetRayGenerationProgram(context_, entry_point_index, &p));
  return Program::take(p);
}
inline void ContextObj::setExceptionProgram(unsigned int entry_point_index, Program program) {
  checkError(
      rtContextSetExceptionProgram(context_, entry_point_index, optixpp_detail::Raw(program)));
}
inline Program ContextObj::getExceptionProgram(unsigned int entry_point_index) const {
  RTprogram p = nullptr;
  checkError(rtContextGetExceptionProgram(context_, entry_point_index, &p));
  return Program::take(p);
}
inline void ContextObj::setExceptionEnabled(RTexception exception, bool enabled) {
  checkError(rtContextSetExceptionEnabled(context_, exception, enabled ? 1 : 0));
}
inline bool ContextObj::getExceptionEnabled(RTexception exception) const {
  int enabled = 0;
  checkError(rtContextGetExceptionEnabled(context_, exception, &enabled));
  return enabled != 0;
}

inline void ContextObj::setRayTypeCount(unsigned int num_ray_types) {
  checkError(rtContextSetRayTypeCount(context_, num_ray_types));
}
inline unsigned int ContextObj::getRayTypeCount() const {
  unsigned int count = 0;
  checkError(rtContextGetRayTypeCount(context_, &count));
  return count;
}
inline void ContextObj::setMissProgram(unsigned int ray_type_index, Program program) {
  checkError(rtContextSetMissProgram(context_, ray_type_index, optixpp_detail::Raw(program)));
}
inline Program ContextObj::getMissProgram(unsigned int ray_type_index) const {
  RTprogram p = nullptr;
  checkError(rtContextGetMissProgram(context_, ray_type_index, &p));
  return Program::take(p);
}

inline void ContextObj::setPrintEnabled(bool enabled) {
  checkError(rtContextSetPrintEnabled(context_, enabled ? 1 : 0));
}
inline bool ContextObj::getPrintEnabled() const {
  int enabled = 0;
  checkError(rtContextGetPrintEnabled(context_, &enabled));
  return enabled != 0;
}
inline void ContextObj::setPrintBufferSize(RTsize buffer_size_bytes) {
  checkError(rtContextSetPrintBufferSize(context_, buffer_size_bytes));
}
inline RTsize ContextObj::getPrintBufferSize() const {
  RTsize size = 0;
  checkError(rtContextGetPrintBufferSize(context_, &size));
  return size;
}
inline void ContextObj::setPrintLaunchIndex(int x, int y, int z) {
  checkError(rtContextSetPrintLaunchIndex(context_, x, y, z));
}
inline int3 ContextObj::getPrintLaunchIndex() const {
  int3 index = {0, 0, 0};
  checkError(rtContextGetPrintLaunchIndex(context_, &index.x, &index.y, &index.z));
  return index;
}

// ---- Program --------------------------------------------------------------------------------

inline ProgramObj::ProgramObj(RTprogram program)
    : ScopedObj(optixpp_detail::ContextOf(&rtProgramGetContext, program)), program_(program) {}
OPTIXPP_SCOPED_DEFS_(ProgramObj, Program, program_)
inline int ProgramObj::getId() const {
  int id = 0;
  checkError(rtProgramGetId(program_, &id));
  return id;
}

// ---- Node children --------------------------------------------------------------------------

namespace optixpp_detail {

// Child handling shared by Group and Selector (`Fns` names the C functions).
template <class Api>
struct ChildFns {
  RTresult (*set_count)(Api, unsigned int);
  RTresult (*get_count)(Api, unsigned int*);
  RTresult (*set_child)(Api, unsigned int, RTobject);
  RTresult (*get_child)(Api, unsigned int, RTobject*);
  RTresult (*get_type)(Api, unsigned int, RTobjecttype*);
};

template <class T, class Api>
T GetTypedChild(const APIObj& owner, const ChildFns<Api>& fns, Api node, unsigned int index,
                const char* owner_kind) {
  RTobject child = nullptr;
  owner.checkError(fns.get_child(node, index, &child));
  RTobjecttype type = RT_OBJECTTYPE_UNKNOWN;
  owner.checkError(fns.get_type(node, index, &type));
  const RTobjecttype wanted = NodeType<typename T::element_type>::value;
  if (child != nullptr && type != wanted) {
    throw Exception(std::string("getChild: child ") + std::to_string(index) + " of the " +
                        owner_kind + " is a " + KindName(type) + ", not a " + KindName(wanted),
                    RT_ERROR_TYPE_MISMATCH);
  }
  return T::take(child);
}

template <class Api>
unsigned int AddChild(const APIObj& owner, const ChildFns<Api>& fns, Api node, RTobject child) {
  unsigned int count = 0;
  owner.checkError(fns.get_count(node, &count));
  owner.checkError(fns.set_count(node, count + 1));
  try {
    owner.checkError(fns.set_child(node, count, child));
  } catch (...) {
    fns.set_count(node, count);  // undo the growth; the error of the set is the one reported
    throw;
  }
  return count;
}

template <class Api>
void RemoveChild(const APIObj& owner, const ChildFns<Api>& fns, Api node, unsigned int index,
                 bool keep_order = false) {
  unsigned int count = 0;
  owner.checkError(fns.get_count(node, &count));
  if (index >= count) {
    throw Exception("removeChild: index " + std::to_string(index) + " is out of range (" +
                        std::to_string(count) + " children)",
                    RT_ERROR_INVALID_VALUE);
  }
  if (keep_order) {
    for (unsigned int i = index + 1; i < count; ++i) {
      RTobject next = nullptr;
      owner.checkError(fns.get_child(node, i, &next));
      owner.checkError(fns.set_child(node, i - 1, next));
    }
  } else if (index != count - 1) {
    RTobject last = nullptr;
    owner.checkError(fns.get_child(node, count - 1, &last));
    owner.checkError(fns.set_child(node, index, last));
  }
  owner.checkError(fns.set_count(node, count - 1));
}

template <class Api>
unsigned int ChildIndex(const APIObj& owner, const ChildFns<Api>& fns, Api node, RTobject child) {
  if (child == nullptr) {
    throw Exception("getChildIndex: null child handle", RT_ERROR_INVALID_VALUE);
  }
  unsigned int count = 0;
  owner.checkError(fns.get_count(node, &count));
  for (unsigned int i = 0; i < count; ++i) {
    RTobject c = nullptr;
    owner.checkError(fns.get_child(node, i, &c));
    if (c == child) return i;
  }
  throw Exception("getChildIndex: the object is not a child", RT_ERROR_INVALID_VALUE);
}

inline const ChildFns<RTgroup>& GroupFns() {
  static const ChildFns<RTgroup> fns = {&rtGroupSetChildCount, &rtGroupGetChildCount,
                                        &rtGroupSetChild, &rtGroupGetChild, &rtGroupGetChildType};
  return fns;
}
inline const ChildFns<RTselector>& SelectorFns() {
  static const ChildFns<RTselector> fns = {&rtSelectorSetChildCount, &rtSelectorGetChildCount,
                                           &rtSelectorSetChild, &rtSelectorGetChild,
                                           &rtSelectorGetChildType};
  return fns;
}

}  // namespace optixpp_detail

// ---- Group ----------------------------------------------------------------------------------

inline GroupObj::GroupObj(RTgroup group)
    : DestroyableObj(optixpp_detail::ContextOf(&rtGroupGetContext, group)), group_(group) {}
OPTIXPP_DESTROYABLE_DEFS_(GroupObj, Group, group_)

inline void GroupObj::setAcceleration(Acceleration acceleration) {
  checkError(rtGroupSetAcceleration(group_, optixpp_detail::Raw(acceleration)));
}
inline Acceleration GroupObj::getAcceleration() const {
  RTacceleration a = nullptr;
  checkError(rtGroupGetAcceleration(group_, &a));
  return Acceleration::take(a);
}
inline void GroupObj::setChildCount(unsigned int count) {
  checkError(rtGroupSetChildCount(group_, count));
}
inline unsigned int GroupObj::getChildCount() const {
  unsigned int count = 0;
  checkError(rtGroupGetChildCount(group_, &count));
  return count;
}
template <class T>
void GroupObj::setChild(unsigned int index, T child) {
  checkError(rtGroupSetChild(group_, index, optixpp_detail::Raw(child)));
}
template <class T>
T GroupObj::getChild(unsigned int index) const {
  return optixpp_detail::GetTypedChild<T>(*this, optixpp_detail::GroupFns(), group_, index,
                                          "group");
}
inline RTobjecttype GroupObj::getChildType(unsigned int index) const {
  RTobjecttype type = RT_OBJECTTYPE_UNKNOWN;
  checkError(rtGroupGetChildType(group_, index, &type));
  return type;
}
template <class T>
unsigned int GroupObj::addChild(T child) {
  return optixpp_detail::AddChild(*this, optixpp_detail::GroupFns(), group_,
                                  optixpp_detail::Raw(child));
}
inline void GroupObj::removeChild(unsigned int index) {
  optixpp_detail::RemoveChild(*this, optixpp_detail::GroupFns(), group_, index);
}
template <class T>
unsigned int GroupObj::removeChild(Handle<T> child) {
  const unsigned int index = getChildIndex(child);
  removeChild(index);
  return index;
}
template <class T>
unsigned int GroupObj::getChildIndex(T child) const {
  return optixpp_detail::ChildIndex(*this, optixpp_detail::GroupFns(), group_,
                                    optixpp_detail::Raw(child));
}

// ---- GeometryGroup --------------------------------------------------------------------------

inline GeometryGroupObj::GeometryGroupObj(RTgeometrygroup geometrygroup)
    : DestroyableObj(optixpp_detail::ContextOf(&rtGeometryGroupGetContext, geometrygroup)),
      geometrygroup_(geometrygroup) {}
OPTIXPP_DESTROYABLE_DEFS_(GeometryGroupObj, GeometryGroup, geometrygroup_)

inline void GeometryGroupObj::setAcceleration(Acceleration acceleration) {
  checkError(rtGeometryGroupSetAcceleration(geometrygroup_, optixpp_detail::Raw(acceleration)));
}
inline Acceleration GeometryGroupObj::getAcceleration() const {
  RTacceleration a = nullptr;
  checkError(rtGeometryGroupGetAcceleration(geometrygroup_, &a));
  return Acceleration::take(a);
}
inline void GeometryGroupObj::setChildCount(unsigned int count) {
  checkError(rtGeometryGroupSetChildCount(geometrygroup_, count));
}
inline unsigned int GeometryGroupObj::getChildCount() const {
  unsigned int count = 0;
  checkError(rtGeometryGroupGetChildCount(geometrygroup_, &count));
  return count;
}
inline void GeometryGroupObj::setChild(unsigned int index, GeometryInstance geometryinstance) {
  checkError(rtGeometryGroupSetChild(geometrygroup_, index, optixpp_detail::Raw(geometryinstance)));
}
inline GeometryInstance GeometryGroupObj::getChild(unsigned int index) const {
  RTgeometryinstance gi = nullptr;
  checkError(rtGeometryGroupGetChild(geometrygroup_, index, &gi));
  return GeometryInstance::take(gi);
}
inline unsigned int GeometryGroupObj::addChild(GeometryInstance geometryinstance) {
  const unsigned int index = getChildCount();
  setChildCount(index + 1);
  try {
    setChild(index, geometryinstance);
  } catch (...) {
    rtGeometryGroupSetChildCount(geometrygroup_, index);  // undo the growth
    throw;
  }
  return index;
}
inline void GeometryGroupObj::removeChild(unsigned int index) {
  const unsigned int count = getChildCount();
  if (index >= count) {
    throw Exception("removeChild: index " + std::to_string(index) + " is out of range (" +
                        std::to_string(count) + " children)",
                    RT_ERROR_INVALID_VALUE);
  }
  if (index != count - 1) setChild(index, getChild(count - 1));
  setChildCount(count - 1);
}
inline unsigned int GeometryGroupObj::removeChild(GeometryInstance geometryinstance) {
  const unsigned int index = getChildIndex(geometryinstance);
  removeChild(index);
  return index;
}
inline unsigned int GeometryGroupObj::getChildIndex(GeometryInstance geometryinstance) const {
  if (!geometryinstance) {
    throw Exception("getChildIndex: null geometry instance handle", RT_ERROR_INVALID_VALUE);
  }
  const unsigned int count = getChildCount();
  for (unsigned int i = 0; i < count; ++i) {
    RTgeometryinstance gi = nullptr;
    checkError(rtGeometryGroupGetChild(geometrygroup_, i, &gi));
    if (gi == optixpp_detail::Raw(geometryinstance)) return i;
  }
  throw Exception("getChildIndex: the geometry instance is not a child", RT_ERROR_INVALID_VALUE);
}

// ---- Transform ------------------------------------------------------------------------------

inline TransformObj::TransformObj(RTtransform transform)
    : DestroyableObj(optixpp_detail::ContextOf(&rtTransformGetContext, transform)),
      transform_(transform) {}
OPTIXPP_DESTROYABLE_DEFS_(TransformObj, Transform, transform_)

template <class T>
void TransformObj::setChild(T child) {
  checkError(rtTransformSetChild(transform_, optixpp_detail::Raw(child)));
}
template <class T>
T TransformObj::getChild() const {
  RTobject child = nullptr;
  checkError(rtTransformGetChild(transform_, &child));
  const RTobjecttype wanted = optixpp_detail::NodeType<typename T::element_type>::value;
  const RTobjecttype type = child != nullptr ? getChildType() : wanted;
  if (type != wanted) {
    throw Exception(std::string("getChild: the transform's child is a ") +
                        optixpp_detail::KindName(type) + ", not a " +
                        optixpp_detail::KindName(wanted),
                    RT_ERROR_TYPE_MISMATCH);
  }
  return T::take(child);
}
inline RTobjecttype TransformObj::getChildType() const {
  RTobjecttype type = RT_OBJECTTYPE_UNKNOWN;
  checkError(rtTransformGetChildType(transform_, &type));
  return type;
}
inline void TransformObj::setMatrix(bool transpose, const float* matrix,
                                    const float* inverse_matrix) {
  checkError(rtTransformSetMatrix(transform_, transpose ? 1 : 0, matrix, inverse_matrix));
}
inline void TransformObj::getMatrix(bool transpose, float* matrix, float* inverse_matrix) const {
  checkError(rtTransformGetMatrix(transform_, transpose ? 1 : 0, matrix, inverse_matrix));
}

// ---- Selector -------------------------------------------------------------------------------

inline SelectorObj::SelectorObj(RTselector selector)
    : ScopedObj(optixpp_detail::ContextOf(&rtSelectorGetContext, selector)), selector_(selector) {}
OPTIXPP_SCOPED_DEFS_(SelectorObj, Selector, selector_)

inline void SelectorObj::setVisitProgram(Program program) {
  checkError(rtSelectorSetVisitProgram(selector_, optixpp_detail::Raw(program)));
}
inline Program SelectorObj::getVisitProgram() const {
  RTprogram p = nullptr;
  checkError(rtSelectorGetVisitProgram(selector_, &p));
  return Program::take(p);
}
inline void SelectorObj::setChildCount(unsigned int count) {
  checkError(rtSelectorSetChildCount(selector_, count));
}
inline unsigned int SelectorObj::getChildCount() const {
  unsigned int count = 0;
  checkError(rtSelectorGetChildCount(selector_, &count));
  return count;
}
template <class T>
void SelectorObj::setChild(unsigned int index, T child) {
  checkError(rtSelectorSetChild(selector_, index, optixpp_detail::Raw(child)));
}
template <class T>
T SelectorObj::getChild(unsigned int index) const {
  return optixpp_detail::GetTypedChild<T>(*this, optixpp_detail::SelectorFns(), selector_, index,
                                          "selector");
}
inline RTobjecttype SelectorObj::getChildType(unsigned int index) const {
  RTobjecttype type = RT_OBJECTTYPE_UNKNOWN;
  checkError(rtSelectorGetChildType(selector_, index, &type));
  return type;
}
template <class T>
unsigned int SelectorObj::addChild(T child) {
  return optixpp_detail::AddChild(*this, optixpp_detail::SelectorFns(), selector_,
                                  optixpp_detail::Raw(child));
}
inline void SelectorObj::removeChild(unsigned int index) {
  optixpp_detail::RemoveChild(*this, optixpp_detail::SelectorFns(), selector_, index,
                              /*keep_order=*/true);
}
template <class T>
unsigned int SelectorObj::removeChild(Handle<T> child) {
  const unsigned int index = getChildIndex(child);
  removeChild(index);
  return index;
}
template <class T>
unsigned int SelectorObj::getChildIndex(T child) const {
  return optixpp_detail::ChildIndex(*this, optixpp_detail::SelectorFns(), selector_,
                                    optixpp_detail::Raw(child));
}

// ---- Acceleration ---------------------------------------------------------------------------

inline AccelerationObj::AccelerationObj(RTacceleration acceleration)
    : DestroyableObj(optixpp_detail::ContextOf(&rtAccelerationGetContext, acceleration)),
      acceleration_(acceleration) {}
OPTIXPP_DESTROYABLE_DEFS_(AccelerationObj, Acceleration, acceleration_)

inline void AccelerationObj::markDirty() { checkError(rtAccelerationMarkDirty(acceleration_)); }
inline bool AccelerationObj::isDirty() const {
  int dirty = 0;
  checkError(rtAccelerationIsDirty(acceleration_, &dirty));
  return dirty != 0;
}
inline void AccelerationObj::setProperty(const std::string& name, const std::string& value) {
  checkError(rtAccelerationSetProperty(acceleration_, name.c_str(), value.c_str()));
}
inline std::string AccelerationObj::getProperty(const std::string& name) const {
  const char* value = nullptr;
  checkError(rtAccelerationGetProperty(acceleration_, name.c_str(), &value));
  return value != nullptr ? value : "";
}
inline void AccelerationObj::setBuilder(const std::string& builder) {
  checkError(rtAccelerationSetBuilder(acceleration_, builder.c_str()));
}
inline std::string AccelerationObj::getBuilder() const {
  const char* builder = nullptr;
  checkError(rtAccelerationGetBuilder(acceleration_, &builder));
  return builder != nullptr ? builder : "";
}
inline void AccelerationObj::setTraverser(const std::string& traverser) {
  checkError(rtAccelerationSetTraverser(acceleration_, traverser.c_str()));
}
inline std::string AccelerationObj::getTraverser() const {
  const char* traverser = nullptr;
  checkError(rtAccelerationGetTraverser(acceleration_, &traverser));
  return traverser != nullptr ? traverser : "";
}
inline RTsize AccelerationObj::getDataSize() const {
  RTsize size = 0;
  checkError(rtAccelerationGetDataSize(acceleration_, &size));
  return size;
}
inline void AccelerationObj::getData(void* data) const {
  checkError(rtAccelerationGetData(acceleration_, data));
}
inline void AccelerationObj::setData(const void* data, RTsize size) {
  checkError(rtAccelerationSetData(acceleration_, data, size));
}

// ---- GeometryInstance -----------------------------------------------------------------------

inline GeometryInstanceObj::GeometryInstanceObj(RTgeometryinstance geometryinstance)
    : ScopedObj(optixpp_detail::ContextOf(&rtGeometryInstanceGetContext, geometryinstance)),
      geometryinstance_(geometryinstance) {}
OPTIXPP_SCOPED_DEFS_(GeometryInstanceObj, GeometryInstance, geometryinstance_)

inline void GeometryInstanceObj::setGeometry(Geometry geometry) {
  checkError(rtGeometryInstanceSetGeometry(geometryinstance_, optixpp_detail::Raw(geometry)));
}
inline Geometry GeometryInstanceObj::getGeometry() const {
  RTgeometry g = nullptr;
  checkError(rtGeometryInstanceGetGeometry(geometryinstance_, &g));
  return Geometry::take(g);
}
inline void GeometryInstanceObj::setGeometryTriangles(GeometryTriangles geometrytriangles) {
  checkError(rtGeometryInstanceSetGeometryTriangles(geometryinstance_,
                                                    optixpp_detail::Raw(geometrytriangles)));
}
inline GeometryTriangles GeometryInstanceObj::getGeometryTriangles() const {
  RTgeometrytriangles g = nullptr;
  checkError(rtGeometryInstanceGetGeometryTriangles(geometryinstance_, &g));
  return GeometryTriangles::take(g);
}
inline void GeometryInstanceObj::setMaterialCount(unsigned int count) {
  checkError(rtGeometryInstanceSetMaterialCount(geometryinstance_, count));
}
inline unsigned int GeometryInstanceObj::getMaterialCount() const {
  unsigned int count = 0;
  checkError(rtGeometryInstanceGetMaterialCount(geometryinstance_, &count));
  return count;
}
inline void GeometryInstanceObj::setMaterial(unsigned int index, Material material) {
  checkError(
      rtGeometryInstanceSetMaterial(geometryinstance_, index, optixpp_detail::Raw(material)));
}
inline Material GeometryInstanceObj::getMaterial(unsigned int index) const {
  RTmaterial m = nullptr;
  checkError(rtGeometryInstanceGetMaterial(geometryinstance_, index, &m));
  return Material::take(m);
}
inline unsigned int GeometryInstanceObj::addMaterial(Material material) {
  const unsigned int index = getMaterialCount();
  setMaterialCount(index + 1);
  try {
    setMaterial(index, material);
  } catch (...) {
    rtGeometryInstanceSetMaterialCount(geometryinstance_, index);  // undo the growth
    throw;
  }
  return index;
}

// ---- Geometry -------------------------------------------------------------------------------

inline GeometryObj::GeometryObj(RTgeometry geometry)
    : ScopedObj(optixpp_detail::ContextOf(&rtGeometryGetContext, geometry)), geometry_(geometry) {}
OPTIXPP_SCOPED_DEFS_(GeometryObj, Geometry, geometry_)

inline void GeometryObj::markDirty() { checkError(rtGeometryMarkDirty(geometry_)); }
inline bool GeometryObj::isDirty() const {
  int dirty = 0;
  checkError(rtGeometryIsDirty(geometry_, &dirty));
  return dirty != 0;
}
inline void GeometryObj::setPrimitiveCount(unsigned int num_primitives) {
  checkError(rtGeometrySetPrimitiveCount(geometry_, num_primitives));
}
inline unsigned int GeometryObj::getPrimitiveCount() const {
  unsigned int count = 0;
  checkError(rtGeometryGetPrimitiveCount(geometry_, &count));
  return count;
}
inline void GeometryObj::setBoundingBoxProgram(Program program) {
  checkError(rtGeometrySetBoundingBoxProgram(geometry_, optixpp_detail::Raw(program)));
}
inline Program GeometryObj::getBoundingBoxProgram() const {
  RTprogram p = nullptr;
  checkError(rtGeometryGetBoundingBoxProgram(geometry_, &p));
  return Program::take(p);
}
inline void GeometryObj::setIntersectionProgram(Program program) {
  checkError(rtGeometrySetIntersectionProgram(geometry_, optixpp_detail::Raw(program)));
}
inline Program GeometryObj::getIntersectionProgram() const {
  RTprogram p = nullptr;
  checkError(rtGeometryGetIntersectionProgram(geometry_, &p));
  return Program::take(p);
}

// ---- GeometryTriangles ----------------------------------------------------------------------

inline GeometryTrianglesObj::GeometryTrianglesObj(RTgeometrytriangles geometrytriangles)
    : ScopedObj(optixpp_detail::ContextOf(&rtGeometryTrianglesGetContext, geometrytriangles)),
      geometrytriangles_(geometrytriangles) {}
OPTIXPP_SCOPED_DEFS_(GeometryTrianglesObj, GeometryTriangles, geometrytriangles_)

inline void GeometryTrianglesObj::setPrimitiveIndexOffset(unsigned int index_offset) {
  checkError(rtGeometryTrianglesSetPrimitiveIndexOffset(geometrytriangles_, index_offset));
}
inline unsigned int GeometryTrianglesObj::getPrimitiveIndexOffset() const {
  unsigned int offset = 0;
  checkError(rtGeometryTrianglesGetPrimitiveIndexOffset(geometrytriangles_, &offset));
  return offset;
}
inline void GeometryTrianglesObj::setPrimitiveCount(unsigned int num_triangles) {
  checkError(rtGeometryTrianglesSetPrimitiveCount(geometrytriangles_, num_triangles));
}
inline unsigned int GeometryTrianglesObj::getPrimitiveCount() const {
  unsigned int count = 0;
  checkError(rtGeometryTrianglesGetPrimitiveCount(geometrytriangles_, &count));
  return count;
}
inline void GeometryTrianglesObj::setTriangleIndices(Buffer index_buffer,
                                                     RTformat tri_indices_format) {
  setTriangleIndices(index_buffer, 0, 0, tri_indices_format);
}
inline void GeometryTrianglesObj::setTriangleIndices(Buffer index_buffer,
                                                     RTsize index_buffer_byte_offset,
                                                     RTformat tri_indices_format) {
  setTriangleIndices(index_buffer, index_buffer_byte_offset, 0, tri_indices_format);
}
inline void GeometryTrianglesObj::setTriangleIndices(Buffer index_buffer,
                                                     RTsize index_buffer_byte_offset,
                                                     RTsize tri_indices_byte_stride,
                                                     RTformat tri_indices_format) {
  checkError(rtGeometryTrianglesSetTriangleIndices(
      geometrytriangles_, optixpp_detail::Raw(index_buffer), index_buffer_byte_offset,
      tri_indices_byte_stride, tri_indices_format));
}
inline void GeometryTrianglesObj::setVertices(unsigned int num_vertices, Buffer vertex_buffer,
                                              RTformat position_format) {
  setVertices(num_vertices, vertex_buffer, 0, 0, position_format);
}
inline void GeometryTrianglesObj::setVertices(unsigned int num_vertices, Buffer vertex_buffer,
                                              RTsize vertex_buffer_byte_offset,
                                              RTsize vertex_byte_stride, RTformat position_format) {
  checkError(rtGeometryTrianglesSetVertices(
      geometrytriangles_, num_vertices, optixpp_detail::Raw(vertex_buffer),
      vertex_buffer_byte_offset, vertex_byte_stride, position_format));
}
inline void GeometryTrianglesObj::setAttributeProgram(Program program) {
  checkError(
      rtGeometryTrianglesSetAttributeProgram(geometrytriangles_, optixpp_detail::Raw(program)));
}
inline Program GeometryTrianglesObj::getAttributeProgram() const {
  RTprogram p = nullptr;
  checkError(rtGeometryTrianglesGetAttributeProgram(geometrytriangles_, &p));
  return Program::take(p);
}
inline void GeometryTrianglesObj::setMaterialCount(unsigned int num_materials) {
  checkError(rtGeometryTrianglesSetMaterialCount(geometrytriangles_, num_materials));
}
inline unsigned int GeometryTrianglesObj::getMaterialCount() const {
  unsigned int count = 0;
  checkError(rtGeometryTrianglesGetMaterialCount(geometrytriangles_, &count));
  return count;
}
inline void GeometryTrianglesObj::setMaterialIndices(Buffer material_index_buffer,
                                                     RTsize material_index_buffer_byte_offset,
                                                     RTsize material_index_byte_stride,
                                                     RTformat material_index_format) {
  checkError(rtGeometryTrianglesSetMaterialIndices(
      geometrytriangles_, optixpp_detail::Raw(material_index_buffer),
      material_index_buffer_byte_offset, material_index_byte_stride, material_index_format));
}

// ---- Material -------------------------------------------------------------------------------

inline MaterialObj::MaterialObj(RTmaterial material)
    : ScopedObj(optixpp_detail::ContextOf(&rtMaterialGetContext, material)), material_(material) {}
OPTIXPP_SCOPED_DEFS_(MaterialObj, Material, material_)

inline void MaterialObj::setClosestHitProgram(unsigned int ray_type_index, Program program) {
  checkError(
      rtMaterialSetClosestHitProgram(material_, ray_type_index, optixpp_detail::Raw(program)));
}
inline Program MaterialObj::getClosestHitProgram(unsigned int ray_type_index) const {
  RTprogram p = nullptr;
  checkError(rtMaterialGetClosestHitProgram(material_, ray_type_index, &p));
  return Program::take(p);
}
inline void MaterialObj::setAnyHitProgram(unsigned int ray_type_index, Program program) {
  checkError(rtMaterialSetAnyHitProgram(material_, ray_type_index, optixpp_detail::Raw(program)));
}
inline Program MaterialObj::getAnyHitProgram(unsigned int ray_type_index) const {
  RTprogram p = nullptr;
  checkError(rtMaterialGetAnyHitProgram(material_, ray_type_index, &p));
  return Program::take(p);
}

// ---- Buffer ---------------------------------------------------------------------------------

inline BufferObj::BufferObj(RTbuffer buffer)
    : DestroyableObj(optixpp_detail::ContextOf(&rtBufferGetContext, buffer)), buffer_(buffer) {}
OPTIXPP_DESTROYABLE_DEFS_(BufferObj, Buffer, buffer_)

inline void BufferObj::setFormat(RTformat format) {
  checkError(rtBufferSetFormat(buffer_, format));
}
inline RTformat BufferObj::getFormat() const {
  RTformat format = RT_FORMAT_UNKNOWN;
  checkError(rtBufferGetFormat(buffer_, &format));
  return format;
}
inline void BufferObj::setElementSize(RTsize size_of_element) {
  checkError(rtBufferSetElementSize(buffer_, size_of_element));
}
inline RTsize BufferObj::getElementSize() const {
  RTsize size = 0;
  checkError(rtBufferGetElementSize(buffer_, &size));
  return size;
}
inline void BufferObj::setSize(RTsize width) { checkError(rtBufferSetSize1D(buffer_, width)); }
inline void BufferObj::getSize(RTsize& width) const {
  checkError(rtBufferGetSize1D(buffer_, &width));
}
inline void BufferObj::setSize(RTsize width, RTsize height) {
  checkError(rtBufferSetSize2D(buffer_, width, height));
}
inline void BufferObj::getSize(RTsize& width, RTsize& height) const {
  checkError(rtBufferGetSize2D(buffer_, &width, &height));
}
inline void BufferObj::setSize(RTsize width, RTsize height, RTsize depth) {
  checkError(rtBufferSetSize3D(buffer_, width, height, depth));
}
inline void BufferObj::getSize(RTsize& width, RTsize& height, RTsize& depth) const {
  checkError(rtBufferGetSize3D(buffer_, &width, &height, &depth));
}
inline void BufferObj::setSize(unsigned int dimensionality, const RTsize* dims) {
  checkError(rtBufferSetSizev(buffer_, dimensionality, dims));
}
inline void BufferObj::getSize(unsigned int dimensionality, RTsize* dims) const {
  checkError(rtBufferGetSizev(buffer_, dimensionality, dims));
}
inline unsigned int BufferObj::getDimensionality() const {
  unsigned int dimensionality = 0;
  checkError(rtBufferGetDimensionality(buffer_, &dimensionality));
  return dimensionality;
}
inline void* BufferObj::map(unsigned int level, unsigned int map_flags, void* user_owned) {
  if (user_owned != nullptr) {
    throw Exception("Buffer::map: user-owned memory is not supported", RT_ERROR_NOT_SUPPORTED);
  }
  void* p = nullptr;
  checkError(rtBufferMapEx(buffer_, map_flags, level, nullptr, &p));
  return p;
}
inline void BufferObj::unmap(unsigned int level) { checkError(rtBufferUnmapEx(buffer_, level)); }
inline void BufferObj::setMipLevelCount(unsigned int levels) {
  checkError(rtBufferSetMipLevelCount(buffer_, levels));
}
inline unsigned int BufferObj::getMipLevelCount() const {
  unsigned int levels = 0;
  checkError(rtBufferGetMipLevelCount(buffer_, &levels));
  return levels;
}
inline void BufferObj::getMipLevelSize(unsigned int level, RTsize& width) const {
  checkError(rtBufferGetMipLevelSize1D(buffer_, level, &width));
}
inline void BufferObj::getMipLevelSize(unsigned int level, RTsize& width, RTsize& height) const {
  checkError(rtBufferGetMipLevelSize2D(buffer_, level, &width, &height));
}
inline void BufferObj::getMipLevelSize(unsigned int level, RTsize& width, RTsize& height,
                                       RTsize& depth) const {
  checkError(rtBufferGetMipLevelSize3D(buffer_, level, &width, &height, &depth));
}
inline int BufferObj::getId() const {
  int id = 0;
  checkError(rtBufferGetId(buffer_, &id));
  return id;
}
inline void BufferObj::markDirty() { checkError(rtBufferMarkDirty(buffer_)); }
inline void* BufferObj::getDevicePointer(int optix_device_number) {
  void* p = nullptr;
  checkError(rtBufferGetDevicePointer(buffer_, static_cast<unsigned int>(optix_device_number), &p));
  return p;
}
inline void BufferObj::setDevicePointer(int optix_device_number, void* device_pointer) {
  checkError(rtBufferSetDevicePointer(buffer_, static_cast<unsigned int>(optix_device_number),
                                      device_pointer));
}

// ---- TextureSampler -------------------------------------------------------------------------

inline TextureSamplerObj::TextureSamplerObj(RTtexturesampler sampler)
    : DestroyableObj(optixpp_detail::ContextOf(&rtTextureSamplerGetContext, sampler)),
      sampler_(sampler) {}
OPTIXPP_DESTROYABLE_DEFS_(TextureSamplerObj, TextureSampler, sampler_)

inline void TextureSamplerObj::setMipLevelCount(unsigned int num_mip_levels) {
  checkError(rtTextureSamplerSetMipLevelCount(sampler_, num_mip_levels));
}
inline unsigned int TextureSamplerObj::getMipLevelCount() const {
  unsigned int n = 0;
  checkError(rtTextureSamplerGetMipLevelCount(sampler_, &n));
  return n;
}
inline void TextureSamplerObj::setArraySize(unsigned int num_textures_in_array) {
  checkError(rtTextureSamplerSetArraySize(sampler_, num_textures_in_array));
}
inline unsigned int TextureSamplerObj::getArraySize() const {
  unsigned int n = 0;
  checkError(rtTextureSamplerGetArraySize(sampler_, &n));
  return n;
}
inline void TextureSamplerObj::setWrapMode(unsigned int dim, RTwrapmode wrapmode) {
  checkError(rtTextureSamplerSetWrapMode(sampler_, dim, wrapmode));
}
inline RTwrapmode TextureSamplerObj::getWrapMode(unsigned int dim) const {
  RTwrapmode mode = RT_WRAP_REPEAT;
  checkError(rtTextureSamplerGetWrapMode(sampler_, dim, &mode));
  return mode;
}
inline void TextureSamplerObj::setFilteringModes(RTfiltermode minification,
                                                 RTfiltermode magnification,
                                                 RTfiltermode mipmapping) {
  checkError(rtTextureSamplerSetFilteringModes(sampler_, minification, magnification, mipmapping));
}
inline void TextureSamplerObj::getFilteringModes(RTfiltermode& minification,
                                                 RTfiltermode& magnification,
                                                 RTfiltermode& mipmapping) const {
  checkError(
      rtTextureSamplerGetFilteringModes(sampler_, &minification, &magnification, &mipmapping));
}
inline void TextureSamplerObj::setMaxAnisotropy(float value) {
  checkError(rtTextureSamplerSetMaxAnisotropy(sampler_, value));
}
inline float TextureSamplerObj::getMaxAnisotropy() const {
  float value = 0.f;
  checkError(rtTextureSamplerGetMaxAnisotropy(sampler_, &value));
  return value;
}
inline void TextureSamplerObj::setMipLevelClamp(float min_level, float max_level) {
  checkError(rtTextureSamplerSetMipLevelClamp(sampler_, min_level, max_level));
}
inline void TextureSamplerObj::getMipLevelClamp(float& min_level, float& max_level) const {
  checkError(rtTextureSamplerGetMipLevelClamp(sampler_, &min_level, &max_level));
}
inline void TextureSamplerObj::setMipLevelBias(float value) {
  checkError(rtTextureSamplerSetMipLevelBias(sampler_, value));
}
inline float TextureSamplerObj::getMipLevelBias() const {
  float value = 0.f;
  checkError(rtTextureSamplerGetMipLevelBias(sampler_, &value));
  return value;
}
inline void TextureSamplerObj::setReadMode(RTtexturereadmode readmode) {
  checkError(rtTextureSamplerSetReadMode(sampler_, readmode));
}
inline RTtexturereadmode TextureSamplerObj::getReadMode() const {
  RTtexturereadmode mode = RT_TEXTURE_READ_ELEMENT_TYPE;
  checkError(rtTextureSamplerGetReadMode(sampler_, &mode));
  return mode;
}
inline void TextureSamplerObj::setIndexingMode(RTtextureindexmode indexmode) {
  checkError(rtTextureSamplerSetIndexingMode(sampler_, indexmode));
}
inline RTtextureindexmode TextureSamplerObj::getIndexingMode() const {
  RTtextureindexmode mode = RT_TEXTURE_INDEX_NORMALIZED_COORDINATES;
  checkError(rtTextureSamplerGetIndexingMode(sampler_, &mode));
  return mode;
}
inline void TextureSamplerObj::setBuffer(unsigned int texture_array_idx, unsigned int mip_level,
                                         Buffer buffer) {
  checkError(rtTextureSamplerSetBuffer(sampler_, texture_array_idx, mip_level,
                                       optixpp_detail::Raw(buffer)));
}
inline Buffer TextureSamplerObj::getBuffer(unsigned int texture_array_idx,
                                           unsigned int mip_level) const {
  RTbuffer b = nullptr;
  checkError(rtTextureSamplerGetBuffer(sampler_, texture_array_idx, mip_level, &b));
  return Buffer::take(b);
}
inline void TextureSamplerObj::setBuffer(Buffer buffer) { setBuffer(0, 0, buffer); }
inline Buffer TextureSamplerObj::getBuffer() const { return getBuffer(0, 0); }
inline int TextureSamplerObj::getId() const {
  int id = 0;
  checkError(rtTextureSamplerGetId(sampler_, &id));
  return id;
}

#undef OPTIXPP_SCOPED_DEFS_
#undef OPTIXPP_DESTROYABLE_DEFS_

}  // namespace optix

#endif  // OPTIXU_OPTIXPP_NAMESPACE_H_
