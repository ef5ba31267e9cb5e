// optixPipelineCreate, optixPipelineSetStackSize, optixPipelineDestroy. A pipeline is its program
// groups and the compile and link options programs see, as devices receive it
// (v1::Optix7Pipeline).
#include <algorithm>
#include <memory>
#include <string>

#include "absl/strings/str_cat.h"
#include "call.h"
#include "optix_host.h"

namespace tessera::optix7 {
namespace {

// Whether a module's program the pipeline links can read the launch parameters.
bool AnyModuleExports(const Pipeline& p, const std::string& name) {
  for (const auto& g : p.groups) {
    for (const auto& m : g->modules) {
      auto it = m->symbols.find(name);
      if (it != m->symbols.end() && it->second == SymbolKind::kObject) return true;
    }
  }
  return false;
}

absl::StatusOr<std::shared_ptr<Pipeline>> CreatePipeline(
    Call& call, const std::shared_ptr<DeviceContext>& c, const OptixPipelineCompileOptions& compile,
    const OptixPipelineLinkOptions& link, const OptixProgramGroup* groups, unsigned count) {
  auto p = std::make_shared<Pipeline>();
  p->context = c;
  p->max_trace_depth = link.maxTraceDepth;
  const PipelineOptions options = CopyPipelineOptions(compile);
  int payload_values = compile.numPayloadValues;
  for (unsigned i = 0; i < count; ++i) {
    std::shared_ptr<ProgramGroup> g;
    const std::string where = absl::StrCat("programGroups[", i, "]");
    if (absl::Status s = call.Lookup(groups[i], where, &g); !s.ok()) return s;
    if (g->context != c) {
      return OptixError(OPTIX_ERROR_INVALID_VALUE,
                        absl::StrCat(where, " belongs to another device context"));
    }
    // OptiX requires the pipeline's compile options to be those its modules were compiled with.
    // A difference is an error in validation mode and a warning otherwise, where it only
    // matters if programs rely on the option (payload or attribute counts, exception flags).
    for (const auto& m : g->modules) {
      const std::string diff = PipelineOptionsDifference(options, m->options);
      if (!diff.empty()) {
        const std::string message =
            absl::StrCat("pipelineCompileOptions differ from those module ", m->name, " of ", where,
                         " was compiled with: ", diff);
        if (c->validation()) return OptixError(OPTIX_ERROR_INVALID_VALUE, message);
        call.Log(kLogWarning, message);
      }
      payload_values = std::max(payload_values, m->payload_values);
    }
    p->groups.push_back(g);
    p->launch.groups.push_back(&g->launch);
    p->launch.wire.add_program_groups(g->launch.wire.id());
  }
  v1::Optix7Pipeline& wire = p->launch.wire;
  wire.set_id(NextObjectId());
  wire.set_version(1);
  if (options.params_name) {
    wire.set_params_name(*options.params_name);
    if (!AnyModuleExports(*p, *options.params_name)) {
      call.Log(kLogWarning,
               absl::StrCat("no module of the pipeline exports '", *options.params_name,
                            "' (pipelineLaunchParamsVariableName): programs cannot "
                            "read optixLaunch's parameters"));
    }
  }
  wire.set_max_trace_depth(link.maxTraceDepth);
  wire.set_exception_flags(compile.exceptionFlags);
  wire.set_num_payload_values(static_cast<uint32_t>(payload_values));
  wire.set_num_attribute_values(static_cast<uint32_t>(compile.numAttributeValues));
  wire.set_traversable_graph_flags(compile.traversableGraphFlags);
  wire.set_primitive_type_flags(EffectivePrimitiveTypeFlags(compile.usesPrimitiveTypeFlags));
  wire.set_uses_motion_blur(compile.usesMotionBlur != 0);
  return p;
}

}  // namespace
}  // namespace tessera::optix7

using tessera::optix7::Call;
using tessera::optix7::DeviceContext;
using tessera::optix7::OptixError;
using tessera::optix7::Pipeline;

