#include "bench/peers/report.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace invmap::bench {
namespace {

/// printf-style formatting of one number.
std::string Format(const char* format, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), format, value);
  return buffer;
}

/// "12.3 % (1234)", "0": a share of `total` with its count.
std::string Share(std::int64_t count, std::int64_t total) {
  if (count == 0) return "0";
  const double percent = total > 0 ? 100.0 * count / total : 0.0;
  std::ostringstream s;
  s << Format(percent < 0.1 ? "%.3f" : "%.1f", percent) << " % (" << count << ")";
  return s.str();
}

/// "2.54x", "126x"; "-" when undefined.
std::string Ratio(double ratio) {
  if (!std::isfinite(ratio)) return "-";
  return Format(ratio < 10 ? "%.2f" : (ratio < 100 ? "%.1f" : "%.0f"), ratio) + "x";
}

/// Seconds with two decimals below 10 s.
std::string Seconds(double s) { return Format(s < 10 ? "%.2f" : "%.0f", s); }

/// "1.00 / 2.00 / 3.00": the three load averages.
std::string Load(const double* load) {
  std::ostringstream s;
  s << Format("%.2f", load[0]) << " / " << Format("%.2f", load[1]) << " / " << Format("%.2f", load[2]);
  return s.str();
}

/// Doubles a CSV field's quotes and quotes it when needed.
std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

/// invmap's row of `workload`, or nullptr.
const InvmapRow* InvmapRowOf(const std::vector<InvmapRow>& invmapRows, const std::string& workload) {
  for (const InvmapRow& row : invmapRows) {
    if (row.workload == workload) return &row;
  }
  return nullptr;
}

/// The peer's time per point over invmap's oracle's (NaN without the
/// workload's row): invmap's oracle ratio measured on the peer.
double PeerOverOracle(const PeerRow& peer, const std::vector<InvmapRow>& invmapRows) {
  const InvmapRow* invmap = InvmapRowOf(invmapRows, peer.workload);
  if (!invmap || !(invmap->oracleSeconds > 0.0)) return std::nan("");
  return (peer.seconds1 / peer.count) / (invmap->oracleSeconds / invmap->count);
}

}  // namespace

std::string HumanRate(double rate) {
  if (!std::isfinite(rate) || rate <= 0) return "-";
  if (rate >= 1e6) return Format("%.2f M", rate / 1e6);
  if (rate >= 1e3) return Format(rate >= 1e5 ? "%.0f k" : "%.1f k", rate / 1e3);
  return Format("%.0f", rate);
}

std::string MarkdownReport(const RunInfo& info, const std::vector<InvmapRow>& invmapRows,
                           const std::vector<PeerRow>& peerRows, const std::vector<std::string>& notes) {
  std::ostringstream md;
  const std::string all = std::to_string(info.allThreads) + " threads";
  md << "### invmap against its peers\n\n"
     << "- Date: " << info.date << "\n"
     << "- Machine: " << info.machine << "\n"
     << "- Load average (1/5/15 min) at start: " << Load(info.loadStart) << "; at end: " << Load(info.loadEnd)
     << "\n"
     << "- Parallel capacity: " << all << " ran a CPU-bound loop " << Ratio(info.capacityStart) << " (start) and "
     << Ratio(info.capacityEnd) << " (end) as fast as 1 thread (" << Ratio(info.allThreads)
     << " on an idle machine); the " << all << " columns cannot do better\n"
     << "- Build: " << info.compiler << "\n"
     << "- Command: `" << info.command << "` (" << Format("%.0f", info.seconds) << " s)\n"
     << "- Peers found: ";
  for (std::size_t i = 0; i < info.peersFound.size(); ++i) md << (i ? ", " : "") << info.peersFound[i];
  if (info.peersFound.empty()) md << "none";
  md << "; missing: ";
  for (std::size_t i = 0; i < info.peersMissing.size(); ++i) md << (i ? ", " : "") << info.peersMissing[i];
  if (info.peersMissing.empty()) md << "none";
  md << "\n\n";

  md << "#### invmap\n\n"
     << "Points per second. Oracle ratio: the full engine's time over the time of solving each point only on "
        "the cell invmap reported, from the cell's center (1 thread).\n\n"
     << "| workload | cells | N | build s | 1 thread | " << all << " | speed-up | oracle ratio | "
     << "1 thread = " << all << " |\n"
     << "|---|---:|---:|---:|---:|---:|---:|---:|---|\n";
  for (const InvmapRow& r : invmapRows) {
    md << "| " << r.workload << " | " << r.cells << " | " << r.count << " | " << Seconds(r.buildSeconds) << " | "
       << HumanRate(r.count / r.seconds1) << " | " << HumanRate(r.count / r.secondsAll) << " | "
       << Ratio(r.seconds1 / r.secondsAll) << " | " << Ratio(r.seconds1 / r.oracleSeconds) << " | "
       << (r.threadMismatches == 0 ? "yes" : "no (" + std::to_string(r.threadMismatches) + ")") << " |\n";
  }

  md << "\n#### Peers\n\n"
     << "Ratio = invmap's points/s over the peer's, both from this run. Agreement on the peer's N points: "
        "*peer farther* = the peer's distance exceeds invmap's by more than 1e-9 x the geometry's size (a local "
        "minimum, a missed boundary), *invmap farther* = the reverse (invmap wrong), *max diff* = largest "
        "|distance difference|, *failed* = no answer from the peer, *over oracle* = the peer's time per point over "
        "invmap's oracle's (a solve on the known cell only, as in invmap's oracle ratio).\n\n"
     << "| workload | peer | N | set-up s | peer 1 thread | peer " << all << " | invmap/peer 1 thread | invmap/peer "
     << all << " | peer farther | invmap farther | max diff | failed | over oracle |\n"
     << "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const PeerRow& r : peerRows) {
    const double rate1 = r.count / r.seconds1;
    const bool threaded = r.secondsAll > 0;
    const double rateAll = threaded ? r.count / r.secondsAll : rate1;
    md << "| " << r.workload << " | " << r.peer << " | " << r.count << " | " << Seconds(r.setupSeconds) << " | "
       << HumanRate(rate1) << " | " << (threaded ? HumanRate(rateAll) : "1 thread only") << " | "
       << Ratio(r.invmapRate1 / rate1) << " | " << Ratio(r.invmapRateAll / rateAll) << (threaded ? "" : "*")
       << " | " << Share(r.agreement.peerFarther, r.count) << " | " << Share(r.agreement.invmapFarther, r.count)
       << " | " << Format("%.1e", r.agreement.maxDifference) << " | " << Share(r.agreement.peerFailed, r.count)
       << " | " << Ratio(PeerOverOracle(r, invmapRows)) << " |\n";
  }
  md << "\n\\* the peer runs on 1 thread only; the ratio compares invmap on " << all
     << " with the peer on 1 thread.\n\n";

  md << "Workloads:\n\n";
  for (const InvmapRow& r : invmapRows) {
    md << "- **" << r.workload << "**: " << r.description << "; size (box diagonal) " << Format("%.4g", r.size)
       << ", agreement tolerance " << Format("%.2g", 1e-9 * r.size) << ".\n";
  }
  if (!notes.empty()) {
    md << "\nNotes:\n\n";
    for (const std::string& note : notes) md << "- " << note << "\n";
  }
  return md.str();
}

