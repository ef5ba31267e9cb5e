// The variables declared on one scope object (context, program, geometry, geometry instance,
// material, selector), in declaration order. Variables are objects of their own so that their
// handles can be checked; the scope holds the only reference.
#ifndef TESSERA_API_SRC_VARIABLE_SCOPE_H_
#define TESSERA_API_SRC_VARIABLE_SCOPE_H_

#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "absl/strings/string_view.h"
#include "variable.h"

namespace tessera::api {

// A C identifier, or identifiers joined by "::" (OptiX 2+ variables may live in namespaces).
bool IsValidVariableName(absl::string_view name);

class VariableScope {
 public:
  explicit VariableScope(Object* owner) : owner_(owner) {}
  ~VariableScope() { Clear(); }
  VariableScope(const VariableScope&) = delete;
  VariableScope& operator=(const VariableScope&) = delete;

  absl::StatusOr<Variable*> Declare(absl::string_view name);
  // Null when no variable has that name.
  Variable* Query(absl::string_view name) const;
  absl::Status Remove(Variable* variable);
  absl::StatusOr<Variable*> At(unsigned index) const;
  size_t count() const { return variables_.size(); }
  const std::vector<Variable*>& variables() const { return variables_; }
  // Destroys every variable (the owner is being destroyed).
  void Clear();
  void VisitEdges(Object::EdgeVisitor visit) const;

 private:
  Object* const owner_;
  std::vector<Variable*> variables_;
};

}  // namespace tessera::api

#endif  // TESSERA_API_SRC_VARIABLE_SCOPE_H_
