#include "io/mesh_readers.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <istream>
#include <string_view>
#include <memory>
#include <set>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "io/file_io.h"
#include "io/input_error.h"
#include "kernels/cell_shape.h"

namespace invmap::io {
namespace {

/// Lines of a file read through an InputBuffer, without their end-of-line
/// characters ("\n" or "\r\n"), with 1-based numbers for messages. A line
/// is valid until the next one is read; one longer than
/// InputBuffer::kMaxLineBytes is an error (an endless or binary file).
class LineReader {
 public:
  /// `in` must outlive the reader.
  explicit LineReader(InputBuffer* in) : in_(in) {}

  /// The next line; false at the end of the input.
  bool Next(std::string_view* line) { return in_->ReadLine(line); }

  /// Number of the line last returned (0 before the first); at the end of
  /// the input, the last line.
  std::int64_t line() const { return in_->lineNumber(); }
  /// Bytes not yet read, -1 when the input's size is unknown (a pipe).
  std::int64_t remaining() const { return in_->remaining(); }

 private:
  InputBuffer* in_;
};

/// White space between tokens (any line ending included).
bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

/// Splits the next whitespace-separated token off the front of `rest`; false
/// when only whitespace is left.
bool NextToken(std::string_view* rest, std::string_view* token) {
  std::size_t begin = 0;
  while (begin < rest->size() && IsSpace((*rest)[begin])) ++begin;
  if (begin == rest->size()) {
    *rest = {};
    return false;
  }
  std::size_t end = begin;
  while (end < rest->size() && !IsSpace((*rest)[end])) ++end;
  *token = rest->substr(begin, end - begin);
  *rest = rest->substr(end);
  return true;
}

/// `line` without a `#` comment.
std::string_view StripComment(std::string_view line) { return line.substr(0, line.find('#')); }

/// ASCII case-insensitive equality (STL keywords appear in either case).
bool EqualsIgnoreCase(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i]))) return false;
  }
  return true;
}

/// True for the keywords of an ASCII STL.
bool IsStlKeyword(std::string_view token) {
  for (const char* keyword : {"solid", "endsolid", "facet", "endfacet", "normal", "outer", "loop", "endloop", "vertex"}) {
    if (EqualsIgnoreCase(token, keyword)) return true;
  }
  return false;
}

/// A token shown in a message: quoted, long ones shortened.
std::string Quote(std::string_view token) {
  constexpr std::size_t kShown = 40;
  return "\"" + std::string(token.substr(0, kShown)) + (token.size() > kShown ? "...\"" : "\"");
}

/// A finite coordinate within the supported range from `token`, or an
/// InputError at `line` whose message begins with where() (built only then:
/// this runs for every coordinate). The engine checks the range again; here
/// the message can name the line.
template <class Where>
double ParseCoordinate(std::string_view token, const std::string& name, std::int64_t line, const Where& where) {
  double value = 0.0;
  if (!ParseDouble(token, &value)) throw InputError(name, line, where() + ": " + Quote(token) + " is not a number");
  if (!std::isfinite(value)) throw InputError(name, line, where() + ": " + Quote(token) + " is not a finite number");
  if (std::abs(value) > kernels::kMaxCoordinate) {
    throw InputError(name, line,
                     where() + ": " + Quote(token) + " is outside [-1e100, 1e100] (the range invmap supports)");
  }
  return value;
}

/// Faces collected by type, and the vertices they index.
struct MeshBuilder {
  std::vector<double> vertices;     ///< xyz per vertex.
  std::vector<std::int64_t> tris;   ///< 3 vertex indices per triangle.
  std::vector<std::int64_t> quads;  ///< 4 vertex indices per quad.

  /// Vertices so far.
  std::int64_t numVertices() const { return static_cast<std::int64_t>(vertices.size() / 3); }

  /// Appends a vertex.
  void AddVertex(double x, double y, double z) {
    vertices.push_back(x);
    vertices.push_back(y);
    vertices.push_back(z);
  }

  /// A face of n >= 3 valid vertex indices, in the file's order: a quad
  /// (its cyclic order is the finite-element quad order), else tris
  /// (AppendPolygon).
  void AddPolygon(const std::int64_t* v, std::size_t n) {
    if (n == 4) {
      quads.insert(quads.end(), v, v + 4);
      return;
    }
    AppendPolygon(v, n, &tris);
  }

