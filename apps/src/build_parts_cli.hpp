#pragma once
// Command-line options that need an optional part of strata: in a build that leaves the part
// out they are refused when the command line is parsed, before anything is read or run (exit
// status 2), with the option that turns the part on.
#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <strata/config.hpp>

#include <string>
#include <string_view>

namespace strata::app {

/// Whether this build has the optional part switched by `option` (e.g. "STRATA_WITH_HDF5").
inline bool have_part(std::string_view option) {
  for (const auto& f : config::kFeatures)
    if (option == f.option) return f.enabled;
  throw std::logic_error(fmt::format("have_part: no optional part is switched by {}", option));
}

/// A CLI11 check: passes when this build has the part switched by `option`, or when the value
/// given is `harmless` (e.g. "0" for a number of frames); otherwise says that `what` needs the
/// part and how to turn it on.
inline CLI::Validator needs_part(std::string option, std::string what, std::string harmless = {}) {
  return CLI::Validator(
      [=](std::string& value) -> std::string {
        if (have_part(option) || (!harmless.empty() && value == harmless)) return {};
        return fmt::format("{} needs a part this build of strata leaves out: reconfigure with -D{}=ON", what,
                           option);
      },
      "");
}

}  // namespace strata::app
