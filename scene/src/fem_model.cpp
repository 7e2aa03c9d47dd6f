// The FEM side of a model: FEM regions meshed (alone, or with the overlap ring of a coupled
// model), their materials, node groups, boundary conditions and loads, the integrator and
// its time step, and the coupling with the particles through the overlap layers.
#include <strata/core/error.hpp>
#include <strata/core/log.hpp>
#include <strata/core/numbers.hpp>
#include <strata/dem/lattice_elastic.hpp>
#include <strata/fem/mesh.hpp>
#include <strata/fem/solver.hpp>
#include <strata/preprocess/overlap.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <set>

#include "model_parts.hpp"

namespace strata::scene {
namespace {

/// Elastic constants and density of a material as a continuum. Given youngs_modulus and
/// poisson_ratio are used as they are; otherwise the material's lattice is homogenised: in
/// 2D the hexagonal lattice per unit thickness, E·t = 2√3·Kn(Kn+Ks)/(3Kn+Ks) and
/// ν = (Kn−Ks)/(3Kn+Ks); in 3D the isotropic (Voigt) average of the close-packed lattice,
/// E = 2√2·Kn(2Kn+3Ks)/(d(4Kn+Ks)) and ν = (Kn−Ks)/(4Kn+Ks) (Liu, Pollard & Shi 2013). The
/// density per volume is the lattice's mass over its area times the thickness (2D: density/t,
/// the [[material]] density being per unit area of the lattice) or its volume (3D).
fem::Material continuum(const MaterialTable& mat, int dim, double thickness, double diameter) {
  fem::Material m;
  const double kn = mat.kn, ks = mat.ks;
  if (mat.youngs_modulus.given) {
    m.E = mat.youngs_modulus;
    m.nu = mat.poisson_ratio;
  } else if (dim == 2) {
    const dem::LatticeElastic e = dem::hex_elastic(kn, ks);
    m.E = e.E / thickness;
    m.nu = e.nu;
  } else {
    STRATA_CHECK(diameter > 0, Input,
                 "{}: material '{}' fills an FEM region of a scene without particles: "
                 "give it youngs_modulus and poisson_ratio",
                 mat.name.pos.str(), mat.name.value);
    const dem::LatticeElastic e = dem::close_packed_isotropic_elastic(kn, ks, diameter);
    m.E = e.E;
    m.nu = e.nu;
  }
  m.rho = dim == 2 ? mat.density / thickness : mat.density;
  m.thickness = thickness;
  m.plane = fem::PlaneMode::Stress;
  return m;
}

const MaterialTable& material_table(const Scene& sc, const std::string& name) {
  for (const auto& t : sc.materials)
    if (t.name == name) return t;
  fail(ErrorKind::Internal, "material '{}' not found after validation", name);
}

/// FEM nodes of a group: the candidates (the nodes of the named region, or of every FEM
/// region) that the selection picks.
std::vector<std::uint32_t> select_nodes(const GroupTable& g, const preprocess::SimplexMesh& mesh,
                                        const std::vector<std::uint32_t>& candidates) {
  const GroupSelect sel = g.select;
  if (sel == GroupSelect::All) return candidates;
  if (sel == GroupSelect::Box) {
    const auto lo = vec3(g.box_min), hi = vec3(g.box_max);
    std::vector<std::uint32_t> out;
    for (auto n : candidates) {
      const auto x = mesh.node(n);
      bool in = true;
      for (int a = 0; a < mesh.dim; ++a) in = in && x[a] >= lo[a] && x[a] <= hi[a];
      if (in) out.push_back(n);
    }
    return out;
  }
  int axis = -1, side = 0;
  if (sel == GroupSelect::TopRow) axis = 1, side = 1;
  if (sel == GroupSelect::BottomRow) axis = 1, side = -1;
  if (sel == GroupSelect::RightColumn) axis = 0, side = 1;
  if (sel == GroupSelect::LeftColumn) axis = 0, side = -1;
  if (sel == GroupSelect::TopLayer) axis = 2, side = 1;
  if (sel == GroupSelect::BottomLayer) axis = 2, side = -1;
  if (axis < 0)
    g.select.fail(
        fmt::format("select = \"{}\" picks particles; FEM nodes are picked with \"all\", \"box\", "
                    "\"top_row\", \"bottom_row\", \"left_column\", \"right_column\", \"top_layer\" "
                    "or \"bottom_layer\" (the nodes on the region's extreme side)",
                    to_string(sel)));
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (auto n : candidates) lo = std::min(lo, mesh.node(n)[axis]), hi = std::max(hi, mesh.node(n)[axis]);
  const double tol = 1e-6 * std::max(hi - lo, 1e-300);
  std::vector<std::uint32_t> out;
  for (auto n : candidates) {
    const double c = mesh.node(n)[axis];
    if (side > 0 ? c >= hi - tol : c <= lo + tol) out.push_back(n);
  }
  return out;
}

/// One component of a force history: from one listed value to the next linearly or
/// smoothly (strata/core/ramp.hpp), constant outside the listed times.
struct HistoryComponent {
  std::vector<double> t, f;
  Ramp ramp = Ramp::Linear;
  double operator()(double time) const {
    if (time <= t.front()) return f.front();
    if (time >= t.back()) return f.back();
    const auto k = std::size_t(std::upper_bound(t.begin(), t.end(), time) - t.begin());
    const double w = ramp_weight((time - t[k - 1]) / (t[k] - t[k - 1]), ramp);
    return f[k - 1] + w * (f[k] - f[k - 1]);
  }
};

/// Each node's share of the mesh boundary between `nodes` (sorted): half the length of every
/// boundary edge (2D) or a third of the area of every boundary triangle (3D) whose corners
/// are all in `nodes`, in the order of `nodes`. A traction t on that boundary, applied as
/// t·share at each node, is the consistent load of linear elements.
std::vector<double> boundary_shares(const preprocess::SimplexMesh& mesh,
                                    const std::vector<std::uint32_t>& nodes) {
  const std::size_t npe = std::size_t(mesh.nodes_per_cell()), nf = npe - 1;  // corners per facet
  std::vector<std::array<std::uint32_t, 3>> facets;  // sorted corners (3D; the third is unused in 2D)
  facets.reserve(mesh.cell_count() * npe);
  for (std::size_t e = 0; e < mesh.cell_count(); ++e)
    for (std::size_t skip = 0; skip < npe; ++skip) {  // the facet opposite corner `skip`
      std::array<std::uint32_t, 3> f{0, 0, 0};
      for (std::size_t k = 0, i = 0; k < npe; ++k)
        if (k != skip) f[i++] = mesh.cells[e * npe + k];
      if (f[0] > f[1]) std::swap(f[0], f[1]);  // corners in ascending order
      if (nf == 3) {
        if (f[1] > f[2]) std::swap(f[1], f[2]);
        if (f[0] > f[1]) std::swap(f[0], f[1]);
      }
      facets.push_back(f);
    }
  std::sort(facets.begin(), facets.end());
  auto member = [&](std::uint32_t n) { return std::binary_search(nodes.begin(), nodes.end(), n); };
  std::vector<double> share(nodes.size(), 0.0);
  auto add = [&](std::uint32_t n, double v) {
    share[std::size_t(std::lower_bound(nodes.begin(), nodes.end(), n) - nodes.begin())] += v;
  };
  for (std::size_t i = 0; i < facets.size();) {
    std::size_t j = i + 1;
    while (j < facets.size() && facets[j] == facets[i]) ++j;
    const auto& f = facets[i];
    const bool boundary = j - i == 1;  // a facet of one cell only
    i = j;
    if (!boundary || !std::all_of(f.begin(), f.begin() + std::ptrdiff_t(nf), member)) continue;
    const auto a = mesh.node(f[0]), b = mesh.node(f[1]);
    if (nf == 2) {
      double l2 = 0;
      for (int c = 0; c < 3; ++c) l2 += (b[c] - a[c]) * (b[c] - a[c]);
      const double half = 0.5 * std::sqrt(l2);
      add(f[0], half);
      add(f[1], half);
    } else {
      const auto c = mesh.node(f[2]);
      const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]},
                   v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
      const double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
      const double third = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) / 6;  // area / 3
      for (int k = 0; k < 3; ++k) add(f[std::size_t(k)], third);
    }
  }
  return share;
}

