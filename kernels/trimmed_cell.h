// A Bezier cell of a trimmed surface that its face's trimming loops cross:
// what its certified search needs to respect the face's region.
//
// The closest point on a trimmed face is either a KKT point of the
// distance over one of its cells' boxes that lies inside the region, or a
// point of the region's boundary, which the face's edges (curve cells)
// cover. So the search over such a cell may drop a subdomain that lies
// wholly outside the region, or that holds no KKT point (LocateKktPoints),
// and keeps a local solution only when it is not outside the region.
#pragma once

#include <vector>

#include "kernels/own_parameter.h"
#include "kernels/trim_region.h"

namespace invmap::kernels {

struct TrimmedCell {
  /// The face's region, in the surface's own parameters.
  const TrimRegion* region = nullptr;
  /// The cell's knot box: own parameter d at reference coordinate w is
  /// OwnParameter(paramLo[d], paramScale[d], angular[d], w).
  double paramLo[2] = {0, 0};
  double paramScale[2] = {1, 1};
  bool angular[2] = {false, false};
  /// The region's pieces that may meet the cell's own box, halved to its
  /// scale (TrimRegion::PiecesFor).
  TrimPieces near;

  /// Own parameters of reference point `ref`.
  void ToOwn(const double* ref, double* own) const {
    for (int d = 0; d < 2; ++d) own[d] = OwnParameter(paramLo[d], paramScale[d], angular[d], ref[d]);
  }

  /// Side of the reference box [lo, hi] (degenerate boxes allowed).
  TrimRegion::Side ClassifySubdomain(const double* lo, const double* hi) const;

  /// True unless `ref` lies outside the region (a point within its
  /// resolution of the boundary is kept: the edge there gives the same).
  bool Admits(const double* ref) const;
};

}  // namespace invmap::kernels
