// What a scene asks of the optional parts of strata, against what this build has.
#include <strata/scene/scene.hpp>

#include <fmt/format.h>
#include <strata/config.hpp>
#include <strata/core/log.hpp>
#include <strata/preprocess/geometry.hpp>

#include <algorithm>
#include <cctype>
#include <iterator>
#include <string>

namespace strata::scene {
namespace {

/// One optional part: its CMake option, what it is in a message, and whether this build has it.
struct Part {
  const char* option;
  const char* what;
  bool present;
};

constexpr Part kGmsh{"STRATA_WITH_GMSH", "gmsh", STRATA_WITH_GMSH != 0};
constexpr Part kCgal{"STRATA_WITH_CGAL", "CGAL (inside tests on closed surfaces)", STRATA_WITH_CGAL != 0};
constexpr Part kHdf5{"STRATA_WITH_HDF5", "HDF5 (checkpoints)", STRATA_WITH_HDF5 != 0};
constexpr Part kVtk{"STRATA_WITH_VTK", "VTK (frames as .vtp/.vtu files and .pvd series)",
                    STRATA_WITH_VTK != 0};
constexpr Part kRender{"STRATA_WITH_RENDER", "rendering (PNG pictures and plots)", STRATA_WITH_RENDER != 0};

/// "<asks> needs <part>, a part this build of strata leaves out: reconfigure with -D<option>=ON
/// [, or <instead>]" at the key's file:line:col.
template <class T>
[[noreturn]] void refuse(const Located<T>& key, const std::string& asks, const Part& part,
                         const std::string& instead = {}) {
  key.fail(fmt::format("{} needs {}, a part this build of strata leaves out: reconfigure with -D{}=ON{}",
                       asks, part.what, part.option, instead.empty() ? "" : ", or " + instead));
}

void check_regions(const Scene& sc) {
  for (const RegionTable& r : sc.regions) {
    const std::string name = fmt::format("[[region]] '{}'", r.name.value);
    if (r.shape == RegionShape::File) {
      if (preprocess::is_gmsh_file(r.file.value) && !kGmsh.present)
        refuse(r.file, fmt::format("{}: the geometry file {}", name, r.file.value.string()), kGmsh);
      if (preprocess::is_surface_file(r.file.value) && !kCgal.present)
        refuse(r.file, fmt::format("{}: the closed surface {}", name, r.file.value.string()), kCgal);
    }
    if (r.kind == RegionKind::Fem && !kGmsh.present)
      refuse(r.kind, fmt::format("{}: kind = \"fem\" (FEM regions are meshed by gmsh)", name), kGmsh);
  }
}

void check_coupled_model(const CoupledTable& c) {
  if (c.case_name.value != "wave" || kGmsh.present) return;
  if (c.geometry.given)
    refuse(c.geometry,
           fmt::format("[coupled] geometry {} (the wave's regions are read and meshed by gmsh)",
                       c.geometry.value.string()),
           kGmsh);
  refuse(c.case_name, "[coupled] case = \"wave\" (its regions are read and meshed by gmsh)", kGmsh);
}

void check_coupled_outputs(const Scene& sc, const CoupledTable& c) {
  if (!kVtk.present && c.frames.given && c.frames > 0)
    refuse(c.frames, fmt::format("[coupled] frames = {}", c.frames.value), kVtk, "set coupled.frames = 0");
  if (!kRender.present && sc.output.render.given && sc.output.render)
    refuse(sc.output.render, "output.render = true (the sweep's plots)", kRender,
           "set output.render = false");
}

void check_outputs(const OutputTable& o) {
  if (!kHdf5.present && o.checkpoint_every > 0)
    refuse(o.checkpoint_every, fmt::format("output.checkpoint_every = {}", o.checkpoint_every.value), kHdf5,
           "remove the key");

  // Frames: asked for by output.vtk = true, or by a frame cadence the scene writes, unless the
  // scene turns VTK off itself.
  const bool frames_off = o.vtk.given && !o.vtk.value;
  if (!kVtk.present && !frames_off) {
    const std::string instead = "set output.vtk = false";
    if (o.vtk.given) refuse(o.vtk, "output.vtk = true", kVtk, instead);
    if (o.frames.given && o.frames > 0)
      refuse(o.frames, fmt::format("output.frames = {}", o.frames.value), kVtk, instead);
    if (o.frame_every_time.given && o.frame_every_time > 0)
      refuse(o.frame_every_time, fmt::format("output.frame_every_time = {}", o.frame_every_time.value), kVtk,
             instead);
    if (o.frame_every_breaks.given && o.frame_every_breaks > 0)
      refuse(o.frame_every_breaks, fmt::format("output.frame_every_breaks = {}", o.frame_every_breaks.value),
             kVtk, instead);
    const bool would_write = o.frames > 0 || o.frame_every_time > 0 || o.frame_every_breaks > 0;
    if (would_write)
      log::warn("VTK frames skipped: this build has no VTK (reconfigure with -D{}=ON)", kVtk.option);
  }

  // Pictures and plots: asked for by output.render = true, or by the keys that only make sense
  // with pictures, unless the scene turns rendering off itself.
  const bool pictures_off = o.render.given && !o.render.value;
  if (!kRender.present && !pictures_off) {
    const std::string instead = "set output.render = false";
    if (o.render.given) refuse(o.render, "output.render = true", kRender, instead);
    if (o.render_while_running.given && o.render_while_running)
      refuse(o.render_while_running, "output.render_while_running = true", kRender, instead);
    if (o.movie.given && o.movie) refuse(o.movie, "output.movie = true", kRender, instead);
  }
}

}  // namespace

const Scene& require_build_parts(const Scene& sc, SceneUse use) {
  if (sc.coupled) {
    check_coupled_model(*sc.coupled);
    if (use == SceneUse::Run) check_coupled_outputs(sc, *sc.coupled);
    return sc;
  }
  if (sc.network) {
    if (use == SceneUse::Run) check_outputs(sc.output);
    return sc;
  }
  check_regions(sc);
  if (use == SceneUse::Run) check_outputs(sc.output);
  return sc;
}

}  // namespace strata::scene
