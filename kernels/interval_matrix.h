// Positive definiteness of every symmetric matrix within entry-wise bounds:
// the last step of the convexity tests, once the bounds of a Hessian over a
// cell are known.
#pragma once

namespace invmap::kernels {

/// True when every symmetric dim x dim matrix H (dim 1..3) with
/// lo[a][b] <= H_ab <= hi[a][b] (entries a <= b are read) is positive
/// definite, proved by either of two tests:
///  - interval: H = mid + E with |E_ab| <= rad_ab, so lambda_min >=
///    lambda_min(mid) - ||rad||_F > 0; tight when the entries vary little;
///  - scaled: the diagonal scaled out (given positive lower bounds lo_aa),
///    the off-diagonal's spectral radius below one; tight when the diagonal
///    entries vary a lot but stay positive and the mixed ones are small, as
///    over a cell whose parametrization speeds up along it.
/// False whenever a diagonal lower bound is not positive.
bool IntervalMatrixIsPositive(int dim, const double lo[3][3], const double hi[3][3]);

}  // namespace invmap::kernels
