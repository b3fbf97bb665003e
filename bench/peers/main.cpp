// invmap_bench_peers: invmap against the libraries users would otherwise pick
// (OpenCascade, SISL, Embree, CGAL, gmsh), on the same points in the same run,
// speed and correct answers both (issue 5). Peers missing at build time are
// listed and skipped.
//
//   invmap_bench_peers [--quick] [--markdown F] [--csv F] [--scaling-csv F] ...
//   (--help lists every option)
#include <sys/utsname.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <thread>

#include "bench/peers/harness.h"
#include "bench/peers/peer.h"
#include "bench/peers/report.h"
#include "bench/peers/scaling.h"
#include "bench/peers/workloads.h"

namespace invmap::bench {
namespace {

/// Command-line options.
struct Options {
  bool quick = false;
  std::int64_t points = -1;      ///< Per point set; -1: 10^6 (quick: 2 x 10^4).
  double peerBudget = -1;        ///< Seconds of a peer's 1-thread run; -1: 2.5 (quick: 0.1).
  double invmapBudget = -1;      ///< Seconds of invmap's 1-thread run; -1: 4 (quick: 0.2).
  int threads = 0;               ///< "All threads"; 0: the hardware's.
  std::string markdown = "peers_results.md";
  std::string csv = "peers_results.csv";
  std::string scalingCsv = "peers_scaling.csv";
  std::string workDir = "peers_work";
  std::string only;
  bool peers = true;
  bool scaling = true;
  int listDisagreements = 0;  ///< Points per row to print where the two disagree.
  bool invmapOnly = false;    ///< invmap and its oracle without the peers (for profiling).
};

void PrintHelp() {
  std::printf(
      "invmap_bench_peers: invmap against OpenCascade, SISL, Embree, CGAL and gmsh (those found at build time).\n"
      "  --quick             small workloads and budgets (a smoke run of a few seconds)\n"
      "  --points N          points per point set (default 1000000; quick 20000)\n"
      "  --budget S          seconds of each peer's 1-thread run, which sets its N (default 2.5)\n"
      "  --invmap-budget S   seconds of invmap's 1-thread run (default 4; never below 10^5 points)\n"
      "  --threads T         threads of the 'all threads' runs (default: all hardware threads)\n"
      "  --markdown F        Markdown report (default peers_results.md; also printed)\n"
      "  --csv F             CSV of the comparison (default peers_results.csv)\n"
      "  --scaling-csv F     CSV of the scaling study (default peers_scaling.csv)\n"
      "  --work-dir D        where the gmsh meshes are written (default peers_work)\n"
      "  --only NAME         only workloads whose geometry name contains NAME\n"
      "                      (surface, torus, curve, trimesh, small trimesh, tets order 2, tets order 3,\n"
      "                      cad bracket, cad screw, cad bearing)\n"
      "  --list-disagreements K  print up to K points per peer and workload where the distances disagree\n"
      "  --invmap-only       run invmap and its oracle but no peer (for profiling invmap)\n"
      "  --no-scaling        skip the scaling study\n"
      "  --scaling-only      only the scaling study\n");
}

/// Parses argv; exits with a message on a bad option.
Options ParseOptions(int argc, char** argv) {
  Options o;
  auto value = [&](int& i) -> std::string {
    if (i + 1 >= argc) {
      std::fprintf(stderr, "invmap_bench_peers: %s needs a value\n", argv[i]);
      std::exit(1);
    }
    return argv[++i];
  };
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") {
      o.quick = true;
    } else if (a == "--points") {
      o.points = std::atoll(value(i).c_str());
    } else if (a == "--budget") {
      o.peerBudget = std::atof(value(i).c_str());
    } else if (a == "--invmap-budget") {
      o.invmapBudget = std::atof(value(i).c_str());
    } else if (a == "--threads") {
      o.threads = std::atoi(value(i).c_str());
    } else if (a == "--markdown") {
      o.markdown = value(i);
    } else if (a == "--csv") {
      o.csv = value(i);
    } else if (a == "--scaling-csv") {
      o.scalingCsv = value(i);
    } else if (a == "--work-dir") {
      o.workDir = value(i);
    } else if (a == "--only") {
      o.only = value(i);
    } else if (a == "--list-disagreements") {
      o.listDisagreements = std::atoi(value(i).c_str());
    } else if (a == "--invmap-only") {
      o.invmapOnly = true;
    } else if (a == "--no-scaling") {
      o.scaling = false;
    } else if (a == "--scaling-only") {
      o.peers = false;
    } else if (a == "--help" || a == "-h") {
      PrintHelp();
      std::exit(0);
    } else {
      std::fprintf(stderr, "invmap_bench_peers: unknown option '%s' (--help lists them)\n", a.c_str());
      std::exit(1);
    }
  }
  if (o.points < 0) o.points = o.quick ? 20000 : 1000000;
  if (o.peerBudget < 0) o.peerBudget = o.quick ? 0.1 : 2.5;
  if (o.invmapBudget < 0) o.invmapBudget = o.quick ? 0.2 : 4.0;
  return o;
}

