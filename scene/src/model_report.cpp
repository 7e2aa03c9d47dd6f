#include <strata/scene/model_report.hpp>

#include <strata/config.hpp>
#include <strata/core/clock.hpp>
#include <strata/core/error.hpp>
#include <strata/core/log.hpp>
#include <strata/core/memory.hpp>
#include <strata/core/parallel.hpp>
#include <strata/dem/lattice_elastic.hpp>
#include <strata/io/csv.hpp>
#include <strata/io/plot.hpp>
#include <strata/io/series.hpp>
#include <strata/preprocess/ecc.hpp>

#include <algorithm>
#include <cmath>
#include <map>

namespace strata::scene {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {
/// The analytical elastic constants of a region's regular lattice with its material's Kn
/// and Ks (2D: hexagonal, isotropic, E per unit thickness in N/m; 3D: along the stacking
/// axis z, for FCC also along a cube axis, and the isotropic average, in Pa).
json lattice_elastic_json(const MaterialTable& mat, int dim, const RegionInfo& r) {
  auto entry = [](const dem::LatticeElastic& e) {
    return json{{"youngs_modulus", e.E}, {"poisson_ratio", e.nu}};
  };
  json j = {{"regular_lattice", !r.eccentric}};
  if (dim == 2) {
    j["unit"] = "N/m (E times the thickness)";
    j["isotropic"] = entry(dem::hex_elastic(mat.kn, mat.ks));
    return j;
  }
  j["unit"] = "Pa";
  j["along_z"] = entry(dem::close_packed_stacking_axis_elastic(mat.kn, mat.ks, r.diameter));
  if (r.lattice == "fcc")
    j["along_cube_axis"] = entry(dem::fcc_cube_axis_elastic(mat.kn, mat.ks, r.diameter));
  j["isotropic_average"] = entry(dem::close_packed_isotropic_elastic(mat.kn, mat.ks, r.diameter));
  return j;
}

/// What every model report holds: scene, regions, groups (`strata check`, `run`, `mesh`).
json model_counts_json(const Scene& sc, int dim, const std::vector<RegionInfo>& regions_in,
                       const std::map<std::string, std::size_t>& groups_in) {
  json regions = json::array();
  for (const auto& r : regions_in) {
    json region = {{"name", r.name},
                   {"lattice", r.lattice},
                   {"particles", r.particles},
                   {"diameter_m", r.diameter},
                   {"packing_density", r.packing}};
    for (const auto& mat : sc.materials)
      if (mat.name.value == r.material) region["lattice_elastic"] = lattice_elastic_json(mat, dim, r);
    if (r.eccentric)
      region["eccentric"] = {
          {"bonds", r.bonds}, {"weakened_bonds", r.weakened_bonds}, {"l_max_m", r.longest_bond}};
    regions.push_back(std::move(region));
  }
  json groups = json::object();
  for (const auto& [name, n] : groups_in) groups[name] = n;
  return {{"scene", sc.file.string()},
          {"title", sc.network ? sc.network->title.value : sc.scene.title.value},
          {"dimension", dim},
          {"regions", regions},
          {"groups", groups}};
}

/// `strata mesh`'s report of a model description: counts only, no DEM quantities (dt_crit,
/// dt, memory of the model arrays are `strata check`'s, which builds the DEM model).
json description_json(const ModelDescription& d, const Scene& sc, std::size_t bonds) {
  std::map<std::string, std::size_t> groups;
  for (const auto& g : d.groups) groups[g.name] = g.count;
  json j = model_counts_json(sc, d.dim, d.regions, groups);
  json fem = json::array();
  for (const auto& f : d.fem)
    fem.push_back({{"name", f.name}, {"nodes", f.mesh.node_count()}, {"elements", f.mesh.cell_count()}});
  j.update({{"particles", d.particle_count()},
            {"bonds", bonds},
            {"fem_nodes", d.fem_nodes()},
            {"fem_elements", d.fem_elements()},
            {"fem_regions", fem},
            {"threads", par::threads()}});
  return j;
}
}  // namespace

json model_json(const BuiltModel& m, const Scene& sc) {
  json j = model_counts_json(sc, m.dim, m.regions, m.groups);
  const bool p = m.has_particles();
  j.update({{"particles", p ? m.sim().particle_count() : 0},
            {"bonds", p ? m.sim().bond_count() : 0},
            {"fem_nodes", m.has_fem() ? m.fem().mesh().nodes() : 0},
            {"fem_elements", 0},
            {"memory_bytes", p ? m.sim().memory_bytes() : 0},
            {"setup_seconds", m.build_seconds},
            {"dt_s", m.dt},
            {"dt_automatic", m.dt_automatic},
            {"dt_crit_s", m.dt_crit},
            {"dt_over_dt_crit", m.dt / m.dt_crit},
            {"steps", m.steps},
            {"simulated_time_s", double(m.steps) * m.dt},
            {"threads", par::threads()}});
  if (m.settle_steps > 0) {
    j["settle_steps"] = m.settle_steps;
    j["settle_time_s"] = double(m.settle_steps) * m.dt;
  }
  if (m.has_fem()) {
    std::size_t elements = 0;
    json fem = json::array();
    for (const auto& r : m.fem_regions) {
      elements += r.elements;
      fem.push_back({{"name", r.name},
                     {"elements", r.elements},
                     {"youngs_modulus_pa", r.youngs_modulus},
                     {"poisson_ratio", r.poisson_ratio},
                     {"density_kg_m3", r.density}});
    }
    json groups = json::object();
    for (const auto& [name, nodes] : m.fem_groups) groups[name] = nodes.size();
    j["fem_elements"] = elements;
    j["fem_regions"] = fem;
    j["fem_groups"] = groups;
    j["fem_integrator"] = m.fem_integrator();
    j["fem_dt_s"] = m.dt * double(m.coupled() ? m.eta : 1);
    j["fem_dt_crit_s"] = std::isfinite(m.fem_dt_crit) ? json(m.fem_dt_crit) : json("unconditional");
    j["fem_explicit_dt_crit_s"] = m.fem_explicit_dt_crit;
  }
  if (m.has_network()) {
    const NetworkTable& t = *sc.network;
    j["network"] = {{"nodes", t.mass->size()},
                    {"springs", t.springs->size()},
                    {"walls", t.walls->size()},
                    {"fem_nodes", t.fem_nodes->size()},
                    {"particle_nodes", t.particle_nodes->size()},
                    {"loads", t.sine_loads->size()}};
  }
  if (m.coupled()) {
    j["eta"] = m.eta;
    j["coupling"] = m.execution();
    j["overlap_external_particles"] = m.overlap_particles;
    j["overlap_external_nodes"] = m.overlap_nodes;
  }
  return j;
}

BondStats bond_stats(const ModelDescription& d, std::size_t bonds) {
  BondStats s;
  s.d_ref = d.regions.empty() ? 0.0 : d.regions.front().diameter;
  if (bonds > kMaxReportedBonds || bonds == 0) return s;
  s.length.reserve(bonds);
  s.azimuth.reserve(bonds);
  const auto add = [&](const preprocess::Lattice& l, const preprocess::BondList& b) {
    std::vector<double> az, polar;
    preprocess::bond_directions(l, b, az, polar);
    s.length.insert(s.length.end(), b.length.begin(), b.length.end());
    s.azimuth.insert(s.azimuth.end(), az.begin(), az.end());
    s.polar.insert(s.polar.end(), polar.begin(), polar.end());
  };
  if (d.bonds_across_regions && d.sites.size() > 1) {
    // Bonds between regions too: list them over all sites, as one lattice.
    preprocess::Lattice all;
    all.dim = d.dim;
    for (const auto& r : d.sites) all.x.insert(all.x.end(), r.sites.x.begin(), r.sites.x.end());
    add(all, preprocess::touching_pairs(d.lattices()));
    return s;
  }
  for (const auto& r : d.sites) add(r.sites, r.eccentric ? r.bonds : preprocess::touching_pairs(r.sites));
  return s;
}

nlohmann::json bond_length_classes(const preprocess::PairCounts& c) {
  nlohmann::json j = nlohmann::json::object();
  for (std::size_t k = 0; k < c.by_class.size(); ++k)
    if (c.by_class[k] > 0) j[fmt::format("{:.2f}", double(k) * c.width)] = c.by_class[k];
  return j;
}

io::PointCloud description_particles(const ModelDescription& d, const std::vector<std::uint32_t>& ids) {
  io::PointCloud pc;
  pc.dim = d.dim;
  pc.time = 0.0;
  pc.step = 0;
  pc.xyz.reserve(ids.size() * 3);
  io::Array radius{std::string(io::kRadiusArray), 1, {}, io::ArrayType::Float64};
  io::Array id{"id", 1, {}, io::ArrayType::Int64};
  radius.values.reserve(ids.size());
  id.values.reserve(ids.size());
  std::size_t k = 0;  // region of the current id (ids ascending)
  for (std::uint32_t i : ids) {
    while (i >= d.sites[k].first_id + d.sites[k].sites.size()) ++k;
    const auto& x = d.sites[k].sites.x[i - d.sites[k].first_id];
    pc.xyz.insert(pc.xyz.end(), x.begin(), x.end());
    radius.values.push_back(d.regions[k].diameter / 2);
    id.values.push_back(double(i));
  }
  // The last-made group of each particle (as dem::Simulation::last_group numbers groups),
  // members found by binary search in the ascending ids.
  std::vector<double> last(ids.size(), -1.0);
  std::vector<std::string> names;
  for (const auto& g : d.groups) {
    auto it = std::find(names.begin(), names.end(), g.name);
    if (it == names.end()) it = names.insert(names.end(), g.name);
    const auto index = double(it - names.begin());
    auto mark = [&](auto at) {
      double& l = last[std::size_t(at - ids.begin())];
      l = std::max(l, index);
    };
    if (g.region >= 0) {
      const auto& s = d.sites[std::size_t(g.region)];
      const auto lo = std::lower_bound(ids.begin(), ids.end(), s.first_id);
      const auto hi = std::lower_bound(ids.begin(), ids.end(), s.first_id + std::uint32_t(g.count));
      for (auto at = lo; at != hi; ++at) mark(at);
    } else {
      for (std::uint32_t member : g.ids) {
        const auto at = std::lower_bound(ids.begin(), ids.end(), member);
        if (at != ids.end() && *at == member) mark(at);
      }
    }
  }
  io::Array group{"group", 1, std::move(last), io::ArrayType::Int64};
  pc.point_data = {std::move(radius), std::move(id), std::move(group)};
  return pc;
}

io::MeshFrame description_fem(const ModelDescription& d) {
  io::MeshFrame f;
  f.dim = d.dim;
  f.time = 0.0;
  f.step = 0;
  io::Array region{"region", 1, {}, io::ArrayType::Int32};
  for (std::size_t r = 0; r < d.fem.size(); ++r) {
    const preprocess::SimplexMesh& m = d.fem[r].mesh;
    const auto base = std::int64_t(f.nodes());
    for (std::size_t i = 0; i < m.node_count(); ++i) f.xyz.insert(f.xyz.end(), {m.x[i], m.y[i], m.z[i]});
    const io::CellType type = m.dim == 3 ? io::CellType::Tetra : io::CellType::Triangle;
    const auto npc = std::size_t(m.nodes_per_cell());
    for (std::size_t e = 0; e < m.cell_count(); ++e) {
      f.cell_types.push_back(type);
      for (std::size_t k = 0; k < npc; ++k)
        f.connectivity.push_back(base + std::int64_t(m.cells[e * npc + k]));
      region.values.push_back(double(r));
    }
  }
  f.cell_data.push_back(std::move(region));
  return f;
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

json mesh_report(const Scene& sc, const fs::path& output) {
  require_build_parts(sc, SceneUse::Model);  // a geometry file or FEM region this build cannot mesh
  // The model as a description only (never a dem::Simulation): regions filled, FEM regions
  // meshed, bonds counted on a cell grid by length class (regular regions; never stored).
  const auto t0 = WallClock::now();
  const ModelDescription d = describe_model(sc, /*allow_fem=*/true);
  const preprocess::PairCounts bonds = count_bonds(d);
  const double seconds = seconds_since(t0);
  json j = description_json(d, sc, bonds.pairs);
  j["seconds"] = seconds;
  j["particles_per_s"] = seconds > 0 ? double(d.particle_count()) / seconds : 0.0;
  // Bond counts by length class (length / d, classes 0.02 wide): one class for a regular
  // lattice, a spread for an eccentric one (ECC4D, Zhao et al. 2021).
  if (bonds.pairs > 0) j["bond_length_classes"] = bond_length_classes(bonds);
  if (!output.empty()) {
    // Particles: all of them up to kMaxWrittenParticles, else the surface (or none).
    const std::size_t n = d.particle_count();
    std::vector<std::uint32_t> ids;
    std::string which = "all";
    if (n <= kMaxWrittenParticles) {
      ids.resize(n);
      for (std::size_t i = 0; i < n; ++i) ids[i] = std::uint32_t(i);
    } else {
      ids = surface_particles(d);
      which = "surface";
      if (ids.size() > kMaxWrittenParticles) ids.clear(), which = "none";
    }
    j["written"] = json::array();
    j["written_particles"] = {{"selection", which}, {"count", ids.size()}};
    if (!ids.empty()) {
      io::Series particles(output, "model");
      j["written"].push_back(particles.add_particles(0.0, description_particles(d, ids)).string());
    }
    if (!d.fem.empty()) {
      io::Series fem(output, "fem");
      j["written"].push_back(fem.add_mesh(0.0, description_fem(d)).string());
    }
    for (const auto& f : write_bond_histograms(bond_stats(d, bonds.pairs), output))
      j["written"].push_back(f.string());
  }
  j["peak_rss_bytes"] = sys::peak_rss_bytes();
  return j;
}

}  // namespace strata::scene
