// Programs of bindless_test.cc (OptiX 3.5+ ids): buffers reached through rtBufferId values held in
// a buffer of buffer ids, a struct, a variable set with rtVariableSetInt; writes through an id;
// callable programs called by id from a buffer of program ids, each with its own scope; bound
// rtCallableProgramX variables; invalid ids.
#include <optix.h>
#include <optixu/optixu_math_namespace.h>

using namespace optix;

// The layout OptiX promises: an id is just an int, so a buffer of RT_FORMAT_BUFFER_ID or
// RT_FORMAT_PROGRAM_ID elements, or a user struct, carries it.
static_assert(sizeof(rtBufferId<float, 1>) == sizeof(int), "rtBufferId is an int");
static_assert(sizeof(rtBufferId<float4, 3>) == sizeof(int), "rtBufferId is an int");
static_assert(sizeof(rtCallableProgramId<float(float)>) == sizeof(int), "a program id is an int");

rtDeclareVariable(uint2, launch_index, rtLaunchIndex, );
rtDeclareVariable(int, mode, , );
rtBuffer<float, 2> result;

// ---- A buffer of buffer ids ----------------------------------------------------------------
// Row y reads table y % count at x % its size, plus 100 times that size.
rtBuffer<rtBufferId<float, 1>, 1> tables;
RT_PROGRAM void read_tables() {
  const rtBufferId<float, 1> t = tables[launch_index.y % tables.size()];
  const size_t n = t.size();
  result[launch_index] = t[launch_index.x % n] + 100.f * static_cast<float>(n);
}

// ---- A struct with buffer id members, set with rtVariableSetUserData ----------------------
struct Mesh {
  rtBufferId<float3, 1> positions;
  rtBufferId<int, 1> indices;
  float scale;
};
rtDeclareVariable(Mesh, mesh, , );
RT_PROGRAM void read_mesh() {
  const unsigned i = launch_index.y * 4 + launch_index.x;
  const float3 p = mesh.positions[mesh.indices[i % mesh.indices.size()]];
  result[launch_index] = (p.x + 10.f * p.y + 100.f * p.z) * mesh.scale;
}

// ---- Ids in variables set with rtVariableSetInt: one to read, one to write --------------------
// A typedef, as in OptiX: the comma of rtBufferId<float, 2> would split the macro's arguments.
typedef rtBufferId<float, 2> FloatImage;
rtDeclareVariable(FloatImage, source, , );
rtDeclareVariable(FloatImage, target, , );
// `target` is an OUTPUT (or INPUT_OUTPUT) buffer no variable names: what reaches the host is
// what the write marks of an access by id say.
RT_PROGRAM void copy_by_id() {
  target[launch_index] = target[launch_index] + 2.f * source[launch_index];
  result[launch_index] = static_cast<float>(source.size().x * 1000 + source.size().y);
}

// ---- Bindless callable programs, chosen per hit from a buffer of program ids ---------------
struct Payload {
  float value;
};
rtDeclareVariable(rtObject, top_object, , );
rtDeclareVariable(optix::Ray, ray, rtCurrentRay, );
rtDeclareVariable(Payload, prd, rtPayload, );
rtDeclareVariable(int, which, attribute which, );
rtBuffer<rtCallableProgramId<float(float)>, 1> shaders;

// `factor` from the callee's own program scope, `offset` from the context: OptiX 6 looks a
// bindless callable program's variables up there, not in its caller's scopes.
rtDeclareVariable(float, factor, , ) = 1.f;
rtDeclareVariable(float, offset, , ) = 0.f;
RT_CALLABLE_PROGRAM float scale_by(float v) { return v * factor + offset; }
RT_CALLABLE_PROGRAM float square(float v) { return v * v + offset; }
// A bindless callable calling another by id, from its own scope.
rtDeclareVariable(rtCallableProgramId<float(float)>, inner, , );
RT_CALLABLE_PROGRAM float twice_inner(float v) { return 2.f * inner(v); }

// One primitive hit at t = 1; the attribute says which shader the hit takes (x % shader count).
RT_PROGRAM void intersect(int) {
  if (rtPotentialIntersection(1.f)) {
    which = static_cast<int>(ray.origin.x) % static_cast<int>(shaders.size());
    rtReportIntersection(0);
  }
}
RT_PROGRAM void bounds(int, float result_box[6]) {
  result_box[0] = result_box[1] = result_box[2] = -1e6f;
  result_box[3] = result_box[4] = result_box[5] = 1e6f;
}
RT_PROGRAM void ch_shade() { prd.value = shaders[which](ray.origin.y + 1.f); }
RT_PROGRAM void trace_raygen() {
  Payload p = {-1.f};
  const float3 origin =
      make_float3(static_cast<float>(launch_index.x), static_cast<float>(launch_index.y), -1.f);
  rtTrace(top_object, make_Ray(origin, make_float3(0.f, 0.f, 1.f), 0, 0.f, RT_DEFAULT_MAX), p);
  result[launch_index] = p.value;
}

// ---- A bound rtCallableProgramX variable (set with rtVariableSetObject) ---------------------
rtDeclareVariable(rtCallableProgramX<float(float)>, bound_fn, , );
RT_PROGRAM void ch_bound() { prd.value = bound_fn(ray.origin.y + 1.f); }

// ---- Invalid ids, as `mode` says ------------------------------------------------------------
typedef rtBufferId<float, 1> FloatArray;
rtDeclareVariable(FloatArray, some_buffer, , );
rtDeclareVariable(rtCallableProgramId<float(float)>, some_program, , );
struct NoDefault {
  explicit NoDefault(float v) : value(v) {}
  float value;
};
rtDeclareVariable(rtCallableProgramId<NoDefault(float)>, no_default, , );
RT_CALLABLE_PROGRAM NoDefault make_no_default(float v) { return NoDefault(v + 0.5f); }
RT_PROGRAM void invalid_ids() {
  float v = -1.f;
  switch (mode) {
    case 0:  // read through the buffer id
      v = some_buffer[launch_index.x] + 10.f * static_cast<float>(some_buffer.size());
      break;
    case 1:  // write through it, then read back
      some_buffer[launch_index.x] = 5.f;
      v = some_buffer[launch_index.x];
      break;
    case 2:  // call the program id
      v = some_program(3.f);
      break;
    case 3:  // a program id whose call returns a type without a default constructor
      v = no_default(3.f).value;
      break;
    case 4:  // an index past the end of a valid buffer id
      v = some_buffer[launch_index.x + 1000u];
      break;
    case 5:  // the id's bool and getId()
      v = (some_buffer ? 1.f : 0.f) + (some_program ? 2.f : 0.f) +
          10.f * static_cast<float>(some_program.getId() == some_buffer.getId());
      break;
  }
  result[launch_index] = v;
}
RT_PROGRAM void on_exception() { result[launch_index] = -static_cast<float>(rtGetExceptionCode()); }

// ---- Ids of the wrong element type or dimensionality ----------------------------------------
typedef rtBufferId<float4> Float4Array;
rtDeclareVariable(Float4Array, wide, , );
RT_PROGRAM void read_wide() { result[launch_index] = wide[0u].x; }
