#include "variable_scope.h"

#include <algorithm>

#include "absl/strings/str_cat.h"
#include "handle_registry.h"
#include "status.h"

namespace tessera::api {
namespace {

bool IsIdentifier(absl::string_view s) {
  if (s.empty()) return false;
  auto alpha = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; };
  if (!alpha(s[0])) return false;
  return std::all_of(s.begin() + 1, s.end(),
                     [&](char c) { return alpha(c) || (c >= '0' && c <= '9'); });
}

}  // namespace

bool IsValidVariableName(absl::string_view name) {
  while (true) {
    size_t sep = name.find("::");
    if (!IsIdentifier(name.substr(0, sep))) return false;
    if (sep == absl::string_view::npos) return true;
    name.remove_prefix(sep + 2);
  }
}

absl::StatusOr<Variable*> VariableScope::Declare(absl::string_view name) {
  if (!IsValidVariableName(name)) {
    return RtError(RT_ERROR_ILLEGAL_SYMBOL,
                   absl::StrCat("'", name, "' is not a valid variable name (a C identifier)"));
  }
  if (Query(name) != nullptr) {
    return RtError(RT_ERROR_VARIABLE_REDECLARED,
                   absl::StrCat("variable '", name, "' is already declared"));
  }
  auto* variable = new Variable(owner_->context(), owner_, std::string(name));
  HandleRegistry::Get().Add(variable);
  variables_.push_back(variable);
  owner_->Touch();
  return variable;
}

Variable* VariableScope::Query(absl::string_view name) const {
  for (Variable* v : variables_) {
    if (v->name() == name) return v;
  }
  return nullptr;
}

absl::Status VariableScope::Remove(Variable* variable) {
  auto it = std::find(variables_.begin(), variables_.end(), variable);
  if (it == variables_.end()) {
    return RtError(RT_ERROR_VARIABLE_NOT_FOUND,
                   absl::StrCat("variable '", variable->name(), "' is not declared here"));
  }
  variables_.erase(it);
  variable->Destroy();
  variable->Release();
  owner_->Touch();
  return absl::OkStatus();
}

absl::StatusOr<Variable*> VariableScope::At(unsigned index) const {
  if (index >= variables_.size()) {
    return RtError(
        RT_ERROR_INVALID_VALUE,
        absl::StrCat("variable index ", index, " is out of range (count ", variables_.size(), ")"));
  }
  return variables_[index];
}

void VariableScope::Clear() {
  std::vector<Variable*> variables;
  variables.swap(variables_);
  for (Variable* v : variables) {
    v->Destroy();
    v->Release();
  }
}

void VariableScope::VisitEdges(Object::EdgeVisitor visit) const {
  for (const Variable* v : variables_) v->VisitEdges(visit);
}

}  // namespace tessera::api
