#include <strata/scene/model.hpp>

#include "model_parts.hpp"

#include <strata/core/clock.hpp>
#include <strata/core/error.hpp>
#include <strata/core/log.hpp>
#include <strata/core/numbers.hpp>
#include <strata/core/parallel.hpp>
#include <strata/preprocess/ecc.hpp>
#include <strata/preprocess/fill.hpp>
#include <strata/preprocess/geometry.hpp>
#include <strata/preprocess/mesh_fill.hpp>
#include <strata/preprocess/overlap.hpp>

#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <random>
#include <set>

namespace strata::scene {
namespace {

using preprocess::Lattice;
using preprocess::Shape;

Shape shape_of(const RegionTable& r, int dim) {
  Shape s;
  s.dim = dim;
  const RegionShape kind = r.shape;
  if (kind == RegionShape::Box) {
    s.kind = Shape::Kind::Box;
    s.origin = vec3(r.origin);
    s.size = vec3(r.size);
  } else if (kind == RegionShape::Disk || kind == RegionShape::Sphere) {
    s.kind = kind == RegionShape::Disk ? Shape::Kind::Disk : Shape::Kind::Sphere;
    s.center = vec3(r.center);
    s.radius = r.radius;
  } else if (kind == RegionShape::Cylinder) {  // a disk extruded along z
    s.kind = Shape::Kind::Disk;
    s.center = vec3(r.center);
    s.radius = r.radius;
    s.z_min = s.center[2] - 0.5 * r.height;
    s.z_max = s.center[2] + 0.5 * r.height;
  } else if (kind == RegionShape::Polygon) {
    s.kind = Shape::Kind::Polygon;
    for (const auto& p : r.points.value) s.polygon.push_back({p[0], p[1]});
  }
  return s;  // shape = "file" regions are filled from their geometry (fill_file_region)
}

preprocess::LatticeKind lattice_of(const RegionTable& r, int dim, std::string& name) {
  name = r.lattice;
  if (name == "auto") name = dim == 2 ? "hex" : "hcp";
  return name == "hex"   ? preprocess::LatticeKind::Hex2D
         : name == "hcp" ? preprocess::LatticeKind::HCP
                         : preprocess::LatticeKind::FCC;
}

/// A filled region: its lattice and, for geometry files, what group selections need.
struct Filled {
  Lattice shape_lattice;  ///< primitive shapes
  std::uint32_t first_id = 0;
  std::shared_ptr<const preprocess::Geometry> geometry;  ///< shape = "file" only
  std::optional<preprocess::GeometryRegion> region;
  std::optional<preprocess::RegionFill> fill;  ///< shape = "file": the lattice and its entity ranges
  const Lattice& lattice() const { return fill ? fill->lattice : shape_lattice; }
  Lattice& lattice() { return fill ? fill->lattice : shape_lattice; }
};

/// Refuses, at the region's diameter, a region whose particles cannot fit on this machine
/// (preprocess::check_sites_fit); `total` adds up the regions so far. Large fills say so
/// before they start.
void check_fits(const RegionTable& r, int dim, double measure, double& total, bool shear) {
  const double n = preprocess::sites_in(measure, r.diameter, dim);
  total += n;
  r.diameter.blame([&] {
    preprocess::check_sites_fit(
        total, dim,
        fmt::format("region '{}' with particles of diameter {} m (and the regions before it)", r.name.value,
                    r.diameter.value),
        shear);
  });
  if (n > 2e6) log::info("region '{}': filling about {:.3g} particles", r.name.value, n);
}

/// The geometry of a shape = "file" region and its region in it: a file is read once per
/// path, mesh size and unit (`cache`); errors point at the `file` and `physical` keys.
void with_geometry(Filled& f, const RegionTable& r, const preprocess::GeometryOptions& go,
                   std::map<std::string, std::shared_ptr<const preprocess::Geometry>>& cache) {
  const std::string file = r.file->string();
  auto& geo = cache[fmt::format("{}#{}#{}", file, go.mesh_size, go.unit)];
  if (!geo)
    geo = r.file.blame(
        [&] { return std::make_shared<const preprocess::Geometry>(preprocess::read_geometry(file, go)); });
  f.geometry = geo;
  f.region = r.physical.blame([&] { return geo->region(r.physical); });
}

/// Fills a shape = "file" region.
Filled fill_file_region(const RegionTable& r, int dim, preprocess::LatticeKind kind, double d, double& total,
                        bool shear,
                        std::map<std::string, std::shared_ptr<const preprocess::Geometry>>& cache) {
  // mesh_size: the largest element of the geometry mesh the inside tests use (0: the file's
  // own sizes); curved CAD surfaces need it near the particle size to be filled to their volume.
  preprocess::GeometryOptions go;
  go.dim = dim;
  go.mesh_size = r.mesh_size;
  go.unit = metres(r.unit);
  Filled f;
  with_geometry(f, r, go, cache);
  const auto& geo = f.geometry;
  preprocess::FillOptions fo;
  fo.kind = kind;
  fo.d = d;
  fo.orientation_deg = r.orientation;
  fo.min_boundary_distance = r.min_boundary_distance;
  // One lattice origin per geometry (its lower corner + d/2), so neighbouring regions of a
  // file share one lattice and never overlap.
  if (geo->mesh.node_count() > 0) {
    const preprocess::Bounds b = geo->mesh.bounds();
    fo.origin = preprocess::Vec3{b.lo[0] + d / 2, b.lo[1] + d / 2, dim == 3 ? b.lo[2] + d / 2 : 0.0};
  }
  check_fits(r, dim, f.region->measure(), total, shear);
  f.fill = r.diameter.blame([&] { return preprocess::fill_region(*f.region, fo); });
  return f;
}

/// A particle region of a coupled model: its sites as the overlap made them (those of
/// particle_region k, in order), and the geometry region for group selections.
Filled coupled_region(const RegionTable& r, const preprocess::OverlapModel& ov, int dim,
                      std::map<std::string, std::shared_ptr<const preprocess::Geometry>>& cache) {
  const auto& names = ov.particle_region_names;
  const auto k = std::find(names.begin(), names.end(), r.physical.value) - names.begin();
  Filled f;
  Lattice& l = f.shape_lattice;
  l.dim = ov.particles.dim;
  l.radius = ov.particles.radius;
  const bool rows = !ov.particles.row.empty();
  for (std::size_t i = 0; i < ov.particles.size(); ++i) {
    if (ov.particle_region[i] != k) continue;
    l.x.push_back(ov.particles.x[i]);
    if (rows) {
      l.row.push_back(ov.particles.row[i]);
      l.layer.push_back(ov.particles.layer[i]);
    }
  }
  preprocess::GeometryOptions go;
  go.dim = dim;
  with_geometry(f, r, go, cache);
  return f;
}

/// The overlap band of a coupled model (the DEM external particles, inside the FEM regions):
/// a region and group of its own, "overlap", of the first particle region's material and
/// lattice.
void add_overlap_band(const Scene& sc, const preprocess::OverlapModel& ov, ModelDescription& d,
                      std::vector<Filled>& filled, std::uint32_t& next_id) {
  Filled f;
  Lattice& l = f.shape_lattice;
  l.dim = ov.particles.dim;
  l.radius = ov.particles.radius;
  for (std::size_t i = 0; i < ov.particles.size(); ++i)
    if (ov.particle_region[i] < 0) l.x.push_back(ov.particles.x[i]);
  const RegionTable* first = nullptr;
  for (const auto& r : sc.regions)
    if (r.kind == RegionKind::Particles && !first) first = &r;
  RegionInfo info;
  info.name = "overlap";
  info.lattice = d.regions.front().lattice;
  info.diameter = d.regions.front().diameter;
  info.particles = l.size();
  info.material = first->material;
  RegionSites s;
  s.first_id = next_id;
  s.material = first->material;
  f.first_id = next_id;
  next_id += std::uint32_t(l.size());
  d.groups.push_back({info.name, info.particles, {}, int(d.regions.size())});
  d.regions.push_back(info);
  d.sites.push_back(std::move(s));
  filled.push_back(std::move(f));
  // Overlap particle index -> particle id: regions in scene order, then the band.
  std::vector<std::size_t> seen(ov.particle_region_names.size() + 1, 0);
  d.overlap_particle_id.resize(ov.particles.size());
  std::vector<std::uint32_t> region_first(ov.particle_region_names.size());
  for (std::size_t k = 0; k + 1 < d.regions.size(); ++k) {
    const auto& names = ov.particle_region_names;
    for (const auto& r : sc.regions)
      if (r.name == d.regions[k].name) {
        const auto j = std::size_t(std::find(names.begin(), names.end(), r.physical.value) - names.begin());
        region_first[j] = d.sites[k].first_id;
      }
  }
  for (std::size_t i = 0; i < ov.particles.size(); ++i) {
    const std::int32_t k = ov.particle_region[i];
    const std::size_t slot = k < 0 ? seen.size() - 1 : std::size_t(k);
    const std::uint32_t base = k < 0 ? d.sites.back().first_id : region_first[std::size_t(k)];
    d.overlap_particle_id[i] = base + std::uint32_t(seen[slot]++);
  }
}

std::vector<std::uint32_t> select(const GroupTable& g, const Filled& f) {
  const Lattice& l = f.lattice();
  switch (g.select.value) {
    case GroupSelect::Physical:
    case GroupSelect::HoleRim: {
      if (!f.geometry)
        g.select.fail(
            fmt::format("select = \"{}\" picks from a region read from a geometry file "
                        "(shape = \"file\"); name such a region in 'region'",
                        to_string(g.select)));
      const double w = g.width > 0 ? g.width : 2 * l.radius;
      if (g.select == GroupSelect::Physical)
        return g.physical.blame(
            [&] { return preprocess::physical_group_members(*f.geometry, *f.fill, g.physical, w); });
      return g.hole.blame([&] { return preprocess::hole_rim(*f.region, l, int(g.hole), w); });
    }
    case GroupSelect::All: {
      std::vector<std::uint32_t> all(l.size());
      for (std::size_t i = 0; i < l.size(); ++i) all[i] = std::uint32_t(i);
      return all;
    }
    case GroupSelect::TopRow:
      return preprocess::top_row(l);
    case GroupSelect::BottomRow:
      return preprocess::bottom_row(l);
    case GroupSelect::TopLayer:
      return preprocess::top_layer(l);
    case GroupSelect::BottomLayer:
      return preprocess::bottom_layer(l);
    case GroupSelect::LeftColumn:
      return preprocess::left_column(l);
    case GroupSelect::RightColumn:
      return preprocess::right_column(l);
    case GroupSelect::Box:
      break;
  }
  return preprocess::in_box(l, vec3(g.box_min), vec3(g.box_max));
}

/// The particles' current positions, indexed by particle id.
std::vector<std::array<double, 3>> positions_by_id(const dem::Simulation& sim) {
  const auto pos = sim.positions();
  const auto ids = sim.ids();
  std::vector<std::array<double, 3>> out(pos.size());
  for (std::size_t i = 0; i < ids.size(); ++i) out[ids[i]] = pos[i];
  return out;
}

/// Mean coordinate `axis` of the particles with these ids.
double mean_along(const std::vector<std::array<double, 3>>& by_id, const std::vector<std::uint32_t>& ids,
                  int axis) {
  double sum = 0;
  for (auto id : ids) sum += by_id[id][axis];
  return sum / double(ids.size());
}

/// Distance between the outer faces of the two platen groups along the probe axis.
double platen_distance(const BuiltModel& m, const std::vector<std::array<double, 3>>& by_id) {
  const PlatenProbe& p = m.platens;
  return mean_along(by_id, m.sim().group_members(p.top), p.axis) -
         mean_along(by_id, m.sim().group_members(p.bottom), p.axis) + 2 * p.radius;
}

/// Drops a lattice's rows and layers (the groups are selected): the sites keep positions only.
void drop_rows(Lattice& l) {
  std::vector<std::int32_t>().swap(l.row);
  std::vector<std::int32_t>().swap(l.layer);
}

/// FEM mesh of a kind = "fem" region: the geometry file's physical group, or the shape.
preprocess::SimplexMesh mesh_fem(const RegionTable& r, int dim) {
  const double size = r.mesh_size;
  if (r.shape == RegionShape::File) {
    preprocess::FemMeshOptions o;
    o.size = size;
    o.unit = metres(r.unit);
    return preprocess::mesh_fem_region(r.file->string(), r.physical, dim, o);
  }
  return preprocess::mesh_fem_shape(shape_of(r, dim), size);
}
}  // namespace

std::size_t ModelDescription::particle_count() const {
  std::size_t n = 0;
  for (const auto& s : sites) n += s.sites.size();
  return n;
}
std::size_t ModelDescription::fem_nodes() const {
  std::size_t n = 0;
  for (const auto& f : fem) n += f.mesh.node_count();
  return n;
}
std::size_t ModelDescription::fem_elements() const {
  std::size_t n = 0;
  for (const auto& f : fem) n += f.mesh.cell_count();
  return n;
}
std::vector<const Lattice*> ModelDescription::lattices() const {
  std::vector<const Lattice*> out;
  for (const auto& s : sites) out.push_back(&s.sites);
  return out;
}

ModelDescription describe_model(const scene::Scene& sc, bool allow_fem,
                                const preprocess::OverlapModel* coupled) {
  const auto t0 = WallClock::now();
  const SceneTable& st = sc.scene;
  const int dim = st.dimension;
  ModelDescription d;
  d.dim = dim;

  // Regions: fill each shape with its lattice; keep each region's regular lattice (rows,
  // layers) until the groups are selected from it.
  std::vector<Filled> filled;
  std::map<std::string, std::size_t> region_index;  // groups visit regions by name
  std::map<std::string, std::shared_ptr<const preprocess::Geometry>> geometries;
  std::uint32_t next_id = 0;
  double estimated = 0;  // particles of the regions so far, estimated before each fill
  // without shear springs in any material the model keeps no shear history (less memory)
  bool shear = false;
  for (const auto& m : sc.materials) shear |= m.ks > 0;
  for (const auto& r : sc.regions) {
    if (r.kind == RegionKind::Fem) {
      if (!allow_fem)
        r.kind.fail(
            fmt::format("region '{}': kind = \"fem\" cannot be run or checked in this version of "
                        "strata (allowed here: kind = \"particles\"); 'strata mesh' meshes FEM "
                        "regions for inspection, and coupled FEM-DEM runs go through a [coupled] "
                        "scene or 'strata report wave'",
                        r.name.value));
      // A coupled model's FEM mesh is the overlap's (FEM regions and the overlap ring).
      if (!coupled)
        d.fem.push_back(FemRegion{r.name, r.material,
                                  blame_at(r.shape == RegionShape::File ? r.file.pos : r.mesh_size.pos,
                                           [&] { return mesh_fem(r, dim); })});
      continue;
    }
    RegionInfo info;
    info.name = r.name;
    info.material = r.material;
    const Shape shape = shape_of(r, dim);
    const auto kind = lattice_of(r, dim, info.lattice);
    info.diameter = r.diameter;
    Filled f;
    if (coupled) {
      // The coupled model's particles of this region, in the order the overlap made them.
      f = coupled_region(r, *coupled, dim, geometries);
      info.measure = f.region->mesh.measure();
    } else if (r.shape == RegionShape::File) {
      f = fill_file_region(r, dim, kind, info.diameter, estimated, shear, geometries);
      info.measure = f.fill->measure;
    } else {
      check_fits(r, dim, shape.measure(), estimated, shear);
      f.shape_lattice =
          r.diameter.blame([&] { return preprocess::fill_shape(shape, kind, info.diameter, r.orientation); });
      info.measure = shape.measure();
    }
    if (f.lattice().size() == 0)
      r.diameter.fail(
          fmt::format("region '{}' holds no particle of diameter {} m: the shape is smaller "
                      "than one particle",
                      info.name, info.diameter));
    f.first_id = next_id;
    next_id += std::uint32_t(f.lattice().size());
    RegionSites s;
    s.first_id = f.first_id;
    s.material = r.material;
    // Bonds: the touching pairs of the regular lattice, region by region when any region is
    // eccentric (ECC4D of Zhao et al. 2021: centroids offset, bonds kept, long ones weakened by γ);
    // otherwise all touching pairs of the model (bonds_across_regions).
    if (r.eccentricity != RegionEccentricity::None) {
      preprocess::EccOptions o;
      o.type = r.eccentricity == RegionEccentricity::Cube ? preprocess::Eccentricity::Cube
                                                          : preprocess::Eccentricity::Sphere;
      o.ra = r.ra;
      o.rc = r.rc;
      o.gamma = r.gamma;
      o.seed = std::uint64_t(st.seed.value) + d.regions.size();  // one stream per region
      preprocess::EccLattice e = preprocess::make_eccentric(f.lattice(), o);
      s.eccentric = info.eccentric = true;
      info.bonds = e.bonds.size();
      info.weakened_bonds = e.bonds.weakened();
      info.longest_bond = e.bonds.max_length;
      s.sites = std::move(e.lattice);
      s.bonds = std::move(e.bonds);
      d.bonds_across_regions = false;
    }
    if (r.strength_spread != StrengthSpread::None) {
      s.strength_spread = r.strength_spread;
      s.strength_cov = r.strength_cov;
      // its own stream: the seed, the region's index and a tag apart from the offsets'
      s.strength_seed = (std::uint64_t(st.seed.value) << 20) ^ (d.regions.size() << 4) ^ 0x5u;
      d.bonds_across_regions = false;  // each region bonded within itself, factors per bond
    }
    info.particles = f.lattice().size();
    const double rad = info.diameter / 2;
    const double one = dim == 2 ? M_PI * rad * rad : 4.0 / 3.0 * M_PI * rad * rad * rad;
    info.packing = double(info.particles) * one / info.measure;
    // Every region is also a group of its own name.
    d.groups.push_back({info.name, info.particles, {}, int(d.regions.size())});
    region_index[info.name] = d.regions.size();
    d.regions.push_back(info);
    d.sites.push_back(std::move(s));
    filled.push_back(std::move(f));
  }

  if (coupled) add_overlap_band(sc, *coupled, d, filled, next_id);

  std::set<std::string> fem_regions;
  for (const auto& r : sc.regions)
    if (r.kind == RegionKind::Fem) fem_regions.insert(r.name);
  for (const auto& g : sc.groups) {
    std::vector<std::uint32_t> ids;
    const std::string& region = g.region;
    if (fem_regions.count(region)) continue;  // FEM nodes (fem_model.cpp)
    for (const auto& [name, k] : region_index) {
      if (!region.empty() && name != region) continue;
      const Filled& f = filled[k];
      for (std::uint32_t i : select(g, f)) ids.push_back(f.first_id + i);
    }
    // A group over every region may hold FEM nodes only (fem_model.cpp checks it is not empty).
    if (ids.empty() && fem_regions.empty())
      g.select.fail(fmt::format("group '{}' selects no particle", g.name.value));
    const std::size_t n = ids.size();
    d.groups.push_back({g.name, n, std::move(ids), -1});
  }

  // The regular lattices become the model's sites (moved, not copied); eccentric regions
  // hold theirs already.
  for (std::size_t k = 0; k < filled.size(); ++k) {
    if (!d.sites[k].eccentric) d.sites[k].sites = std::move(filled[k].lattice());
    drop_rows(d.sites[k].sites);
  }
  d.seconds = seconds_since(t0);
  return d;
}

preprocess::PairCounts count_bonds(const ModelDescription& d) {
  const double d_ref = d.regions.empty() ? 1.0 : d.regions.front().diameter;
  if (d.bonds_across_regions) return preprocess::count_touching_pairs(d.lattices(), d_ref);
  preprocess::PairCounts total;
  total.d_ref = d_ref;
  total.width = 0.02;
  auto add = [&](std::size_t k, std::size_t n) {
    if (total.by_class.size() <= k) total.by_class.resize(k + 1, 0);
    total.by_class[k] += n;
    total.pairs += n;
  };
  for (const auto& s : d.sites) {
    if (s.eccentric) {
      const double unit = 1 / (d_ref * total.width);
      for (double len : s.bonds.length) add(std::size_t(len * unit + 0.5), 1);  // as count_touching_pairs
    } else {
      const auto c = preprocess::count_touching_pairs({&s.sites}, d_ref, 1e-6, total.width);
      for (std::size_t k = 0; k < c.by_class.size(); ++k)
        if (c.by_class[k] > 0) add(k, c.by_class[k]);
    }
  }
  return total;
}

std::vector<std::uint32_t> surface_particles(const ModelDescription& d) {
  const int full = d.dim == 2 ? 6 : 12;  // coordination of the hex / close-packed lattice
  if (d.bonds_across_regions) return preprocess::undercoordinated_sites(d.lattices(), full);
  std::vector<std::uint32_t> out;
  for (const auto& s : d.sites) {
    if (s.eccentric) {
      std::vector<int> count(s.sites.size(), 0);
      for (std::size_t b = 0; b < s.bonds.size(); ++b) ++count[s.bonds.i[b]], ++count[s.bonds.j[b]];
      for (std::size_t i = 0; i < count.size(); ++i)
        if (count[i] < full) out.push_back(s.first_id + std::uint32_t(i));
    } else {
      for (std::uint32_t i : preprocess::undercoordinated_sites({&s.sites}, full))
        out.push_back(s.first_id + i);
    }
  }
  return out;
}

dem::Settings dem_settings(const Scene& sc, bool force) {
  const SolverTable& solver = sc.solver;
  dem::Settings set;
  set.dt = solver.dt;
  // dt is checked against the model's dt_crit once it is built, so a refusal points at the scene.
  set.allow_unstable = force || solver.allow_unstable;
  set.damping = solver.damping == SolverDamping::Viscous ? dem::Settings::Damping::Viscous
                : solver.damping == SolverDamping::Local ? dem::Settings::Damping::Local
                                                         : dem::Settings::Damping::None;
  set.viscous_c = solver.viscous_c;
  set.local_alpha = solver.local_damping;
  set.gravity = vec3(solver.gravity);
  set.min_particles_per_thread = int(solver.min_particles_per_thread);
  set.lattice_slots = solver.lattice_slots;
  // Contact search only where new contacts can form: between particles whose bonds can
  // break, between regions, or against walls. "on"/"off" override.
  bool breakable = false;
  for (const auto& t : sc.materials)
    breakable |= std::isfinite(t.tensile_strength.value) || std::isfinite(t.shear_strength.value);
  // Eccentric lattices: "auto" leaves the search off, since offset centroids can overlap
  // unbonded neighbours at the start (broken bonds still push back and slide).
  bool eccentric = false;
  std::size_t particle_regions = 0;
  for (const auto& t : sc.regions) {
    eccentric |= t.eccentricity != RegionEccentricity::None;
    particle_regions += t.kind == RegionKind::Particles;
  }
  const ContactDetection cd = solver.contact_detection;
  set.contact_detection =
      cd == ContactDetection::On || (cd == ContactDetection::Auto && !eccentric &&
                                     (breakable || particle_regions > 1 || !sc.walls.empty()));
  return set;
}

void populate_particles(const Scene& sc, ModelDescription& d, dem::Simulation& sim, BuiltModel& m) {
  const int dim = m.dim;
  std::map<std::string, int> material_id;
  double max_kn = 0;
  for (const auto& t : sc.materials) {
    dem::Material mat;
    mat.density = t.density;
    mat.kn = t.kn;
    mat.ks = t.ks;
    mat.friction = t.friction;
    mat.tensile_strength = t.tensile_strength;
    mat.shear_strength = t.shear_strength;
    mat.friction_strengthens_bonds = t.friction_strengthens_bonds;
    mat.law = t.law;
    max_kn = std::max(max_kn, mat.kn);
    material_id[t.name] = sim.add_material(mat);
  }

  // The particles, groups and bonds of the filled regions.
  log::Phases ph("scene set-up");  // strata -v: each part's time and memory
  m.regions = d.regions;
  sim.reserve(d.particle_count());
  for (std::size_t k = 0; k < d.sites.size(); ++k) {
    const int mat = material_id.at(d.sites[k].material);
    const double rad = d.regions[k].diameter / 2;
    // a mass that underflows (density 1e-320, say) is the density's fault
    const auto& table = *std::find_if(sc.materials.begin(), sc.materials.end(),
                                      [&](const MaterialTable& t) { return t.name == d.sites[k].material; });
    table.density.blame([&] { sim.add_particles(d.sites[k].sites.x, rad, mat); });
  }
  ph.lap("particles added");
  for (const auto& g : d.groups) {
    if (g.count == 0) continue;  // a group of FEM nodes only
    if (g.region >= 0) {         // a region's own group: its ids [first_id, first_id + count)
      const RegionSites& s = d.sites[std::size_t(g.region)];
      std::vector<std::uint32_t> ids;
      par::resize_paged(ids, g.count);  // (first writes on all threads: par::page_in)
      std::iota(ids.begin(), ids.end(), s.first_id);
      sim.add_to_group(ids, g.name);
    } else {
      sim.add_to_group(g.ids, g.name);
    }
    m.groups[g.name] = g.count;
  }
  ph.lap("groups");

  if (d.bonds_across_regions) {
    sim.bond_touching_pairs();
  } else {
    // eccentric regions present: bonds as data, each region bonded within itself
    std::vector<std::uint32_t> bi, bj;
    std::vector<double> factor, strength;
    for (auto& s : d.sites) {
      if (!s.eccentric) s.bonds = preprocess::touching_pairs(s.sites);
      const auto& b = s.bonds;
      for (std::size_t q = 0; q < b.size(); ++q) {
        bi.push_back(s.first_id + b.i[q]);
        bj.push_back(s.first_id + b.j[q]);
        factor.push_back(b.stiffness_factor[q]);
      }
      if (s.strength_spread == StrengthSpread::None) {
        strength.insert(strength.end(), b.size(), 1.0);
      } else {
        const auto f = strength_factors(s.strength_spread, s.strength_cov, b.size(), s.strength_seed);
        strength.insert(strength.end(), f.begin(), f.end());
      }
    }
    sim.set_bonds(bi, bj, factor, strength);
  }
  ph.lap("bonds");

  for (const auto& b : sc.boundaries) {
    const std::string& group = b.group;
    if (!m.groups.count(group)) continue;  // FEM nodes only (fem_model.cpp)
    const unsigned axes = axes_mask(b.axes, dim);
    if (b.type == BoundaryType::Fixed) {
      sim.fix(group, axes);
    } else if (b.type == BoundaryType::Velocity) {
      sim.prescribe_velocity(group, vec3(b.velocity), axes);
    } else {
      auto inc = vec3(b.increment);
      for (int a = 0; a < 3; ++a)
        if (!(axes >> a & 1u)) inc[a] = 0;
      sim.step_displacement(group, inc, b.every, axes);  // named axes held, zero increment or not
    }
  }
  for (const auto& l : sc.loads) {
    if (!m.groups.count(l.group)) continue;  // FEM nodes only (fem_model.cpp)
    if (l.per == LoadPer::Boundary)
      l.per.fail(
          fmt::format("group '{}' holds particles: per = \"boundary\" spreads a traction over the "
                      "boundary of FEM nodes (allowed for particles: \"particle\" or \"group\")",
                      l.group.value));
    const double sharers = l.per == LoadPer::Group ? double(m.groups.at(l.group)) : 1.0;
    if (l.type == LoadType::Radial) {
      std::vector<double> magnitudes = l.magnitudes;
      for (double& f : magnitudes) f /= sharers;
      std::array<double, 3> centre = vec3(l.center);
      if (l.center->empty()) {  // the group's mean position
        const auto by_id = positions_by_id(sim);
        const auto members = sim.group_members(l.group);
        centre = {0, 0, 0};
        for (const auto id : members)
          for (int a = 0; a < 3; ++a) centre[a] += by_id[id][a] / double(members.size());
      }
      sim.radial_force_history(l.group, l.times, std::move(magnitudes), centre, vec3(l.axis), l.ramp);
      continue;
    }
    std::vector<std::array<double, 3>> forces;
    for (const auto& row : l.forces.value) forces.push_back(vec3(row));
    for (auto& f : forces)
      for (double& c : f) c /= sharers;
    sim.force_history(l.group, l.times, std::move(forces), l.ramp);
  }
  for (const auto& w : sc.walls) {
    const double k = w.stiffness > 0 ? w.stiffness : max_kn;
    auto n = vec3(w.normal);
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);  // > 0: checked by the loader
    for (double& c : n) c /= len;
    sim.add_wall(vec3(w.point), n, vec3(w.velocity), k);
  }
}

