#include "tests/cad/occ_nearest.h"

#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Vertex.hxx>

#include <algorithm>
#include <cmath>
#include <limits>

namespace invmap::cadtest {

struct OccNearest::Item {
  enum class Kind { Face, Edge, Vertex } kind;
  int index;
  bool bounded;  ///< False when OpenCascade gives no box: always searched.
  double lo[3], hi[3];
};

namespace {

/// The shape's box from its geometry and tolerances: BndLib bounds curves
/// and surfaces by their exact extents or control points, so the box holds
/// the whole shape (a box from a mesh might not).
bool GeometryBox(const TopoDS_Shape& shape, double* lo, double* hi) {
  Bnd_Box box;
  BRepBndLib::Add(shape, box, /*useTriangulation=*/false);
  if (box.IsVoid() || box.IsOpen()) return false;
  box.Get(lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
  return true;
}

double SquaredDistanceToBox(const double* x, const double* lo, const double* hi) {
  double sum = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double gap = std::max({lo[k] - x[k], 0.0, x[k] - hi[k]});
    sum += gap * gap;
  }
  return sum;
}

}  // namespace

OccNearest::OccNearest(const std::vector<TopoDS_Face>& faces) : faces_(faces) {
  TopTools_IndexedMapOfShape edges, vertices;
  for (const TopoDS_Face& face : faces) {
    TopExp::MapShapes(face, TopAbs_EDGE, edges);
    TopExp::MapShapes(face, TopAbs_VERTEX, vertices);
  }
  for (int i = 1; i <= edges.Extent(); ++i) {
    const TopoDS_Edge& edge = TopoDS::Edge(edges(i));
    if (!BRep_Tool::Degenerated(edge)) edges_.push_back(edge);  // a point in space: its vertex answers
  }
  for (int i = 1; i <= vertices.Extent(); ++i) vertices_.push_back(BRep_Tool::Pnt(TopoDS::Vertex(vertices(i))));
  faceExtrema_.resize(faces_.size());
  edgeExtrema_.resize(edges_.size());
  auto add = [&](Item::Kind kind, int index, const TopoDS_Shape& shape) {
    Item item{kind, index, false, {}, {}};
    item.bounded = GeometryBox(shape, item.lo, item.hi);
    items_.push_back(item);
  };
  for (std::size_t i = 0; i < faces_.size(); ++i) add(Item::Kind::Face, static_cast<int>(i), faces_[i]);
  for (std::size_t i = 0; i < edges_.size(); ++i) add(Item::Kind::Edge, static_cast<int>(i), edges_[i]);
  for (std::size_t i = 0; i < vertices_.size(); ++i) {
    Item item{Item::Kind::Vertex, static_cast<int>(i), true, {}, {}};
    vertices_[i].Coord(item.lo[0], item.lo[1], item.lo[2]);
    std::copy(item.lo, item.lo + 3, item.hi);
    items_.push_back(item);
  }
}

OccNearest::~OccNearest() = default;

double OccNearest::Distance(const double* point) {
  order_.clear();
  for (std::size_t i = 0; i < items_.size(); ++i) {
    const Item& item = items_[i];
    order_.emplace_back(item.bounded ? SquaredDistanceToBox(point, item.lo, item.hi) : 0.0, static_cast<int>(i));
  }
  std::sort(order_.begin(), order_.end());
  const gp_Pnt p(point[0], point[1], point[2]);
  const TopoDS_Vertex vertex = BRepBuilderAPI_MakeVertex(p).Vertex();
  double best = std::numeric_limits<double>::infinity();  // squared
  for (const auto& [boxDistance, index] : order_) {
    if (boxDistance > best) break;  // this item and every later one lie farther than the best
    const Item& item = items_[index];
    switch (item.kind) {
      case Item::Kind::Face: {
        std::unique_ptr<BRepExtrema_ExtPF>& extrema = faceExtrema_[item.index];
        if (!extrema) {
          extrema = std::make_unique<BRepExtrema_ExtPF>();
          extrema->Initialize(faces_[item.index]);  // DistShapeShape's defaults: MINMAX, gradient
        }
        extrema->Perform(vertex, faces_[item.index]);
        if (!extrema->IsDone()) break;
        for (int k = 1; k <= extrema->NbExt(); ++k) best = std::min(best, extrema->SquareDistance(k));
        break;
      }
      case Item::Kind::Edge: {
        std::unique_ptr<BRepExtrema_ExtPC>& extrema = edgeExtrema_[item.index];
        if (!extrema) {
          extrema = std::make_unique<BRepExtrema_ExtPC>();
          extrema->Initialize(edges_[item.index]);
        }
        extrema->Perform(vertex);
        if (!extrema->IsDone()) break;
        for (int k = 1; k <= extrema->NbExt(); ++k) best = std::min(best, extrema->SquareDistance(k));
        break;
      }
      case Item::Kind::Vertex:
        best = std::min(best, p.SquareDistance(vertices_[item.index]));
        break;
    }
  }
  return std::sqrt(best);
}

}  // namespace invmap::cadtest
