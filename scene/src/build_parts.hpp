#pragma once
// Internal: what a scene asks of the optional parts of strata (gmsh, CGAL, HDF5, VTK,
// rendering), checked against this build before anything is built or written.
//
// A key the scene writes that needs a part this build leaves out is refused at its
// file:line:col, naming the CMake option that turns the part on. A key left at its default
// never is: a build without VTK writes no frames, one without rendering draws no pictures
// (the run says so). docs/architecture.md, "Optional parts", has the whole table.
#include <strata/scene/scene.hpp>

namespace strata::scene {

/// What the caller is about to do with the scene.
enum class SceneUse {
  Model,  ///< fill and mesh the regions only (`strata mesh`): geometry files, FEM meshes
  Run,    ///< build and run it: also the outputs it asks for (frames, pictures, checkpoints)
};

/// Throws strata::Error (Input) "file:line:col: ..." at the first key of `sc` that needs a
/// part this build leaves out for `use`, naming the option (e.g. -DSTRATA_WITH_GMSH=ON).
/// Returns `sc`, so that a constructor can check the scene in its initialiser list.
const Scene& require_build_parts(const Scene& sc, SceneUse use = SceneUse::Run);

}  // namespace strata::scene