/// The FEM mesh as libfem's: one block per cell group of `mesh` (in group order), each with
/// the continuum of its material.
fem::Mesh fem_mesh_of(const preprocess::SimplexMesh& mesh, const std::vector<fem::Material>& group_material) {
  fem::Mesh out;
  out.dim = mesh.dim;
  for (std::size_t n = 0; n < mesh.node_count(); ++n) out.add_node(mesh.x[n], mesh.y[n], mesh.z[n]);
  const int npe = mesh.nodes_per_cell();
  std::vector<fem::ElementBlock> blocks(group_material.size());
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    blocks[b].type = mesh.dim == 2 ? fem::ElementType::Tri3 : fem::ElementType::Tet4;
    blocks[b].material = group_material[b];
  }
  for (std::size_t e = 0; e < mesh.cell_count(); ++e) {
    auto& conn = blocks[std::size_t(mesh.cell_group[e])].conn;
    for (int k = 0; k < npe; ++k)
      conn.push_back(std::int32_t(mesh.cells[e * std::size_t(npe) + std::size_t(k)]));
  }
  for (auto& b : blocks)
    if (!b.conn.empty()) out.blocks.push_back(std::move(b));
  return out;
}

/// Merges FEM regions meshed one by one into one mesh with one cell group per region (nodes
/// are not shared between regions: FEM regions of a scene without particles are separate
/// bodies unless they come from one geometry file's shared mesh).
preprocess::SimplexMesh merge_meshes(const std::vector<FemRegion>& regions, int dim) {
  preprocess::SimplexMesh out;
  out.dim = dim;
  for (std::size_t r = 0; r < regions.size(); ++r) {
    const auto& m = regions[r].mesh;
    const auto base = std::uint32_t(out.node_count());
    for (std::size_t n = 0; n < m.node_count(); ++n) out.add_node(m.node(n));
    for (auto c : m.cells) out.cells.push_back(base + c);
    out.cell_group.insert(out.cell_group.end(), m.cell_count(), std::int32_t(r));
    out.group_names.push_back(regions[r].name);
  }
  return out;
}

