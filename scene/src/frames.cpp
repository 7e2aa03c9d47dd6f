#include <strata/scene/frames.hpp>

#include <strata/core/error.hpp>
#include <strata/dem/strain.hpp>
#include <strata/fem/stress.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace strata::scene {

namespace {
bool wants(const std::vector<std::string>& fields, const char* name) {
  return std::find(fields.begin(), fields.end(), name) != fields.end();
}

io::Array vector_array(const char* name, const std::vector<std::array<double, 3>>& v) {
  io::Array a{name, 3, {}, io::ArrayType::Float64};
  a.values.reserve(v.size() * 3);
  for (const auto& x : v) a.values.insert(a.values.end(), x.begin(), x.end());
  return a;
}

/// The entries of a per-particle array (`components` values per particle, internal order) at `rows`.
template <typename T>
std::vector<double> at_rows(const std::vector<T>& all, int components, std::span<const std::uint32_t> rows) {
  const auto c = std::size_t(components);
  std::vector<double> out;
  out.reserve(rows.size() * c);
  for (const std::uint32_t r : rows)
    out.insert(out.end(), all.begin() + std::ptrdiff_t(r * c), all.begin() + std::ptrdiff_t((r + 1) * c));
  return out;
}

/// 0, 1, ..., n - 1.
std::vector<std::uint32_t> every_row(std::size_t n) {
  std::vector<std::uint32_t> rows(n);
  std::iota(rows.begin(), rows.end(), 0u);
  return rows;
}

/// Rows are visited in chunks of this many, so that a selection of a large model never holds
/// a copy of every particle's position.
constexpr std::size_t kRowChunk = 1u << 16;

/// The bonds and contacts of bond_frame, those whose two particles pass `pass` (empty: all).
io::LineSet selected_bonds(const dem::Simulation& sim, const FrameSelection& sel,
                           const std::vector<std::uint8_t>& pass) {
  io::LineSet ls;
  io::Array state{std::string(io::kBondStateArray), 1, {}, io::ArrayType::UInt8};
  io::Array fn{"Fn", 1, {}, io::ArrayType::Float64}, fs{"Fs", 1, {}, io::ArrayType::Float64};
  const auto which = sel.bonds;
  const auto bonds = which == FrameSelection::Bonds::All      ? sim.bonds()
                     : which == FrameSelection::Bonds::Broken ? sim.broken_bonds()
                                                              : std::vector<dem::PairView>{};
  // A pair is written when both its particles pass the group and slice selection.
  auto selected = [&](const dem::PairView& p) { return pass.empty() || (pass[p.i] && pass[p.j]); };
  for (const auto& b : bonds) {
    if (!selected(b)) continue;
    ls.ends.push_back(b.i);
    ls.ends.push_back(b.j);
    // A broken bond as it is now: closed when it touches again after having opened (it may
    // open again later), else its mode of failure (a crack broken in shear may still touch).
    const io::BondState s = b.kind == dem::PairKind::Intact          ? io::BondState::Intact
                            : b.reclosed && b.touching               ? io::BondState::Closed
                            : b.kind == dem::PairKind::BrokenTension ? io::BondState::BrokenTension
                                                                     : io::BondState::BrokenShear;
    state.values.push_back(double(int(s)));
    fn.values.push_back(b.fn);
    fs.values.push_back(b.fs);
  }
  if (sel.contacts) {
    // contacts() lists the unbonded pairs within the search distance; write those touching.
    for (const auto& c : sim.contacts()) {
      if (c.kind != dem::PairKind::Contact || !c.touching || !selected(c)) continue;
      ls.ends.push_back(c.i);
      ls.ends.push_back(c.j);
      state.values.push_back(double(int(io::BondState::Contact)));
      fn.values.push_back(c.fn);
      fs.values.push_back(c.fs);
    }
  }
  ls.cell_data = {std::move(state), std::move(fn), std::move(fs)};
  return ls;
}
}  // namespace

io::PointCloud particle_frame(const dem::Simulation& sim, const std::vector<std::string>& fields) {
  return particle_frame(sim, fields, every_row(sim.particle_count()));
}