extern "C" {

OptixResult optixPipelineCreate(OptixDeviceContext context,
                                const OptixPipelineCompileOptions* pipelineCompileOptions,
                                const OptixPipelineLinkOptions* pipelineLinkOptions,
                                const OptixProgramGroup* programGroups,
                                unsigned int numProgramGroups, char* logString,
                                size_t* logStringSize, OptixPipeline* pipeline) {
  return Call("optixPipelineCreate", logString, logStringSize).Run([&](Call& call) -> absl::Status {
    std::shared_ptr<DeviceContext> c;
    if (absl::Status s = call.Lookup(context, "context", &c); !s.ok()) return s;
    if (absl::Status s = call.NotNull(pipelineCompileOptions, "pipelineCompileOptions"); !s.ok()) {
      return s;
    }
    if (absl::Status s = tessera::optix7::CheckPipelineCompileOptions(*pipelineCompileOptions);
        !s.ok()) {
      return s;
    }
    if (absl::Status s = call.NotNull(pipelineLinkOptions, "pipelineLinkOptions"); !s.ok()) {
      return s;
    }
    if (pipelineLinkOptions->maxTraceDepth > tessera::optix7::kMaxTraceDepth) {
      return OptixError(
          OPTIX_ERROR_INVALID_VALUE,
          absl::StrCat("pipelineLinkOptions->maxTraceDepth is ", pipelineLinkOptions->maxTraceDepth,
                       "; OptiX allows at most ", tessera::optix7::kMaxTraceDepth));
    }
    if (absl::Status s = call.NotNull(programGroups, "programGroups"); !s.ok()) return s;
    if (absl::Status s = call.NotNull(pipeline, "pipeline"); !s.ok()) return s;
    if (numProgramGroups == 0) {
      return OptixError(OPTIX_ERROR_INVALID_VALUE, "numProgramGroups is 0");
    }
    absl::StatusOr<std::shared_ptr<Pipeline>> p = tessera::optix7::CreatePipeline(
        call, c, *pipelineCompileOptions, *pipelineLinkOptions, programGroups, numProgramGroups);
    if (!p.ok()) return p.status();
    tessera::optix7::Register(*p, c.get());
    *pipeline = reinterpret_cast<OptixPipeline>(p->get());
    return absl::OkStatus();
  });
}

OptixResult optixPipelineDestroy(OptixPipeline pipeline) {
  return Call("optixPipelineDestroy").Run([&](Call& call) -> absl::Status {
    std::shared_ptr<Pipeline> p;
    if (absl::Status s = call.Lookup(pipeline, "pipeline", &p); !s.ok()) return s;
    tessera::optix7::UnregisterObject(Pipeline::kKind, pipeline);
    return absl::OkStatus();
  });
}

// Checked and otherwise ignored: programs run on worker threads' own stacks (see the stack sizes
// of program_groups.cc).
OptixResult optixPipelineSetStackSize(OptixPipeline pipeline,
                                      unsigned int directCallableStackSizeFromTraversal,
                                      unsigned int directCallableStackSizeFromState,
                                      unsigned int continuationStackSize,
                                      unsigned int maxTraversableGraphDepth) {
  (void)directCallableStackSizeFromTraversal;
  (void)directCallableStackSizeFromState;
  (void)continuationStackSize;
  return Call("optixPipelineSetStackSize").Run([&](Call& call) -> absl::Status {
    std::shared_ptr<Pipeline> p;
    if (absl::Status s = call.Lookup(pipeline, "pipeline", &p); !s.ok()) return s;
    if (maxTraversableGraphDepth == 0 || maxTraversableGraphDepth > 31) {
      return OptixError(OPTIX_ERROR_INVALID_VALUE,
                        absl::StrCat("maxTraversableGraphDepth is ", maxTraversableGraphDepth,
                                     "; OptiX allows 1 to 31"));
    }
    const unsigned flags = p->launch.wire.traversable_graph_flags();
    const unsigned allowed = (flags & OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_SINGLE_LEVEL_INSTANCING)
                                 ? 2
                             : (flags & OPTIX_TRAVERSABLE_GRAPH_FLAG_ALLOW_SINGLE_GAS) ? 1
                                                                                       : 31;
    if (maxTraversableGraphDepth > allowed) {
      return OptixError(OPTIX_ERROR_INVALID_VALUE,
                        absl::StrCat("maxTraversableGraphDepth is ", maxTraversableGraphDepth,
                                     " but the pipeline's traversableGraphFlags (0x",
                                     absl::Hex(flags), ") allow a depth of at most ", allowed));
    }
    return absl::OkStatus();
  });
}

}  // extern "C"
