// OpenCascade's point-to-shape distance, set up once per model: the
// extrema BRepExtrema_DistShapeShape computes between a vertex and each
// face, edge and vertex of the boundary, without its per-call set-up.
#pragma once

#include <BRepExtrema_ExtPC.hxx>
#include <BRepExtrema_ExtPF.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <gp_Pnt.hxx>

#include <memory>
#include <vector>

namespace invmap::cadtest {

/// The least distance from a point to a boundary given as its faces: the
/// least of BRepExtrema_ExtPF's minima on each face (the surface's extrema
/// its face classifier keeps), BRepExtrema_ExtPC's on each edge, and the
/// distances to the vertices. These are the extrema DistShapeShape takes
/// the least of between a vertex and the same faces; here each face's and
/// edge's extrema are initialised once (the face's sampling grid is the
/// costly part of a DistShapeShape call), and an item whose bounding box
/// (OpenCascade's, from the geometry and tolerances, never from a mesh) is
/// farther than the best distance so far is skipped: it cannot hold the
/// minimum. Not thread-safe: one object per thread.
class OccNearest {
 public:
  explicit OccNearest(const std::vector<TopoDS_Face>& faces);
  ~OccNearest();

  /// The distance from `point` (3 coordinates) to the boundary.
  double Distance(const double* point);

 private:
  struct Item;
  std::vector<Item> items_;
  std::vector<std::unique_ptr<BRepExtrema_ExtPF>> faceExtrema_;  ///< Built the first time a point needs the face.
  std::vector<std::unique_ptr<BRepExtrema_ExtPC>> edgeExtrema_;
  std::vector<TopoDS_Face> faces_;
  std::vector<TopoDS_Edge> edges_;
  std::vector<gp_Pnt> vertices_;
  std::vector<std::pair<double, int>> order_;  ///< Per query: (box distance squared, item).
};

}  // namespace invmap::cadtest