  /// The geometry: a tri patch, then a quad patch, each present only when it
  /// has cells. Throws InputError at `line` when there is no face at all.
  Geometry Finish(const std::string& name, std::int64_t line) {
    if (tris.empty() && quads.empty()) {
      throw InputError(name, line, "no faces: a mesh file needs at least one triangle or quad");
    }
    Geometry geometry;
    geometry.dimension = 3;
    const bool both = !tris.empty() && !quads.empty();
    if (!tris.empty()) {
      Patch patch;
      patch.kind = Patch::Kind::Mesh;
      patch.cell = CellType::Tri;
      patch.points = both ? vertices : std::move(vertices);
      patch.cells = std::move(tris);
      geometry.patches.push_back(std::move(patch));
    }
    if (!quads.empty()) {
      Patch patch;
      patch.kind = Patch::Kind::Mesh;
      patch.cell = CellType::Quad;
      patch.points = std::move(vertices);
      patch.cells = std::move(quads);
      geometry.patches.push_back(std::move(patch));
    }
    return geometry;
  }
};

/// The line number to report at the end of a text (line 1 for an empty one).
std::int64_t EndLine(const LineReader& lines) { return std::max<std::int64_t>(lines.line(), 1); }

// ---------------------------------------------------------------- OBJ

/// Reads an OBJ text (see ReadObj).
Geometry ParseObj(InputBuffer* in, const std::string& name) {
  MeshBuilder mesh;
  LineReader lines(in);
  std::vector<std::int64_t> face;
  // Positive indices may name vertices defined further down; the largest is
  // checked at the end, at the line that used it.
  std::int64_t maxIndex = 0, maxIndexLine = 0;
  std::string_view line;
  while (lines.Next(&line)) {
    std::string_view rest = StripComment(line);
    std::string_view keyword;
    if (!NextToken(&rest, &keyword)) continue;
    if (keyword == "v") {
      double xyz[3];
      for (int k = 0; k < 3; ++k) {
        std::string_view token;
        if (!NextToken(&rest, &token)) {
          throw InputError(name, lines.line(), "v: " + std::to_string(k) + " coordinates, expected 3 (x y z)");
        }
        xyz[k] = ParseCoordinate(token, name, lines.line(), [k] { return "v: coordinate " + std::to_string(k); });
      }
      mesh.AddVertex(xyz[0], xyz[1], xyz[2]);
    } else if (keyword == "f") {
      face.clear();
      std::string_view token;
      while (NextToken(&rest, &token)) {
        std::int64_t index = 0;
        if (!ParseInteger(token.substr(0, token.find('/')), &index)) {
          throw InputError(name, lines.line(),
                           "f: " + Quote(token) + " is not a vertex reference (v, v/vt, v/vt/vn or v//vn)");
        }
        if (index == 0) throw InputError(name, lines.line(), "f: vertex index 0 (OBJ indices start at 1)");
        if (index < 0) {
          // Relative: -1 is the last vertex defined so far.
          if (index < -mesh.numVertices()) {
            throw InputError(name, lines.line(),
                             "f: relative vertex index " + std::to_string(index) + " refers before the first vertex (" +
                                 std::to_string(mesh.numVertices()) + " defined so far)");
          }
          index = mesh.numVertices() + index;
        } else {
          if (index > maxIndex) {
            maxIndex = index;
            maxIndexLine = lines.line();
          }
          index -= 1;
        }
        face.push_back(index);
      }
      if (face.size() < 3) {
        throw InputError(name, lines.line(),
                         "f: " + std::to_string(face.size()) + " vertices, a face needs at least 3");
      }
      mesh.AddPolygon(face.data(), face.size());
    }
  }
  if (maxIndex > mesh.numVertices()) {
    throw InputError(name, maxIndexLine,
                     "f: vertex index " + std::to_string(maxIndex) + " out of range (the file has " +
                         std::to_string(mesh.numVertices()) + " vertices)");
  }
  return mesh.Finish(name, EndLine(lines));
}

// ---------------------------------------------------------------- STL

