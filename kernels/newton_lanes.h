// The local solve of many query points on ONE curved cell at once, one point
// per SIMD lane (structure of arrays): Newton steps, the bounds of the
// domain, the stationarity and release tests and the KKT check are lane
// masks. A lane whose solve leaves the common path (a step that the line
// search would have to shorten, a Hessian that is not positive definite, a
// constraint to release) stops there and hands its iterate to the scalar
// local solve (kernels/local_solver.h), which carries on from it.
//
// Covered cells: curves (2D or 3D) and surfaces in 3D whose factors are all
// lines (line and quad cells), polynomial or rational, any degree up to
// kMaxDegree; cubic factors get loops of constant length.
//
// Each lane runs the same IEEE operations whatever the other lanes hold and
// whatever the vector width: AVX-512, AVX2 and SSE2 give the same answer bit
// for bit (the flags keep the compiler from fusing multiplies and adds), so
// an answer never depends on which points shared its vector, nor on the
// machine's instruction set.
#pragma once

#include <cstdint>

#include "kernels/cell_map.h"
#include "kernels/curvature_bounds.h"

namespace invmap::kernels {

/// The instruction sets the lanes are compiled for.
enum class LaneIsa : std::uint8_t { Sse2, Avx2, Avx512 };

/// The widest instruction set this processor (and the OS) runs; detected
/// once.
LaneIsa BestLaneIsa();
/// Name for reports ("avx512", "avx2", "sse2").
const char* LaneIsaName(LaneIsa isa);
/// True when this processor runs `isa`.
bool LaneIsaAvailable(LaneIsa isa);

/// How a lane's local solve ended.
enum class LaneOutcome : std::uint8_t {
  /// A KKT point (independently checked, as LocalSolveResult::kkt), with
  /// `closest` and `squaredDistance` set.
  Kkt,
  /// Left the lanes: `ref` is the iterate to continue from in the scalar solve.
  Handover,
  /// Stopped at `ref`, where the tangent plane of W^2 (|x - p|^2 - level)
  /// stays positive over the whole domain (TangentPlaneLowerBound with the
  /// lane's exclusionLevel): the cell cannot beat the level if that function
  /// is also convex, which the caller confirms (LocalSolve's exclusion).
  AboveLevel,
};

/// Lanes of one call, structure of arrays; every array has `count` entries.
struct NewtonLanes {
  int count = 0;
  /// Query points (ambientDim arrays).
  const double* point[3] = {nullptr, nullptr, nullptr};
  /// In: the starts (paramDim arrays, clamped into [0, 1]); out: the KKT
  /// point or the iterate handed over.
  double* ref[3] = {nullptr, nullptr, nullptr};
  /// Out (Kkt lanes): the map at ref and |closest - point|^2.
  double* closest[3] = {nullptr, nullptr, nullptr};
  double* squaredDistance = nullptr;
  /// Out (Kkt lanes): true when a constraint is held at the answer.
  bool* onBoundary = nullptr;
  LaneOutcome* outcome = nullptr;
  /// Out: Newton iterations of each lane.
  int* iterations = nullptr;
  /// In: instead of `ref`, start at the Greville parameters of the control
  /// point nearest to each point (as the scalar solve's cold start).
  bool startAtNearestControlPoint = false;
  /// In (optional, surfaces): per lane, the level of LocalSolve's exclusion
  /// test (LocalSolveOptions::exclusionLevel), tried at each iterate until
  /// it first holds; -infinity for none.
  const double* exclusionLevel = nullptr;
};

/// True for the cells SolveNewtonLanes covers (see the top of this file).
bool NewtonLanesCover(const CellView& cell);

/// The local solve of every lane on `cell` (NewtonLanesCover(cell)), with the
/// tolerances of LocalSolve for a cell of length scale `size`. Query points
/// must be finite.
void SolveNewtonLanes(const CellView& cell, double size, const NewtonLanes& lanes, LaneIsa isa = BestLaneIsa());

/// How a lane's inside solve (SolveInsideLanes) ended.
enum class InsideOutcome : std::uint8_t {
  Inside,     ///< Converged within the distance tolerance of the point: `ref`, `closest` set.
  NotInside,  ///< Converged farther than that: the point is not in the cell.
  Handover,   ///< Left the lanes: the scalar inside solve decides (from the lane's start).
};

/// Lanes of SolveInsideLanes, structure of arrays of `count` entries.
struct InsideLanes {
  int count = 0;
  const double* point[3] = {nullptr, nullptr, nullptr};
  /// In: the starts (inside the domain); out: the answers of Inside lanes.
  double* ref[3] = {nullptr, nullptr, nullptr};
  double* closest[3] = {nullptr, nullptr, nullptr};  ///< Out (Inside lanes).
  double* squaredDistance = nullptr;                 ///< Out (Inside and NotInside lanes).
  InsideOutcome* outcome = nullptr;
  int* iterations = nullptr;
};

/// True for the cells SolveInsideLanes covers: polynomial tetrahedra in 3D.
bool InsideLanesCover(const CellView& cell);

/// The inside solve of CellSolver::SolveInside for every lane on `cell`
/// (InsideLanesCover(cell)): LocalSolve's full-rank Newton steps -J^-1 r
/// (7.3.2.1) from each lane's start, with its tolerances for a cell of length
/// scale `size`; a step that would leave the domain or fail Armijo's test at
/// once hands the lane over. Query points must be finite.
void SolveInsideLanes(const CellView& cell, double size, const InsideLanes& lanes, LaneIsa isa = BestLaneIsa());

/// Lower bounds of the squared distance from `count` points to a cell, from
/// the nets of DistanceNets (NN = |N|^2, NW_k = N_k W and WW = W^2, built
/// around `center`): per point d = p - center and
///   min_i (NN_i - 2 d . NW_i + |d|^2 WW_i) / WW_i,
/// one fused loop over the coefficients for all lanes (the quotient only for
/// a rational cell: a polynomial cell's WW is 1 up to rounding). The values
/// are DistanceNets::SquaredDistanceNumerator's and NetLowerBound's, bit
/// for bit; the caller subtracts the rounding slack.
struct NetLanes {
  int size = 0;  ///< Coefficients per net.
  int ambientDim = 3;
  bool rational = false;
  const double* nn = nullptr;
  const double* nw[3] = {nullptr, nullptr, nullptr};
  const double* ww = nullptr;
  const double* center = nullptr;
};
void NetLowerBoundLanes(const NetLanes& nets, int count, const double* const point[3], double* lowerBound,
                        LaneIsa isa = BestLaneIsa());

/// CurvatureBounds::ProvesConvex for `count` points at once: proved[l] is
/// its answer for point l (the same arithmetic, lane by lane) and level[l].
/// Cells of one or two parameters.
void ProvesConvexLanes(const CurvatureBounds& bounds, int count, const double* const point[3], const double* level,
                       bool* proved, LaneIsa isa = BestLaneIsa());

/// The lanes' access to CurvatureBounds' ranges.
struct CurvatureLanes {
  template <class Arch>
  static void Prove(const CurvatureBounds& bounds, int count, const double* const point[3], const double* level,
                    bool* proved);
};

}  // namespace invmap::kernels
