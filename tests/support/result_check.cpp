#include "tests/support/result_check.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <ctime>
#include <sstream>

namespace invmap::testing {
namespace {

const char* StatusName(Status s) {
  switch (s) {
    case Status::Found:
      return "found";
    case Status::None:
      return "none";
    case Status::Invalid:
      return "invalid";
  }
  return "?";
}

/// True when the not-found fields hold their documented values.
bool NotFoundFieldsOk(const Results& r, std::size_t i) {
  bool ok = r.patch[i] == -1 && r.cell[i] == -1 && std::isnan(r.distance[i]);
  for (int k = 0; k < 3; ++k) ok = ok && std::isnan(r.params[3 * i + k]) && std::isnan(r.closest[3 * i + k]);
  return ok;
}

template <typename T>
bool SameBits(const std::vector<T>& a, const std::vector<T>& b, std::size_t* at) {
  if (a.size() != b.size()) {
    *at = std::min(a.size(), b.size());
    return false;
  }
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::memcmp(&a[i], &b[i], sizeof(T)) != 0) {
      *at = i;
      return false;
    }
  }
  return true;
}

}  // namespace

std::string DescribeResult(const Results& r, std::size_t i) {
  std::ostringstream os;
  os.precision(17);
  os << StatusName(r.status[i]) << " patch " << r.patch[i] << " cell " << r.cell[i] << " params (" << r.params[3 * i]
     << ", " << r.params[3 * i + 1] << ", " << r.params[3 * i + 2] << ") closest (" << r.closest[3 * i] << ", "
     << r.closest[3 * i + 1] << ", " << r.closest[3 * i + 2] << ") distance " << r.distance[i] << " iterations "
     << r.iterations[i];
  return os.str();
}

