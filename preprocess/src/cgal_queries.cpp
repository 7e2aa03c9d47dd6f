// CGAL: exact predicates, closed surfaces (STL/OFF) and boundary distance queries.
#include "cgal_queries.hpp"

#include <strata/config.hpp>
#include <strata/core/error.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#if STRATA_WITH_CGAL
#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Aff_transformation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/IO/polygon_mesh_io.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/transform.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#endif

namespace strata::preprocess {

#if STRATA_WITH_CGAL
namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using P3 = K::Point_3;
using Mesh = CGAL::Surface_mesh<P3>;
P3 p3(const Vec3& p) { return {p[0], p[1], p[2]}; }
}  // namespace

struct ClosedSurface {
  Mesh mesh;
  std::unique_ptr<CGAL::Side_of_triangle_mesh<Mesh, K>> inside;
  double volume = 0;
  Bounds bounds;
};
#else
struct ClosedSurface {};
#endif

namespace detail {

int orient3d_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p) {
#if STRATA_WITH_CGAL
  return static_cast<int>(CGAL::orientation(p3(a), p3(b), p3(c), p3(p)));
#else
  using L = long double;
  const L m[3][3] = {{L(b[0]) - a[0], L(b[1]) - a[1], L(b[2]) - a[2]},
                     {L(c[0]) - a[0], L(c[1]) - a[1], L(c[2]) - a[2]},
                     {L(p[0]) - a[0], L(p[1]) - a[1], L(p[2]) - a[2]}};
  const L det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  return (det > 0) - (det < 0);
#endif
}

int orient2d_exact(double au, double av, double bu, double bv, double cu, double cv) {
#if STRATA_WITH_CGAL
  return static_cast<int>(CGAL::orientation(K::Point_2(au, av), K::Point_2(bu, bv), K::Point_2(cu, cv)));
#else
  using L = long double;
  const L det = (L(bu) - au) * (L(cv) - av) - (L(bv) - av) * (L(cu) - au);
  return (det > 0) - (det < 0);
#endif
}

std::shared_ptr<const ClosedSurface> read_closed_surface(const std::filesystem::path& file, double unit) {
#if STRATA_WITH_CGAL
  namespace PMP = CGAL::Polygon_mesh_processing;
  auto s = std::make_shared<ClosedSurface>();
  bool ok = false;
  try {
    ok = PMP::IO::read_polygon_mesh(file.string(), s->mesh);
  } catch (const std::exception& e) {
    fail(ErrorKind::Input,
         "{}: CGAL cannot read this surface ({}); allowed: a closed triangle surface in "
         "ASCII or binary STL, or OFF",
         file.string(), e.what());
  }
  STRATA_CHECK(ok && s->mesh.number_of_faces() > 0, Input,
               "{}: CGAL cannot read a surface from this file (empty, or not valid {}); allowed: a closed "
               "triangle surface in ASCII or binary STL, or OFF",
               file.string(), file.extension().string());
  if (!CGAL::is_triangle_mesh(s->mesh)) PMP::triangulate_faces(s->mesh);
  if (unit != 1.0) PMP::transform(CGAL::Aff_transformation_3<K>(CGAL::SCALING, unit), s->mesh);
  std::size_t border = 0;
  for (auto h : s->mesh.halfedges())
    if (s->mesh.is_border(h)) ++border;
  STRATA_CHECK(border == 0, Input,
               "{}: the surface is not closed: {} edges belong to one triangle only (holes or cracks in the "
               "surface); a region from an STL/OFF file must be a closed (watertight) surface",
               file.string(), border);
  s->volume = PMP::volume(s->mesh);
  if (s->volume < 0) {
    PMP::reverse_face_orientations(s->mesh);
    s->volume = -s->volume;
  }
  STRATA_CHECK(s->volume > 0, Input, "{}: the closed surface encloses no volume", file.string());
  const auto bb = CGAL::Polygon_mesh_processing::bbox(s->mesh);
  s->bounds.lo = {bb.xmin(), bb.ymin(), bb.zmin()};
  s->bounds.hi = {bb.xmax(), bb.ymax(), bb.zmax()};
  s->inside = std::make_unique<CGAL::Side_of_triangle_mesh<Mesh, K>>(s->mesh);
  (void)(*s->inside)(P3(s->bounds.lo[0] - 1, 0, 0));  // builds the AABB tree now, before any threads
  return s;
#else
  fail_missing_feature("STRATA_WITH_CGAL",
                       fmt::format("closed surfaces (.stl, .off) such as {}", file.string()));
#endif
}

bool surface_contains(const ClosedSurface& s, const Vec3& p) {
#if STRATA_WITH_CGAL
  return (*s.inside)(p3(p)) != CGAL::ON_UNBOUNDED_SIDE;
#else
  return false;
#endif
}

double surface_volume(const ClosedSurface& s) {
#if STRATA_WITH_CGAL
  return s.volume;
#else
  return 0;
#endif
}

Bounds surface_bounds(const ClosedSurface& s) {
#if STRATA_WITH_CGAL
  return s.bounds;
#else
  return {};
#endif
}

SimplexMesh surface_triangles(const ClosedSurface& s) {
  SimplexMesh m;
  m.dim = 2;
#if STRATA_WITH_CGAL
  for (auto v : s.mesh.vertices()) {
    const auto& p = s.mesh.point(v);
    m.add_node({p.x(), p.y(), p.z()});
  }
  for (auto f : s.mesh.faces())
    for (auto v : CGAL::vertices_around_face(s.mesh.halfedge(f), s.mesh))
      m.cells.push_back(std::uint32_t(v.idx()));
#endif
  return m;
}

}  // namespace detail

