// invmap_embree_cost: Embree's side of the cost curves (bench/cost_curves.py):
// the same mesh file and point file that `invmap invert` reads, Embree's
// scene built from it and every point queried with rtcPointQuery (the
// harness' Embree peer, bench/peers/peer_embree.cpp), the points streamed a
// chunk at a time as `invmap invert` streams them. Prints one line of
// key=value pairs: build and query seconds, points, and a checksum of the
// distances. Peak memory is measured from outside (GNU time).
//
//   invmap_embree_cost MESH POINTS
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>

#include "bench/peers/peer.h"
#include "io/geometry_file.h"
#include "io/point_reader.h"

int main(int argc, char** argv) {
  using Clock = std::chrono::steady_clock;
  if (argc != 3) {
    std::fprintf(stderr, "usage: invmap_embree_cost MESH POINTS\n");
    return 2;
  }
  try {
    invmap::bench::GeometryCase mesh;
    mesh.kind = invmap::bench::CaseKind::TriangleMesh;
    mesh.geometry = invmap::io::ReadGeometryFile(argv[1]);
    const Clock::time_point buildStart = Clock::now();
    const invmap::bench::PeerList peers = invmap::bench::MakeEmbreePeers(mesh);
    if (peers.empty()) {
      std::fprintf(stderr, "invmap_embree_cost: %s is not a triangle mesh\n", argv[1]);
      return 2;
    }
    const std::unique_ptr<invmap::bench::PeerMethod> method = peers[0]();
    const double buildSeconds = std::chrono::duration<double>(Clock::now() - buildStart).count();
    const std::unique_ptr<invmap::bench::PeerWorker> worker = method->NewWorker();
    const std::unique_ptr<invmap::io::PointReader> reader = invmap::io::OpenPointReader(argv[2], 3);
    invmap::io::PointChunk chunk;
    double querySeconds = 0.0, checksum = 0.0;
    long long points = 0;
    while (reader->ReadChunk(std::size_t{1} << 18, &chunk)) {
      const std::size_t n = chunk.count;
      const Clock::time_point start = Clock::now();
      for (std::size_t i = 0; i < n; ++i) {
        invmap::bench::PeerAnswer answer;
        worker->Query(&chunk.xyz[3 * i], &answer);
        checksum += answer.distance;
      }
      querySeconds += std::chrono::duration<double>(Clock::now() - start).count();
      points += static_cast<long long>(n);
    }
    std::printf("build_s=%.6f query_s=%.6f points=%lld checksum=%.17g\n", buildSeconds, querySeconds, points,
                checksum);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "invmap_embree_cost: %s\n", e.what());
    return 1;
  }
  return 0;
}
