#include "kernels/face_certificate.h"

#include <vector>

#include "kernels/bernstein_net.h"

namespace invmap::kernels {
namespace {

/// Largest face net: a quad face of a hex net of degree 2 kMaxDegree.
constexpr int kMaxFaceNet = (2 * kMaxDegree + 1) * (2 * kMaxDegree + 1);

/// The stencil of a face shape. HessianStencil::Get takes a lock; the few
/// face shapes one thread meets are remembered here (stencils live forever).
const HessianStencil& FaceStencil(const CellShape& face) {
  struct Known {
    CellType type;
    int degree0, degree1;
    const HessianStencil* stencil;
  };
  thread_local std::vector<Known> known;
  const int degree1 = face.numFactors() > 1 ? face.factor(1).degree : 0;
  for (const Known& k : known) {
    if (k.type == face.type() && k.degree0 == face.factor(0).degree && k.degree1 == degree1) return *k.stencil;
  }
  const HessianStencil& stencil = HessianStencil::Get(face);
  known.push_back(Known{face.type(), face.factor(0).degree, degree1, &stencil});
  return stencil;
}

}  // namespace

bool HasFaceCertificate(const CellShape& shape) {
  return shape.type() == CellType::Line || shape.type() == CellType::Quad || shape.type() == CellType::Hex;
}

bool IsMinimalOnFace(const CellShape& shape, const double* f, const NetNoise& noise, const int* side) {
  const int dims = shape.numFactors();
  int size[3] = {1, 1, 1}, stride[3] = {1, 1, 1};
  for (int d = 0; d < dims; ++d) size[d] = shape.factor(d).degree + 1;
  stride[1] = size[0];
  stride[2] = size[0] * size[1];
  const int n = size[0] * size[1] * size[2];

  bool constrained = false;
  for (int d = 0; d < dims; ++d) {
    if (side[d] < 0) continue;
    constrained = true;
    if (size[d] < 2) return false;
    // Coefficient differences along d: the derivative net, up to its
    // positive factor. Away from face t_d = 0 f must not decrease, away
    // from t_d = 1 not increase; strictly and beyond the coefficients'
    // rounding, so rounding cannot fake it.
    const int s = stride[d];
    for (int i = 0; i < n; ++i) {
      if ((i / s) % size[d] == size[d] - 1) continue;
      const double rounding = noise.weights ? noise.scale * (noise.weights[i + s] + noise.weights[i]) : 0.0;
      const double difference = f[i + s] - f[i];
      if (side[d] == 0 ? !(difference > rounding) : !(difference < -rounding)) return false;
    }
  }
  if (!constrained) return false;

  // The face net: the coefficients with every constrained index at its side.
  int freeDims[3] = {0, 0, 0}, freeCount = 0, base = 0;
  for (int d = 0; d < dims; ++d) {
    if (side[d] < 0) {
      freeDims[freeCount++] = d;
    } else if (side[d] == 1) {
      base += (size[d] - 1) * stride[d];
    }
  }
  if (freeCount == 0) return true;  // F is the vertex x*, where f = 0
  double face[kMaxFaceNet], faceWeights[kMaxFaceNet];
  const int n0 = size[freeDims[0]];
  const int n1 = freeCount > 1 ? size[freeDims[1]] : 1;
  for (int j = 0; j < n1; ++j) {
    for (int i = 0; i < n0; ++i) {
      int index = base + i * stride[freeDims[0]];
      if (freeCount > 1) index += j * stride[freeDims[1]];
      face[i + n0 * j] = f[index];
      if (noise.weights) faceWeights[i + n0 * j] = noise.weights[index];
    }
  }
  const CellShape faceShape = freeCount == 1 ? CellShape(CellType::Line, {n0 - 1, 0, 0})
                                             : CellShape(CellType::Quad, {n0 - 1, n1 - 1, 0});
  const NetNoise faceNoise{noise.weights ? faceWeights : nullptr, noise.scale};
  return FaceStencil(faceShape).IsConvex(face, faceNoise);
}

}  // namespace invmap::kernels
