// OpenCascade's BRepExtrema_DistShapeShape on CAD models: the distance from
// each query point (a vertex) to the model's faces, the way a user checks a
// point against a part with OpenCascade. The faces are loaded once per
// worker (LoadS2), each point then only sets the vertex and performs.
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRep_Builder.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS_Compound.hxx>

#include <string>

#include "bench/peers/peer.h"
#include "cad/shape_reader.h"

namespace invmap::bench {
namespace {

class ExtremaWorker : public PeerWorker {
 public:
  explicit ExtremaWorker(const TopoDS_Shape& faces) { extrema_.LoadS2(faces); }
  void Query(const double* point, PeerAnswer* answer) override {
    try {
      extrema_.LoadS1(BRepBuilderAPI_MakeVertex(gp_Pnt(point[0], point[1], point[2])).Vertex());
      answer->failed = !extrema_.Perform() || extrema_.NbSolution() == 0;
      if (!answer->failed) answer->distance = extrema_.Value();
    } catch (const Standard_Failure&) {
      answer->failed = true;
    }
  }

 private:
  BRepExtrema_DistShapeShape extrema_;
};

class ExtremaMethod : public PeerMethod {
 public:
  explicit ExtremaMethod(const std::string& path) {
    // The boundary: a compound of the faces (a solid would measure 0 inside),
    // of the shape as invmap reads it (the same default readers).
    std::string format;
    const TopoDS_Shape shape = cad::ReadCadShape(path, &format);
    TopTools_IndexedMapOfShape map;
    TopExp::MapShapes(shape, TopAbs_FACE, map);
    BRep_Builder builder;
    builder.MakeCompound(faces_);
    for (int i = 1; i <= map.Extent(); ++i) builder.Add(faces_, map(i));
  }
  std::string name() const override { return "OCC BRepExtrema_DistShapeShape"; }
  bool threadSafe() const override { return false; }
  std::unique_ptr<PeerWorker> NewWorker() override { return std::make_unique<ExtremaWorker>(faces_); }
  std::string note() const override {
    return "a vertex per point against the compound of the model's faces, loaded once (LoadS2), default "
           "precision";
  }

 private:
  TopoDS_Compound faces_;
};

}  // namespace

PeerList MakeOccCadPeers(const GeometryCase& geometryCase) {
  PeerList peers;
  if (geometryCase.kind == CaseKind::CadModel) {
    const std::string path = geometryCase.cadPath;
    peers.push_back([path] { return std::make_unique<ExtremaMethod>(path); });
  }
  return peers;
}

}  // namespace invmap::bench
