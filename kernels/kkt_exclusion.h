// Where a subdomain of a cell can hold a KKT point of the squared distance
// over the cell's box, from the signs of its directional derivatives in
// Bernstein form.
//
// With f = q / WW, the derivative along u_d is (q_d - f WW_d) / WW, and at a
// KKT point of value f in [levelLo, levelHi] its sign is that of q_d - f WW_d,
// which is affine in f: when the nets of q - levelLo WW and q - levelHi WW
// both rise strictly along d (all their differences along d positive), so
// does f everywhere on the subdomain at every such value. A KKT point then
// needs the lower face u_d = 0 of the cell's box (where the constraint
// takes the slope), and the subdomain holds none unless it reaches that
// face; on the face (the net's first row along d) the other directions are
// judged again. Falling strictly: likewise with the upper face.
#pragma once

#include "kernels/cell_shape.h"

namespace invmap::kernels {

/// For a tensor product of lines (`shape`, every factor of dim 1), the net
/// q (and ww, null for a polynomial cell) of a subdomain, whose factor d
/// reaches the cell's face u_d = 0 when reachesLow[d] and u_d = 1 when
/// reachesHigh[d]. `noise`: each coefficient of q is off by at most noise
/// (times ww's coefficient for a rational cell); differences must clear it.
/// Returns false when no point of the subdomain can be a KKT point with a
/// squared distance in [levelLo, levelHi]; otherwise `face[d]` is -1 when
/// such points may lie anywhere along d, 0 or 1 when they can only lie on
/// the cell's face u_d = 0 or 1.
bool LocateKktPoints(const CellShape& shape, const double* q, const double* ww, double levelLo, double levelHi,
                     double noise, const bool* reachesLow, const bool* reachesHigh, int* face);

}  // namespace invmap::kernels