io::PointCloud particle_frame(const dem::Simulation& sim, const std::vector<std::string>& fields,
                              std::span<const std::uint32_t> rows) {
  io::PointCloud pc;
  pc.dim = sim.dim();
  pc.time = sim.time();
  pc.step = sim.step_count();
  const auto pos = sim.positions(rows);
  pc.xyz.reserve(pos.size() * 3);
  for (const auto& p : pos) pc.xyz.insert(pc.xyz.end(), p.begin(), p.end());

  const auto r = sim.radii(rows);
  pc.point_data.push_back({std::string(io::kRadiusArray), 1, {r.begin(), r.end()}, io::ArrayType::Float64});
  if (wants(fields, "id")) {
    const auto ids = sim.ids(rows);
    pc.point_data.push_back({"id", 1, {ids.begin(), ids.end()}, io::ArrayType::Int64});
  }
  if (wants(fields, "displacement"))
    pc.point_data.push_back(vector_array("displacement", sim.displacements(rows)));
  if (wants(fields, "velocity")) pc.point_data.push_back(vector_array("velocity", sim.velocities(rows)));
  if (wants(fields, "force")) {
    // Sum of the bond and contact forces on each particle, from the pairs' forces on their
    // first particle (an output-time gather over every pair; the step loop keeps no force array).
    std::vector<double> f(sim.particle_count() * 3, 0.0);
    auto add = [&](const std::vector<dem::PairView>& pairs) {
      for (const auto& p : pairs)
        for (int a = 0; a < 3; ++a) {
          f[p.i * 3 + a] += p.force_on_i[a];
          f[p.j * 3 + a] -= p.force_on_i[a];
        }
    };
    add(sim.bonds());
    add(sim.contacts());
    pc.point_data.push_back({"force", 3, at_rows(f, 3, rows), io::ArrayType::Float64});
  }
  if (wants(fields, "group")) {
    const auto g = sim.last_group(rows);
    pc.point_data.push_back({"group", 1, {g.begin(), g.end()}, io::ArrayType::Int64});
  }
  if (wants(fields, "shear_strain") && sim.dim() == 2) {
    // each particle's strain from its neighbours: computed over all particles
    const auto now = sim.positions();
    const auto u = sim.displacements();
    std::vector<std::array<double, 3>> start(now.size());
    for (std::size_t i = 0; i < now.size(); ++i)
      for (int a = 0; a < 3; ++a) start[i][a] = now[i][a] - u[i][a];
    const auto g = shear_strain_since_start(start, now, sim.radii());
    pc.point_data.push_back({"shear_strain", 1, at_rows(g, 1, rows), io::ArrayType::Float32});
  }
  if (wants(fields, "damage")) {
    const auto d = sim.damage(rows);
    pc.point_data.push_back({"damage", 1, {d.begin(), d.end()}, io::ArrayType::Float32});
  }
  return pc;
}

void FrameSelection::find_surface(const dem::Simulation& sim) {
  const auto ids = sim.ids();
  const auto count = sim.bond_counts();        // every bond entry, broken or not
  const int inside = sim.dim() == 2 ? 6 : 12;  // coordination of the hex / close-packed lattice
  surface_by_id.assign(ids.size(), 0);
  for (std::size_t i = 0; i < count.size(); ++i) surface_by_id[ids[i]] = count[i] < inside;
}

bool FrameSelection::in_groups_and_slice(bool in_group, const double* x) const {
  if (!groups.empty() && !in_group) return false;
  if (slice_thickness > 0) {
    double dist = 0;
    for (int a = 0; a < 3; ++a) dist += (x[a] - slice_point[a]) * slice_normal[a];
    if (std::abs(dist) > slice_thickness / 2) return false;
  }
  return true;
}

std::vector<std::uint8_t> FrameSelection::passes(const dem::Simulation& sim) const {
  if (groups.empty() && slice_thickness == 0) return {};
  const std::size_t n = sim.particle_count();
  std::vector<std::uint8_t> pass = groups.empty() ? std::vector<std::uint8_t>(n, 1) : sim.in_groups(groups);
  if (slice_thickness == 0) return pass;
  std::vector<std::uint32_t> chunk;
  for (std::size_t first = 0; first < n; first += kRowChunk) {
    chunk.resize(std::min(kRowChunk, n - first));
    std::iota(chunk.begin(), chunk.end(), std::uint32_t(first));
    const auto pos = sim.positions(chunk);
    for (std::size_t k = 0; k < chunk.size(); ++k)
      pass[first + k] = in_groups_and_slice(pass[first + k], pos[k].data());
  }
  return pass;
}

