// invmap::cad: CAD models (STEP, IGES, OpenCascade BREP) as invmap geometry,
// and signed distances to their solids. The library invmap_cad reads them
// with OpenCascade, which this header never names. It is internal to this
// build (the command and the Python module link it) and not installed.
//
//   invmap::cad::LoadResult loaded = invmap::cad::Model::Load("part.step");
//   if (!loaded.error.empty()) { ... }               // "no faces (12 edges, 8 vertices) ..."
//   const invmap::cad::Model& model = *loaded.model;
//   invmap::BuildResult built = invmap::Manifold::Build(model.geometry());
//   built.manifold.Invert(points, options, &results);
//   std::vector<double> sd(n);
//   model.SignDistances(xyz, n, results, sd.data());  // negative inside (closed solids only)
//
// The geometry has one TrimmedSurface patch per face, in OpenCascade's
// TopExp::MapShapes face order (docs/cad.md).
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "invmap/invmap.h"

namespace invmap::cad {

/// What `invmap info` says about a CAD model.
struct ModelInfo {
  std::string format;  ///< "STEP", "IGES" or "BREP".
  std::size_t faces = 0, edges = 0, vertices = 0, shells = 0, solids = 0;
  /// Faces per surface kind: plane, cylinder, cone, sphere, torus,
  /// revolution, extrusion, bspline, bezier, offset, other.
  std::vector<std::pair<std::string, std::size_t>> facesBySurface;
  /// Shells that are not closed, and faces in no shell, as "shell 2 (faces 5 to 9)" / "face 12".
  std::vector<std::string> openParts;
  /// Faces (0-based) whose surface, or a curve of whose boundary, is
  /// approximated rather than converted exactly (docs/cad.md), the
  /// tolerance aimed at (1e-7 of the model's size) and the largest
  /// deviation measured between an approximation and the exact geometry.
  std::vector<int> approximatedFaces;
  double approximationTolerance = 0.0;
  double approximationDeviation = 0.0;
  /// The model's box (OpenCascade's exact bounds of its faces).
  double boundsLo[3] = {0, 0, 0};
  double boundsHi[3] = {0, 0, 0};
};

class Model;
struct ScanOptions;  // cad/sample_part.h (the demo's simulated scans)

/// Model::Load's outcome: a model, or the reason it could not be read.
struct LoadResult {
  std::unique_ptr<Model> model;
  /// Empty on success; otherwise why the file is not a usable model (the
  /// caller names the file: "path: " + error).
  std::string error;
  /// With an error: true when the file itself could not be opened (missing,
  /// a directory, unreadable), false when its content is not a usable model.
  bool fileError = false;
};

/// A CAD model read from a file, with its geometry for the engine.
class Model {
 public:
  /// Reads a .step/.stp, .iges/.igs or .brep file (by its extension, case
  /// insensitive) with OpenCascade's default readers. Never throws.
  static LoadResult Load(const std::string& path);

  ~Model();
  Model(const Model&) = delete;
  Model& operator=(const Model&) = delete;

  /// One TrimmedSurface patch per face, in face-map order.
  const Geometry& geometry() const;
  ModelInfo Info() const;

  /// Empty when every face belongs to a closed shell (so the inside of the
  /// model is defined); otherwise a message naming the first open shell or
  /// free face.
  std::string SignedUnsupported() const;

  /// The signed distances of `count` points (`xyz`, 3 per point) whose
  /// results on this model's geometry are `results`: the distance, negative
  /// for points inside any of its solids (closed shells), positive outside
  /// all of them, 0 on the surface, NaN where the point was not found.
  /// Signs come from the face normal at the closest point, or from the
  /// faces around it when that point is on an edge or a vertex; in a model
  /// of several solids, from each solid that may hold the point, on its own
  /// (docs/cad.md). Precondition: SignedUnsupported() is
  /// empty. Thread-safe; `threads` as InversionOptions::threads.
  void SignDistances(const double* xyz, std::size_t count, const Results& results, double* signedDistances,
                     int threads = 0) const;

 private:
  friend std::vector<double> SimulateScan(const Model& model, const ScanOptions& options);
  friend Patch Tessellate(const Model& model, double deflection);
  Model();
  /// SignDistances' second pass on a model of several solids: the points
  /// inside a solid other than the one their nearest face bounds.
  void SignInOtherSolids(const double* xyz, std::size_t count, const Results& results, double* signedDistances,
                         int threads) const;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// True when `path`'s extension is one Model::Load reads.
bool IsCadFile(const std::string& path);

}  // namespace invmap::cad