/// The nodes of each FEM region: the nodes of the elements of cell groups 0 .. regions-1 of
/// `mesh` (named as `info` names them), sorted, each once. Later groups (overlap rings) are
/// not regions of the scene.
std::map<std::string, std::vector<std::uint32_t>> region_nodes_of(const preprocess::SimplexMesh& mesh,
                                                                  const std::vector<FemRegionInfo>& info,
                                                                  std::size_t regions) {
  std::map<std::string, std::vector<std::uint32_t>> out;
  const auto npe = std::size_t(mesh.nodes_per_cell());
  for (std::size_t e = 0; e < mesh.cell_count(); ++e) {
    const auto g = std::size_t(mesh.cell_group[e]);
    if (g >= regions) continue;
    auto& nodes = out[info[g].name];
    nodes.insert(nodes.end(), mesh.cells.begin() + std::ptrdiff_t(e * npe),
                 mesh.cells.begin() + std::ptrdiff_t((e + 1) * npe));
  }
  for (auto& [name, nodes] : out) {
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  }
  return out;
}

/// A radial [[load]] on FEM nodes: each node pushed along the unit vector from the load's
/// centre (default: the nodes' mean position) to the node, its component along `axis` removed,
/// times its share of the load (in the order of `nodes`).
void radial_fem_load(const LoadTable& l, const std::vector<std::uint32_t>& nodes,
                     const std::vector<double>& share, const preprocess::SimplexMesh& mesh,
                     fem::Solver& solver) {
  const int dim = mesh.dim;
  std::array<double, 3> centre = vec3(l.center);
  if (l.center->empty()) {
    centre = {0, 0, 0};
    for (auto n : nodes)
      for (int a = 0; a < 3; ++a) centre[a] += mesh.node(n)[a] / double(nodes.size());
  }
  const auto axis = vec3(l.axis);
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    const std::uint32_t n = nodes[k];
    const auto dir = dem::Simulation::radial_direction(mesh.node(n), centre, axis, dim);
    for (int a = 0; a < dim; ++a) {  // a node at the centre has no direction: no load
      HistoryComponent h;
      h.t = l.times;
      h.ramp = l.ramp;
      for (double f : l.magnitudes.value) h.f.push_back(share[k] * f * dir[a]);
      if (std::all_of(h.f.begin(), h.f.end(), [](double f) { return f == 0; })) continue;
      solver.add_load(std::size_t(n) * std::size_t(dim) + std::size_t(a), h);
    }
  }
}

