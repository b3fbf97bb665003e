#include "kernels/cell_minima.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "kernels/active_set.h"
#include "kernels/bernstein_net.h"
#include "kernels/cell_bounds.h"
#include "kernels/kkt_point.h"
#include "kernels/local_solver.h"
#include "kernels/tolerances.h"

namespace invmap::kernels {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// How far off every face of the domain a converged solve must lie (in
/// barycentric coordinates) for the cells' refusal of it to be suspect:
/// beyond rounding of the boundary, where the distance may fall into it.
constexpr double kOffFace = 1e-9;

/// A subdomain in the workspace: its depth, the vertices of each factor's
/// sub-simplex in the cell's reference coordinates, the q and WW nets of
/// the point (DistanceNets), and the cell's homogeneous control net on the
/// subdomain (w P, then w), for a local solve restricted to it.
constexpr int kDepth = 0;
constexpr int kVertices = 1;
constexpr int kHeaderSize = kVertices + kMaxFactors * 4 * 3;

double* Vertex(double* slot, int factor, int vertex) { return slot + kVertices + (factor * 4 + vertex) * 3; }

/// The factor's barycentric coordinates of a point of its free coordinates.
void Barycentric(int dim, const double* s, double* lambda) {
  lambda[0] = 1.0;
  for (int i = 0; i < dim; ++i) {
    lambda[i + 1] = s[i];
    lambda[0] -= s[i];
  }
}

class MinimaSearch {
 public:
  MinimaSearch(const CellSolver& solver, const double* point, double maxDistance, MinimaWorkspace* ws)
      : solver_(solver), cell_(solver.cell()), nets_(solver.nets()), ws_(ws), maxDistance_(maxDistance) {
    lineFactors_ = true;
    for (int f = 0; f < cell_.shape.numFactors(); ++f) lineFactors_ = lineFactors_ && cell_.shape.factor(f).dim == 1;
    ad_ = cell_.ambientDim;
    std::copy(point, point + ad_, point_);
    n2_ = nets_.size();
    ncp_ = cell_.shape.numControlPoints();
    slotSize_ = kHeaderSize + 2 * n2_ + (ad_ + 1) * ncp_;
    slack_ = nets_.RoundingSlack(point);
    double center[3];
    ReferenceCenter(cell_.shape, center);
    MapJet jet;
    EvaluateMap(cell_, center, JetOrder::First, &jet);
    for (int i = 0; i < cell_.shape.paramDim(); ++i) {
      double length2 = 0.0;
      for (int k = 0; k < ad_; ++k) length2 += jet.d1[k][i] * jet.d1[k][i];
      paramScale_[i] = std::sqrt(length2) + 1e-3 * solver.size();
    }
  }

  CellMinimaResult Run();

