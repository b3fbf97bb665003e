#include "tests/support/pcd_writer.h"

#include <lzf.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace invmap::testing {
namespace {

/// Appends `value` as a little-endian value of `type` and `size`.
void PutValue(double value, char type, std::size_t size, std::string* out) {
  char raw[8];
  if (type == 'F' && size == 4) {
    const auto v = static_cast<float>(value);
    std::memcpy(raw, &v, 4);
  } else if (type == 'F') {
    std::memcpy(raw, &value, 8);
  } else if (type == 'I') {
    const auto v = static_cast<std::int64_t>(value);
    std::memcpy(raw, &v, 8);  // little-endian host: the low `size` bytes come first
  } else {
    const auto v = static_cast<std::uint64_t>(value);
    std::memcpy(raw, &v, 8);
  }
  out->append(raw, size);
}

std::string Format(double value, char type, std::size_t size) {
  if (std::isnan(value)) return "nan";
  char text[64];
  if (type != 'F') {
    std::snprintf(text, sizeof text, "%.0f", value);
  } else {
    std::snprintf(text, sizeof text, size == 4 ? "%.9g" : "%.17g", value);
  }
  return text;
}

}  // namespace

double PcdStored(double value, char type, std::size_t size) {
  return type == 'F' && size == 4 ? static_cast<double>(static_cast<float>(value)) : value;
}

std::string WritePcd(const PcdTestCloud& cloud, const std::string& encoding) {
  const std::size_t width = cloud.width == 0 ? cloud.points.size() : cloud.width;
  std::string fields, sizes, types, counts;
  for (const PcdTestField& f : cloud.fields) {
    fields += " " + f.name;
    sizes += " " + std::to_string(f.size);
    types += std::string(" ") + f.type;
    counts += " " + std::to_string(f.count);
  }
  std::string out = "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS" + fields + "\nSIZE" + sizes +
                    "\nTYPE" + types + "\nCOUNT" + counts + "\nWIDTH " + std::to_string(width) + "\nHEIGHT " +
                    std::to_string(cloud.height) + "\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " +
                    std::to_string(cloud.points.size()) + "\nDATA " + encoding + "\n";
  if (encoding == "ascii") {
    for (const std::vector<double>& point : cloud.points) {
      std::size_t v = 0;
      std::string line;
      for (const PcdTestField& f : cloud.fields) {
        for (std::size_t c = 0; c < f.count; ++c, ++v) line += (line.empty() ? "" : " ") + Format(point[v], f.type, f.size);
      }
      out += line + "\n";
    }
  } else if (encoding == "binary") {
    for (const std::vector<double>& point : cloud.points) {
      std::size_t v = 0;
      for (const PcdTestField& f : cloud.fields) {
        for (std::size_t c = 0; c < f.count; ++c, ++v) PutValue(point[v], f.type, f.size, &out);
      }
    }
  } else if (encoding == "binary_compressed") {
    // Field after field, each with every point's values; "_" left out.
    std::string columns;
    std::size_t first = 0;
    for (const PcdTestField& f : cloud.fields) {
      if (f.name != "_") {
        for (const std::vector<double>& point : cloud.points) {
          for (std::size_t c = 0; c < f.count; ++c) PutValue(point[first + c], f.type, f.size, &columns);
        }
      }
      first += f.count;
    }
    std::string packed(columns.size() * 2 + 64, '\0');
    const unsigned int n = columns.empty() ? 0
                                           : lzf_compress(columns.data(), static_cast<unsigned int>(columns.size()),
                                                          packed.data(), static_cast<unsigned int>(packed.size()));
    if (!columns.empty() && n == 0) throw std::runtime_error("lzf_compress failed");
    const std::uint32_t sizesField[2] = {n, static_cast<std::uint32_t>(columns.size())};
    out.append(reinterpret_cast<const char*>(sizesField), 8);
    out.append(packed.data(), n);
  } else {
    throw std::invalid_argument("WritePcd: unknown encoding " + encoding);
  }
  return out;
}

PcdTestCloud RandomPcdCloud(std::size_t count, char coordinateType, std::size_t coordinateSize, bool withPadding,
                            std::mt19937_64* random) {
  PcdTestCloud cloud;
  cloud.fields = {{"x", coordinateType, coordinateSize, 1},
                  {"intensity", 'F', 4, 1},
                  {"y", coordinateType, coordinateSize, 1},
                  {"normal", 'F', 4, 3},
                  {"z", coordinateType, coordinateSize, 1},
                  {"label", 'U', 2, 1},
                  {"offset", 'I', 8, 1},
                  {"flags", 'I', 1, 2},
                  {"curvature", 'F', 8, 1}};
  if (withPadding) cloud.fields.insert(cloud.fields.begin() + 3, PcdTestField{"_", 'U', 1, 3});
  std::mt19937_64& rng = *random;
  std::uniform_int_distribution<int> grid(-4000, 4000);
  for (std::size_t i = 0; i < count; ++i) {
    std::vector<double> values;
    for (const PcdTestField& f : cloud.fields) {
      for (std::size_t c = 0; c < f.count; ++c) {
        double v = 0.0;
        if (f.name == "_") {
          v = 0.0;
        } else if (f.type == 'F') {
          // Multiples of 1/1024: exact in float, and in ascii at 9 digits.
          v = grid(rng) / 1024.0;
        } else if (f.type == 'U') {
          v = std::uniform_int_distribution<int>(0, 255)(rng) * (f.size == 1 ? 1 : 257);
        } else {
          v = std::uniform_int_distribution<int>(-128, 127)(rng);
        }
        values.push_back(PcdStored(v, f.type, f.size));
      }
    }
    cloud.points.push_back(values);
  }
  return cloud;
}

}  // namespace invmap::testing
