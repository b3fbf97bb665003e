#include "kernels/newton_lanes.h"

namespace invmap::kernels {
namespace lanes {
// One definition per instruction set, each in its own file compiled for it
// (newton_lanes_<isa>.cpp, newton_lanes_impl.h).
void SolveNewtonLanesSse2(const CellView& view, double size, const NewtonLanes& lanes);
void SolveNewtonLanesAvx2(const CellView& view, double size, const NewtonLanes& lanes);
void SolveNewtonLanesAvx512(const CellView& view, double size, const NewtonLanes& lanes);
void NetLowerBoundLanesSse2(const NetLanes& nets, int count, const double* const point[3], double* lower);
void NetLowerBoundLanesAvx2(const NetLanes& nets, int count, const double* const point[3], double* lower);
void NetLowerBoundLanesAvx512(const NetLanes& nets, int count, const double* const point[3], double* lower);
void ProvesConvexLanesSse2(const CurvatureBounds& bounds, int count, const double* const point[3], const double* level,
                           bool* proved);
void ProvesConvexLanesAvx2(const CurvatureBounds& bounds, int count, const double* const point[3], const double* level,
                           bool* proved);
void ProvesConvexLanesAvx512(const CurvatureBounds& bounds, int count, const double* const point[3],
                             const double* level, bool* proved);
void SolveInsideLanesSse2(const CellView& view, double size, const InsideLanes& lanes);
void SolveInsideLanesAvx2(const CellView& view, double size, const InsideLanes& lanes);
void SolveInsideLanesAvx512(const CellView& view, double size, const InsideLanes& lanes);
}  // namespace lanes

namespace {

/// The definition of one entry point for `isa`.
template <typename Function>
Function* Pick(LaneIsa isa, Function* sse2, Function* avx2, Function* avx512) {
  return isa == LaneIsa::Avx512 ? avx512 : isa == LaneIsa::Avx2 ? avx2 : sse2;
}

}  // namespace

bool LaneIsaAvailable(LaneIsa isa) {
  // GCC's checks include the operating system's support of the registers.
  switch (isa) {
    case LaneIsa::Sse2:
      return true;  // every x86-64 processor
    case LaneIsa::Avx2:
      return __builtin_cpu_supports("avx2");
    case LaneIsa::Avx512:
      return __builtin_cpu_supports("avx512f");
  }
  return false;
}

LaneIsa BestLaneIsa() {
  static const LaneIsa best = LaneIsaAvailable(LaneIsa::Avx512) ? LaneIsa::Avx512
                              : LaneIsaAvailable(LaneIsa::Avx2) ? LaneIsa::Avx2
                                                                 : LaneIsa::Sse2;
  return best;
}

const char* LaneIsaName(LaneIsa isa) {
  switch (isa) {
    case LaneIsa::Sse2:
      return "sse2";
    case LaneIsa::Avx2:
      return "avx2";
    case LaneIsa::Avx512:
      return "avx512";
  }
  return "?";
}

bool NewtonLanesCover(const CellView& cell) {
  const CellShape& shape = cell.shape;
  if (!shape.isBox()) return false;
  for (int f = 0; f < shape.numFactors(); ++f) {
    if (shape.factor(f).degree < 1) return false;
  }
  const int pd = shape.paramDim();
  return (pd == 1 && (cell.ambientDim == 2 || cell.ambientDim == 3)) || (pd == 2 && cell.ambientDim == 3);
}

void SolveNewtonLanes(const CellView& cell, double size, const NewtonLanes& lanes, LaneIsa isa) {
  if (lanes.count <= 0) return;
  Pick(isa, lanes::SolveNewtonLanesSse2, lanes::SolveNewtonLanesAvx2, lanes::SolveNewtonLanesAvx512)(cell, size, lanes);
}

bool InsideLanesCover(const CellView& cell) {
  return cell.shape.type() == CellType::Tet && cell.ambientDim == 3 && cell.weights == nullptr &&
         cell.shape.factor(0).degree >= 1;
}

void SolveInsideLanes(const CellView& cell, double size, const InsideLanes& lanes, LaneIsa isa) {
  if (lanes.count <= 0) return;
  Pick(isa, lanes::SolveInsideLanesSse2, lanes::SolveInsideLanesAvx2, lanes::SolveInsideLanesAvx512)(cell, size, lanes);
}

void NetLowerBoundLanes(const NetLanes& nets, int count, const double* const point[3], double* lowerBound,
                        LaneIsa isa) {
  if (count <= 0) return;
  Pick(isa, lanes::NetLowerBoundLanesSse2, lanes::NetLowerBoundLanesAvx2, lanes::NetLowerBoundLanesAvx512)(nets, count, point, lowerBound);
}

void ProvesConvexLanes(const CurvatureBounds& bounds, int count, const double* const point[3], const double* level,
                       bool* proved, LaneIsa isa) {
  if (count <= 0) return;
  Pick(isa, lanes::ProvesConvexLanesSse2, lanes::ProvesConvexLanesAvx2, lanes::ProvesConvexLanesAvx512)(bounds, count, point, level, proved);
}

}  // namespace invmap::kernels
