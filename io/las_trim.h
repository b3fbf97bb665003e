// The LAS part of `invmap trim`: a valid LAS file of the kept records,
// byte for byte, with the header's counts and bounds rewritten.
#pragma once

#include <cstddef>
#include <cstdint>

#include "io/file_io.h"
#include "io/las_format.h"

namespace invmap::io {

/// Writes a LAS file of the kept records of the LAS input `layout`
/// describes. The output keeps the input's header, variable length records
/// and any bytes up to the first point record, then the kept records, then
/// everything after the input's point records (extended variable length
/// records, waveform data) verbatim. At the end the header gets the kept
/// count (legacy and 1.4 fields), the counts by return number and the
/// bounds of the kept points, and the offsets of the waveform data and the
/// first extended record move with the bytes they point to. The legacy
/// fields of a 1.4 file are kept in step only when the input filled them
/// (else they stay zero); with no point kept the bounds are all zero.
class LasTrimWriter {
 public:
  /// Copies the input's bytes before its first point record to `out`.
  /// Throws InputError naming the input when it cannot be read.
  LasTrimWriter(const LasLayout& layout, AtomicOutput* out);

  /// Counts `count` consecutive kept records at `records` (which the caller
  /// writes to the output itself): their return numbers and bounds.
  void Tally(const char* records, std::size_t count);

  /// Copies the input's bytes after its point records and rewrites the
  /// header's counts, bounds and offsets in `out`.
  void Finish(AtomicOutput* out);

 private:
  LasLayout layout_;
  std::uint64_t kept_ = 0;
  /// Kept records by return number 1 to 15 (index 0 is return 1); return
  /// number 0, which LAS does not allow, is counted nowhere.
  std::uint64_t byReturn_[las::kExtendedReturns] = {};
  std::int32_t min_[3] = {0, 0, 0};  ///< Smallest X, Y, Z record values kept.
  std::int32_t max_[3] = {0, 0, 0};  ///< Largest X, Y, Z record values kept.
};

}  // namespace invmap::io
