// Textbook B-spline evaluation (Cox-de Boor), kept deliberately naive so that
// tests can check the engine's Bezier extraction against independent code.
#pragma once

#include <vector>

#include "engine/bezier_extraction.h"

namespace invmap::testing {

/// Values N_{i,p}(t) for i = 0 .. knots.size() - p - 2 of the degree-p
/// B-spline basis, by the Cox-de Boor recursion with 0/0 = 0. The degree-0
/// functions are 1 on knot span `span` only, so the result is the polynomial
/// piece of that span, also at its ends and outside it.
/// Precondition: knots[span] < knots[span + 1].
std::vector<double> CoxDeBoorBasis(const std::vector<double>& knots, int degree, int span,
                                   double t);

/// Point of `patch` at parameters params[0 .. paramDim) using the polynomial
/// pieces of knot spans spans[0 .. paramDim), written to out[0 .. ambientDim).
/// Sums over every control point (rational if the patch has weights).
void EvaluateBSplinePatch(const engine::BSplinePatch& patch, const int* spans, const double* params,
                          double* out);

}  // namespace invmap::testing
