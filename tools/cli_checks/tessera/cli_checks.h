// Number checks for the options of Tessera's commands and benchmarks. CLI11's PositiveNumber and
// NonNegativeNumber say what they want as a range ending in DBL_MAX written out in full (309
// digits: "Value 0 not in range 0.000000 to 17976931348623157..."); these say it in words:
// "--fps: must be greater than 0 (got 0)".
#ifndef TESSERA_TOOLS_CLI_CHECKS_TESSERA_CLI_CHECKS_H_
#define TESSERA_TOOLS_CLI_CHECKS_TESSERA_CLI_CHECKS_H_

#include <CLI/CLI.hpp>
#include <cmath>
#include <string>

namespace tessera::cli {

namespace detail {
// The number `text` holds, or an error message.
inline std::string ParseNumber(const std::string& text, double* value) {
  if (!CLI::detail::lexical_cast(text, *value) || std::isnan(*value)) {
    return "must be a number (got '" + text + "')";
  }
  return {};
}
}  // namespace detail

// A number greater than 0.
inline const CLI::Validator kPositive(
    [](std::string& text) -> std::string {
      double v = 0;
      std::string error = detail::ParseNumber(text, &v);
      if (error.empty() && !(v > 0)) error = "must be greater than 0 (got " + text + ")";
      return error;
    },
    "POSITIVE", "POSITIVE");

// A number of at least 0.
inline const CLI::Validator kNonNegative(
    [](std::string& text) -> std::string {
      double v = 0;
      std::string error = detail::ParseNumber(text, &v);
      if (error.empty() && !(v >= 0)) error = "must be 0 or more (got " + text + ")";
      return error;
    },
    "NONNEGATIVE", "NONNEGATIVE");

}  // namespace tessera::cli

#endif  // TESSERA_TOOLS_CLI_CHECKS_TESSERA_CLI_CHECKS_H_
