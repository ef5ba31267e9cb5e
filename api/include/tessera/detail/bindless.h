// OptiX 3.5+ ids on the program side, included by tessera/device.h (which it relies on):
//  - rtBufferId<T, Dim>: a buffer reached by the id rtBufferGetId gave, not by a variable;
//  - rtCallableProgramId<R(A...)>: a "bindless" callable program, reached by the id
//    rtProgramGetId gave; it sees its own scope's variables, then the context's;
//  - rtCallableProgramX<R(A...)>: a "bound" callable program, set with rtVariableSetObject like an
//    rtCallableProgram variable (OptiX 3.6's templated spelling of it).
// Ids are plain ints: a struct, a payload, a variable set with rtVariableSetInt, or a buffer of
// RT_FORMAT_BUFFER_ID / RT_FORMAT_PROGRAM_ID elements carries them. The engine resolves an id
// through a table indexed by id that it builds once per launch plan (docs/programs.md, "Buffer
// and program ids").
#ifndef TESSERA_DETAIL_BINDLESS_H_
#define TESSERA_DETAIL_BINDLESS_H_

#include <type_traits>

namespace tessera::detail {

// The running plan's buffers by id (TesseraRuntime::buffer_id_table_offset); never null.
inline const TesseraBufferIdTable* BufferIdTable() {
  return AtThreadPointer<const TesseraBufferIdTable>(Rt()->buffer_id_table_offset);
}

}  // namespace tessera::detail

namespace optix {

// A host translation unit that included optixu/optixpp_namespace.h first has its host versions
// of these (an int and getId(), to fill mapped buffers): a program module includes optix.h first.
#ifndef TESSERA_OPTIXPP_HOST_ID_TYPES_

// The buffer of id `getId()`. Indices go through the same checks and write marks as an rtBuffer
// (tessera::detail::BufferAccess): elements written in an OUTPUT or INPUT_OUTPUT buffer reach
// the host after the launch. An invalid id (RT_BUFFER_ID_NULL, or no buffer of the context has
// it) raises RT_EXCEPTION_BUFFER_ID_INVALID; with that exception disabled the buffer reads as
// empty: size() is 0, reads give zeros and writes go to scratch memory. A buffer whose elements
// or dimensionality differ from T and Dim fails the launch, naming it.
template <typename T, int Dim = 1>
class bufferId : public ::tessera::detail::BufferAccess<bufferId<T, Dim>, T, Dim> {
 public:
  bufferId() = default;
  bufferId(RTbufferidnull) {
  }  // NOLINT: implicit, as in OptiX (`bufferId<float> b = RT_BUFFER_ID_NULL`)
  explicit bufferId(int id) : id_(id) {}
  bufferId& operator=(RTbufferidnull) {
    id_ = RT_BUFFER_ID_NULL;
    return *this;
  }
  int getId() const { return id_; }
  operator bool() const { return id_ != RT_BUFFER_ID_NULL; }  // NOLINT: as OptiX

 private:
  friend class ::tessera::detail::BufferAccess<bufferId<T, Dim>, T, Dim>;
  // The engine's table indexed by id, read without a call when the id's entry exists and fits
  // T and Dim; anything else asks the engine, which raises or fails the launch as it must.
  const TesseraBufferView& View() const {
    const TesseraBufferIdTable* t = ::tessera::detail::BufferIdTable();
    const unsigned long long u = static_cast<unsigned>(id_);  // a negative id is past the end
    if (u < t->count) {
      const TesseraBufferIdEntry& e = t->entries[u];
      if (e.view != nullptr && e.view->element_size == sizeof(T) &&
          (e.dimensionality == 0 || e.dimensionality == Dim)) {
        return *e.view;
      }
    }
    return *::tessera::detail::Rt()->buffer_by_id(id_, sizeof(T), Dim);
  }
  void* OutOfBounds(unsigned long long x, unsigned long long y, unsigned long long z) const {
    return ::tessera::detail::Rt()->buffer_id_index_error(id_, sizeof(T), x, y, z);
  }

  // Unlike OptiX, a default-constructed id is RT_BUFFER_ID_NULL rather than garbage.
  int id_ = RT_BUFFER_ID_NULL;
};

template <typename Signature>
class callableProgramId;

// The callable program of id `getId()`, called like a function. Signatures are not checked (a
// module's symbols carry none): the program must take and return what the type says, as in C.
// An invalid id (RT_PROGRAM_ID_NULL, or no program of the context was given it) raises
// RT_EXCEPTION_PROGRAM_ID_INVALID; with that exception disabled the call is skipped and returns
// R() (a type without a default constructor fails the launch instead).
template <typename R, typename... A>
class callableProgramId<R(A...)> {
 public:
  callableProgramId() = default;
  callableProgramId(RTprogramidnull) {}  // NOLINT: implicit, as in OptiX
  explicit callableProgramId(int id) : id_(id) {}
  callableProgramId& operator=(RTprogramidnull) {
    id_ = RT_PROGRAM_ID_NULL;
    return *this;
  }
  int getId() const { return id_; }
  operator bool() const { return id_ != RT_PROGRAM_ID_NULL; }  // NOLINT: as OptiX

  R operator()(A... args) const {
    constexpr bool kSkippable = std::is_void_v<R> || std::is_default_constructible_v<R>;
    TesseraCallFrame frame;
    void* function = ::tessera::detail::Rt()->callable_id_enter(id_, kSkippable ? 1 : 0, &frame);
    if (function == nullptr) {
      if constexpr (kSkippable) {
        return R();
      } else {
        __builtin_trap();  // the engine fails the launch instead of returning null here
      }
    }
    struct Leave {
      TesseraCallFrame* frame;
      ~Leave() { ::tessera::detail::Rt()->callable_leave(frame); }  // also when rtThrow unwinds
    } leave{&frame};
    return reinterpret_cast<R (*)(A...)>(function)(args...);
  }

 private:
  int id_ = RT_PROGRAM_ID_NULL;
};

#endif  // TESSERA_OPTIXPP_HOST_ID_TYPES_

// rtCallableProgramX: the bound callable program of OptiX 3.6, the same as an rtCallableProgram
// variable (set with rtVariableSetObject; the callee sees its own scope, then its caller's).
template <typename Signature>
using boundCallableProgramId = ::tessera::detail::CallableProgram<Signature>;

}  // namespace optix

namespace tessera::detail {

// The semantic rtDeclareVariable registers for a variable of type T: a bound callable program
// (rtCallableProgramX, also through a typedef) is an rtCallableProgram variable whatever the
// declaration writes as its semantic.
template <typename T>
inline constexpr bool kBoundCallable = false;
template <typename Signature>
inline constexpr bool kBoundCallable<CallableProgram<Signature>> = true;
template <typename T>
constexpr const char* SemanticOf(const char* written) {
  return kBoundCallable<T> ? "rtCallableProgram" : written;
}

}  // namespace tessera::detail

#define rtBufferId ::optix::bufferId
#define rtCallableProgramId ::optix::callableProgramId
#define rtCallableProgramX ::optix::boundCallableProgramId

// OptiX 3.6: with RT_USE_TEMPLATED_RTCALLABLEPROGRAM defined before optix.h, rtCallableProgram is
// the template (`rtDeclareVariable(rtCallableProgram<float(float)>, f, , )`), not the macro.
#ifdef RT_USE_TEMPLATED_RTCALLABLEPROGRAM
#undef rtCallableProgram
#define rtCallableProgram rtCallableProgramX
#endif

#endif  // TESSERA_DETAIL_BINDLESS_H_
