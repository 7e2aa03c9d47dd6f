#include "mesh_report.hpp"

#include <strata/config.hpp>
#include <strata/core/error.hpp>
#include <strata/core/log.hpp>
#include <strata/io/csv.hpp>
#include <strata/io/plot.hpp>
#include <strata/preprocess/ecc.hpp>

#include <algorithm>
#include <cmath>
#include <map>

namespace strata::app {

namespace fs = std::filesystem;

BondStats bond_stats(const dem::Simulation& sim, double d_ref) {
  BondStats s;
  s.d_ref = d_ref;
  if (sim.bond_count() > kMaxReportedBonds || sim.bond_count() == 0) return s;
  const auto pos = sim.positions();
  const auto bonds = sim.bonds();
  s.length.reserve(bonds.size());
  s.azimuth.reserve(bonds.size());
  for (const auto& b : bonds) {
    const auto &p = pos[b.i], &q = pos[b.j];
    const double dx = q[0] - p[0], dy = q[1] - p[1], dz = q[2] - p[2];
    const double len = std::sqrt(dx * dx + dy * dy + dz * dz);
    s.length.push_back(len);
    double az = std::atan2(dy, dx) * 180 / M_PI;
    if (az < 0) az += 180;
    if (az >= 180) az -= 180;
    s.azimuth.push_back(az);
    if (sim.dim() == 3) s.polar.push_back(std::acos(std::min(1.0, std::abs(dz) / len)) * 180 / M_PI);
  }
  return s;
}

nlohmann::json bond_length_classes(const BondStats& s, double width) {
  std::map<long, std::size_t> classes;
  for (double len : s.length) ++classes[std::lround(len / s.d_ref / width)];
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [k, n] : classes) j[fmt::format("{:.2f}", double(k) * width)] = n;
  return j;
}

namespace {
/// Histogram of v over [lo, hi] as (bin centre, count) columns.
void histogram_columns(const std::vector<double>& v, double lo, double hi, int bins, std::vector<double>& x,
                       std::vector<double>& y) {
  const auto h = preprocess::histogram(v, lo, hi, bins);
  x.resize(h.size());
  y.resize(h.size());
  for (std::size_t k = 0; k < h.size(); ++k)
    x[k] = lo + (double(k) + 0.5) * (hi - lo) / double(h.size()), y[k] = double(h[k]);
}

void plot(const std::string& title, const std::string& xl, std::vector<io::PlotSeries> series,
          const fs::path& png, std::vector<fs::path>& written) {
#if STRATA_WITH_RENDER
  try {
    io::PlotRequest p;
    p.title = title;
    p.x_label = xl;
    p.y_label = "bonds";
    p.series = std::move(series);
    p.png = png;
    io::plot_xy(p);
    written.push_back(png);
  } catch (const std::exception& e) {
    log::warn("plot {} skipped: {}", png.string(), e.what());
  }
#else
  (void)title, (void)xl, (void)series, (void)png, (void)written;
#endif
}
}  // namespace

std::vector<fs::path> write_bond_histograms(const BondStats& s, const fs::path& dir, int bins) {
  std::vector<fs::path> written;
  if (s.length.empty()) return written;
  fs::create_directories(dir);
  // Lengths relative to d: a regular lattice puts every bond in the bin of 1.
  std::vector<double> rel(s.length.size());
  for (std::size_t k = 0; k < rel.size(); ++k) rel[k] = s.length[k] / s.d_ref;
  const auto [mn, mx] = std::minmax_element(rel.begin(), rel.end());
  const double half = std::max({1.0 - *mn, *mx - 1.0, 0.01}) * 1.05;
  std::vector<double> lx, ly;
  histogram_columns(rel, 1 - half, 1 + half, bins, lx, ly);
  {
    io::CsvWriter csv(dir / "bond_lengths.csv", {"length_over_d", "bonds"});
    for (std::size_t k = 0; k < lx.size(); ++k) csv.row({lx[k], ly[k]});
  }
  written.push_back(dir / "bond_lengths.csv");
  std::vector<double> ax, ay, px, py;
  // 2-degree bins centred on even angles, so 0, 60 and 120 degrees fall mid-bin; azimuths
  // just below 180 are the same direction as just above 0.
  std::vector<double> az(s.azimuth);
  for (double& a : az)
    if (a >= 179) a -= 180;
  histogram_columns(az, -1, 179, 90, ax, ay);
  if (!s.polar.empty()) histogram_columns(s.polar, -1, 91, 46, px, py);
  {
    std::vector<std::string> cols{"angle_deg", "bonds_azimuth"};
    if (!s.polar.empty()) cols.push_back("bonds_polar");
    io::CsvWriter csv(dir / "bond_directions.csv", cols);
    for (std::size_t k = 0; k < ax.size(); ++k) {
      if (s.polar.empty()) {
        csv.row({ax[k], ay[k]});
      } else {
        // polar bins cover [-1, 91] with the same 2-degree centres: 0 beyond 90
        csv.row({ax[k], ay[k], k < py.size() ? py[k] : 0.0});
      }
    }
  }
  written.push_back(dir / "bond_directions.csv");
  plot("Bond lengths", "bond length / particle diameter [-]", {{"bonds", lx, ly, true, true}},
       dir / "bond_lengths.png", written);
  std::vector<io::PlotSeries> dirs{{"azimuth in the xy plane", ax, ay, true, true}};
  if (!s.polar.empty()) dirs.push_back({"angle to the z axis", px, py, true, true});
  plot("Bond directions", "angle [degrees]", std::move(dirs), dir / "bond_directions.png", written);
  return written;
}

}  // namespace strata::app
