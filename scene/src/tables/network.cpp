// [network]: its keys, declared once (they validate scene files and generate
// docs/scene-reference.md), and their reading into NetworkTable.
#include "table_file.hpp"

namespace strata::scene::tables {

TableSpec network_spec() {
  // A network scene: the loader allows beside it only [scene], [solver] and some [output]
  // keys (job_tables(), schema.cpp); the checks between its keys (node numbers, rows, solver
  // keys that do not apply) are in checks.cpp.
  return {"network",
          false,
          false,
          "A network of point masses and linear springs with one degree of freedom per node (a "
          "displacement along the chain), split into an FEM part and a particle part that overlap by one "
          "layer of nodes and run coupled at the time-step ratio solver.eta: the verification chains of "
          "Li et al. 2023, where the coupled answer can be compared with an exact one. The particle part "
          "steps by velocity Verlet at solver.dt (0: dt_safety × its critical step 2/ω_max, ω_max² <= "
          "max over nodes of (2 Σ k + Σ k_wall)/m); the FEM part (spring elements with lumped masses) by "
          "solver.fem_integrator at η·dt. A network scene holds [network] and, besides, only "
          "[solver] (dt, dt_safety, steps, duration, allow_unstable, threads, fem_integrator, eta, "
          "coupling) and output.directory, probe_every, checkpoint_every and render. Its probes.csv holds "
          "both parts' energies and the displacement and velocity of the probe_nodes, plotted with "
          "output.render; it writes no frames.",
          {
              K("title", String).def(R"("")").doc("A name for the run, shown in its report."),
              K("mass", RealList, "kg")
                  .required()
                  .gt(0)
                  .length(2, 0)
                  .doc("Mass of each node; node numbers count from 0 in this order."),
              K("springs", RealTable)
                  .required()
                  .length(3, 3)
                  .doc("Springs between nodes, one row [i, j, k] each: node numbers i and j, stiffness k "
                       "in N/m."),
              K("walls", RealTable)
                  .def("[]")
                  .length(2, 2)
                  .doc("Springs from a node to a fixed wall, one row [i, k] each: node number i, stiffness "
                       "k in N/m."),
              K("fem_nodes", IntegerList)
                  .required()
                  .ge(0)
                  .length(2, 0)
                  .doc("Nodes of the FEM part, with the springs between them."),
              K("particle_nodes", IntegerList)
                  .required()
                  .ge(0)
                  .length(2, 0)
                  .doc("Nodes of the particle part, with the springs between them. The two parts must "
                       "share one layer of nodes: a shared node linked to a particle-only node is driven "
                       "by the particle part (external to the FEM), one linked to an FEM-only node by "
                       "the FEM part, and the spring between two shared nodes is in both."),
              K("sine_loads", RealTable)
                  .def("[]")
                  .length(4, 4)
                  .doc("Sinusoidal forces, one row [i, P, period, end] each: P·sin(2π t/period) on node i "
                       "(N) from t = 0 until `end` (s; 0: no end), zero after. A half-sine pulse of length "
                       "T is [i, P, 2T, T]."),
              K("probe_nodes", IntegerList)
                  .def("[]")
                  .ge(0)
                  .doc("Nodes whose displacement and velocity go to probes.csv at every probe row "
                       "(columns node<i>_u, node<i>_v)."),
          }};
}

NetworkTable read_network(const Table& t) {
  Reader read(t, "network");
  NetworkTable n;
  n.pos = t.where();
  read("title", n.title);
  read("mass", n.mass);
  read("springs", n.springs);
  read("walls", n.walls);
  read("fem_nodes", n.fem_nodes);
  read("particle_nodes", n.particle_nodes);
  read("sine_loads", n.sine_loads);
  read("probe_nodes", n.probe_nodes);
  read.done();
  return n;
}

}  // namespace strata::scene::tables
