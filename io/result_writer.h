// Streaming output of inversion results (docs/formats.md section 5) as CSV, PLY
// or npy, chosen by the output's extension. Rows are appended chunk by
// chunk in input order; counts that a header needs are patched in place at
// the end, and the file appears under its name only once complete.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "invmap/invmap.h"
#include "io/file_io.h"

namespace invmap::io {

/// Options of OpenResultWriter.
struct ResultWriteOptions {
  /// PLY only: add uchar properties red, green, blue that colour each found
  /// point by its distance with the viridis colormap (dark purple at
  /// colorMin, yellow at colorMax, clamped outside); points not found or
  /// invalid are grey (128, 128, 128).
  bool colorByDistance = false;
  /// Distance shown as the first colour. NaN (default): the smallest
  /// distance of the found points. A NaN end is found by a second pass over
  /// the temporary output at Finish (streaming cannot know it earlier),
  /// which rereads and rewrites the colours of every row.
  double colorMin = std::numeric_limits<double>::quiet_NaN();
  /// Distance shown as the last colour. NaN (default): the largest distance
  /// of the found points (second pass as for colorMin). The CLI can pass
  /// --max-distance here to keep one pass.
  double colorMax = std::numeric_limits<double>::quiet_NaN();
  /// Columns after the standard ones (`invmap probe`'s field components):
  /// CSV columns after `distance`, PLY double properties after all others,
  /// npy columns 11, 12, ... Their values come with each chunk (WriteChunk's
  /// `extra`); NaN is an empty CSV field. A name with a comma or a quote is
  /// quoted in the CSV header; white space becomes '_' in PLY names.
  std::vector<std::string> extraColumns;
  /// With colorByDistance: colour by this extra column instead, a signed
  /// distance (CAD solids' `signed_distance`, negative inside), on a
  /// diverging blue-white-red map centred on 0 (white) over [-m, m]: m the
  /// largest |value| found, or colorMax when given. -1: the distance.
  int signedColorColumn = -1;
};

/// Writes result rows to one file. Not thread-safe.
///
/// Formats, by extension (case-insensitive):
///  - .csv: the header `index,status,patch,cell,u,v,w,x,y,z,distance`, then
///    one line per point, "\n"-terminated. status is found/none/invalid;
///    numbers are %.17g. A found row has its patch and cell, the parameters
///    (empty where unused, i.e. NaN), the closest point (z empty in 2D) and
///    the distance. A row that is not found (none or invalid) has patch
///    and cell -1 and all of u..distance empty.
///  - .ply: binary_little_endian; element vertex with the query point as
///    double x, y, z (z = 0 in 2D), uchar status (0 found, 1 none,
///    2 invalid), int patch, int cell, double u, v, w, cx, cy, cz (cz = 0
///    in 2D), distance, and with colorByDistance uchar red, green, blue and
///    a header comment giving the distance range of the colours. Rows not
///    found have patch and cell -1 and NaN in u..distance; unused
///    parameters are NaN.
///  - .npy: float64 (little endian) array of shape (N, 11) in the CSV
///    column order, status 0/1/2, NaN where the CSV is empty.
class ResultWriter {
 public:
  virtual ~ResultWriter() = default;

  /// Appends the rows of `count` points. `points`: the query points,
  /// count * dim values point-major (used by PLY only; may be null for CSV
  /// and npy). `results`: the results of exactly these points (at least
  /// `count` entries per field, params and closest 3 per point).
  /// `firstIndex`: the input index of the first point; it must equal the
  /// number of rows written so far (rows are in input order), else
  /// std::invalid_argument. `extra`: the values of the extra columns,
  /// count * extraColumns.size() values point-major (null when there are
  /// none). Throws InputError of kind Output when the file cannot be written.
  void WriteChunk(const double* points, std::size_t count, const Results& results, std::int64_t firstIndex,
                  const double* extra = nullptr);

  /// Completes the file (header counts, colours) and renames it onto the
  /// output path. Without a successful Finish the output path is left as
  /// it was and the temporary file is deleted with the writer.
  void Finish();

  /// Rows written so far.
  std::int64_t rows() const { return rows_; }

 protected:
  /// Creates the temporary output for `path`.
  ResultWriter(const std::string& path, int dim, std::size_t extraColumns)
      : out_(path), dim_(dim), extraColumns_(extraColumns) {}

  /// Appends rows for points [0, count) of the chunk; row i has index
  /// rows_ + i; `extra` as in WriteChunk.
  virtual void WriteRows(const double* points, std::size_t count, const Results& results, const double* extra) = 0;
  /// Patches what the header needs once all rows are written.
  virtual void Complete() = 0;

  AtomicOutput out_;       ///< The output, renamed into place by Finish.
  int dim_;                ///< Dimension of the query points, 2 or 3.
  std::size_t extraColumns_;  ///< ResultWriteOptions::extraColumns.size().
  std::int64_t rows_ = 0;  ///< Rows written so far.

 private:
  bool finished_ = false;  ///< Set by a successful Finish.
};

/// True when OpenResultWriter writes files named like `path` (.csv, .ply,
/// .npy, case-insensitive).
bool IsResultFileName(const std::string& path);

/// Opens a result file for points of dimension `dim` (2 or 3), choosing the
/// format by extension (.csv, .ply, .npy). Throws InputError of kind Output
/// for another extension or when the file cannot be created.
std::unique_ptr<ResultWriter> OpenResultWriter(const std::string& path, int dim,
                                               const ResultWriteOptions& options = {});

/// Colour of t in [0, 1] (clamped; NaN gives grey 128, 128, 128) on
/// matplotlib's viridis colormap (CC0, van der Walt, Smith and Firing),
/// sampled at 256 levels: rgb[0..3).
void ViridisColor(double t, unsigned char rgb[3]);

/// Colour of t in [0, 1] (clamped; NaN gives grey) on a diverging
/// blue-white-red map (Moreland's cool-warm): blue at 0, a light grey at
/// 1/2, red at 1. Signed distances use it centred on 0.
void DivergingColor(double t, unsigned char rgb[3]);

}  // namespace invmap::io