/// Merges vertices with identical coordinates so that an STL's triangles,
/// which each list their own corners, share vertices.
class VertexMerger {
 public:
  /// `mesh` receives the distinct vertices and outlives the merger;
  /// `expected` is a size hint already checked against the file size.
  VertexMerger(MeshBuilder* mesh, std::size_t expected) : mesh_(mesh) { index_.reserve(expected); }

  /// The index of vertex (x, y, z), added to the mesh when new.
  std::int64_t Add(double x, double y, double z) {
    // + 0.0 turns -0.0 into 0.0, so that the two zeros are one vertex.
    const Key key{x + 0.0, y + 0.0, z + 0.0};
    const auto [it, inserted] = index_.try_emplace(key, mesh_->numVertices());
    if (inserted) mesh_->AddVertex(key[0], key[1], key[2]);
    return it->second;
  }

 private:
  using Key = std::array<double, 3>;
  /// Mixes the coordinates' bit patterns (equal keys have equal bits once
  /// -0.0 is folded into 0.0).
  struct KeyHash {
    std::size_t operator()(const Key& key) const {
      std::uint64_t h = 0x9e3779b97f4a7c15ull;
      for (double x : key) {
        std::uint64_t bits;
        std::memcpy(&bits, &x, sizeof bits);
        h ^= bits + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
      }
      return static_cast<std::size_t>(h);
    }
  };

  MeshBuilder* mesh_;                                     ///< Not owned.
  std::unordered_map<Key, std::int64_t, KeyHash> index_;  ///< Vertex -> its index in mesh_.
};

/// An unsigned 32-bit integer stored little-endian.
std::uint32_t ReadU32LE(const unsigned char* p) {
  return std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 | std::uint32_t{p[2]} << 16 | std::uint32_t{p[3]} << 24;
}

/// An IEEE single stored little-endian, whatever the host's byte order.
float ReadF32LE(const unsigned char* p) {
  const std::uint32_t bits = ReadU32LE(p);
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

/// Binary STL layout: an 80-byte header and the triangle count, then 50
/// bytes per triangle.
constexpr std::size_t kStlHeaderBytes = 84;
constexpr std::size_t kStlTriangleBytes = 50;

/// Reads the `count` triangles of a binary STL whose header `in` has
/// consumed. `sizeChecked`: the file size matched the count, which may then
/// size the arrays; otherwise (a pipe) the input must end right after them.
Geometry ParseBinaryStl(InputBuffer* in, const std::string& name, std::uint32_t count, bool sizeChecked) {
  MeshBuilder mesh;
  if (sizeChecked) mesh.tris.reserve(static_cast<std::size_t>(count) * 3);
  VertexMerger merger(&mesh, sizeChecked ? static_cast<std::size_t>(count) / 2 + 3 : 0);
  for (std::uint32_t t = 0; t < count; ++t) {
    if (!in->Fill(kStlTriangleBytes)) {
      throw InputError(name, 0,
                       "the file ends in triangle " + std::to_string(t) + " of the " + std::to_string(count) +
                           " its binary header declares");
    }
    // 12 bytes of normal (ignored), 3 x 12 bytes of corners, 2 attribute bytes.
    const unsigned char* corner = reinterpret_cast<const unsigned char*>(in->data()) + 12;
    for (int v = 0; v < 3; ++v, corner += 12) {
      const double x = ReadF32LE(corner), y = ReadF32LE(corner + 4), z = ReadF32LE(corner + 8);
      if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
        throw InputError(
            name, 0,
            "triangle " + std::to_string(t) + ", vertex " + std::to_string(v) + ": coordinate is not a finite number");
      }
      mesh.tris.push_back(merger.Add(x, y, z));
    }
    in->Consume(kStlTriangleBytes);
  }
  if (!sizeChecked && in->Fill(1)) {
    throw InputError(name, 0,
                     "not an STL file: more bytes after the " + std::to_string(count) +
                         " triangles its binary header declares");
  }
  return mesh.Finish(name, 0);
}

