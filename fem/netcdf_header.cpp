#include "fem/netcdf_header.h"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string>
#include <fstream>
#include <vector>

namespace invmap::fem {
namespace {

/// Big-endian reads over the header, each checked against the file's end.
class HeaderReader {
 public:
  HeaderReader(const std::vector<char>& bytes, bool wide) : bytes_(bytes), wide_(wide) {}

  /// A count: 4 bytes, 8 in CDF-5. False past the end.
  bool Count(std::uint64_t* value) { return Unsigned(wide_ ? 8 : 4, value); }
  bool Unsigned(int size, std::uint64_t* value) {
    if (position_ + static_cast<std::uint64_t>(size) > bytes_.size()) return false;
    *value = 0;
    for (int k = 0; k < size; ++k) *value = (*value << 8) | static_cast<unsigned char>(bytes_[position_ + k]);
    position_ += static_cast<std::uint64_t>(size);
    return true;
  }
  /// Skips `count` bytes padded to 4. False when they are not all in the file.
  bool Skip(std::uint64_t count) {
    const std::uint64_t padded = count + (4 - count % 4) % 4;
    if (count > bytes_.size() || padded > bytes_.size() - position_) return false;
    position_ += padded;
    return true;
  }
  bool Name() {
    std::uint64_t length = 0;
    return Count(&length) && Skip(length);
  }

