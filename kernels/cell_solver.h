// The closest point on ONE cell: a local active-set Newton solve (algorithm 5)
// made global over the cell by a certified branch and bound.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "kernels/cell_charts.h"
#include "kernels/cell_map.h"
#include "kernels/curvature_bounds.h"
#include "kernels/distance_net.h"
#include "kernels/local_solver.h"
#include "kernels/tolerances.h"
#include "kernels/trimmed_cell.h"

namespace invmap::kernels {

/// Outcome of one point's solve on one cell.
enum class PointStatus : std::uint8_t {
  Converged,            ///< Global minimum over the cell, in the interior of the reference domain.
  ProjectedToBoundary,  ///< Global minimum over the cell, on a face, edge or vertex of the domain.
  NotCertified,         ///< Best point found, but the search budget ran out before
                        ///< every other part of the cell was excluded (near-ties, evolutes).
  InvalidInput,         ///< The query point has a NaN or infinite coordinate.
  Farther,              ///< No point of the cell is closer than the caller's bound
                        ///< (see Solve); the other fields are not meaningful.
};

/// Result of one point's solve on one cell.
struct CellSolveResult {
  double ref[3] = {0, 0, 0};      ///< Reference coordinates of the closest point (paramDim used).
  double closest[3] = {0, 0, 0};  ///< The closest point, the cell's map at `ref`.
  double distance = 0.0;          ///< Euclidean distance from the query point (+infinity
                                  ///< where its square overflows, beyond about 1e154).
  PointStatus status = PointStatus::InvalidInput;
  int iterations = 0;  ///< Newton iterations over all local solves of this query.
};

/// Reusable scratch memory for CellSolver::Solve, so the hot path never
/// allocates once warmed up. One per thread; not shared between threads.
struct SolveWorkspace {
  std::vector<double> nets;      ///< Bernstein nets of the search's subdomains.
  std::vector<int> freeSlots;    ///< Recycled subdomain slots.
  std::vector<int> heap;         ///< Subdomains ordered by lower bound.
  std::vector<double> scratch;   ///< Derivative nets of the convexity test.
};

/// A batch of queries against one cell, structure of arrays. Lane l's point
/// is (coord[0][l], coord[1][l], coord[2][l]); coord[2] is unused in 2D.
struct QueryLane {
  int count = 0;
  const double* coord[3] = {nullptr, nullptr, nullptr};
  /// Optional: initial reference coordinates per lane (warm start), same
  /// layout; nullptr starts from the cell's center.
  const double* initialRef[3] = {nullptr, nullptr, nullptr};
  /// Optional: per lane, the squared distance of the best point found
  /// elsewhere (Solve's bound2; +infinity for none); nullptr for no bounds.
  const double* bound2 = nullptr;
};

/// Output arrays of a QueryLane, each of length count (ref and closest as
/// three separate arrays, the unused ones may be null).
struct ResultLane {
  double* ref[3] = {nullptr, nullptr, nullptr};
  double* closest[3] = {nullptr, nullptr, nullptr};
  double* distance = nullptr;
  PointStatus* status = nullptr;
  int* iterations = nullptr;
};

/// The solver for one cell. Construction precomputes the cell's bounds, size,
/// affine flag and the point-independent parts of its squared-distance nets;
/// afterwards Solve is const and thread-safe (given one workspace per thread).
/// The view's arrays must outlive the solver.
class CellSolver {
 public:
  /// Precondition: cell.shape.IsValid(), ambientDim in {2, 3} and
  /// paramDim <= ambientDim, weights in [1 / kMaxWeight, kMaxWeight],
  /// finite control points.
  explicit CellSolver(const CellView& cell);
  /// An empty solver, to be assigned; Solve must not be called on it.
  CellSolver() = default;

  /// Closest point on the cell to `point` (ambientDim coordinates). The result
  /// is the global minimum over the reference domain up to the tolerances of
  /// kernels/tolerances.h. `initialRef` (optional) seeds the first local solve.
  /// `bound2`: the squared distance of the best point found elsewhere; parts
  /// of the cell that cannot beat it are skipped, and a cell that cannot beat
  /// it at all returns status Farther (often without any Newton iteration).
  /// `model` (optional) receives the local model at the answer, when the
  /// answer is a curved cell's local solve's (known = false otherwise).
  CellSolveResult Solve(const double* point, const double* initialRef, SolveWorkspace* ws,
                        double bound2 = std::numeric_limits<double>::infinity(), AnswerModel* model = nullptr) const;

