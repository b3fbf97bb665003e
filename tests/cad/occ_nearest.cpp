#include "tests/cad/occ_nearest.h"

#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepClass_FaceClassifier.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <BndLib_AddSurface.hxx>
#include <Bnd_Box.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Precision.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Vertex.hxx>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace invmap::cadtest {

struct OccNearest::Item {
  enum class Kind { FacePiece, Edge, Vertex } kind;
  int index;
  bool bounded;  ///< False when OpenCascade gives no box: always searched.
  double lo[3], hi[3];
};

namespace {

bool CornersOf(const Bnd_Box& box, double* lo, double* hi) {
  if (box.IsVoid() || box.IsOpen()) return false;
  box.Get(lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
  return true;
}

/// The shape's box from its geometry and tolerances: BndLib bounds curves
/// and surfaces by their exact extents or control points, so the box holds
/// the whole shape (a box from a mesh might not).
bool GeometryBox(const TopoDS_Shape& shape, double* lo, double* hi) {
  Bnd_Box box;
  BRepBndLib::Add(shape, box, /*useTriangulation=*/false);
  return CornersOf(box, lo, hi);
}

/// A B-spline face is cut into pieces of at most this many spans a side.
constexpr int kPieceSpans = 16;

/// The ends of the spans of [first, last] along one direction: first, the
/// knots strictly inside, last.
std::vector<double> KnotsWithin(const TColStd_Array1OfReal& knots, double first, double last) {
  std::vector<double> inside = {first};
  for (int i = knots.Lower(); i <= knots.Upper(); ++i) {
    if (knots(i) > first && knots(i) < last) inside.push_back(knots(i));
  }
  inside.push_back(last);
  return inside;
}

/// Piece k of `knots` (as from KnotsWithin): spans [k * kPieceSpans,
/// (k + 1) * kPieceSpans] grown by one span on each side where there is one.
std::pair<double, double> PieceRange(const std::vector<double>& knots, int k) {
  const int last = static_cast<int>(knots.size()) - 1;
  const int from = std::max(0, k * kPieceSpans - 1);
  const int to = std::min(last, (k + 1) * kPieceSpans + 1);
  return {knots[from], knots[to]};
}

int PieceCount(const std::vector<double>& knots) {
  const int spans = static_cast<int>(knots.size()) - 1;
  return (spans + kPieceSpans - 1) / kPieceSpans;
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
  edgeExtrema_.resize(edges_.size());
  auto add = [&](Item::Kind kind, int index, const TopoDS_Shape& shape) {
    Item item{kind, index, false, {}, {}};
    item.bounded = GeometryBox(shape, item.lo, item.hi);
    items_.push_back(item);
  };
  for (std::size_t i = 0; i < faces_.size(); ++i) AddFacePieces(static_cast<int>(i));
  for (std::size_t i = 0; i < edges_.size(); ++i) add(Item::Kind::Edge, static_cast<int>(i), edges_[i]);
  for (std::size_t i = 0; i < vertices_.size(); ++i) {
    Item item{Item::Kind::Vertex, static_cast<int>(i), true, {}, {}};
    vertices_[i].Coord(item.lo[0], item.lo[1], item.lo[2]);
    std::copy(item.lo, item.lo + 3, item.hi);
    items_.push_back(item);
  }
}

OccNearest::~OccNearest() = default;

void OccNearest::AddFacePieces(int face) {
  surfaces_.push_back(new BRepAdaptor_Surface(faces_[face], /*restriction=*/false));  // as BRepExtrema_ExtPF
  const BRepAdaptor_Surface& surface = *surfaces_.back();
  double u0, u1, v0, v1;
  BRepTools::UVBounds(faces_[face], u0, u1, v0, v1);
  std::vector<double> uKnots = {u0, u1}, vKnots = {v0, v1};
  if (surface.GetType() == GeomAbs_BSplineSurface) {
    const Handle(Geom_BSplineSurface) spline = surface.BSpline();
    uKnots = KnotsWithin(spline->UKnots(), u0, u1);
    vKnots = KnotsWithin(spline->VKnots(), v0, v1);
  }
  const bool whole = PieceCount(uKnots) == 1 && PieceCount(vKnots) == 1;
  for (int i = 0; i < PieceCount(uKnots); ++i) {
    for (int j = 0; j < PieceCount(vKnots); ++j) {
      const auto [pu0, pu1] = PieceRange(uKnots, i);
      const auto [pv0, pv1] = PieceRange(vKnots, j);
      Item item{Item::Kind::FacePiece, static_cast<int>(pieces_.size()), false, {}, {}};
      if (whole) {
        item.bounded = GeometryBox(faces_[face], item.lo, item.hi);
      } else {
        Bnd_Box box;
        BndLib_AddSurface::Add(surface, pu0, pu1, pv0, pv1, BRep_Tool::Tolerance(faces_[face]), box);
        item.bounded = CornersOf(box, item.lo, item.hi);
      }
      items_.push_back(item);
      pieces_.push_back({face, pu0, pu1, pv0, pv1, nullptr});
    }
  }
}

// BRepExtrema_ExtPF's steps over the piece's range: the surface's extrema
// (its tolerances, DistShapeShape's flag and algorithm), those the face's
// classifier puts inside the face. As in DistShapeShape, not those it finds
// on the boundary: there the edges and vertices answer (a point of the
// surface within the tolerance beyond an edge is no point of the model).
void OccNearest::SearchPiece(FacePiece& piece, const gp_Pnt& point, double* best) {
  const TopoDS_Face& face = faces_[piece.face];
  const BRepAdaptor_Surface& surface = *surfaces_[piece.face];
  if (surface.GetType() == GeomAbs_OtherSurface) return;  // as ExtPF: no geometry to search
  if (!piece.extrema) {
    const double tolerance = std::min(BRep_Tool::Tolerance(face), Precision::Confusion());
    piece.extrema = std::make_unique<Extrema_ExtPS>();
    piece.extrema->SetFlag(Extrema_ExtFlag_MINMAX);
    piece.extrema->SetAlgo(Extrema_ExtAlgo_Grad);
    piece.extrema->Initialize(surface, piece.u0, piece.u1, piece.v0, piece.v1,
                              std::max(surface.UResolution(tolerance), Precision::PConfusion()),
                              std::max(surface.VResolution(tolerance), Precision::PConfusion()));
  }
  piece.extrema->Perform(point);
  if (!piece.extrema->IsDone()) return;
  BRepClass_FaceClassifier classifier;
  for (int k = 1; k <= piece.extrema->NbExt(); ++k) {
    if (piece.extrema->SquareDistance(k) >= *best) continue;  // cannot lower the best: skip its classification
    double u, v;
    piece.extrema->Point(k).Parameter(u, v);
    classifier.Perform(face, gp_Pnt2d(u, v), BRep_Tool::Tolerance(face));
    if (classifier.State() == TopAbs_IN) *best = piece.extrema->SquareDistance(k);
  }
}

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
      case Item::Kind::FacePiece:
        SearchPiece(pieces_[item.index], p, &best);
        break;
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
