#include "kernels/cell_solver.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/active_set.h"
#include "kernels/affine_simplex.h"
#include "kernels/affine_simplex_lanes.h"
#include "kernels/cell_bounds.h"
#include "kernels/cell_charts.h"
#include "kernels/cramer.h"
#include "kernels/face_certificate.h"
#include "kernels/kkt_exclusion.h"
#include "kernels/layer_newton.h"
#include "kernels/simplex_subdomain.h"
#include "kernels/slot_pool.h"
#include "kernels/simplex_index.h"
#include "kernels/local_solver.h"
#include "kernels/reference_faces.h"
#include "kernels/tolerances.h"

namespace invmap::kernels {
namespace {

/// A subdomain of the branch and bound lives in one slot of the workspace:
/// a header (lower bound, depth, for trimmed cells its TrimRegion::Side,
/// the vertices of each factor's sub-simplex in the cell's reference
/// coordinates) followed by its q net and, for rational cells, its WW net.
constexpr int kLowerBound = 0;
constexpr int kDepth = 1;
constexpr int kTrimSide = 2;
constexpr int kVertices = 3;  // [factor][vertex][coordinate], 3 x 4 x 3 values
constexpr int kHeaderSize = kVertices + kMaxFactors * 4 * 3;

double* Vertex(double* slot, int factor, int vertex) { return slot + kVertices + (factor * 4 + vertex) * 3; }

/// The reference domain's vertices: for each factor, the origin and the unit
/// points of its free coordinates.
void SetReferenceVertices(const CellShape& shape, double* slot) {
  std::fill(slot + kVertices, slot + kHeaderSize, 0.0);
  for (int f = 0; f < shape.numFactors(); ++f) {
    for (int v = 1; v <= shape.factor(f).dim; ++v) Vertex(slot, f, v)[v - 1] = 1.0;
  }
}

/// Centroid of the subdomain, in the cell's reference coordinates.
void SubdomainCenter(const CellShape& shape, double* slot, double* ref) {
  for (int f = 0; f < shape.numFactors(); ++f) {
    const SimplexFactor& fac = shape.factor(f);
    for (int i = 0; i < fac.dim; ++i) {
      double sum = 0.0;
      for (int v = 0; v <= fac.dim; ++v) sum += Vertex(slot, f, v)[i];
      ref[fac.offset + i] = sum / (fac.dim + 1);
    }
  }
}

/// True when `ref` lies in the subdomain up to kInsideTolerance in each
/// factor's barycentric coordinates.
bool SubdomainContains(const CellShape& shape, double* slot, const double* ref) {
  for (int f = 0; f < shape.numFactors(); ++f) {
    const SimplexFactor& fac = shape.factor(f);
    if (!InSimplexSubdomain(fac.dim, ref + fac.offset, [&](int v) { return Vertex(slot, f, v); })) return false;
  }
  return true;
}

/// For cells of line factors: side[d] = 0 or 1 when `ref` lies on a face
/// u_d = 0 or 1 of the cell's domain and the subdomain's local face t_d =
/// side[d] is that face, -1 when `ref` is inside in direction d. False when
/// `ref` is on a face of the cell that the subdomain does not reach.
bool ConstrainedSides(const CellShape& shape, double* slot, const double* ref, int* side) {
  for (int d = 0; d < shape.numFactors(); ++d) {
    side[d] = -1;
    for (const double face : {0.0, 1.0}) {
      if (std::abs(ref[d] - face) > kOnFaceTolerance) continue;
      if (Vertex(slot, d, 0)[0] == face) {
        side[d] = 0;
      } else if (Vertex(slot, d, 1)[0] == face) {
        side[d] = 1;
      } else {
        return false;
      }
    }
  }
  return true;
}

/// The edge to bisect next: the longest edge of any factor's sub-simplex,
/// measured with the cell's typical length per parameter.
void ChooseSplit(const CellShape& shape, double* slot, const double* paramScale, int* factor, int* vi, int* vj) {
  double longest = -1.0;
  for (int f = 0; f < shape.numFactors(); ++f) {
    const SimplexFactor& fac = shape.factor(f);
    for (int a = 0; a <= fac.dim; ++a) {
      for (int b = a + 1; b <= fac.dim; ++b) {
        double len2 = 0.0;
        for (int i = 0; i < fac.dim; ++i) {
          const double e = (Vertex(slot, f, a)[i] - Vertex(slot, f, b)[i]) * paramScale[fac.offset + i];
          len2 += e * e;
        }
        if (len2 > longest) {
          longest = len2;
          *factor = f;
          *vi = a;
          *vj = b;
        }
      }
    }
  }
}

/// True when a subdomain of line factors is over kMaxElongation times as
/// long (in the cell's lengths per parameter) along one factor as along
/// another. Trimmed cells split such subdomains across their length: split
/// where the net bends most, the subdomains along a trimming curve or a
/// collapsed edge could become slivers that no test ever closes.
constexpr double kMaxElongation = 16.0;
bool Elongated(const CellShape& shape, double* slot, const double* paramScale) {
  double shortest = std::numeric_limits<double>::infinity(), longest = 0.0;
  for (int f = 0; f < shape.numFactors(); ++f) {
    const double length = (Vertex(slot, f, 1)[0] - Vertex(slot, f, 0)[0]) * paramScale[shape.factor(f).offset];
    shortest = std::min(shortest, length);
    longest = std::max(longest, length);
  }
  return longest > kMaxElongation * shortest;
}

/// A trimmed cell's subdomain box in reference coordinates (line factors).
void SubdomainBox(const CellShape& shape, double* slot, double* lo, double* hi) {
  for (int d = 0; d < shape.numFactors(); ++d) {
    lo[d] = Vertex(slot, d, 0)[0];
    hi[d] = Vertex(slot, d, 1)[0];
  }
}

/// The local answer at `ref` that a trimmed cell's search keeps when no KKT
/// point of its region has been found: any point of the face bounds the
/// distance from above, which lets the search prune (it is never certified).
LocalSolveResult SampleAnswer(const double* ref, int paramDim, const MapJet& jet, int ambientDim, double f) {
  LocalSolveResult sample;
  std::copy(ref, ref + paramDim, sample.ref);
  std::copy(jet.x, jet.x + ambientDim, sample.closest);
  sample.squaredDistance = f;
  return sample;
}

/// True for polynomial cells and rational ones whose weights vary by at most
/// 5%: beyond that the curvature bounds of a rational cell, which bound the
/// Hessians of NN, NW and WW separately, lose the cancellations between
/// them and prove nothing (measured on the NURBS torus and curve).
bool WeightsNearlyEqual(const CellView& cell) {
  if (!cell.weights) return true;
  const auto [least, most] = std::minmax_element(cell.weights, cell.weights + cell.shape.numControlPoints());
  return *most <= 1.05 * *least;
}

/// WW coefficients further apart than this ratio make a rational cell's
/// weights unbalanced: its certificates then see past the rounding of each
/// coefficient and its search splits by its own rule (see CellSolver::Search)
/// with a larger budget. Far above the ratios of ordinary NURBS (a torus's
/// WW spans a factor of 4).
constexpr double kUnbalancedWeights = 16.0;
/// Unbalanced cells' search budget and hard seeds, in units of
/// kMaxSubdomains and kHardSeeds.
constexpr int kUnbalancedBudget = 8;

}  // namespace

double CellSolver::SizeOfBox(const double* lo, const double* hi, int dim) {
  double diag2 = 0.0;
  double center[3] = {0, 0, 0};
  for (int k = 0; k < dim; ++k) {
    diag2 += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    center[k] = 0.5 * (lo[k] + hi[k]);
  }
  const double size = std::sqrt(diag2);
  // A cell of a single point still needs a positive length scale.
  if (!(size > 0.0)) return std::max(1.0, std::abs(center[0]) + std::abs(center[1]) + std::abs(center[2])) * 1e-300;
  return size;
}

CellSolver::CellSolver(const CellView& cell) : cell_(cell) {
  ComputeControlBox(cell, boxLo_, boxHi_);
  double center[3] = {0, 0, 0};
  for (int k = 0; k < cell.ambientDim; ++k) center[k] = 0.5 * (boxLo_[k] + boxHi_[k]);
  size_ = SizeOfBox(boxLo_, boxHi_, cell.ambientDim);
  affine_ = IsAffineCell(cell, size_);
  if (cell.shape.numFactors() == 1) {
    // A simplex's corner control points are its vertices.
    const SimplexFactor& fac = cell.shape.factor(0);
    const SimplexIndex& index = SimplexIndex::Get(fac.dim, fac.degree);
    for (int v = 0; v <= fac.dim; ++v) {
      std::array<int, 4> corner{0, 0, 0, 0};
      corner[v] = fac.degree;
      cornerControl_[v] = index.Position(corner);
      if (affine_) vertexControl_[v] = cornerControl_[v];
    }
  }
  if (affine_ && isFullRank() && vertexControl_[0] < 0) {
    // The corners at the origin and at the unit points e_i (vertex i + 1 of
    // the factor holding parameter i).
    for (int i = -1; i < cell.shape.paramDim(); ++i) {
      int vertex[kMaxFactors] = {0, 0, 0};
      for (int f = 0; f < cell.shape.numFactors() && i >= 0; ++f) {
        const SimplexFactor& fac = cell.shape.factor(f);
        if (i >= fac.offset && i < fac.offset + fac.dim) vertex[f] = i - fac.offset + 1;
      }
      frameControl_[i + 1] = CornerControlPoint(cell.shape, vertex);
    }
  }
  if (isTetrahedron()) {
    // The cell lies in the convex hull of its control points, so no point of
    // it has a corner barycentric coordinate below theirs.
    double least = 0.0;
    for (int c = 0; c < cell.shape.numControlPoints(); ++c) {
      double lambda[4];
      if (!CornerBarycentric(cell.points + static_cast<size_t>(c) * 3, lambda)) {
        least = -std::numeric_limits<double>::infinity();
        break;
      }
      least = std::min({least, lambda[0], lambda[1], lambda[2], lambda[3]});
    }
    cornerHullMargin_ = -least;
  }

  double ref[3];
  ReferenceCenter(cell.shape, ref);
  MapJet jet;
  EvaluateMap(cell, ref, JetOrder::First, &jet);
  for (int i = 0; i < cell.shape.paramDim(); ++i) {
    double len2 = 0.0;
    for (int k = 0; k < cell.ambientDim; ++k) len2 += jet.d1[k][i] * jet.d1[k][i];
    // Parameters the map barely depends on still get split now and then.
    paramScale_[i] = std::sqrt(len2) + 1e-3 * size_;
  }
  if (!affine_) {
    nets_.Build(cell, center);
    stencil_ = &HessianStencil::Get(nets_.shape());
    if (WeightsNearlyEqual(cell)) curvature_ = std::make_unique<const CurvatureBounds>(nets_, *stencil_);
    if (nets_.rational()) {
      // Subdomains' WW coefficients are convex combinations of the cell's:
      // none spans a wider range.
      const auto [least, most] = std::minmax_element(nets_.ww(), nets_.ww() + nets_.size());
      unbalancedWeights_ = *most > kUnbalancedWeights * *least;
      if (unbalancedWeights_) {
        // Each bisection that balances the weights halves their range at
        // best: they need that many more levels to reach the usual scale.
        maxDepth_ += static_cast<int>(std::ceil(std::log2(*most / *least)));
        // The heavy weight's reach ends along a curve such as u v = 1 /
        // weight, which crosses subdomains at every scale down to that
        // product: a bicubic with one weight 1e10 to 1e50 times the others
        // examined 2,800 to 24,000 subdomains a point on average (measured).
        maxSubdomains_ *= kUnbalancedBudget;
        // Seeds too: a bound stays loose across a heavy weight's layer, and
        // a local solve from inside it (in its chart) is what finds a basin
        // there (QA's rational tets at 1e12: an inside point reported 0.004
        // off, an answer depending on the batch's other points).
        maxHardSeeds_ *= kUnbalancedBudget;
        charts_ = std::make_unique<const CellCharts>(cell);
      }
    }
  }
}

double CellSolver::SquaredDistanceLowerBound(const double* point, double slack, SolveWorkspace* ws) const {
  double box2 = 0.0;
  for (int k = 0; k < cell_.ambientDim; ++k) {
    const double d = std::max({boxLo_[k] - point[k], 0.0, point[k] - boxHi_[k]});
    box2 += d * d;
  }
  if (affine_) return box2;
  const int n = nets_.size();
  if (ws->scratch.size() < static_cast<size_t>(n)) ws->scratch.resize(n);
  nets_.SquaredDistanceNumerator(point, ws->scratch.data());
  const double lb = NetLowerBound(n, ws->scratch.data(), nets_.rational() ? nets_.ww() : nullptr);
  return std::max(box2, lb - slack);
}

CellSolveResult CellSolver::Solve(const double* point, const double* initialRef, SolveWorkspace* ws,
                                  double bound2, AnswerModel* model) const {
  CellSolveResult result;
  if (model) model->known = false;
  const int pd = cell_.shape.paramDim();
  const int ad = cell_.ambientDim;
  for (int k = 0; k < ad; ++k) {
    if (!std::isfinite(point[k])) return result;  // status InvalidInput
  }
  // An infinite bound is no bound: beyond about 1e154 the squared distance
  // itself overflows to infinity, and such a point must still get its answer.
  const bool bounded = bound2 < std::numeric_limits<double>::infinity();
  // The rounding of the nets' coefficients at this point, for every bound below.
  const double slack = affine_ ? 0.0 : nets_.RoundingSlack(point);
  double* q = nullptr;  // the q net of `point`, when the lower bound has computed it
  if (bounded) {
    if (SquaredDistanceLowerBound(point, slack, ws) >= bound2) {
      result.status = PointStatus::Farther;
      return result;
    }
    if (!affine_) q = ws->scratch.data();
  }
  if (vertexControl_[0] >= 0) {
    SolveAffineSimplex(point, &result);
    if (bounded && result.distance * result.distance >= bound2) result.status = PointStatus::Farther;
    return result;
  }
  double start[3];
  if (initialRef) {
    std::copy(initialRef, initialRef + pd, start);
  } else if (!NearestControlPointStart(point, start)) {
    ReferenceCenter(cell_.shape, start);
  }
  const double tau = kDistanceTolerance * size_;
  LocalSolveOptions options;
  options.affine = affine_;
  options.size = size_;
  // The search below trusts the local answer only at a KKT point.
  options.checkKkt = !affine_;
  // A cell that has to beat a bound is given up as soon as a tangent plane
  // shows it cannot (a neighbour of the best cell, usually). Not on curves:
  // their local solves take a few cheap iterations, and the test cost more
  // than it saved there (measured, 3%).
  struct Exclusion {
    const CellSolver* solver;
    const double* point;
    double level;
    double slack;
    double* q;
  } exclusion{this, point, 0.0, slack, q};
  if (q && pd > 1) {
    exclusion.level = ExclusionLevel(bound2, tau, slack);
    options.exclusionLevel = exclusion.level;
    options.exclusionContext = &exclusion;
    options.confirmExclusion = [](const void* context) {
      const Exclusion& e = *static_cast<const Exclusion*>(context);
      return e.solver->ExcessIsConvex(e.point, e.level, e.slack, e.q);
    };
  }
  options.model = model;
  LocalSolveResult best = LocalSolveCharted(point, start, options);
  result.iterations = best.iterations;
  if (best.aboveLevel) {
    result.status = PointStatus::Farther;
    return result;
  }
  Rejected rejected;
  if (trim_ && !trim_->Admits(best.ref)) {
    // Outside the face: no answer yet. An affine cell's distance is convex,
    // so its only KKT point is this one, and the face's closest point in it
    // lies on the region's boundary, which the edges answer.
    if (model) model->known = false;
    if (affine_) {
      result.status = PointStatus::Farther;
      return result;
    }
    rejected.Add(best);
    best.squaredDistance = std::numeric_limits<double>::infinity();
    best.kkt = false;
  }

  bool certified = true;
  // An affine map makes the squared distance convex: the KKT point is global.
  // A distance within tau of zero cannot be beaten by more than tau.
  if (!affine_ && best.squaredDistance > tau * tau) {
    const double localRef[3] = {best.ref[0], best.ref[1], best.ref[2]};
    if (charts_) SeedFaceLayers(point, &best, &result.iterations);
    certified = Search(point, bound2, slack, &best, &result.iterations, ws, trim_ ? &rejected : nullptr);
    // A nearer minimum the search found has no model here.
    if (model && !std::equal(localRef, localRef + pd, best.ref)) model->known = false;
  }

  if (best.squaredDistance == std::numeric_limits<double>::infinity() && trim_) {
    result.status = PointStatus::Farther;  // no point of the region beats the edges
    return result;
  }
  std::copy(best.ref, best.ref + pd, result.ref);
  std::copy(best.closest, best.closest + ad, result.closest);
  result.distance = std::sqrt(best.squaredDistance);
  if (bounded && best.squaredDistance >= bound2) {
    result.status = PointStatus::Farther;
  } else if (!certified) {
    result.status = PointStatus::NotCertified;
  } else {
    result.status = best.onBoundary ? PointStatus::ProjectedToBoundary : PointStatus::Converged;
  }
  return result;
}

LocalSolveResult CellSolver::LocalSolveCharted(const double* point, const double* start,
                                               const LocalSolveOptions& options) const {
  if (!charts_) return LocalSolve(cell_, point, start, options);
  // The chart of the start's largest coordinates, then, if the answer lies
  // where others are largest, once more from there. (Without an answer
  // model: its derivatives would be the chart's.)
  LocalSolveOptions charted = options;
  charted.model = nullptr;
  if (options.model) options.model->known = false;
  Barycentric at = charts_->ToBarycentric(0, start);
  int chart = -1;
  LocalSolveResult result;
  int iterations = 0;
  for (int pass = 0; pass < 2; ++pass) {
    const int next = charts_->ChartFor(at);
    if (next == chart) break;
    chart = next;
    double chartStart[3] = {0, 0, 0};
    charts_->FromBarycentric(chart, at, chartStart);
    result = LocalSolve(charts_->view(chart), point, chartStart, charted);
    iterations += result.iterations;
    const bool stalled = !result.converged || (charted.checkKkt && !result.kkt);
    if (stalled && !result.aboveLevel && !options.stopAtBoundary) {
      result = LayerPolish(charts_->view(chart), point, result, charted, &iterations);
    }
    at = charts_->ToBarycentric(chart, result.ref);
    if (result.aboveLevel) break;
  }
  result.iterations = iterations;
  charts_->FromBarycentric(0, at, result.ref);
  return result;
}

LocalSolveResult CellSolver::LayerPolish(const CellView& chart, const double* point, const LocalSolveResult& stalled,
                                         const LocalSolveOptions& options, int* iterations) const {
  // A solve that ran into its iteration cap (or stopped on steps too short
  // to matter, short of a KKT point) inside a heavy weight's layer is
  // crawling along a curved valley (kernels/layer_newton.h): Newton in
  // the layer's logarithms reaches its floor, and a local solve from there
  // confirms the point (a KKT point, a face it lies on).
  double ref[3] = {stalled.ref[0], stalled.ref[1], stalled.ref[2]};
  const int layerIterations = LayerNewton(chart, point, size_, ref);
  if (layerIterations == 0) return stalled;
  *iterations += layerIterations;
  LocalSolveResult polished = LocalSolve(chart, point, ref, options);
  *iterations += polished.iterations;
  return polished.squaredDistance <= stalled.squaredDistance ? polished : stalled;
}

void CellSolver::SeedFaceLayers(const double* point, LocalSolveResult* best, int* iterations) const {
  // The answer moved onto each face of each factor (that barycentric
  // coordinate set to zero, the others scaled up to sum one): in its chart
  // the coordinate is free, so the solve can enter the face's layer, where
  // a heavy weight's reach ends and the search's bounds stay loose longest.
  // (Faces of two factors at once found nothing more on QA's cases.)
  LocalSolveOptions options;
  options.size = size_;
  options.checkKkt = true;
  const Barycentric at = charts_->ToBarycentric(0, best->ref);
  for (int f = 0; f < cell_.shape.numFactors(); ++f) {
    const int dim = cell_.shape.factor(f).dim;
    for (int k = 0; k <= dim; ++k) {
      const double others = 1.0 - at.lambda[f][k];
      if (!(others > 0.0)) continue;
      Barycentric onFace = at;
      for (int i = 0; i <= dim; ++i) onFace.lambda[f][i] = i == k ? 0.0 : at.lambda[f][i] / others;
      double start[3] = {0, 0, 0};
      charts_->FromBarycentric(0, onFace, start);
      const LocalSolveResult local = LocalSolveCharted(point, start, options);
      *iterations += local.iterations;
      if (local.squaredDistance < best->squaredDistance && (!trim_ || trim_->Admits(local.ref))) *best = local;
    }
  }
}

bool CellSolver::ExcessIsConvex(const double* point, double level, double slack, double* q) const {
  if (curvature_ && curvature_->ProvesConvex(point, level)) return true;
  const int n = nets_.size();
  const double* ww = nets_.rational() ? nets_.ww() : nullptr;
  for (int i = 0; i < n; ++i) q[i] -= level * (ww ? ww[i] : 1.0);
  return stencil_->IsConvex(q, RoundingNoise(ww, slack));
}

NetNoise CellSolver::RoundingNoise(const double* ww, double slack) const {
  // A polynomial net's rounding is the same for every coefficient, a tiny
  // share of f*: a convexity it fakes errs by rounding of the answer itself.
  // So does a rational net's while its WW coefficients (and with them the
  // rounding, slack WW_i: see RoundingSlack) stay within a small factor.
  // Where they span orders of magnitude, the rounding of the heavy
  // coefficients swamps what the light ones say: the tests must see past it.
  if (!ww || !unbalancedWeights_) return NetNoise{};
  return NetNoise{ww, slack};
}

void CellSolver::SolveAffineSimplex(const double* point, CellSolveResult* result) const {
  const double* vertices[4];
  for (int v = 0; v <= cell_.shape.paramDim(); ++v) {
    vertices[v] = cell_.points + static_cast<size_t>(vertexControl_[v]) * cell_.ambientDim;
  }
  SolveAffineSimplex(cell_.shape.paramDim(), cell_.ambientDim, vertices, point, result);
}

void CellSolver::SolveAffineSimplex(int paramDim, int ambientDim, const double* const* v, const double* point,
                                    CellSolveResult* result) {
  bool onBoundary = false;
  const double d2 = ClosestPointOnSimplex(paramDim, ambientDim, v, point, result->ref, result->closest, &onBoundary);
  result->distance = std::sqrt(d2);
  result->iterations = 0;
  result->status = onBoundary ? PointStatus::ProjectedToBoundary : PointStatus::Converged;
}

bool CellSolver::CornerBarycentric(const double* point, double* lambda) const {
  if (!isTetrahedron()) return false;
  const double* v[4];
  for (int i = 0; i < 4; ++i) v[i] = CornerPoint(i);
  return TetBarycentric(v, point, lambda);
}

bool CellSolver::TetBarycentric(const double* const* v, const double* point, double* lambda) {
  double e[3][3], w[3];
  for (int k = 0; k < 3; ++k) {
    for (int i = 0; i < 3; ++i) e[i][k] = v[i + 1][k] - v[0][k];
    w[k] = point[k] - v[0][k];
  }
  // Cramer's rule; a flat corner tetrahedron has no barycentric coordinates.
  const double det = Determinant3(e[0], e[1], e[2]);
  if (!(std::fabs(det) > 0)) return false;
  CramerSolve3(e[0], e[1], e[2], det, w, lambda + 1);
  lambda[0] = 1 - lambda[1] - lambda[2] - lambda[3];
  return std::isfinite(lambda[0]) && std::isfinite(lambda[1]) && std::isfinite(lambda[2]) && std::isfinite(lambda[3]);
}

bool CellSolver::FrameCoordinates(const double* point, double* ref) const {
  if (frameControl_[0] < 0) return false;
  const int ad = cell_.ambientDim;
  const double* origin = cell_.points + static_cast<size_t>(frameControl_[0]) * ad;
  double e[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 1}}, w[3] = {0, 0, 0};
  for (int k = 0; k < ad; ++k) {
    for (int i = 0; i < ad; ++i) e[i][k] = cell_.points[static_cast<size_t>(frameControl_[i + 1]) * ad + k] - origin[k];
    w[k] = point[k] - origin[k];
  }
  // In the plane, the third column is the unit normal: its coordinate is 0.
  const double det = Determinant3(e[0], e[1], e[2]);
  if (!(std::fabs(det) > 0)) return false;
  double x[3];
  CramerSolve3(e[0], e[1], e[2], det, w, x);
  for (int i = 0; i < ad; ++i) {
    if (!std::isfinite(x[i])) return false;
    ref[i] = x[i];
  }
  return true;
}

