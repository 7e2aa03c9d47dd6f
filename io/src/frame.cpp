#include "strata/io/frame.hpp"

#include "strata/core/error.hpp"

namespace strata::io {
namespace {
template <typename Arrays>
auto* find_in(Arrays& arrays, std::string_view name) {
  for (auto& a : arrays)
    if (a.name == name) return &a;
  return static_cast<decltype(&arrays.front())>(nullptr);
}

void check_arrays(const std::vector<Array>& arrays, std::size_t n, const char* what) {
  for (const auto& a : arrays) {
    STRATA_CHECK(!a.name.empty(), Input, "{} array without a name", what);
    STRATA_CHECK(a.components >= 1, Input, "{} array '{}': components = {} must be >= 1", what, a.name,
                 a.components);
    STRATA_CHECK(a.values.size() == n * static_cast<std::size_t>(a.components), Input,
                 "{} array '{}': {} values, expected {} ({} tuples x {} components)", what, a.name,
                 a.values.size(), n * a.components, n, a.components);
  }
}
}  // namespace

const Array* PointCloud::find(std::string_view name) const { return find_in(point_data, name); }
Array* PointCloud::find(std::string_view name) { return find_in(point_data, name); }
const Array* LineSet::find(std::string_view name) const { return find_in(cell_data, name); }
Array* LineSet::find(std::string_view name) { return find_in(cell_data, name); }

const Array* MeshFrame::find_point(std::string_view name) const { return find_in(point_data, name); }
Array* MeshFrame::find_point(std::string_view name) { return find_in(point_data, name); }
const Array* MeshFrame::find_cell(std::string_view name) const { return find_in(cell_data, name); }

void MeshFrame::add_cell(CellType type, std::initializer_list<std::int64_t> nodes) {
  STRATA_CHECK(nodes.size() == static_cast<std::size_t>(nodes_per_cell(type)), Input,
               "mesh cell of type {} given {} nodes, needs {}", static_cast<int>(type), nodes.size(),
               nodes_per_cell(type));
  cell_types.push_back(type);
  connectivity.insert(connectivity.end(), nodes.begin(), nodes.end());
}

void validate(const MeshFrame& mesh) {
  STRATA_CHECK(mesh.dim == 2 || mesh.dim == 3, Input, "mesh dim = {} must be 2 or 3", mesh.dim);
  STRATA_CHECK(mesh.xyz.size() % 3 == 0, Input, "mesh: {} coordinates is not 3 per node", mesh.xyz.size());
  std::size_t need = 0;
  for (const CellType t : mesh.cell_types) {
    STRATA_CHECK(t == CellType::Line || t == CellType::Triangle || t == CellType::Tetra, Input,
                 "mesh: unknown cell type {}", static_cast<int>(t));
    need += static_cast<std::size_t>(nodes_per_cell(t));
  }
  STRATA_CHECK(need == mesh.connectivity.size(), Input,
               "mesh: {} connectivity entries, the {} cell types need {}", mesh.connectivity.size(),
               mesh.cells(), need);
  const auto n = static_cast<std::int64_t>(mesh.nodes());
  for (std::size_t i = 0; i < mesh.connectivity.size(); ++i)
    STRATA_CHECK(mesh.connectivity[i] >= 0 && mesh.connectivity[i] < n, Input,
                 "mesh connectivity entry {}: node index {} outside [0, {})", i, mesh.connectivity[i], n);
  check_arrays(mesh.point_data, mesh.nodes(), "point");
  check_arrays(mesh.cell_data, mesh.cells(), "cell");
}

void validate(const PointCloud& cloud, const LineSet* lines) {
  STRATA_CHECK(cloud.dim == 2 || cloud.dim == 3, Input, "point cloud dim = {} must be 2 or 3", cloud.dim);
  STRATA_CHECK(cloud.xyz.size() % 3 == 0, Input, "point cloud: {} coordinates is not 3 per point",
               cloud.xyz.size());
  check_arrays(cloud.point_data, cloud.size(), "point");
  if (!lines) return;
  STRATA_CHECK(lines->ends.size() % 2 == 0, Input, "line set: {} line ends is not 2 per line",
               lines->ends.size());
  const auto n = static_cast<std::int64_t>(cloud.size());
  for (std::size_t i = 0; i < lines->ends.size(); ++i)
    STRATA_CHECK(lines->ends[i] >= 0 && lines->ends[i] < n, Input, "line {}: point index {} outside [0, {})",
                 i / 2, lines->ends[i], n);
  check_arrays(lines->cell_data, lines->size(), "cell");
}

}  // namespace strata::io
