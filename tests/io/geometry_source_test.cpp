// Tests of GeometrySource: the lines of a geometry's parts, stored as runs,
// and the place of a GeometryError found from them.
#include "io/geometry_source.h"

#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

namespace invmap::io {
namespace {

TEST(LineRuns, EveryElementGetsItsLineWhateverTheLayout) {
  // Elements one per line, several per line, with gaps in the lines and
  // elements never recorded, checked against a plain table.
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 50; ++trial) {
    LineRuns runs;
    std::vector<std::int64_t> expected(400, 0);
    std::int64_t line = 1 + static_cast<std::int64_t>(rng() % 5);
    for (std::int64_t e = 0; e < 400; ++e) {
      switch (rng() % 6) {
        case 0:
          continue;  // not recorded
        case 1:
        case 2:
          break;  // same line
        case 3:
        case 4:
          line += 1;
          break;
        default:
          line += 2 + static_cast<std::int64_t>(rng() % 7);
      }
      runs.Add(e, line);
      expected[e] = line;
    }
    for (std::int64_t e = 0; e < 400; ++e) {
      ASSERT_EQ(runs.LineOf(e), expected[e]) << "trial " << trial << " element " << e;
    }
    EXPECT_EQ(runs.LineOf(400), 0);
    EXPECT_EQ(runs.LineOf(-1), 0);
  }
}

TEST(GeometrySource, TheLineOfTheMostPreciseRecordedPlace) {
  GeometrySource source("g.json");
  source.BeginPatch(3);
  source.Field(GeometryField::Knots, 4);
  source.Element(GeometryField::Knots, 0, 4);
  source.Element(GeometryField::Knots, 1, 5);
  source.Item(GeometryField::Knots, 1, 6, 7);
  source.Field(GeometryField::Degrees, 9);
  source.BeginPatch(12);

  GeometryError e{0, GeometryField::Knots, 1, 6, "decreasing at index 6 (0.5 > 0.25)"};
  EXPECT_EQ(source.LineOf(e), 7);  // the item, off its row's line
  e.item = 5;
  EXPECT_EQ(source.LineOf(e), 5);  // the element
  e.element = 2;
  EXPECT_EQ(source.LineOf(e), 4);  // no such element: the field
  e = GeometryError{0, GeometryField::Degrees, 0, -1, "9, expected 1 to 8"};
  EXPECT_EQ(source.LineOf(e), 9);  // elements of the field not recorded
  e = GeometryError{0, GeometryField::Weights, 3, -1, "0 is not positive"};
  EXPECT_EQ(source.LineOf(e), 3);  // field not recorded: the patch
  e = GeometryError{1, GeometryField::Cells, 0, 1, "vertex index 7 out of range"};
  EXPECT_EQ(source.LineOf(e), 12);
  e = GeometryError{2, GeometryField::Cells, 0, 1, "vertex index 7 out of range"};
  EXPECT_EQ(source.LineOf(e), 0);  // a patch the file did not have
  e = GeometryError{-1, GeometryField::None, -1, -1, "the geometry is 1e-120 across"};
  EXPECT_EQ(source.LineOf(e), 0);
}

TEST(GeometrySource, ErrorsReadAsTheReadersOwn) {
  GeometrySource source("g.json");
  source.BeginPatch(2);
  source.Element(GeometryField::Knots, 0, 4);
  const GeometryError knots{0, GeometryField::Knots, 0, 4, "decreasing at index 4 (0.5 > 0.25)"};
  EXPECT_STREQ(source.ToInputError(knots).what(), "g.json:4: patches[0].knots[0]: decreasing at index 4 (0.5 > 0.25)");
  EXPECT_EQ(source.ToInputError(knots).line(), 4);
  EXPECT_EQ(source.ToInputError(knots).kind(), InputError::Kind::Input);
  const GeometryError field{0, GeometryField::Counts, -1, -1, "2 values, expected one per degree (1)"};
  EXPECT_STREQ(source.ToInputError(field).what(), "g.json:2: patches[0].counts: 2 values, expected one per degree (1)");
  const GeometryError whole{-1, GeometryField::None, -1, -1, "the geometry is 1e-120 across"};
  EXPECT_STREQ(source.ToInputError(whole).what(), "g.json: the geometry is 1e-120 across");
  EXPECT_THROW(source.Check(knots), InputError);
  EXPECT_NO_THROW(source.Check(GeometryError{}));
  EXPECT_EQ(GeometryPath(GeometryError{3, GeometryField::None, -1, -1, "x"}), "patches[3]");
  EXPECT_EQ(GeometryPath(GeometryError{-1, GeometryField::Dimension, -1, -1, "x"}), "dimension");
  EXPECT_EQ(GeometryPath(GeometryError{1, GeometryField::Vertices, 7, 2, "x"}), "patches[1].vertices[7]");
}

}  // namespace
}  // namespace invmap::io
