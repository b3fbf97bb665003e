// Exact evaluation of the Loop subdivision limit surface of a closed
// triangle mesh at any barycentric point of any triangle (the parametrization
// subdivision itself induces: a point at dyadic barycentric coordinates of a
// triangle is the limit of the refined vertex there).
//
// The method: the triangle's neighbourhood (the triangles around its three
// corners, which hold the support of the limit over it) is subdivided with
// Loop's rules, again and again, keeping only the subtriangle that holds the
// point and its neighbourhood, until
//  - the subtriangle is regular (three corners of valence 6): the limit over
//    it is a quartic box-spline patch of its 12 surrounding vertices,
//    evaluated exactly (its Bezier form is derived once from the same rules,
//    by the limit masks at 15 lattice points of a twice subdivided patch);
//  - or the point is a corner: Loop's limit mask there;
//  - or, next to an extraordinary vertex, 48 levels have passed: the point is
//    then within 2^-48 of the triangle's size of the limit position of that
//    vertex, and the limit positions of the subtriangle's corners are
//    interpolated linearly (an error of the order of 2^-96 of the size).
// This is Stam's evaluation with the subdivision steps applied one by one
// instead of through the eigenvectors of the subdivision matrix.
#pragma once

#include <cstdint>

#include "pou/closed_mesh.h"

namespace invmap::pou {

/// The limit point of triangle t of `mesh` at barycentric coordinates
/// `bary` (in the triangle's vertex order).
void LoopLimitPoint(const ClosedMesh& mesh, std::int64_t t, const double bary[3], double out[3]);

/// The limit position of vertex v (Loop's limit mask).
void LoopLimitVertex(const ClosedMesh& mesh, std::int64_t v, double out[3]);

}  // namespace invmap::pou
