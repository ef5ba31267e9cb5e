// absl::Status inside, RTresult at the C boundary: one table maps between them.
// Errors that must surface as a specific RTresult carry it as a payload.
#ifndef TESSERA_API_SRC_STATUS_H_
#define TESSERA_API_SRC_STATUS_H_

#include "absl/status/status.h"
#include "absl/strings/string_view.h"
#include "tessera/rt.h"

namespace tessera::api {

// A failed status whose RTresult is exactly `code` (the canonical code comes from the table).
absl::Status RtError(RTresult code, absl::string_view message);

// The RTresult for `status`: its payload when it carries one, else the table entry for its code.
RTresult ToRtResult(const absl::Status& status);

// The canonical absl code the table pairs with `code`.
absl::StatusCode StatusCodeFor(RTresult code);

// A generic description of `code` ("RT_ERROR_INVALID_VALUE: invalid value"); never null.
const char* ResultText(RTresult code);

}  // namespace tessera::api

#define TS_STATUS_CONCAT_INNER(a, b) a##b
#define TS_STATUS_CONCAT(a, b) TS_STATUS_CONCAT_INNER(a, b)

#define TS_RETURN_IF_ERROR(expr)             \
  do {                                       \
    ::absl::Status ts_status_ = (expr);      \
    if (!ts_status_.ok()) return ts_status_; \
  } while (false)

#define TS_ASSIGN_OR_RETURN(lhs, expr) \
  TS_ASSIGN_OR_RETURN_IMPL(TS_STATUS_CONCAT(ts_statusor_, __LINE__), lhs, expr)
#define TS_ASSIGN_OR_RETURN_IMPL(tmp, lhs, expr) \
  auto tmp = (expr);                             \
  if (!tmp.ok()) return tmp.status();            \
  lhs = std::move(tmp).value()

#endif  // TESSERA_API_SRC_STATUS_H_