bool WriteCsv(const std::string& path, const RunInfo& info, const std::vector<InvmapRow>& invmapRows,
              const std::vector<PeerRow>& peerRows) {
  std::ofstream out(path);
  if (!out) return false;
  out.precision(9);
  out << "date,capacity_start,capacity_end,workload,method,cells,size,points,setup_seconds,seconds_1_thread,points_per_second_1_thread,"
         "threads,seconds_all_threads,points_per_second_all_threads,invmap_over_peer_1_thread,"
         "invmap_over_peer_all_threads,peer_farther,invmap_farther,max_difference,peer_failed,"
         "thread_mismatches,oracle_ratio\n";
  // oracle_ratio: invmap's time per point over its oracle's; on a peer's
  // row, the peer's time per point over the same oracle's.
  for (const InvmapRow& r : invmapRows) {
    out << info.date << "," << info.capacityStart << "," << info.capacityEnd << "," << CsvField(r.workload) << ",invmap," << r.cells << "," << r.size << "," << r.count
        << "," << r.buildSeconds << "," << r.seconds1 << "," << r.count / r.seconds1 << "," << info.allThreads << ","
        << r.secondsAll << "," << r.count / r.secondsAll << ",,,,,,," << r.threadMismatches << ","
        << r.seconds1 / r.oracleSeconds << "\n";
  }
  for (const PeerRow& r : peerRows) {
    const double rate1 = r.count / r.seconds1;
    const bool threaded = r.secondsAll > 0;
    const double rateAll = threaded ? r.count / r.secondsAll : rate1;
    const InvmapRow* invmap = InvmapRowOf(invmapRows, r.workload);
    const std::int64_t cells = invmap ? invmap->cells : 0;
    const double size = invmap ? invmap->size : 0.0;
    out << info.date << "," << info.capacityStart << "," << info.capacityEnd << "," << CsvField(r.workload) << ","
        << CsvField(r.peer) << "," << cells << "," << size << ","
        << r.count << "," << r.setupSeconds << "," << r.seconds1 << "," << rate1 << "," << (threaded ? r.threads : 1)
        << "," << (threaded ? r.secondsAll : r.seconds1) << "," << rateAll << "," << r.invmapRate1 / rate1 << ","
        << r.invmapRateAll / rateAll << "," << r.agreement.peerFarther << "," << r.agreement.invmapFarther << ","
        << r.agreement.maxDifference << "," << r.agreement.peerFailed << "," << r.threadMismatches << ","
        << PeerOverOracle(r, invmapRows) << "\n";
  }
  return static_cast<bool>(out);
}

}  // namespace invmap::bench
