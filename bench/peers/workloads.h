// The fixed, deterministic workloads of the peer comparison (issue 5): the
// geometries, in invmap's form and in the data the peers are built from, and
// their query points.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "invmap/invmap.h"

namespace invmap::bench {

/// What a geometry case is, which decides the peers that apply to it.
enum class CaseKind {
  SplineSurface,  ///< One B-spline/NURBS surface patch (OpenCascade, SISL).
  SplineCurve,    ///< One planar B-spline/NURBS curve patch (OpenCascade, SISL).
  TriangleMesh,   ///< One linear triangle mesh patch (Embree, CGAL).
  TetMesh,        ///< A high-order tet mesh made by gmsh, in a .msh file (gmsh).
  CadModel,       ///< A CAD model file (OpenCascade's BRepExtrema; Embree on tessellations of it).
};

/// One set of query points of a case.
struct PointSet {
  std::string name;            ///< "near", "far", "everywhere", "inside", ...
  std::vector<double> coords;  ///< Interleaved, `dim` values per point.
  int dim = 3;
  /// Number of points.
  std::int64_t count() const { return static_cast<std::int64_t>(coords.size()) / dim; }
  /// Coordinates of point i.
  const double* point(std::int64_t i) const { return coords.data() + i * dim; }
};

/// A geometry with its query point sets.
struct GeometryCase {
  std::string name;         ///< Short name used in tables: "surface", "torus", ...
  std::string description;  ///< What the geometry is, for the notes.
  CaseKind kind = CaseKind::SplineSurface;
  /// What invmap builds. For the spline and mesh kinds, patches[0] is also
  /// what the peers are converted from (the same knots, weights and vertices).
  Geometry geometry;
  std::vector<PointSet> pointSets;
  /// TetMesh: the gmsh mesh file (MSH 4.1) that invmap read and gmsh reloads.
  std::string mshPath;
  /// TetMesh: the element order.
  int order = 0;
  /// CadModel: the model file OpenCascade reads (invmap's geometry is its
  /// faces), and tessellations of it for the mesh peers, each with the
  /// chordal deflection OpenCascade's mesher was given.
  std::string cadPath;
  struct Tessellation {
    double deflection = 0.0;
    Patch mesh;  ///< A triangle mesh patch.
  };
  std::vector<Tessellation> tessellations;
};

/// Sizes of the workloads.
struct WorkloadOptions {
  bool quick = false;            ///< Small geometries and point sets (a smoke run).
  std::int64_t points = 1000000;  ///< Points per point set.
  /// Directory where the gmsh meshes are written (created if missing).
  std::string workDir = ".";
  /// Only cases whose name contains this (empty: all).
  std::string only;
};

/// Builds every case. A case that cannot be made (no gmsh to mesh the tet
/// solid) is left out with a message on stderr.
std::vector<GeometryCase> MakeCases(const WorkloadOptions& options);

/// Appends the CAD cases (bench/peers/cad_workloads.cpp; built only with
/// invmap's CAD library): the demo's bracket and two of OpenCascade's sample
/// models, with simulated scans of them.
void AddCadCases(const WorkloadOptions& options, std::vector<GeometryCase>* cases);

/// Point of a B-spline/NURBS patch (curve or surface) at knot parameters
/// `params` (one per parametric direction), written to `point` (`dim` values).
/// Independent of invmap's engine: de Boor's basis functions on the patch data.
void EvaluatePatch(const Patch& patch, int dim, const double* params, double* point);

/// Diagonal of the box of a patch's control points (`dim` coordinates each):
/// the length scale the peers' tolerances are set from.
double ControlBoxSize(const Patch& patch, int dim);

/// Parameter range [lo, hi] of direction `direction` of a B-spline patch.
void PatchRange(const Patch& patch, int direction, double* lo, double* hi);

/// The gmsh .geo text of the curved solid meshed for the tet workloads.
std::string TetSolidGeo(int order, double meshSize);

}  // namespace invmap::bench
