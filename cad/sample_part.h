// The sample part of the scan-to-CAD demo, simulated scans and
// tessellations of CAD models (the peer comparison's mesh peers), made with
// OpenCascade but declared with standard types only (the command and the
// benchmark include this header).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cad/model.h"

namespace invmap::cad {

/// Writes the sample bracket as a STEP file (millimetres): an L of an 80 x
/// 50 x 8 base and a 60 high, 8 thick upright, a rounded inner corner
/// (radius 6) and rounded outer corners (radius 5), two 10 mm holes
/// through the base and a 12 mm hole through the upright, and a turned
/// boss on the base (a profile revolved about a vertical axis: a 20 mm
/// collar, a 45 degree chamfer up to 14 mm, drilled 6 mm). Returns an empty
/// string on success, else why the file could not be written.
std::string WriteSampleBracket(const std::string& path);

/// What SimulateScan puts on the model's surface.
struct ScanOptions {
  std::int64_t count = 1000000;
  /// Gaussian measurement noise along the surface normal (model units).
  double noise = 0.01;
  /// The part as made: grown along the normals by `warp` at the top of its
  /// box (z) and not at all at the bottom, linearly in between.
  double warp = 0.05;
  /// Share of outliers (stray reflections): points up to `outlierReach`
  /// off the surface, either side.
  double outliers = 0.002;
  double outlierReach = 1.0;
  std::uint64_t seed = 1;
};

/// Points on the model's faces (uniform by area, on the exact surfaces:
/// OpenCascade's mesh picks a place, the face's surface is evaluated at
/// its parameters), moved along the outward normal by the warp, the noise
/// and, for the outliers, a random reach. 3 coordinates per point.
std::vector<double> SimulateScan(const Model& model, const ScanOptions& options);

/// OpenCascade's tessellation of the model (BRepMesh_IncrementalMesh with
/// chordal deflection `deflection`, angular deflection 0.5) as one triangle
/// mesh patch: what a user exports to a mesh-based tool.
Patch Tessellate(const Model& model, double deflection);

}  // namespace invmap::cad
