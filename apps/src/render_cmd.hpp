#pragma once
/// `strata render`: PNG frames (and an MP4 where ffmpeg is installed) of a written series.
#include <filesystem>
#include <string>
#include <vector>

namespace strata::app {

struct RenderOptions {
  std::filesystem::path series;  ///< particles .pvd
  std::filesystem::path output;  ///< PNG directory; empty: <series dir>/png
  std::string field = "damage";  ///< point array used for colour
  std::vector<int> size{1600, 1200};
  bool no_movie = false;
};

int render_series_cmd(const RenderOptions& opt);

}  // namespace strata::app
