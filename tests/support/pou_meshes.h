// Closed triangle meshes for the partition-of-unity surface tests: vertices
// of any valence from 3, spheres and tori sampled from the analytic surfaces at
// several resolutions, and a genus-2 surface.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace invmap::testing {

struct TriangleMesh {
  std::string name;
  std::vector<double> xyz;               ///< 3 per vertex.
  std::vector<std::int64_t> triangles;   ///< 3 per triangle, counter-clockwise seen from outside.
  std::int64_t numVertices() const { return static_cast<std::int64_t>(xyz.size() / 3); }
  std::int64_t numTriangles() const { return static_cast<std::int64_t>(triangles.size() / 3); }
  /// The diagonal of the vertices' bounding box: the size tolerances scale with.
  double diagonal() const;
};

/// Two apexes of valence n joined through an equator of n vertices (valence 4).
TriangleMesh Bipyramid(int n);
/// The icosahedron refined `levels` times (each triangle into 4), every
/// vertex on the sphere of radius `radius` about the origin (valences 5 and 6).
TriangleMesh Icosphere(int levels, double radius);
/// A torus about the z axis (major radius big, minor small), `around` x
/// `across` vertices on it, every quad split into two triangles (valence 6).
TriangleMesh Torus(int around, int across, double big, double small);
/// A closed cylinder about the z axis (radius 1, height 2) with `around`
/// vertices on each of its `rings` + 1 circles and each cap a fan of
/// triangles about its centre vertex (valence `around`), as CAD tessellators
/// make them.
TriangleMesh Cylinder(int around, int rings);
/// The boundary of a plate of 5 x 3 unit cubes with two cubes taken out
/// (genus 2), squares split into triangles, then moved onto a smoother
/// shape by `smoothing` steps of Laplacian smoothing (valences 3 to 7).
TriangleMesh GenusTwo(int smoothing);
/// The mesh with every triangle split into 4 (the new vertices at the
/// midpoints of the edges).
TriangleMesh Refine(const TriangleMesh& mesh);

}  // namespace invmap::testing
