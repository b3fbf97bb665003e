// A PCD writer for the tests, independent of io/'s reader: the header lines
// in the Point Cloud Library's order and the data in each of its encodings
// (binary_compressed compresses with liblzf, as PCL does). Files written by
// PCL itself come from its command-line converter (pcl-tools) in the tests.
#pragma once

#include <cstddef>
#include <random>
#include <string>
#include <vector>

namespace invmap::testing {

/// One header field.
struct PcdTestField {
  std::string name;
  char type = 'F';        ///< I, U or F.
  std::size_t size = 4;   ///< Bytes of a value.
  std::size_t count = 1;  ///< Values per point.
};

/// A cloud: fields and, per point, all its values in field order.
struct PcdTestCloud {
  std::vector<PcdTestField> fields;
  std::vector<std::vector<double>> points;
  std::size_t width = 0;   ///< 0: the number of points (HEIGHT 1).
  std::size_t height = 1;
};

/// The file in `encoding` ("ascii", "binary" or "binary_compressed").
/// Values are converted to their field's type (an integer field's values
/// must be integers in its range); ascii writes floats with 9 and doubles
/// with 17 significant digits, so they read back exactly.
std::string WritePcd(const PcdTestCloud& cloud, const std::string& encoding);

/// The value of `value` as stored in a field of `type` and `size` (a float
/// field rounds to float).
double PcdStored(double value, char type, std::size_t size);

/// A cloud of `count` points with fields x y z of `coordinateType` and size,
/// and passed-through fields of several types and counts (including a
/// normal of count 3 and a padding field "_" when `withPadding`), random
/// values stored exactly.
PcdTestCloud RandomPcdCloud(std::size_t count, char coordinateType, std::size_t coordinateSize, bool withPadding,
                            std::mt19937_64* random);

}  // namespace invmap::testing