/// Tokens of an ASCII STL with the line of each (its keywords need not sit
/// on separate lines), read a line at a time. A NUL byte, which no ASCII
/// STL holds, is binary data: the error then gives `binaryWhy`, what the
/// size rule says of the file.
class TokenReader {
 public:
  /// `in` and `binaryWhy` must outlive the reader.
  TokenReader(InputBuffer* in, const std::string& name, const std::string& binaryWhy)
      : in_(in), name_(name), binaryWhy_(binaryWhy) {}

  /// The next token; false at the end of the input.
  bool Next(std::string_view* token) {
    while (!NextToken(&rest_, token)) {
      if (!in_->ReadLine(&rest_)) return false;
      if (rest_.find('\0') != std::string_view::npos) {
        throw InputError(name_, 0, "not an STL file: binary data after a \"solid\" header" + binaryWhy_);
      }
    }
    return true;
  }

  /// Skips to the end of the current line (a solid's name is free text).
  void SkipLine() { rest_ = {}; }

  /// 1-based line of the last token (or of the end of the input).
  std::int64_t line() const { return std::max<std::int64_t>(in_->lineNumber(), 1); }

 private:
  InputBuffer* in_;
  const std::string& name_;
  const std::string& binaryWhy_;
  std::string_view rest_;  ///< The current line after the last token.
};

/// Reads an ASCII STL: solids of facets, each an outer loop of 3 vertices.
Geometry ParseAsciiStl(InputBuffer* in, const std::string& name, const std::string& binaryWhy) {
  TokenReader tokens(in, name, binaryWhy);
  MeshBuilder mesh;
  VertexMerger merger(&mesh, 0);
  std::string_view token;
  const auto expect = [&](const char* keyword) {
    if (!tokens.Next(&token)) {
      throw InputError(name, tokens.line(), std::string("unexpected end of file, expected \"") + keyword + "\"");
    }
    if (!EqualsIgnoreCase(token, keyword)) {
      throw InputError(name, tokens.line(), "unexpected " + Quote(token) + ", expected \"" + keyword + "\"");
    }
  };
  expect("solid");
  tokens.SkipLine();
  while (true) {
    if (!tokens.Next(&token)) {
      throw InputError(name, tokens.line(), "unexpected end of file, expected \"facet\" or \"endsolid\"");
    }
    if (EqualsIgnoreCase(token, "endsolid")) {
      tokens.SkipLine();
      // Some files hold several solids one after the other.
      if (!tokens.Next(&token)) break;
      if (!EqualsIgnoreCase(token, "solid")) {
        throw InputError(name, tokens.line(), "unexpected " + Quote(token) + " after \"endsolid\", expected \"solid\"");
      }
      tokens.SkipLine();
      continue;
    }
    if (!EqualsIgnoreCase(token, "facet")) {
      throw InputError(name, tokens.line(), "unexpected " + Quote(token) + ", expected \"facet\" or \"endsolid\"");
    }
    expect("normal");
    for (int k = 0; k < 3; ++k) {
      if (!tokens.Next(&token)) throw InputError(name, tokens.line(), "unexpected end of file in a facet normal");
    }
    expect("outer");
    expect("loop");
    std::int64_t corners[3];
    for (int v = 0; v < 3; ++v) {
      expect("vertex");
      const std::int64_t vertexLine = tokens.line();
      double xyz[3];
      for (int k = 0; k < 3; ++k) {
        if (!tokens.Next(&token)) {
          throw InputError(name, tokens.line(), "unexpected end of file, expected a vertex coordinate");
        }
        // A keyword on a later line where a coordinate should be: the
        // vertex's own line is short of coordinates, and that is the line to fix.
        if (tokens.line() != vertexLine && IsStlKeyword(token)) {
          throw InputError(name, vertexLine,
                           "vertex: " + std::to_string(k) + " coordinate" + (k == 1 ? "" : "s") + ", expected 3");
        }
        xyz[k] = ParseCoordinate(token, name, tokens.line(), [k] { return "vertex: coordinate " + std::to_string(k); });
      }
      corners[v] = merger.Add(xyz[0], xyz[1], xyz[2]);
    }
    expect("endloop");
    expect("endfacet");
    mesh.tris.insert(mesh.tris.end(), corners, corners + 3);
  }
  return mesh.Finish(name, tokens.line());
}