/// Applies [[group]], [[boundary]] and [[load]] entries to FEM nodes. `region_nodes` maps a
/// region name to its nodes.
void fem_conditions(const Scene& sc, const preprocess::SimplexMesh& mesh,
                    const std::map<std::string, std::vector<std::uint32_t>>& region_nodes,
                    fem::Solver& solver, BuiltModel& m) {
  const int dim = mesh.dim;
  for (const auto& [name, nodes] : region_nodes) m.fem_groups[name] = nodes;
  std::vector<std::uint32_t> every;
  for (const auto& [name, nodes] : region_nodes) every.insert(every.end(), nodes.begin(), nodes.end());
  std::sort(every.begin(), every.end());
  every.erase(std::unique(every.begin(), every.end()), every.end());
  for (const auto& g : sc.groups) {
    const std::string& region = g.region;
    const bool fem_region = region_nodes.count(region) > 0;
    if (!region.empty() && !fem_region) continue;  // a particle region's group
    std::vector<std::uint32_t> nodes = select_nodes(g, mesh, fem_region ? region_nodes.at(region) : every);
    if (nodes.empty() && !m.groups.count(g.name))
      g.select.fail(fmt::format("group '{}' selects no particle and no FEM node", g.name.value));
    if (!nodes.empty()) m.fem_groups[g.name] = std::move(nodes);
  }
  for (const auto& b : sc.boundaries) {
    const auto it = m.fem_groups.find(b.group);
    if (it == m.fem_groups.end()) continue;
    const BoundaryType type = b.type;
    if (type == BoundaryType::StepDisplacement)
      b.type.fail(
          fmt::format("group '{}' holds FEM nodes: a step_displacement boundary moves particles only; "
                      "use type = \"velocity\" (or \"fixed\") for FEM nodes",
                      b.group.value));
    const unsigned axes = axes_mask(b.axes, dim);
    const auto v = type == BoundaryType::Velocity ? vec3(b.velocity) : std::array<double, 3>{};
    for (auto n : it->second)
      for (int a = 0; a < dim; ++a) {
        if (!(axes >> a & 1u)) continue;
        const std::size_t d = std::size_t(n) * std::size_t(dim) + std::size_t(a);
        if (type == BoundaryType::Fixed)
          solver.fix(d);
        else
          solver.prescribe(d, 0.0, v[a]);
      }
  }
  for (const auto& l : sc.loads) {
    const auto it = m.fem_groups.find(l.group);
    if (it == m.fem_groups.end()) continue;
    const std::vector<std::uint32_t>& nodes = it->second;
    // each node's share of the load: 1, 1/count, or its share of the group's boundary
    std::vector<double> share(nodes.size(), l.per == LoadPer::Group ? 1.0 / double(nodes.size()) : 1.0);
    if (l.per == LoadPer::Boundary) {
      share = boundary_shares(mesh, nodes);
      if (std::all_of(share.begin(), share.end(), [](double s) { return s == 0; }))
        l.per.fail(
            fmt::format("group '{}': no boundary {} of the FEM mesh has all its corners in the group, "
                        "so a traction has nothing to act on; select FEM nodes along the boundary "
                        "(e.g. a box around one side)",
                        l.group.value, dim == 2 ? "edge" : "triangle"));
    }
    if (l.type == LoadType::Radial) {
      radial_fem_load(l, nodes, share, mesh, solver);
      continue;
    }
    for (std::size_t k = 0; k < nodes.size(); ++k)
      for (int a = 0; a < dim; ++a) {
        HistoryComponent h;
        h.t = l.times;
        h.ramp = l.ramp;
        for (const auto& row : l.forces.value) h.f.push_back(share[k] * vec3(row)[a]);
        if (std::all_of(h.f.begin(), h.f.end(), [](double f) { return f == 0; })) continue;
        solver.add_load(std::size_t(nodes[k]) * std::size_t(dim) + std::size_t(a), h);
      }
  }
}

