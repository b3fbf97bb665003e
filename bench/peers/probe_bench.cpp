// invmap_bench_probe: `invmap probe`'s work (inversion of the points, then
// the node field interpolated in the found cell) against vtkProbeFilter on
// linear and quadratic tetrahedra and hexahedra, and against gmsh's view
// interpolation (gmsh::view::probe) on tetrahedra of order 2 and 3: points
// per second in the same run, and wrong answers counted for every method as
// the peer harness counts them: a point of the mesh not found, or a value
// off the exact field by more than 1e-9 of the field's range (the peers'
// values off by more than 1e-6 of it are counted too, and the largest error).
//
//   invmap_bench_probe [--quick] [--points N] [--threads T] [--repeat R] [--only TEXT] [--markdown F] [--csv F]
//                      [--work-dir D]
//
// --only TEXT runs the meshes whose name contains TEXT ("linear hexes", "gmsh").
// --repeat R times every method R times (default 3) and reports the run of
// median time.
#include <gmsh.h>
#include <vtkCellLocatorStrategy.h>
#include <vtkCharArray.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkProbeFilter.h>
#include <vtkStaticCellLocator.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "bench/peers/probe_meshes.h"
#include "fem/register_readers.h"
#include "invmap/fields.h"
#include "io/field_geometry_file.h"

namespace invmap::bench {
namespace {

double Seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

struct Options {
  bool quick = false;
  std::int64_t points = 200000;
  int threads = 0;
  int repeat = 3;  ///< Timed runs of each method; the median is reported.
  std::string markdown = "probe_results.md";
  std::string csv = "probe_results.csv";
  std::string workDir = "probe_work";
  std::string only;  ///< Run only the meshes whose name contains this.
};

/// One method's run on a point set.
struct MethodRun {
  std::string method;
  std::int64_t points = 0;
  double seconds = 0.0;  ///< Timed part (the probe; set-up excluded).
  double setupSeconds = 0.0;
  std::int64_t notFound = 0;  ///< Points of the mesh the method did not find.
  std::int64_t wrong = 0;     ///< Not found, or off the exact field by more than 1e-9 of its range.
  std::int64_t farOff = 0;    ///< Found, but off by more than 1e-6 of the range.
  double maxError = 0.0;      ///< Largest error of a found point, relative to the range.
  double rate() const { return seconds > 0 ? points / seconds : 0.0; }