/// Reads an STL, binary or ASCII by the size rule (see ReadStl), deciding
/// from the header and the file size before reading further.
Geometry ParseStl(InputBuffer* in, const std::string& name) {
  const std::int64_t size = in->size();
  in->Fill(size >= 0 ? static_cast<std::size_t>(std::min<std::int64_t>(size, kStlHeaderBytes)) : kStlHeaderBytes);
  const bool haveHeader = in->available() >= kStlHeaderBytes;
  const auto* header = reinterpret_cast<const unsigned char*>(in->data());
  const std::uint32_t count = haveHeader ? ReadU32LE(header + 80) : 0;
  const std::uint64_t binarySize = kStlHeaderBytes + std::uint64_t{kStlTriangleBytes} * count;
  if (haveHeader && size >= 0 && static_cast<std::uint64_t>(size) == binarySize) {
    in->Consume(kStlHeaderBytes);
    return ParseBinaryStl(in, name, count, true);
  }
  const std::string_view start(in->data(), in->available());
  const std::size_t first = std::min(start.find_first_not_of(" \t\r\n"), start.size());
  const bool solidHeader = start.size() - first >= 5 && EqualsIgnoreCase(start.substr(first, 5), "solid");
  if (size < 0) {
    // A pipe: no size to decide by, so the header does.
    if (solidHeader) return ParseAsciiStl(in, name, "");
    if (!haveHeader) throw InputError(name, 0, "not an STL file: it ends within the 84 bytes of a binary header");
    in->Consume(kStlHeaderBytes);
    return ParseBinaryStl(in, name, count, false);
  }
  const std::string why = !haveHeader ? std::to_string(size) + " bytes is too short for a binary STL (at least 84)"
                                      : "a binary STL declaring " + std::to_string(count) + " triangles has 84 + 50 x " +
                                            std::to_string(count) + " = " + std::to_string(binarySize) +
                                            " bytes, this file has " + std::to_string(size);
  if (!solidHeader) throw InputError(name, 0, "not an STL file: no ASCII \"solid\" header, and " + why);
  // Binary headers often begin with "solid" too, but ASCII STL never holds a
  // NUL byte: then the size mismatch is the real problem.
  return ParseAsciiStl(in, name, ", and " + why);
}

// ---------------------------------------------------------------- OFF

/// The next line with content (comments and blank lines skipped), its
/// comment removed; false at the end of the text.
bool NextContentLine(LineReader* lines, std::string_view* line) {
  while (lines->Next(line)) {
    *line = StripComment(*line);
    if (line->find_first_not_of(" \t\r\v\f") != std::string_view::npos) return true;
  }
  return false;
}

/// True for the OFF header keywords whose vertex lines start with x y z:
/// [ST][C][N]OFF. (4OFF and nOFF change the vertex layout.)
bool IsOffKeyword(std::string_view token) {
  if (token.size() < 3 || token.substr(token.size() - 3) != "OFF") return false;
  std::string_view prefix = token.substr(0, token.size() - 3);
  if (prefix.substr(0, 2) == "ST") prefix.remove_prefix(2);
  if (!prefix.empty() && prefix.front() == 'C') prefix.remove_prefix(1);
  if (!prefix.empty() && prefix.front() == 'N') prefix.remove_prefix(1);
  return prefix.empty();
}