/// A model of FEM regions only.
BuiltModel build_fem_only(const Scene& sc, bool force) {
  const SolverTable& solver = sc.solver;
  const int dim = sc.scene.dimension;
  const double thickness = sc.scene.thickness;
  ModelDescription d = describe_model(sc, /*allow_fem=*/true);
  BuiltModel m;
  m.dim = dim;
  const preprocess::SimplexMesh mesh = merge_meshes(d.fem, dim);
  std::vector<fem::Material> materials;
  for (const auto& r : d.fem) {
    const fem::Material mat = continuum(material_table(sc, r.material), dim, thickness, 0.0);
    materials.push_back(mat);
    m.fem_regions.push_back({r.name, r.mesh.cell_count(), mat.E, mat.nu, mat.rho});
  }
  const auto region_nodes = region_nodes_of(mesh, m.fem_regions, d.fem.size());
  fem::SolverSettings fs;
  fs.dt = 1.0;  // set below, once the critical step is known
  fs.allow_unstable = force || solver.allow_unstable;
  fs.scheme = fem::Scheme::CentralDifference;
  auto part = std::make_unique<couple::FemPartition>(fem::Solver(fem_mesh_of(mesh, materials), fs));
  fem::Solver& s = part->solver();
  fem_conditions(sc, mesh, region_nodes, s, m);

  m.fem_explicit_dt_crit = s.stability().explicit_dt_crit;
  m.dt_automatic = solver.dt == 0.0;
  const double dt = m.dt_automatic ? solver.dt_safety * m.fem_explicit_dt_crit : solver.dt;
  s.set_scheme(scheme_of(solver, dt, m.fem_explicit_dt_crit));
  s.set_dt(dt);
  m.fem_dt_crit = s.stability().dt_crit;
  m.dt_crit = m.fem_dt_crit;
  if (dt > m.fem_dt_crit && !fs.allow_unstable) {
    const auto [dt_text, crit_text] = distinct_pair(dt, m.fem_dt_crit);
    solver.dt.fail(
        fmt::format("dt = {} s exceeds the critical time step {} s of the FEM regions with "
                    "the {} integrator (dt/dt_crit = {}); the run would blow up. Allowed: dt <= "
                    "{:.4g} s, fem_integrator = \"implicit-newmark\" (unconditionally stable), or "
                    "dt = 0 for {} x dt_crit; solver.allow_unstable = true or --force runs anyway",
                    dt_text, crit_text, fem::to_string(s.settings().scheme), ratio_text(dt, m.fem_dt_crit),
                    m.fem_dt_crit, solver.dt_safety.value));
  }
  s.initialise();
  m.dt = dt;
  m.steps = step_count_of(solver, m.dt, 1);
  m.fem_partition_ = std::move(part);
  return m;
}

