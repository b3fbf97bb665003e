#include "tests/cad/occ_reference.h"

#include "tests/cad/occ_nearest.h"

#include <BRepAdaptor_Curve.hxx>
#include <BRepBndLib.hxx>
#include <BRepGProp.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepClass_FaceClassifier.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <GProp_GProps.hxx>
#include <IGESControl_Reader.hxx>
#include <Poly_Triangulation.hxx>
#include <STEPControl_Reader.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Vertex.hxx>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <sstream>
#include <thread>

namespace invmap::cadtest {

std::string ScratchDir() {
  static const std::string dir = [] {
    const std::filesystem::path path =
        std::filesystem::temp_directory_path() / ("invmap_cad_tests_" + std::to_string(getpid()));
    std::filesystem::create_directories(path);
    return path.string();
  }();
  return dir;
}

std::unique_ptr<cad::Model> LoadShape(const TopoDS_Shape& shape, const std::string& name) {
  const std::string path = ScratchDir() + "/" + name + ".brep";
  EXPECT_TRUE(BRepTools::Write(shape, path.c_str()));
  cad::LoadResult loaded = cad::Model::Load(path);
  EXPECT_EQ(loaded.error, "") << path;
  return std::move(loaded.model);
}

TopoDS_Shape ReadShape(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext == ".step" || ext == ".stp") {
    STEPControl_Reader reader;
    reader.ReadFile(path.c_str());
    reader.TransferRoots();
    return reader.OneShape();
  }
  if (ext == ".iges" || ext == ".igs") {
    IGESControl_Reader reader;
    reader.ReadFile(path.c_str());
    reader.TransferRoots();
    return reader.OneShape();
  }
  TopoDS_Shape shape;
  BRep_Builder builder;
  BRepTools::Read(shape, path.c_str(), builder);
  return shape;
}

std::vector<TopoDS_Face> Faces(const TopoDS_Shape& shape) {
  TopTools_IndexedMapOfShape map;
  TopExp::MapShapes(shape, TopAbs_FACE, map);
  std::vector<TopoDS_Face> faces;
  for (int i = 1; i <= map.Extent(); ++i) faces.push_back(TopoDS::Face(map(i)));
  return faces;
}

TopoDS_Compound Compound(const std::vector<TopoDS_Face>& faces) {
  TopoDS_Compound compound;
  BRep_Builder builder;
  builder.MakeCompound(compound);
  for (const TopoDS_Face& face : faces) builder.Add(compound, face);
  return compound;
}

TopoDS_Compound CompoundOf(std::initializer_list<TopoDS_Shape> shapes) {
  TopoDS_Compound compound;
  BRep_Builder builder;
  builder.MakeCompound(compound);
  for (const TopoDS_Shape& shape : shapes) builder.Add(compound, shape);
  return compound;
}

double OccDistance(const TopoDS_Shape& shape, const double* point) {
  const TopoDS_Vertex vertex = BRepBuilderAPI_MakeVertex(gp_Pnt(point[0], point[1], point[2])).Vertex();
  BRepExtrema_DistShapeShape distance(vertex, shape);
  return distance.IsDone() ? distance.Value() : std::nan("");
}

double ShapeSize(const TopoDS_Shape& shape) {
  Bnd_Box box;
  BRepBndLib::AddOptimal(shape, box, false, false);
  return std::sqrt(box.SquareExtent());
}

std::vector<double> PointsAround(const TopoDS_Shape& shape, std::size_t count, double near, double far,
                                 unsigned seed, std::size_t farEvery) {
  return PointsAround(shape, count, std::vector<double>{near}, far, seed, farEvery);
}