bool CellSolver::NearestControlPointStart(const double* point, double* ref) const {
  const CellShape& shape = cell_.shape;
  for (int f = 0; f < shape.numFactors(); ++f) {
    if (shape.factor(f).dim != 1 || shape.factor(f).degree < 1) return false;
  }
  const int ad = cell_.ambientDim;
  int nearest = 0;
  double nearest2 = std::numeric_limits<double>::infinity();
  for (int c = 0; c < shape.numControlPoints(); ++c) {
    const double* x = cell_.points + static_cast<size_t>(c) * ad;
    double d2 = 0.0;
    for (int k = 0; k < ad; ++k) d2 += (x[k] - point[k]) * (x[k] - point[k]);
    if (d2 < nearest2) {
      nearest2 = d2;
      nearest = c;
    }
  }
  // Control point (i, j, ..) sits over the Greville parameters (i / p, j / q, ..).
  // A volume's start is kept off the faces: a start on a face enforces its
  // constraint, which rules out the full-rank step for the rest of the solve.
  // Curves and surfaces start on the face: LocalSolve keeps only the
  // constraints the descent presses against there (a point beyond the edge).
  const double inset = isFullRank() ? kStartInset : 0.0;
  for (int f = 0; f < shape.numFactors(); ++f) {
    const int n = shape.factor(f).degree + 1;
    ref[f] = std::clamp(static_cast<double>(nearest % n) / (n - 1), inset, 1.0 - inset);
    nearest /= n;
  }
  return true;
}

