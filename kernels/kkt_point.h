// The independent check the global search trusts a local solution by: the
// first-order (KKT) conditions of the squared distance at a point.
#pragma once

#include "kernels/cell_map.h"

namespace invmap::kernels {

/// An independent check of the first-order (KKT) conditions of |x(u) - p|^2
/// at `ref`: the gradient projected on the face of the constraints active
/// there is small, and no active constraint's release direction descends,
/// each direction judged by how far the map moves along it (a thin cell's
/// thickness by the thickness, not by the cell's size).
/// The global search trusts a local solution only after this check.
/// `jet`: the map at `ref`, evaluated to at least first order.
bool IsKktPoint(const CellView& cell, const MapJet& jet, const double* point, const double* ref, double size);

}  // namespace invmap::kernels
