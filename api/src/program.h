// A program: one function in a program module (a shared library built from C++, the PTX
// analogue), plus the variables declared on the program object.
#ifndef TESSERA_API_SRC_PROGRAM_H_
#define TESSERA_API_SRC_PROGRAM_H_

#include <memory>
#include <string>

#include "object.h"
#include "variable_scope.h"

namespace tessera::api {

class Program : public Object {
 public:
  static constexpr Kind kKind = Kind::kProgram;

  Program(Context* context, uint64_t id, std::string module_path, std::string module_hash,
          std::shared_ptr<const std::string> module_bytes, std::string function)
      : Object(Kind::kProgram, context, id),
        module_path_(std::move(module_path)),
        module_hash_(std::move(module_hash)),
        module_bytes_(std::move(module_bytes)),
        function_(std::move(function)),
        variables_(this) {
    Touch();
  }

  const std::string& module_path() const { return module_path_; }
  const std::string& module_hash() const { return module_hash_; }
  // The module file as read at creation (program_loader.h ModuleRef::bytes); never null.
  const std::string& module_bytes() const { return *module_bytes_; }
  const std::string& function() const { return function_; }
  // rtProgramGetId: programs can now call it by id (rtCallableProgramId), so it reaches the
  // devices whether or not a variable names it (Context::VisitEdges) and they bind it by id.
  void NoteIdTaken() { id_taken_ = true; }
  bool id_taken() const { return id_taken_; }

  VariableScope* scope() override { return &variables_; }
  const VariableScope& variables() const { return variables_; }
  void VisitEdges(EdgeVisitor visit) const override { variables_.VisitEdges(visit); }

 private:
  void DropLinks() override { variables_.Clear(); }

  const std::string module_path_;
  const std::string module_hash_;
  const std::shared_ptr<const std::string> module_bytes_;
  const std::string function_;
  VariableScope variables_;
  bool id_taken_ = false;
};

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_PROGRAM_H_