double CellSolver::InsideScore(const double* point) const {
  double lambda[4];
  if (CornerBarycentric(point, lambda)) return std::min({lambda[0], lambda[1], lambda[2], lambda[3]});
  double ref[3];
  if (FrameCoordinates(point, ref)) return LeastBarycentric(cell_.shape, ref);
  return -kInsideScoreUnknown;
}

void CellSolver::SolveAffineSimplexLane(int pd, int ad, const double* const* vertices, const QueryLane& queries,
                                        const ResultLane& results) {
  double ref[3][kSimplexLaneChunk], dist2[kSimplexLaneChunk];
  bool onBoundary[kSimplexLaneChunk];
  for (int first = 0; first < queries.count; first += kSimplexLaneChunk) {
    const int n = std::min(kSimplexLaneChunk, queries.count - first);
    const double* const coord[3] = {queries.coord[0] + first, queries.coord[1] + first,
                                    ad > 2 ? queries.coord[2] + first : nullptr};
    double* const refOut[3] = {ref[0], ref[1], ref[2]};
    ClosestPointsOnSimplexLanes(pd, ad, vertices, coord, n, refOut, dist2, onBoundary);
    for (int l = 0; l < n; ++l) {
      const int lane = first + l;
      bool finite = true;
      for (int k = 0; k < ad; ++k) finite = finite && std::isfinite(coord[k][l]);
      if (!finite) {
        constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
        for (int i = 0; i < 3; ++i) {
          if (results.ref[i]) results.ref[i][lane] = kNaN;
          if (results.closest[i]) results.closest[i][lane] = kNaN;
        }
        if (results.distance) results.distance[lane] = kNaN;
        if (results.status) results.status[lane] = PointStatus::InvalidInput;
        if (results.iterations) results.iterations[lane] = 0;
        continue;
      }
      for (int i = 0; i < 3; ++i) {
        if (results.ref[i]) results.ref[i][lane] = i < pd ? ref[i][l] : std::numeric_limits<double>::quiet_NaN();
      }
      for (int k = 0; k < 3; ++k) {
        if (!results.closest[k]) continue;
        if (k >= ad) {
          results.closest[k][lane] = std::numeric_limits<double>::quiet_NaN();
          continue;
        }
        double x = vertices[0][k];
        for (int i = 0; i < pd; ++i) x += ref[i][l] * (vertices[i + 1][k] - vertices[0][k]);
        results.closest[k][lane] = x;
      }
      if (results.distance) results.distance[lane] = std::sqrt(dist2[l]);
      const bool farther = queries.bound2 && dist2[l] >= queries.bound2[lane];
      if (results.status) {
        results.status[lane] = farther      ? PointStatus::Farther
                               : onBoundary[l] ? PointStatus::ProjectedToBoundary
                                               : PointStatus::Converged;
      }
      if (results.iterations) results.iterations[lane] = 0;
    }
  }
}

