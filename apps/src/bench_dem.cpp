// `strata bench dem`: see bench_dem.hpp.
#include "bench_dem.hpp"

#include <strata/core/error.hpp>
#include <strata/core/log.hpp>
#include <strata/core/parallel.hpp>
#include <strata/dem/simulation.hpp>
#include <strata/preprocess/lattice.hpp>

#include <fmt/format.h>

#include <cstdio>
#include <cstring>

#include <strata/core/clock.hpp>
#include <strata/core/memory.hpp>
#include <strata/dem/presets.hpp>

namespace strata::app {
namespace {}  // namespace

std::string bench_dem_json(const BenchDemOptions& o) {
  STRATA_CHECK(o.dim == 2 || o.dim == 3, Input, "bench dem: --dim {} must be 2 or 3", o.dim);
  STRATA_CHECK(o.particles >= 16, Input, "bench dem: --particles {} must be >= 16", o.particles);
  STRATA_CHECK(o.steps >= 1, Input, "bench dem: --steps {} must be >= 1", o.steps);
  STRATA_CHECK(o.lattice == "hcp" || o.lattice == "fcc", Input, "bench dem: lattice '{}' must be hcp or fcc",
               o.lattice);
  if (o.threads > 0) par::set_threads(o.threads);
  const int threads = par::threads();
  const double rss0 = double(sys::rss_bytes());
  const auto t0 = WallClock::now();

  // The micro-parameters of Liu, Pollard & Shi 2013 for 1 mm disks; 3D uses the same springs with ρ in kg/m³.
  // --normal-only drops the shear springs (the model then keeps no shear history).
  const double d = 1e-3;
  dem::Material m = dem::liu2013_rock();
  if (o.normal_only) m.ks = 0;
  dem::Settings s;
  s.dt = 1e-15;  // replaced by 0.5·critical_dt below
  s.damping = dem::Settings::Damping::Viscous;
  s.viscous_c = 1.16e3;
  s.contact_detection = true;

  log::Phases ph("bench dem set-up");
  preprocess::Lattice lat;
  const double side = preprocess::box_side_for(o.dim, o.particles, d);
  if (o.dim == 2)
    lat = preprocess::hex2d_box(0, 0, side, side, d);
  else
    lat =
        preprocess::close_packed_box(o.lattice == "hcp" ? preprocess::Packing::HCP : preprocess::Packing::FCC,
                                     {0, 0, 0}, {side, side, side}, d);
  const auto top = preprocess::top_row(lat), bottom = preprocess::bottom_row(lat);
  ph.lap("lattice");

  dem::Simulation sim(o.dim, s);
  const int mat = sim.add_material(m);
  sim.reserve(lat.size());
  sim.add_particles(lat.x, lat.radius, mat);
  const std::size_t n = lat.size();
  lat.release();
  ph.lap("particles added");
  sim.add_to_group(top, "top");
  sim.add_to_group(bottom, "bottom");
  const unsigned ax = o.dim == 2 ? dem::kY : dem::kZ;
  sim.fix("top", ax);
  sim.fix("bottom", ax);
  sim.bond_touching_pairs();
  sim.initialise();
  sim.set_dt(0.5 * sim.critical_dt());
  // slow compression: platens move inward at an axial strain rate of 1/s (about 60 times the
  // rate of the uniaxial compression run of Li et al. 2017, 1.9e-9 m per platen every 400 steps
  // of 2e-8 s on 0.03 m; still quasi-static: thousands of wave transits to failure)
  const double v = 0.5 * 1.0 * side;
  std::array<double, 3> vt{0, 0, 0}, vb{0, 0, 0};
  vt[o.dim - 1] = -v;
  vb[o.dim - 1] = v;
  sim.prescribe_velocity("top", vt, ax);
  sim.prescribe_velocity("bottom", vb, ax);
  const auto t1 = WallClock::now();
  sim.run(o.steps);
  const auto t2 = WallClock::now();
  const double secs = seconds_between(t1, t2);
  const double setup = seconds_between(t0, t1);
  const double hwm = double(sys::peak_rss_bytes());
  // the model as it steps (a 2D lattice in slots holds its bonds' state arrays again while
  // something reads them between steps: the state hash and counts below)
  const double model_bytes = static_cast<double>(sim.memory_bytes());
  const double nn = static_cast<double>(n);
  const double streamed = static_cast<double>(sim.streamed_bytes_per_step());
  return fmt::format(
      "{{\"dim\": {}, \"lattice\": \"{}\", \"springs\": \"{}\", \"side\": {:.9g}, \"particles\": {}, "
      "\"bonds\": {}, \"steps\": "
      "{}, \"threads\": {}, "
      "\"seconds\": {:.6g}, \"particle_steps_per_s\": {:.6g}, \"bytes_per_particle\": {:.1f}, "
      "\"model_bytes_per_particle\": {:.1f}, \"streamed_bytes_per_particle_step\": {:.1f}, "
      "\"streamed_gb_per_s\": {:.4g}, \"dt\": {:.6g}, \"dt_over_dt_crit\": {:.4g}, \"broken_bonds\": "
      "{}, "
      "\"contacts\": {}, \"setup_seconds\": {:.4g}, \"steps_in_lattice_slots\": {}, \"state_hash\": "
      "\"{:016x}\"}}",
      o.dim, o.dim == 2 ? "hex" : o.lattice, o.normal_only ? "normal" : "normal and shear", side, n,
      sim.bond_count(), o.steps, threads, secs, nn * static_cast<double>(o.steps) / secs, (hwm - rss0) / nn,
      model_bytes / nn, streamed / nn, streamed * static_cast<double>(o.steps) / secs * 1e-9, sim.dt(),
      sim.dt() / sim.critical_dt(), sim.broken_count(), sim.contact_count(), setup,
      sim.steps_in_lattice_slots(), sim.state_hash());
}

}  // namespace strata::app
