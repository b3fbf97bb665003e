// The faces and corners of a cell's reference domain (a tensor product of
// simplices, docs/formats.md section 1), for the walk from cell to cell
// across the faces of a volume mesh (engine/face_adjacency.h).
#pragma once

#include "kernels/cell_shape.h"

namespace invmap::kernels {

/// Most faces of a reference domain (a hexahedron's six).
constexpr int kMaxFaces = 6;
/// Most corners of a face (a quadrilateral's four).
constexpr int kMaxFaceCorners = 4;

/// Face (f, k) is where barycentric coordinate k of factor f is zero (the
/// side opposite the factor's vertex k); faces are numbered factor by
/// factor: a tetrahedron's face k is opposite its corner k, a hexahedron's
/// face 2i is u_i = 1 and face 2i + 1 is u_i = 0, a wedge's faces 0 to 2 are
/// its quadrilaterals (opposite the triangle's vertices) and 3, 4 its
/// triangles at w = 1 and w = 0.
int NumFaces(const CellShape& shape);

/// The control points at the corners of face `face`: `corners` receives
/// their indices in the control net, returns how many (3 or 4). The cell's
/// map passes through its corner control points, so two cells that share a
/// face have the same points there.
int FaceCornerControlPoints(const CellShape& shape, int face, int* corners);

/// The index in the control net of the corner where factor f sits at its
/// vertex vertex[f] (the cell's map passes through it).
int CornerControlPoint(const CellShape& shape, const int* vertex);

/// The faces whose constraint `ref` lies on or beyond (barycentric
/// coordinate at most kOnFaceTolerance), into `faces`, the most negative
/// coordinate first; returns how many. For reference coordinates outside
/// the domain, the first is the face the point lies farthest beyond.
int FacesAt(const CellShape& shape, const double* ref, int* faces);

/// The least barycentric coordinate of any factor at `ref`: negative
/// outside the reference domain.
double LeastBarycentric(const CellShape& shape, const double* ref);

}  // namespace invmap::kernels