bool CellSolver::InsideStart(const double* initialRef, const double* lambdaIn, bool haveLambda, double* start) const {
  const int pd = cell_.shape.paramDim();
  double lambda[4];
  if (haveLambda) std::copy(lambdaIn, lambdaIn + 4, lambda);
  if (haveLambda) {
    // Beyond the control points' hull (with a margin far above the distance
    // tolerance): outside the cell, no solve needed.
    if (*std::min_element(lambda, lambda + 4) < -cornerHullMargin_ - kHullSlack) return false;
    // The point's place in the straight tetrahedron of the corners: exact
    // for a straight cell, close for the mildly curved cells of meshes, and
    // better than the previous point's answer (measured on order-2 meshes).
    // Kept off the faces: a start on a face would end the inside solve of a
    // point in a cell's outward bulge at once (see stopAtBoundary).
    double sum = 0.0;
    for (double& l : lambda) sum += (l = std::max(l, kStartInset));
    for (int i = 0; i < 3; ++i) start[i] = lambda[i + 1] / sum;
  } else if (initialRef) {
    std::copy(initialRef, initialRef + pd, start);
  } else {
    ReferenceCenter(cell_.shape, start);
  }
  return true;
}

bool CellSolver::SolveInside(const double* point, const double* initialRef, CellSolveResult* result,
                             const double* cornerLambda) const {
  const int pd = cell_.shape.paramDim();
  double start[3];
  // (Simplices have no frame; their corners are read first, on a hot line.)
  if (cornerControl_[0] < 0 && FrameCoordinates(point, start)) {
    // An affine cell: `start` is the point's preimage, exact up to
    // rounding. Beyond the domain (by a margin far above the rounding) the
    // point is outside. Else the map there (clamped into the domain) is the
    // point itself to the distance tolerance, as the local solve would
    // confirm, unless rounding in a nearly flat cell says otherwise.
    result->iterations = 0;
    const double least = LeastBarycentric(cell_.shape, start);
    if (least < -kHullSlack) {
      std::copy(start, start + pd, result->ref);
      return false;
    }
    ClampToDomain(cell_.shape, start);
    MapJet jet;
    EvaluateMap(cell_, start, JetOrder::Value, &jet);
    double d2 = 0.0;
    for (int k = 0; k < cell_.ambientDim; ++k) d2 += (jet.x[k] - point[k]) * (jet.x[k] - point[k]);
    const double tau = kDistanceTolerance * size_;
    if (!(d2 <= tau * tau)) return FinishInside(point, start, result);
    std::copy(start, start + pd, result->ref);
    std::copy(jet.x, jet.x + cell_.ambientDim, result->closest);
    result->distance = std::sqrt(d2);
    result->status = least > 0.0 ? PointStatus::Converged : PointStatus::ProjectedToBoundary;
    return true;
  }
  double lambda[4];
  if (cornerLambda) std::copy(cornerLambda, cornerLambda + 4, lambda);
  const bool haveLambda = cornerLambda || CornerBarycentric(point, lambda);
  if (!InsideStart(initialRef, lambda, haveLambda, start)) {
    result->iterations = 0;
    ReferenceCenter(cell_.shape, result->ref);
    return false;
  }
  if (vertexControl_[0] >= 0) {
    SolveAffineSimplex(point, result);
    return result->distance <= kDistanceTolerance * size_;
  }
  return FinishInside(point, start, result);
}

