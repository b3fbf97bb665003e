// invmap_bench_distance_peers: model-to-model minimum distance against the
// libraries users would otherwise pick. OpenCascade's
// BRepExtrema_DistShapeShape (spline surfaces as faces, triangle meshes as
// compounds of planar faces) and FCL's distance on OBBRSS BVH models of
// triangle meshes. CGAL offers no minimum distance between two general
// (non-convex) models and is not run. A CAD workload (the bundled bracket
// against itself, read from its STEP file by both) runs where invmap's CAD
// reader is built.
//
// Every workload runs the same poses through every engine in one process,
// one thread each, timed on the thread's CPU clock (so other processes on a
// loaded machine do not count): fresh queries at random poses, then a
// trajectory of small steps (invmap's DistanceTracker against the peers'
// fresh query per pose, as they have no tracking). Each peer answer is
// compared with invmap's: invmap must never be farther.
//
//   invmap_bench_distance_peers [--quick] [--only TEXT] [--markdown FILE] [--csv FILE]
//
// --only runs the workloads whose name contains TEXT.
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "samples/sample_geometries.h"
#include "invmap/distance.h"
#include "invmap/invmap.h"

#if INVMAP_PEER_OCC
#include "bench/peers/occ_bspline.h"

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRep_Builder.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Precision.hxx>
#include <Standard_Failure.hxx>
#include <Standard_Version.hxx>
#include <TopLoc_Location.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Shape.hxx>
#include <gp_Trsf.hxx>
#endif

#if INVMAP_PEER_FCL
#include <fcl/fcl.h>
#endif

#if INVMAP_PEER_CAD
#include "cad/model.h"
#include "cad/shape_reader.h"
#endif

