#include "render_cmd.hpp"

#include <strata/config.hpp>
#include <strata/core/error.hpp>
#include <strata/io/render.hpp>
#include <strata/io/series.hpp>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include <strata/scene/frames.hpp>

namespace strata::app {

namespace {
/// Splits "1,2,3" at commas into numbers; nullopt when a part is not one finite number.
std::optional<std::vector<double>> split_numbers(const std::string& text) {
  std::vector<double> out;
  std::stringstream ss(text);
  for (std::string part; std::getline(ss, part, ',');) {
    const char* begin = part.c_str();
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(begin, &end);
    while (end && (*end == ' ' || *end == '\t')) ++end;
    if (end == begin || !end || *end != '\0' || errno == ERANGE || !std::isfinite(v)) return std::nullopt;
    out.push_back(v);
  }
  if (!text.empty() && text.back() == ',') return std::nullopt;  // getline drops a trailing empty part
  return out;
}
}  // namespace

std::string number_list_error(const std::string& text, std::size_t count, std::size_t nonzero_from,
                              const std::string& what) {
  const auto v = split_numbers(text);
  if (!v || v->size() != count)
    return fmt::format("'{}' is not {}: {} comma-separated numbers", text, what, count);
  bool all_zero = true;
  for (std::size_t i = nonzero_from; i < count; ++i) all_zero = all_zero && (*v)[i] == 0;
  if (nonzero_from < count && all_zero)
    return fmt::format("'{}': the {} must not be zero", text, nonzero_from == 0 ? "vector" : "normal");
  return {};
}

std::vector<double> parse_number_list(const std::string& text) {
  return split_numbers(text).value_or(std::vector<double>{});
}

int render_series_cmd(const RenderOptions& opt) {
#if STRATA_WITH_RENDER
  const bool mesh_series = io::is_mesh_series(opt.series);
  const std::string field = !opt.field.empty() ? opt.field : mesh_series ? "displacement" : "damage";
  io::RenderStyle style = scene::field_style(field);
  style.width = opt.size.at(0);
  style.height = opt.size.at(1);
  style.show_contacts = opt.contacts;
  style.show_broken_bonds = !opt.no_cracks;
  // The options were checked by number_list_error when parsed.
  auto vec3 = [](const std::string& text, std::array<double, 3>& out) {
    if (text.empty()) return;
    const auto v = parse_number_list(text);
    STRATA_CHECK(v.size() == 3, Input, "'{}' is not 3 comma-separated numbers", text);
    std::copy_n(v.begin(), 3, out.begin());
  };
  vec3(opt.view, style.view_direction);
  vec3(opt.up, style.view_up);
  if (!opt.clip.empty()) {
    const auto v = parse_number_list(opt.clip);
    STRATA_CHECK(v.size() == 6, Input, "--clip '{}' is not 6 comma-separated numbers", opt.clip);
    std::array<double, 6> c{};
    std::copy_n(v.begin(), 6, c.begin());
    style.clip_plane = c;
  }
  const auto dir = opt.output.empty() ? opt.series.parent_path() / "png" : opt.output;
  // The bonds and walls series written beside the particles, if there are.
  io::SeriesPaths series{opt.series, {}, opt.mesh, {}};
  if (!mesh_series)
    for (auto [path, name] : {std::pair{&series.bonds, "bonds.pvd"}, std::pair{&series.walls, "walls.pvd"}})
      if (std::filesystem::exists(opt.series.parent_path() / name)) *path = opt.series.parent_path() / name;
  const auto pngs = io::render_series(series, dir, style);
  std::printf("wrote %zu pictures in %s\n", pngs.size(), dir.string().c_str());
  if (!opt.no_movie && !pngs.empty())
    if (const auto movie = io::make_movie(dir, dir / "movie"); !movie.empty())
      std::printf("wrote %s\n", movie.string().c_str());
  return 0;
#else
  (void)opt;
  fail_missing_feature("STRATA_WITH_RENDER", "strata render");
#endif
}

}  // namespace strata::app
