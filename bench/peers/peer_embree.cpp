// Embree 3 peer: rtcPointQuery on a triangle-geometry scene with a
// point-triangle callback that computes the exact distance in double and
// shrinks the query radius (the pattern of Embree's closest_point tutorial).
#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "bench/peers/peer.h"
#include "bench/peers/triangle_distance.h"

namespace invmap::bench {
namespace {

/// The mesh in double (what the callback measures) and the float slack of the
/// scene Embree traverses.
struct MeshData {
  const double* vertices = nullptr;     ///< x, y, z per vertex.
  const std::int64_t* triangles = nullptr;  ///< 3 vertex indices per triangle.
  /// Embree's boxes come from the float vertices and its traversal runs in
  /// float, so the query radius is kept this much above the best double
  /// distance: a triangle closer in double is never culled.
  float slack = 0.0f;
};

/// Per-query state handed to the callback through userPtr.
struct QueryState {
  const MeshData* mesh;
  const double* point;
  double best2;
};

bool ClosestTriangleCallback(RTCPointQueryFunctionArguments* args) {
  QueryState* state = static_cast<QueryState*>(args->userPtr);
  const MeshData& mesh = *state->mesh;
  const std::int64_t* t = mesh.triangles + 3 * static_cast<std::int64_t>(args->primID);
  const double d2 = PointTriangleDistance2(state->point, mesh.vertices + 3 * t[0], mesh.vertices + 3 * t[1],
                                           mesh.vertices + 3 * t[2]);
  if (d2 >= state->best2) return false;
  state->best2 = d2;
  const float radius = static_cast<float>(std::sqrt(d2)) + mesh.slack;
  if (radius >= args->query->radius) return false;
  args->query->radius = radius;
  return true;  // the radius shrank: Embree culls with the smaller sphere
}

class EmbreeWorker : public PeerWorker {
 public:
  EmbreeWorker(RTCScene scene, const MeshData* mesh) : scene_(scene), mesh_(mesh) {}
  void Query(const double* point, PeerAnswer* answer) override {
    RTCPointQuery query;
    query.x = static_cast<float>(point[0]);
    query.y = static_cast<float>(point[1]);
    query.z = static_cast<float>(point[2]);
    query.time = 0.0f;
    query.radius = std::numeric_limits<float>::infinity();
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    QueryState state{mesh_, point, std::numeric_limits<double>::infinity()};
    rtcPointQuery(scene_, &query, &context, ClosestTriangleCallback, &state);
    answer->failed = !std::isfinite(state.best2);
    answer->distance = std::sqrt(state.best2);
  }

 private:
  RTCScene scene_;
  const MeshData* mesh_;
};

class EmbreeMethod : public PeerMethod {
 public:
  /// `label`: what the mesh is, when it stands for another geometry (a CAD
  /// model's tessellation), added to the name and the note.
  explicit EmbreeMethod(const Patch& patch, std::string label = {}) : label_(std::move(label)) {
    device_ = rtcNewDevice(nullptr);
    scene_ = rtcNewScene(device_);
    const std::size_t numVertices = patch.points.size() / 3, numTriangles = patch.cells.size() / 3;
    RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    float* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0,
                                                                  RTC_FORMAT_FLOAT3, 3 * sizeof(float), numVertices));
    unsigned* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), numTriangles));
    double maxAbs = 0.0;
    for (std::size_t i = 0; i < 3 * numVertices; ++i) {
      vertices[i] = static_cast<float>(patch.points[i]);
      maxAbs = std::max(maxAbs, std::abs(patch.points[i]));
    }
    for (std::size_t i = 0; i < 3 * numTriangles; ++i) indices[i] = static_cast<unsigned>(patch.cells[i]);
    numTriangles_ = numTriangles;
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene_, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene_);
    mesh_.vertices = patch.points.data();
    mesh_.triangles = patch.cells.data();
    // Rounding the vertices and the query to float moves them by at most half
    // a float ulp of the largest coordinate; 16 ulps covers that and the
    // float arithmetic of the traversal's distance tests.
    mesh_.slack = static_cast<float>(16.0 * maxAbs * std::numeric_limits<float>::epsilon());
  }
  ~EmbreeMethod() override {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  std::string name() const override {
    return label_.empty() ? "Embree rtcPointQuery" : "Embree rtcPointQuery on " + label_;
  }
  bool threadSafe() const override { return true; }
  std::unique_ptr<PeerWorker> NewWorker() override { return std::make_unique<EmbreeWorker>(scene_, &mesh_); }
  std::string note() const override {
    return (label_.empty() ? std::string() : label_ + " of " + std::to_string(numTriangles_) + " triangles: ") +
           "triangle geometry (float), default build quality; callback: exact double point-triangle distance, "
           "radius = distance + 16 float ulps" +
           (label_.empty() ? std::string()
                           : "; the mesh is not the model, so its farther columns and max diff are the "
                             "tessellation's error against the exact distance, not wrong answers");
  }

 private:
  std::string label_;
  std::size_t numTriangles_ = 0;
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  MeshData mesh_;
};

}  // namespace

std::string EmbreeVersion() { return std::string("Embree ") + RTC_VERSION_STRING; }

PeerList MakeEmbreePeers(const GeometryCase& geometryCase) {
  PeerList peers;
  if (geometryCase.kind == CaseKind::TriangleMesh) {
    const Patch& patch = geometryCase.geometry.patches[0];
    peers.push_back([&patch] { return std::make_unique<EmbreeMethod>(patch); });
  }
  // A CAD model's tessellations: the distance to the mesh, not to the model,
  // whose difference the comparison's "max diff" column shows.
  for (const GeometryCase::Tessellation& t : geometryCase.tessellations) {
    char label[64];
    std::snprintf(label, sizeof label, "tessellation (deflection %.2g)", t.deflection);
    peers.push_back([&t, name = std::string(label)] { return std::make_unique<EmbreeMethod>(t.mesh, name); });
  }
  return peers;
}

}  // namespace invmap::bench