namespace {

using invmap::Geometry;
using invmap::Pose;

double ThreadSeconds() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// One engine's answer to a pose: the distance (NaN when it failed).
struct Answer {
  double distance = std::numeric_limits<double>::quiet_NaN();
};

/// A peer: prepared once per workload, then asked pose after pose.
struct Peer {
  std::string name;
  std::function<Answer(const Pose&)> query;
  /// Poses it is given (the slowest peers get a prefix of the list).
  std::size_t maxPoses = static_cast<std::size_t>(-1);
};

/// A workload: two models, B posed against A (at the identity).
struct Workload {
  std::string name;
  Geometry a, b;
  std::vector<Pose> fresh;       ///< Random poses.
  std::vector<Pose> trajectory;  ///< Small steps in time order.
  bool meshes = false;
  /// OpenCascade on the meshes of this workload (too slow on large ones).
  bool occ = true;
  double tolerance = 1e-7;  ///< "Farther" means by more than this.
  /// A CAD file both models are read from (invmap's reader, OpenCascade's), or empty.
  std::string cadFile;
};

Geometry Scaled(Geometry g, double s) {
  for (auto& patch : g.patches) {
    for (double& x : patch.points) x *= s;
  }
  return g;
}

Pose AxisAngle(double ax, double ay, double az, double angle, double tx, double ty, double tz) {
  const double n = std::sqrt(ax * ax + ay * ay + az * az);
  const double axis[3] = {ax / n, ay / n, az / n};
  const double t[3] = {tx, ty, tz};
  return Pose::FromAxisAngle(axis, angle, t);
}

// ---------------------------------------------------------------- workloads

std::vector<Workload> MakeWorkloads(bool quick) {
  std::vector<Workload> list;
  const int freshCount = quick ? 4 : 40;
  const int trackCount = quick ? 20 : 400;
  std::mt19937_64 rng(26);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double pi = 3.14159265358979323846;

  {
    Workload w;
    w.name = "bicubic surface 32x32 spans / NURBS torus";
    w.a = invmap::samples::WavySurface(32);
    w.b = invmap::samples::NurbsTorus(0.1, 0.04);
    for (int i = 0; i < freshCount; ++i) {
      w.fresh.push_back(AxisAngle(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5, 2 * pi * u(rng), 0.15 + 0.7 * u(rng),
                                  0.15 + 0.7 * u(rng), 0.4 + 0.2 * u(rng)));
    }
    for (int i = 0; i < trackCount; ++i) {
      const double t = 1e-3 * i;
      w.trajectory.push_back(AxisAngle(1, 0.5, 0.2, 0.3 + t, 0.5 + 0.3 * std::sin(t), 0.5 + 0.3 * std::cos(1.3 * t),
                                       0.38 + 0.02 * std::sin(2 * t)));
    }
    list.push_back(std::move(w));
  }
  {
    Workload w;
    w.name = "bicubic surface 16x16 spans / bicubic 8x8 facing it";
    w.a = invmap::samples::WavySurface(16);
    w.b = invmap::samples::WavySurface(8);
    for (int i = 0; i < freshCount; ++i) {
      // B upside down (about x), shifted, turned a little about z.
      w.fresh.push_back(AxisAngle(std::cos(0.2 * u(rng)), std::sin(0.2 * u(rng)), 0.0, pi, 0.3 * u(rng) - 0.15,
                                  0.3 * u(rng) + 0.85, 0.45 + 0.1 * u(rng)));
    }
    for (int i = 0; i < trackCount; ++i) {
      const double t = 1e-3 * i;
      w.trajectory.push_back(AxisAngle(1, 0.05 * std::sin(t), 0, pi, 0.1 * std::sin(t), 1.0 + 0.1 * std::cos(t), 0.5));
    }
    list.push_back(std::move(w));
  }
  auto meshWorkload = [&](const std::string& name, std::int64_t bigTriangles, std::int64_t smallTriangles, bool occ) {
    Workload w;
    w.name = name;
    w.meshes = true;
    w.occ = occ;
    w.a = invmap::samples::BumpySphere(bigTriangles);
    w.b = Scaled(invmap::samples::BumpySphere(smallTriangles), 0.15);
    for (int i = 0; i < freshCount; ++i) {
      const double z = 2 * u(rng) - 1, phi = 2 * pi * u(rng), r = std::sqrt(1 - z * z), d = 1.3 + 0.2 * u(rng);
      w.fresh.push_back(AxisAngle(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5, 2 * pi * u(rng), d * r * std::cos(phi),
                                  d * r * std::sin(phi), d * z));
    }
    for (int i = 0; i < trackCount; ++i) {
      const double t = 2e-3 * i;
      w.trajectory.push_back(AxisAngle(0, 0, 1, t, 1.3 * std::cos(t), 1.3 * std::sin(t), 0.3 * std::sin(0.7 * t)));
    }
    return w;
  };
  list.push_back(meshWorkload("triangle meshes 1,280 / 320", 1280, 320, true));
  list.push_back(meshWorkload("triangle meshes 81,920 / 5,120", 81920, 5120, false));
#if INVMAP_PEER_CAD
  {
    // The bracket against a copy of itself turned about a random axis,
    // its centre 0.6 to 0.9 of the bracket's size from the first one's.
    Workload w;
    w.name = "CAD bracket.step / bracket.step (trimmed faces)";
    w.cadFile = std::string(INVMAP_SOURCE_DIR) + "/examples/data/bracket.step";
    const invmap::cad::LoadResult loaded = invmap::cad::Model::Load(w.cadFile);
    if (!loaded.error.empty()) {
      std::fprintf(stderr, "%s: %s\n", w.cadFile.c_str(), loaded.error.c_str());
      std::exit(1);
    }
    w.a = w.b = loaded.model->geometry();
    const invmap::cad::ModelInfo info = loaded.model->Info();
    double center[3], size2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      center[k] = 0.5 * (info.boundsLo[k] + info.boundsHi[k]);
      size2 += (info.boundsHi[k] - info.boundsLo[k]) * (info.boundsHi[k] - info.boundsLo[k]);
    }
    const double size = std::sqrt(size2);
    w.tolerance = 1e-6 * size;
    auto posed = [&](double ax, double ay, double az, double angle, double dx, double dy, double dz, double reach) {
      // x -> R (x - c) + c + reach d: turned about the centre, moved along d.
      Pose pose = AxisAngle(ax, ay, az, angle, 0, 0, 0);
      const double n = std::sqrt(dx * dx + dy * dy + dz * dz);
      for (int k = 0; k < 3; ++k) {
        double rc = 0.0;
        for (int l = 0; l < 3; ++l) rc += pose.m[4 * k + l] * center[l];
        pose.m[4 * k + 3] = center[k] - rc + reach * size * (k == 0 ? dx : k == 1 ? dy : dz) / n;
      }
      return pose;
    };
    for (int i = 0; i < freshCount; ++i) {
      w.fresh.push_back(posed(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5, 2 * pi * u(rng), u(rng) - 0.5, u(rng) - 0.5,
                              u(rng) - 0.5, 0.6 + 0.3 * u(rng)));
    }
    for (int i = 0; i < trackCount; ++i) {
      const double t = 1e-3 * i;
      w.trajectory.push_back(posed(1, 0.5, 0.2, 0.3 + t, std::cos(t), std::sin(t), 0.3, 0.75));
    }
    list.push_back(std::move(w));
  }
#endif
  return list;
}

