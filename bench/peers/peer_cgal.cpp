// CGAL peer: AABB_tree of the mesh's triangles with accelerated distance
// queries, closest_point_and_primitive per point.
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/version.h>

#include <cmath>

#include "bench/peers/peer.h"

namespace invmap::bench {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Triangles = std::vector<Kernel::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, Triangles::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

class CgalWorker : public PeerWorker {
 public:
  explicit CgalWorker(const Tree* tree) : tree_(tree) {}
  void Query(const double* point, PeerAnswer* answer) override {
    const Kernel::Point_3 p(point[0], point[1], point[2]);
    const auto closest = tree_->closest_point_and_primitive(p);
    answer->distance = std::sqrt(CGAL::squared_distance(p, closest.first));
    answer->failed = !std::isfinite(answer->distance);
  }

 private:
  const Tree* tree_;
};

class CgalMethod : public PeerMethod {
 public:
  explicit CgalMethod(const Patch& patch) {
    const std::size_t numTriangles = patch.cells.size() / 3;
    triangles_.reserve(numTriangles);
    auto vertex = [&](std::int64_t i) {
      return Kernel::Point_3(patch.points[3 * i], patch.points[3 * i + 1], patch.points[3 * i + 2]);
    };
    for (std::size_t t = 0; t < numTriangles; ++t) {
      triangles_.emplace_back(vertex(patch.cells[3 * t]), vertex(patch.cells[3 * t + 1]),
                              vertex(patch.cells[3 * t + 2]));
    }
    tree_.insert(triangles_.cbegin(), triangles_.cend());
    // Both builds up front: afterwards queries are const and read-only, so
    // threads can share the tree.
    tree_.build();
    tree_.accelerate_distance_queries();
  }
  std::string name() const override { return "CGAL AABB_tree closest_point_and_primitive"; }
  bool threadSafe() const override { return true; }
  std::unique_ptr<PeerWorker> NewWorker() override { return std::make_unique<CgalWorker>(&tree_); }
  std::string note() const override { return "Simple_cartesian<double>, accelerate_distance_queries()"; }

 private:
  Triangles triangles_;
  Tree tree_;
};

}  // namespace

std::string CgalVersion() { return std::string("CGAL ") + CGAL_VERSION_STR; }

PeerList MakeCgalPeers(const GeometryCase& geometryCase) {
  PeerList peers;
  if (geometryCase.kind == CaseKind::TriangleMesh) {
    const Patch& patch = geometryCase.geometry.patches[0];
    peers.push_back([&patch] { return std::make_unique<CgalMethod>(patch); });
  }
  return peers;
}

}  // namespace invmap::bench
