// Independent reference for the cell kernels: a naive Bezier evaluator, a
// brute-force closest-point search and generators of test cells and queries.
//
// Nothing here calls into kernels/ beyond the plain types CellType, CellShape
// and CellView: the tests compare the solver against this code, so a bug shared
// by both would go unnoticed. Keep it that way.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "kernels/cell_map.h"
#include "kernels/cell_shape.h"

namespace invmap::testing {

/// An owning Bezier cell for tests: the same data as kernels::CellView, kept
/// alive in vectors.
struct RefCell {
  kernels::CellType type = kernels::CellType::Line;
  /// Degree per simplex factor as in docs/formats.md section 2 (line [p], tri [p],
  /// quad [p, q], tet [p], hex [p, q, r], wedge [p_tri, q_line]); unused
  /// entries are 0.
  std::array<int, 3> degrees{{0, 0, 0}};
  int ambientDim = 3;  ///< 2 or 3.
  /// Control points, Cartesian, point-major (point k's coordinate i at
  /// points[k * ambientDim + i]), docs/formats.md section 1 order.
  std::vector<double> points;
  /// One positive weight per control point; empty for a polynomial cell.
  std::vector<double> weights;

  /// Non-owning view for the kernels; valid while this RefCell lives and its
  /// vectors are not resized.
  kernels::CellView view() const;
  /// The shape (type and degrees) as the kernels see it.
  kernels::CellShape shape() const;
  /// 1, 2 or 3.
  int paramDim() const;
  /// Product of the factors' basis sizes; points.size() / ambientDim.
  int numControlPoints() const;
  /// True when weights are given.
  bool isRational() const { return !weights.empty(); }
  /// Diagonal of the control points' axis-aligned box: the length scale of
  /// every tolerance (the same definition as CellSolver::size()).
  double size() const;
};

/// Human-readable dump of a cell (type, degrees, every control point and
/// weight with 17 significant digits) for failure diagnostics: enough to
/// rebuild the cell by hand.
std::string Describe(const RefCell& cell);

/// Parametric dimension of a cell type (1, 2 or 3).
int ParamDimOf(kernels::CellType type);

/// Evaluates the map of `cell` at reference coordinates `ref` (paramDim
/// values) into `x` (ambientDim values), by the direct multinomial formula
/// B_a = p!/(a0!..ad!) l0^a0..ld^ad per simplex factor, multiplied across
/// factors; rational cells divide sum(w B P) by sum(w B). Points outside the
/// domain evaluate the polynomial extension.
void RefEvaluate(const RefCell& cell, const double* ref, double* x);

/// Map value with first and second derivatives, computed by the product rule
/// on the same multinomial formula (independent of kernels::EvaluateMap).
/// Indices: k = ambient coordinate, i, j = parametric coordinate.
struct RefJet {
  double x[3] = {0, 0, 0};
  double d1[3][3] = {};     ///< dx_k/du_i as d1[k][i].
  double d2[3][3][3] = {};  ///< d2x_k/du_i du_j as d2[k][i][j].
};

/// Evaluates value and derivatives of the map at `ref`; `order` 0, 1 or 2.
void RefEvaluateJet(const RefCell& cell, const double* ref, int order, RefJet* out);

/// True when `ref` (paramDim values) lies in the reference domain of `type`
/// up to `tol` on every constraint (docs/formats.md section 1).
bool InReferenceDomain(kernels::CellType type, const double* ref, double tol);

/// Reference location of every control point (paramDim values each, stored
/// as 3): simplex multi-index a at (a1/p, .., ad/p), concatenated across
/// factors. A degree-0 factor puts its single point at the factor's centroid.
std::vector<std::array<double, 3>> ControlPointRefLocations(kernels::CellType type,
                                                            const std::array<int, 3>& degrees);

/// Closest point found by BruteForceClosest.
struct RefClosest {
  double distance = 0.0;             ///< Euclidean distance to the query point.
  std::array<double, 3> ref{{0, 0, 0}};  ///< Reference coordinates (paramDim used), in the domain.
  std::array<double, 3> x{{0, 0, 0}};    ///< RefEvaluate(cell, ref).
  int starts = 0;                    ///< Local solves run (diagnostics).
};

/// Tuning of the brute-force search.
struct BruteForceOptions {
  /// Lattice divisions per parameter direction; 0 picks 256, 64 and 32 for
  /// curves, surfaces and volumes (about 260, 4200 and 36000 samples for
  /// line, quad and hex).
  int divisions = 0;
  /// At most this many sampled local minima are polished per query.
  int maxStarts = 12;
  /// The nearest this many samples are polished whether or not they are
  /// local minima (folds can hide a basin inside one lattice step).
  int nearestStarts = 3;
};

/// Brute-force closest point search for one cell, with the per-cell work done
/// once: construction samples the map on a lattice of the reference domain
/// (whose points include every face, edge and vertex) and builds a k-d tree
/// over the samples. A query:
///  1. polishes the nearest sample; a distance of zero ends the search;
///  2. takes every sample within `resolution()` of that distance (the global
///     minimizer's nearest sample is among them);
///  3. polishes, best first, the lattice-local minima among them (at most
///     maxStarts), the next nearestStarts - 1 samples, and every local
///     minimum of a group of samples that the map collapses onto one point
///     (a collapsed edge, a pole), where each sample is a stationary point
///     of its own.
/// Polishing is an active-set Newton method on the polytope of the reference
/// domain: steps stop at the constraints they hit, Lagrange multipliers
/// release them, so faces, edges and vertices are all reached. The distance
/// is accurate to about 1e-13 of the cell size when the lattice resolves the
/// global minimum's basin, which the generators below are made for (and
/// ReferenceBruteForce.AgreesWithADenserSearchOnCurvedCells checks).
///
/// Not thread-safe: Closest reuses per-object scratch.
class BruteForceReference {
 public:
  explicit BruteForceReference(const RefCell& cell, BruteForceOptions options = {});
  ~BruteForceReference();
  BruteForceReference(BruteForceReference&&) noexcept;
  BruteForceReference& operator=(BruteForceReference&&) noexcept;