// -------------------------------------------------------------------- peers

#if INVMAP_PEER_OCC
/// The geometry as an OpenCascade shape: a B-spline surface patch as a face
/// on a Geom_BSplineSurface (same poles, weights and knots), a triangle mesh
/// as a compound of planar triangular faces.
TopoDS_Shape ToOccShape(const Geometry& g) {
  BRep_Builder builder;
  TopoDS_Compound compound;
  builder.MakeCompound(compound);
  for (const invmap::Patch& patch : g.patches) {
    if (patch.kind == invmap::Patch::Kind::BSpline && patch.degrees.size() == 2) {
      const Handle(Geom_BSplineSurface) surface = invmap::bench::ToOccSurface(patch);
      builder.Add(compound, BRepBuilderAPI_MakeFace(surface, Precision::Confusion()).Face());
    } else if (patch.kind == invmap::Patch::Kind::Mesh && patch.cell == invmap::CellType::Tri) {
      for (std::size_t c = 0; c + 2 < patch.cells.size(); c += 3) {
        gp_Pnt p[3];
        for (int v = 0; v < 3; ++v) {
          const double* x = &patch.points[3 * static_cast<std::size_t>(patch.cells[c + v])];
          p[v] = gp_Pnt(x[0], x[1], x[2]);
        }
        BRepBuilderAPI_MakePolygon polygon(p[0], p[1], p[2], Standard_True);
        builder.Add(compound, BRepBuilderAPI_MakeFace(polygon.Wire(), Standard_True).Face());
      }
    }
  }
  return compound;
}

Peer MakeOccPeer(const Workload& w) {
  auto a = std::make_shared<TopoDS_Shape>();
  auto b = std::make_shared<TopoDS_Shape>();
#if INVMAP_PEER_CAD
  if (!w.cadFile.empty()) {
    std::string format;
    *a = *b = invmap::cad::ReadCadShape(w.cadFile, &format);
  }
#endif
  if (w.cadFile.empty()) {
    *a = ToOccShape(w.a);
    *b = ToOccShape(w.b);
  }
  Peer peer;
  peer.name = std::string("OpenCascade ") + OCC_VERSION_COMPLETE + " BRepExtrema_DistShapeShape";
  peer.query = [a, b](const Pose& pose) {
    Answer answer;
    try {
      gp_Trsf trsf;
      const double* m = pose.m;
      trsf.SetValues(m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8], m[9], m[10], m[11]);
      BRepExtrema_DistShapeShape extrema;
      extrema.SetFlag(Extrema_ExtFlag_MIN);
      extrema.LoadS1(*a);
      extrema.LoadS2(b->Moved(TopLoc_Location(trsf)));
      if (extrema.Perform() && extrema.IsDone() && extrema.NbSolution() > 0) answer.distance = extrema.Value();
    } catch (const Standard_Failure&) {
    }
    return answer;
  };
  return peer;
}
#endif

#if INVMAP_PEER_FCL
std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> ToFclModel(const Geometry& g) {
  auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  std::vector<fcl::Vector3d> points;
  std::vector<fcl::Triangle> triangles;
  for (const invmap::Patch& patch : g.patches) {
    const std::size_t first = points.size();
    for (std::size_t i = 0; i + 2 < patch.points.size(); i += 3) {
      points.emplace_back(patch.points[i], patch.points[i + 1], patch.points[i + 2]);
    }
    for (std::size_t c = 0; c + 2 < patch.cells.size(); c += 3) {
      triangles.emplace_back(first + patch.cells[c], first + patch.cells[c + 1], first + patch.cells[c + 2]);
    }
  }
  model->beginModel();
  model->addSubModel(points, triangles);
  model->endModel();
  return model;
}