std::string UtcNow() {
  const std::time_t now = std::time(nullptr);
  char buffer[32];
  std::strftime(buffer, sizeof(buffer), "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  return buffer;
}

/// "Intel(R) Xeon(R) ... , 2 hardware threads, 24 GiB, Linux 6.1": from /proc.
std::string MachineLine() {
  std::string model = "unknown CPU";
  std::ifstream cpu("/proc/cpuinfo");
  for (std::string line; std::getline(cpu, line);) {
    if (line.rfind("model name", 0) == 0) {
      model = line.substr(line.find(':') + 2);
      break;
    }
  }
  double memoryGiB = 0.0;
  std::ifstream memory("/proc/meminfo");
  for (std::string line; std::getline(memory, line);) {
    if (line.rfind("MemTotal:", 0) == 0) memoryGiB = std::atof(line.c_str() + 9) / (1024.0 * 1024.0);
  }
  utsname system;
  std::string kernel = uname(&system) == 0 ? std::string(system.sysname) + " " + system.release : "";
  std::ostringstream s;
  s << model << ", " << std::thread::hardware_concurrency() << " hardware threads, " << std::lround(memoryGiB)
    << " GiB, " << kernel;
  return s.str();
}

std::string CompilerLine() {
  std::ostringstream s;
#if defined(__clang__)
  s << "clang " << __clang_major__ << "." << __clang_minor__;
#elif defined(__GNUC__)
  s << "GCC " << __GNUC__ << "." << __GNUC_MINOR__;
#endif
#if defined(NDEBUG)
  s << ", optimized (NDEBUG)";
#else
  s << ", NOT optimized (assertions on): timings are meaningless";
#endif
  return s.str();
}

void Loads(double* load) {
  if (getloadavg(load, 3) != 3) load[0] = load[1] = load[2] = -1;
}

/// Every peer library's factories for a case, in table order.
PeerList AllPeers(const GeometryCase& c) {
  PeerList all;
  auto add = [&](PeerList list) {
    for (PeerFactory& f : list) all.push_back(std::move(f));
  };
#if defined(INVMAP_PEER_OCC)
  add(MakeOccPeers(c));
#endif
#if defined(INVMAP_PEER_OCC) && defined(INVMAP_BENCH_CAD)
  add(MakeOccCadPeers(c));
#endif
#if defined(INVMAP_PEER_SISL)
  add(MakeSislPeers(c));
#endif
#if defined(INVMAP_PEER_EMBREE)
  add(MakeEmbreePeers(c));
#endif
#if defined(INVMAP_PEER_CGAL)
  add(MakeCgalPeers(c));
#endif
#if defined(INVMAP_PEER_GMSH)
  add(MakeGmshPeers(c));
#endif
  (void)add;
  (void)c;
  return all;
}

void FindPeers(RunInfo* info) {
#if defined(INVMAP_PEER_OCC)
  info->peersFound.push_back(OccVersion());
#else
  info->peersMissing.push_back("OpenCascade (libocct-modeling-algorithms-dev)");
#endif
#if defined(INVMAP_PEER_SISL)
  info->peersFound.push_back(SislVersion());
#else
  info->peersMissing.push_back("SISL (libsisl-dev)");
#endif
#if defined(INVMAP_PEER_EMBREE)
  info->peersFound.push_back(EmbreeVersion());
#else
  info->peersMissing.push_back("Embree 3 (libembree-dev)");
#endif
#if defined(INVMAP_PEER_CGAL)
  info->peersFound.push_back(CgalVersion());
#else
  info->peersMissing.push_back("CGAL (libcgal-dev)");
#endif
#if defined(INVMAP_PEER_GMSH)
  info->peersFound.push_back(GmshVersion());
#else
  info->peersMissing.push_back("gmsh (libgmsh-dev)");
#endif
}

/// Prints up to `limit` points where the peer's and invmap's distances differ
/// by more than `tolerance`, with both answers, for investigation.
void ListDisagreements(int limit, const PointSet& set, const std::vector<PeerAnswer>& answers, const Results& results,
                       double tolerance, const std::string& peer) {
  int printed = 0;
  for (std::size_t i = 0; i < answers.size() && printed < limit; ++i) {
    if (answers[i].failed || results.status[i] != invmap::Status::Found) continue;
    if (std::abs(answers[i].distance - results.distance[i]) <= tolerance) continue;
    const double* p = set.point(static_cast<std::int64_t>(i));
    std::fprintf(stderr,
                 "    %s: point %zu (%.17g, %.17g, %.17g): peer %.17g, invmap %.17g at cell %lld (%.17g, %.17g, %.17g)\n",
                 peer.c_str(), i, p[0], p[1], set.dim == 3 ? p[2] : 0.0, answers[i].distance, results.distance[i],
                 static_cast<long long>(results.cell[i]), results.params[3 * i], results.params[3 * i + 1],
                 results.params[3 * i + 2]);
    ++printed;
  }
}

/// Runs the comparison, appending rows and notes.
void RunComparison(const Options& options, int allThreads, std::vector<InvmapRow>* invmapRows,
                   std::vector<PeerRow>* peerRows, std::vector<std::string>* notes) {
  WorkloadOptions workloadOptions;
  workloadOptions.quick = options.quick;
  workloadOptions.points = options.points;
  workloadOptions.workDir = options.workDir;
  workloadOptions.only = options.only;
  std::fprintf(stderr, "making the workloads...\n");
  const std::vector<GeometryCase> cases = MakeCases(workloadOptions);
  const std::int64_t minPeerCount = options.quick ? 50 : 1000;
  const int invmapThreads = options.threads;  // 0: invmap uses all cores
  std::map<std::string, std::string> peerNotes;

  for (const GeometryCase& c : cases) {
    std::fprintf(stderr, "%s: building invmap's manifold...\n", c.name.c_str());
    double t0 = Now();
    BuildResult built = Manifold::Build(c.geometry);
    const double buildSeconds = Now() - t0;
    if (!built.error.empty()) {
      std::fprintf(stderr, "invmap_bench_peers: %s: %s\n", c.name.c_str(), built.error.c_str());
      std::exit(2);
    }
    const ManifoldInfo manifoldInfo = built.manifold.Info();
    double size2 = 0.0;
    for (int k = 0; k < 3; ++k) size2 += std::pow(manifoldInfo.boundsHi[k] - manifoldInfo.boundsLo[k], 2);
    const double size = std::sqrt(size2);
    const double tolerance = 1e-9 * size;

    std::vector<InvmapRun> invmapRuns;
    for (const PointSet& set : c.pointSets) {
      const std::string workload = c.name + " " + set.name;
      InvmapRun run = RunInvmap(built.manifold, set, options.points, options.invmapBudget, invmapThreads);
      const OracleRun oracle = RunOracle(c.geometry, set, run.count, run.results, tolerance);
      InvmapRow row;
      row.workload = workload;
      row.description = c.description + "; " + set.name + " points (the first N of " + std::to_string(set.count()) +
                        ")";
      row.cells = static_cast<std::int64_t>(manifoldInfo.cells);
      row.size = size;
      row.buildSeconds = buildSeconds;
      row.count = run.count;
      row.seconds1 = run.seconds1;
      row.secondsAll = run.secondsAll;
      row.threadMismatches = run.threadMismatches;
      row.notFound = run.notFound;
      row.oracleSeconds = oracle.seconds;
      row.oracleDisagreements = oracle.disagreements;
      std::fprintf(stderr, "  invmap %-24s N %8lld  1 thread %s/s  all %s/s  oracle ratio %.2f\n", workload.c_str(),
                   static_cast<long long>(run.count), HumanRate(run.count / run.seconds1).c_str(),
                   HumanRate(run.count / run.secondsAll).c_str(), run.seconds1 / oracle.seconds);
      if (run.notFound) notes->push_back(workload + ": invmap did not find " + std::to_string(run.notFound) + " points.");
      if (oracle.disagreements) {
        notes->push_back(workload + ": the oracle's distance differs from invmap's on " +
                         std::to_string(oracle.disagreements) + " points.");
      }
      invmapRows->push_back(row);
      invmapRuns.push_back(std::move(run));
    }

    for (const PeerFactory& factory : options.invmapOnly ? PeerList() : AllPeers(c)) {
      t0 = Now();
      std::unique_ptr<PeerMethod> method = factory();
      const double setupSeconds = Now() - t0;
      for (std::size_t s = 0; s < c.pointSets.size(); ++s) {
        const PointSet& set = c.pointSets[s];
        const InvmapRun& invmap = invmapRuns[s];
        const PeerRun run = RunPeer(*method, set, invmap.count, minPeerCount, options.peerBudget,
                                    allThreads);
        PeerRow row;
        row.workload = c.name + " " + set.name;
        row.peer = method->name();
        row.note = method->note();
        row.setupSeconds = setupSeconds + run.workerSetupSeconds;
        row.count = run.count;
        row.seconds1 = run.seconds1;
        row.secondsAll = run.secondsAll;
        row.threads = run.threads;
        row.threadMismatches = run.threadMismatches;
        row.invmapRate1 = invmap.count / invmap.seconds1;
        row.invmapRateAll = invmap.count / invmap.secondsAll;
        row.agreement = Compare(run.answers, invmap.results, tolerance);
        std::fprintf(stderr,
                     "  %-62s %-22s N %7lld  1 thread %s/s  invmap/peer %.1fx  peer farther %lld  invmap farther "
                     "%lld  failed %lld\n",
                     row.peer.c_str(), row.workload.c_str(), static_cast<long long>(run.count),
                     HumanRate(run.count / run.seconds1).c_str(), row.invmapRate1 * run.seconds1 / run.count,
                     static_cast<long long>(row.agreement.peerFarther),
                     static_cast<long long>(row.agreement.invmapFarther),
                     static_cast<long long>(row.agreement.peerFailed));
        ListDisagreements(options.listDisagreements, set, run.answers, invmap.results, tolerance, row.peer);
        if (run.threadMismatches) {
          notes->push_back(row.peer + " on " + row.workload + ": " + std::to_string(run.threadMismatches) +
                           " answers differ between its 1-thread and threaded runs.");
        }
        if (!row.note.empty()) peerNotes[row.peer] = row.note;
        peerRows->push_back(row);
      }
    }
  }
  for (const auto& [peer, note] : peerNotes) notes->push_back(peer + ": " + note + ".");
}

}  // namespace
}  // namespace invmap::bench

