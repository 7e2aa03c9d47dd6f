#pragma once
// Internal (io): a MeshFrame's points and cells as a VTK unstructured grid, shared by the
// .vtu writer and the pictures. Only with STRATA_WITH_VTK.
#include "strata/io/frame.hpp"

#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

namespace strata::io::detail {

/// Points and cells of `mesh` (no point or cell arrays).
vtkSmartPointer<vtkUnstructuredGrid> mesh_grid(const MeshFrame& mesh);

}  // namespace strata::io::detail