// ---- BoundaryDistance --------------------------------------------------------------------

#if STRATA_WITH_CGAL
struct BoundaryDistance::Impl {
  using Tri = K::Triangle_3;
  using Seg = K::Segment_3;
  using TriTree = CGAL::AABB_tree<
      CGAL::AABB_traits<K, CGAL::AABB_triangle_primitive<K, std::vector<Tri>::const_iterator>>>;
  using SegTree = CGAL::AABB_tree<
      CGAL::AABB_traits<K, CGAL::AABB_segment_primitive<K, std::vector<Seg>::const_iterator>>>;
  SimplexMesh facets;
  std::vector<Tri> tris;
  std::vector<Seg> segs;
  std::unique_ptr<TriTree> tri_tree;
  std::unique_ptr<SegTree> seg_tree;
};

BoundaryDistance::BoundaryDistance(const SimplexMesh& f) : impl_(std::make_unique<Impl>()) {
  impl_->facets = f;
  const std::size_t n = f.cell_count();
  auto pt = [&](std::size_t e, int k) { return p3(f.node(f.cells[e * f.nodes_per_cell() + k])); };
  if (f.dim == 1) {
    for (std::size_t e = 0; e < n; ++e) impl_->segs.emplace_back(pt(e, 0), pt(e, 1));
    impl_->seg_tree = std::make_unique<Impl::SegTree>(impl_->segs.begin(), impl_->segs.end());
    impl_->seg_tree->accelerate_distance_queries();
    if (n) (void)impl_->seg_tree->squared_distance(P3(0, 0, 0));  // build the search tree now
  } else {
    for (std::size_t e = 0; e < n; ++e) impl_->tris.emplace_back(pt(e, 0), pt(e, 1), pt(e, 2));
    impl_->tri_tree = std::make_unique<Impl::TriTree>(impl_->tris.begin(), impl_->tris.end());
    impl_->tri_tree->accelerate_distance_queries();
    if (n) (void)impl_->tri_tree->squared_distance(P3(0, 0, 0));
  }
}

double BoundaryDistance::operator()(const Vec3& p) const {
  if (impl_->seg_tree && !impl_->segs.empty()) return std::sqrt(impl_->seg_tree->squared_distance(p3(p)));
  if (impl_->tri_tree && !impl_->tris.empty()) return std::sqrt(impl_->tri_tree->squared_distance(p3(p)));
  return std::numeric_limits<double>::infinity();
}

bool BoundaryDistance::near_box(const Vec3& lo, const Vec3& hi, double r) const {
  const CGAL::Bbox_3 box(lo[0] - r, lo[1] - r, lo[2] - r, hi[0] + r, hi[1] + r, hi[2] + r);
  if (impl_->seg_tree && !impl_->segs.empty()) return impl_->seg_tree->do_intersect(box);
  if (impl_->tri_tree && !impl_->tris.empty()) return impl_->tri_tree->do_intersect(box);
  return false;
}
void BoundaryDistance::facets_near_box(const Vec3& lo, const Vec3& hi, double r,
                                       std::vector<std::uint32_t>& out) const {
  out.clear();
  const CGAL::Bbox_3 box(lo[0] - r, lo[1] - r, lo[2] - r, hi[0] + r, hi[1] + r, hi[2] + r);
  if (impl_->seg_tree && !impl_->segs.empty()) {
    std::vector<Impl::SegTree::Primitive_id> ids;
    impl_->seg_tree->all_intersected_primitives(box, std::back_inserter(ids));
    for (auto it : ids) out.push_back(std::uint32_t(it - impl_->segs.cbegin()));
  } else if (impl_->tri_tree && !impl_->tris.empty()) {
    std::vector<Impl::TriTree::Primitive_id> ids;
    impl_->tri_tree->all_intersected_primitives(box, std::back_inserter(ids));
    for (auto it : ids) out.push_back(std::uint32_t(it - impl_->tris.cbegin()));
  }
  std::sort(out.begin(), out.end());
}
#else
struct BoundaryDistance::Impl {
  SimplexMesh facets;
};
void BoundaryDistance::facets_near_box(const Vec3&, const Vec3&, double,
                                       std::vector<std::uint32_t>& out) const {
  out.resize(impl_->facets.cell_count());
  for (std::size_t e = 0; e < out.size(); ++e) out[e] = std::uint32_t(e);
}
BoundaryDistance::BoundaryDistance(const SimplexMesh& f) : impl_(std::make_unique<Impl>(Impl{f})) {}
double BoundaryDistance::operator()(const Vec3& p) const { return distance_to_facets(impl_->facets, p); }
bool BoundaryDistance::near_box(const Vec3&, const Vec3&, double) const { return true; }
#endif

BoundaryDistance::~BoundaryDistance() = default;

const SimplexMesh& BoundaryDistance::facets() const { return impl_->facets; }

double BoundaryDistance::distance_to(const std::vector<std::uint32_t>& facets, const Vec3& p) const {
  double best = std::numeric_limits<double>::infinity();
  for (auto e : facets) best = std::min(best, distance_to_facet(impl_->facets, e, p));
  return best;
}

}  // namespace strata::preprocess
