// OpenCascade as the independent reference of the CAD tests: its distance
// queries, face classifier and meshing, and helpers to turn shapes the
// tests build into models invmap reads from files.
#pragma once

#include <TopoDS_Compound.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <gp_Pnt.hxx>

#include <initializer_list>
#include <memory>
#include <string>
#include <vector>

#include "cad/model.h"
#include "invmap/invmap.h"

namespace invmap::cadtest {

/// A scratch directory for this test process (created on first use).
std::string ScratchDir();

/// Writes `shape` as `name`.brep in the scratch directory and loads it the
/// way a user would (cad::Model::Load); fails the test on an error.
std::unique_ptr<cad::Model> LoadShape(const TopoDS_Shape& shape, const std::string& name);

/// Reads a CAD file with OpenCascade's default readers, as invmap does.
TopoDS_Shape ReadShape(const std::string& path);

/// The model's faces in face-map order, and all of them as one compound:
/// the boundary, which BRepExtrema measures to (a solid would give 0 inside).
std::vector<TopoDS_Face> Faces(const TopoDS_Shape& shape);
TopoDS_Compound Compound(const std::vector<TopoDS_Face>& faces);
/// Shapes as one compound (an assembly of them).
TopoDS_Compound CompoundOf(std::initializer_list<TopoDS_Shape> shapes);

/// BRepExtrema_DistShapeShape from the point to `shape`.
double OccDistance(const TopoDS_Shape& shape, const double* point);

/// The diagonal of the shape's box.
double ShapeSize(const TopoDS_Shape& shape);

/// `count` query points: every `farEvery`-th uniform in the box grown by
/// `far` times the size on each side, the others near the surface (a random
/// point of a triangle of OpenCascade's mesh, moved along a random direction
/// by up to `near` times the size).
std::vector<double> PointsAround(const TopoDS_Shape& shape, std::size_t count, double near, double far,
                                 unsigned seed, std::size_t farEvery = 2);
/// The same with near points moved by up to nears[0], nears[1], ... times
/// the size in turn.
std::vector<double> PointsAround(const TopoDS_Shape& shape, std::size_t count, const std::vector<double>& nears,
                                 double far, unsigned seed, std::size_t farEvery);

/// `count` query points near the model's edges, where trimming decides the
/// answer: a random point of a random edge (weighted by length; degenerate
/// edges left out), moved along a random direction by up to nears[0],
/// nears[1], ... times the size in turn.
std::vector<double> PointsNearEdges(const TopoDS_Shape& shape, std::size_t count, const std::vector<double>& nears,
                                    unsigned seed);

/// Dense samples of trimmed faces: a grid of (grid + 1)^2 points over each
/// face's parameter box, those its face classifier keeps, then 4 grid + 1
/// points along each of its edges' curves.
struct FaceSamples {
  std::vector<gp_Pnt> points;
  std::vector<std::size_t> onEdge;  ///< Indices of the edges' samples.
  double spacing = 0.0;             ///< Largest gap between neighbouring grid samples.
  double edgeSpacing = 0.0;         ///< Largest gap between neighbouring edge samples.
};
FaceSamples SampleFaces(const std::vector<TopoDS_Face>& faces, int grid);

/// Inverts `points` (3 per point) on the model's geometry with one thread.
Results InvertOnModel(const cad::Model& model, const std::vector<double>& points);
/// The same on `geometry`; `kept` (optional) receives the manifold built.
Results InvertOnGeometry(const Geometry& geometry, const std::vector<double>& points, Manifold* kept = nullptr);

/// The model's own precision at a face: the largest tolerance of the face
/// and its edges and vertices, or, where larger, how far its edges' curves
/// lie from its surface through their pcurves (sampled).
double FaceTolerance(const TopoDS_Face& face);

/// Tallies of CheckAgainstOpenCascade.
struct Comparison {
  int points = 0;
  int notFound = 0;
  int farther = 0;       ///< invmap farther than OpenCascade beyond the tolerance
  int offFace = 0;       ///< the reported (u, v) lies outside the reported face
  int badParameters = 0; ///< the face's surface at (u, v) is not the reported point
  double worstExcess = 0.0;  ///< largest (invmap - OpenCascade) / size
  std::string firstFailure;
};

/// Checks every point's answer: found, never farther than OpenCascade's
/// distance to the faces (OccNearest: DistShapeShape's extrema, set up once)
/// beyond `tolerance` times the size, the reported (u, v) inside the reported face (its classifier) and
/// the face's surface there at the reported point (within the face's own
/// tolerance where an edge answers). OpenCascade's queries run on two threads.
Comparison CheckAgainstOpenCascade(const TopoDS_Shape& shape, const cad::Model& model,
                                   const std::vector<double>& points, double tolerance);

}  // namespace invmap::cadtest
