#include "render_cmd.hpp"

#include <strata/config.hpp>
#include <strata/core/error.hpp>
#include <strata/io/render.hpp>

#include <cstdio>

#include "frames.hpp"

namespace strata::app {

int render_series_cmd(const RenderOptions& opt) {
#if STRATA_WITH_RENDER
  io::RenderStyle style = field_style(opt.field);
  style.width = opt.size.at(0);
  style.height = opt.size.at(1);
  const auto dir = opt.output.empty() ? opt.series.parent_path() / "png" : opt.output;
  // The bonds series written beside the particles, if there is one.
  auto bonds = opt.series.parent_path() / "bonds.pvd";
  if (!std::filesystem::exists(bonds)) bonds.clear();
  const auto pngs = io::render_series(opt.series, dir, style, bonds);
  std::printf("wrote %zu pictures in %s\n", pngs.size(), dir.string().c_str());
  if (!opt.no_movie && io::make_movie(dir, dir / "movie.mp4"))
    std::printf("wrote %s\n", (dir / "movie.mp4").string().c_str());
  return 0;
#else
  (void)opt;
  fail_missing_feature("STRATA_WITH_RENDER", "strata render");
#endif
}

}  // namespace strata::app