CheckSummary CheckResults(const Geometry& geometry, const QuerySet& queries, const Results& results,
                          const ReferenceFn& reference, const CheckOptions& options) {
  CheckSummary s;
  const int dim = geometry.dimension;
  const double size = GeometrySize(geometry);
  const double tol = options.relTol * size;
  const std::size_t n = queries.size();
  s.points = static_cast<std::int64_t>(n);
  std::ostringstream details;
  details.precision(17);
  int reported = 0;
  double cellsSolved = 0.0;
  if (results.status.size() != n || results.distance.size() != n || results.closest.size() != 3 * n ||
      results.params.size() != 3 * n || results.patch.size() != n || results.cell.size() != n) {
    s.failures = static_cast<std::int64_t>(n);
    s.report = "results have the wrong length";
    return s;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double* p = queries.point(i);
    bool finite = true;
    for (int k = 0; k < dim; ++k) finite = finite && std::isfinite(p[k]);
    std::string problem;
    ReferenceAnswer ref;
    if (!finite) {
      if (results.status[i] != Status::Invalid || !NotFoundFieldsOk(results, i)) {
        ++s.badStatus;
        problem = "a non-finite point must be invalid with patch/cell -1 and NaN fields";
      }
    } else {
      ref = reference(p);
      cellsSolved += ref.cellsSolved;
      const Status st = results.status[i];
      if (st == Status::Found) {
        ++s.found;
        const double d = results.distance[i];
        const double* c = &results.closest[3 * i];
        if (!(d <= ref.distance + tol)) {
          ++s.fartherThanReference;
          problem += "farther than the reference (a local minimum); ";
        }
        if (!(d >= ref.distance - tol)) {
          ++s.closerThanReference;
          problem += "closer than the reference (the reference missed it); ";
        }
        if (std::isfinite(d) && std::isfinite(ref.distance)) {
          s.worstExcess = std::max(s.worstExcess, (d - ref.distance) / size);
          s.worstDeficit = std::max(s.worstDeficit, (ref.distance - d) / size);
        }
        if (!(d <= options.maxDistance + tol)) {
          ++s.badStatus;
          problem += "found beyond maxDistance; ";
        }
        double x[3];
        const std::string why = EvaluateReported(geometry, results.patch[i], results.cell[i], &results.params[3 * i],
                                                 options.paramTol, x);
        double evalError = 0.0, d2 = 0.0;
        for (int k = 0; k < dim; ++k) {
          evalError = std::max(evalError, std::fabs(x[k] - c[k]));
          d2 += (c[k] - p[k]) * (c[k] - p[k]);
        }
        if (!why.empty() || !(evalError <= tol) || (dim == 2 && c[2] != 0.0)) {
          ++s.badEvaluation;
          problem += why.empty() ? "closest point is not the patch at (cell, params)" : why;
          if (why.empty()) {
            std::ostringstream e;
            e.precision(17);
            e << " (evaluated (" << x[0] << ", " << x[1] << ", " << x[2] << "), error " << evalError << ")";
            problem += e.str();
          }
          problem += "; ";
        }
        if (!(std::fabs(std::sqrt(d2) - d) <= tol)) {
          ++s.badDistance;
          problem += "distance != |closest - p|; ";
        }
      } else if (st == Status::None) {
        // A point at distance <= maxDistance is always found (no tolerance:
        // the reference's distance is that of a point of the geometry, so
        // the true one is at most that). An infinite reference distance
        // means the geometry has no cell.
        if (!(std::isinf(ref.distance) || ref.distance > options.maxDistance) || !NotFoundFieldsOk(results, i)) {
          ++s.badStatus;
          problem = "status none, but the reference is within maxDistance (or fields not NaN/-1)";
        }
      } else {
        ++s.badStatus;
        problem = "status invalid for a finite point";
      }
    }
    if (problem.empty()) continue;
    ++s.failures;
    if (reported++ >= options.maxReports) continue;
    details << "point " << i << " (" << queries.kinds[i] << ") p = (";
    for (int k = 0; k < dim; ++k) details << (k ? ", " : "") << p[k];
    details << "): " << problem << "\n    invmap:    " << DescribeResult(results, i) << "\n    reference: distance "
            << ref.distance << " patch " << ref.patch << " cell " << ref.cell << " params (" << ref.params[0] << ", "
            << ref.params[1] << ", " << ref.params[2] << ") x (" << ref.x[0] << ", " << ref.x[1] << ", " << ref.x[2]
            << ")";
    if (ref.patch >= 0) {
      // Re-evaluate the reference's own answer, so a report of a missed
      // minimum carries its proof (the closer point is on the geometry).
      double y[3];
      const std::string why = EvaluateReported(geometry, ref.patch, ref.cell, ref.params.data(), options.paramTol, y);
      double e = 0.0;
      for (int k = 0; k < dim; ++k) e = std::max(e, std::fabs(y[k] - ref.x[k]));
      details << (why.empty() ? " (re-evaluated: error " + std::to_string(e) + ")" : " (re-evaluation: " + why + ")");
    }
    details << "\n";
  }
  s.meanCellsSolved = n ? cellsSolved / static_cast<double>(n) : 0.0;
  std::ostringstream os;
  os << s.failures << " of " << n << " points fail (found " << s.found << "; farther than reference "
     << s.fartherThanReference << ", closer than reference " << s.closerThanReference << ", bad evaluation "
     << s.badEvaluation << ", bad distance " << s.badDistance << ", bad status " << s.badStatus
     << "); worst excess " << s.worstExcess << ", worst deficit " << s.worstDeficit << " (x size " << size
     << "); reference solved " << s.meanCellsSolved << " cells per point\n"
     << details.str();
  s.report = os.str();
  return s;
}

std::string CompareBitwise(const Results& a, const Results& b) {
  std::size_t at = 0;
  if (!SameBits(a.status, b.status, &at)) return "status differs at point " + std::to_string(at);
  if (!SameBits(a.patch, b.patch, &at)) return "patch differs at point " + std::to_string(at);
  if (!SameBits(a.cell, b.cell, &at)) return "cell differs at point " + std::to_string(at);
  if (!SameBits(a.params, b.params, &at)) return "params differ at point " + std::to_string(at / 3);
  if (!SameBits(a.closest, b.closest, &at)) return "closest differs at point " + std::to_string(at / 3);
  if (!SameBits(a.distance, b.distance, &at)) return "distance differs at point " + std::to_string(at);
  if (!SameBits(a.iterations, b.iterations, &at)) return "iterations differ at point " + std::to_string(at);
  return "";
}

double Seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double CpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace invmap::testing
