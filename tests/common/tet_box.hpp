#pragma once
// The small tetrahedral test mesh shared by the io tests (io_test_util.hpp) and the cli
// tests (series_check.cpp).
#include <strata/io/frame.hpp>

#include <cstdint>

namespace fixtures {

/// Index of node (i, j, k) of tet_box(n): x fastest, then y, then z.
inline std::int64_t tet_box_node(int n, int i, int j, int k) {
  return static_cast<std::int64_t>((k * (n + 1) + j) * (n + 1) + i);
}

/// A cube [0, n]^3 of unit cells, each split into six tetrahedra along its main diagonal
/// (conforming across faces), with one cell array, "cx" (the cell centroid's x) stored as
/// `cx_type`, and no point arrays.
inline strata::io::MeshFrame tet_box(int n, strata::io::ArrayType cx_type) {
  using namespace strata::io;
  MeshFrame m;
  m.dim = 3;
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) m.xyz.insert(m.xyz.end(), {double(i), double(j), double(k)});
  Array cx{"cx", 1, {}, cx_type};
  // The six paths from corner (i, j, k) to (i+1, j+1, k+1), one axis a step.
  static constexpr int kPerm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (const auto& p : kPerm) {
          int c[3] = {i, j, k};
          std::int64_t v[4] = {tet_box_node(n, i, j, k), 0, 0, 0};
          double sx = i;
          for (int s = 0; s < 3; ++s) {
            ++c[p[s]];
            v[s + 1] = tet_box_node(n, c[0], c[1], c[2]);
            sx += c[0];
          }
          m.add_cell(CellType::Tetra, {v[0], v[1], v[2], v[3]});
          cx.values.push_back(sx / 4);
        }
  m.cell_data = {cx};
  return m;
}

}  // namespace fixtures
