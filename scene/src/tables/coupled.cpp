// [coupled]: its keys, declared once (they validate scene files and generate
// docs/scene-reference.md), and their reading into CoupledTable.
#include <strata/core/parallel.hpp>

#include "table_file.hpp"

namespace strata::scene::tables {

TableSpec coupled_spec() {
  // A coupled scene: the loader allows beside it only the tables and [output] keys of
  // its entry of job_tables() (schema.cpp), and of [coupled] only the
  // keys whose cases() hold its case; checks between these keys (keys a case needs, duration
  // against η·dt_DEM) are in loader.cpp, stability (it needs the model) in
  // cases/src/chain_report.cpp and cases/src/wave_report.cpp.
  const std::vector<std::string> chains{"chain6", "metamaterial"}, wave{"wave"};
  return {
      "coupled",
      false,
      false,
      "A coupled FEM–DEM model run as a sweep over the time-step ratio η: a chain of Li et al. 2023 "
      "(chain6, metamaterial; error and run time per η against an exact or reference answer) or "
      "the 2D coupled wave of examples/04_coupled_wave (wave; reflection and transmission of a "
      "pulse per η and pulse length). A scene with [coupled] describes the whole model: besides "
      "it, it may hold only [output] with directory and render. Keys marked with a case apply "
      "only to it.",
      {
          K("case", Choice)
              .required()
              .choices({"chain6", "metamaterial", "wave"})
              .doc("Which model: chain6, the 6-DOF verification chain (k = 1 N/m, m = 1 kg, P·sin(πt/2) on "
                   "m2; error of m3 against the exact modal solution); metamaterial, 800 outer masses and "
                   "200 resonators (error of DEM mass 250 against a monolithic implicit Newmark run at "
                   "dt_ref), as in Li et al. 2023; wave, a 1D strain pulse from an FEM block into a "
                   "particle block built from a 2D geometry file (R and T against the matched-impedance "
                   "answer R = 0, T = 1), see examples/04_coupled_wave."),
          K("title", String).def(R"("")").doc("A name for the run, shown in the report."),
          K("dt_dem", Real, "s")
              .gt(0)
              .cases(chains)
              .doc("DEM time step dt_DEM (velocity Verlet); the FEM step is η·dt_DEM; required for the "
                   "chains. An unstable dt_DEM is refused by `strata check` and `strata run` (the "
                   "metamaterial chain needs dt_DEM <= 7.68e-5 s; the 1e-4 s of Li et al. 2023 is "
                   "unstable). η·dt_DEM above the DEM partition's limit (8.0e-5 s for the metamaterial "
                   "chain) is refused too: the copied overlap drives the DEM partition like a step of "
                   "η·dt_DEM and the run grows unstable, so the paper's η up to 20 needs dt_DEM <= 4e-6 s. "
                   "The wave sets dt_DEM with dt_fraction."),
          K("eta", IntegerList)
              .ge(1)
              .length(1, 0)
              .default_note(
                  "per case: chain6, metamaterial `[1, 2, 3, 4, 5, 10, 20]` (those of Li et al. 2023); "
                  "wave `[1, 2, 4, 5, 10]`, embedded `[1, 2, 5]`")
              .doc("Time-step ratios η = dt_FEM/dt_DEM of the sweep, one run per value and mode "
                   "(and per wavelength for the wave)."),
          K("modes", Choice)
              .choices({"serial", "parallel", "both"})
              .def(R"("both")")
              .doc("serial: both partitions on one thread; parallel: each on its own thread, meeting "
                   "once per system step; both: every η in both modes (results are the same bit for bit, "
                   "only the run time differs)."),
          K("duration", Real, "s")
              .ge(0)
              .def("0.0")
              .cases(chains)
              .doc("Simulated time; 0 uses the case's (20 s for chain6, 0.075 s for metamaterial). It "
                   "must hold at least one FEM step of the largest η. The wave runs until its gauges "
                   "have seen the reflected and transmitted pulses."),
          K("fem_scheme", Choice)
              .choices({"auto", "central-difference", "explicit-newmark", "implicit-newmark"})
              .def(R"("auto")")
              .doc("Integrator of the FEM partition: explicit-newmark is the predictor-corrector Newmark "
                   "of Li et al. 2023 with a lumped mass (explicit: stable only for ω·dt <= 2); "
                   "central-difference is explicit too; implicit-newmark (β = 1/4, γ = 1/2, factorised "
                   "once) is unconditionally stable. auto is explicit-newmark for chain6, implicit-newmark "
                   "for metamaterial, and per η for the wave: central-difference while η·dt_DEM is below "
                   "the FEM's explicit limit, implicit-newmark above it. An explicit FEM above its limit "
                   "is refused."),
          K("dt_ref", Real, "s")
              .gt(0)
              .def("1e-6")
              .cases({"metamaterial"})
              .doc("Step of the monolithic implicit Newmark reference run."),
          K("pulse_amplitude", Real, "N")
              .def("100.0")
              .cases({"metamaterial"})
              .doc("Peak of the half-sine force pulse on outer mass 1, the free end (Li et al. 2023 show "
                   "their load history only in a figure, so this pulse is strata's choice)."),
          K("pulse_duration", Real, "s")
              .gt(0)
              .def("1e-3")
              .cases({"metamaterial"})
              .doc("Length of the half-sine force pulse."),
          K("geometry", Path)
              .cases(wave)
              .doc("2D geometry file (gmsh .geo) with the physical surfaces named by particle_region, "
                   "fem_region (and exit_region), sharing straight sides; relative to the scene file; "
                   "required for the wave (examples/04_coupled_wave/wave.geo, wave_embedded.geo)."),
          K("particle_region", String)
              .def(R"("dem")")
              .cases(wave)
              .doc("Physical surface of the geometry filled with a hexagonal lattice of particles."),
          K("fem_region", String)
              .def(R"("fem")")
              .cases(wave)
              .doc("Physical surface meshed with linear triangles for the FEM; the pulse is loaded on "
                   "its far side."),
          K("exit_region", String)
              .def(R"("")")
              .cases(wave)
              .doc("A second FEM surface beyond the particles (FEM | DEM | FEM); empty: none, or "
                   "\"fem_exit\" with embedded = true."),
          K("embedded", Bool)
              .def("false")
              .cases(wave)
              .doc("FEM | DEM | FEM: a particle strip between two FEM blocks (exit_region, default "
                   "\"fem_exit\"); also changes the defaults of eta and wavelengths."),
          K("wavelengths", RealList, "particle diameters")
              .gt(0)
              .length(1, 0)
              .cases(wave)
              .default_note("`[10, 20, 40, 80]`; embedded `[20, 40]`")
              .doc("Pulse lengths λ = c·T of the sweep, in particle diameters; each must fit the "
                   "geometry (incident, reflected and transmitted pulses must separate in time)."),
          K("diameter", Real, "m")
              .gt(0)
              .def("1e-3")
              .cases(wave)
              .doc("Particle diameter d of the lattice (and the FEM element size at the interface)."),
          K("dt_fraction", Real)
              .gt(0)
              .le(1)
              .def("0.15")
              .cases(wave)
              .doc("dt_DEM as a fraction of the lattice's critical step 2/√λmax. 0.15 keeps dt_FEM <= "
                   "1.5 × the DEM limit up to η = 10: the overlap exchange was measured unstable from "
                   "about 2 × (examples/04_coupled_wave/README.md)."),
          K("fem_far_size", Real, "particle diameters")
              .ge(1)
              .le(100)
              .def("1.0")
              .cases(wave)
              .doc("Largest FEM element; 1 gives a uniform mesh of size d, the cleanest measurement."),
          K("fem_growth", Real)
              .ge(0)
              .def("0.1")
              .cases(wave)
              .doc("Growth of the FEM element size per metre away from the interface (m/m), up to "
                   "fem_far_size."),
          K("peak_velocity", Real, "m/s")
              .gt(0)
              .def("0.1")
              .cases(wave)
              .doc("v0: peak particle velocity of the incident sin² pulse."),
          K("frames", Integer)
              .ge(0)
              .def("12")
              .cases(wave)
              .doc("VTK frames of one extra run (serial, η = series_eta, the longest pulse) in "
                   "DIR/series, with PNGs of the pulse crossing the overlap unless output.render = "
                   "false; 0: no series."),
          K("series_eta", Integer).ge(1).def("1").cases(wave).doc("η of the series run."),
          K("repeats", Integer)
              .ge(1)
              .default_note("per case: chain6, metamaterial `3`; wave `1`")
              .doc("Runs per point; the fastest run time is reported."),
          K("threads", Integer)
              .ge(0)
              .le(strata::par::kMaxThreads)
              .default_note("per case: chain6, metamaterial `0`; wave `1`")
              .doc("Threads for parallel loops (the wave: inside each partition; its models are small, "
                   "and a thread hand-off per step costs more than it saves); 0 uses all cores. "
                   "`strata run --threads` overrides it."),
      }};
}

CoupledTable read_coupled(const Table& t) {
  Reader read(t, "coupled");
  CoupledTable c;
  c.pos = t.where();
  read("case", c.case_name);
  read("title", c.title);
  read("dt_dem", c.dt_dem);
  read("eta", c.eta);
  read("modes", c.modes);
  read("duration", c.duration);
  read("fem_scheme", c.fem_scheme);
  read("dt_ref", c.dt_ref);
  read("pulse_amplitude", c.pulse_amplitude);
  read("pulse_duration", c.pulse_duration);
  read("geometry", c.geometry);
  read("particle_region", c.particle_region);
  read("fem_region", c.fem_region);
  read("exit_region", c.exit_region);
  read("embedded", c.embedded);
  read("wavelengths", c.wavelengths);
  read("diameter", c.diameter);
  read("dt_fraction", c.dt_fraction);
  read("fem_far_size", c.fem_far_size);
  read("fem_growth", c.fem_growth);
  read("peak_velocity", c.peak_velocity);
  read("frames", c.frames);
  read("series_eta", c.series_eta);
  read("repeats", c.repeats);
  read("threads", c.threads);
  read.done();
  return c;
}

}  // namespace strata::scene::tables
