#pragma once
// Internal to strata::cases: small helpers its sources share (the first line of an error
// message). One definition here: the library is compiled as one batch of sources per compiler
// run in the sanitizer and minimal builds, where two file-local copies would clash.
#include <string>

namespace strata::cases::detail {

/// The first line of `s` (an error message's headline), without its newline.
inline std::string first_line(const std::string& s) { return s.substr(0, s.find('\n')); }

}  // namespace strata::cases::detail
