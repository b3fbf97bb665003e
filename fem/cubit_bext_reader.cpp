#include "fem/cubit_bext_reader.h"

#include <cmath>
#include <memory>
#include <string_view>

#include "fem/extraction_cells.h"
#include "io/file_io.h"
#include "io/input_error.h"

namespace invmap::fem {
namespace {

/// The lines of a BEXT file without comments and blank lines, as tokens.
class BextLines {
 public:
  explicit BextLines(io::InputBuffer& in) : in_(in) {}

  /// The next non-comment, non-blank line's tokens; false at the end.
  bool Next(std::vector<std::string_view>* tokens) {
    std::string_view line;
    while (in_.ReadLine(&line)) {
      line_ = in_.lineNumber();
      if (line.substr(0, 2) == "$#") continue;
      tokens->clear();
      std::size_t i = 0;
      while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r' || line[i] == ',')) ++i;
        std::size_t j = i;
        while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r' && line[j] != ',') ++j;
        if (j > i) tokens->push_back(line.substr(i, j - i));
        i = j;
      }
      if (!tokens->empty()) return true;
    }
    return false;
  }

  /// The next line, which must exist (`what` names it otherwise).
  const std::vector<std::string_view>& Require(const char* what) {
    if (!Next(&tokens_)) Fail(std::string("unexpected end of file, expected ") + what);
    return tokens_;
  }

  std::int64_t Int(std::string_view token, const char* what) const {
    std::int64_t value = 0;
    if (!io::ParseInteger(token, &value)) Fail(std::string("expected ") + what + " (an integer), found '" + std::string(token) + "'");
    return value;
  }

  double Real(std::string_view token, const char* what) const {
    double value = 0;
    if (!io::ParseDouble(token, &value) || !std::isfinite(value)) {
      Fail(std::string("expected ") + what + " (a finite number), found '" + std::string(token) + "'");
    }
    return value;
  }

  /// `count` integers over as many lines as they take.
  std::vector<std::int64_t> Ints(std::int64_t count, const char* what) {
    std::vector<std::int64_t> values;
    while (static_cast<std::int64_t>(values.size()) < count) {
      const auto& tokens = Require(what);
      if (static_cast<std::int64_t>(values.size() + tokens.size()) > count) Fail(std::string("too many values in ") + what);
      for (const auto token : tokens) values.push_back(Int(token, what));
    }
    return values;
  }

  /// `count` numbers over as many lines as they take.
  std::vector<double> Reals(std::int64_t count, const char* what) {
    std::vector<double> values;
    while (static_cast<std::int64_t>(values.size()) < count) {
      const auto& tokens = Require(what);
      if (static_cast<std::int64_t>(values.size() + tokens.size()) > count) Fail(std::string("too many values in ") + what);
      for (const auto token : tokens) values.push_back(Real(token, what));
    }
    return values;
  }

  /// Refuses a count that the rest of the input cannot hold (at least 2
  /// bytes an entry), so that a corrupt count drives no allocation.
  void CheckCount(std::int64_t count, const char* what) const {
    const std::int64_t remaining = in_.remaining();
    if (count < 0) Fail(std::string("negative ") + what);
    if (remaining >= 0 && count > remaining / 2 + 1) {
      Fail(std::string(what) + " " + std::to_string(count) + " exceeds what the rest of the file can hold");
    }
  }

  [[noreturn]] void Fail(const std::string& what) const { throw io::InputError(in_.name(), line_, what); }
  std::int64_t line() const { return line_; }

