// Partition-of-unity manifold surfaces (docs/manifold.md): a C-infinity
// surface over a closed, oriented, manifold triangle mesh, one chart per
// vertex, glued by transition maps and blended by bump functions.
//
//   invmap::Patch patch;
//   std::string error = invmap::BuildPouManifold(xyz, nv, triangles, nt, {}, &patch);
//   invmap::Geometry geometry;                   // dimension 3
//   geometry.patches.push_back(patch);           // kind PouManifold
//   invmap::BuildResult built = invmap::Manifold::Build(geometry);   // invert onto it
//
//   invmap::PouCharts charts;                    // evaluation at chart coordinates
//   error = invmap::PouCharts::Create(patch, &charts);
//   invmap::ChartJet jet;
//   charts.Evaluate(vertex, u, v, &jet);
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "invmap/invmap.h"

namespace invmap {

/// The surface the shape functions are fitted to.
enum class PouBase : std::uint8_t {
  Flat,         ///< The mesh itself.
  PnTriangles,  ///< PN triangles (cubic Bezier triangles from the vertex normals).
  Loop,         ///< The Loop subdivision limit surface, evaluated exactly.
};

struct PouOptions {
  PouBase base = PouBase::Loop;
  /// Bidegree of every chart's shape function, 1 to 8; 0 chooses
  /// min(valence + 1, 7) per chart.
  int degree = 0;
};

/// Builds the pou_manifold patch of the mesh (`numVertices` points of 3
/// coordinates at `xyz`, `numTriangles` triangles of 3 0-based indices).
/// Returns an empty string, or a message naming the vertex, edge or triangle
/// that makes the mesh unfit (a boundary, a non-manifold edge or vertex, an
/// isolated vertex, inconsistent orientation, a degenerate triangle, a vertex
/// of valence below 3). Never throws.
std::string BuildPouManifold(const double* xyz, std::int64_t numVertices, const std::int64_t* triangles,
                             std::int64_t numTriangles, const PouOptions& options, Patch* out);

/// theta_v at chart coordinates (u, v): the point and its first and second
/// partial derivatives.
struct ChartJet {
  double point[3];
  double du[3], dv[3];
  double duu[3], duv[3], dvv[3];
};

/// The charts of a pou_manifold patch, for evaluation. Immutable, thread-safe
/// to read, movable.
class PouCharts {
 public:
  /// Validates the patch and prepares its charts. Returns an error message
  /// (naming the field) or an empty string. Never throws.
  static std::string Create(const Patch& patch, PouCharts* out);

  PouCharts();
  ~PouCharts();
  PouCharts(PouCharts&&) noexcept;
  PouCharts& operator=(PouCharts&&) noexcept;

  std::int64_t NumCharts() const;
  int Valence(std::int64_t chart) const;
  /// The p-domain's radius, cos(pi / valence): theta_v is defined for u^2 + v^2 < radius^2.
  double Radius(std::int64_t chart) const;
  /// Evaluates theta_chart at (u, v). False for a chart out of range or a
  /// point outside its p-domain.
  bool Evaluate(std::int64_t chart, double u, double v, ChartJet* out) const;
  /// A triangle mesh of the surface: each mesh triangle split into
  /// resolution^2 triangles (resolution + 1 samples along each edge), every
  /// vertex evaluated on the surface and shared between neighbouring
  /// triangles. resolution >= 1.
  void Tessellate(int resolution, std::vector<double>* xyz, std::vector<std::int64_t>* triangles) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace invmap