/// The coupling's copies in libcouple's terms: per axis, DOF i·dim + a of a target takes
/// the weighted sum of the same axis of its sources. Particle sources and targets are the
/// overlap's particle indices, mapped to particle ids.
couple::Overlap coupling_links(const preprocess::OverlapModel& ov,
                               const std::vector<std::uint32_t>& particle_id, int dim) {
  couple::Overlap out;
  const auto D = std::size_t(dim);
  auto expand = [&](const preprocess::OverlapLinks& in, bool from_particles,
                    std::vector<couple::Link>& links) {
    for (std::size_t k = 0; k < in.size(); ++k)
      for (std::size_t a = 0; a < D; ++a) {
        couple::Link l{};
        const std::size_t to = from_particles ? in.target[k] : particle_id[in.target[k]];
        l.to = to * D + a;
        const std::uint32_t j0 = in.first[k], j1 = in.first[k + 1];
        for (std::uint32_t j = j0; j < j1; ++j) {
          const std::size_t src = from_particles ? particle_id[in.source[j]] : in.source[j];
          l.sources.push_back(src * D + a);
          l.weight.push_back(in.weight[j]);
        }
        l.from = l.sources.front();
        if (j1 - j0 == 1 && in.weight[j0] == 1.0) l.sources.clear(), l.weight.clear();  // a copy
        links.push_back(std::move(l));
      }
  };
  expand(ov.fem_to_dem, /*from_particles=*/false, out.fem_to_dem);
  expand(ov.dem_to_fem, /*from_particles=*/true, out.dem_to_fem);
  return out;
}

