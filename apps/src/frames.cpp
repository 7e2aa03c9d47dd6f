#include "frames.hpp"

#include <algorithm>
#include <cmath>

namespace strata::app {

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
}  // namespace

io::PointCloud particle_frame(const dem::Simulation& sim, const std::vector<std::string>& fields) {
  io::PointCloud pc;
  pc.dim = sim.dim();
  pc.time = sim.time();
  pc.step = sim.step_count();
  const auto pos = sim.positions();
  pc.xyz.reserve(pos.size() * 3);
  for (const auto& p : pos) pc.xyz.insert(pc.xyz.end(), p.begin(), p.end());

  const auto r = sim.radii();
  pc.point_data.push_back({std::string(io::kRadiusArray), 1, {r.begin(), r.end()}, io::ArrayType::Float64});
  if (wants(fields, "id")) {
    const auto ids = sim.ids();
    pc.point_data.push_back({"id", 1, {ids.begin(), ids.end()}, io::ArrayType::Int64});
  }
  if (wants(fields, "displacement"))
    pc.point_data.push_back(vector_array("displacement", sim.displacements()));
  if (wants(fields, "velocity")) pc.point_data.push_back(vector_array("velocity", sim.velocities()));
  if (wants(fields, "force")) {
    // Sum of the bond and contact forces on each particle, from the pairs' forces on their
    // first particle (an output-time gather; the step loop keeps no force array).
    io::Array f{"force", 3, std::vector<double>(pos.size() * 3, 0.0), io::ArrayType::Float64};
    auto add = [&](const std::vector<dem::PairView>& pairs) {
      for (const auto& p : pairs)
        for (int a = 0; a < 3; ++a) {
          f.values[p.i * 3 + a] += p.force_on_i[a];
          f.values[p.j * 3 + a] -= p.force_on_i[a];
        }
    };
    add(sim.bonds());
    add(sim.contacts());
    pc.point_data.push_back(std::move(f));
  }
  if (wants(fields, "group")) {
    const auto g = sim.group_bits();
    pc.point_data.push_back({"group", 1, {g.begin(), g.end()}, io::ArrayType::Int64});
  }
  if (wants(fields, "damage")) {
    const auto d = sim.damage();
    pc.point_data.push_back({"damage", 1, {d.begin(), d.end()}, io::ArrayType::Float32});
  }
  return pc;
}

void FrameSelection::find_surface(const dem::Simulation& sim) {
  const auto ids = sim.ids();
  std::vector<int> count(ids.size(), 0);
  for (const auto& b : sim.bonds()) ++count[ids[b.i]], ++count[ids[b.j]];
  const int inside = sim.dim() == 2 ? 6 : 12;  // coordination of the hex / close-packed lattice
  surface_by_id.assign(ids.size(), 0);
  for (std::size_t id = 0; id < count.size(); ++id) surface_by_id[id] = count[id] < inside;
}

io::PointCloud select_particles(const dem::Simulation& sim, const io::PointCloud& all,
                                const FrameSelection& sel) {
  if (sel.keeps_all()) return all;
  const auto ids = sim.ids();
  const auto groups = sim.group_bits();
  std::vector<std::size_t> keep;
  if (sel.particles != FrameSelection::Particles::None) {
    for (std::size_t i = 0; i < all.size(); ++i) {
      if (sel.particles == FrameSelection::Particles::Surface && !sel.surface_by_id[ids[i]]) continue;
      if (sel.group_mask != 0 && (groups[i] & sel.group_mask) == 0) continue;
      if (sel.slice_thickness > 0) {
        double dist = 0;
        for (int a = 0; a < 3; ++a) dist += (all.xyz[3 * i + a] - sel.slice_point[a]) * sel.slice_normal[a];
        if (std::abs(dist) > sel.slice_thickness / 2) continue;
      }
      keep.push_back(i);
    }
  }
  io::PointCloud out;
  out.dim = all.dim;
  out.time = all.time;
  out.step = all.step;
  out.xyz.reserve(keep.size() * 3);
  for (std::size_t i : keep) out.xyz.insert(out.xyz.end(), &all.xyz[3 * i], &all.xyz[3 * i] + 3);
  for (const auto& a : all.point_data) {
    io::Array b{a.name, a.components, {}, a.type};
    b.values.reserve(keep.size() * std::size_t(a.components));
    for (std::size_t i : keep)
      b.values.insert(b.values.end(), a.values.begin() + std::ptrdiff_t(i * a.components),
                      a.values.begin() + std::ptrdiff_t((i + 1) * a.components));
    out.point_data.push_back(std::move(b));
  }
  return out;
}

io::LineSet bond_frame(const dem::Simulation& sim, FrameSelection::Bonds which) {
  io::LineSet ls;
  io::Array state{std::string(io::kBondStateArray), 1, {}, io::ArrayType::UInt8};
  io::Array fn{"Fn", 1, {}, io::ArrayType::Float64}, fs{"Fs", 1, {}, io::ArrayType::Float64};
  if (which == FrameSelection::Bonds::None) return ls;
  for (const auto& b : sim.bonds()) {
    if (b.kind == dem::PairKind::Intact && which == FrameSelection::Bonds::Broken) continue;
    ls.ends.push_back(b.i);
    ls.ends.push_back(b.j);
    const io::BondState s = b.kind == dem::PairKind::Intact          ? io::BondState::Intact
                            : b.reclosed                             ? io::BondState::Closed
                            : b.kind == dem::PairKind::BrokenTension ? io::BondState::BrokenTension
                                                                     : io::BondState::BrokenShear;
    state.values.push_back(double(int(s)));
    fn.values.push_back(b.fn);
    fs.values.push_back(b.fs);
  }
  ls.cell_data = {std::move(state), std::move(fn), std::move(fs)};
  return ls;
}

io::RenderStyle field_style(const std::string& field) {
  io::RenderStyle style;
  style.field = field;
  if (field == "displacement") style.field_scale = 1e3, style.unit = "mm";
  if (field == "velocity") style.unit = "m/s";
  if (field == "damage") style.range = std::array<double, 2>{0.0, 1.0};
  return style;
}

}  // namespace strata::app