std::vector<double> strength_factors(StrengthSpread spread, double cov, std::size_t count,
                                     std::uint64_t seed) {
  std::vector<double> out(count, 1.0);
  if (spread == StrengthSpread::None || count == 0) return out;
  STRATA_CHECK(cov > 0 && cov <= 1, Input, "strength_cov = {} must be in (0, 1]", cov);
  std::mt19937_64 rng(seed);
  if (spread == StrengthSpread::Normal) {
    std::normal_distribution<double> normal(1.0, cov);
    for (double& f : out) do
        f = normal(rng);
      while (f < 1e-3);  // no bond without strength
    return out;
  }
  // Weibull: the modulus k whose coefficient of variation √(Γ(1+2/k)/Γ(1+1/k)² − 1) is cov
  // (it falls as k grows), and the scale that makes the mean 1
  auto cov_of = [](double k) {
    const double g1 = std::tgamma(1 + 1 / k);
    return std::sqrt(std::tgamma(1 + 2 / k) / (g1 * g1) - 1);
  };
  double lo = 0.2, hi = 1e3;
  for (int it = 0; it < 200; ++it) {
    const double mid = std::sqrt(lo * hi);
    (cov_of(mid) > cov ? lo : hi) = mid;
  }
  const double k = std::sqrt(lo * hi);
  std::weibull_distribution<double> weibull(k, 1 / std::tgamma(1 + 1 / k));
  for (double& f : out) do
      f = weibull(rng);
    while (f < 1e-3);
  return out;
}