  /// Closest point on the cell to `point` (ambientDim coordinates, finite).
  RefClosest Closest(const double* point);

  /// Local constrained minimization of the distance from `start` (paramDim
  /// values, projected into the domain first). Exposed for tests of the
  /// reference itself.
  RefClosest Polish(const double* point, const double* start) const;

  /// The reference's own copy of the cell.
  const RefCell& cell() const;
  /// Number of lattice samples.
  int numSamples() const;
  /// Physical sampling resolution: every point of the cell lies within this
  /// distance of a sample (estimated from the lattice with a safety factor).
  double resolution() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One-shot convenience: BruteForceReference(cell).Closest(point). Slow
/// (builds the lattice each call); use BruteForceReference for many queries.
RefClosest BruteForceClosest(const RefCell& cell, const double* point);

/// A random curved, non-degenerate cell: the control points start at their
/// reference locations under a random well-conditioned affine map (scaled to
/// a size of order 1, randomly translated), then move by random offsets of
/// 10% to 25% of the cell size. Surfaces and curves with ambientDim 3 are
/// embedded in a random plane/line before the offsets (which are 3D, so they
/// bend out of that plane). A draw is redrawn (with slowly shrinking offsets)
/// unless, on a sample lattice, the Jacobian measure stays above 5% of its
/// affine value (signed, so positive, for full-rank cells) and no two parts
/// of the cell come closer than 20% of the affine stretch times their
/// parametric distance (no folds or near self-contact). Rational cells draw
/// weights log-uniformly in [0.5, 2]. Every factor gets degree `degree`.
/// Precondition: paramDim(type) <= ambientDim, 1 <= degree <= 8.
RefCell RandomCurvedCell(kernels::CellType type, int degree, bool rational, int ambientDim,
                         std::mt19937_64& rng);

/// Same as RandomCurvedCell with per-factor degrees (docs/formats.md order).
RefCell RandomCurvedCell(kernels::CellType type, const std::array<int, 3>& degrees, bool rational,
                         int ambientDim, std::mt19937_64& rng);

/// Control points at their reference locations under the affine map
/// x = A ref + b (A is ambientDim x paramDim, row-major; b has ambientDim
/// values): an affine cell whose map is exactly A ref + b.
RefCell AffineCell(kernels::CellType type, const std::array<int, 3>& degrees, int ambientDim,
                   const double* a, const double* b);

/// A 2D quad bent into a C (an annular sector of 300 degrees, inner radius
/// 0.5, outer 1, centered at the origin): the first parameter runs along the
/// arc, the second across it. The control net interpolates the exact sector at
/// Chebyshev-like nodes, so the cell's centre of curvature (the origin) is
/// nearly equidistant to the whole inner arc. Degrees (degree, 1).
/// Precondition: 2 <= degree <= 8.
RefCell CShapedQuad(int degree);

/// A 2D quad wound along 1.25 turns of an Archimedean spiral (degree 8 along
/// the spiral, 1 across; arms do not overlap). Points between arms have
/// several far-apart local minima.
RefCell SpiralQuad();

/// A quadratic 2D quad whose whole t = 1 edge collapses to one point (a
/// triangle parametrized by a quad): the Jacobian vanishes along that edge.
RefCell CollapsedEdgeQuad();

/// A quadratic triangle whose six control points are collinear in 2D: the
/// cell has zero area and maps onto a segment (folded over itself).
RefCell ZeroAreaTriangle();

/// Center and radius of PoleQuad's sphere.
constexpr std::array<double, 3> kPoleQuadCenter{{0.25, -0.5, 0.125}};
constexpr double kPoleQuadRadius = 1.5;

/// Rational biquadratic patch of revolution covering exactly one octant of a
/// sphere (center kPoleQuadCenter, radius kPoleQuadRadius): the first
/// parameter turns around the z axis from +x to +y, the second runs along the
/// meridian from the equator to the pole, so the last row of control points
/// coincides at the pole. For a query c + rho v with v a unit vector of the
/// open positive octant and rho > 0, the distance is |rho - R|.
RefCell PoleQuad();

/// Rational quadratic quarter circle in 2D (exact): from center + (R, 0) to
/// center + (0, R) counter-clockwise, weights 1, sqrt(2)/2, 1.
RefCell QuarterCircleArc(const std::array<double, 2>& center, double radius);

/// Kinds of query points relative to a cell.
enum class QueryKind : std::uint8_t {
  Inside,    ///< The image of a random reference point (on the cell; inside a volume).
  Near,      ///< Inside moved by 1e-9..0.2 cell sizes in a random direction.
  Far,       ///< Inside moved by 1..4 cell sizes in a random direction.
  Boundary,  ///< A random point of a random face, edge or vertex of the domain,
             ///< mapped and moved outward (or not at all) so the answer lies there.
};

/// Name of a query kind for diagnostics.
const char* QueryKindName(QueryKind kind);

/// A query point with how it was made.
struct Query {
  std::array<double, 3> point{{0, 0, 0}};
  QueryKind kind = QueryKind::Inside;
  /// The reference point whose image the query started from.
  std::array<double, 3> sourceRef{{0, 0, 0}};
};

/// The centre of the reference domain of `type` (docs/formats.md section 1):
/// each simplex factor's centroid.
std::array<double, 3> RefDomainCenter(kernels::CellType type);

/// Uniformly distributed point of the reference domain of `type`.
std::array<double, 3> RandomRefPoint(kernels::CellType type, std::mt19937_64& rng);

/// A point on a random proper face (facet, edge or vertex) of the reference
/// domain; `outwardRef` (optional) receives the sum of the outward normals of
/// the constraints that are active there.
std::array<double, 3> RandomBoundaryRefPoint(kernels::CellType type, std::mt19937_64& rng,
                                             std::array<double, 3>* outwardRef = nullptr);

/// A random query of the given kind (see QueryKind).
Query RandomQuery(const RefCell& cell, QueryKind kind, std::mt19937_64& rng);

}  // namespace invmap::testing
