// The base surfaces the shape functions are fitted to: one parametric patch
// per triangle of the mesh, evaluated at barycentric coordinates given in the
// triangle's own vertex order.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "pou/closed_mesh.h"

namespace invmap::pou {

enum class BaseKind { Flat, PnTriangles, Loop };

class BaseSurface {
 public:
  virtual ~BaseSurface() = default;
  /// The point of triangle t's patch at barycentric coordinates `bary`
  /// (nonnegative, summing to 1; bary[k] belongs to the triangle's vertex k).
  virtual void Evaluate(std::int64_t t, const double bary[3], double out[3]) const = 0;
};

/// `flat`: the mesh itself. `pn`: the PN triangles of Vlachos, Peters, Boyd
/// and Mitchell (a cubic Bezier triangle per triangle from its corners and
/// the vertex normals, angle-weighted averages of the face normals). `loop`:
/// the limit surface of Loop subdivision (pou/loop_limit.h), evaluated
/// exactly. The mesh must outlive the surface.
std::unique_ptr<BaseSurface> MakeBaseSurface(BaseKind kind, const ClosedMesh& mesh);

}  // namespace invmap::pou
