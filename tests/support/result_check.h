// Checks of invmap's per-point Results against an independent reference,
// with a readable report of the failures for the engine tests.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

// The support library is built without the engine's include path; this is
// the same public header that tests include as "invmap/invmap.h".
#include "invmap/invmap.h"
#include "tests/support/closest_reference.h"

namespace invmap::testing {

/// Query points with a label per point saying how each was made (for
/// diagnostics), `dim` interleaved coordinates per point.
struct QuerySet {
  int dim = 3;
  std::vector<double> points;
  std::vector<const char*> kinds;  ///< Static strings ("near", "far", ...).

  std::size_t size() const { return kinds.size(); }
  const double* point(std::size_t i) const { return points.data() + i * dim; }
  void Add(const double* p, const char* kind) {
    points.insert(points.end(), p, p + dim);
    kinds.push_back(kind);
  }
};

/// The reference's closest point for a query point (dim coordinates).
using ReferenceFn = std::function<ReferenceAnswer(const double* point)>;

/// Tolerances and options of CheckResults.
struct CheckOptions {
  /// Length tolerance relative to the geometry size (GeometrySize).
  double relTol = 1e-9;
  /// Parameter tolerance of EvaluateReported, relative to a cell's extent.
  double paramTol = 1e-9;
  /// The gap tolerance the batch ran with.
  double maxDistance = std::numeric_limits<double>::infinity();
  /// Failures described in the report (all are counted).
  int maxReports = 12;
};

/// Outcome of CheckResults. Every count is a number of points.
struct CheckSummary {
  std::int64_t points = 0;
  std::int64_t found = 0;
  std::int64_t failures = 0;   ///< Points failing any check.
  std::int64_t fartherThanReference = 0;  ///< invmap > reference + tol: a missed global minimum.
  std::int64_t closerThanReference = 0;   ///< invmap < reference - tol: the reference missed one.
  std::int64_t badEvaluation = 0;  ///< closest != patch(cell, params), or params invalid.
  std::int64_t badDistance = 0;    ///< distance != |closest - p|.
  std::int64_t badStatus = 0;      ///< Wrong status or not-found fields.
  double worstExcess = 0.0;        ///< max (invmap - reference) / size.
  double worstDeficit = 0.0;       ///< max (reference - invmap) / size.
  double meanCellsSolved = 0.0;    ///< Reference effort (diagnostics).
  std::string report;              ///< Counts and the first failures in detail.
};

/// Checks every point of `queries` (results from one Invert call on
/// `geometry`, same order):
/// - non-finite points must be Invalid with patch/cell -1 and NaN fields;
/// - a point the reference puts farther than maxDistance + tol must be None
///   (patch/cell -1, NaN params, closest and distance); one at most
///   maxDistance away must be Found; in between either;
/// - Found points: distance <= reference + tol (no local minimum) and
///   >= reference - tol (sanity of the reference); closest equals
///   EvaluateReported(patch, cell, params) within tol; | |closest - p| -
///   distance | <= tol; unused params NaN; closest's z is 0 in 2D.
/// tol = relTol * GeometrySize(geometry).
CheckSummary CheckResults(const Geometry& geometry, const QuerySet& queries, const Results& results,
                          const ReferenceFn& reference, const CheckOptions& options = {});

/// Bitwise comparison of two Results (every field, NaN payloads included);
/// "" when identical, else the first difference.
std::string CompareBitwise(const Results& a, const Results& b);

/// One point's answer as text (status, patch, cell, params, closest, distance).
std::string DescribeResult(const Results& results, std::size_t i);

/// Runs one interleaved float64 batch of `queries`; *error receives the
/// Error code and message when the call fails ("" on success). Inline: the
/// support library links no engine (the kernel tests use it too).
inline Results InvertQueries(const Manifold& manifold, const QuerySet& queries, const InversionOptions& options,
                             std::string* error) {
  Results results;
  std::string message;
  const Error e = manifold.Invert(PointsView::Interleaved(queries.points.data(), queries.size(), queries.dim), options,
                                  &results, &message);
  if (error) *error = e == Error::Ok ? "" : "error " + std::to_string(static_cast<int>(e)) + ": " + message;
  return results;
}

/// Wall-clock seconds since an arbitrary origin (for the tests' timing logs).
double Seconds();
/// CPU seconds of the whole process (all threads) since it started: the
/// tests log it beside wall time because the machine may be shared.
double CpuSeconds();

}  // namespace invmap::testing
