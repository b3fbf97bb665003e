// The interface every peer library implements in the comparison harness: a
// method bound to one geometry, and per-thread workers that answer one query
// point at a time (the way each peer's API is meant to be called).
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "bench/peers/workloads.h"

namespace invmap::bench {

/// A peer's answer for one query point.
struct PeerAnswer {
  /// Distance from the query point to the point the peer returned; NaN when
  /// failed. Peers that return only an element and local coordinates fill it in
  /// PeerWorker::Finish, outside the timed loop.
  double distance = std::numeric_limits<double>::quiet_NaN();
  /// True when the peer returned no point (no projection, an error status, an
  /// exception, no element).
  bool failed = true;
  /// Optional: what Finish needs (gmsh: the element tag and u, v, w).
  std::int64_t element = 0;
  double local[3] = {0, 0, 0};
};

/// Per-thread state of a peer (projector objects, surface copies, query
/// contexts). Created outside the timed loop; one per thread, never shared.
class PeerWorker {
 public:
  virtual ~PeerWorker() = default;
  /// Answers one query point (`dim` coordinates of the case). Timed.
  virtual void Query(const double* point, PeerAnswer* answer) = 0;
  /// Completes `answer` after the timed loop (default: nothing to do).
  virtual void Finish(const double* point, PeerAnswer* answer) {
    (void)point;
    (void)answer;
  }
};

/// One peer method bound to one geometry case. Construction does the
/// per-geometry set-up (conversion to the peer's representation, tree
/// builds), which the harness times separately from the queries.
class PeerMethod {
 public:
  virtual ~PeerMethod() = default;
  /// Library and call, e.g. "OpenCascade ShapeAnalysis_Surface::ValueOfUV".
  virtual std::string name() const = 0;
  /// True when several workers may query at once (each on its own thread).
  virtual bool threadSafe() const = 0;
  /// A new worker; its per-surface initialization happens here, once.
  virtual std::unique_ptr<PeerWorker> NewWorker() = 0;
  /// Optional: settings worth printing with the results (tolerances, guesses).
  virtual std::string note() const { return {}; }
};

/// Makes one peer method; the harness times the call as the peer's set-up and
/// destroys the method after its runs, so only one peer's data is alive at a time.
using PeerFactory = std::function<std::unique_ptr<PeerMethod>()>;
using PeerList = std::vector<PeerFactory>;

/// Peers of each library for `geometryCase` (empty when the library does not
/// handle that kind of geometry). Each is defined only when the library was
/// found at configure time (see bench/peers/CMakeLists.txt). The factories
/// refer to `geometryCase`, which must outlive them.
PeerList MakeOccPeers(const GeometryCase& geometryCase);
/// OpenCascade's BRepExtrema on CAD cases (with invmap's CAD library only).
PeerList MakeOccCadPeers(const GeometryCase& geometryCase);
PeerList MakeSislPeers(const GeometryCase& geometryCase);
PeerList MakeEmbreePeers(const GeometryCase& geometryCase);
PeerList MakeCgalPeers(const GeometryCase& geometryCase);
PeerList MakeGmshPeers(const GeometryCase& geometryCase);

/// Name and version of each library ("OpenCascade 7.6.3"), defined with its peers.
std::string OccVersion();
std::string SislVersion();
std::string EmbreeVersion();
std::string CgalVersion();
std::string GmshVersion();

/// Meshes the .geo file `geoPath` with gmsh's API (3D, the options set in the
/// file) and writes `mshPath`. Defined only with libgmsh; false with a
/// message on failure.
bool MeshWithGmshApi(const std::string& geoPath, const std::string& mshPath, std::string* message);

}  // namespace invmap::bench