std::vector<std::uint32_t> FrameSelection::particle_rows(const dem::Simulation& sim,
                                                         const std::vector<std::uint8_t>& pass) const {
  std::vector<std::uint32_t> rows;
  if (particles == Particles::None) return rows;
  const bool surface = particles == Particles::Surface, both = particles == Particles::SurfaceAndSlice;
  const auto ids = surface || both ? sim.ids() : std::vector<std::uint32_t>{};
  const auto in_group = both && !groups.empty() ? sim.in_groups(groups) : std::vector<std::uint8_t>{};
  for (std::size_t i = 0; i < sim.particle_count(); ++i) {
    const bool passes = pass.empty() || pass[i];
    const bool keep = both ? passes || (surface_by_id[ids[i]] && (in_group.empty() || in_group[i]))
                           : passes && (!surface || surface_by_id[ids[i]]);
    if (keep) rows.push_back(std::uint32_t(i));
  }
  return rows;
}

io::LineSet bond_frame(const dem::Simulation& sim, const FrameSelection& sel) {
  return selected_bonds(sim, sel, sel.passes(sim));
}

io::PointCloud SelectedFrame::particles() const {
  if (kept.size() == points.size()) return points;
  io::PointCloud out;
  out.dim = points.dim;
  out.time = points.time;
  out.step = points.step;
  out.xyz = at_rows(points.xyz, 3, kept);
  for (const auto& a : points.point_data)
    out.point_data.push_back({a.name, a.components, at_rows(a.values, a.components, kept), a.type});
  return out;
}

SelectedFrame selected_frame(const dem::Simulation& sim, const std::vector<std::string>& fields,
                             const FrameSelection& sel, bool every_point) {
  SelectedFrame f;
  const std::size_t n = sim.particle_count();
  const auto pass = sel.passes(sim);
  const auto rows = sel.keeps_all() ? every_row(n) : sel.particle_rows(sim, pass);
  f.bonds = selected_bonds(sim, sel, pass);
  // The points: the written particles and the bonds' ends, in internal order.
  if (every_point || rows.size() == n) {
    f.rows = every_row(n);
  } else {
    std::vector<std::uint8_t> used(n, 0);
    for (const std::uint32_t r : rows) used[r] = 1;
    for (const std::uint32_t e : f.bonds.ends) used[e] = 1;
    for (std::size_t i = 0; i < n; ++i)
      if (used[i]) f.rows.push_back(std::uint32_t(i));
  }
  auto index_of = [&](std::uint32_t row) {
    return std::size_t(std::lower_bound(f.rows.begin(), f.rows.end(), row) - f.rows.begin());
  };
  for (auto& e : f.bonds.ends) e = index_of(std::uint32_t(e));
  f.kept.reserve(rows.size());
  for (const std::uint32_t r : rows) f.kept.push_back(std::uint32_t(index_of(r)));
  f.points = particle_frame(sim, fields, f.rows);
  return f;
}

io::MeshFrame fem_frame(const fem::Mesh& mesh, const Eigen::VectorXd& u, const Eigen::VectorXd& v,
                        double time, std::int64_t step) {
  const std::size_t n = mesh.nodes();
  const int dim = mesh.dim;
  STRATA_CHECK(
      static_cast<std::size_t>(u.size()) == mesh.dofs() && static_cast<std::size_t>(v.size()) == mesh.dofs(),
      Input, "fem_frame: u has {} and v {} values, the mesh has {} DOFs", u.size(), v.size(), mesh.dofs());
  io::MeshFrame f;
  f.dim = dim == 3 ? 3 : 2;
  f.time = time;
  f.step = step;
  f.xyz.resize(3 * n, 0.0);
  io::Array disp{"displacement", 3, std::vector<double>(3 * n, 0.0), io::ArrayType::Float64};
  io::Array vel{"velocity", 3, std::vector<double>(3 * n, 0.0), io::ArrayType::Float64};
  for (std::size_t i = 0; i < n; ++i)
    for (int a = 0; a < dim; ++a) {
      f.xyz[3 * i + a] = mesh.x[static_cast<std::size_t>(a)][i];
      disp.values[3 * i + a] = u[static_cast<Eigen::Index>(i) * dim + a];
      vel.values[3 * i + a] = v[static_cast<Eigen::Index>(i) * dim + a];
    }
  io::Array stress{"stress", 6, {}, io::ArrayType::Float64};
  io::Array mises{"von_mises", 1, {}, io::ArrayType::Float64};
  io::Array block_id{"block", 1, {}, io::ArrayType::Int32};
  for (std::size_t b = 0; b < mesh.blocks.size(); ++b) {
    const fem::ElementBlock& block = mesh.blocks[b];
    const io::CellType type = block.type == fem::ElementType::Tri3   ? io::CellType::Triangle
                              : block.type == fem::ElementType::Tet4 ? io::CellType::Tetra
                                                                     : io::CellType::Line;
    const auto npe = static_cast<std::size_t>(fem::nodes_per_element(block.type));
    for (std::size_t e = 0; e < block.size(); ++e) {
      f.cell_types.push_back(type);
      for (std::size_t k = 0; k < npe; ++k) f.connectivity.push_back(block.conn[e * npe + k]);
      // Voigt (xx, yy, zz, yz, xz, xy) -> ParaView's tensor order (xx, yy, zz, xy, yz, xz).
      const auto s = fem::element_stress(mesh, block, e, u);
      stress.values.insert(stress.values.end(), {s[0], s[1], s[2], s[5], s[3], s[4]});
      const double dev =
          (s[0] - s[1]) * (s[0] - s[1]) + (s[1] - s[2]) * (s[1] - s[2]) + (s[2] - s[0]) * (s[2] - s[0]);
      mises.values.push_back(std::sqrt(0.5 * dev + 3 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5])));
      block_id.values.push_back(double(b));
    }
  }
  f.point_data = {std::move(disp), std::move(vel)};
  f.cell_data = {std::move(stress), std::move(mises), std::move(block_id)};
  return f;
}