bool CellSolver::FinishInside(const double* point, const double* start, CellSolveResult* result) const {
  const int pd = cell_.shape.paramDim();
  LocalSolveOptions options;
  options.affine = affine_;
  options.size = size_;
  options.stopAtBoundary = true;
  const LocalSolveResult local = LocalSolveCharted(point, start, options);
  result->iterations = local.iterations;
  const double tau = kDistanceTolerance * size_;
  std::copy(local.ref, local.ref + pd, result->ref);
  if (!(local.squaredDistance <= tau * tau)) return false;
  std::copy(local.closest, local.closest + cell_.ambientDim, result->closest);
  result->distance = std::sqrt(local.squaredDistance);
  result->status = local.onBoundary ? PointStatus::ProjectedToBoundary : PointStatus::Converged;
  return true;
}

bool CellSolver::Search(const double* point, double bound2, double slack, LocalSolveResult* best, int* iterations,
                        SolveWorkspace* ws, Rejected* rejected) const {
  const CellShape& netShape = nets_.shape();
  const int n = nets_.size();
  const bool rational = nets_.rational();
  const int slotSize = kHeaderSize + n * (rational ? 2 : 1);
  const double tau = kDistanceTolerance * size_;
  // Subdomains whose lower bound reaches this cannot beat the best by more than tau.
  auto pruneLevel = [&] { return ExclusionLevel(std::min(best->squaredDistance, bound2), tau, slack); };
  SlotPool pool(&ws->nets, &ws->freeSlots, slotSize);
  if (ws->scratch.size() < static_cast<size_t>(n)) ws->scratch.resize(n);
  const HessianStencil& stencil = *stencil_;
  const bool faceCertificate = HasFaceCertificate(netShape);
  // Splits by the net's bends (below) choose among the lines of a tensor
  // product; a curve has one line. Simplices keep the longest edge: bisected
  // along their most bent edge again and again they turn into slivers, and
  // random curved tets took 2.6 times as long (bench_kernels).
  bool bentSplit = netShape.numFactors() > 1;
  for (int f = 0; f < netShape.numFactors(); ++f) bentSplit = bentSplit && netShape.factor(f).dim == 1;
  // The certificate below is only sound at a true KKT point; a local solve
  // that stopped early (iteration cap, rounding) does not get it.
  bool bestIsKkt = best->kkt;
  // The convexity certificate: q - f* WW convex on a subdomain holding the
  // KKT point x* means q >= f* WW there, so no point of it is closer.
  auto certifiedAround = [&](double* slot) {
    if (!bestIsKkt || !SubdomainContains(cell_.shape, slot, best->ref)) return false;
    double* f = ws->scratch.data();
    const double* q = slot + kHeaderSize;
    const double* ww = rational ? q + n : nullptr;
    for (int i = 0; i < n; ++i) f[i] = q[i] - best->squaredDistance * (ww ? ww[i] : 1.0);
    const NetNoise noise = RoundingNoise(ww, slack);
    if (stencil.IsConvex(f, noise)) return true;
    int side[3];
    return faceCertificate && ConstrainedSides(cell_.shape, slot, best->ref, side) &&
           IsMinimalOnFace(netShape, f, noise, side);
  };
  auto lowerBound = [&](double* slot) {
    const double* q = slot + kHeaderSize;
    return NetLowerBound(n, q, rational ? q + n : nullptr);
  };
  // Trimmed cells: a KKT point x_r outside the region, of squared distance
  // f_r, and a subdomain holding it where q - c WW is convex for every c
  // from f_r to the best so far (for c at both ends: the Hessian is affine
  // in c; one c for a polynomial cell, whose WW is constant). A KKT point y
  // there with f_r < f(y) <= best would minimize the convex q - f(y) WW over
  // the subdomain (a KKT point of it too), at value 0, while x_r gives it
  // WW (f_r - f(y)) < 0: there is none, and the subdomain holds no
  // candidate but x_r. So the subdomains around the stationary points
  // beyond the face's edges go as soon as they are convex, long before
  // they are small enough to lie outside the region.
  auto aroundRejected = [&](double* slot) {
    if (!rejected) return false;
    const double* q = slot + kHeaderSize;
    const double* ww = rational ? q + n : nullptr;
    double* f = ws->scratch.data();
    double upper = std::min(best->squaredDistance, bound2);
    if (ww && !(upper < std::numeric_limits<double>::infinity())) {
      upper = 0.0;
      for (int i = 0; i < n; ++i) upper = std::max(upper, q[i] / ww[i]);
    }
    const NetNoise noise = RoundingNoise(ww, slack);
    for (int r = 0; r < rejected->count; ++r) {
      const LocalSolveResult& x = rejected->points[r];
      if (!SubdomainContains(cell_.shape, slot, x.ref)) continue;
      // Convex, or (x_r on a face of the cell) rising away from the face and
      // convex on it, which bounds q - c WW by its least value on the face
      // the same way (face_certificate.h).
      int side[3];
      const bool onFace = faceCertificate && ConstrainedSides(cell_.shape, slot, x.ref, side);
      bool convex = true, minimalOnFace = onFace;
      for (const double level : {x.squaredDistance, upper}) {
        for (int i = 0; i < n; ++i) f[i] = q[i] - level * (ww ? ww[i] : 1.0);
        convex = convex && stencil.IsConvex(f, noise);
        minimalOnFace = minimalOnFace && IsMinimalOnFace(netShape, f, noise, side);
        if (!ww) break;
      }
      if (convex || minimalOnFace) return true;
    }
    return false;
  };

  // The certificate below for the whole cell, from the curvature bounds.
  if (bestIsKkt && curvature_ && curvature_->ProvesConvex(point, best->squaredDistance)) return true;
  const int root = pool.Allocate();
  {
    double* slot = pool[root];
    SetReferenceVertices(cell_.shape, slot);
    slot[kDepth] = 0;
    slot[kTrimSide] = static_cast<double>(trim_ ? TrimRegion::Side::Crossing : TrimRegion::Side::Inside);
    nets_.SquaredDistanceNumerator(point, slot + kHeaderSize);
    if (rational) std::copy(nets_.ww(), nets_.ww() + n, slot + kHeaderSize + n);
    slot[kLowerBound] = lowerBound(slot);
  }
  // And the trimmed cell's: convex around a KKT point outside the region,
  // at both levels (one for a polynomial cell, whose WW is constant), the
  // cell has no other candidate.
  if (rejected && rejected->count > 0 && !bestIsKkt && curvature_) {
    double upper = std::min(best->squaredDistance, bound2);
    if (rational && !(upper < std::numeric_limits<double>::infinity())) {
      const double* q = pool[root] + kHeaderSize;
      upper = 0.0;
      for (int i = 0; i < n; ++i) upper = std::max(upper, q[i] / q[n + i]);
    }
    for (int r = 0; r < rejected->count; ++r) {
      if (curvature_->ProvesConvex(point, rejected->points[r].squaredDistance) &&
          (!rational || curvature_->ProvesConvex(point, upper))) {
        pool.Free(root);
        return true;
      }
    }
  }
  std::vector<int>& heap = ws->heap;
  heap.clear();
  auto byLowerBound = [&](int a, int b) { return pool[a][kLowerBound] > pool[b][kLowerBound]; };
  if (pool[root][kLowerBound] < pruneLevel()) heap.push_back(root);

  bool certified = true;
  int examined = 0;
  int hardSeeds = 0;
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), byLowerBound);
    const int s = heap.back();
    heap.pop_back();
    if (pool[s][kLowerBound] >= pruneLevel()) break;  // every other subdomain is farther still
    if (++examined > maxSubdomains_) {
      certified = false;
      break;
    }
    if (trim_ && !MayHoldTrimmedMinimum(pool[s], pool[s] + kHeaderSize, rational ? pool[s] + kHeaderSize + n : nullptr,
                                        std::min(best->squaredDistance, bound2), slack)) {
      pool.Free(s);
      continue;
    }
    if (certifiedAround(pool[s]) || aroundRejected(pool[s])) {
      pool.Free(s);
      continue;
    }
    // A better basin may lie here: start a local solve from the center when
    // the center itself already beats the best.
    double center[3];
    SubdomainCenter(cell_.shape, pool[s], center);
    MapJet jet;
    EvaluateMap(cell_, center, JetOrder::Value, &jet);
    double fCenter = 0.0;
    for (int k = 0; k < cell_.ambientDim; ++k) fCenter += (jet.x[k] - point[k]) * (jet.x[k] - point[k]);
    // A search that has not closed after kHardSearch subdomains is near a
    // tie or a degenerate piece (a collapsed edge, where the local minima of
    // the parameters form a continuum): from then on every subdomain also
    // seeds a local solve, which finds basins its center value cannot show.
    const bool seed = examined > kHardSearch && hardSeeds < maxHardSeeds_;
    hardSeeds += seed ? 1 : 0;
    // A trimmed cell seeds only from centers in its region: a KKT point
    // inside the region is the center's limit in the subdomains that shrink
    // onto it, and the stationary points outside it, which centers outside
    // would find again and again, are no answers.
    const bool centerAdmitted = !trim_ || pool[s][kTrimSide] == static_cast<double>(TrimRegion::Side::Inside) ||
                                trim_->Admits(center);
    if ((fCenter < best->squaredDistance || seed) && centerAdmitted) {
      LocalSolveOptions options;
      options.size = size_;
      options.checkKkt = true;
      const LocalSolveResult local = LocalSolveCharted(point, center, options);
      *iterations += local.iterations;
      const bool admitted = !trim_ || trim_->Admits(local.ref);
      if (!admitted) rejected->Add(local);
      if (trim_ && !(admitted && local.squaredDistance < best->squaredDistance) && fCenter < best->squaredDistance) {
        *best = SampleAnswer(center, cell_.shape.paramDim(), jet, cell_.ambientDim, fCenter);
        bestIsKkt = false;
      }
      if (admitted && local.squaredDistance < best->squaredDistance) {
        *best = local;
        bestIsKkt = best->kkt;
        // As in Solve: a distance within tau of zero cannot be beaten by
        // more than tau (no bound can exclude the rest of a cell the point lies on).
        if (best->squaredDistance <= tau * tau) break;
      }
      if (pool[s][kLowerBound] >= pruneLevel() || certifiedAround(pool[s])) {
        pool.Free(s);
        continue;
      }
    }
    if (pool[s][kDepth] >= maxDepth_) {
      certified = false;
      pool.Free(s);
      continue;
    }
    int factor = 0, vi = 0, vj = 1;
    if (unbalancedWeights_) {
      // Min q_i / WW_i is a weighted mean bound: where WW's coefficients
      // differ by orders of magnitude it stays loose however small the
      // subdomain gets in other directions, so the direction where they
      // change most is split first. Then the one where the quotients q_i /
      // WW_i (squared distances, roughly) change most: the cell's typical
      // lengths per parameter (paramScale_) say nothing about a subdomain
      // that the heavy weight squeezes or stretches by orders of magnitude.
      const double* q = pool[s] + kHeaderSize;
      if (SteepestRatioEdge(netShape, q + n, &factor, &vi, &vj) <= kUnbalancedWeights) {
        double* quotient = ws->scratch.data();
        for (int i = 0; i < n; ++i) quotient[i] = q[i] / q[n + i];
        SteepestDifferenceEdge(netShape, quotient, &factor, &vi, &vj);
      }
    } else {
      // Where the net of q - level WW bends most, its least coefficient
      // stays furthest below the function's least value: splitting there
      // raises the bound most. Along a valley of equal distances (a
      // cylinder or a torus seen from its axis) the bound is exact along
      // the valley, and the splits go across it only.
      const double* q = pool[s] + kHeaderSize;
      // Before anything is found (a trimmed cell's search) the level is the
      // subdomain's own bound: an infinite one would bend every line alike.
      const double level = std::isinf(pruneLevel()) ? pool[s][kLowerBound] : pruneLevel();
      if (!bentSplit || MostBentLine(netShape, q, rational ? q + n : nullptr, level, &factor) == 0.0 ||
          (trim_ && Elongated(cell_.shape, pool[s], paramScale_))) {
        ChooseSplit(cell_.shape, pool[s], paramScale_, &factor, &vi, &vj);
      }
    }
    for (int child = 0; child < 2; ++child) {
      const int keep = child == 0 ? vi : vj;
      const int move = child == 0 ? vj : vi;
      const int c = pool.Allocate();
      double* parent = pool[s];
      double* slot = pool[c];
      std::copy(parent, parent + kHeaderSize, slot);
      slot[kDepth] = parent[kDepth] + 1;
      double* moved = Vertex(slot, factor, move);
      const double* kept = Vertex(slot, factor, keep);
      for (int i = 0; i < 3; ++i) moved[i] = 0.5 * (moved[i] + kept[i]);
      if (trim_ && slot[kTrimSide] != static_cast<double>(TrimRegion::Side::Inside)) {
        double lo[3], hi[3];
        SubdomainBox(cell_.shape, slot, lo, hi);
        const TrimRegion::Side side = trim_->ClassifySubdomain(lo, hi);
        if (side == TrimRegion::Side::Outside) {
          pool.Free(c);
          continue;
        }
        slot[kTrimSide] = static_cast<double>(side);
      }
      SplitNet(netShape, factor, keep, move, parent + kHeaderSize, slot + kHeaderSize);
      if (rational) SplitNet(netShape, factor, keep, move, parent + kHeaderSize + n, slot + kHeaderSize + n);
      slot[kLowerBound] = lowerBound(slot);
      if (slot[kLowerBound] < pruneLevel()) {
        heap.push_back(c);
        std::push_heap(heap.begin(), heap.end(), byLowerBound);
      } else {
        pool.Free(c);
      }
    }
    pool.Free(s);
  }
  return certified;
}

