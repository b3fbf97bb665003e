// A partition-of-unity surface: the charts of a closed triangle mesh, one
// shape function per chart, and the blended parametrizations
//
//   theta_v(p) = sum_z gamma_z(phi_zv(p)) psi_z(phi_zv(p)) / sum_z gamma_z(phi_zv(p))
//
// over the vertices z whose gluing domain with v holds p (v itself and at
// most two neighbours), gamma_z(q) = xi(|q| / R_z) the bump of chart z and
// psi_z its shape function (docs/manifold.md). theta_v(p) = theta_u(phi_uv(p))
// wherever both are defined, so the charts' images form one C-infinity
// surface.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "pou/base_surface.h"
#include "pou/closed_mesh.h"
#include "pou/jet.h"
#include "pou/shape_function.h"

namespace invmap::pou {

/// theta_v (three coordinates) with its first and second derivatives.
struct ThetaJet {
  Jet<double> x[3];
};

/// The parts of theta_v at a point of chart v (pou/piece_bounds.h bounds
/// them): psi_v and the bump gamma_v, and for each neighbour asked for its
/// bump beta_z (zero outside its support) and psi_z o phi_zv, by the
/// formula of the transition map wherever that is defined (the point not the
/// centre, less than FormulaAngle from the edge: pou/chart_maps.h), inside
/// the gluing domain or not. All as jets in the chart's (u, v).
struct BlendParts {
  Jet<double> own[3];
  Jet<double> ownWeight;
  std::vector<int> edges;          ///< The neighbours asked for, by edge.
  /// Per edge, set by the caller (empty: all): evaluate it, or leave it
  /// undefined with a zero bump (for an edge whose bump cannot reach).
  std::vector<char> active;
  std::vector<char> defined;       ///< Per edge: psi_z o phi_zv's formula is defined.
  std::vector<Jet<double>> weights;  ///< Per edge: beta_z.
  std::vector<Jet<double>> shapes;   ///< Per edge, 3 coordinates: psi_z o phi_zv.
  /// theta_v itself (the edges must include every neighbour whose bump is
  /// positive at the point).
  ThetaJet Theta() const;
};

/// Where a point of a chart is reported: the chart whose bump is largest
/// there (the vertex nearest in the canonical frames) and the point's
/// coordinates in it.
struct ChartPoint {
  std::int64_t chart = 0;
  double u = 0.0, v = 0.0;
};

class PouSurface {
 public:
  /// Builds the surface over the mesh: validates it (ClosedMesh::Build),
  /// samples the base surface over every p-domain and fits the shape
  /// functions. `degree` 0 chooses each chart's bidegree as the published
  /// implementation does, min(valence + 1, 7); otherwise every chart gets
  /// `degree` (1 to 8). Returns an error message or an empty string.
  std::string Build(const double* xyz, std::int64_t numVertices, const std::int64_t* triangles,
                    std::int64_t numTriangles, BaseKind base, int degree);
  /// Restores a surface from its mesh, degrees and nets (a pou_manifold
  /// patch). Returns an error message naming the field, or an empty string.
  std::string Restore(const std::vector<double>& xyz, const std::vector<std::int64_t>& triangles,
                      const std::vector<int>& degrees, const std::vector<double>& nets);

  const ClosedMesh& mesh() const { return mesh_; }
  std::int64_t numCharts() const { return mesh_.numVertices(); }
  int valence(std::int64_t v) const { return mesh_.valence(v); }
  /// The p-domain's radius cos(pi / valence).
  double radius(std::int64_t v) const { return radius_[v]; }
  int degree(std::int64_t v) const { return degree_[v]; }
  ShapeNet net(std::int64_t v) const { return {degree_[v], radius_[v], &nets_[netOffset_[v]]}; }
  /// Bounds of chart v's shape function and its derivatives over its square
  /// enlarged by kShapeBoundExtension.
  const ShapeBounds& shapeBounds(std::int64_t v) const { return bounds_[v]; }
  const std::vector<int>& degrees() const { return degree_; }
  const std::vector<double>& nets() const { return nets_; }

  /// theta_v at (u, v) with derivatives; (u, v) must lie in the p-domain
  /// (|p| < R).
  ThetaJet Evaluate(std::int64_t chart, double u, double v) const;
  /// The parts theta_v blends at (u, v), for the caller's list of
  /// neighbours (parts->edges): see BlendParts.
  void EvaluateParts(std::int64_t chart, double u, double v, BlendParts* parts) const;
  /// The point only.
  void EvaluatePoint(std::int64_t chart, double u, double v, double out[3]) const;
  /// The chart with the largest bump at (u, v) of `chart`, and the point there.
  ChartPoint Owner(std::int64_t chart, double u, double v) const;
  /// phi_{u v}: the point (x, y) of chart v in the chart of its neighbour
  /// number `edge`. False when (x, y) is not in their gluing domain.
  bool Transition(std::int64_t chart, int edge, double x, double y, double* qx, double* qy) const;

 private:
  std::string FitCharts(const BaseSurface& base, int degree);
  void ComputeBounds();

  ClosedMesh mesh_;
  std::vector<int> degree_;
  std::vector<double> radius_;
  std::vector<std::int64_t> netOffset_;
  std::vector<double> nets_;
  std::vector<ShapeBounds> bounds_;
};

/// Inside this share of the p-domain's radius no neighbour's gluing domain
/// reaches (canonical distance 1 - sqrt(3)/2 from the vertex, that is
/// 2 / sqrt(3) - 1 = 0.15470 of R), so theta_v = psi_v there.
constexpr double kOwnOnly = 0.1547;

/// The bidegree the published implementation gives a chart of valence n.
inline int AutomaticDegree(int valence) { return valence > 6 ? 7 : valence + 1; }

}  // namespace invmap::pou
