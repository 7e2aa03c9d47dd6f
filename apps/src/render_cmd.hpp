#pragma once
/// `strata render`: PNG frames (and an MP4 where ffmpeg is installed) of a written series.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace strata::app {

struct RenderOptions {
  std::filesystem::path series;  ///< particles .pvd, or a FEM .pvd (.vtu frames)
  std::filesystem::path output;  ///< PNG directory; empty: <series dir>/png
  /// Array used for colour; empty: damage for particles, displacement for a FEM series.
  std::string field;
  std::vector<int> size{1600, 1200};
  bool no_movie = false;
  std::filesystem::path mesh;  ///< FEM series drawn under the particles (coupled models)
  bool contacts = false;       ///< draw contacts (state 4 lines of bonds.pvd)
  bool no_cracks = false;      ///< leave the broken bonds out
  std::string view, up, clip;  ///< "X,Y,Z" / "OX,OY,OZ,NX,NY,NZ" as given (checked by number_list_error)
};

/// Why `text` is not a list of `count` comma-separated finite numbers whose numbers from
/// index `nonzero_from` on are not all zero (a direction); empty when it is.
std::string number_list_error(const std::string& text, std::size_t count, std::size_t nonzero_from,
                              const std::string& what);

/// The numbers of a list that number_list_error accepted.
std::vector<double> parse_number_list(const std::string& text);

int render_series_cmd(const RenderOptions& opt);

}  // namespace strata::app