Peer MakeFclPeer(const Workload& w) {
  auto a = std::make_shared<fcl::CollisionObjectd>(ToFclModel(w.a));
  auto b = std::make_shared<fcl::CollisionObjectd>(ToFclModel(w.b));
  Peer peer;
  peer.name = "FCL " FCL_VERSION " distance (OBBRSS BVH models)";
  peer.query = [a, b](const Pose& pose) {
    fcl::Transform3d transform = fcl::Transform3d::Identity();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) transform.linear()(r, c) = pose.m[4 * r + c];
      transform.translation()(r) = pose.m[4 * r + 3];
    }
    b->setTransform(transform);
    b->computeAABB();
    fcl::DistanceRequestd request(true);
    fcl::DistanceResultd result;
    fcl::distance(a.get(), b.get(), request, result);
    Answer answer;
    answer.distance = std::max(0.0, result.min_distance);
    return answer;
  };
  return peer;
}
#endif

// ------------------------------------------------------------------ running

struct Row {
  std::string workload, mode, engine;
  std::size_t poses = 0;
  double secondsPerPose = 0.0;
  double ratio = 1.0;            ///< Peer time / invmap time (1 for invmap).
  int invmapFarther = 0;         ///< Poses where invmap's answer is farther than this peer's.
  int peerFarther = 0;           ///< Poses where this peer's answer is farther than invmap's.
  int failed = 0;                ///< Poses this engine gave no answer for.
  double worstExcess = 0.0;      ///< Largest invmap - peer distance.
  int uncertified = 0;           ///< invmap's answers not certified.
};

struct InvmapModels {
  invmap::Manifold ma, mb;
  invmap::DistanceModel a, b;
};

std::unique_ptr<InvmapModels> BuildInvmap(const Workload& w) {
  auto models = std::make_unique<InvmapModels>();
  auto ba = invmap::Manifold::Build(w.a);
  auto bb = invmap::Manifold::Build(w.b);
  if (!ba.error.empty() || !bb.error.empty()) {
    std::fprintf(stderr, "build failed: %s %s\n", ba.error.c_str(), bb.error.c_str());
    std::exit(1);
  }
  models->ma = std::move(ba.manifold);
  models->mb = std::move(bb.manifold);
  models->a = invmap::DistanceModel::Build(models->ma).model;
  models->b = invmap::DistanceModel::Build(models->mb).model;
  return models;
}

void RunWorkload(const Workload& w, std::vector<Row>* rows) {
  std::fprintf(stderr, "%s\n", w.name.c_str());
  const auto models = BuildInvmap(w);
  invmap::DistanceOptions options;
  options.threads = 1;
  // A first query builds what is built lazily, outside the timings.
  {
    invmap::DistanceResult warm;
    invmap::Distance(models->a, Pose(), models->b, w.fresh.front(), options, &warm);
  }

  std::vector<Peer> peers;
#if INVMAP_PEER_OCC
  if (!w.meshes || w.occ) {
    peers.push_back(MakeOccPeer(w));
    // BRepExtrema on hundreds of faces takes a while per pose.
    if (w.meshes) peers.back().maxPoses = 8;
  }
#endif
#if INVMAP_PEER_FCL
  if (w.meshes) peers.push_back(MakeFclPeer(w));
#endif

  for (int mode = 0; mode < 2; ++mode) {
    const bool tracked = mode == 1;
    const std::vector<Pose>& poses = tracked ? w.trajectory : w.fresh;
    std::vector<double> ours(poses.size());
    Row mine;
    mine.workload = w.name;
    mine.mode = tracked ? "tracked pose" : "fresh query";
    mine.engine = tracked ? "invmap DistanceTracker" : "invmap Distance";
    mine.poses = poses.size();
    invmap::DistanceTracker tracker(models->a, models->b, Pose(), options);
    const double start = ThreadSeconds();
    for (std::size_t i = 0; i < poses.size(); ++i) {
      invmap::DistanceResult result;
      const invmap::Error error = tracked ? tracker.Update(poses[i], &result)
                                          : invmap::Distance(models->a, Pose(), models->b, poses[i], options, &result);
      ours[i] = error == invmap::Error::Ok && result.nearest.found ? result.nearest.distance
                                                                    : std::numeric_limits<double>::quiet_NaN();
      if (std::isnan(ours[i])) ++mine.failed;
      if (!result.nearest.certified) ++mine.uncertified;
    }
    mine.secondsPerPose = (ThreadSeconds() - start) / static_cast<double>(poses.size());
    rows->push_back(mine);

    for (const Peer& peer : peers) {
      Row row;
      row.workload = w.name;
      row.mode = mine.mode;
      row.engine = peer.name + (tracked ? " (fresh per pose)" : "");
      row.poses = std::min(poses.size(), peer.maxPoses);
      // Spread over the list, so a prefix is not a special stretch.
      const std::size_t stride = std::max<std::size_t>(1, poses.size() / row.poses);
      double seconds = 0.0;
      double ourSeconds = 0.0;
      std::size_t asked = 0;
      for (std::size_t i = 0; i < poses.size() && asked < row.poses; i += stride, ++asked) {
        const double t0 = ThreadSeconds();
        const Answer answer = peer.query(poses[i]);
        seconds += ThreadSeconds() - t0;
        if (std::isnan(answer.distance)) {
          ++row.failed;
          continue;
        }
        const double excess = ours[i] - answer.distance;
        row.worstExcess = std::max(row.worstExcess, excess);
        if (excess > w.tolerance) ++row.invmapFarther;
        if (-excess > w.tolerance) ++row.peerFarther;
      }
      row.poses = asked;
      (void)ourSeconds;
      row.secondsPerPose = seconds / static_cast<double>(std::max<std::size_t>(asked, 1));
      row.ratio = row.secondsPerPose / mine.secondsPerPose;
      rows->push_back(row);
    }
  }
}