/// Particle regions coupled with FEM regions through the overlap layers of one geometry file.
BuiltModel build_coupled(const Scene& sc, bool force) {
  const SolverTable& solver = sc.solver;
  const int dim = sc.scene.dimension;
  const double thickness = sc.scene.thickness;

  // Every region of a coupled scene comes from one geometry file, with one lattice.
  std::vector<std::string> particle_names, fem_names;
  const RegionTable* first_particles = nullptr;
  std::string file;
  double far_size = 0;
  for (const auto& r : sc.regions) {
    const bool particles = r.kind == RegionKind::Particles;
    if (r.shape != RegionShape::File)
      r.shape.fail(
          fmt::format("region '{}': a scene with particle and FEM regions couples them through the "
                      "interfaces of one geometry file; every region must be shape = \"file\" "
                      "(allowed: a physical group of the geometry file)",
                      r.name.value));
    if (file.empty()) file = r.file->string();
    if (r.file->string() != file)
      r.file.fail(
          fmt::format("region '{}' is in {}, the first region in {}: the particle and FEM regions "
                      "of a coupled scene must come from one geometry file",
                      r.name.value, r.file->string(), file));
    if (r.unit != LengthUnit::Metre)
      r.unit.fail(
          "the geometry of a coupled scene is read in metres for now (allowed: unit = \"m\"); scale the "
          "file to metres (e.g. Dilate in a .geo)");
    if (particles) {
      if (!first_particles) first_particles = &r;
      if (r.diameter.value != first_particles->diameter.value ||
          r.lattice.value != first_particles->lattice.value ||
          r.orientation.value != first_particles->orientation.value)
        r.diameter.fail(
            fmt::format("region '{}': the particle regions of a coupled scene share one lattice "
                        "(diameter, lattice and orientation of region '{}')",
                        r.name.value, first_particles->name.value));
      if (r.eccentricity != RegionEccentricity::None)
        r.eccentricity.fail(
            "eccentric particle regions cannot be coupled with FEM regions yet (allowed: "
            "eccentricity = \"none\")");
      particle_names.push_back(r.physical);
    } else {
      fem_names.push_back(r.physical);
      far_size = std::max(far_size, r.mesh_size.value);
    }
  }
  const RegionTable& pr = *first_particles;
  // The overlap meshes its FEM side at the particle size; a far field of elements far smaller
  // than the particles has no use, and at 1e-9 m gmsh would mesh for ever.
  for (const auto& r : sc.regions)
    if (r.kind == RegionKind::Fem && r.mesh_size > 0 && r.mesh_size < 0.1 * pr.diameter)
      r.mesh_size.fail(fmt::format(
          "mesh_size = {} m: the FEM far field of a coupled scene has elements at least a tenth of the "
          "particle diameter ({} m); allowed: mesh_size >= {} m, or 0 to choose it automatically",
          r.mesh_size.value, pr.diameter.value, 0.1 * pr.diameter.value));
  preprocess::OverlapOptions oo;
  std::string lattice = pr.lattice;
  if (lattice == "auto") lattice = dim == 2 ? "hex" : "hcp";
  oo.kind = lattice == "hex"   ? preprocess::LatticeKind::Hex2D
            : lattice == "hcp" ? preprocess::LatticeKind::HCP
                               : preprocess::LatticeKind::FCC;
  oo.d = pr.diameter;
  oo.far_size = far_size;
  oo.orientation_deg = pr.orientation;
  preprocess::OverlapModel ov;
  try {
    ov = preprocess::build_coupled_model(file, particle_names, fem_names, oo);
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::Input) throw;
    pr.file.fail(e.what());  // the geometry's problem, at the scene line that names it
  }

  // Particles: the overlap's, region by region, then the band ("overlap", DEM externals).
  ModelDescription d = describe_model(sc, /*allow_fem=*/true, &ov);
  const std::vector<std::uint32_t> particle_id = d.overlap_particle_id;
  BuiltModel m;
  m.dim = dim;
  m.eta = int(solver.eta);
  m.execution_mode =
      solver.coupling == SolverCoupling::Parallel ? couple::Execution::Parallel : couple::Execution::Serial;
  dem::Settings ds = dem_settings(sc, force);
  ds.dt = std::numeric_limits<double>::min();  // set below, once the critical steps are known
  dem::Simulation sim(dim, ds);
  populate_particles(sc, d, sim, m);
  d = ModelDescription{};

  // FEM: the FEM regions' elements and the overlap rings, each with its material's continuum.
  std::vector<fem::Material> group_material;
  std::map<std::string, std::string> material_of;  // physical group -> material
  std::map<std::string, std::string> name_of;      // physical group -> region name
  for (const auto& r : sc.regions) material_of[r.physical] = r.material, name_of[r.physical] = r.name;
  std::vector<std::size_t> group_elements(ov.fem.group_names.size(), 0);
  for (auto g : ov.fem.cell_group) ++group_elements[std::size_t(g)];
  for (std::size_t g = 0; g < ov.fem.group_names.size(); ++g) {
    std::string physical = ov.fem.group_names[g];
    const bool ring = physical.size() > 5 && physical.ends_with(":ring");
    if (ring) physical.resize(physical.size() - 5);
    const fem::Material mat = continuum(material_table(sc, material_of.at(physical)), dim, thickness, oo.d);
    group_material.push_back(mat);
    m.fem_regions.push_back({ring ? name_of.at(physical) + ":ring" : name_of.at(physical), group_elements[g],
                             mat.E, mat.nu, mat.rho});
  }
  // Groups: the FEM regions in the order given, then the overlap rings.
  const auto region_nodes = region_nodes_of(ov.fem, m.fem_regions, fem_names.size());
  fem::SolverSettings fs;
  fs.dt = double(m.eta) * ds.dt;
  fs.allow_unstable = ds.allow_unstable;
  fs.scheme = fem::Scheme::CentralDifference;
  fem::Solver fem_solver(fem_mesh_of(ov.fem, group_material), fs);
  fem_conditions(sc, ov.fem, region_nodes, fem_solver, m);
  for (std::size_t n = 0; n < ov.node_tag.size(); ++n)
    m.overlap_nodes += ov.node_tag[n] == preprocess::OverlapTag::External;
  for (auto t : ov.particle_tag) m.overlap_particles += t == preprocess::OverlapTag::External;

  m.dem_partition_ = std::make_unique<couple::DemPartition>(std::move(sim), "DEM");
  m.fem_partition_ = std::make_unique<couple::FemPartition>(std::move(fem_solver), "FEM");
  m.coupler_ = std::make_unique<couple::Coupler>(
      *m.fem_partition_, *m.dem_partition_, coupling_links(ov, particle_id, dim), m.eta, m.execution_mode);
  // The limits, with the externals of each side held: the DEM step from the particles, the
  // FEM step η·dt from the FEM integrator (central difference while it is stable, implicit
  // Newmark above its limit, unless fem_integrator says otherwise).
  m.fem_partition_->prepare();
  m.dem_partition_->prepare();
  dem::Simulation& s = m.sim();
  fem::Solver& f = m.fem();
  m.dt_crit = s.critical_dt();
  m.fem_explicit_dt_crit = f.stability().explicit_dt_crit;
  m.dt_automatic = solver.dt == 0.0;
  const double eta = double(m.eta);
  double dt = solver.dt;
  if (m.dt_automatic) {
    dt = solver.dt_safety * m.dt_crit;
    if (solver.fem_integrator.value != "auto" &&
        fem::is_explicit(fem::scheme_from_string(solver.fem_integrator.value)))
      dt = std::min(dt, solver.dt_safety * m.fem_explicit_dt_crit / eta);
  }
  if (dt > m.dt_crit && !ds.allow_unstable) {
    const auto [dt_text, crit_text] = distinct_pair(dt, m.dt_crit);
    solver.dt.fail(
        fmt::format("dt = {} s exceeds the critical time step {} s of the particles (the "
                    "overlap's external particles held; dt/dt_crit = {}); the run would blow up. "
                    "Allowed: dt <= {:.4g} s, or dt = 0 for {} x dt_crit; solver.allow_unstable = "
                    "true or --force runs anyway",
                    dt_text, crit_text, ratio_text(dt, m.dt_crit), m.dt_crit, solver.dt_safety.value));
  }
  // The exchange itself: copies η·dt apart drive the particles' side like a step of η·dt.
  // Measured on the tunnel example (interpolated overlap): stable at η·dt = 0.6·dt_crit, growing
  // without bound at 0.9 and above; strata refuses more than kExchangeLimit·dt_crit.
  constexpr double kExchangeLimit = 0.65;
  if (eta * dt > kExchangeLimit * m.dt_crit && !ds.allow_unstable)
    solver.eta.fail(
        fmt::format("the exchange interval eta x dt = {} x {:.4g} s = {:.4g} s exceeds {} x the "
                    "particles' critical step {:.4g} s: the coupled exchange grows unstable there. "
                    "Allowed: eta <= {}",
                    m.eta, dt, eta * dt, kExchangeLimit, m.dt_crit,
                    std::max(1, int(std::floor(kExchangeLimit * m.dt_crit / dt)))));
  f.set_scheme(scheme_of(solver, eta * dt, m.fem_explicit_dt_crit));
  f.set_dt(eta * dt);
  m.fem_dt_crit = f.stability().dt_crit;
  if (eta * dt > m.fem_dt_crit && !ds.allow_unstable)
    solver.eta.fail(
        fmt::format("the FEM step eta x dt = {} x {:.4g} s = {:.4g} s exceeds the limit {:.4g} s of "
                    "the {} integrator (the overlap's external nodes held); allowed: eta <= {}, or "
                    "fem_integrator = \"implicit-newmark\" (or \"auto\", which takes it above the "
                    "explicit limit)",
                    m.eta, dt, eta * dt, m.fem_dt_crit, fem::to_string(f.settings().scheme),
                    std::max(1, int(std::floor(m.fem_dt_crit / dt)))));
  s.set_dt(dt);
  m.coupler_->initialise(ds.allow_unstable);
  m.dt = dt;
  m.steps = step_count_of(solver, m.dt, m.eta);
  return m;
}
}  // namespace

fem::Scheme scheme_of(const SolverTable& solver, double dt_fem, double explicit_limit) {
  const std::string& s = solver.fem_integrator;
  if (s != "auto") return fem::scheme_from_string(s);
  return dt_fem <= explicit_limit ? fem::Scheme::CentralDifference : fem::Scheme::ImplicitNewmark;
}

BuiltModel build_fem_model(const Scene& sc, bool force) {
  bool any_particles = false;
  for (const auto& r : sc.regions) any_particles |= r.kind == RegionKind::Particles;
  if (!any_particles) return build_fem_only(sc, force);
  return build_coupled(sc, force);
}

}  // namespace strata::scene
