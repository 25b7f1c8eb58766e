#include "app/cli_checks.h"

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>

namespace aerograsp::cli {
namespace {

/// The number in `text`, or an error message when it is not a finite number.
std::string ParseFinite(const std::string& text, double* value) {
  char* end = nullptr;
  *value = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size()) return "'" + text + "' is not a number";
  if (!std::isfinite(*value)) return text + " is not a finite number";
  return "";
}

std::string Format(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

CLI::Validator Range(double min, double max) {
  const std::string description = "[" + Format(min) + ", " + Format(max) + "]";
  return CLI::Validator(
      [min, max, description](std::string& text) -> std::string {
        double v = 0.0;
        std::string error = ParseFinite(text, &v);
        if (error.empty() && (v < min || v > max)) error = text + " is not in " + description;
        return error;
      },
      "NUMBER in " + description);
}

CLI::Validator Finite() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double v = 0.0;
        return ParseFinite(text, &v);
      },
      "FINITE");
}

CLI::Validator Seed() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const std::string error =
            "'" + text + "' is not a seed (a whole number from 0 to 18446744073709551615)";
        if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos) return error;
        errno = 0;
        (void)std::strtoull(text.c_str(), nullptr, 10);
        return errno == ERANGE ? error : "";
      },
      "SEED");
}

}  // namespace aerograsp::cli