 private:
  const std::vector<char>& bytes_;
  bool wide_;
  std::uint64_t position_ = 4;  // after the magic number
};

/// Bytes of one value of a netCDF type; 0 for an unknown type.
std::uint64_t TypeSize(std::uint64_t type) {
  switch (type) {
    case 1: case 2: case 7: return 1;   // byte, char, ubyte
    case 3: case 8: return 2;           // short, ushort
    case 4: case 5: case 9: return 4;   // int, float, uint
    case 6: case 10: case 11: return 8; // double, int64, uint64
    default: return 0;
  }
}

/// An attribute list (after its tag): names, types and values in the file.
bool Attributes(HeaderReader& r, std::uint64_t count, std::string* problem) {
  for (std::uint64_t a = 0; a < count; ++a) {
    std::uint64_t type = 0, elements = 0;
    if (!r.Name() || !r.Unsigned(4, &type) || !r.Count(&elements) || TypeSize(type) == 0 ||
        elements > (std::uint64_t{1} << 40) || !r.Skip(elements * TypeSize(type))) {
      *problem = "attribute " + std::to_string(a) + " does not fit in the file";
      return false;
    }
  }
  return true;
}

/// A list's tag and count: tag 0 with count 0 is an absent list.
bool ListHeader(HeaderReader& r, std::uint64_t expectedTag, std::uint64_t* count) {
  std::uint64_t tag = 0;
  if (!r.Unsigned(4, &tag) || !r.Count(count)) return false;
  return tag == expectedTag || (tag == 0 && *count == 0);
}

/// Where a variable's values lie: from `begin`, `bytes` of them (a record
/// variable: `bytes` per record, the records `recordSize` apart).
struct VariableExtent {
  std::uint64_t begin = 0;
  std::uint64_t bytes = 1;
  bool perRecord = false;
};

/// What is wrong when the values of a variable reach past the file's end (a
/// file cut short: the netCDF library reads what is missing as zeros), else
/// an empty string. Records are as the format lays them out: one after the
/// other, each holding every record variable padded to 4 bytes, unpadded
/// when there is a single record variable.
std::string CheckDataExtents(const std::vector<VariableExtent>& extents, std::uint64_t records,
                             std::uint64_t fileSize) {
  const auto padded = [](std::uint64_t n) { return n + (4 - n % 4) % 4; };
  std::uint64_t recordSize = 0, recordVariables = 0;
  for (const VariableExtent& extent : extents) {
    if (!extent.perRecord) continue;
    recordSize += padded(extent.bytes);
    ++recordVariables;
  }
  if (recordVariables == 1) {
    for (const VariableExtent& extent : extents) {
      if (extent.perRecord) recordSize = extent.bytes;
    }
  }
  // A streamed file's record count is left indeterminate (all ones).
  const bool recordsKnown = records != 0xFFFFFFFFu && records != ~std::uint64_t{0};
  for (std::size_t v = 0; v < extents.size(); ++v) {
    const VariableExtent& extent = extents[v];
    // 128 bits: a hostile header's counts must not wrap around.
    unsigned __int128 end = static_cast<unsigned __int128>(extent.begin) + extent.bytes;
    if (extent.perRecord) {
      if (!recordsKnown || records == 0) continue;
      end += static_cast<unsigned __int128>(records - 1) * recordSize;
    }
    if (end > fileSize) {
      const std::string at = end >> 64 ? std::string("beyond 2^64") : "at byte " + std::to_string(static_cast<std::uint64_t>(end));
      return "the file is cut short: netCDF variable " + std::to_string(v) + " ends " + at + ", the file has " +
             std::to_string(fileSize) + " bytes";
    }
  }
  return {};
}

}  // namespace

std::string CheckNetcdfHeader(const std::string& path) {
  // The header is read from the file's first bytes only: it holds names and
  // attributes (kilobytes), where reading the whole file took gigabytes of
  // memory for a large model (and never ended on /dev/zero).
  constexpr std::size_t kMaxHeaderBytes = std::size_t{64} << 20;
  std::ifstream in(path, std::ios::binary);
  std::vector<char> bytes;
  char chunk[1 << 16];
  while (bytes.size() < kMaxHeaderBytes &&
         (in.read(chunk, static_cast<std::streamsize>(std::min(sizeof chunk, kMaxHeaderBytes - bytes.size()))) ||
          in.gcount() > 0)) {
    bytes.insert(bytes.end(), chunk, chunk + in.gcount());
  }
  static const char kHdf5[8] = {'\x89', 'H', 'D', 'F', '\r', '\n', '\x1a', '\n'};
  if (bytes.size() >= 8 && std::equal(kHdf5, kHdf5 + 8, bytes.begin())) return {};  // netCDF-4: the library checks it
  if (bytes.size() < 4 || bytes[0] != 'C' || bytes[1] != 'D' || bytes[2] != 'F') {
    return "neither a netCDF (CDF) nor an HDF5 signature at its start";
  }
  const int version = bytes[3];
  if (version != 1 && version != 2 && version != 5) return "unknown netCDF version " + std::to_string(version);
  HeaderReader r(bytes, version == 5);
  std::uint64_t records = 0, count = 0;
  if (!r.Count(&records)) return "the netCDF header is truncated";
  if (!ListHeader(r, 0x0A, &count)) return "the netCDF dimension list is malformed";
  std::vector<std::uint64_t> dimensionLengths;  // 0: the record dimension
  for (std::uint64_t d = 0; d < count; ++d) {
    std::uint64_t length = 0;
    if (!r.Name() || !r.Count(&length)) return "netCDF dimension " + std::to_string(d) + " does not fit in the file";
    dimensionLengths.push_back(length);
  }
  std::string problem;
  if (!ListHeader(r, 0x0C, &count)) return "the netCDF global attribute list is malformed";
  if (!Attributes(r, count, &problem)) return "netCDF global " + problem;
  if (!ListHeader(r, 0x0B, &count)) return "the netCDF variable list is malformed";
  std::vector<VariableExtent> extents;
  for (std::uint64_t v = 0; v < count; ++v) {
    std::uint64_t dims = 0, attributes = 0, type = 0, size = 0, begin = 0;
    if (!r.Name() || !r.Count(&dims) || dims > bytes.size()) return "netCDF variable " + std::to_string(v) + " does not fit in the file";
    VariableExtent extent;
    for (std::uint64_t k = 0; k < dims; ++k) {
      std::uint64_t id = 0;
      if (!r.Count(&id)) return "netCDF variable " + std::to_string(v) + " does not fit in the file";
      if (id >= dimensionLengths.size()) return "netCDF variable " + std::to_string(v) + ": no dimension " + std::to_string(id);
      const std::uint64_t length = dimensionLengths[id];
      if (k == 0 && length == 0) {
        extent.perRecord = true;
      } else if (length != 0 && extent.bytes > (std::uint64_t{1} << 62) / length) {
        return "netCDF variable " + std::to_string(v) + " is larger than any file";
      } else {
        extent.bytes *= length;
      }
    }
    if (!ListHeader(r, 0x0C, &attributes)) return "netCDF variable " + std::to_string(v) + ": malformed attribute list";
    if (!Attributes(r, attributes, &problem)) return "netCDF variable " + std::to_string(v) + ": " + problem;
    if (!r.Unsigned(4, &type) || !r.Count(&size) || !r.Unsigned(version == 1 ? 4 : 8, &begin)) {
      return "netCDF variable " + std::to_string(v) + " does not fit in the file";
    }
    extent.bytes *= TypeSize(type);
    extent.begin = begin;
    extents.push_back(extent);
  }
  std::error_code error;
  const std::uint64_t fileSize = std::filesystem::file_size(path, error);
  if (error) return {};
  return CheckDataExtents(extents, records, fileSize);
}

}  // namespace invmap::fem