/// Reads an OFF text (see ReadOff).
Geometry ParseOff(InputBuffer* in, const std::string& name) {
  LineReader lines(in);
  std::string_view line;
  if (!NextContentLine(&lines, &line)) {
    throw InputError(name, EndLine(lines), "empty file, expected the \"OFF\" header");
  }
  std::string_view rest = line;
  std::string_view token;
  NextToken(&rest, &token);
  std::int64_t probe = 0;
  if (IsOffKeyword(token)) {
    // The counts may follow the keyword on the same line.
    std::string_view after = rest;
    if (!NextToken(&after, &token)) {
      if (!NextContentLine(&lines, &line)) {
        throw InputError(name, EndLine(lines), "unexpected end of file, expected the vertex and face counts");
      }
      rest = line;
    }
  } else if (token.find("OFF") != std::string_view::npos) {
    throw InputError(name, lines.line(),
                     "unsupported OFF variant " + Quote(token) + " (only 3D vertex lines are read)");
  } else if (ParseInteger(token, &probe)) {
    rest = line;  // No header: this line holds the counts.
  } else {
    throw InputError(name, lines.line(),
                     "expected the \"OFF\" header or the vertex and face counts, found " + Quote(token));
  }
  std::int64_t counts[2];
  const char* countNames[2] = {"vertex count", "face count"};
  for (int k = 0; k < 2; ++k) {
    if (!NextToken(&rest, &token)) {
      throw InputError(name, lines.line(),
                       std::string("expected the ") + countNames[k] + ", found the end of the line");
    }
    if (!ParseInteger(token, &counts[k]) || counts[k] < 0) {
      throw InputError(name, lines.line(),
                       std::string(countNames[k]) + ": " + Quote(token) + " is not a non-negative integer");
    }
  }
  const std::int64_t numVertices = counts[0], numFaces = counts[1];
  // The shortest vertex line is "0 0 0" and the shortest line a face can be
  // read from at all a single token, each with a separator: claims beyond
  // what the rest of the file can hold are refused before anything is
  // allocated. (Counting a valid face, "3 0 0 0", blamed the header for a
  // file whose real fault was a face of 2 vertices.) A pipe's size is
  // unknown: then nothing is reserved, and memory grows only with the
  // lines actually read.
  const std::int64_t remaining = lines.remaining();
  if (remaining >= 0 && (numVertices > (remaining + 1) / 6 || numFaces > (remaining + 1) / 2 ||
                         numVertices * 6 + numFaces * 2 > remaining + 1)) {
    throw InputError(name, lines.line(),
                     "the header declares " + std::to_string(numVertices) + " vertices and " +
                         std::to_string(numFaces) + " faces, more than the remaining " + std::to_string(remaining) +
                         " bytes can hold");
  }
  MeshBuilder mesh;
  if (remaining >= 0) mesh.vertices.reserve(static_cast<std::size_t>(numVertices) * 3);
  for (std::int64_t i = 0; i < numVertices; ++i) {
    if (!NextContentLine(&lines, &line)) {
      throw InputError(
          name, EndLine(lines),
          "unexpected end of file after " + std::to_string(i) + " of " + std::to_string(numVertices) + " vertices");
    }
    rest = line;
    double xyz[3];
    for (int k = 0; k < 3; ++k) {
      if (!NextToken(&rest, &token)) {
        throw InputError(name, lines.line(),
                         "vertex " + std::to_string(i) + ": " + std::to_string(k) + " coordinates, expected 3 (x y z)");
      }
      xyz[k] = ParseCoordinate(token, name, lines.line(),
                               [i, k] { return "vertex " + std::to_string(i) + ": coordinate " + std::to_string(k); });
    }
    mesh.AddVertex(xyz[0], xyz[1], xyz[2]);
  }
  std::vector<std::int64_t> face;
  for (std::int64_t i = 0; i < numFaces; ++i) {
    if (!NextContentLine(&lines, &line)) {
      throw InputError(
          name, EndLine(lines),
          "unexpected end of file after " + std::to_string(i) + " of " + std::to_string(numFaces) + " faces");
    }
    rest = line;
    const auto where = [i] { return "face " + std::to_string(i); };
    std::int64_t n = 0;
    NextToken(&rest, &token);
    if (!ParseInteger(token, &n)) {
      throw InputError(name, lines.line(), where() + ": vertex count " + Quote(token) + " is not an integer");
    }
    if (n < 3) {
      throw InputError(name, lines.line(), where() + ": " + std::to_string(n) + " vertices, a face needs at least 3");
    }
    face.clear();
    // n is only a claim: indices are read while the line has them.
    for (std::int64_t k = 0; k < n; ++k) {
      std::int64_t index = 0;
      if (!NextToken(&rest, &token)) {
        throw InputError(name, lines.line(),
                         where() + ": " + std::to_string(k) + " vertex indices, expected " + std::to_string(n));
      }
      if (!ParseInteger(token, &index)) {
        throw InputError(name, lines.line(), where() + ": vertex index " + Quote(token) + " is not an integer");
      }
      if (index < 0 || index >= numVertices) {
        throw InputError(name, lines.line(),
                         where() + ": vertex index " + std::to_string(index) + " out of range (the file has " +
                             std::to_string(numVertices) + " vertices, numbered from 0)");
      }
      face.push_back(index);
    }
    // The shortest triangle line is "3 0 0 0" and its newline.
    if (face.size() != 4) ReserveTriangles(numFaces - i, remaining + 1, 8, &mesh.tris);
    mesh.AddPolygon(face.data(), face.size());
  }
  // Faces beyond the header's count would be dropped unseen.
  if (NextContentLine(&lines, &line)) {
    throw InputError(name, lines.line(),
                     "data after the last of the " + std::to_string(numFaces) + " faces the header declares");
  }
  return mesh.Finish(name, EndLine(lines));
}

}  // namespace