io::MeshFrame wall_frame(const dem::Simulation& sim) {
  io::MeshFrame f;
  f.dim = sim.dim();
  f.time = sim.time();
  f.step = sim.step_count();
  const auto walls = sim.walls();
  const auto pos = sim.positions();
  if (walls.empty() || pos.empty()) return f;
  // The particles' box now, radii included.
  const auto r = sim.radii();
  std::array<double, 3> lo{}, hi{};
  lo.fill(std::numeric_limits<double>::infinity());
  hi.fill(-std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < pos.size(); ++i)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], pos[i][a] - r[i]);
      hi[a] = std::max(hi[a], pos[i][a] + r[i]);
    }
  if (f.dim == 2) lo[2] = hi[2] = 0;
  double diagonal = 0;
  for (int a = 0; a < 3; ++a) diagonal += (hi[a] - lo[a]) * (hi[a] - lo[a]);
  const double margin = 0.05 * std::sqrt(diagonal);

  auto dot = [](const std::array<double, 3>& a, const std::array<double, 3>& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  };
  io::Array index{"wall", 1, {}, io::ArrayType::Int32};
  io::Array normal{"normal", 3, {}, io::ArrayType::Float64};
  io::Array velocity{"velocity", 3, {}, io::ArrayType::Float64};
  for (std::size_t w = 0; w < walls.size(); ++w) {
    const dem::WallView& wall = walls[w];
    const auto& n = wall.normal;
    // In-plane unit directions: in 2D the line's direction; in 3D the axis least along n
    // made normal to it, and n × that one.
    std::array<double, 3> t1{-n[1], n[0], 0.0}, t2{};
    if (f.dim == 3) {
      int least = 0;
      for (int a = 1; a < 3; ++a)
        if (std::abs(n[a]) < std::abs(n[least])) least = a;
      t1 = {0, 0, 0};
      t1[least] = 1;
      const double along = t1[least] * n[least];
      for (int a = 0; a < 3; ++a) t1[a] -= along * n[a];
      const double len = std::sqrt(dot(t1, t1));
      for (double& c : t1) c /= len;
      t2 = {n[1] * t1[2] - n[2] * t1[1], n[2] * t1[0] - n[0] * t1[2], n[0] * t1[1] - n[1] * t1[0]};
    }
    // The extent of the box's corners projected onto the plane, widened by the margin.
    double s1[2] = {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
    double s2[2] = {s1[0], s1[1]};
    for (int corner = 0; corner < 8; ++corner) {
      std::array<double, 3> c{};
      for (int a = 0; a < 3; ++a) c[a] = ((corner >> a & 1) ? hi[a] : lo[a]) - wall.point[a];
      s1[0] = std::min(s1[0], dot(c, t1)), s1[1] = std::max(s1[1], dot(c, t1));
      s2[0] = std::min(s2[0], dot(c, t2)), s2[1] = std::max(s2[1], dot(c, t2));
    }
    auto add_node = [&](double a, double b) {
      for (int k = 0; k < 3; ++k) f.xyz.push_back(wall.point[k] + (a * t1[k] + b * t2[k]));
      return std::int64_t(f.nodes() - 1);
    };
    const double a0 = s1[0] - margin, a1 = s1[1] + margin;
    auto add_cell_data = [&] {
      index.values.push_back(double(w));
      normal.values.insert(normal.values.end(), n.begin(), n.end());
      velocity.values.insert(velocity.values.end(), wall.velocity.begin(), wall.velocity.end());
    };
    if (f.dim == 2) {
      const auto p0 = add_node(a0, 0), p1 = add_node(a1, 0);
      f.add_cell(io::CellType::Line, {p0, p1});
      add_cell_data();
    } else {
      const double b0 = s2[0] - margin, b1 = s2[1] + margin;
      const auto p0 = add_node(a0, b0), p1 = add_node(a1, b0), p2 = add_node(a1, b1), p3 = add_node(a0, b1);
      f.add_cell(io::CellType::Triangle, {p0, p1, p2});
      f.add_cell(io::CellType::Triangle, {p0, p2, p3});
      add_cell_data();
      add_cell_data();
    }
  }
  f.cell_data = {std::move(index), std::move(normal), std::move(velocity)};
  return f;
}

