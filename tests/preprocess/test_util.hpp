#pragma once
// Helpers of the preprocess tests: data paths and small surfaces written on the fly.
#include <strata/preprocess/shapes.hpp>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace strata::test {

inline std::filesystem::path data(const std::string& name) {
  return std::filesystem::path(STRATA_SOURCE_DIR) / "tests" / "preprocess" / "data" / name;
}

inline std::filesystem::path scratch(const std::string& name) {
  const auto dir = std::filesystem::path(STRATA_BINARY_DIR) / "test-preprocess";
  std::filesystem::create_directories(dir);
  return dir / name;
}

using Tri = std::array<preprocess::Vec3, 3>;

/// Writes triangles as ASCII STL.
inline void write_stl(const std::filesystem::path& path, const std::vector<Tri>& tris) {
  std::ofstream f(path);
  f.precision(17);
  f << "solid s\n";
  for (const auto& t : tris) {
    f << " facet normal 0 0 0\n  outer loop\n";
    for (const auto& p : t) f << "   vertex " << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
    f << "  endloop\n endfacet\n";
  }
  f << "endsolid s\n";
}

/// Outward triangles of the box [lo, lo + size].
inline std::vector<Tri> box_triangles(preprocess::Vec3 lo, preprocess::Vec3 s) {
  auto P = [&](int i, int j, int k) {
    return preprocess::Vec3{lo[0] + i * s[0], lo[1] + j * s[1], lo[2] + k * s[2]};
  };
  std::vector<Tri> t;
  auto quad = [&](preprocess::Vec3 a, preprocess::Vec3 b, preprocess::Vec3 c, preprocess::Vec3 d) {
    t.push_back({a, b, c});
    t.push_back({a, c, d});
  };
  quad(P(0, 0, 0), P(0, 1, 0), P(1, 1, 0), P(1, 0, 0));  // z = 0, normal -z
  quad(P(0, 0, 1), P(1, 0, 1), P(1, 1, 1), P(0, 1, 1));  // z = 1
  quad(P(0, 0, 0), P(1, 0, 0), P(1, 0, 1), P(0, 0, 1));  // y = 0
  quad(P(0, 1, 0), P(0, 1, 1), P(1, 1, 1), P(1, 1, 0));  // y = 1
  quad(P(0, 0, 0), P(0, 0, 1), P(0, 1, 1), P(0, 1, 0));  // x = 0
  quad(P(1, 0, 0), P(1, 1, 0), P(1, 1, 1), P(1, 0, 1));  // x = 1
  return t;
}

/// Icosphere of radius r about c with `levels` subdivisions (20·4^levels triangles).
inline std::vector<Tri> icosphere(preprocess::Vec3 c, double r, int levels) {
  using V = preprocess::Vec3;
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<V> v = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                      {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  auto norm = [](V p) {
    const double n = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    return V{p[0] / n, p[1] / n, p[2] / n};
  };
  for (auto& p : v) p = norm(p);
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto m = [&](int a, int b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back(norm({(v[a][0] + v[b][0]) / 2, (v[a][1] + v[b][1]) / 2, (v[a][2] + v[b][2]) / 2}));
      return mid[key] = int(v.size() - 1);
    };
    std::vector<std::array<int, 3>> g;
    for (auto [a, b, cc] : f) {
      const int ab = m(a, b), bc = m(b, cc), ca = m(cc, a);
      g.push_back({a, ab, ca});
      g.push_back({b, bc, ab});
      g.push_back({cc, ca, bc});
      g.push_back({ab, bc, ca});
    }
    f = std::move(g);
  }
  std::vector<Tri> out;
  for (auto [a, b, cc] : f) {
    auto P = [&](int i) { return V{c[0] + r * v[i][0], c[1] + r * v[i][1], c[2] + r * v[i][2]}; };
    out.push_back({P(a), P(b), P(cc)});
  }
  return out;
}

}  // namespace strata::test
