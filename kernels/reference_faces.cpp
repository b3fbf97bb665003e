#include "kernels/reference_faces.h"

#include <algorithm>

#include "kernels/active_set.h"
#include "kernels/simplex_index.h"

namespace invmap::kernels {
namespace {

/// The factor and barycentric index of face `face`.
void FaceOf(const CellShape& shape, int face, int* factor, int* index) {
  int f = 0;
  while (face > shape.factor(f).dim) face -= shape.factor(f++).dim + 1;
  *factor = f;
  *index = face;
}

/// The position in factor `fac`'s control net of its vertex `v` (where
/// barycentric coordinate v is one).
int VertexPosition(const SimplexFactor& fac, int v) {
  int a[3] = {0, 0, 0};
  if (v > 0) a[v - 1] = fac.degree;
  return SimplexIndex::Get(fac.dim, fac.degree).Position(a[0], a[1], a[2]);
}

}  // namespace

int NumFaces(const CellShape& shape) {
  int n = 0;
  for (int f = 0; f < shape.numFactors(); ++f) n += shape.factor(f).dim + 1;
  return n;
}

int CornerControlPoint(const CellShape& shape, const int* vertex) {
  // The net lists its first factor fastest.
  int index = 0, stride = 1;
  for (int f = 0; f < shape.numFactors(); ++f) {
    const SimplexFactor& fac = shape.factor(f);
    index += stride * VertexPosition(fac, vertex[f]);
    stride *= SimplexBasisSize(fac.dim, fac.degree);
  }
  return index;
}

int FaceCornerControlPoints(const CellShape& shape, int face, int* corners) {
  int faceFactor = 0, faceIndex = 0;
  FaceOf(shape, face, &faceFactor, &faceIndex);
  // The corners are the products of one vertex per factor, the face's
  // factor skipping its vertex `faceIndex`.
  int count = 0;
  int vertex[kMaxFactors] = {0, 0, 0};
  while (true) {
    if (vertex[faceFactor] != faceIndex) corners[count++] = CornerControlPoint(shape, vertex);
    int f = 0;
    while (f < shape.numFactors() && ++vertex[f] > shape.factor(f).dim) vertex[f++] = 0;
    if (f == shape.numFactors()) return count;
  }
}

int FacesAt(const CellShape& shape, const double* ref, int* faces) {
  double beyond[kMaxFaces];
  int n = 0, face = 0;
  for (int f = 0; f < shape.numFactors(); ++f) {
    double lambda[4];
    FactorBarycentric(shape, f, ref, lambda);
    for (int k = 0; k <= shape.factor(f).dim; ++k, ++face) {
      if (!(lambda[k] <= kOnFaceTolerance)) continue;
      // Insertion, most negative first.
      int at = n++;
      for (; at > 0 && beyond[at - 1] > lambda[k]; --at) {
        beyond[at] = beyond[at - 1];
        faces[at] = faces[at - 1];
      }
      beyond[at] = lambda[k];
      faces[at] = face;
    }
  }
  return n;
}

double LeastBarycentric(const CellShape& shape, const double* ref) {
  double least = 1.0;
  for (int f = 0; f < shape.numFactors(); ++f) {
    double lambda[4];
    FactorBarycentric(shape, f, ref, lambda);
    for (int k = 0; k <= shape.factor(f).dim; ++k) least = std::min(least, lambda[k]);
  }
  return least;
}

}  // namespace invmap::kernels
