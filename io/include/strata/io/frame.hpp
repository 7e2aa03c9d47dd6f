#pragma once
/// Neutral data views that the io library writes and renders.
///
/// io does not know about DEM or FEM types: the driver copies (or views) its state into
/// these plain structs. Everything is stored as double; `Array::type` only decides how an
/// array is written to disk (identifiers and bond states are nicer as integers).
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace strata::io {

/// How an array is stored in a file. Values are held as double in memory; integer types
/// round them when written (exact up to 2^53).
enum class ArrayType { Float64, Float32, Int64, Int32, UInt8 };

/// One named point-data or cell-data array, `components` values per point (or cell),
/// interleaved: values[i * components + c].
struct Array {
  std::string name;
  int components = 1;
  std::vector<double> values;
  ArrayType type = ArrayType::Float64;

  /// Number of tuples (points or cells) the array holds.
  std::size_t tuples() const { return components > 0 ? values.size() / components : 0; }
  /// Value of tuple i, component c.
  double at(std::size_t i, int c = 0) const { return values[i * components + c]; }
};

/// Name of the particle radius array: write_particles requires it (ParaView's Glyph and
/// strata's pictures scale particles by it).
inline constexpr std::string_view kRadiusArray = "radius";

/// Particles (or any points): xyz holds 3 coordinates per point, z = 0 in 2D.
struct PointCloud {
  int dim = 3;                       ///< 2 or 3: decides the camera of a picture
  std::vector<double> xyz;           ///< 3 per point
  std::vector<Array> point_data;     ///< one tuple per point each
  std::optional<double> time;        ///< written as field data "TimeValue" (ParaView reads it)
  std::optional<std::int64_t> step;  ///< written as field data "step"

  std::size_t size() const { return xyz.size() / 3; }
  /// The point array called `name`, or nullptr.
  const Array* find(std::string_view name) const;
  Array* find(std::string_view name);
};

/// Bond modes as stored in a LineSet's state array (`kBondStateArray`): the driver maps
/// its own bond states onto these codes, and pictures colour broken bonds by them.
enum class BondState : int {
  Intact = 0,         ///< bonded, carrying tension and shear
  BrokenTension = 1,  ///< broken in tension and open
  BrokenShear = 2,    ///< broken in shear
  Closed = 3,         ///< broken (either mode) and in contact again: friction only
  Contact = 4,        ///< never bonded, touching now: compression and friction only
};

/// Name of the bond-state cell array used by pictures (values are BondState codes).
inline constexpr std::string_view kBondStateArray = "state";

/// Line cells (bonds and contacts) between points of a PointCloud: ends holds 2 point
/// indices per line.
struct LineSet {
  std::vector<std::int64_t> ends;  ///< 2 per line, indices into the PointCloud
  std::vector<Array> cell_data;    ///< one tuple per line each

  std::size_t size() const { return ends.size() / 2; }
  /// The cell array called `name`, or nullptr.
  const Array* find(std::string_view name) const;
  Array* find(std::string_view name);
};

/// Throws strata::Error (Input) when sizes disagree: xyz not a multiple of 3, an array
/// with the wrong number of values, a line end out of range (when `lines` is given).
void validate(const PointCloud& cloud, const LineSet* lines = nullptr);

/// Linear cell types of a MeshFrame; the values are VTK's cell type codes.
enum class CellType : std::uint8_t {
  Line = 3,      ///< 2 nodes (bars, springs)
  Triangle = 5,  ///< 3 nodes
  Tetra = 10,    ///< 4 nodes
};

/// Nodes of a cell type (2, 3 or 4).
constexpr int nodes_per_cell(CellType t) {
  return t == CellType::Tetra ? 4 : t == CellType::Triangle ? 3 : 2;
}

/// A FEM mesh (or any linear unstructured grid): nodes, cells of one or mixed linear types,
/// point and cell arrays. Cell c uses cell_types[c] and the next nodes_per_cell(cell_types[c])
/// entries of `connectivity` (cells in order, no offsets stored).
struct MeshFrame {
  int dim = 3;                             ///< 2 or 3: decides the camera of a picture
  std::vector<double> xyz;                 ///< 3 per node, z = 0 in 2D
  std::vector<CellType> cell_types;        ///< one per cell
  std::vector<std::int64_t> connectivity;  ///< node indices, cell after cell
  std::vector<Array> point_data;           ///< one tuple per node each
  std::vector<Array> cell_data;            ///< one tuple per cell each
  std::optional<double> time;              ///< written as field data "TimeValue"
  std::optional<std::int64_t> step;        ///< written as field data "step"

  std::size_t nodes() const { return xyz.size() / 3; }
  std::size_t cells() const { return cell_types.size(); }
  /// Appends a cell; `nodes` must hold nodes_per_cell(type) indices.
  void add_cell(CellType type, std::initializer_list<std::int64_t> nodes);
  /// The point array called `name`, or nullptr.
  const Array* find_point(std::string_view name) const;
  Array* find_point(std::string_view name);
  /// The cell array called `name`, or nullptr.
  const Array* find_cell(std::string_view name) const;
};

/// Throws strata::Error (Input) when sizes disagree: xyz not 3 per node, connectivity not
/// matching the cell types, a node index out of range, an array of the wrong length.
void validate(const MeshFrame& mesh);

}  // namespace strata::io
