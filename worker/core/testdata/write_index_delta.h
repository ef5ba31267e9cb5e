// A hand-built StateDelta for transport and worker tests: the `write_index` program of
// basic_programs.cu (worker_core_test_programs.so) writes (x, y, 2, 1) into a w×h float4 OUTPUT
// buffer (program id 1, buffer id 2, bound as the context variable `output`). The module's bytes
// travel in the delta unless `ship_module` is false (a device that has them already).
#ifndef TESSERA_WORKER_CORE_TESTDATA_WRITE_INDEX_DELTA_H_
#define TESSERA_WORKER_CORE_TESTDATA_WRITE_INDEX_DELTA_H_

#include <cstdint>
#include <string>

#include "module_delta.h"
#include "tessera/rt.h"
#include "tessera/v1/launch.pb.h"
#include "tessera/v1/state.pb.h"

namespace tessera::testing {

inline v1::StateDelta WriteIndexDelta(const std::string& module, uint64_t session,
                                      uint64_t sequence, uint64_t w, uint64_t h,
                                      bool ship_module = true) {
  v1::StateDelta d;
  d.set_session_id(session);
  d.set_sequence(sequence);
  v1::ContextState* c = d.mutable_context();
  c->set_entry_point_count(1);
  c->set_ray_type_count(1);
  c->set_stack_size(1024);
  for (int i = 0; i < 3; ++i) c->add_print_launch_index(-1);
  c->add_ray_generation(1);
  v1::Program* p = d.add_objects()->mutable_program();
  p->set_id(1);
  p->set_version(1);
  p->set_module_path(module);
  const std::string bytes = ReadModuleFile(module);
  p->set_module_hash(ship_module ? AddModuleBytes(&d, bytes) : Sha256Hex(bytes));
  p->set_function("write_index");
  v1::Buffer* b = d.add_objects()->mutable_buffer();
  b->set_id(2);
  b->set_version(sequence);
  b->set_desc(RT_BUFFER_OUTPUT);
  b->set_format(RT_FORMAT_FLOAT4);
  b->set_element_size(16);
  b->add_dims(w);
  b->add_dims(h);
  v1::Variable* v = c->add_variables();
  v->set_name("output");
  v->set_type(RT_OBJECTTYPE_BUFFER);
  v->set_object_id(2);
  return d;
}

// Writes the bytes `region` carries for `buffer_id` into `out` (grown as needed): one range, or
// packed runs.
inline void ApplyRegion(const v1::BufferRegion& region, uint64_t buffer_id, std::string* out) {
  if (region.buffer_id() != buffer_id) return;
  auto put = [&](uint64_t offset, const char* data, uint64_t size) {
    if (out->size() < offset + size) out->resize(offset + size);
    out->replace(offset, size, data, size);
  };
  if (region.run_offsets_size() == 0) {
    put(region.offset(), region.data().data(), region.data().size());
    return;
  }
  uint64_t at = 0;
  for (int r = 0; r < region.run_offsets_size(); ++r) {
    put(region.run_offsets(r), region.data().data() + at, region.run_sizes(r));
    at += region.run_sizes(r);
  }
}

}  // namespace tessera::testing

#endif  // TESSERA_WORKER_CORE_TESTDATA_WRITE_INDEX_DELTA_H_
