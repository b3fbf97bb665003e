// Independent references for model-to-model distances: dense sampling of
// both models followed by a polished joint local solve (its own projected
// Gauss-Newton on the tests' own evaluator), and exact all-pairs distances
// between triangle meshes by formulas of its own.
//
// Nothing here calls invmap's engine or its pair kernels.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

// The support library is built without the engine's include path; this is
// the same public header that tests include as "invmap/invmap.h".
#include "invmap/invmap.h"

namespace invmap::testing {

/// A rigid pose as 12 row-major numbers (r00 r01 r02 tx r10 .. tz).
using PoseRows = std::array<double, 12>;
PoseRows IdentityRows();
/// Rotation by `angle` about the unit axis, then the translation.
PoseRows RotationRows(const std::array<double, 3>& axis, double angle, const std::array<double, 3>& translation);
/// out = R x + t.
void ApplyRows(const PoseRows& pose, const double* x, double* out);

/// One side of a reference answer.
struct PairReferencePoint {
  std::int32_t patch = -1;
  std::int64_t cell = -1;
  std::array<double, 3> ref{{0, 0, 0}};  ///< The cell's reference coordinates.
  std::array<double, 3> point{{0, 0, 0}};  ///< World coordinates.
};

struct PairReferenceAnswer {
  double distance = 0.0;
  PairReferencePoint a, b;
};

struct PairReferenceOptions {
  /// Lattice divisions per parameter for curve, surface and volume cells.
  int divisions[3] = {160, 28, 8};
  /// Cell pairs whose sampled distance is within this many sample spacings
  /// of the best sampled distance are polished.
  double polishBand = 3.0;
};

/// The global minimum distance between geometries a and b under the poses:
/// every pair of cells whose control boxes may hold a closer pair than the
/// best sampled one is sampled on a lattice; the best sample pair of each
/// cell pair near the best is polished by a projected Gauss-Newton solve on
/// the two cells' joint parameters. An upper bound of the true minimum that
/// meets it when the lattice resolves the minimum's basin.
PairReferenceAnswer BruteForcePairDistance(const Geometry& a, const PoseRows& poseA, const Geometry& b,
                                           const PoseRows& poseB, const PairReferenceOptions& options = {});

/// Every local minimum of the distance between a and b (curves and
/// surfaces) up to `maxDistance`, as the lattices show them: the sample
/// pairs that no neighbouring sample pair (one lattice step on either side,
/// across cells of a patch too) beats, polished, then merged where their
/// polished points coincide (within `mergeTolerance` on both sides).
std::vector<PairReferenceAnswer> BruteForcePairMinima(const Geometry& a, const PoseRows& poseA, const Geometry& b,
                                                      const PoseRows& poseB, double maxDistance,
                                                      double mergeTolerance, const PairReferenceOptions& options = {});

/// Every local minimum of the distance from `point` to `geometry` up to
/// `maxDistance`, as a dense lattice of each cell shows them: the samples no
/// neighbouring sample beats (one lattice step away in their cell, or the
/// same point of another cell and its neighbours), polished by a projected
/// Gauss-Newton solve in their cell, kept when no sample within two lattice
/// steps of the polished point (in any cell) is closer to the point, and
/// merged where the polished points coincide (within `mergeTolerance`).
std::vector<PairReferencePoint> BruteForcePointMinima(const Geometry& geometry, const double* point, double maxDistance,
                                                      double mergeTolerance, int divisions);

/// True when `x`, a point of `geometry`, is a local minimum of the distance
/// to `point` as the tests' own evaluator sees it: in every cell that holds
/// x (a polish of x onto the cell reaches it), no point on rings of
/// reference coordinates around it (radii 1e-2 down to 1e-6, projected into
/// the cell's domain) is closer to `point` than x by more than `tolerance`.
/// For minima too shallow for a lattice to resolve.
bool VerifyLocalMinimum(const Geometry& geometry, const double* point, const double* x, double tolerance);

/// Exact distance between triangles (a0 a1 a2) and (b0 b1 b2) in 3D, from
/// the vertex-to-triangle distances, the edge-to-edge distances (each a
/// convex function of one edge parameter, minimized exactly) and the
/// crossing of an edge through the other triangle (Moller-Trumbore).
double TriangleTriangleDistance(const double* a0, const double* a1, const double* a2, const double* b0,
                                const double* b1, const double* b2);

/// All-pairs minimum distance between two triangle mesh patches (3D
/// vertices, 3 indices per triangle) under the poses.
double AllPairsMeshDistance(const Patch& a, const PoseRows& poseA, const Patch& b, const PoseRows& poseB);

}  // namespace invmap::testing
