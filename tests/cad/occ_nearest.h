// OpenCascade's point-to-shape distance, set up once per model: the
// extrema BRepExtrema_DistShapeShape computes between a vertex and each
// face, edge and vertex of the boundary, without its per-call set-up.
#pragma once

#include <BRepAdaptor_Surface.hxx>
#include <BRepExtrema_ExtPC.hxx>
#include <Extrema_ExtPS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <gp_Pnt.hxx>

#include <memory>
#include <vector>

namespace invmap::cadtest {

/// The least distance from a point to a boundary given as its faces: the
/// least of the surface's extrema on each face that its face classifier
/// puts inside it (BRepExtrema_ExtPF's, without those on the face's
/// boundary, as DistShapeShape takes them), BRepExtrema_ExtPC's on each
/// edge, and the distances to the vertices. These are the extrema
/// DistShapeShape takes the least of between a vertex and the same faces.
/// Here each face's and edge's extrema are initialised once (the face's
/// sampling grid is the costly part of a DistShapeShape call), and an item
/// whose bounding box (OpenCascade's, from the geometry and tolerances,
/// never from a mesh) is farther than the best distance so far is skipped:
/// it cannot hold the minimum.
///
/// A B-spline face of many spans is searched in pieces of at most 16 x 16
/// of its spans, each grown by one span on every side (so every stationary
/// point inside the face lies inside a piece, not on its rim), each with its
/// own box and extrema: the sampling grid OpenCascade passes over per point
/// covers the whole surface, 30 ms a point on a face of 100,000 spans.
/// Not thread-safe: one object per thread.
class OccNearest {
 public:
  explicit OccNearest(const std::vector<TopoDS_Face>& faces);
  ~OccNearest();

  /// The distance from `point` (3 coordinates) to the boundary.
  double Distance(const double* point);

 private:
  /// A face, or a piece of its parameter box, searched by one Extrema_ExtPS.
  struct FacePiece {
    int face;
    double u0, u1, v0, v1;
    std::unique_ptr<Extrema_ExtPS> extrema;  ///< Built the first time a point needs the piece.
  };
  struct Item;

  void AddFacePieces(int face);
  void SearchPiece(FacePiece& piece, const gp_Pnt& point, double* best);

  std::vector<Item> items_;
  std::vector<TopoDS_Face> faces_;
  std::vector<Handle(BRepAdaptor_Surface)> surfaces_;  ///< Per face; the extrema keep a pointer to it.
  std::vector<FacePiece> pieces_;
  std::vector<TopoDS_Edge> edges_;
  std::vector<std::unique_ptr<BRepExtrema_ExtPC>> edgeExtrema_;  ///< Built the first time a point needs the edge.
  std::vector<gp_Pnt> vertices_;
  std::vector<std::pair<double, int>> order_;  ///< Per query: (box distance squared, item).
};

}  // namespace invmap::cadtest
