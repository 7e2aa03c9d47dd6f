// [solver]: its keys, declared once (they validate scene files and generate
// docs/scene-reference.md), and their reading into SolverTable.
#include <strata/core/parallel.hpp>

#include "table_file.hpp"

namespace strata::scene::tables {
namespace {
const Word<SolverDamping> kDamping[] = {
    {"none", SolverDamping::None}, {"viscous", SolverDamping::Viscous}, {"local", SolverDamping::Local}};
const Word<ContactDetection> kContactDetection[] = {
    {"auto", ContactDetection::Auto}, {"on", ContactDetection::On}, {"off", ContactDetection::Off}};
const Word<SolverCoupling> kCoupling[] = {{"serial", SolverCoupling::Serial},
                                          {"parallel", SolverCoupling::Parallel}};
}  // namespace

TableSpec solver_spec() {
  return {
      "solver",
      false,
      false,
      "Time stepping and damping. Before a run strata compares the time step with the critical one "
      "(for the 2D hexagonal lattice dt_crit = 2·√(m/(6Kn+2Ks))).",
      {
          K("dt", Real, "s")
              .ge(0)
              .def("0.0")
              .doc("Time step; 0 chooses dt_safety × dt_crit. A dt above dt_crit is refused unless "
                   "allow_unstable = true."),
          K("dt_safety", Real)
              .gt(0)
              .le(1)
              .def("0.2")
              .doc("Fraction of the critical time step used when dt = 0 (Li et al. 2017 used "
                   "0.14)."),
          K("steps", Integer)
              .ge(0)
              .def("0")
              .doc("Number of time steps; when 0 the run lasts `duration`. Set steps or duration."),
          K("duration", Real, "s").ge(0).def("0.0").doc("Simulated time, used when steps = 0."),
          K("settle", Real, "s")
              .ge(0)
              .def("0.0")
              .doc("Length of a settling stage before the run (particle models): gravity and damping "
                   "act while prescribed motions, moving walls and loads wait, each prescribed axis held "
                   "where it is. The settled state is the start of the run: time, steps, displacements "
                   "and work count from it, and bonds that broke while settling have negative steps. "
                   "A layered cover settles under its weight before a wall shortens it. 0: none."),
          K("damping", Choice)
              .choices(words(kDamping))
              .def(R"("none")")
              .doc("none; viscous: a force −c·v on each particle (the artificial viscosity of Li et al. "
                   "2017); local: each force component is reduced by local_damping times its size, "
                   "against the velocity (Cundall's local damping)."),
          K("viscous_c", Real, "N·s/m")
              .ge(0)
              .def("0.0")
              .doc("c of the viscous damping force −c·v (Li et al. 2017 use 1.16e3 N·s/m)."),
          K("local_damping", Real)
              .ge(0)
              .lt(1)
              .def("0.7")
              .doc("Coefficient of local damping (damping = \"local\")."),
          K("gravity", RealList, "m/s^2")
              .per_axis()
              .def("[0.0, 0.0, 0.0]")
              .doc("Acceleration of gravity, e.g. [0, -9.81] in 2D."),
          K("contact_detection", Choice)
              .choices(words(kContactDetection))
              .def(R"("auto")")
              .doc("Search for new contacts between particles that were not bonded at the start: on, "
                   "off, or auto (on only when particles can meet new neighbours, e.g. when bonds can "
                   "break or walls move, and off with eccentric regions, whose offset centroids can "
                   "overlap unbonded neighbours at the start)."),
          K("allow_unstable", Bool)
              .def("false")
              .doc("Run even when dt exceeds the critical time step, with a warning."),
          K("threads", Integer)
              .ge(0)
              .le(strata::par::kMaxThreads)
              .def("0")
              .doc("Number of threads; 0 uses all cores. Results are the same for any number."),
          K("min_particles_per_thread", Integer)
              .ge(1)
              .def("4096")
              .doc("A thread is used only for at least this many particles (a parallel step costs a few "
                   "microseconds of synchronisation, more than it saves on small models when other work "
                   "shares the cores). Results do not depend on it."),
          K("lattice_slots", Bool)
              .def("true")
              .doc("A lattice numbered row by row (a hexagonal region, or a close-packed one layer by layer) "
                   "steps its bonds direction by direction while it has no contacts, faster and in less "
                   "memory, on any number of threads; false takes the general bond pass. Results do not "
                   "depend on it."),
          K("fem_integrator", Choice)
              .choices({"auto", "central-difference", "explicit-newmark", "implicit-newmark"})
              .def(R"("auto")")
              .doc("Time integrator of FEM regions. auto: central difference while the FEM step is below "
                   "its explicit limit, implicit Newmark (β = 1/4, γ = 1/2, unconditionally stable) above "
                   "it. explicit-newmark is the predictor-corrector Newmark with a lumped mass: explicit, "
                   "stable only for ω·dt ≤ 2."),
          K("eta", Integer)
              .ge(1)
              .le(1000000)
              .def("1")
              .doc("η: FEM step over DEM step in a model with particle and FEM regions. One system step "
                   "is one FEM step of η·dt and η particle steps of dt; the two sides exchange the overlap "
                   "at every system step."),
          K("coupling", Choice)
              .choices(words(kCoupling))
              .def(R"("serial")")
              .doc("How a coupled model runs its two sides: one after the other, or the FEM side and the "
                   "particles on two threads meeting once per system step. Both give the same bits."),
      }};
}

SolverTable read_solver(const Table& t) {
  Reader read(t, "solver");
  SolverTable s;
  s.pos = t.where();
  read("dt", s.dt);
  read("dt_safety", s.dt_safety);
  read("steps", s.steps);
  read("duration", s.duration);
  read("settle", s.settle);
  read("damping", s.damping, kDamping);
  read("viscous_c", s.viscous_c);
  read("local_damping", s.local_damping);
  read("gravity", s.gravity);
  read("contact_detection", s.contact_detection, kContactDetection);
  read("allow_unstable", s.allow_unstable);
  read("threads", s.threads);
  read("min_particles_per_thread", s.min_particles_per_thread);
  read("lattice_slots", s.lattice_slots);
  read("fem_integrator", s.fem_integrator);
  read("eta", s.eta);
  read("coupling", s.coupling, kCoupling);
  read.done();
  return s;
}

}  // namespace strata::scene::tables

namespace strata::scene {
std::string_view to_string(SolverDamping v) { return tables::word_of(tables::kDamping, v); }
std::string_view to_string(ContactDetection v) { return tables::word_of(tables::kContactDetection, v); }
std::string_view to_string(SolverCoupling v) { return tables::word_of(tables::kCoupling, v); }
}  // namespace strata::scene
