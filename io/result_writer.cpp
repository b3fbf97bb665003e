#include "io/result_writer.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "io/input_error.h"
#include "io/npy.h"
#include "io/ply.h"

namespace invmap::io {
namespace {

/// matplotlib's viridis at 256 levels, as 8-bit sRGB (rounded from the
/// published floating-point table).
constexpr unsigned char kViridis[256][3] = {
    {68, 1, 84},    {68, 2, 86},    {69, 4, 87},    {69, 5, 89},    {70, 7, 90},    {70, 8, 92},    {70, 10, 93},
    {70, 11, 94},   {71, 13, 96},   {71, 14, 97},   {71, 16, 99},   {71, 17, 100},  {71, 19, 101},  {72, 20, 103},
    {72, 22, 104},  {72, 23, 105},  {72, 24, 106},  {72, 26, 108},  {72, 27, 109},  {72, 28, 110},  {72, 29, 111},
    {72, 31, 112},  {72, 32, 113},  {72, 33, 115},  {72, 35, 116},  {72, 36, 117},  {72, 37, 118},  {72, 38, 119},
    {72, 40, 120},  {72, 41, 121},  {71, 42, 122},  {71, 44, 122},  {71, 45, 123},  {71, 46, 124},  {71, 47, 125},
    {70, 48, 126},  {70, 50, 126},  {70, 51, 127},  {70, 52, 128},  {69, 53, 129},  {69, 55, 129},  {69, 56, 130},
    {68, 57, 131},  {68, 58, 131},  {68, 59, 132},  {67, 61, 132},  {67, 62, 133},  {66, 63, 133},  {66, 64, 134},
    {66, 65, 134},  {65, 66, 135},  {65, 68, 135},  {64, 69, 136},  {64, 70, 136},  {63, 71, 136},  {63, 72, 137},
    {62, 73, 137},  {62, 74, 137},  {62, 76, 138},  {61, 77, 138},  {61, 78, 138},  {60, 79, 138},  {60, 80, 139},
    {59, 81, 139},  {59, 82, 139},  {58, 83, 139},  {58, 84, 140},  {57, 85, 140},  {57, 86, 140},  {56, 88, 140},
    {56, 89, 140},  {55, 90, 140},  {55, 91, 141},  {54, 92, 141},  {54, 93, 141},  {53, 94, 141},  {53, 95, 141},
    {52, 96, 141},  {52, 97, 141},  {51, 98, 141},  {51, 99, 141},  {50, 100, 142}, {50, 101, 142}, {49, 102, 142},
    {49, 103, 142}, {49, 104, 142}, {48, 105, 142}, {48, 106, 142}, {47, 107, 142}, {47, 108, 142}, {46, 109, 142},
    {46, 110, 142}, {46, 111, 142}, {45, 112, 142}, {45, 113, 142}, {44, 113, 142}, {44, 114, 142}, {44, 115, 142},
    {43, 116, 142}, {43, 117, 142}, {42, 118, 142}, {42, 119, 142}, {42, 120, 142}, {41, 121, 142}, {41, 122, 142},
    {41, 123, 142}, {40, 124, 142}, {40, 125, 142}, {39, 126, 142}, {39, 127, 142}, {39, 128, 142}, {38, 129, 142},
    {38, 130, 142}, {38, 130, 142}, {37, 131, 142}, {37, 132, 142}, {37, 133, 142}, {36, 134, 142}, {36, 135, 142},
    {35, 136, 142}, {35, 137, 142}, {35, 138, 141}, {34, 139, 141}, {34, 140, 141}, {34, 141, 141}, {33, 142, 141},
    {33, 143, 141}, {33, 144, 141}, {33, 145, 140}, {32, 146, 140}, {32, 146, 140}, {32, 147, 140}, {31, 148, 140},
    {31, 149, 139}, {31, 150, 139}, {31, 151, 139}, {31, 152, 139}, {31, 153, 138}, {31, 154, 138}, {30, 155, 138},
    {30, 156, 137}, {30, 157, 137}, {31, 158, 137}, {31, 159, 136}, {31, 160, 136}, {31, 161, 136}, {31, 161, 135},
    {31, 162, 135}, {32, 163, 134}, {32, 164, 134}, {33, 165, 133}, {33, 166, 133}, {34, 167, 133}, {34, 168, 132},
    {35, 169, 131}, {36, 170, 131}, {37, 171, 130}, {37, 172, 130}, {38, 173, 129}, {39, 173, 129}, {40, 174, 128},
    {41, 175, 127}, {42, 176, 127}, {44, 177, 126}, {45, 178, 125}, {46, 179, 124}, {47, 180, 124}, {49, 181, 123},
    {50, 182, 122}, {52, 182, 121}, {53, 183, 121}, {55, 184, 120}, {56, 185, 119}, {58, 186, 118}, {59, 187, 117},
    {61, 188, 116}, {63, 188, 115}, {64, 189, 114}, {66, 190, 113}, {68, 191, 112}, {70, 192, 111}, {72, 193, 110},
    {74, 193, 109}, {76, 194, 108}, {78, 195, 107}, {80, 196, 106}, {82, 197, 105}, {84, 197, 104}, {86, 198, 103},
    {88, 199, 101}, {90, 200, 100}, {92, 200, 99},  {94, 201, 98},  {96, 202, 96},  {99, 203, 95},  {101, 203, 94},
    {103, 204, 92}, {105, 205, 91}, {108, 205, 90}, {110, 206, 88}, {112, 207, 87}, {115, 208, 86}, {117, 208, 84},
    {119, 209, 83}, {122, 209, 81}, {124, 210, 80}, {127, 211, 78}, {129, 211, 77}, {132, 212, 75}, {134, 213, 73},
    {137, 213, 72}, {139, 214, 70}, {142, 214, 69}, {144, 215, 67}, {147, 215, 65}, {149, 216, 64}, {152, 216, 62},
    {155, 217, 60}, {157, 217, 59}, {160, 218, 57}, {162, 218, 55}, {165, 219, 54}, {168, 219, 52}, {170, 220, 50},
    {173, 220, 48}, {176, 221, 47}, {178, 221, 45}, {181, 222, 43}, {184, 222, 41}, {186, 222, 40}, {189, 223, 38},
    {192, 223, 37}, {194, 223, 35}, {197, 224, 33}, {200, 224, 32}, {202, 225, 31}, {205, 225, 29}, {208, 225, 28},
    {210, 226, 27}, {213, 226, 26}, {216, 226, 25}, {218, 227, 25}, {221, 227, 24}, {223, 227, 24}, {226, 228, 24},
    {229, 228, 25}, {231, 228, 25}, {234, 229, 26}, {236, 229, 27}, {239, 229, 28}, {241, 229, 29}, {244, 230, 30},
    {246, 230, 32}, {248, 230, 33}, {251, 231, 35}, {253, 231, 37},
};

/// Grey of rows that have no distance to colour.
constexpr unsigned char kNoColor = 128;

/// Moreland's cool-warm diverging map at 9 levels (8-bit sRGB), from blue
/// through a light grey to red.
constexpr unsigned char kCoolWarm[9][3] = {{59, 76, 192},   {98, 130, 234},  {141, 176, 254},
                                           {184, 208, 249}, {221, 221, 221}, {245, 196, 173},
                                           {244, 154, 123}, {222, 96, 77},   {180, 4, 38}};

/// Value of the fields that are empty in CSV.
constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

/// Bytes a CSV row can take: 11 fields and the extra ones, each at most 24
/// characters and a separator.
constexpr std::size_t MaxCsvRow(std::size_t extraColumns) { return (11 + extraColumns) * 25 + 1; }

/// A CSV header field: quoted (quotes doubled) when it holds a separator,
/// a quote or a line break.
std::string CsvName(const std::string& name) {
  if (name.find_first_of(",\"\r\n") == std::string::npos) return name;
  std::string quoted = "\"";
  for (const char c : name) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

/// A PLY property name: one token.
std::string PlyName(const std::string& name) {
  std::string token = name.empty() ? std::string("_") : name;
  for (char& c : token) {
    if (c == ' ' || c == '\t' || c == '\r' || c == '\n') c = '_';
  }
  return token;
}

/// Writes `value` as %.17g (to_chars with precision 17 in general format is
/// specified to match printf, and is much faster) and returns the end.
char* WriteDouble(char* p, double value) { return std::to_chars(p, p + 32, value, std::chars_format::general, 17).ptr; }

/// Writes `value` unless it is NaN (an empty CSV field), then the separator.
char* WriteField(char* p, double value, char separator) {
  if (!std::isnan(value)) p = WriteDouble(p, value);
  *p++ = separator;
  return p;
}

/// Writes `value` in decimal and returns the end.
char* WriteInteger(char* p, std::int64_t value) { return std::to_chars(p, p + 24, value).ptr; }

/// The CSV status words, indexed by Status.
const char* const kStatusWords[] = {"found", "none", "invalid"};

/// The .csv layout (ResultWriter).
class CsvResultWriter : public ResultWriter {
 public:
  /// Creates the file and writes the header line.
  CsvResultWriter(const std::string& path, int dim, const std::vector<std::string>& extraColumns)
      : ResultWriter(path, dim, extraColumns.size()) {
    std::string header = "index,status,patch,cell,u,v,w,x,y,z,distance";
    for (const std::string& name : extraColumns) header += "," + CsvName(name);
    out_.Write(header + "\n");
  }

 private:
  /// See ResultWriter::WriteRows.
  void WriteRows(const double*, std::size_t count, const Results& results, const double* extra) override {
    for (std::size_t i = 0; i < count; ++i) {
      char* const start = out_.Reserve(MaxCsvRow(extraColumns_));
      char* p = WriteInteger(start, rows_ + static_cast<std::int64_t>(i));
      *p++ = ',';
      const Status status = results.status[i];
      const char* word = kStatusWords[static_cast<int>(status)];
      const std::size_t length = std::strlen(word);
      std::memcpy(p, word, length);
      p += length;
      if (status != Status::Found) {
        std::memcpy(p, ",-1,-1,,,,,,,", 13);
        p += 13;
        std::memset(p, ',', extraColumns_);
        p += extraColumns_;
        *p++ = '\n';
        out_.Advance(static_cast<std::size_t>(p - start));
        continue;
      }
      *p++ = ',';
      p = WriteInteger(p, results.patch[i]);
      *p++ = ',';
      p = WriteInteger(p, results.cell[i]);
      *p++ = ',';
      for (int k = 0; k < 3; ++k) p = WriteField(p, results.params[3 * i + k], ',');
      p = WriteField(p, results.closest[3 * i], ',');
      p = WriteField(p, results.closest[3 * i + 1], ',');
      p = WriteField(p, dim_ == 3 ? results.closest[3 * i + 2] : kNan, ',');
      p = WriteField(p, results.distance[i], extraColumns_ > 0 ? ',' : '\n');
      for (std::size_t k = 0; k < extraColumns_; ++k) {
        p = WriteField(p, extra[i * extraColumns_ + k], k + 1 < extraColumns_ ? ',' : '\n');
      }
      out_.Advance(static_cast<std::size_t>(p - start));
    }
  }

  /// Nothing to patch: CSV has no counts.
  void Complete() override {}
};

/// The .ply layout (ResultWriter), optionally coloured.
class PlyResultWriter : public ResultWriter {
 public:
  /// Creates the file and writes the header with a zero count.
  PlyResultWriter(const std::string& path, int dim, const ResultWriteOptions& options)
      : ResultWriter(path, dim, options.extraColumns.size()), options_(options) {
    recordBytes_ = 3 * 8 + 1 + 2 * 4 + 7 * 8 + (options_.colorByDistance ? 3 : 0) + 8 * extraColumns_;
    signed_ = options_.signedColorColumn >= 0 && static_cast<std::size_t>(options_.signedColorColumn) < extraColumns_;
    twoPass_ = options_.colorByDistance &&
               (signed_ ? std::isnan(options_.colorMax) : std::isnan(options_.colorMin) || std::isnan(options_.colorMax));
    std::string header = "ply\nformat binary_little_endian 1.0\ncomment invmap invert results (docs/formats.md section 5)\n";
    if (options_.colorByDistance) {
      colorCommentOffset_ = static_cast<std::int64_t>(header.size());
      header += ColorComment(options_.colorMin, options_.colorMax);
    }
    header += "element vertex ";
    countOffset_ = static_cast<std::int64_t>(header.size());
    header += PlyPatchableCount(0) + "\n";
    for (const char* name : {"x", "y", "z"}) header += std::string("property double ") + name + "\n";
    header += "property uchar status\nproperty int patch\nproperty int cell\n";
    for (const char* name : {"u", "v", "w", "cx", "cy", "cz", "distance"}) {
      header += std::string("property double ") + name + "\n";
    }
    if (options_.colorByDistance) header += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    for (const std::string& name : options_.extraColumns) header += "property double " + PlyName(name) + "\n";
    header += "end_header\n";
    dataOffset_ = static_cast<std::int64_t>(header.size());
    out_.Write(header);
  }

 private:
  /// Bytes of the colour comment line, fixed so that a second pass can
  /// rewrite it with the measured range.
  static constexpr std::size_t kColorCommentBytes = 128;

  /// The header comment naming the colours' distance range, padded to
  /// kColorCommentBytes.
  std::string ColorComment(double lo, double hi) const {
    char text[kColorCommentBytes + 1];
    const std::string what = signed_ ? "cool-warm colormap of " + PlyName(options_.extraColumns[options_.signedColorColumn])
                                     : std::string("viridis colormap of distance");
    if (std::isnan(lo) || std::isnan(hi)) {
      std::snprintf(text, sizeof(text), "comment red green blue: %s, no found points", what.c_str());
    } else {
      std::snprintf(text, sizeof(text), "comment red green blue: %s from %.17g to %.17g", what.c_str(), lo, hi);
    }
    std::string line(text);
    line.resize(kColorCommentBytes - 1, ' ');
    return line + "\n";
  }

  /// Colour of a distance on [lo, hi]; a flat range maps to the first
  /// colour (a signed distance's to the middle, white).
  void Color(double distance, double lo, double hi, unsigned char rgb[3]) const {
    if (signed_) {
      DivergingColor(hi > lo ? (distance - lo) / (hi - lo) : 0.5, rgb);
    } else {
      ViridisColor(hi > lo ? (distance - lo) / (hi - lo) : 0.0, rgb);
    }
  }

  /// The colours' range: given, or the shown values' range (a signed
  /// distance's centred on 0).
  void ColorRange(double* lo, double* hi) const {
    const bool anyFound = minDistance_ <= maxDistance_;
    if (signed_) {
      *hi = !std::isnan(options_.colorMax) ? options_.colorMax
            : anyFound                     ? std::max(std::abs(minDistance_), std::abs(maxDistance_))
                                           : kNan;
      *lo = -*hi;
      return;
    }
    *lo = !std::isnan(options_.colorMin) ? options_.colorMin : anyFound ? minDistance_ : kNan;
    *hi = !std::isnan(options_.colorMax) ? options_.colorMax : anyFound ? maxDistance_ : kNan;
  }

  /// Offsets in a record of the status byte and of the distance.
  static constexpr std::size_t kStatusOffset = 3 * 8;
  static constexpr std::size_t kDistanceOffset = 3 * 8 + 1 + 2 * 4 + 6 * 8;
  /// Offset of the colours, right after the distance.
  static constexpr std::size_t kColorOffset = kDistanceOffset + 8;

  /// See ResultWriter::WriteRows.
  void WriteRows(const double* points, std::size_t count, const Results& results, const double* extra) override {
    if (points == nullptr && count > 0) throw std::invalid_argument("ResultWriter: PLY output needs the query points");
    for (std::size_t i = 0; i < count; ++i) {
      char* const start = out_.Reserve(recordBytes_);
      char* p = start;
      for (int k = 0; k < 3; ++k, p += 8) {
        StoreLittleEndian<double>(p, k < dim_ ? points[i * static_cast<std::size_t>(dim_) + k] : 0.0);
      }
      const Status status = results.status[i];
      const bool found = status == Status::Found;
      *p++ = static_cast<char>(status);
      if (found && results.cell[i] > std::numeric_limits<std::int32_t>::max()) {
        throw InputError(out_.path(), 0, "cell index " + std::to_string(results.cell[i]) + " does not fit a PLY int",
                         InputError::Kind::Output);
      }
      StoreLittleEndian<std::int32_t>(p, found ? results.patch[i] : -1);
      StoreLittleEndian<std::int32_t>(p + 4, found ? static_cast<std::int32_t>(results.cell[i]) : -1);
      p += 8;
      double values[7] = {kNan, kNan, kNan, kNan, kNan, kNan, kNan};
      if (found) {
        for (int k = 0; k < 3; ++k) values[k] = results.params[3 * i + k];
        for (int k = 0; k < 3; ++k) values[3 + k] = k < dim_ ? results.closest[3 * i + k] : 0.0;
        values[6] = results.distance[i];
      }
      for (double value : values) {
        StoreLittleEndian<double>(p, value);
        p += 8;
      }
      if (options_.colorByDistance) {
        unsigned char rgb[3] = {kNoColor, kNoColor, kNoColor};
        const double shown = !found ? kNan : signed_ ? extra[i * extraColumns_ + options_.signedColorColumn] : values[6];
        if (found && !twoPass_) {
          Color(shown, signed_ ? -options_.colorMax : options_.colorMin, options_.colorMax, rgb);
        }
        if (found && std::isfinite(shown)) {
          minDistance_ = std::min(minDistance_, shown);
          maxDistance_ = std::max(maxDistance_, shown);
        }
        std::memcpy(p, rgb, 3);
        p += 3;
      }
      for (std::size_t k = 0; k < extraColumns_; ++k, p += 8) {
        StoreLittleEndian<double>(p, found ? extra[i * extraColumns_ + k] : kNan);
      }
      out_.Advance(recordBytes_);
    }
  }

  /// Patches the count and, when colouring, the range comment and (in
  /// the two-pass case) the colours.
  void Complete() override {
    out_.WriteAt(countOffset_, PlyPatchableCount(rows_).data(), static_cast<std::size_t>(kPlyPatchableCountBytes));
    if (!options_.colorByDistance) return;
    const bool anyFound = minDistance_ <= maxDistance_;
    double lo, hi;
    ColorRange(&lo, &hi);
    out_.WriteAt(colorCommentOffset_, ColorComment(lo, hi).data(), kColorCommentBytes);
    if (!twoPass_ || !anyFound) return;
    // Second pass: the colours of found rows, block by block.
    constexpr std::int64_t kBlockRows = 1 << 16;
    std::vector<char> block;
    for (std::int64_t first = 0; first < rows_; first += kBlockRows) {
      const std::int64_t n = std::min(kBlockRows, rows_ - first);
      const std::int64_t offset = dataOffset_ + first * static_cast<std::int64_t>(recordBytes_);
      block.resize(static_cast<std::size_t>(n) * recordBytes_);
      out_.ReadAt(offset, block.data(), block.size());
      for (std::int64_t r = 0; r < n; ++r) {
        char* record = block.data() + static_cast<std::size_t>(r) * recordBytes_;
        if (record[kStatusOffset] != static_cast<char>(Status::Found)) continue;
        const std::size_t shownOffset = signed_ ? kColorOffset + 3 + 8 * options_.signedColorColumn : kDistanceOffset;
        const double distance = LoadValue<double>(record + shownOffset, false);
        Color(distance, lo, hi, reinterpret_cast<unsigned char*>(record + kColorOffset));
      }
      out_.WriteAt(offset, block.data(), block.size());
    }
  }

  ResultWriteOptions options_;
  std::size_t recordBytes_ = 0;          ///< 89 bytes, 92 with colours, 8 more per extra column.
  bool twoPass_ = false;                 ///< Colours wait for the distance range at Complete.
  bool signed_ = false;                  ///< Colours show ResultWriteOptions::signedColorColumn.
  std::int64_t countOffset_ = 0;         ///< Offset of the vertex count digits.
  std::int64_t colorCommentOffset_ = 0;  ///< Offset of the colour comment line.
  std::int64_t dataOffset_ = 0;          ///< Offset of the first record.
  /// Range of the finite distances of found rows so far.
  double minDistance_ = std::numeric_limits<double>::infinity();
  double maxDistance_ = -std::numeric_limits<double>::infinity();
};

/// The .npy layout (ResultWriter).
class NpyResultWriter : public ResultWriter {
 public:
  /// Creates the file with a fixed-size header for 0 rows.
  NpyResultWriter(const std::string& path, int dim, std::size_t extraColumns)
      : ResultWriter(path, dim, extraColumns) {
    out_.Write(FixedNpyHeader("<f8", 0, static_cast<int>(kColumns + extraColumns_)));
  }

 private:
  /// The CSV columns.
  static constexpr int kColumns = 11;

  /// See ResultWriter::WriteRows.
  void WriteRows(const double*, std::size_t count, const Results& results, const double* extra) override {
    for (std::size_t i = 0; i < count; ++i) {
      const bool found = results.status[i] == Status::Found;
      double row[kColumns] = {static_cast<double>(rows_ + static_cast<std::int64_t>(i)),
                              static_cast<double>(results.status[i]),
                              -1.0,
                              -1.0,
                              kNan,
                              kNan,
                              kNan,
                              kNan,
                              kNan,
                              kNan,
                              kNan};
      if (found) {
        row[2] = results.patch[i];
        row[3] = static_cast<double>(results.cell[i]);
        for (int k = 0; k < 3; ++k) row[4 + k] = results.params[3 * i + k];
        for (int k = 0; k < dim_; ++k) row[7 + k] = results.closest[3 * i + k];
        row[10] = results.distance[i];
      }
      char* p = out_.Reserve(sizeof(row) + 8 * extraColumns_);
      for (double value : row) {
        StoreLittleEndian<double>(p, value);
        p += 8;
      }
      for (std::size_t k = 0; k < extraColumns_; ++k, p += 8) {
        StoreLittleEndian<double>(p, found ? extra[i * extraColumns_ + k] : kNan);
      }
      out_.Advance(sizeof(row) + 8 * extraColumns_);
    }
  }

  /// Rewrites the header with the row count.
  void Complete() override {
    const std::string header = FixedNpyHeader("<f8", rows_, static_cast<int>(kColumns + extraColumns_));
    out_.WriteAt(0, header.data(), header.size());
  }
};

}  // namespace

void DivergingColor(double t, unsigned char rgb[3]) {
  if (std::isnan(t)) {
    rgb[0] = rgb[1] = rgb[2] = kNoColor;
    return;
  }
  const double x = std::min(std::max(t, 0.0), 1.0) * 8.0;
  const int i = std::min(7, static_cast<int>(x));
  const double f = x - i;
  for (int k = 0; k < 3; ++k) {
    rgb[k] = static_cast<unsigned char>(std::lround((1.0 - f) * kCoolWarm[i][k] + f * kCoolWarm[i + 1][k]));
  }
}

void ViridisColor(double t, unsigned char rgb[3]) {
  if (std::isnan(t)) {
    rgb[0] = rgb[1] = rgb[2] = kNoColor;
    return;
  }
  const int level = static_cast<int>(std::lround(std::min(std::max(t, 0.0), 1.0) * 255.0));
  std::memcpy(rgb, kViridis[level], 3);
}

void ResultWriter::WriteChunk(const double* points, std::size_t count, const Results& results,
                              std::int64_t firstIndex, const double* extra) {
  if (finished_) throw std::logic_error("ResultWriter::WriteChunk after Finish");
  if (firstIndex != rows_) {
    throw std::invalid_argument("ResultWriter::WriteChunk: firstIndex " + std::to_string(firstIndex) + " but " +
                                std::to_string(rows_) + " rows written (rows must be in input order)");
  }
  if (results.status.size() < count || results.patch.size() < count || results.cell.size() < count ||
      results.distance.size() < count || results.params.size() < 3 * count || results.closest.size() < 3 * count) {
    throw std::invalid_argument("ResultWriter::WriteChunk: results hold fewer than count points");
  }
  if (extraColumns_ > 0 && extra == nullptr && count > 0) {
    throw std::invalid_argument("ResultWriter::WriteChunk: the extra columns need their values");
  }
  WriteRows(points, count, results, extra);
  rows_ += static_cast<std::int64_t>(count);
}

void ResultWriter::Finish() {
  if (finished_) throw std::logic_error("ResultWriter::Finish called twice");
  Complete();
  out_.Commit();
  finished_ = true;
}

bool IsResultFileName(const std::string& path) {
  const std::string ext = LowerExtension(path);
  return ext == ".csv" || ext == ".ply" || ext == ".npy";
}

std::unique_ptr<ResultWriter> OpenResultWriter(const std::string& path, int dim, const ResultWriteOptions& options) {
  if (dim != 2 && dim != 3) throw std::invalid_argument("OpenResultWriter: dim must be 2 or 3");
  const std::string ext = LowerExtension(path);
  if (ext == ".csv") return std::make_unique<CsvResultWriter>(path, dim, options.extraColumns);
  if (ext == ".ply") return std::make_unique<PlyResultWriter>(path, dim, options);
  if (ext == ".npy") return std::make_unique<NpyResultWriter>(path, dim, options.extraColumns.size());
  throw InputError(path, 0, "unknown result file extension '" + ext + "' (expected .csv, .ply or .npy)",
                   InputError::Kind::Output);
}

}  // namespace invmap::io