Geometry ReadMeshFile(const std::string& path) {
  const std::string ext = LowerExtension(path);
  Geometry (*parse)(InputBuffer*, const std::string&) = nullptr;
  if (ext == ".obj") parse = ParseObj;
  if (ext == ".stl") parse = ParseStl;
  if (ext == ".off") parse = ParseOff;
  if (!parse) {
    throw InputError(path, 0, "unknown mesh file extension \"" + ext + "\" (supported: .obj, .stl, .off)");
  }
  InputBuffer in(path);
  return parse(&in, path);
}

namespace {

/// Reads `in` with `parse` through a stream of its own over the caller's
/// buffer (reading advances `in`).
Geometry ParseStream(std::istream& in, const std::string& name, Geometry (*parse)(InputBuffer*, const std::string&)) {
  InputBuffer buffer(std::make_unique<std::istream>(in.rdbuf()), name);
  return parse(&buffer, name);
}

}  // namespace

Geometry ReadObj(std::istream& in, const std::string& nameForMessages) {
  return ParseStream(in, nameForMessages, ParseObj);
}

Geometry ReadStl(std::istream& in, const std::string& nameForMessages) {
  return ParseStream(in, nameForMessages, ParseStl);
}

Geometry ReadOff(std::istream& in, const std::string& nameForMessages) {
  return ParseStream(in, nameForMessages, ParseOff);
}

void ReserveTriangles(std::int64_t faces, std::int64_t bytes, std::int64_t minTriangleBytes,
                      std::vector<std::int64_t>* tris) {
  if (bytes < 0 || tris->capacity() > 0) return;
  const std::int64_t count = std::min(faces, bytes / std::max<std::int64_t>(minTriangleBytes, 1));
  if (count > 0) tris->reserve(3 * static_cast<std::size_t>(count));
}

void AppendPolygon(const std::int64_t* v, std::size_t n, std::vector<std::int64_t>* tris) {
  std::vector<std::int64_t> sorted(v, v + n);
  std::sort(sorted.begin(), sorted.end());
  if (n == 3 || std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end()) {
    // Distinct indices (the usual polygon): every fan triangle is a distinct one.
    for (std::size_t i = 1; i + 1 < n; ++i) tris->insert(tris->end(), {v[0], v[i], v[i + 1]});
    return;
  }
  // A repeated index: fan triangles may repeat a vertex (a segment or a
  // point) or each other. Kept: each distinct triangle of three distinct
  // vertices once; then, for a left-out triangle's segment from v[0] to its
  // other vertex x, one triangle (v[0], x, x) where no kept triangle holds
  // x (each one that does has that segment as an edge), once per x.
  std::set<std::array<std::int64_t, 3>> kept;
  std::unordered_set<std::int64_t> covered;
  for (std::size_t i = 1; i + 1 < n; ++i) {
    if (v[i] == v[0] || v[i] == v[i + 1] || v[i + 1] == v[0]) continue;
    std::array<std::int64_t, 3> key{v[0], v[i], v[i + 1]};
    std::sort(key.begin(), key.end());
    if (!kept.insert(key).second) continue;
    tris->insert(tris->end(), {v[0], v[i], v[i + 1]});
    covered.insert({v[0], v[i], v[i + 1]});
  }
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const std::int64_t x = v[i] != v[0] ? v[i] : v[i + 1];
    if (covered.insert(x).second) tris->insert(tris->end(), {v[0], x, x});
  }
}

}  // namespace invmap::io