std::string Format(double seconds) {
  char buffer[64];
  if (seconds < 1e-3) {
    std::snprintf(buffer, sizeof buffer, "%.1f us", seconds * 1e6);
  } else if (seconds < 1.0) {
    std::snprintf(buffer, sizeof buffer, "%.2f ms", seconds * 1e3);
  } else {
    std::snprintf(buffer, sizeof buffer, "%.2f s", seconds);
  }
  return buffer;
}

std::string Markdown(const std::vector<Row>& rows) {
  std::ostringstream out;
  out << "| workload | mode | engine | poses | CPU time per pose | peer / invmap | invmap farther | peer farther | "
         "failed | invmap uncertified |\n";
  out << "|---|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const Row& r : rows) {
    char ratio[32];
    std::snprintf(ratio, sizeof ratio, "%.1fx", r.ratio);
    const bool ours = r.engine.rfind("invmap", 0) == 0;
    out << "| " << r.workload << " | " << r.mode << " | " << r.engine << " | " << r.poses << " | "
        << Format(r.secondsPerPose) << " | " << (ours ? "" : ratio) << " | " << (ours ? "" : std::to_string(r.invmapFarther))
        << " | " << (ours ? "" : std::to_string(r.peerFarther)) << " | " << r.failed << " | "
        << (ours ? std::to_string(r.uncertified) : "") << " |\n";
  }
  return out.str();
}

std::string Csv(const std::vector<Row>& rows) {
  std::ostringstream out;
  out << "workload,mode,engine,poses,seconds_per_pose,peer_over_invmap,invmap_farther,peer_farther,failed,worst_excess,"
         "invmap_uncertified\n";
  for (const Row& r : rows) {
    out << '"' << r.workload << "\"," << r.mode << ",\"" << r.engine << "\"," << r.poses << "," << r.secondsPerPose
        << "," << r.ratio << "," << r.invmapFarther << "," << r.peerFarther << "," << r.failed << "," << r.worstExcess
        << "," << r.uncertified << "\n";
  }
  return out.str();
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::string markdownPath, csvPath, only;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--quick") {
      quick = true;
    } else if (arg == "--markdown" && i + 1 < argc) {
      markdownPath = argv[++i];
    } else if (arg == "--only" && i + 1 < argc) {
      only = argv[++i];
    } else if (arg == "--csv" && i + 1 < argc) {
      csvPath = argv[++i];
    } else {
      std::fprintf(stderr, "usage: %s [--quick] [--only TEXT] [--markdown FILE] [--csv FILE]\n", argv[0]);
      return 2;
    }
  }
#if !INVMAP_PEER_OCC
  std::fprintf(stderr, "OpenCascade not found: its rows are missing\n");
#endif
#if !INVMAP_PEER_FCL
  std::fprintf(stderr, "FCL not found: its rows are missing\n");
#endif
  std::vector<Row> rows;
  for (const Workload& w : MakeWorkloads(quick)) {
    if (w.name.find(only) != std::string::npos) RunWorkload(w, &rows);
  }
  const std::string table = Markdown(rows);
  std::fputs(table.c_str(), stdout);
  if (!markdownPath.empty()) std::ofstream(markdownPath) << table;
  if (!csvPath.empty()) std::ofstream(csvPath) << Csv(rows);
  int farther = 0;
  for (const Row& r : rows) farther += r.invmapFarther;
  return farther == 0 ? 0 : 1;
}
