// gmsh peer (C++ API of libgmsh-dev): element search and local coordinates
// on the high-order tet meshes, reloaded from the same .msh file invmap read.
// Also meshes the tet workloads' solid.
#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "bench/peers/peer.h"

namespace invmap::bench {
namespace {

/// gmsh's API works on one global model: initialize it once per process.
void EnsureGmsh() {
  static bool initialized = false;
  if (initialized) return;
  gmsh::initialize(0, nullptr, false);  // no user configuration files: a fixed set-up
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::option::setNumber("General.Verbosity", 0);
  initialized = true;
}

/// Which gmsh calls a query makes.
enum class GmshCall {
  ElementByCoordinates,   ///< getElementByCoordinates (returns u, v, w too).
  ElementsThenLocal,      ///< getElementsByCoordinates, then getLocalCoordinatesInElement.
};

class GmshWorker : public PeerWorker {
 public:
  explicit GmshWorker(GmshCall call) : call_(call) {}
  void Query(const double* point, PeerAnswer* answer) override {
    answer->failed = true;
    try {
      if (call_ == GmshCall::ElementByCoordinates) {
        std::size_t tag = 0;
        int type = 0;
        double u = 0, v = 0, w = 0;
        gmsh::model::mesh::getElementByCoordinates(point[0], point[1], point[2], tag, type, nodeTags_, u, v, w, 3,
                                                   false);
        SetAnswer(tag, u, v, w, answer);
      } else {
        gmsh::model::mesh::getElementsByCoordinates(point[0], point[1], point[2], tags_, 3, false);
        if (tags_.empty()) return;
        double u = 0, v = 0, w = 0;
        gmsh::model::mesh::getLocalCoordinatesInElement(tags_[0], point[0], point[1], point[2], u, v, w);
        SetAnswer(tags_[0], u, v, w, answer);
      }
    } catch (...) {
      // gmsh reports "no element found" by an error (and, depending on the
      // build, an exception): a failed point.
      answer->failed = true;
    }
  }

  /// The distance from the point to the element's map at the returned local
  /// coordinates, clamped into the reference tet first (a location outside
  /// the element is not a point of the mesh).
  void Finish(const double* point, PeerAnswer* answer) override {
    if (answer->failed) return;
    double uvw[3];
    for (int k = 0; k < 3; ++k) uvw[k] = std::max(0.0, answer->local[k]);
    const double sum = uvw[0] + uvw[1] + uvw[2];
    if (sum > 1.0) {
      for (double& x : uvw) x /= sum;
    }
    std::vector<double> jacobians, determinants, coord;
    try {
      gmsh::model::mesh::getJacobian(static_cast<std::size_t>(answer->element), {uvw[0], uvw[1], uvw[2]}, jacobians,
                                     determinants, coord);
    } catch (...) {
      answer->failed = true;
      return;
    }
    if (coord.size() < 3) {
      answer->failed = true;
      return;
    }
    answer->distance = std::sqrt((coord[0] - point[0]) * (coord[0] - point[0]) +
                                 (coord[1] - point[1]) * (coord[1] - point[1]) +
                                 (coord[2] - point[2]) * (coord[2] - point[2]));
  }

 private:
  static void SetAnswer(std::size_t tag, double u, double v, double w, PeerAnswer* answer) {
    if (tag == 0) return;
    answer->failed = false;
    answer->element = static_cast<std::int64_t>(tag);
    answer->local[0] = u;
    answer->local[1] = v;
    answer->local[2] = w;
    answer->distance = std::numeric_limits<double>::quiet_NaN();  // set by Finish
  }

  GmshCall call_;
  std::vector<std::size_t> nodeTags_;
  std::vector<std::size_t> tags_;
};

class GmshMethod : public PeerMethod {
 public:
  /// Loads the mesh into gmsh's global model, replacing what was there (the
  /// harness keeps one peer alive at a time).
  GmshMethod(const std::string& mshPath, GmshCall call) : call_(call) {
    EnsureGmsh();
    gmsh::clear();
    gmsh::open(mshPath);
  }
  std::string name() const override {
    return call_ == GmshCall::ElementByCoordinates
               ? "gmsh getElementByCoordinates"
               : "gmsh getElementsByCoordinates + getLocalCoordinatesInElement";
  }
  // gmsh's API shares one global model and its search caches.
  bool threadSafe() const override { return false; }
  std::unique_ptr<PeerWorker> NewWorker() override { return std::make_unique<GmshWorker>(call_); }
  std::string note() const override {
    return "dim = 3, strict = false; distance at the returned (u, v, w) clamped to the tet, outside the timing";
  }

 private:
  GmshCall call_;
};

}  // namespace

std::string GmshVersion() { return std::string("gmsh ") + GMSH_API_VERSION; }

bool MeshWithGmshApi(const std::string& geoPath, const std::string& mshPath, std::string* message) {
  try {
    EnsureGmsh();
    gmsh::clear();
    gmsh::open(geoPath);
    gmsh::model::mesh::generate(3);
    gmsh::write(mshPath);
    gmsh::clear();
  } catch (const std::exception& e) {
    *message = std::string("gmsh: ") + e.what();
    return false;
  } catch (...) {
    *message = "gmsh failed to mesh " + geoPath;
    return false;
  }
  return true;
}

PeerList MakeGmshPeers(const GeometryCase& geometryCase) {
  PeerList peers;
  if (geometryCase.kind == CaseKind::TetMesh) {
    const std::string& path = geometryCase.mshPath;
    for (GmshCall call : {GmshCall::ElementByCoordinates, GmshCall::ElementsThenLocal}) {
      peers.push_back([&path, call] { return std::make_unique<GmshMethod>(path, call); });
    }
  }
  return peers;
}

}  // namespace invmap::bench