std::int64_t steps_in(double seconds, double dt) { return std::int64_t(std::ceil(seconds / dt - 1e-9)); }

std::int64_t step_count_of(const SolverTable& solver, double dt, int quantum) {
  const std::int64_t given = solver.steps;
  std::int64_t steps = given > 0 ? given : steps_in(solver.duration, dt);
  return (steps + quantum - 1) / quantum * quantum;  // whole system steps
}

void setup_platens(const Scene& sc, BuiltModel& m) {
  const ProbeTable& probe = sc.probe;
  if (!probe.stress_strain) return;
  const int dim = m.dim;
  const dem::Simulation& sim = m.sim();
  // Platen probe geometry: platens' outer faces and the loaded width.
  PlatenProbe& p = m.platens;
  p.enabled = true;
  p.top = probe.top_group;
  p.bottom = probe.bottom_group;
  p.axis = axis_index(probe.axis);
  const auto pos = sim.positions();
  const auto rad = sim.radii();
  std::array<double, 3> lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (std::size_t i = 0; i < pos.size(); ++i)
    for (int a = 0; a < dim; ++a)
      lo[a] = std::min(lo[a], pos[i][a] - rad[i]), hi[a] = std::max(hi[a], pos[i][a] + rad[i]);
  p.area = 1;
  for (int a = 0; a < dim; ++a)
    if (a != p.axis) p.area *= hi[a] - lo[a];
  if (dim == 2) p.area *= sc.scene.thickness;
  p.radius = rad.empty() ? 0 : rad[0];
  p.length0 = platen_distance(m, positions_by_id(sim));
  // the free sides: centres within 0.75 d of the outermost column's (a hexagonal lattice's
  // shorter rows start half a diameter in), platen rows left out
  const auto ids = sim.ids();
  std::vector<char> platen(ids.size(), 0);
  for (const auto& g : {p.top, p.bottom})
    for (auto id : sim.group_members(g)) platen[id] = 1;
  for (int a = 0; a < dim; ++a) {
    if (a == p.axis) continue;
    PlatenProbe::Sides s;
    s.axis = a;
    double low_sum = 0, high_sum = 0;
    for (std::size_t i = 0; i < pos.size(); ++i) {
      if (platen[ids[i]]) continue;
      const double band = 1.5 * rad[i];
      if (pos[i][a] - rad[i] <= lo[a] + band) s.low.push_back(ids[i]), low_sum += pos[i][a];
      if (pos[i][a] + rad[i] >= hi[a] - band) s.high.push_back(ids[i]), high_sum += pos[i][a];
    }
    if (s.low.empty() || s.high.empty()) continue;
    s.width0 = high_sum / double(s.high.size()) - low_sum / double(s.low.size());
    if (s.width0 > 0) p.sides.push_back(std::move(s));
  }
}

