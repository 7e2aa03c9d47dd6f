#include "frames.hpp"

#include <algorithm>

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

io::LineSet broken_bond_frame(const dem::Simulation& sim) {
  io::LineSet ls;
  io::Array state{std::string(io::kBondStateArray), 1, {}, io::ArrayType::UInt8};
  io::Array fn{"Fn", 1, {}, io::ArrayType::Float64}, fs{"Fs", 1, {}, io::ArrayType::Float64};
  for (const auto& b : sim.bonds()) {
    if (b.kind == dem::PairKind::Intact) continue;
    ls.ends.push_back(b.i);
    ls.ends.push_back(b.j);
    const io::BondState s = b.reclosed                               ? io::BondState::Closed
                            : b.kind == dem::PairKind::BrokenTension ? io::BondState::BrokenTension
                                                                     : io::BondState::BrokenShear;
    state.values.push_back(double(int(s)));
    fn.values.push_back(b.fn);
    fs.values.push_back(b.fs);
  }
  ls.cell_data = {std::move(state), std::move(fn), std::move(fs)};
  return ls;
}

}  // namespace strata::app