bool CellSolver::MayHoldTrimmedMinimum(double* slot, const double* q, const double* ww, double level2,
                                       double slack) const {
  const CellShape& netShape = nets_.shape();
  const int n = nets_.size();
  bool reachesLow[3] = {false, false, false}, reachesHigh[3] = {false, false, false};
  for (int d = 0; d < netShape.numFactors(); ++d) {
    reachesLow[d] = Vertex(slot, d, 0)[0] == 0.0;
    reachesHigh[d] = Vertex(slot, d, 1)[0] == 1.0;
  }
  // The squared distances a candidate can have here: from the subdomain's
  // lower bound up to the best so far (or the net's largest ratio).
  double levelHi = level2;
  if (!(levelHi < std::numeric_limits<double>::infinity())) {
    levelHi = -std::numeric_limits<double>::infinity();
    for (int i = 0; i < n; ++i) levelHi = std::max(levelHi, ww ? q[i] / ww[i] : q[i]);
  }
  int face[3];
  if (!LocateKktPoints(netShape, q, ww, slot[kLowerBound] - slack, levelHi + slack, slack, reachesLow, reachesHigh,
                       face)) {
    return false;
  }
  if (slot[kTrimSide] == static_cast<double>(TrimRegion::Side::Inside)) return true;
  // The candidates lie on a face (edge, corner) of the cell: that part of
  // the subdomain must meet the region.
  double lo[3], hi[3];
  SubdomainBox(cell_.shape, slot, lo, hi);
  bool onFace = false;
  for (int d = 0; d < netShape.numFactors(); ++d) {
    if (face[d] < 0) continue;
    lo[d] = hi[d] = face[d];
    onFace = true;
  }
  return !onFace || trim_->ClassifySubdomain(lo, hi) != TrimRegion::Side::Outside;
}