 private:
  io::InputBuffer& in_;
  std::vector<std::string_view> tokens_;
  std::int64_t line_ = 0;
};

/// One patch, from its header line on; appends its control points (with
/// weight 1 when the patch has no weights), coefficient vectors and
/// elements. Returns whether the patch is rational.
bool ReadPatch(BextLines& lines, const std::vector<std::string_view>& header, ExtractedSpline* spline,
               std::vector<ExtractionElement>* elements) {
  if (header.size() != 5) lines.Fail("patch header: expected 5 integers (pid nn ne ncv wfl)");
  const std::int64_t numPoints = lines.Int(header[1], "the control point count");
  const std::int64_t numElements = lines.Int(header[2], "the element count");
  lines.Int(header[3], "the coefficient vector count");
  const std::int64_t weightFlag = lines.Int(header[4], "the weight flag");
  lines.CheckCount(numPoints, "control point count");
  lines.CheckCount(numElements, "element count");
  if (weightFlag != 0 && weightFlag != 1) lines.Fail("weight flag must be 0 or 1");
  for (std::int64_t i = 0; i < numPoints; ++i) {
    const auto& tokens = lines.Require("a control point");
    if (tokens.size() != 4 && !(tokens.size() == 3 && weightFlag == 0)) lines.Fail("control point: expected x y z w");
    for (int k = 0; k < 3; ++k) spline->points.push_back(lines.Real(tokens[k], "a coordinate"));
    const double w = weightFlag == 1 ? lines.Real(tokens[3], "a weight") : 1.0;
    if (!(w > 0.0)) lines.Fail("control point " + std::to_string(i + 1) + ": weight " + std::string(tokens[3]) + " is not positive");
    spline->weights.push_back(w);
  }
  const auto& blockCount = lines.Require("the number of element blocks");
  if (blockCount.size() != 1) lines.Fail("expected the number of element blocks");
  const std::int64_t numBlocks = lines.Int(blockCount[0], "the number of element blocks");
  lines.CheckCount(numBlocks, "element block count");
  struct Block {
    std::int64_t count, points, vectors;
    CellType type;
    std::array<int, 3> degrees;
    std::int64_t line;
  };
  std::vector<Block> blocks;
  std::int64_t total = 0;
  for (std::int64_t b = 0; b < numBlocks; ++b) {
    const auto& tokens = lines.Require("an element block header");
    if (tokens.size() < 5 || tokens.size() > 7) lines.Fail("element block header: expected ETYPE NE NN NCV and 1 to 3 degrees");
    Block block{lines.Int(tokens[1], "the element count"), lines.Int(tokens[2], "control points per element"),
                lines.Int(tokens[3], "coefficient vectors per element"), CellType::Line, {0, 0, 0}, lines.line()};
    const std::int64_t type = lines.Int(tokens[0], "the element type");
    if (type != 1) {
      lines.Fail("element type " + std::to_string(type) + " is not read (only type 1, tensor-product Bezier elements)");
    }
    const std::size_t directions = tokens.size() - 4;
    block.type = directions == 1 ? CellType::Line : directions == 2 ? CellType::Quad : CellType::Hex;
    for (std::size_t d = 0; d < directions; ++d) block.degrees[d] = static_cast<int>(lines.Int(tokens[4 + d], "a degree"));
    lines.CheckCount(block.count, "element count");
    lines.CheckCount(block.points, "control points per element");
    if (block.points != block.vectors) lines.Fail("control points and coefficient vectors per element differ");
    total += block.count;
    blocks.push_back(block);
  }
  if (total != numElements) {
    lines.Fail("the element blocks hold " + std::to_string(total) + " elements, the patch header says " +
               std::to_string(numElements));
  }
  const std::size_t firstElement = elements->size();
  const std::int64_t firstPoint = static_cast<std::int64_t>(spline->points.size() / 3) - numPoints;
  const std::int64_t firstVector = static_cast<std::int64_t>(spline->coefficientVectors.size());
  for (const Block& block : blocks) {
    for (std::int64_t e = 0; e < block.count; ++e) {
      ExtractionElement element;
      element.type = block.type;
      element.degrees = block.degrees;
      element.points = lines.Ints(block.points, "an element's control point ids");
      element.where = "element " + std::to_string(elements->size() - firstElement + 1) + " (line " +
                      std::to_string(lines.line()) + ")";
      element.coefficientVectors = lines.Ints(block.vectors, "an element's coefficient vector ids");
      for (std::int64_t& p : element.points) p = firstPoint + p - 1;
      for (std::int64_t& v : element.coefficientVectors) v = firstVector + v - 1;
      elements->push_back(std::move(element));
    }
  }
  const auto& coefficientHeader = lines.Require("the coefficient vector block counts");
  if (coefficientHeader.size() != 2) lines.Fail("expected the numbers of dense and sparse coefficient vector blocks");
  const std::int64_t dense = lines.Int(coefficientHeader[0], "the number of dense blocks");
  const std::int64_t sparse = lines.Int(coefficientHeader[1], "the number of sparse blocks");
  if (sparse != 0) lines.Fail("sparse coefficient vector blocks are not read");
  lines.CheckCount(dense, "dense block count");
  std::vector<std::pair<std::int64_t, std::int64_t>> denseBlocks;
  for (std::int64_t b = 0; b < dense; ++b) {
    const auto& tokens = lines.Require("a dense block header");
    if (tokens.size() != 2) lines.Fail("dense block header: expected the vector count and length");
    denseBlocks.emplace_back(lines.Int(tokens[0], "the vector count"), lines.Int(tokens[1], "the vector length"));
    lines.CheckCount(denseBlocks.back().first * denseBlocks.back().second, "coefficient count");
  }
  for (const auto& [count, length] : denseBlocks) {
    for (std::int64_t v = 0; v < count; ++v) spline->coefficientVectors.push_back(lines.Reals(length, "a coefficient vector"));
  }
  return weightFlag == 1;
}

FieldGeometry ReadBext(io::InputBuffer& in) {
  BextLines lines(in);
  std::vector<std::string_view> tokens;
  const bool header = lines.Next(&tokens) && tokens.size() == 5 && tokens[0] == "B" && tokens[1] == "E" &&
                      tokens[2] == "X" && tokens[3] == "T";
  if (!header) {
    // The binary form's layout is not defined in what was available
    // (docs/fields.md): say so rather than only that the header is wrong.
    for (std::string_view token : tokens) {
      for (const char c : token) {
        if (static_cast<unsigned char>(c) < 0x20 || c == '\x7f') {
          lines.Fail("a binary file: the binary LS-DYNA Bezier extraction form is not read (only the ASCII form, "
                     "whose first line is 'B E X T 2.0')");
        }
      }
    }
    lines.Fail("not a Bezier extraction file: the first line must be 'B E X T 2.0'");
  }
  if (tokens[4] != "2.0") lines.Fail("BEXT version " + std::string(tokens[4]) + " is not read (only 2.0)");
  ExtractedSpline spline;
  std::vector<std::vector<ExtractionElement>> patches;
  bool rational = false;
  while (lines.Next(&tokens)) rational = ReadPatch(lines, tokens, &spline, &patches.emplace_back()) || rational;
  if (patches.empty()) lines.Fail("no patch");
  // Weights of 1 throughout: a polynomial spline.
  if (!rational) spline.weights.clear();
  std::vector<ExtractionElement> all;
  for (const auto& p : patches) all.insert(all.end(), p.begin(), p.end());
  FieldGeometry out;
  out.geometry.dimension = ExtractedDimension(spline, all);
  for (const auto& elements : patches) {
    Patch& patch = out.geometry.patches.emplace_back(EmptyCellsPatch());
    for (const ExtractionElement& element : elements) AddExtractedCell(spline, element, out.geometry.dimension, in.name(), &patch);
  }
  return out;
}

}  // namespace

FieldGeometry ReadCubitBext(const std::string& path) {
  io::InputBuffer in(path);
  return ReadBext(in);
}

FieldGeometry ReadCubitBext(std::istream& in, const std::string& name) {
  io::InputBuffer buffer(std::make_unique<std::istream>(in.rdbuf()), name);
  return ReadBext(buffer);
}

}  // namespace invmap::fem