  /// Scores one answer against the exact value; `range` is the field's.
  void Score(bool found, double value, double exact, double range) {
    if (!found) {
      ++notFound;
      ++wrong;
      return;
    }
    const double error = std::abs(value - exact) / range;
    maxError = std::max(maxError, error);
    wrong += error > 1e-9;
    farOff += error > 1e-6;
  }
};

struct Row {
  std::string mesh;
  std::int64_t cells = 0;
  MethodRun invmap1, invmapAll;
  std::vector<MethodRun> peers;
};

/// The run of median time of `repeat` runs of `run`: on a shared machine
/// one run in a few is slowed by others' work.
MethodRun MedianRun(int repeat, const std::function<MethodRun()>& run) {
  std::vector<MethodRun> runs;
  for (int r = 0; r < std::max(1, repeat); ++r) runs.push_back(run());
  std::sort(runs.begin(), runs.end(), [](const MethodRun& a, const MethodRun& b) { return a.seconds < b.seconds; });
  return runs[runs.size() / 2];
}

/// The range of the exact values (at least 1e-300).
double Range(const std::vector<double>& exact) {
  const auto [lo, hi] = std::minmax_element(exact.begin(), exact.end());
  return std::max(*hi - *lo, 1e-300);
}

/// Uniform points of the mesh's domain (the sheared unit box) and their exact values.
void MakePoints(std::int64_t count, int degree, bool boxOnly, std::vector<double>* xyz, std::vector<double>* exact) {
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  xyz->clear();
  exact->clear();
  for (std::int64_t i = 0; i < count; ++i) {
    const std::array<double, 3> r{u(rng), u(rng), u(rng)};
    const std::array<double, 3> x = boxOnly ? r : BoxPoint(r);
    xyz->insert(xyz->end(), x.begin(), x.end());
    exact->push_back(ExactField(x, degree));
  }
}

/// invmap: Invert then ProbeFields, timed together.
MethodRun RunInvmap(const FieldGeometry& model, const Manifold& manifold, const std::vector<double>& xyz,
                    const std::vector<double>& exact, int threads, const std::string& name) {
  MethodRun run;
  run.method = name;
  run.points = static_cast<std::int64_t>(exact.size());
  InversionOptions options;
  options.threads = threads;
  Results results;
  std::vector<double> values;
  const std::vector<const NodeField*> fields = {&model.fields[0]};
  // Warm-up on a few points (first-touch allocations), then the timed run.
  manifold.Invert(PointsView::Interleaved(xyz.data(), std::min<std::size_t>(1000, exact.size()), 3), options, &results);
  const double t0 = Seconds();
  manifold.Invert(PointsView::Interleaved(xyz.data(), exact.size(), 3), options, &results);
  ProbeFields(model.geometry, fields, results, &values, nullptr, threads);
  run.seconds = Seconds() - t0;
  const double range = Range(exact);
  for (std::size_t i = 0; i < exact.size(); ++i) run.Score(results.status[i] == Status::Found, values[i], exact[i], range);
  return run;
}

/// vtkProbeFilter on the first `count` points; with a static cell locator
/// built before the timing, or VTK's default search (vtkDataSet::FindCell).
MethodRun RunVtkProbe(vtkUnstructuredGrid* grid, const std::vector<double>& xyz, const std::vector<double>& exact,
                      std::int64_t count, bool locator) {
  MethodRun run;
  run.method = locator ? "vtkProbeFilter + vtkStaticCellLocator" : "vtkProbeFilter (default FindCell)";
  run.points = count;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(count);
  for (std::int64_t i = 0; i < count; ++i) points->SetPoint(i, xyz.data() + 3 * i);
  vtkNew<vtkPolyData> input;
  input->SetPoints(points);
  vtkNew<vtkProbeFilter> probe;
  probe->SetInputData(input);
  probe->SetSourceData(grid);
  vtkNew<vtkStaticCellLocator> cellLocator;
  vtkNew<vtkCellLocatorStrategy> strategy;
  if (locator) {
    const double t0 = Seconds();
    cellLocator->SetDataSet(grid);
    cellLocator->BuildLocator();
    strategy->SetCellLocator(cellLocator);
    probe->SetFindCellStrategy(strategy);
    run.setupSeconds = Seconds() - t0;
  }
  const double t0 = Seconds();
  probe->Update();
  run.seconds = Seconds() - t0;
  vtkDataArray* values = probe->GetOutput()->GetPointData()->GetArray("f");
  vtkDataArray* valid = probe->GetOutput()->GetPointData()->GetArray(probe->GetValidPointMaskArrayName());
  const double range = Range(exact);
  for (std::int64_t i = 0; i < count; ++i) {
    run.Score(valid->GetComponent(i, 0) != 0.0, values->GetComponent(i, 0), exact[i], range);
  }
  return run;
}

/// How many points a peer gets: what it does in about `budget` seconds,
/// measured on a small sample, at most `limit`.
std::int64_t Calibrate(const std::function<double(std::int64_t)>& secondsFor, std::int64_t limit, double budget) {
  const std::int64_t sample = std::min<std::int64_t>(limit, 2000);
  const double s = std::max(secondsFor(sample), 1e-6);
  return std::min<std::int64_t>(limit, std::max<std::int64_t>(sample, static_cast<std::int64_t>(budget * sample / s)));
}

Row VtkRow(const ProbeMeshKind& kind, int cells, const Options& options) {
  Row row;
  row.mesh = ProbeMeshName(kind);
  vtkSmartPointer<vtkUnstructuredGrid> grid = MakeProbeMesh(kind, cells);
  row.cells = grid->GetNumberOfCells();
  const std::string path = options.workDir + "/" + (kind.hexes ? "hex" : "tet") + std::to_string(kind.order) + ".vtu";
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(grid);
  writer->SetDataModeToAppended();
  writer->Write();
  const FieldGeometry model = io::ReadGeometryWithFields(path);
  BuildResult built = Manifold::Build(model.geometry);
  std::vector<double> xyz, exact;
  MakePoints(options.points, kind.order, false, &xyz, &exact);
  const int repeat = options.repeat;
  row.invmap1 = MedianRun(repeat, [&] { return RunInvmap(model, built.manifold, xyz, exact, 1, "invmap, 1 thread"); });
  row.invmapAll = MedianRun(
      repeat, [&] { return RunInvmap(model, built.manifold, xyz, exact, options.threads, "invmap, all threads"); });
  const double budget = options.quick ? 0.2 : 3.0;
  row.peers.push_back(
      MedianRun(repeat, [&] { return RunVtkProbe(grid, xyz, exact, static_cast<std::int64_t>(exact.size()), true); }));
  const std::int64_t n = Calibrate(
      [&](std::int64_t count) { return RunVtkProbe(grid, xyz, exact, count, false).seconds; },
      static_cast<std::int64_t>(exact.size()), budget);
  row.peers.push_back(MedianRun(repeat, [&] { return RunVtkProbe(grid, xyz, exact, n, false); }));
  return row;
}

std::string GmshMeshName(int order) { return "gmsh tets, order " + std::to_string(order); }

/// gmsh: the unit cube in tetrahedra of `order` with the exact field as a
/// NodeData view, probed point by point by gmsh::view::probe; invmap reads
/// the .msh gmsh writes.
Row GmshRow(int order, const Options& options) {
  Row row;
  row.mesh = GmshMeshName(order);
  gmsh::clear();
  gmsh::model::add("cube");
  gmsh::model::occ::addBox(0, 0, 0, 1, 1, 1);
  gmsh::model::occ::synchronize();
  gmsh::option::setNumber("Mesh.CharacteristicLengthMax", options.quick ? 0.25 : 0.07);
  gmsh::model::mesh::generate(3);
  gmsh::model::mesh::setOrder(order);
  std::vector<std::size_t> tags;
  std::vector<double> coordinates, parametric;
  gmsh::model::mesh::getNodes(tags, coordinates, parametric);
  std::vector<std::vector<double>> data;
  for (std::size_t i = 0; i < tags.size(); ++i) {
    data.push_back({ExactField({coordinates[3 * i], coordinates[3 * i + 1], coordinates[3 * i + 2]}, order)});
  }
  const int view = gmsh::view::add("f");
  gmsh::view::addModelData(view, 0, "cube", "NodeData", tags, data);
  const std::string path = options.workDir + "/gmsh_order" + std::to_string(order) + ".msh";
  gmsh::option::setNumber("Mesh.MshFileVersion", 4.1);
  gmsh::option::setNumber("Mesh.Binary", 1);
  gmsh::option::setNumber("PostProcessing.SaveMesh", 1);
  gmsh::view::write(view, path);
  // gmsh probes the file invmap reads, as a user would (reloaded, its
  // order-3 views probe; the in-memory view of a mesh raised to order 3
  // found no point).
  gmsh::clear();
  gmsh::open(path);
  std::vector<int> views;
  gmsh::view::getTags(views);
  const int loaded = views.at(0);
  std::vector<int> types;
  std::vector<std::vector<std::size_t>> elementTags, nodeTags;
  gmsh::model::mesh::getElements(types, elementTags, nodeTags, 3);
  for (const auto& t : elementTags) row.cells += static_cast<std::int64_t>(t.size());

  const FieldGeometry model = io::ReadGeometryWithFields(path);
  BuildResult built = Manifold::Build(model.geometry);
  std::vector<double> xyz, exact;
  MakePoints(options.points, order, true, &xyz, &exact);
  row.invmap1 =
      MedianRun(options.repeat, [&] { return RunInvmap(model, built.manifold, xyz, exact, 1, "invmap, 1 thread"); });
  row.invmapAll = MedianRun(options.repeat, [&] {
    return RunInvmap(model, built.manifold, xyz, exact, options.threads, "invmap, all threads");
  });
  const auto gmshRun = [&](std::int64_t count) {
    MethodRun run;
    run.method = "gmsh::view::probe";
    run.points = count;
    std::vector<std::vector<double>> values(static_cast<std::size_t>(count));
    const double t0 = Seconds();
    for (std::int64_t i = 0; i < count; ++i) {
      try {
        gmsh::view::probe(loaded, xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2], values[i], 0);
      } catch (...) {
        values[i].clear();
      }
    }
    run.seconds = Seconds() - t0;
    const double range = Range(exact);
    for (std::int64_t i = 0; i < count; ++i) {
      run.Score(values[i].size() == 1, values[i].empty() ? 0.0 : values[i][0], exact[i], range);
    }
    return run;
  };
  const std::int64_t n = Calibrate([&](std::int64_t count) { return gmshRun(count).seconds; },
                                   static_cast<std::int64_t>(exact.size()), options.quick ? 0.2 : 3.0);
  row.peers.push_back(MedianRun(options.repeat, [&] { return gmshRun(n); }));
  return row;
}

void Report(const std::vector<Row>& rows, const Options& options, int threads) {
  std::ostringstream md, csv;
  md << "| mesh | cells | invmap 1 thread (points/s) | invmap " << threads
     << " threads (points/s) | invmap wrong | peer | peer points | peer points/s | peer wrong (not found, off > 1e-6) | "
        "peer max error | ratio 1 thread | ratio "
     << threads << " threads |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  csv << "mesh,cells,invmap_points,invmap_rate_1,invmap_rate_all,invmap_wrong,invmap_max_error,peer,peer_points,"
         "peer_rate,peer_wrong,peer_not_found,peer_off_1e-6,peer_max_error,peer_setup_seconds,ratio_1,ratio_all\n";
  for (const Row& row : rows) {
    const std::int64_t invmapWrong = row.invmap1.wrong + row.invmapAll.wrong;
    const double invmapMax = std::max(row.invmap1.maxError, row.invmapAll.maxError);
    for (const MethodRun& peer : row.peers) {
      char line[1024];
      std::snprintf(line, sizeof line,
                    "| %s | %lld | %.3g | %.3g | %lld of %lld | %s | %lld | %.3g | %lld (%lld, %lld) | %.2g | %.1fx | "
                    "%.1fx |\n",
                    row.mesh.c_str(), static_cast<long long>(row.cells), row.invmap1.rate(), row.invmapAll.rate(),
                    static_cast<long long>(invmapWrong),
                    static_cast<long long>(row.invmap1.points + row.invmapAll.points), peer.method.c_str(),
                    static_cast<long long>(peer.points), peer.rate(), static_cast<long long>(peer.wrong),
                    static_cast<long long>(peer.notFound), static_cast<long long>(peer.farOff), peer.maxError,
                    row.invmap1.rate() / peer.rate(), row.invmapAll.rate() / peer.rate());
      md << line;
      std::snprintf(line, sizeof line, "%s,%lld,%lld,%.6g,%.6g,%lld,%.3g,%s,%lld,%.6g,%lld,%lld,%lld,%.3g,%.6g,%.6g,%.6g\n",
                    row.mesh.c_str(), static_cast<long long>(row.cells), static_cast<long long>(row.invmap1.points),
                    row.invmap1.rate(), row.invmapAll.rate(), static_cast<long long>(invmapWrong), invmapMax,
                    peer.method.c_str(), static_cast<long long>(peer.points), peer.rate(),
                    static_cast<long long>(peer.wrong), static_cast<long long>(peer.notFound),
                    static_cast<long long>(peer.farOff), peer.maxError, peer.setupSeconds,
                    row.invmap1.rate() / peer.rate(), row.invmapAll.rate() / peer.rate());
      csv << line;
    }
  }
  std::printf("%s", md.str().c_str());
  std::ofstream(options.markdown) << md.str();
  std::ofstream(options.csv) << csv.str();
}

int Main(int argc, char** argv) {
  Options options;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto next = [&]() -> std::string { return i + 1 < argc ? argv[++i] : ""; };
    if (a == "--quick") {
      options.quick = true;
      options.points = 5000;
    } else if (a == "--points") {
      options.points = std::stoll(next());
    } else if (a == "--threads") {
      options.threads = std::stoi(next());
    } else if (a == "--repeat") {
      options.repeat = std::stoi(next());
    } else if (a == "--only") {
      options.only = next();
    } else if (a == "--markdown") {
      options.markdown = next();
    } else if (a == "--csv") {
      options.csv = next();
    } else if (a == "--work-dir") {
      options.workDir = next();
    } else {
      std::fprintf(stderr,
                   "usage: invmap_bench_probe [--quick] [--points N] [--threads T] [--repeat R] [--only TEXT] "
                   "[--markdown F] [--csv F] [--work-dir D]\n");
      return 2;
    }
  }
  std::filesystem::create_directories(options.workDir);
  fem::RegisterFemReaders();
  gmsh::initialize(0, nullptr, false);
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::option::setNumber("General.Verbosity", 0);
  const int threads = options.threads > 0 ? options.threads : static_cast<int>(std::thread::hardware_concurrency());
  std::vector<Row> rows;
  for (const ProbeMeshKind kind : {ProbeMeshKind{false, 1}, ProbeMeshKind{false, 2}, ProbeMeshKind{true, 1},
                                   ProbeMeshKind{true, 2}}) {
    if (ProbeMeshName(kind).find(options.only) == std::string::npos) continue;
    const int cells = options.quick ? 6 : (kind.hexes ? (kind.order == 1 ? 40 : 30) : (kind.order == 1 ? 24 : 20));
    rows.push_back(VtkRow(kind, cells, options));
  }
  for (int order : {2, 3}) {
    if (GmshMeshName(order).find(options.only) != std::string::npos) {
      rows.push_back(GmshRow(order, options));
    }
  }
  gmsh::finalize();
  Report(rows, options, threads);
  return 0;
}

}  // namespace
}  // namespace invmap::bench

int main(int argc, char** argv) { return invmap::bench::Main(argc, argv); }