void CellSolver::SolveLane(const QueryLane& queries, const ResultLane& results, SolveWorkspace* ws) const {
  if (vertexControl_[0] >= 0) {
    const int pd = cell_.shape.paramDim();
    const double* vertices[4];
    for (int v = 0; v <= pd; ++v) vertices[v] = cell_.points + static_cast<size_t>(vertexControl_[v]) * cell_.ambientDim;
    SolveAffineSimplexLane(pd, cell_.ambientDim, vertices, queries, results);
    return;
  }
  SolveCurvedLanes(queries, results, ws);
}

void CellSolver::WriteLane(int l, const CellSolveResult& r, const ResultLane& results) const {
  const int pd = cell_.shape.paramDim();
  const int ad = cell_.ambientDim;
  for (int i = 0; i < 3; ++i) {
    if (results.ref[i]) results.ref[i][l] = i < pd ? r.ref[i] : std::numeric_limits<double>::quiet_NaN();
    if (results.closest[i]) results.closest[i][l] = i < ad ? r.closest[i] : std::numeric_limits<double>::quiet_NaN();
  }
  if (results.distance) results.distance[l] = r.distance;
  if (results.status) results.status[l] = r.status;
  if (results.iterations) results.iterations[l] = r.iterations;
}

}  // namespace invmap::kernels
