#pragma once
// Helpers shared by the io tests: a fresh folder per test, a small hexagonal patch and a
// tetrahedral box.
#include <gtest/gtest.h>
#include <strata/io/frame.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

#include "tet_box.hpp"

namespace strata::io::test {
namespace fs = std::filesystem;

/// A fresh folder per test, removed afterwards.
class IoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("strata_test_io_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }
  fs::path dir_;
};

/// A 2D hexagonal patch of `cols` x `rows` disks of radius r, with displacement growing
/// to the right, ids, and bonds to the right and upper neighbours.
struct Patch {
  PointCloud cloud;
  LineSet bonds;
};

inline Patch hex_patch(int cols, int rows, double r = 0.5e-3) {
  Patch p;
  p.cloud.dim = 2;
  Array radius{std::string(kRadiusArray), 1, {}, ArrayType::Float64};
  Array disp{"displacement", 3, {}, ArrayType::Float32};
  Array id{"id", 1, {}, ArrayType::Int64};
  const double dy = r * std::sqrt(3.0);
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < cols; ++i) {
      const double x = 2 * r * i + (j % 2) * r, y = dy * j;
      p.cloud.xyz.insert(p.cloud.xyz.end(), {x, y, 0.0});
      radius.values.push_back(r);
      disp.values.insert(disp.values.end(), {1e-6 * i, -2e-7 * j, 0.0});
      id.values.push_back(j * cols + i);
    }
  p.cloud.point_data = {radius, disp, id};
  Array state{std::string(kBondStateArray), 1, {}, ArrayType::Int32};
  Array fn{"Fn", 1, {}, ArrayType::Float64};
  auto add = [&](int a, int b) {
    p.bonds.ends.insert(p.bonds.ends.end(), {a, b});
    const int n = static_cast<int>(p.bonds.size());
    // A diagonal band of tensile cracks, some shear cracks near the middle, a few closed.
    const int ia = a % cols, ja = a / cols;
    int s = 0;
    if (std::abs(ia - ja) <= 0) s = 1;
    if (std::abs(ia + ja - cols) <= 0) s = 2;
    if (s == 1 && ja % 5 == 0) s = 3;
    state.values.push_back(s);
    fn.values.push_back(100.0 * n);
  };
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < cols; ++i) {
      const int a = j * cols + i;
      if (i + 1 < cols) add(a, a + 1);
      if (j + 1 < rows) {
        const int up_left = (j % 2) ? a + cols : a + cols - 1;
        const int up_right = (j % 2) ? a + cols + 1 : a + cols;
        if (up_left >= (j + 1) * cols && up_left < (j + 2) * cols) add(a, up_left);
        if (up_right < (j + 2) * cols && ((j % 2) == 0 || i + 1 < cols)) add(a, up_right);
      }
    }
  p.bonds.cell_data = {state, fn};
  return p;
}

/// tet_box of tests/common (a cube [0, n]^3 of unit cells, six tetrahedra each, cell array
/// "cx" = the cell centroid's x as Float32) with point array "x" (the node's x); n = 1 and
/// `extras` add a triangle and a line to test mixed cells.
inline MeshFrame tet_box(int n, bool extras = false) {
  MeshFrame m = fixtures::tet_box(n, ArrayType::Float32);
  Array x{"x", 1, {}, ArrayType::Float64};
  for (std::size_t a = 0; a < m.nodes(); ++a) x.values.push_back(m.xyz[3 * a]);
  m.point_data = {x};
  if (extras) {
    auto& cx = m.cell_data[0].values;
    m.add_cell(CellType::Triangle, {0, 1, fixtures::tet_box_node(n, 0, 1, 0)});
    cx.push_back(1.0 / 3);
    m.add_cell(CellType::Line, {0, fixtures::tet_box_node(n, 0, 0, 1)});
    cx.push_back(0);
  }
  return m;
}

inline std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace strata::io::test