int main(int argc, char** argv) {
  using namespace invmap::bench;
  const Options options = ParseOptions(argc, argv);
  RunInfo info;
  info.date = UtcNow();
  info.machine = MachineLine();
  info.compiler = CompilerLine();
  for (int i = 0; i < argc; ++i) info.command += (i ? " " : "") + std::string(argv[i]);
  info.allThreads = options.threads > 0 ? options.threads : static_cast<int>(std::thread::hardware_concurrency());
  Loads(info.loadStart);
  info.capacityStart = ParallelCapacity(info.allThreads);
  FindPeers(&info);
  const double start = Now();
  std::fprintf(stderr, "invmap_bench_peers: %s; load average %.2f; %d threads run %.2fx as fast as 1\n",
               info.machine.c_str(), info.loadStart[0], info.allThreads, info.capacityStart);
  for (const std::string& missing : info.peersMissing) {
    std::fprintf(stderr, "invmap_bench_peers: peer not built: %s\n", missing.c_str());
  }

  std::vector<InvmapRow> invmapRows;
  std::vector<PeerRow> peerRows;
  std::vector<std::string> notes;
  if (options.peers) RunComparison(options, info.allThreads, &invmapRows, &peerRows, &notes);

  if (options.scaling) {
    std::fprintf(stderr, "scaling study...\n");
    ScalingOptions scalingOptions;
    scalingOptions.quick = options.quick;
    scalingOptions.allThreads = options.threads;
    scalingOptions.allThreadsCount = info.allThreads;
    scalingOptions.capSeconds = options.quick ? 1.0 : 12.0;
    const std::vector<ScalingRow> rows = RunScaling(scalingOptions);
    if (!WriteScalingCsv(options.scalingCsv, rows)) {
      std::fprintf(stderr, "invmap_bench_peers: cannot write %s\n", options.scalingCsv.c_str());
      return 1;
    }
    std::fprintf(stderr, "wrote %s\n", options.scalingCsv.c_str());
  }

  Loads(info.loadEnd);
  info.capacityEnd = ParallelCapacity(info.allThreads);
  info.seconds = Now() - start;
  if (options.peers) {
    if (info.loadStart[0] > 0.75 * info.allThreads || info.capacityStart < 0.8 * info.allThreads ||
        info.capacityEnd < 0.8 * info.allThreads) {
      notes.push_back("The machine was loaded by other work during the run (load averages and parallel capacity "
                      "above): absolute rates are low and noisy, and the threaded columns show the cores this "
                      "process got, not the methods' scaling; the 1-thread ratios come from the same run and hold.");
    }
    const std::string markdown = MarkdownReport(info, invmapRows, peerRows, notes);
    std::cout << markdown;
    std::ofstream md(options.markdown);
    md << markdown;
    if (!md || !WriteCsv(options.csv, info, invmapRows, peerRows)) {
      std::fprintf(stderr, "invmap_bench_peers: cannot write %s or %s\n", options.markdown.c_str(),
                   options.csv.c_str());
      return 1;
    }
    std::fprintf(stderr, "wrote %s and %s\n", options.markdown.c_str(), options.csv.c_str());
  }
  return 0;
}