 private:
  double* Slot(int s) { return ws_->slots.data() + static_cast<size_t>(s) * slotSize_; }
  int Allocate() {
    const size_t need = static_cast<size_t>(used_ + 1) * slotSize_;
    if (ws_->slots.size() < need) ws_->slots.resize(std::max(need, 2 * ws_->slots.size()));
    return used_++;
  }
  /// True when along some edge of some factor the distance changes with one
  /// sign over the whole subdomain and the way it decreases never leaves the
  /// cell's domain from a point of the subdomain: no local minimum there.
  bool MonotoneSomewhere(double* slot, double low, double high);
  /// At most one local minimum: q - c WW strictly convex for every c in
  /// [low, high] (its Hessian is affine in c: both ends suffice). A local
  /// minimum x2 in S has f(x2) in that range, and g = q - f(x2) WW is then
  /// strictly convex with x2 its KKT point; a second one x1 with f(x1) <=
  /// f(x2) would give g(x1) <= 0 = min g, against strict convexity.
  bool AtMostOne(double* slot, double low, double high);
  /// The least point of the distance over the subdomain (a local solve on
  /// the subdomain's own net: convex as AtMostOne proved, its KKT point is
  /// that least point); kept when it is also a KKT point of the cell (not
  /// held by the subdomain's own boundary, inside the cell).
  void SolveIn(double* slot, CellMinimaResult* result);
  void Split(double* slot, int* factor, int* vi, int* vj) const;
  /// The Hessian of the distance bounds the second-order conditions a
  /// minimum needs. Over the subdomain, g_c = q - c WW for every c in
  /// [low, high] (at a critical point x, g_{f(x)}'s Hessian is WW times
  /// f's). Concave along a line factor's parameter everywhere: a minimum in
  /// S must sit on a face of the cell across that parameter (*faces gets
  /// the factor's bit). A surface whose Hessian has a negative determinant
  /// everywhere: no minimum inside the cell's domain, only on its faces.
  /// Returns true when S holds no minimum at all; else `faces` lists the
  /// line factors whose cell faces S reaches and where its minima must lie
  /// (0: no restriction).
  bool SecondOrderExcludes(double* slot, double low, double high, unsigned* faces);
  /// A line factor along which the distance is monotone over S and falls
  /// toward a face of the cell that S reaches: S's minima lie on that face.
  /// Returns the factor and the face's side (0: u = 0, 1: u = 1), or -1.
  int MonotoneTowardFace(double* slot, double low, double high, int* side);
  /// The minima of S that lie on its face at line factor f's side `side`
  /// (a face of the cell): the distance restricted to that face, searched as
  /// a cell of its own, each answer kept when it is a KKT point of the cell.
  /// `strict`: S's distance is concave (or a saddle) across the face, so a
  /// point of the face is a minimum only where the distance grows into the
  /// cell at first order (a zero slope there is a maximum or a saddle).
  void SolveOnFace(double* slot, int factor, int side, bool strict, CellMinimaResult* result);
  /// True when a face's control points (Cartesian, ad_ per point) are one
  /// point to the distance tolerance.
  bool CollapsedFace(const std::vector<double>& points) const {
    for (size_t c = ad_; c < points.size(); c += ad_) {
      double gap2 = 0.0;
      for (int k = 0; k < ad_; ++k) gap2 += (points[c + k] - points[k]) * (points[c + k] - points[k]);
      if (!(std::sqrt(gap2) <= kDistanceTolerance * solver_.size())) return false;
    }
    return true;
  }
  /// Whether S reaches the cell's face u_f = side (line factor f).
  bool ReachesFace(double* slot, int factor, int side) const {
    const double v0 = Vertex(slot, factor, 0)[0], v1 = Vertex(slot, factor, 1)[0];
    return side == 0 ? std::min(v0, v1) == 0.0 : std::max(v0, v1) == 1.0;
  }
  /// Newton steps of the distance from ref (each kept in the domain),
  /// checked by the cell's KKT test instead of the distance's decrease:
  /// true, with ref and jet (first order) moved there, when they reach a
  /// KKT point within kSamePointShare of the cell's size and the distance
  /// of where they started. A solve on a subdomain's own net stops where
  /// the distance's rounding hides its decrease, which on a cell small
  /// beside the distance (a sphere of radius 0.01 at 1.3 from the point)
  /// is still short of the cell's test, which judges the slopes' angle.
  bool PolishToKkt(double* ref, MapJet* jet) const;
  /// Records ref (cell coordinates) when it is a KKT point of the cell within
  /// reach; with `strictFactor` >= 0, only when the distance also grows
  /// into the cell along that line factor from its face `strictSide`.
  void Record(const double* ref, CellMinimaResult* result, int strictFactor = -1, int strictSide = 0) const;