  /// Volume cells only: the local full-rank solve alone (7.3.2.1), from the
  /// point's barycentric place in a tetrahedron's corners, else from
  /// `initialRef`, else from the center. Returns
  /// true, with `result` filled, when it converges to a point of the cell
  /// within the distance tolerance of `point` (the point is inside: the
  /// answer is exact and global); false otherwise, with result.iterations
  /// set and result.ref where the solve stopped (the centre when none ran):
  /// on a face of the domain when the point drove it out there; for an
  /// affine cell of FrameCoordinates, the point's preimage beyond the
  /// domain. kernels::FacesAt names the face (the one a walk toward the
  /// point crosses; in a curved cell only a likely one).
  /// `cornerLambda` (4 values): CornerBarycentric(point) when the caller
  /// has it, so it is not computed again.
  bool SolveInside(const double* point, const double* initialRef, CellSolveResult* result,
                   const double* cornerLambda = nullptr) const;

  /// Solves every lane of `queries`; see QueryLane and ResultLane. Affine
  /// segments, triangles and tetrahedra solve all lanes at once in closed
  /// form (vectorized, kernels/affine_simplex_lanes.h); curved curves and
  /// surfaces of line factors run their local solves in SIMD lanes
  /// (kernels/newton_lanes.h) and certify each lane as Solve does; other
  /// cells solve the lanes one after the other (initialRef warm-starts
  /// each). Every lane's answer is the certified global minimum over the
  /// cell, and depends on its own point and start only.
  void SolveLane(const QueryLane& queries, const ResultLane& results, SolveWorkspace* ws) const;

  /// SolveInside for every lane of `queries` (initialRef as SolveInside's):
  /// inside[l] says whether lane l's point is inside, and then `results`
  /// holds its answer (the other lanes' entries are not meaningful). The
  /// local solves of polynomial tetrahedra run in SIMD lanes
  /// (kernels/newton_lanes.h); other cells solve lane by lane.
  void SolveInsideLane(const QueryLane& queries, const ResultLane& results, bool* inside) const;

  /// Tetrahedra: the smallest barycentric coordinate of `point` relative to
  /// the cell's corner control points (its vertices): positive inside the
  /// straight tetrahedron they span, the likeliest to hold the point when the
  /// cell is curved. Affine volume cells of other types: the smallest
  /// barycentric coordinate of the point's preimage (FrameCoordinates).
  /// Other cells: -kInsideScoreUnknown.
  double InsideScore(const double* point) const;
  static constexpr double kInsideScoreUnknown = 1e300;

  /// Tetrahedra: barycentric coordinates (lambda_0 .. lambda_3, lambda_k for
  /// reference vertex k) of `point` relative to the cell's corner control
  /// points; false for other cells and flat corner tetrahedra.
  bool CornerBarycentric(const double* point, double* lambda) const;
  /// CornerBarycentric for the tetrahedron of vertices v[0..3] (3D), for
  /// callers that keep the vertices elsewhere: the same values, bit for bit.
  static bool TetBarycentric(const double* const* v, const double* point, double* lambda);

  /// Affine cells as wide as their space other than simplices
  /// (parallelepiped hexahedra, straight wedges, parallelograms in the
  /// plane): the reference coordinates whose image is `point`, in closed
  /// form from the corners at the reference origin and unit points; outside
  /// the domain when the point is outside the cell. False for other cells
  /// and flat ones.
  bool FrameCoordinates(const double* point, double* ref) const;

  /// True for tetrahedral cells in 3D (CornerPoint is then defined).
  bool isTetrahedron() const { return cornerControl_[0] >= 0 && cell_.shape.paramDim() == 3 && cell_.ambientDim == 3; }
  /// Simplex cells: the control point at corner `v` (the vertex where
  /// barycentric coordinate v is one).
  const double* CornerPoint(int v) const {
    return cell_.points + static_cast<size_t>(cornerControl_[v]) * cell_.ambientDim;
  }

  /// True for affine segments, triangles and tetrahedra, solved in closed form.
  bool isAffineSimplex() const { return vertexControl_[0] >= 0; }

  /// The closed-form answer (7.3.2.2) on the affine segment, triangle or
  /// tetrahedron with vertices v[0..paramDim], as Solve gives it for such a
  /// cell without a bound: for callers that keep the vertices elsewhere.
  static void SolveAffineSimplex(int paramDim, int ambientDim, const double* const* v, const double* point,
                                 CellSolveResult* result);

