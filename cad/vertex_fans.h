// The angle-weighted pseudo-normal at a model's vertices, from each face's
// fan there: the directions in which the face leaves the vertex, each with
// the face's normal along it. At an ordinary corner the fan is a sector of
// the tangent plane and the contribution is the corner's angle times the
// normal (Baerentzen and Aanaes); where the face's surface is singular (a
// cone's apex, a sphere's pole: a degenerate edge in the face's wire, or any
// corner whose surface has no normal there) the fan is the cone of
// generators or meridians the face sweeps, and its contribution is the
// integral of the normal over the arc the directions sweep on the unit
// sphere, the limit of the pseudo-normal of ever finer polyhedra. The fan
// is sampled just inside the face, so the surface is never asked for its
// normal at the singular point itself (where rounding in a file's geometry
// gives one generator's normal, or its opposite).
#pragma once

#include <Geom_Surface.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS_Face.hxx>
#include <gp_Vec.hxx>

#include <vector>

namespace invmap::cad {

/// Adds face `face`'s contribution at each of its vertices to `normals`
/// (indexed as `vertexMap`, 0-based). `surface` is the face's surface,
/// `uvBox` its parameter box; the normals are outward (flipped for a
/// reversed face).
void AddVertexFans(const TopoDS_Face& face, const Handle(Geom_Surface) & surface, const double uvBox[4],
                   const TopTools_IndexedMapOfShape& vertexMap, std::vector<gp_Vec>* normals);

}  // namespace invmap::cad