std::vector<double> shear_strain_since_start(const std::vector<std::array<double, 3>>& start,
                                             const std::vector<std::array<double, 3>>& now,
                                             const std::vector<double>& radii,
                                             const std::vector<std::uint8_t>& only) {
  std::vector<std::size_t> picked;
  for (std::size_t i = 0; i < start.size(); ++i)
    if (only.empty() || only[i]) picked.push_back(i);
  std::vector<double> gamma(start.size(), 0.0);
  if (picked.empty()) return gamma;
  std::vector<std::array<double, 3>> s0, s1;
  std::vector<double> r;
  for (const std::size_t i : picked) s0.push_back(start[i]), s1.push_back(now[i]), r.push_back(radii[i]);
  std::nth_element(r.begin(), r.begin() + long(r.size() / 2), r.end());
  const auto g = dem::shear_strain_2d(s0, s1, 3.0 * r[r.size() / 2]);
  for (std::size_t k = 0; k < picked.size(); ++k) gamma[picked[k]] = g[k];
  return gamma;
}

io::RenderStyle field_style(const std::string& field, const std::vector<std::string>& group_names) {
  io::RenderStyle style;
  style.field = field;
  if (field == "group") style.categories = group_names;
  if (field == "displacement") style.field_scale = 1e3, style.unit = "mm";
  if (field == "velocity") style.unit = "m/s";
  if (field == "damage") style.range = std::array<double, 2>{0.0, 1.0};
  if (field == "shear_strain") {
    // shear zones stand out from 0.25 on; a décollement or a piston's corner shears far more
    style.range = std::array<double, 2>{0.0, 1.5};
    style.field_label = "shear strain";
  }
  return style;
}

void show_overlap(const couple::Coupler& coupler, const dem::Simulation& sim, int dim, io::MeshFrame* mesh,
                  io::PointCloud* particles) {
  const auto d = std::size_t(dim);
  if (particles) {
    const auto ids = sim.ids();  // frame index -> particle id
    std::vector<std::size_t> index_of(ids.size());
    for (std::size_t i = 0; i < ids.size(); ++i) index_of[ids[i]] = i;
    io::Array* pu = particles->find("displacement");
    io::Array* pv = particles->find("velocity");
    const auto u_now = sim.displacements();  // internal order, as the frame
    const couple::Coupler::Exchanged e = coupler.exchanged_to_dem();
    for (std::size_t k = 0; k < e.dof.size(); ++k) {
      const std::size_t i = index_of[e.dof[k] / d], a = e.dof[k] % d;
      particles->xyz[3 * i + a] += e.u[k] - u_now[i][a];
      if (pu) pu->values[3 * i + a] = e.u[k];
      if (pv) pv->values[3 * i + a] = e.v[k];
    }
    const auto roles = coupler.dem_roles();
    io::Array tag{"overlap", 1, std::vector<double>(ids.size()), io::ArrayType::UInt8};
    for (std::size_t i = 0; i < ids.size(); ++i) tag.values[i] = roles[std::size_t(ids[i]) * d];
    particles->point_data.push_back(std::move(tag));
  }
  if (!mesh) return;
  io::Array* mu = mesh->find_point("displacement");
  io::Array* mv = mesh->find_point("velocity");
  const couple::Coupler::Exchanged e = coupler.exchanged_to_fem();
  for (std::size_t k = 0; k < e.dof.size(); ++k) {
    const std::size_t n = e.dof[k] / d, a = e.dof[k] % d;
    if (mu) mu->values[3 * n + a] = e.u[k];
    if (mv) mv->values[3 * n + a] = e.v[k];
  }
  const auto roles = coupler.fem_roles();
  io::Array tag{"overlap", 1, std::vector<double>(mesh->nodes()), io::ArrayType::UInt8};
  for (std::size_t n = 0; n < mesh->nodes(); ++n) tag.values[n] = roles[n * d];
  mesh->point_data.push_back(std::move(tag));
}

}  // namespace strata::scene
