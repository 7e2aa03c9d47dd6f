#pragma once
/// VTK XML frames: particles as vertex cells and bonds/contacts as line cells in PolyData
/// (.vtp); FEM meshes as UnstructuredGrid (.vtu).
///
/// Files are written by VTK's own XML writers in appended raw binary form,
/// zlib-compressed, with 64-bit block headers (pieces over 4 GiB stay readable). Each file
/// is written to `<path>.tmp` in the same directory and renamed onto `<path>`, so a reader
/// (or a run killed half-way) never sees a partial file under the final name.
/// Without STRATA_WITH_VTK these functions throw strata::Error (Unsupported).
#include <filesystem>

#include "strata/io/frame.hpp"

namespace strata::io {

/// Writes particles as points with one vertex cell each (so ParaView shows them directly)
/// and all point arrays. The cloud must have a `radius` array (kRadiusArray) for Glyph
/// scaling. `time` and `step`, when set, become field data.
void write_particles(const std::filesystem::path& path, const PointCloud& particles);

/// Writes bonds as line cells between points of `points`, with the line set's cell arrays.
/// Only the points that some line uses are written (a file of broken bonds stays small),
/// together with their point arrays; line ends are renumbered accordingly.
void write_lines(const std::filesystem::path& path, const PointCloud& points, const LineSet& lines);

/// A .vtp file read back: its points (with point arrays, dim, time, step) and its line
/// cells (with cell arrays). Vertex cells are implied by the points and not returned.
struct VtpContents {
  PointCloud points;
  LineSet lines;
};

/// Reads a .vtp file written by write_particles or write_lines (or any PolyData with
/// points and lines). Integer VTK arrays come back with an integer ArrayType.
VtpContents read_vtp(const std::filesystem::path& path);

/// Writes a mesh as an unstructured grid (.vtu, vtkXMLUnstructuredGridWriter) with its
/// point and cell arrays; `dim`, `time` and `step` become field data, as for particles.
void write_mesh(const std::filesystem::path& path, const MeshFrame& mesh);

/// Reads a .vtu file written by write_mesh (or any unstructured grid of lines, triangles
/// and tetrahedra; other cell types are refused). Integer arrays keep an integer ArrayType.
MeshFrame read_vtu(const std::filesystem::path& path);

}  // namespace strata::io