  /// SolveLane's answers on the affine segment, triangle or tetrahedron
  /// with vertices v[0..paramDim], as SolveAffineSimplex's lane by lane.
  static void SolveAffineSimplexLane(int paramDim, int ambientDim, const double* const* v, const QueryLane& queries,
                                     const ResultLane& results);

  const CellView& cell() const { return cell_; }
  /// Axis-aligned box of the control points: lo[k], hi[k].
  const double* boxLo() const { return boxLo_; }
  const double* boxHi() const { return boxHi_; }
  /// Diagonal of the control-point box, the length scale of the tolerances.
  double size() const { return size_; }
  /// size() of a cell whose control-point box is lo[0..dim), hi[0..dim): its
  /// diagonal, or a tiny positive length for a cell of a single point.
  static double SizeOfBox(const double* lo, const double* hi, int dim);
  /// True when the map is affine (then the squared distance is convex and
  /// one local solve is the global answer).
  bool isAffine() const { return affine_; }
  /// The distance nets of a curved cell (built around the control box's
  /// centre); empty (size 0) for an affine cell, which needs none.
  const DistanceNets& nets() const { return nets_; }
  /// Heap memory of the precomputed nets and bounds, in bytes.
  std::size_t NetMemoryBytes() const { return nets_.MemoryBytes() + (curvature_ ? sizeof(CurvatureBounds) : 0); }
  /// True when the cell is a volume (paramDim == ambientDim).
  bool isFullRank() const { return cell_.shape.paramDim() == cell_.ambientDim; }

  /// Makes the cell one that its trimmed face's loops cross (surfaces of
  /// line factors only): Solve then answers only points of the face's
  /// region and returns Farther when the cell holds no candidate there
  /// (kernels/trimmed_cell.h). `trim` must outlive the solver; null undoes it.
  void SetTrim(const TrimmedCell* trim) { trim_ = trim; }
  const TrimmedCell* trim() const { return trim_; }

 private:
  /// The branch and bound over subdomains of the reference domain that makes
  /// the local answer `best` global; returns false when the budget ran out.
  /// Closed-form answer for affine line, tri and tet cells (7.3.2.2).
  void SolveAffineSimplex(const double* point, CellSolveResult* result) const;
  /// SolveLane for curved cells: the local solves in SIMD lanes
  /// (kernels/newton_lanes.h) where they cover the cell, then each lane's
  /// certificate as Solve's; lanes that leave the lanes, and cells they do
  /// not cover, are solved by Solve (kernels/cell_solver_lanes.cpp).
  void SolveCurvedLanes(const QueryLane& queries, const ResultLane& results, SolveWorkspace* ws) const;
  /// SolveInside's start for a point whose corner barycentrics are
  /// `lambda` (when haveLambda), else `initialRef`, else the centre; false
  /// when `lambda` puts the point beyond the control points' hull (not inside).
  bool InsideStart(const double* initialRef, const double* lambda, bool haveLambda, double* start) const;
  /// SolveInside's local solve from `start` and its verdict.
  bool FinishInside(const double* point, const double* start, CellSolveResult* result) const;
  /// Writes lane l of `results` from one cell's answer.
  void WriteLane(int l, const CellSolveResult& r, const ResultLane& results) const;

  /// Cells of line factors (line, quad, hex): the Greville parameters of the
  /// control point nearest to `point`, a start for the local solve that is
  /// closer than the center; false for other cells.
  bool NearestControlPointStart(const double* point, double* ref) const;

  /// True when g = q - level WW is convex over the whole cell, where the
  /// local solve's tangent plane (LocalSolveResult::aboveLevel) then bounds
  /// it from below. `q`: the q net of `point`, overwritten with g's net
  /// unless the curvature bounds alone prove it; `slack`: the nets'
  /// RoundingSlack at `point`.
  bool ExcessIsConvex(const double* point, double level, double slack, double* q) const;

  /// LocalSolve on this cell; for unbalanced weights in the chart that
  /// resolves the start, and the answer's, best (kernels/cell_charts.h). The
  /// answer's ref is in the cell's own reference coordinates.
  LocalSolveResult LocalSolveCharted(const double* point, const double* start, const LocalSolveOptions& options) const;