  const CellSolver& solver_;
  const CellView& cell_;
  const DistanceNets& nets_;
  MinimaWorkspace* ws_;
  double maxDistance_;
  double point_[3] = {0, 0, 0};
  int ad_ = 3, n2_ = 0, ncp_ = 0, slotSize_ = 0, used_ = 0;
  double slack_ = 0.0;
  double paramScale_[3] = {1, 1, 1};
  bool lineFactors_ = false;  ///< A line, quad or hex cell: faces are cut by one parameter.
};

bool MinimaSearch::MonotoneSomewhere(double* slot, double low, double high) {
  const CellShape& shape = nets_.shape();
  const double* q = slot + kHeaderSize;
  const double* ww = q + n2_;
  std::vector<double>& scratch = ws_->scratch;
  for (int f = 0; f < shape.numFactors(); ++f) {
    const int dim = shape.factor(f).dim;
    if (shape.factor(f).degree < 1) continue;
    // Derivative nets of q and WW along each free coordinate of the factor.
    CellShape derivative;
    const int size = [&] {
      std::array<int, kMaxFactors> degrees{};
      for (int g = 0; g < shape.numFactors(); ++g) degrees[g] = shape.factor(g).degree - (g == f ? 1 : 0);
      return NetSize(CellShape(shape.type(), degrees));
    }();
    scratch.resize(static_cast<size_t>(2 * dim + 1) * size);
    for (int k = 0; k < dim; ++k) {
      DifferentiateNet(shape, f, k, q, scratch.data() + (2 * k) * size, &derivative);
      DifferentiateNet(shape, f, k, ww, scratch.data() + (2 * k + 1) * size, &derivative);
    }
    double* edge = scratch.data() + 2 * dim * size;
    // The factor's sub-simplex vertices' barycentric coordinates in the cell.
    double lambda[4][4];
    for (int v = 0; v <= dim; ++v) Barycentric(dim, Vertex(slot, f, v), lambda[v]);
    for (int vi = 0; vi <= dim; ++vi) {
      for (int vj = vi + 1; vj <= dim; ++vj) {
        // Along the edge vi -> vj the derivative is D_{vj-1} - D_{vi-1} (D_{-1} = 0).
        bool positive = true, negative = true;
        for (const double c : {low, high}) {
          double largest = 0.0;
          for (int i = 0; i < size; ++i) {
            double v = 0.0;
            if (vj > 0) v += scratch[(2 * (vj - 1)) * size + i] - c * scratch[(2 * (vj - 1) + 1) * size + i];
            if (vi > 0) v -= scratch[(2 * (vi - 1)) * size + i] - c * scratch[(2 * (vi - 1) + 1) * size + i];
            edge[i] = v;
            largest = std::max(largest, std::abs(v));
          }
          const double margin = 1e-12 * largest;
          for (int i = 0; i < size; ++i) {
            positive = positive && edge[i] > margin;
            negative = negative && edge[i] < -margin;
          }
        }
        if (!positive && !negative) continue;
        // The distance falls toward vi (positive) or vj (negative). That
        // way is open at every point of the subdomain unless the subdomain
        // reaches a face of the cell that way leaves: a barycentric
        // coordinate that decreases that way and is zero somewhere in it.
        bool open = true;
        for (int b = 0; b <= dim && open; ++b) {
          const double change = positive ? lambda[vi][b] - lambda[vj][b] : lambda[vj][b] - lambda[vi][b];
          if (!(change < 0.0)) continue;
          double least = kInf;
          for (int v = 0; v <= dim; ++v) least = std::min(least, lambda[v][b]);
          open = least > 0.0;
        }
        if (open) return true;
      }
    }
  }
  return false;
}

bool MinimaSearch::AtMostOne(double* slot, double low, double high) {
  const HessianStencil& stencil = HessianStencil::Get(nets_.shape());
  const double* q = slot + kHeaderSize;
  const double* ww = q + n2_;
  std::vector<double>& g = ws_->scratch;
  g.resize(n2_);
  for (const double c : {low, high}) {
    for (int i = 0; i < n2_; ++i) g[i] = q[i] - c * ww[i];
    if (!stencil.IsConvex(g.data())) return false;
  }
  return true;
}


void MinimaSearch::SolveIn(double* slot, CellMinimaResult* result) {
  // The subdomain as a cell of its own: its control net, Cartesian.
  const double* homogeneous = slot + kHeaderSize + 2 * n2_;
  const double* w = homogeneous + static_cast<size_t>(ad_) * ncp_;
  std::vector<double> points(static_cast<size_t>(ncp_) * ad_), weights;
  for (int c = 0; c < ncp_; ++c) {
    for (int k = 0; k < ad_; ++k) points[static_cast<size_t>(c) * ad_ + k] = homogeneous[static_cast<size_t>(k) * ncp_ + c] / w[c];
  }
  if (cell_.weights) weights.assign(w, w + ncp_);
  CellView sub = cell_;
  sub.points = points.data();
  sub.weights = cell_.weights ? weights.data() : nullptr;
  double center[3];
  ReferenceCenter(sub.shape, center);
  LocalSolveOptions options;
  options.size = solver_.size();
  const LocalSolveResult local = LocalSolve(sub, point_, center, options);
  if (!(local.squaredDistance <= maxDistance_ * maxDistance_)) return;
  // Back to the cell's coordinates: per factor, V0 + sum_k t_k (V_k - V0).
  double ref[3] = {0, 0, 0};
  for (int f = 0; f < cell_.shape.numFactors(); ++f) {
    const SimplexFactor& fac = cell_.shape.factor(f);
    for (int i = 0; i < fac.dim; ++i) {
      double v = Vertex(slot, f, 0)[i];
      for (int k = 1; k <= fac.dim; ++k) v += local.ref[fac.offset + k - 1] * (Vertex(slot, f, k)[i] - Vertex(slot, f, 0)[i]);
      ref[fac.offset + i] = v;
    }
  }
  const size_t before = result->minima.size();
  Record(ref, result);
  // The subdomain holds at most one minimum: a converged solve inside it
  // (on none of its faces) that the cell's test refuses is one the search
  // could not settle, not a subdomain without minima.
  if (result->minima.size() == before && local.converged && cell_.shape.IsOffEveryFace(local.ref, kOffFace)) {
    result->certified = false;
  }
}

bool MinimaSearch::PolishToKkt(double* ref, MapJet* jet) const {
  constexpr int kPolishSteps = 4;
  constexpr double kSamePointShare = 1e-6;
  const int pd = cell_.shape.paramDim();
  const double start[3] = {jet->x[0], jet->x[1], jet->x[2]};
  // The test judges slopes by the distance as well as by the cell's size:
  // the polish may move as far on either scale.
  double distance2 = 0.0;
  for (int k = 0; k < ad_; ++k) distance2 += (start[k] - point_[k]) * (start[k] - point_[k]);
  const double reach = kSamePointShare * (solver_.size() + std::sqrt(distance2));
  double at[3] = {ref[0], ref[1], ref[2]};
  for (int step = 0; step < kPolishSteps; ++step) {
    MapJet second;
    EvaluateMap(cell_, at, JetOrder::Second, &second);
    Eigen::Matrix3d h = Eigen::Matrix3d::Identity();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    for (int i = 0; i < pd; ++i) {
      for (int j = 0; j < pd; ++j) {
        h(i, j) = 0.0;
        for (int k = 0; k < ad_; ++k) {
          h(i, j) += second.d1[k][i] * second.d1[k][j] + (second.x[k] - point_[k]) * second.d2[k][i][j];
        }
      }
      for (int k = 0; k < ad_; ++k) g[i] += (second.x[k] - point_[k]) * second.d1[k][i];
    }
    const Eigen::LLT<Eigen::Matrix3d> llt(h);
    if (llt.info() != Eigen::Success) return false;
    const Eigen::Vector3d p = llt.solve(-g);
    for (int i = 0; i < pd; ++i) at[i] += p[i];
    ClampToDomain(cell_.shape, at);
    EvaluateMap(cell_, at, JetOrder::First, jet);
    double moved2 = 0.0;
    for (int k = 0; k < ad_; ++k) moved2 += (jet->x[k] - start[k]) * (jet->x[k] - start[k]);
    if (!(std::sqrt(moved2) <= reach)) return false;
    if (IsKktPoint(cell_, *jet, point_, at, solver_.size())) {
      std::copy(at, at + 3, ref);
      return true;
    }
  }
  return false;
}

void MinimaSearch::Record(const double* at, CellMinimaResult* result, int strictFactor, int strictSide) const {
  double ref[3] = {at[0], at[1], at[2]};
  ClampToDomain(cell_.shape, ref);
  MapJet jet;
  EvaluateMap(cell_, ref, JetOrder::First, &jet);
  if (!IsKktPoint(cell_, jet, point_, ref, solver_.size()) && !PolishToKkt(ref, &jet)) return;
  if (strictFactor >= 0) {
    // The slope into the cell, judged as the KKT test judges slopes: it
    // must be positive beyond rounding, not merely not negative.
    const int a = cell_.shape.factor(strictFactor).offset;
    double slope = 0.0, length2 = 0.0, r2 = 0.0;
    for (int k = 0; k < ad_; ++k) {
      const double r = jet.x[k] - point_[k];
      slope += r * jet.d1[k][a];
      length2 += jet.d1[k][a] * jet.d1[k][a];
      r2 += r * r;
    }
    if (strictSide == 1) slope = -slope;
    const double tolerance =
        (1e-7 * std::sqrt(r2) + 1e-12 * solver_.size()) * std::max(std::sqrt(length2), kThinDirection * solver_.size());
    if (!(slope > tolerance)) return;
  }
  CellMinimum minimum;
  std::copy(ref, ref + 3, minimum.ref);
  double d2 = 0.0;
  for (int k = 0; k < ad_; ++k) {
    minimum.closest[k] = jet.x[k];
    d2 += (jet.x[k] - point_[k]) * (jet.x[k] - point_[k]);
  }
  minimum.distance = std::sqrt(d2);
  if (minimum.distance <= maxDistance_) result->minima.push_back(minimum);
}

bool MinimaSearch::SecondOrderExcludes(double* slot, double low, double high, unsigned* faces) {
  *faces = 0;
  const HessianStencil& stencil = HessianStencil::Get(nets_.shape());
  const double* q = slot + kHeaderSize;
  const double* ww = q + n2_;
  double qlo[3][3], qhi[3][3], wlo[3][3] = {}, whi[3][3] = {};
  stencil.HessianRanges(q, qlo, qhi);
  if (nets_.rational()) stencil.HessianRanges(ww, wlo, whi);
  // H(g_c) = H(q) - c H(WW) for c in [low, high]: interval arithmetic.
  const int pd = cell_.shape.paramDim();
  double hlo[3][3], hhi[3][3];
  for (int a = 0; a < pd; ++a) {
    for (int b = a; b < pd; ++b) {
      const double products[4] = {low * wlo[a][b], low * whi[a][b], high * wlo[a][b], high * whi[a][b]};
      hlo[a][b] = qlo[a][b] - *std::max_element(products, products + 4);
      hhi[a][b] = qhi[a][b] - *std::min_element(products, products + 4);
      if (!std::isfinite(hlo[a][b]) || !std::isfinite(hhi[a][b])) return false;
    }
  }
  bool insideExcluded = false;
  for (int f = 0; f < cell_.shape.numFactors(); ++f) {
    const SimplexFactor& fac = cell_.shape.factor(f);
    for (int i = 0; i < fac.dim; ++i) {
      const int a = fac.offset + i;
      if (!(hhi[a][a] < 0.0)) continue;
      // Concave along parameter a: a minimum cannot have both directions
      // along it open, so it sits on a face of the cell across it.
      insideExcluded = true;
      if (fac.dim == 1) {
        if (ReachesFace(slot, f, 0) || ReachesFace(slot, f, 1)) *faces |= 1u << f;
      } else {
        // A simplex factor: a face the direction crosses, that S reaches.
        double least[4] = {kInf, kInf, kInf, kInf};
        for (int v = 0; v <= fac.dim; ++v) {
          double lambda[4];
          Barycentric(fac.dim, Vertex(slot, f, v), lambda);
          for (int b2 = 0; b2 <= fac.dim; ++b2) least[b2] = std::min(least[b2], lambda[b2]);
        }
        if (least[0] <= 0.0 || least[i + 1] <= 0.0) return false;  // no face reduction for simplices: split on
      }
    }
  }
  if (!insideExcluded && pd == 2) {
    // A saddle everywhere: H00 H11 - H01^2 < 0 at every point.
    const double p[4] = {hlo[0][0] * hlo[1][1], hlo[0][0] * hhi[1][1], hhi[0][0] * hlo[1][1], hhi[0][0] * hhi[1][1]};
    const double mixed = std::min(std::abs(hlo[0][1]), std::abs(hhi[0][1]));
    const bool straddles = hlo[0][1] <= 0.0 && hhi[0][1] >= 0.0;
    if (*std::max_element(p, p + 4) < (straddles ? 0.0 : mixed * mixed)) {
      insideExcluded = true;
      for (int f = 0; f < cell_.shape.numFactors(); ++f) {
        if (cell_.shape.factor(f).dim != 1) {
          // A triangle: its minima would be on its edges; split on unless S
          // is inside the cell.
          double least[4] = {kInf, kInf, kInf, kInf};
          for (int v = 0; v <= 2; ++v) {
            double lambda[4];
            Barycentric(2, Vertex(slot, f, v), lambda);
            for (int b2 = 0; b2 <= 2; ++b2) least[b2] = std::min(least[b2], lambda[b2]);
          }
          if (least[0] <= 0.0 || least[1] <= 0.0 || least[2] <= 0.0) return false;
          continue;
        }
        if (ReachesFace(slot, f, 0) || ReachesFace(slot, f, 1)) *faces |= 1u << f;
      }
    }
  }
  if (!insideExcluded) return false;
  if (*faces != 0 && !lineFactors_) return false;
  return *faces == 0;
}

int MinimaSearch::MonotoneTowardFace(double* slot, double low, double high, int* side) {
  if (!lineFactors_) return -1;
  const CellShape& shape = nets_.shape();
  const double* q = slot + kHeaderSize;
  const double* ww = q + n2_;
  std::vector<double>& scratch = ws_->scratch;
  for (int f = 0; f < shape.numFactors(); ++f) {
    if (shape.factor(f).degree < 1) continue;
    CellShape derivative;
    std::array<int, kMaxFactors> degrees{};
    for (int g = 0; g < shape.numFactors(); ++g) degrees[g] = shape.factor(g).degree - (g == f ? 1 : 0);
    const int size = NetSize(CellShape(shape.type(), degrees));
    scratch.resize(3 * static_cast<size_t>(size));
    DifferentiateNet(shape, f, 0, q, scratch.data(), &derivative);
    DifferentiateNet(shape, f, 0, ww, scratch.data() + size, &derivative);
    bool positive = true, negative = true;
    for (const double c : {low, high}) {
      double largest = 0.0;
      for (int i = 0; i < size; ++i) largest = std::max(largest, std::abs(scratch[i] - c * scratch[size + i]));
      for (int i = 0; i < size; ++i) {
        const double v = scratch[i] - c * scratch[size + i];
        positive = positive && v > 1e-12 * largest;
        negative = negative && v < -1e-12 * largest;
      }
    }
    // Increasing: falls toward u = 0; decreasing: toward u = 1.
    if (positive && ReachesFace(slot, f, 0)) {
      *side = 0;
      return f;
    }
    if (negative && ReachesFace(slot, f, 1)) {
      *side = 1;
      return f;
    }
  }
  return -1;
}

void MinimaSearch::SolveOnFace(double* slot, int factor, int side, bool strict, CellMinimaResult* result) {
  // The subdomain's net restricted to its face at `side` along the factor
  // (a line factor: the control points of index 0 or the last), Cartesian.
  const CellShape& shape = cell_.shape;
  const double* homogeneous = slot + kHeaderSize + 2 * n2_;
  const double* w = homogeneous + static_cast<size_t>(ad_) * ncp_;
  int count[kMaxFactors] = {1, 1, 1}, stride[kMaxFactors] = {1, 1, 1};
  int total = 1;
  for (int f = 0; f < shape.numFactors(); ++f) {
    count[f] = shape.factor(f).degree + 1;
    stride[f] = total;
    total *= count[f];
  }
  // The sub-simplex vertex at `side` of the cell is the subdomain's local 0 or 1.
  const int localSide = Vertex(slot, factor, 0)[0] == static_cast<double>(side) ? 0 : 1;
  const int fixedIndex = localSide == 0 ? 0 : count[factor] - 1;
  std::vector<double> points, weights;
  std::array<int, kMaxFactors> degrees{};
  int faceFactors = 0;
  for (int f = 0; f < shape.numFactors(); ++f) {
    if (f != factor) degrees[faceFactors++] = shape.factor(f).degree;
  }
  for (int c = 0; c < total; ++c) {
    if ((c / stride[factor]) % count[factor] != fixedIndex) continue;
    for (int k = 0; k < ad_; ++k) points.push_back(homogeneous[static_cast<size_t>(k) * ncp_ + c] / w[c]);
    weights.push_back(w[c]);
  }
  if (faceFactors == 0) {
    // A curve's end: one point.
    double ref[3] = {0, 0, 0};
    ref[factor] = Vertex(slot, factor, localSide)[0];
    Record(ref, result, strict ? factor : -1, side);
    return;
  }
  if (CollapsedFace(points)) {
    // A face that is one point (a sphere's pole): searched as a cell of its
    // own, no direction of its parameters changes the distance, and it
    // was split down to the budget, every piece a "minimum". The point
    // counts where the cell's KKT test passes at some place of the face
    // (it depends on the place: the slope into the cell at a pole follows
    // the meridian), its centre or a corner.
    const size_t before = result->minima.size();
    for (int place = 0; place <= (1 << faceFactors) && result->minima.size() == before; ++place) {
      int fi = 0;
      double ref[3] = {0, 0, 0};
      for (int f = 0; f < shape.numFactors(); ++f) {
        const double t = f == factor ? localSide : (place == 0 ? 0.5 : ((place - 1) >> fi++) & 1);
        const double v0 = Vertex(slot, f, 0)[0], v1 = Vertex(slot, f, 1)[0];
        ref[f] = v0 + t * (v1 - v0);
      }
      Record(ref, result, strict ? factor : -1, side);
    }
    return;
  }
  CellView face;
  face.shape = CellShape(faceFactors == 1 ? CellType::Line : CellType::Quad, degrees);
  face.ambientDim = ad_;
  face.points = points.data();
  face.weights = cell_.weights ? weights.data() : nullptr;
  const CellSolver faceSolver(face);
  MinimaWorkspace faceWorkspace;
  const CellMinimaResult onFace = CellLocalMinima(faceSolver, point_, maxDistance_, &faceWorkspace);
  if (!onFace.certified) result->certified = false;
  for (const CellMinimum& m : onFace.minima) {
    int fi = 0;
    double ref[3] = {0, 0, 0};
    for (int f = 0; f < shape.numFactors(); ++f) {
      const double t = f == factor ? localSide : m.ref[fi++];
      const double v0 = Vertex(slot, f, 0)[0], v1 = Vertex(slot, f, 1)[0];
      ref[f] = v0 + t * (v1 - v0);
    }
    Record(ref, result, strict ? factor : -1, side);
  }
}

void MinimaSearch::Split(double* slot, int* factor, int* vi, int* vj) const {
  const CellShape& shape = cell_.shape;
  *factor = 0;
  *vi = 0;
  *vj = 1;
  if (shape.isBox() && shape.numFactors() > 1) {
    // As the cell search: across the line where the net bends most.
    const double* q = slot + kHeaderSize;
    if (MostBentLine(nets_.shape(), q, nets_.rational() ? q + n2_ : nullptr, 0.0, factor) > 0.0) return;
  }
  double longest = -1.0;
  for (int f = 0; f < shape.numFactors(); ++f) {
    const SimplexFactor& fac = shape.factor(f);
    for (int a = 0; a <= fac.dim; ++a) {
      for (int b = a + 1; b <= fac.dim; ++b) {
        double length2 = 0.0;
        for (int i = 0; i < fac.dim; ++i) {
          const double e = (Vertex(slot, f, a)[i] - Vertex(slot, f, b)[i]) * paramScale_[fac.offset + i];
          length2 += e * e;
        }
        if (length2 > longest) {
          longest = length2;
          *factor = f;
          *vi = a;
          *vj = b;
        }
      }
    }
  }
}

CellMinimaResult MinimaSearch::Run() {
  CellMinimaResult result;
  const double limit2 = maxDistance_ < kInf ? maxDistance_ * maxDistance_ : kInf;
  const int root = Allocate();
  {
    double* slot = Slot(root);
    std::fill(slot, slot + kHeaderSize, 0.0);
    for (int f = 0; f < cell_.shape.numFactors(); ++f) {
      for (int v = 1; v <= cell_.shape.factor(f).dim; ++v) Vertex(slot, f, v)[v - 1] = 1.0;
    }
    double* q = slot + kHeaderSize;
    nets_.SquaredDistanceNumerator(point_, q);
    std::copy(nets_.ww(), nets_.ww() + n2_, q + n2_);
    double* homogeneous = q + 2 * n2_;
    for (int c = 0; c < ncp_; ++c) {
      const double w = cell_.weights ? cell_.weights[c] : 1.0;
      for (int k = 0; k < ad_; ++k) homogeneous[static_cast<size_t>(k) * ncp_ + c] = w * cell_.points[static_cast<size_t>(c) * ad_ + k];
      homogeneous[static_cast<size_t>(ad_) * ncp_ + c] = w;
    }
  }
  std::vector<int>& stack = ws_->stack;
  stack.assign(1, root);
  std::vector<int> freeSlots;
  int examined = 0;
  const CellShape& netShape = nets_.shape();
  while (!stack.empty()) {
    const int s = stack.back();
    stack.pop_back();
    double* slot = Slot(s);
    const double* q = slot + kHeaderSize;
    const double* ww = q + n2_;
    double low = kInf, high = -kInf;
    for (int i = 0; i < n2_; ++i) {
      const double ratio = q[i] / ww[i];
      low = std::min(low, ratio);
      high = std::max(high, ratio);
    }
    low -= slack_;
    high += slack_;
    if (low > limit2 || MonotoneSomewhere(slot, low, high)) {
      freeSlots.push_back(s);
      continue;
    }
    if (AtMostOne(slot, std::max(low, 0.0), high)) {
      SolveIn(slot, &result);
      freeSlots.push_back(s);
      continue;
    }
    int side = 0;
    const int toward = MonotoneTowardFace(slot, low, high, &side);
    if (toward >= 0) {
      SolveOnFace(slot, toward, side, false, &result);
      freeSlots.push_back(s);
      continue;
    }
    unsigned faces = 0;
    if (SecondOrderExcludes(slot, std::max(low, 0.0), high, &faces)) {
      freeSlots.push_back(s);
      continue;
    }
    if (faces != 0 && lineFactors_) {
      for (int f = 0; f < cell_.shape.numFactors(); ++f) {
        if (!(faces & (1u << f))) continue;
        for (const int faceSide : {0, 1}) {
          if (ReachesFace(slot, f, faceSide)) SolveOnFace(slot, f, faceSide, true, &result);
        }
      }
      freeSlots.push_back(s);
      continue;
    }
    if (++examined > kMaxSubdomains || slot[kDepth] >= kMaxDepth) {
      // Out of budget: what a local solve finds here is still reported.
      result.certified = false;
      SolveIn(slot, &result);
      freeSlots.push_back(s);
      continue;
    }
    int factor = 0, vi = 0, vj = 1;
    Split(slot, &factor, &vi, &vj);
    for (int child = 0; child < 2; ++child) {
      const int keep = child == 0 ? vi : vj;
      const int move = child == 0 ? vj : vi;
      int c;
      if (!freeSlots.empty()) {
        c = freeSlots.back();
        freeSlots.pop_back();
      } else {
        c = Allocate();
      }
      double* parent = Slot(s);  // Allocate may have moved the pool
      double* target = Slot(c);
      std::copy(parent, parent + kHeaderSize, target);
      target[kDepth] = parent[kDepth] + 1;
      double* moved = Vertex(target, factor, move);
      const double* kept = Vertex(target, factor, keep);
      for (int i = 0; i < 3; ++i) moved[i] = 0.5 * (moved[i] + kept[i]);
      SplitNet(netShape, factor, keep, move, parent + kHeaderSize, target + kHeaderSize);
      SplitNet(netShape, factor, keep, move, parent + kHeaderSize + n2_, target + kHeaderSize + n2_);
      for (int k = 0; k <= ad_; ++k) {
        const size_t offset = kHeaderSize + 2 * n2_ + static_cast<size_t>(k) * ncp_;
        SplitNet(cell_.shape, factor, keep, move, parent + offset, target + offset);
      }
      stack.push_back(c);
    }
    freeSlots.push_back(s);
  }
  return result;
}

}  // namespace

CellMinimaResult CellLocalMinima(const CellSolver& solver, const double* point, double maxDistance,
                                 MinimaWorkspace* ws) {
  if (solver.isAffine() || solver.nets().size() == 0) {
    // An affine map: the distance is convex, its one local minimum is global.
    CellMinimaResult result;
    SolveWorkspace solveWorkspace;
    const CellSolveResult r = solver.Solve(point, nullptr, &solveWorkspace);
    if (r.distance <= maxDistance) {
      CellMinimum minimum;
      std::copy(r.ref, r.ref + 3, minimum.ref);
      std::copy(r.closest, r.closest + 3, minimum.closest);
      minimum.distance = r.distance;
      result.minima.push_back(minimum);
    }
    return result;
  }
  MinimaSearch search(solver, point, maxDistance, ws);
  return search.Run();
}

}  // namespace invmap::kernels
