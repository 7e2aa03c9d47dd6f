#pragma once
// Scene texts shared by the scene tests (tests/scene) and the end-to-end tests of the
// `strata` command (tests/cli).
#include <string>

namespace fixtures {

/// The platens' groups of a 2D block: "top" and "bottom" (its top and bottom rows), the bottom
/// fixed. Eleven lines, from [[group]] to a closing newline.
inline const std::string kPlatenGroups = R"toml([[group]]
name = "top"
select = "top_row"

[[group]]
name = "bottom"
select = "bottom_row"

[[boundary]]
group = "bottom"
type = "fixed"
)toml";

/// A coupled-chain scene ([coupled], Li et al. 2023): `case_name` (chain6 or metamaterial) at
/// dt_dem = `dt_dem` s for the η values `eta` ("1, 20"), serial, output in "res" without
/// pictures; `more` (whole lines) follows the modes line. The tests point at line numbers:
/// 1 [coupled], 2 case, 3 dt_dem, 4 eta, 5 modes, then `more`, a blank line and [output].
inline std::string chain_scene(const std::string& case_name, const std::string& dt_dem,
                               const std::string& eta, const std::string& more = "") {
  return "[coupled]\ncase = \"" + case_name + "\"\ndt_dem = " + dt_dem + "\neta = [" + eta +
         "]\nmodes = \"serial\"\n" + more + R"toml(
[output]
directory = "res"
render = false
)toml";
}

}  // namespace fixtures