  /// Unbalanced cells: `stalled`, a local solve in `chart` that hit its
  /// iteration cap or stopped short of a KKT point, carried on by LayerNewton and polished by LocalSolve with
  /// `options`; the nearer of the two. Adds the iterations to *iterations.
  LocalSolveResult LayerPolish(const CellView& chart, const double* point, const LocalSolveResult& stalled,
                               const LocalSolveOptions& options, int* iterations) const;

  /// Unbalanced cells: local solves from `best` moved onto each face of each
  /// factor; keeps any nearer answer.
  void SeedFaceLayers(const double* point, LocalSolveResult* best, int* iterations) const;

  /// The rounding the convexity and face certificates must see past in a net
  /// of q - c WW: for a rational cell of unbalanced weights (`ww` its WW
  /// net), slack WW_i; none otherwise.
  NetNoise RoundingNoise(const double* ww, double slack) const;

  /// Lower bound of the squared distance from `point` to the cell: the
  /// smallest Bernstein coefficient ratio of the squared distance (exact for
  /// constant distance, tighter than the box) less `slack`, the nets'
  /// RoundingSlack at `point`; the box distance for affine cells. Curved
  /// cells leave the q net of `point` in ws->scratch.
  double SquaredDistanceLowerBound(const double* point, double slack, SolveWorkspace* ws) const;

  /// Trimmed cells: KKT points of the cell that lie outside the face's
  /// region (kept to drop the subdomains around them, see Search).
  struct Rejected {
    static constexpr int kCapacity = 4;
    int count = 0;
    LocalSolveResult points[kCapacity];
    void Add(const LocalSolveResult& r) {
      if (r.kkt && count < kCapacity) points[count++] = r;
    }
  };

  /// `slack`: the nets' RoundingSlack at `point`. `rejected`: trimmed cells'
  /// KKT points outside the region (more are added as found); null otherwise.
  bool Search(const double* point, double bound2, double slack, LocalSolveResult* best, int* iterations,
              SolveWorkspace* ws, Rejected* rejected) const;

  /// Trimmed cells: false when the subdomain in `slot` (its net `q`, `ww`)
  /// can hold no candidate for the face's closest point: no KKT point of a
  /// squared distance up to `level2` (the best so far), or none inside the
  /// region (kernels/kkt_exclusion.h).
  bool MayHoldTrimmedMinimum(double* slot, const double* q, const double* ww, double level2, double slack) const;

  CellView cell_;
  double boxLo_[3] = {0, 0, 0};
  double boxHi_[3] = {0, 0, 0};
  double size_ = 0.0;
  bool affine_ = false;
  /// Affine simplex cells (line, tri, tet): control points at the vertices,
  /// solved in closed form; -1 otherwise.
  int vertexControl_[4] = {-1, -1, -1, -1};
  /// Simplex cells: the control points at the vertices; -1 otherwise.
  int cornerControl_[4] = {-1, -1, -1, -1};
  double paramScale_[3] = {1, 1, 1};  ///< |dx/du_i| at the center: the length of a unit step in u_i.
  /// Tetrahedra: how far (in corner barycentric coordinates) the control
  /// points, and so the cell, reach beyond the straight corner tetrahedron.
  double cornerHullMargin_ = std::numeric_limits<double>::infinity();
  /// FrameCoordinates' cells: the control points at the reference origin
  /// and at the unit point of each parameter; -1 otherwise. (After the
  /// fields a walk through tetrahedra reads, to keep them on their lines.)
  int frameControl_[4] = {-1, -1, -1, -1};
  DistanceNets nets_;
  const HessianStencil* stencil_ = nullptr;  ///< Shared per shape; null for affine cells.
  /// Rational cells whose WW coefficients span more than kUnbalancedWeights.
  bool unbalancedWeights_ = false;
  /// The search's deepest bisection, its budget of subdomains and of hard
  /// seeds: kMaxDepth, kMaxSubdomains and kHardSeeds, more for unbalanced weights.
  int maxDepth_ = kMaxDepth;
  int maxSubdomains_ = kMaxSubdomains;
  int maxHardSeeds_ = kHardSeeds;
  /// Unbalanced weights only: the cell re-rooted at every choice of vertices.
  std::unique_ptr<const CellCharts> charts_;
  /// Curved cells whose weights are nearly equal (null otherwise: most
  /// cells of large meshes are affine, and a pointer keeps their solvers small).
  std::unique_ptr<const CurvatureBounds> curvature_;
  /// Cells of a trimmed face that its loops cross (see SetTrim); null otherwise.
  const TrimmedCell* trim_ = nullptr;
};

}  // namespace invmap::kernels
