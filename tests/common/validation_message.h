// The message a config's Validate(source, prefix) throws, for tests that check
// it names the file, the full key path and the bound.
#pragma once

#include <string>

#include "core/config.h"

namespace aerograsp::testing {

/// The ConfigError's text, or "no error" when `config` is valid.
template <typename Config>
std::string ValidationMessage(const Config& config, const std::string& source,
                              const std::string& prefix) {
  try {
    config.Validate(source, prefix);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace aerograsp::testing
