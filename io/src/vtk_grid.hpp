#pragma once
// Internal (io): a MeshFrame's points and cells as a VTK unstructured grid, shared by the
// .vtu writer and the pictures. Declared only in builds with STRATA_WITH_VTK: without it no
// VTK header is included, so this header is safe to include anywhere.
#include "strata/config.hpp"
#include "strata/io/frame.hpp"

#if STRATA_WITH_VTK
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

namespace strata::io::detail {

/// Points and cells of `mesh` (no point or cell arrays).
vtkSmartPointer<vtkUnstructuredGrid> mesh_grid(const MeshFrame& mesh);

}  // namespace strata::io::detail
#endif