BuiltModel build_model(const Scene& sc, bool force) {
  STRATA_CHECK(!sc.calibrate, Input,
               "{}: a calibration ([calibrate]) builds its own specimens; run it with 'strata calibrate'",
               sc.file.string());
  require_build_parts(sc);  // `strata check` as `strata run`: a key this build cannot serve, at its line
  const auto t0 = WallClock::now();
  if (sc.network) {
    BuiltModel m = build_network_model(sc, force);
    m.build_seconds = seconds_since(t0);
    return m;
  }
  const SolverTable& solver = sc.solver;
  const int dim = sc.scene.dimension;
  bool any_fem = false;
  for (const auto& r : sc.regions) any_fem |= r.kind == RegionKind::Fem;
  if (any_fem) {
    if (solver.settle > 0)
      solver.settle.fail(
          "a settling stage is for models of particles only; this scene has FEM regions. Allowed: "
          "settle = 0 here, or settle the particles in a scene of their own");
    BuiltModel m = build_fem_model(sc, force);  // fem_model.cpp: FEM alone or coupled
    if (m.has_particles()) setup_platens(sc, m);
    m.build_seconds = seconds_since(t0);
    return m;
  }

  const dem::Settings set = dem_settings(sc, force);
  BuiltModel m;
  m.dim = dim;
  m.dem_ = std::make_unique<dem::Simulation>(dim, set);
  dem::Simulation& sim = *m.dem_;
  log::Phases ph("scene set-up");
  {
    ModelDescription d = describe_model(sc, /*allow_fem=*/false);
    ph.lap("regions filled, groups selected");
    populate_particles(sc, d, sim, m);
    ph.lap("particles, groups, bonds and loads");
  }  // the simulation holds the particles now

  // Time step: automatic (dt_safety × dt_crit) or checked against dt_crit. The model is
  // initialised with a tiny step, then given the real one.
  m.dt_automatic = solver.dt == 0.0;
  sim.set_dt(std::numeric_limits<double>::min());
  sim.initialise();
  ph.lap("model initialised");
  m.dt_crit = sim.critical_dt();
  if (!(m.dt_crit > 0 && std::isfinite(m.dt_crit)) && !sc.materials.empty()) {
    // Stiffnesses (or masses) out of any physical range: point at the stiffest spring.
    const MaterialTable* stiff = &sc.materials.front();
    for (const auto& t : sc.materials)
      if (std::max(t.kn.value, t.ks.value) > std::max(stiff->kn.value, stiff->ks.value)) stiff = &t;
    const Located<double>& k = stiff->ks.value > stiff->kn.value ? stiff->ks : stiff->kn;
    k.fail(
        fmt::format("the model's critical time step comes out as {} s: a stiffness of {} N/m with the "
                    "particle masses of this model is beyond what a time step can resolve; allowed: the "
                    "stiffnesses and densities of real materials",
                    m.dt_crit, k.value));
  }
  const double dt = m.dt_automatic ? solver.dt_safety * m.dt_crit : solver.dt;
  if (dt > m.dt_crit && !set.allow_unstable) {
    const auto [dt_text, crit_text] = distinct_pair(dt, m.dt_crit);
    solver.dt.fail(
        fmt::format("dt = {} s exceeds the critical time step {} s of this model "
                    "(dt/dt_crit = {}); the run would blow up. Allowed: dt <= {:.4g} s, or "
                    "dt = 0 for {} x dt_crit; solver.allow_unstable = true or --force runs anyway",
                    dt_text, crit_text, ratio_text(dt, m.dt_crit), m.dt_crit, solver.dt_safety.value));
  }
  sim.set_dt(dt);  // warns when above dt_crit and allowed
  m.dt = sim.dt();
  m.steps = step_count_of(solver, m.dt, 1);
  m.settle_steps = steps_in(solver.settle, m.dt);
  setup_platens(sc, m);
  m.build_seconds = seconds_since(t0);
  return m;
}

AxialState axial_state(const BuiltModel& m) {
  const PlatenProbe& p = m.platens;
  AxialState s;
  if (!p.enabled) return s;
  const auto by_id = positions_by_id(m.sim());
  s.strain = (p.length0 - platen_distance(m, by_id)) / p.length0;
  s.force_top = m.sim().group_force(p.top)[p.axis];
  s.force_bottom = m.sim().group_force(p.bottom)[p.axis];
  // Internal forces push the top platen up (+) and the bottom one down (-) in compression.
  s.stress = 0.5 * (s.force_top - s.force_bottom) / p.area;
  if (!p.sides.empty()) {
    for (const auto& side : p.sides)
      s.lateral_strain +=
          (mean_along(by_id, side.high, side.axis) - mean_along(by_id, side.low, side.axis) - side.width0) /
          side.width0;
    s.lateral_strain /= double(p.sides.size());
  }
  return s;
}

}  // namespace strata::scene