std::vector<double> PointsAround(const TopoDS_Shape& shape, std::size_t count, const std::vector<double>& nears,
                                 double far, unsigned seed, std::size_t farEvery) {
  Bnd_Box box;
  BRepBndLib::AddOptimal(shape, box, false, false);
  double lo[3], hi[3];
  box.Get(lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
  const double size = std::sqrt(box.SquareExtent());
  // Triangles of a coarse mesh, weighted by area, for points near the surface.
  BRepMesh_IncrementalMesh mesher(shape, 0.01 * size, false, 0.5);
  std::vector<gp_Pnt> corners;
  std::vector<double> cumulative;
  for (const TopoDS_Face& face : Faces(shape)) {
    TopLoc_Location location;
    const Handle(Poly_Triangulation) mesh = BRep_Tool::Triangulation(face, location);
    if (mesh.IsNull()) continue;
    for (int t = 1; t <= mesh->NbTriangles(); ++t) {
      int a, b, c;
      mesh->Triangle(t).Get(a, b, c);
      const gp_Pnt pa = mesh->Node(a).Transformed(location), pb = mesh->Node(b).Transformed(location),
                   pc = mesh->Node(c).Transformed(location);
      const double area = 0.5 * gp_Vec(pa, pb).Crossed(gp_Vec(pa, pc)).Magnitude();
      corners.insert(corners.end(), {pa, pb, pc});
      cumulative.push_back((cumulative.empty() ? 0.0 : cumulative.back()) + area);
    }
  }
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<double> points;
  std::size_t nearCount = 0;
  for (std::size_t i = 0; i < count; ++i) {
    if (i % farEvery != farEvery - 1 && !cumulative.empty()) {
      const double near = nears[nearCount++ % nears.size()];
      const double pick = unit(rng) * cumulative.back();
      const std::size_t t = std::lower_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin();
      double s = unit(rng), r = unit(rng);
      if (s + r > 1.0) {
        s = 1.0 - s;
        r = 1.0 - r;
      }
      const gp_Pnt& a = corners[3 * t];
      gp_XYZ p = a.XYZ() + s * (corners[3 * t + 1].XYZ() - a.XYZ()) + r * (corners[3 * t + 2].XYZ() - a.XYZ());
      const gp_XYZ direction(gauss(rng), gauss(rng), gauss(rng));
      p += direction.Normalized() * (near * size * unit(rng));
      points.insert(points.end(), {p.X(), p.Y(), p.Z()});
    } else {
      for (int k = 0; k < 3; ++k) points.push_back(lo[k] - far * size + unit(rng) * (hi[k] - lo[k] + 2.0 * far * size));
    }
  }
  return points;
}

std::vector<double> PointsNearEdges(const TopoDS_Shape& shape, std::size_t count, const std::vector<double>& nears,
                                    unsigned seed) {
  const double size = ShapeSize(shape);
  TopTools_IndexedMapOfShape map;
  TopExp::MapShapes(shape, TopAbs_EDGE, map);
  std::vector<BRepAdaptor_Curve> curves;
  std::vector<double> cumulative;
  for (int i = 1; i <= map.Extent(); ++i) {
    const TopoDS_Edge& edge = TopoDS::Edge(map(i));
    if (BRep_Tool::Degenerated(edge)) continue;
    GProp_GProps properties;
    BRepGProp::LinearProperties(edge, properties);
    curves.emplace_back(edge);
    cumulative.push_back((cumulative.empty() ? 0.0 : cumulative.back()) + properties.Mass());
  }
  std::vector<double> points;
  if (curves.empty() || !(cumulative.back() > 0.0)) return points;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (std::size_t i = 0; i < count; ++i) {
    const double pick = unit(rng) * cumulative.back();
    const std::size_t e = std::lower_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin();
    const BRepAdaptor_Curve& curve = curves[std::min(e, curves.size() - 1)];
    gp_XYZ p = curve.Value(curve.FirstParameter() + unit(rng) * (curve.LastParameter() - curve.FirstParameter())).XYZ();
    const gp_XYZ direction(gauss(rng), gauss(rng), gauss(rng));
    p += direction.Normalized() * (nears[i % nears.size()] * size * unit(rng));
    points.insert(points.end(), {p.X(), p.Y(), p.Z()});
  }
  return points;
}

FaceSamples SampleFaces(const std::vector<TopoDS_Face>& faces, int grid) {
  FaceSamples samples;
  for (const TopoDS_Face& face : faces) {
    double u0, u1, v0, v1;
    BRepTools::UVBounds(face, u0, u1, v0, v1);
    const Handle(Geom_Surface) surface = BRep_Tool::Surface(face);
    for (int j = 0; j <= grid; ++j) {
      for (int i = 0; i <= grid; ++i) {
        const double u = u0 + (u1 - u0) * i / grid, v = v0 + (v1 - v0) * j / grid;
        const gp_Pnt p = surface->Value(u, v);
        samples.spacing = std::max({samples.spacing, p.Distance(surface->Value(u + (u1 - u0) / grid, v)),
                                    p.Distance(surface->Value(u, v + (v1 - v0) / grid))});
        BRepClass_FaceClassifier classifier(face, gp_Pnt2d(u, v), 1e-9);
        if (classifier.State() != TopAbs_OUT) samples.points.push_back(p);
      }
    }
    for (TopExp_Explorer it(face, TopAbs_EDGE); it.More(); it.Next()) {
      double first, last;
      const Handle(Geom_Curve) curve = BRep_Tool::Curve(TopoDS::Edge(it.Current()), first, last);
      if (curve.IsNull()) continue;
      for (int k = 0; k <= 4 * grid; ++k) {
        samples.points.push_back(curve->Value(first + (last - first) * k / (4 * grid)));
        samples.onEdge.push_back(samples.points.size() - 1);
        if (k > 0) {
          const gp_Pnt& previous = samples.points[samples.points.size() - 2];
          samples.edgeSpacing = std::max(samples.edgeSpacing, samples.points.back().Distance(previous));
        }
      }
    }
  }
  return samples;
}

Results InvertOnModel(const cad::Model& model, const std::vector<double>& points) {
  return InvertOnGeometry(model.geometry(), points);
}

Results InvertOnGeometry(const Geometry& geometry, const std::vector<double>& points, Manifold* kept) {
  BuildResult built = Manifold::Build(geometry);
  EXPECT_EQ(built.error, "");
  Results results;
  InversionOptions options;
  options.threads = 1;
  EXPECT_EQ(built.manifold.Invert(PointsView::Interleaved(points.data(), points.size() / 3, 3), options, &results),
            Error::Ok);
  if (kept) *kept = std::move(built.manifold);
  return results;
}

double FaceTolerance(const TopoDS_Face& face) {
  double tolerance = BRep_Tool::Tolerance(face);
  for (TopExp_Explorer it(face, TopAbs_EDGE); it.More(); it.Next()) {
    tolerance = std::max(tolerance, BRep_Tool::Tolerance(TopoDS::Edge(it.Current())));
  }
  for (TopExp_Explorer it(face, TopAbs_VERTEX); it.More(); it.Next()) {
    tolerance = std::max(tolerance, BRep_Tool::Tolerance(TopoDS::Vertex(it.Current())));
  }
  // And how far the edges' curves actually lie from the face's surface
  // through their pcurves (some files' edges exceed their own tolerance).
  const Handle(Geom_Surface) surface = BRep_Tool::Surface(face);
  for (TopExp_Explorer it(face, TopAbs_EDGE); it.More(); it.Next()) {
    const TopoDS_Edge& edge = TopoDS::Edge(it.Current());
    double first, last, pFirst, pLast;
    const Handle(Geom_Curve) curve = BRep_Tool::Curve(edge, first, last);
    const Handle(Geom2d_Curve) pcurve = BRep_Tool::CurveOnSurface(edge, face, pFirst, pLast);
    if (curve.IsNull() || pcurve.IsNull()) continue;
    for (int k = 0; k <= 64; ++k) {
      const double t = first + (last - first) * k / 64.0;
      const gp_Pnt2d uv = pcurve->Value(t);
      tolerance = std::max(tolerance, curve->Value(t).Distance(surface->Value(uv.X(), uv.Y())));
    }
  }
  return tolerance;
}

Comparison CheckAgainstOpenCascade(const TopoDS_Shape& shape, const cad::Model& model,
                                   const std::vector<double>& points, double tolerance) {
  const std::vector<TopoDS_Face> faces = Faces(shape);
  std::vector<double> faceTolerance;
  for (const TopoDS_Face& face : faces) faceTolerance.push_back(FaceTolerance(face));
  const double size = ShapeSize(shape);
  const Results results = InvertOnModel(model, points);
  const std::size_t n = points.size() / 3;
  // OpenCascade's answers, two threads (each with its own extrema objects).
  std::vector<double> occ(n), onFace(n), parameterGap(n);
  auto work = [&](std::size_t first, std::size_t step) {
    OccNearest nearest(faces);
    for (std::size_t i = first; i < n; i += step) {
      occ[i] = nearest.Distance(&points[3 * i]);
      if (results.status[i] != Status::Found) continue;
      // On the face: its surface at the reported (u, v) is the reported
      // point, and the face classifier keeps (u, v).
      const TopoDS_Face& face = faces[results.patch[i]];
      const double* x = &results.closest[3 * i];
      const gp_Pnt2d uv(results.params[3 * i], results.params[3 * i + 1]);
      const gp_Pnt at = BRep_Tool::Surface(face)->Value(uv.X(), uv.Y());
      parameterGap[i] = at.Distance(gp_Pnt(x[0], x[1], x[2]));
      BRepClass_FaceClassifier classifier(face, uv, std::max(1e-9 * size, faceTolerance[results.patch[i]]));
      onFace[i] = classifier.State() == TopAbs_OUT ? 1.0 : 0.0;
    }
  };
  std::thread other(work, 1, 2);
  work(0, 2);
  other.join();
  Comparison c;
  for (std::size_t i = 0; i < n; ++i) {
    ++c.points;
    std::ostringstream why;
    if (results.status[i] != Status::Found) {
      ++c.notFound;
      why << "not found";
    } else {
      const double excess = (results.distance[i] - occ[i]) / size;
      c.worstExcess = std::max(c.worstExcess, excess);
      const double own = std::max(tolerance * size, 2.0 * faceTolerance[results.patch[i]]);
      if (excess > tolerance) {
        ++c.farther;
        why << "farther than OpenCascade by " << excess * size;
      }
      if (onFace[i] > 0.0) {
        ++c.offFace;
        why << " reported (u, v) outside face " << results.patch[i];
      }
      if (parameterGap[i] > own) {
        ++c.badParameters;
        why << " surface at (u, v) " << parameterGap[i] << " from the reported point";
      }
    }
    if (!why.str().empty() && c.firstFailure.empty()) {
      std::ostringstream failure;
      failure.precision(17);
      failure << "point " << i << " (" << points[3 * i] << ", " << points[3 * i + 1] << ", " << points[3 * i + 2]
              << "): " << why.str() << "; patch " << results.patch[i] << " cell " << results.cell[i] << " distance "
              << results.distance[i] << ", OpenCascade " << occ[i];
      c.firstFailure = failure.str();
    }
  }
  return c;
}

}  // namespace invmap::cadtest
