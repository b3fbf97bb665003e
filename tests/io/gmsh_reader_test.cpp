// Tests of the gmsh reader: every element type against polynomial maps it
// must reproduce exactly, node orderings against meshes the gmsh binary
// generates, physical groups and entities as patches, inversion on curved
// gmsh meshes, and malformed files.
#include "io/gmsh_reader.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "engine/cell_store.h"
#include "engine/geometry_validation.h"
#include "invmap/invmap.h"
#include "io/gmsh_elements.h"
#include "io/input_error.h"
#include "io/lagrange_to_bernstein.h"
#include "tests/support/reference_cell.h"

namespace invmap::io {
namespace {

using Vec3 = std::array<double, 3>;
using Exponents = std::array<int, 3>;

// ---------------------------------------------------------------------------
// Writing small MSH 4.1 files.

struct TestEntity {
  int dim = 0;
  int tag = 0;
  std::vector<int> physical;
};

struct TestNodeBlock {
  int dim = 0;
  int tag = 0;
  std::vector<std::uint64_t> tags;
  std::vector<Vec3> xyz;
};

struct TestElementBlock {
  int dim = 0;
  int tag = 0;
  int type = 0;
  std::vector<std::uint64_t> tags;
  std::vector<std::vector<std::uint64_t>> nodes;
};

struct TestMesh {
  std::vector<std::tuple<int, int, std::string>> physicalNames;
  std::vector<TestEntity> entities;
  std::vector<TestNodeBlock> nodeBlocks;
  std::vector<TestElementBlock> elementBlocks;
};

enum class Encoding { Ascii, BinaryLittle, BinaryBig };

const char* EncodingName(Encoding e) {
  return e == Encoding::Ascii ? "ascii" : e == Encoding::BinaryLittle ? "binary LE" : "binary BE";
}

/// Writes values in text or in binary of either byte order.
class MshWriter {
 public:
  explicit MshWriter(Encoding encoding) : encoding_(encoding) {}

  void Text(const std::string& s) { out_ += s; }
  void Int(int v) { Value(v, std::to_string(v)); }
  void Size(std::uint64_t v) { Value(v, std::to_string(v)); }
  void Real(double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    Value(v, buf);
  }
  /// Ends a line of values (ascii only).
  void EndLine() {
    if (encoding_ == Encoding::Ascii) out_ += "\n";
  }
  /// Closes binary data before a section's end marker.
  void EndData() {
    if (encoding_ != Encoding::Ascii) out_ += "\n";
  }
  bool binary() const { return encoding_ != Encoding::Ascii; }
  const std::string& str() const { return out_; }

 private:
  template <class T>
  void Value(T v, const std::string& text) {
    if (encoding_ == Encoding::Ascii) {
      if (!out_.empty() && out_.back() != '\n') out_ += ' ';
      out_ += text;
      return;
    }
    char bytes[sizeof(T)];
    std::memcpy(bytes, &v, sizeof(T));
    if (encoding_ == Encoding::BinaryBig) std::reverse(bytes, bytes + sizeof(T));
    out_.append(bytes, sizeof(T));
  }

  Encoding encoding_;
  std::string out_;
};

std::string WriteMsh(const TestMesh& mesh, Encoding encoding) {
  MshWriter w(encoding);
  w.Text(w.binary() ? "$MeshFormat\n4.1 1 8\n" : "$MeshFormat\n4.1 0 8\n");
  if (w.binary()) {
    w.Int(1);
    w.Text("\n");
  }
  w.Text("$EndMeshFormat\n");
  if (!mesh.physicalNames.empty()) {
    w.Text("$PhysicalNames\n" + std::to_string(mesh.physicalNames.size()) + "\n");
    for (const auto& [dim, tag, name] : mesh.physicalNames) {
      w.Text(std::to_string(dim) + " " + std::to_string(tag) + " \"" + name + "\"\n");
    }
    w.Text("$EndPhysicalNames\n");
  }
  if (!mesh.entities.empty()) {
    w.Text("$Entities\n");
    for (int d = 0; d < 4; ++d) {
      w.Size(
          std::count_if(mesh.entities.begin(), mesh.entities.end(), [d](const TestEntity& e) { return e.dim == d; }));
    }
    w.EndLine();
    for (int d = 0; d < 4; ++d) {
      for (const TestEntity& e : mesh.entities) {
        if (e.dim != d) continue;
        w.Int(e.tag);
        for (int k = 0; k < (d == 0 ? 3 : 6); ++k) w.Real(k < 3 ? 0.0 : 1.0);
        w.Size(e.physical.size());
        for (const int p : e.physical) w.Int(p);
        if (d > 0) w.Size(0);
        w.EndLine();
      }
    }
    w.EndData();
    w.Text("$EndEntities\n");
  }
  std::uint64_t numNodes = 0, minTag = ~std::uint64_t{0}, maxTag = 0;
  for (const auto& b : mesh.nodeBlocks) {
    numNodes += b.tags.size();
    for (const auto t : b.tags) minTag = std::min(minTag, t), maxTag = std::max(maxTag, t);
  }
  w.Text("$Nodes\n");
  w.Size(mesh.nodeBlocks.size());
  w.Size(numNodes);
  w.Size(numNodes ? minTag : 0);
  w.Size(maxTag);
  w.EndLine();
  for (const auto& b : mesh.nodeBlocks) {
    w.Int(b.dim);
    w.Int(b.tag);
    w.Int(0);
    w.Size(b.tags.size());
    w.EndLine();
    for (const auto t : b.tags) {
      w.Size(t);
      w.EndLine();
    }
    for (const Vec3& x : b.xyz) {
      for (const double c : x) w.Real(c);
      w.EndLine();
    }
  }
  w.EndData();
  w.Text("$EndNodes\n");
  std::uint64_t numElements = 0, minElement = ~std::uint64_t{0}, maxElement = 0;
  for (const auto& b : mesh.elementBlocks) {
    numElements += b.tags.size();
    for (const auto t : b.tags) minElement = std::min(minElement, t), maxElement = std::max(maxElement, t);
  }
  w.Text("$Elements\n");
  w.Size(mesh.elementBlocks.size());
  w.Size(numElements);
  w.Size(numElements ? minElement : 0);
  w.Size(maxElement);
  w.EndLine();
  for (const auto& b : mesh.elementBlocks) {
    w.Int(b.dim);
    w.Int(b.tag);
    w.Int(b.type);
    w.Size(b.tags.size());
    w.EndLine();
    for (std::size_t e = 0; e < b.tags.size(); ++e) {
      w.Size(b.tags[e]);
      for (const auto n : b.nodes[e]) w.Size(n);
      w.EndLine();
    }
  }
  w.EndData();
  w.Text("$EndElements\n");
  return w.str();
}

Geometry ReadString(const std::string& text, std::vector<GmshPatchSource>* sources = nullptr) {
  std::istringstream in(text);
  return ReadGmsh(in, "test.msh", sources);
}

// ---------------------------------------------------------------------------
// Cells and reference geometry.

kernels::CellType KernelType(CellType type) {
  switch (type) {
    case CellType::Line:
      return kernels::CellType::Line;
    case CellType::Tri:
      return kernels::CellType::Tri;
    case CellType::Quad:
      return kernels::CellType::Quad;
    case CellType::Tet:
      return kernels::CellType::Tet;
    case CellType::Hex:
      return kernels::CellType::Hex;
    case CellType::Wedge:
      return kernels::CellType::Wedge;
  }
  return kernels::CellType::Line;
}

int ParamDim(CellType type) { return testing::ParamDimOf(KernelType(type)); }

/// Cell c of a BezierCells patch as an independent reference cell.
testing::RefCell CellOf(const Geometry& geometry, const Patch& patch, std::size_t c) {
  testing::RefCell cell;
  cell.type = KernelType(patch.cellTypes[c]);
  cell.degrees = {patch.cellDegrees[3 * c], patch.cellDegrees[3 * c + 1], patch.cellDegrees[3 * c + 2]};
  cell.ambientDim = geometry.dimension;
  cell.points.assign(patch.points.begin() + patch.cellOffsets[c] * geometry.dimension,
                     patch.points.begin() + patch.cellOffsets[c + 1] * geometry.dimension);
  return cell;
}

Vec3 Evaluate(const testing::RefCell& cell, const Vec3& ref) {
  Vec3 x{0, 0, 0};
  testing::RefEvaluate(cell, ref.data(), x.data());
  return x;
}

double Distance(const Vec3& a, const Vec3& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

/// Exponents spanning each element's polynomial space, written down here
/// independently of io/gmsh_elements.cpp. Complete elements: P_p on
/// simplices and their tensor products. Incomplete ones: the lists gmsh 4.8's
/// own shape functions reproduce (found with gmsh::model::mesh::
/// getBasisFunctions, exponents of (u, v, w)); quads and hexes: at most one
/// exponent above 1. gmsh cannot evaluate its incomplete prisms of order 3
/// and 4; invmap's choice extends the 15-node prism's rule.
std::vector<Exponents> SpaceOf(const GmshElementType& type) {
  const int p = type.order;
  std::vector<Exponents> out;
  if (type.incomplete) {
    switch (type.mshType) {
      case 20:
        return {{0, 0, 0}, {0, 1, 0}, {0, 2, 0}, {0, 3, 0}, {1, 0, 0}, {1, 2, 0}, {2, 0, 0}, {2, 1, 0}, {3, 0, 0}};
      case 22:
        return {{0, 0, 0}, {0, 1, 0}, {0, 2, 0}, {0, 3, 0}, {0, 4, 0}, {1, 0, 0},
                {1, 3, 0}, {2, 0, 0}, {2, 2, 0}, {3, 0, 0}, {3, 1, 0}, {4, 0, 0}};
      case 137:
        return {{0, 0, 0}, {0, 0, 1}, {0, 0, 2}, {0, 0, 3}, {0, 1, 0}, {0, 1, 2}, {0, 2, 0}, {0, 2, 1},
                {0, 3, 0}, {1, 0, 0}, {1, 0, 2}, {1, 2, 0}, {2, 0, 0}, {2, 0, 1}, {2, 1, 0}, {3, 0, 0}};
      case 32:
        return {{0, 0, 0}, {0, 0, 1}, {0, 0, 2}, {0, 0, 3}, {0, 0, 4}, {0, 1, 0}, {0, 1, 3}, {0, 2, 0},
                {0, 2, 2}, {0, 3, 0}, {0, 3, 1}, {0, 4, 0}, {1, 0, 0}, {1, 0, 3}, {1, 3, 0}, {2, 0, 0},
                {2, 0, 2}, {2, 2, 0}, {3, 0, 0}, {3, 0, 1}, {3, 1, 0}, {4, 0, 0}};
      case 18:
        return {{0, 0, 0}, {0, 0, 1}, {0, 0, 2}, {0, 1, 0}, {0, 1, 1}, {0, 1, 2}, {0, 2, 0}, {0, 2, 1},
                {1, 0, 0}, {1, 0, 1}, {1, 0, 2}, {1, 1, 0}, {1, 1, 1}, {2, 0, 0}, {2, 0, 1}};
      case 111:
      case 112: {
        // Triangle part: the incomplete triangle space of the same order.
        const std::vector<Exponents> tri =
            p == 3 ? std::vector<Exponents>{{0, 0, 0}, {0, 1, 0}, {0, 2, 0}, {0, 3, 0}, {1, 0, 0},
                                            {1, 2, 0}, {2, 0, 0}, {2, 1, 0}, {3, 0, 0}}
                   : std::vector<Exponents>{{0, 0, 0}, {0, 1, 0}, {0, 2, 0}, {0, 3, 0}, {0, 4, 0}, {1, 0, 0},
                                            {1, 3, 0}, {2, 0, 0}, {2, 2, 0}, {3, 0, 0}, {3, 1, 0}, {4, 0, 0}};
        for (const auto& e : tri) {
          out.push_back({e[0], e[1], 0});
          out.push_back({e[0], e[1], 1});
        }
        for (int c = 2; c <= p; ++c) {
          out.push_back({0, 0, c});
          out.push_back({1, 0, c});
          out.push_back({0, 1, c});
        }
        return out;
      }
      default:
        break;  // quads and hexes below
    }
    const int dims = ParamDim(type.cell);
    for (int c = 0; c <= (dims == 3 ? p : 0); ++c) {
      for (int b = 0; b <= p; ++b) {
        for (int a = 0; a <= p; ++a) {
          if ((a > 1) + (b > 1) + (c > 1) <= 1) out.push_back({a, b, c});
        }
      }
    }
    return out;
  }
  for (int c = 0; c <= p; ++c) {
    for (int b = 0; b <= p; ++b) {
      for (int a = 0; a <= p; ++a) {
        bool in = false;
        switch (type.cell) {
          case CellType::Line:
            in = b == 0 && c == 0;
            break;
          case CellType::Tri:
            in = a + b <= p && c == 0;
            break;
          case CellType::Quad:
            in = c == 0;
            break;
          case CellType::Tet:
            in = a + b + c <= p;
            break;
          case CellType::Hex:
            in = true;
            break;
          case CellType::Wedge:
            in = a + b <= p;
            break;
        }
        if (in) out.push_back({a, b, c});
      }
    }
  }
  return out;
}

/// A random polynomial map R^3 -> R^3 over a set of monomials.
struct PolyMap {
  std::vector<Exponents> exponents;
  std::vector<Vec3> coefficients;
  Vec3 offset{0, 0, 0};

  Vec3 operator()(const Vec3& x) const {
    Vec3 y = offset;
    for (std::size_t i = 0; i < exponents.size(); ++i) {
      const double m =
          std::pow(x[0], exponents[i][0]) * std::pow(x[1], exponents[i][1]) * std::pow(x[2], exponents[i][2]);
      for (int k = 0; k < 3; ++k) y[k] += coefficients[i][k] * m;
    }
    return y;
  }
  /// Largest possible |f - offset| on the unit cube: the error scale.
  double Scale() const {
    double s = 0;
    for (const Vec3& c : coefficients) s += std::abs(c[0]) + std::abs(c[1]) + std::abs(c[2]);
    return s;
  }
};

PolyMap RandomPolyMap(const std::vector<Exponents>& exponents, std::mt19937_64& rng, bool flat) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  PolyMap f;
  f.exponents = exponents;
  for (std::size_t i = 0; i < exponents.size(); ++i) f.coefficients.push_back({u(rng), u(rng), flat ? 0.0 : u(rng)});
  // Far from the origin, so the change of basis must not lose the element's
  // digits to its position.
  f.offset = {1000.0 + u(rng), -2000.0 + u(rng), flat ? 0.0 : 500.0 + u(rng)};
  return f;
}

// ---------------------------------------------------------------------------
// Every element type reproduces polynomial maps of its space.

class ElementTypeTest : public ::testing::TestWithParam<int> {};

TEST_P(ElementTypeTest, ReproducesPolynomialMapsOfItsSpace) {
  const GmshElementType& type = *FindGmshElementType(GetParam());
  const std::vector<Vec3> refNodes = GmshReferenceNodes(type);
  ASSERT_EQ(static_cast<int>(refNodes.size()), type.numNodes);
  const std::vector<Exponents> space = SpaceOf(type);
  ASSERT_EQ(static_cast<int>(space.size()), type.numNodes) << type.name;
  std::mt19937_64 rng(1000 + type.mshType);
  for (const Encoding encoding : {Encoding::Ascii, Encoding::BinaryLittle, Encoding::BinaryBig}) {
    SCOPED_TRACE(EncodingName(encoding));
    // Two elements with their own polynomial maps, nodes numbered from 7 in
    // reverse so tags and indices differ.
    const PolyMap maps[2] = {RandomPolyMap(space, rng, false), RandomPolyMap(space, rng, false)};
    TestMesh mesh;
    mesh.entities.push_back({ParamDim(type.cell), 4, {}});
    TestNodeBlock nodes{ParamDim(type.cell), 4, {}, {}};
    TestElementBlock elements{ParamDim(type.cell), 4, type.mshType, {}, {}};
    const std::uint64_t numNodes = 2 * refNodes.size();
    for (int e = 0; e < 2; ++e) {
      elements.tags.push_back(100 + e);
      elements.nodes.emplace_back();
      for (std::size_t j = 0; j < refNodes.size(); ++j) {
        const std::uint64_t tag = 7 + numNodes - 1 - (e * refNodes.size() + j);
        nodes.tags.push_back(tag);
        nodes.xyz.push_back(maps[e](refNodes[j]));
        elements.nodes.back().push_back(tag);
      }
    }
    mesh.nodeBlocks.push_back(nodes);
    mesh.elementBlocks.push_back(elements);
    const Geometry geometry = ReadString(WriteMsh(mesh, encoding));
    ASSERT_EQ(geometry.dimension, 3);
    ASSERT_EQ(geometry.patches.size(), 1u);
    const Patch& patch = geometry.patches[0];
    ASSERT_EQ(patch.kind, Patch::Kind::BezierCells);
    ASSERT_EQ(patch.cellTypes.size(), 2u);
    for (int e = 0; e < 2; ++e) {
      EXPECT_EQ(patch.cellTypes[e], type.cell);
      const testing::RefCell cell = CellOf(geometry, patch, e);
      ASSERT_EQ(cell.points.size(), static_cast<std::size_t>(BernsteinCount(type.cell, type.order)) * 3);
      for (int k = 0; k < kernels::CellShape::NumFactorsOf(cell.type); ++k) EXPECT_EQ(cell.degrees[k], type.order);
      double worst = 0;
      for (int i = 0; i < 200; ++i) {
        const Vec3 ref = testing::RandomRefPoint(cell.type, rng);
        worst = std::max(worst, Distance(Evaluate(cell, ref), maps[e](ref)));
      }
      // The nodes themselves are interpolated too.
      for (const Vec3& ref : refNodes) worst = std::max(worst, Distance(Evaluate(cell, ref), maps[e](ref)));
      EXPECT_LE(worst, 1e-12 * (maps[e].Scale() + 1)) << type.name << " element " << e;
    }
  }
}

std::string TypeName(const ::testing::TestParamInfo<int>& info) {
  std::string name = FindGmshElementType(info.param)->name;
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return "type" + std::to_string(info.param) + "_" + name;
}

std::vector<int> AllTypeNumbers() {
  std::vector<int> out;
  for (const GmshElementType& t : GmshElementTypes()) out.push_back(t.mshType);
  return out;
}

INSTANTIATE_TEST_SUITE_P(AllTypes, ElementTypeTest, ::testing::ValuesIn(AllTypeNumbers()), TypeName);

TEST(GmshElements, TableCoversOrdersOneToFourOfEverySupportedFamily) {
  // Complete and incomplete element types as numbered in gmsh's GmshDefines.h.
  const std::map<int, std::tuple<CellType, int, bool, int>> expected = {
      {1, {CellType::Line, 1, false, 2}},    {8, {CellType::Line, 2, false, 3}},
      {26, {CellType::Line, 3, false, 4}},   {27, {CellType::Line, 4, false, 5}},
      {2, {CellType::Tri, 1, false, 3}},     {9, {CellType::Tri, 2, false, 6}},
      {21, {CellType::Tri, 3, false, 10}},   {23, {CellType::Tri, 4, false, 15}},
      {20, {CellType::Tri, 3, true, 9}},     {22, {CellType::Tri, 4, true, 12}},
      {3, {CellType::Quad, 1, false, 4}},    {10, {CellType::Quad, 2, false, 9}},
      {36, {CellType::Quad, 3, false, 16}},  {37, {CellType::Quad, 4, false, 25}},
      {16, {CellType::Quad, 2, true, 8}},    {39, {CellType::Quad, 3, true, 12}},
      {40, {CellType::Quad, 4, true, 16}},   {4, {CellType::Tet, 1, false, 4}},
      {11, {CellType::Tet, 2, false, 10}},   {29, {CellType::Tet, 3, false, 20}},
      {30, {CellType::Tet, 4, false, 35}},   {137, {CellType::Tet, 3, true, 16}},
      {32, {CellType::Tet, 4, true, 22}},    {5, {CellType::Hex, 1, false, 8}},
      {12, {CellType::Hex, 2, false, 27}},   {92, {CellType::Hex, 3, false, 64}},
      {93, {CellType::Hex, 4, false, 125}},  {17, {CellType::Hex, 2, true, 20}},
      {99, {CellType::Hex, 3, true, 32}},    {100, {CellType::Hex, 4, true, 44}},
      {6, {CellType::Wedge, 1, false, 6}},   {13, {CellType::Wedge, 2, false, 18}},
      {90, {CellType::Wedge, 3, false, 40}}, {91, {CellType::Wedge, 4, false, 75}},
      {18, {CellType::Wedge, 2, true, 15}},  {111, {CellType::Wedge, 3, true, 24}},
      {112, {CellType::Wedge, 4, true, 33}},
  };
  EXPECT_EQ(GmshElementTypes().size(), expected.size());
  for (const auto& [number, want] : expected) {
    const GmshElementType* t = FindGmshElementType(number);
    ASSERT_NE(t, nullptr) << number;
    EXPECT_EQ(std::make_tuple(t->cell, t->order, t->incomplete, t->numNodes), want) << number;
  }
  for (const int other : {7, 14, 15, 19, 28, 31, 118, 0, -1, 1000}) EXPECT_EQ(FindGmshElementType(other), nullptr);
}

/// Node lattices copied from gmsh 4.8: getElementProperties for the reference
/// elements it can build, nodes of generated meshes for the prisms of order
/// 3 and 4 (for which that call fails). Entries are reference coordinates times the order (invmap's
/// [0, 1] coordinates; gmsh's [-1, 1] ones are mapped).
TEST(GmshElements, NodeOrderMatchesGmshReferenceElements) {
  const std::map<int, std::vector<Exponents>> lattices = {
      {26, {{0, 0, 0}, {3, 0, 0}, {1, 0, 0}, {2, 0, 0}}},
      {23,
       {{0, 0, 0},
        {4, 0, 0},
        {0, 4, 0},
        {1, 0, 0},
        {2, 0, 0},
        {3, 0, 0},
        {3, 1, 0},
        {2, 2, 0},
        {1, 3, 0},
        {0, 3, 0},
        {0, 2, 0},
        {0, 1, 0},
        {1, 1, 0},
        {2, 1, 0},
        {1, 2, 0}}},
      {36,
       {{0, 0, 0},
        {3, 0, 0},
        {3, 3, 0},
        {0, 3, 0},
        {1, 0, 0},
        {2, 0, 0},
        {3, 1, 0},
        {3, 2, 0},
        {2, 3, 0},
        {1, 3, 0},
        {0, 2, 0},
        {0, 1, 0},
        {1, 1, 0},
        {2, 1, 0},
        {2, 2, 0},
        {1, 2, 0}}},
      // The 10-node tetrahedron: node 8 on edge (2, 3), node 9 on edge (1, 3).
      {11,
       {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 0, 2}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {0, 1, 1}, {1, 0, 1}}},
      {29,
       {{0, 0, 0}, {3, 0, 0}, {0, 3, 0}, {0, 0, 3}, {1, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 2, 0}, {0, 2, 0}, {0, 1, 0},
        {0, 0, 2}, {0, 0, 1}, {0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {2, 0, 1}, {1, 1, 0}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}}},
      {12, {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, {0, 0, 2}, {2, 0, 2}, {2, 2, 2}, {0, 2, 2}, {1, 0, 0},
            {0, 1, 0}, {0, 0, 1}, {2, 1, 0}, {2, 0, 1}, {1, 2, 0}, {2, 2, 1}, {0, 2, 1}, {1, 0, 2}, {0, 1, 2},
            {2, 1, 2}, {1, 2, 2}, {1, 1, 0}, {1, 0, 1}, {0, 1, 1}, {2, 1, 1}, {1, 2, 1}, {1, 1, 2}, {1, 1, 1}}},
      {13,
       {{0, 0, 0},
        {2, 0, 0},
        {0, 2, 0},
        {0, 0, 2},
        {2, 0, 2},
        {0, 2, 2},
        {1, 0, 0},
        {0, 1, 0},
        {0, 0, 1},
        {1, 1, 0},
        {2, 0, 1},
        {0, 2, 1},
        {1, 0, 2},
        {0, 1, 2},
        {1, 1, 2},
        {1, 0, 1},
        {0, 1, 1},
        {1, 1, 1}}},
      {90,
       {{0, 0, 0}, {3, 0, 0}, {0, 3, 0}, {0, 0, 3}, {3, 0, 3}, {0, 3, 3}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {0, 2, 0},
        {0, 0, 1}, {0, 0, 2}, {2, 1, 0}, {1, 2, 0}, {3, 0, 1}, {3, 0, 2}, {0, 3, 1}, {0, 3, 2}, {1, 0, 3}, {2, 0, 3},
        {0, 1, 3}, {0, 2, 3}, {2, 1, 3}, {1, 2, 3}, {1, 1, 0}, {1, 1, 3}, {1, 0, 1}, {2, 0, 1}, {2, 0, 2}, {1, 0, 2},
        {0, 1, 1}, {0, 1, 2}, {0, 2, 2}, {0, 2, 1}, {2, 1, 1}, {1, 2, 1}, {1, 2, 2}, {2, 1, 2}, {1, 1, 1}, {1, 1, 2}}},
      {91,
       {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {0, 0, 4}, {4, 0, 4}, {0, 4, 4}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {0, 1, 0},
        {0, 2, 0}, {0, 3, 0}, {0, 0, 1}, {0, 0, 2}, {0, 0, 3}, {3, 1, 0}, {2, 2, 0}, {1, 3, 0}, {4, 0, 1}, {4, 0, 2},
        {4, 0, 3}, {0, 4, 1}, {0, 4, 2}, {0, 4, 3}, {1, 0, 4}, {2, 0, 4}, {3, 0, 4}, {0, 1, 4}, {0, 2, 4}, {0, 3, 4},
        {3, 1, 4}, {2, 2, 4}, {1, 3, 4}, {1, 1, 0}, {1, 2, 0}, {2, 1, 0}, {1, 1, 4}, {2, 1, 4}, {1, 2, 4}, {1, 0, 1},
        {3, 0, 1}, {3, 0, 3}, {1, 0, 3}, {2, 0, 1}, {3, 0, 2}, {2, 0, 3}, {1, 0, 2}, {2, 0, 2}, {0, 1, 1}, {0, 1, 3},
        {0, 3, 3}, {0, 3, 1}, {0, 1, 2}, {0, 2, 3}, {0, 3, 2}, {0, 2, 1}, {0, 2, 2}, {3, 1, 1}, {1, 3, 1}, {1, 3, 3},
        {3, 1, 3}, {2, 2, 1}, {1, 3, 2}, {2, 2, 3}, {3, 1, 2}, {2, 2, 2}, {1, 1, 1}, {1, 1, 3}, {1, 1, 2}, {2, 1, 1},
        {2, 1, 3}, {2, 1, 2}, {1, 2, 1}, {1, 2, 3}, {1, 2, 2}}},
  };
  for (const auto& [number, lattice] : lattices) {
    const GmshElementType& type = *FindGmshElementType(number);
    const std::vector<Vec3> nodes = GmshReferenceNodes(type);
    ASSERT_EQ(nodes.size(), lattice.size()) << type.name;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      for (int k = 0; k < 3; ++k) {
        EXPECT_DOUBLE_EQ(nodes[i][k], static_cast<double>(lattice[i][k]) / type.order) << type.name << " node " << i;
      }
    }
  }
}

TEST(GmshElements, IncompleteSpacesAreGmshs) {
  // tests/io's own lists (SpaceOf) against the reader's rules.
  for (const GmshElementType& type : GmshElementTypes()) {
    std::vector<Exponents> mine = GmshIncompleteMonomials(type);
    std::vector<Exponents> want = type.incomplete ? SpaceOf(type) : std::vector<Exponents>{};
    std::sort(mine.begin(), mine.end());
    std::sort(want.begin(), want.end());
    EXPECT_EQ(mine, want) << type.name;
  }
}

TEST(LagrangeToBernstein, CompleteLinearElementsAreTheIdentityOnVertices) {
  // Degree 1: control points are the vertices; the change of basis only
  // reorders them (quads and hexes: gmsh's counter-clockwise order to the
  // tensor order).
  const LagrangeToBernstein quad(CellType::Quad, 1, GmshReferenceNodes(*FindGmshElementType(3)));
  const int quadOrder[4] = {0, 1, 3, 2};
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) EXPECT_NEAR(quad.coefficient(i, j), j == quadOrder[i] ? 1.0 : 0.0, 1e-15);
  }
}

TEST(LagrangeToBernstein, VertexControlPointsAreTheVertexNodesExactly) {
  // Cells that share a vertex must agree on it bit for bit (the tetrahedral
  // walk pairs faces by their exact corners): coordinates of both signs and
  // of different magnitudes, where arithmetic on them would round.
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-4, 2);
  for (const GmshElementType& type : GmshElementTypes()) {
    SCOPED_TRACE(type.name);
    const std::vector<Vec3> refNodes = GmshReferenceNodes(type);
    const LagrangeToBernstein converter(type.cell, type.order, refNodes, GmshIncompleteMonomials(type));
    std::vector<double> nodes;
    for (std::size_t j = 0; j < refNodes.size(); ++j) {
      for (int k = 0; k < 3; ++k) nodes.push_back(std::ldexp(coordinate(rng), exponent(rng)));
    }
    std::vector<double> control(3 * static_cast<std::size_t>(converter.numControlPoints()));
    converter.Apply(nodes.data(), 3, control.data());
    const std::vector<Vec3> lattice = BernsteinLattice(type.cell, type.order);
    int vertices = 0;
    for (std::size_t i = 0; i < lattice.size(); ++i) {
      if (!std::all_of(lattice[i].begin(), lattice[i].end(), [](double x) { return x == 0.0 || x == 1.0; })) continue;
      const auto node = std::find(refNodes.begin(), refNodes.end(), lattice[i]);
      ASSERT_NE(node, refNodes.end());
      const std::size_t j = static_cast<std::size_t>(node - refNodes.begin());
      for (int k = 0; k < 3; ++k) EXPECT_EQ(control[3 * i + k], nodes[3 * j + k]) << "control point " << i;
      ++vertices;
    }
    EXPECT_GE(vertices, ParamDim(type.cell) + 1);
  }
}

TEST(LagrangeToBernstein, RejectsNodesThatDoNotDetermineThePolynomial) {
  // Six nodes of a quadratic triangle on one line.
  std::vector<Vec3> nodes;
  for (int i = 0; i < 6; ++i) nodes.push_back({i / 5.0, 0, 0});
  EXPECT_THROW(LagrangeToBernstein(CellType::Tri, 2, nodes), std::invalid_argument);
  EXPECT_THROW(LagrangeToBernstein(CellType::Tri, 2, {{0, 0, 0}}), std::invalid_argument);
}

/// A fresh scratch directory for one test's files.
std::filesystem::path ScratchDir(const std::string& name) {
  // The process id keeps concurrent runs (two build trees) apart.
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("invmap_gmsh_test_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// ---------------------------------------------------------------------------
// A small valid file to edit.

/// A valid ascii file of one quadratic triangle: lines are
///  1 $MeshFormat, 2 4.1 0 8, 3 $EndMeshFormat, 4 $Nodes, 5 header,
///  6 block, 7-12 tags, 13-18 coordinates, 19 $EndNodes, 20 $Elements,
///  21 header, 22 block, 23 element, 24 $EndElements.
std::string GoodAscii() {
  TestMesh mesh;
  TestNodeBlock nodes{2, 1, {1, 2, 3, 4, 5, 6}, {}};
  for (const Vec3& ref : GmshReferenceNodes(*FindGmshElementType(9))) nodes.xyz.push_back({ref[0], ref[1], 1.0});
  mesh.nodeBlocks.push_back(nodes);
  mesh.elementBlocks.push_back({2, 1, 9, {1}, {{1, 2, 3, 4, 5, 6}}});
  return WriteMsh(mesh, Encoding::Ascii);
}

std::string ReplaceLine(const std::string& text, int line, const std::string& replacement) {
  std::istringstream in(text);
  std::string out, current;
  for (int i = 1; std::getline(in, current); ++i) out += (i == line ? replacement : current) + "\n";
  return out;
}

// ---------------------------------------------------------------------------
// Patches, dimension, sources.

/// A mesh of one tetrahedron (entity volume 1), its four faces as triangles
/// split over surfaces 1 and 2, and one of its edges (curve 1).
TestMesh TetWithBoundary() {
  TestMesh mesh;
  mesh.nodeBlocks.push_back({3, 1, {1, 2, 3, 4}, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}});
  mesh.elementBlocks.push_back({2, 2, 2, {11, 12}, {{1, 3, 2}, {1, 2, 4}}});
  mesh.elementBlocks.push_back({3, 1, 4, {1}, {{1, 2, 3, 4}}});
  mesh.elementBlocks.push_back({2, 1, 2, {13, 14}, {{1, 4, 3}, {2, 3, 4}}});
  mesh.elementBlocks.push_back({1, 1, 1, {21}, {{1, 2}}});
  mesh.elementBlocks.push_back({0, 1, 15, {31}, {{1}}});
  return mesh;
}

TEST(GmshReader, WithoutPhysicalGroupsOnePatchPerEntityOfTheTopDimension) {
  TestMesh mesh = TetWithBoundary();
  mesh.entities = {{0, 1, {}}, {1, 1, {}}, {2, 1, {}}, {2, 2, {}}, {3, 2, {}}, {3, 1, {}}};
  // A second volume entity, listed before the first in $Entities but whose
  // block comes last: patches follow $Entities.
  mesh.nodeBlocks.push_back({3, 2, {5}, {{1, 1, 1}}});
  mesh.elementBlocks.push_back({3, 2, 4, {2}, {{2, 3, 4, 5}}});
  std::vector<GmshPatchSource> sources;
  const Geometry g = ReadString(WriteMsh(mesh, Encoding::Ascii), &sources);
  EXPECT_EQ(g.dimension, 3);
  ASSERT_EQ(g.patches.size(), 2u);
  ASSERT_EQ(sources.size(), 2u);
  EXPECT_FALSE(sources[0].physicalGroup);
  EXPECT_EQ(std::make_pair(sources[0].dim, sources[0].tag), std::make_pair(3, 2));
  EXPECT_EQ(std::make_pair(sources[1].dim, sources[1].tag), std::make_pair(3, 1));
  EXPECT_EQ(g.patches[0].cellTypes, std::vector<CellType>{CellType::Tet});
  EXPECT_EQ(g.patches[1].cellTypes, std::vector<CellType>{CellType::Tet});
  // Patch 0 is the tet with vertex (1, 1, 1).
  EXPECT_EQ(std::vector<double>(g.patches[0].points.end() - 3, g.patches[0].points.end()),
            (std::vector<double>{1, 1, 1}));
}

TEST(GmshReader, PhysicalGroupsBecomePatchesOfAnyDimension) {
  TestMesh mesh = TetWithBoundary();
  // Surface 1 is in groups 5 ("wall") and 6 (unnamed); surface 2 in 5; the
  // volume in 7 ("body"); the point in 8 (no cells, no patch).
  mesh.entities = {{0, 1, {8}}, {1, 1, {}}, {2, 1, {5, 6}}, {2, 2, {5}}, {3, 1, {7}}};
  mesh.physicalNames = {{3, 7, "body"}, {0, 8, "corner"}, {2, 5, "wall"}};
  for (const Encoding encoding : {Encoding::Ascii, Encoding::BinaryLittle}) {
    std::vector<GmshPatchSource> sources;
    const Geometry g = ReadString(WriteMsh(mesh, encoding), &sources);
    ASSERT_EQ(g.patches.size(), 3u);
    ASSERT_EQ(sources.size(), 3u);
    EXPECT_EQ(sources[0].name, "body");
    EXPECT_TRUE(sources[0].physicalGroup);
    EXPECT_EQ(std::make_pair(sources[0].dim, sources[0].tag), std::make_pair(3, 7));
    EXPECT_EQ(sources[1].name, "wall");
    EXPECT_EQ(std::make_pair(sources[2].dim, sources[2].tag), std::make_pair(2, 6));
    EXPECT_EQ(sources[2].name, "");
    EXPECT_EQ(g.patches[0].cellTypes.size(), 1u);
    // Group 5 holds surface 2's triangles (block 0) then surface 1's (block 2): file order.
    ASSERT_EQ(g.patches[1].cellTypes.size(), 4u);
    EXPECT_EQ(g.patches[1].cellOffsets, (std::vector<std::int64_t>{0, 3, 6, 9, 12}));
    EXPECT_EQ(std::vector<double>(g.patches[1].points.begin(), g.patches[1].points.begin() + 9),
              (std::vector<double>{0, 0, 0, 0, 1, 0, 1, 0, 0}));
    EXPECT_EQ(g.patches[2].cellTypes.size(), 2u);
    EXPECT_EQ(g.patches[1].cellDegrees, (std::vector<int>{1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0}));
  }
}

TEST(GmshReader, FlatMeshesWithoutVolumesAreTwoDimensional) {
  TestMesh mesh;
  const GmshElementType& quad9 = *FindGmshElementType(10);
  TestNodeBlock nodes{2, 1, {}, {}};
  TestElementBlock elements{2, 1, 10, {1}, {{}}};
  for (const Vec3& ref : GmshReferenceNodes(quad9)) {
    nodes.tags.push_back(nodes.tags.size() + 1);
    // A curved quad: x = 2s + t^2, y = t + s t.
    nodes.xyz.push_back({2 * ref[0] + ref[1] * ref[1], ref[1] + ref[0] * ref[1], 0.0});
    elements.nodes[0].push_back(nodes.tags.back());
  }
  mesh.nodeBlocks.push_back(nodes);
  mesh.elementBlocks.push_back(elements);
  Geometry g = ReadString(WriteMsh(mesh, Encoding::Ascii));
  EXPECT_EQ(g.dimension, 2);
  ASSERT_EQ(g.patches.size(), 1u);
  EXPECT_EQ(g.patches[0].points.size(), 9u * 2);
  const testing::RefCell cell = CellOf(g, g.patches[0], 0);
  const Vec3 x = Evaluate(cell, {0.25, 0.5, 0});
  EXPECT_NEAR(x[0], 0.75, 1e-14);
  EXPECT_NEAR(x[1], 0.625, 1e-14);
  // One node off the plane makes it a surface in 3D.
  mesh.nodeBlocks[0].xyz[8][2] = 1e-3;
  g = ReadString(WriteMsh(mesh, Encoding::Ascii));
  EXPECT_EQ(g.dimension, 3);
}

TEST(GmshReader, SkipsParametricCoordinates) {
  // Node block 1 (line 6) stores u, v after x, y, z (Mesh.SaveParametric).
  std::string text = ReplaceLine(GoodAscii(), 6, "2 1 1 6");
  for (int line = 13; line <= 18; ++line) {
    std::istringstream in(text);
    std::string current;
    for (int i = 1; i <= line; ++i) std::getline(in, current);
    text = ReplaceLine(text, line, current + " 0.25 -7");
  }
  const Geometry g = ReadString(text);
  ASSERT_EQ(g.patches.size(), 1u);
  const Vec3 x = Evaluate(CellOf(g, g.patches[0], 0), {0.5, 0.25, 0});
  EXPECT_NEAR(x[0], 0.5, 1e-15);
  EXPECT_NEAR(x[1], 0.25, 1e-15);
  EXPECT_NEAR(x[2], 1.0, 1e-15);
}

TEST(GmshReader, MixedElementTypesShareAPatch) {
  // Every supported type in one entity, each element an affine image of its
  // reference cell: a 1D/2D/3D mixture, so only the volumes make the patch.
  TestMesh mesh;
  TestNodeBlock nodes{3, 1, {}, {}};
  std::vector<int> volumeTypes;
  for (const GmshElementType& type : GmshElementTypes()) {
    TestElementBlock block{3, 1, type.mshType, {static_cast<std::uint64_t>(type.mshType)}, {{}}};
    for (const Vec3& ref : GmshReferenceNodes(type)) {
      nodes.tags.push_back(nodes.tags.size() + 1);
      nodes.xyz.push_back({type.mshType + ref[0], 2 * ref[1], 3 * ref[2]});
      block.nodes[0].push_back(nodes.tags.back());
    }
    mesh.elementBlocks.push_back(block);
    if (ParamDim(type.cell) == 3) volumeTypes.push_back(type.mshType);
  }
  mesh.nodeBlocks.push_back(nodes);
  const Geometry g = ReadString(WriteMsh(mesh, Encoding::BinaryLittle));
  ASSERT_EQ(g.patches.size(), 1u);
  const Patch& patch = g.patches[0];
  ASSERT_EQ(patch.cellTypes.size(), volumeTypes.size());
  std::mt19937_64 rng(5);
  for (std::size_t c = 0; c < volumeTypes.size(); ++c) {
    const testing::RefCell cell = CellOf(g, patch, c);
    EXPECT_EQ(patch.cellTypes[c], FindGmshElementType(volumeTypes[c])->cell);
    const Vec3 ref = testing::RandomRefPoint(cell.type, rng);
    const Vec3 x = Evaluate(cell, ref);
    EXPECT_NEAR(x[0], volumeTypes[c] + ref[0], 1e-12);
    EXPECT_NEAR(x[1], 2 * ref[1], 1e-12);
    EXPECT_NEAR(x[2], 3 * ref[2], 1e-12);
  }
}

TEST(GmshReader, SkipsUnknownSectionsAndReadsFiles) {
  TestMesh mesh = TetWithBoundary();
  std::string ascii = WriteMsh(mesh, Encoding::Ascii);
  ascii += "$NodeData\n1\n\"$EndNodes\"\n1\n0.0\n3\n0\n1\n1\n1 5\n$EndNodeData\n$Comments\nfree text\n$EndComments\n";
  EXPECT_EQ(ReadString(ascii).patches.size(), 1u);
  std::string binary = WriteMsh(mesh, Encoding::BinaryLittle);
  binary.insert(binary.find("$Nodes"), std::string("$Junk\n\x01\x02$End\n\0\xff$EndJu", 16) + "$EndJunk\n");
  EXPECT_EQ(ReadString(binary).patches.size(), 1u);
  // The path overload.
  const std::filesystem::path dir = ScratchDir("path");
  std::ofstream(dir / "mesh.msh", std::ios::binary) << binary;
  EXPECT_EQ(ReadGmsh((dir / "mesh.msh").string()).patches.size(), 1u);
  std::filesystem::remove_all(dir);
}

// ---------------------------------------------------------------------------
// Malformed input: InputError naming the file and (ascii) the line.

/// The InputError that reading `text` throws (fails the test if none).
InputError ErrorOf(const std::string& text) {
  try {
    ReadString(text);
  } catch (const InputError& e) {
    return e;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an InputError: " << e.what();
    return InputError("", 0, "");
  }
  ADD_FAILURE() << "no error for:\n" << text.substr(0, 400);
  return InputError("", 0, "");
}

TEST(GmshReaderErrors, GoodFileReads) { EXPECT_EQ(ReadString(GoodAscii()).patches.size(), 1u); }

TEST(GmshReaderErrors, AsciiProblemsNameTheLine) {
  const std::string good = GoodAscii();
  struct Case {
    std::string text;
    std::int64_t line;
    std::string message;
  };
  const std::vector<Case> cases = {
      {"", 0, "does not start with $MeshFormat"},
      {"$MeshFormat\n2.2 0 8\n$EndMeshFormat\n", 2, "MSH version 2.2 is not supported"},
      {ReplaceLine(good, 2, "4.1 2 8"), 2, "file type must be 0"},
      {ReplaceLine(good, 14, "1 abc 0"), 14, "found 'abc'"},
      {ReplaceLine(good, 14, "1 nan 0"), 14, "not finite"},
      {ReplaceLine(good, 14, "1 0 inf"), 14, "not finite"},
      {ReplaceLine(good, 9, "1"), 9, "defined twice"},
      {ReplaceLine(good, 9, "99"), 9, "outside the header's range"},
      {ReplaceLine(good, 23, "1 1 2 3 4 5 6000"), 23, "refers to node 6000"},
      {ReplaceLine(good, 23, "1 1 2 3 4 5 x"), 23, "found 'x'"},
      {ReplaceLine(good, 23, "1 1 2 3 4 5"), 24, "found '$EndElements'"},
      {ReplaceLine(good, 23, "1 1 2 3 4 5 6 7"), 23, "expected $EndElements, found '7'"},
      {ReplaceLine(good, 5, "1 7 1 6"), 18, "header says 7 nodes"},
      {ReplaceLine(good, 5, "1 5 1 6"), 6, "more nodes than the 5"},
      {ReplaceLine(good, 5, "1 4000000000 1 4000000000"), 5, "exceeds what the remaining"},
      {ReplaceLine(good, 6, "2 1 0 4000000000"), 6, "exceeds what the remaining"},
      {ReplaceLine(good, 21, "1 3000000000 1 3000000000"), 21, "exceeds what the remaining"},
      {ReplaceLine(good, 22, "2 1 9 -1"), 22, "must not be negative"},
      {ReplaceLine(good, 22, "3 1 7 1"), 23, "element 1 is a pyramid (gmsh element type 7)"},
      {ReplaceLine(good, 22, "2 1 25 1"), 23, "element 1 has gmsh element type 25"},
      {ReplaceLine(good, 22, "0 1 15 1"), 23, "expected $EndElements, found '2'"},
      {ReplaceLine(good, 4, "$PartitionedEntities"), 4, "partitioned meshes"},
      {ReplaceLine(good, 4, "$Elements"), 4, "$Elements before $Nodes"},
      {ReplaceLine(good, 20, "$Nodes"), 20, "second $Nodes section"},
      {ReplaceLine(good, 20, "Elements"), 20, "expected a section name"},
      {good.substr(0, good.find("$Elements")), 19, "no $Elements section"},
      {good.substr(0, good.find("$EndNodes")), 18, "unexpected end of file, expected $EndNodes"},
      {good.substr(0, good.find("0.5 0.5")), 16, "unexpected end of file, expected a node coordinate"},
      {good + "$Comments\nnever ends\n", 26, "expected $EndComments"},
  };
  for (const Case& c : cases) {
    const InputError e = ErrorOf(c.text);
    EXPECT_EQ(e.file(), "test.msh");
    EXPECT_EQ(e.line(), c.line) << e.what();
    EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos) << e.what() << "\nexpected: " << c.message;
  }
}

TEST(GmshReaderErrors, PointsOnlyIsNoGeometry) {
  const std::string good = GoodAscii();
  // The triangle's block turned into six point elements.
  std::string text = ReplaceLine(ReplaceLine(good, 21, "1 6 1 6"), 22, "0 1 15 6");
  text = ReplaceLine(text, 23, "1 1\n2 2\n3 3\n4 4\n5 5\n6 6");
  EXPECT_NE(std::string(ErrorOf(text).what()).find("no cells"), std::string::npos);
}

TEST(GmshReaderErrors, BinaryProblemsNameTheOffset) {
  TestMesh mesh;
  mesh.nodeBlocks.push_back({2, 1, {1, 2, 3}, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}});
  mesh.elementBlocks.push_back({2, 1, 2, {1}, {{1, 2, 3}}});
  const std::string good = WriteMsh(mesh, Encoding::BinaryLittle);
  ASSERT_EQ(ReadString(good).patches.size(), 1u);
  const std::size_t nodes = good.find("$Nodes\n") + 7;
  const auto withSize = [&](std::size_t at, std::uint64_t v) {
    std::string t = good;
    std::memcpy(&t[at], &v, 8);
    return t;
  };
  const std::size_t block = nodes + 32;  // after the 4 header size_t
  std::string nanCoordinate = good;
  const double nan = std::nan("");
  std::memcpy(&nanCoordinate[block + 20 + 3 * 8 + 8], &nan, 8);
  std::string badOrder = good;
  badOrder[good.find("4.1 1 8\n") + 8] = 2;
  const std::vector<std::pair<std::string, std::string>> cases = {
      {good.substr(0, nodes + 50), "node block count 1 exceeds what the remaining 18 bytes"},
      {good.substr(0, nodes + 20), "unexpected end of file, expected the minimum node tag"},
      // Counts are checked against the exact size of the data they announce.
      {good.substr(0, good.find("$EndNodes") - 10), "node count 3 exceeds what the remaining 87 bytes"},
      {good.substr(0, good.find("$EndElements") - 3), "element count 1 exceeds what the remaining 30 bytes"},
      {withSize(nodes + 8, std::uint64_t{1} << 40), "exceeds what the remaining"},
      {withSize(nodes, std::uint64_t{1} << 62), "exceeds what the remaining"},
      {withSize(block + 12, 1000000), "exceeds what the remaining"},
      {withSize(block + 20, 3), "defined twice"},
      {nanCoordinate, "not finite"},
      {badOrder, "byte-order integer"},
      {ReplaceLine(good, 2, "4.1 1 4"), "data size 4"},
  };
  for (const auto& [text, message] : cases) {
    const InputError e = ErrorOf(text);
    if (message != "data size 4") {
      EXPECT_EQ(e.line(), 0) << e.what();
    }
    EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what() << "\nexpected: " << message;
  }
}

TEST(GmshReaderErrors, EveryTruncationAndCorruptionIsAnInputError) {
  // Every prefix of an ascii and a binary file, and random byte flips of the
  // binary one, either read or throw InputError: never a crash, a hang or
  // another exception.
  const std::string ascii = GoodAscii();
  TestMesh mesh = TetWithBoundary();
  mesh.entities = {{0, 1, {8}}, {1, 1, {}}, {2, 1, {5, 6}}, {2, 2, {5}}, {3, 1, {7}}};
  mesh.physicalNames = {{3, 7, "body"}, {2, 5, "wall"}};
  const std::string binary = WriteMsh(mesh, Encoding::BinaryLittle);
  // Any exception other than InputError escapes and fails the test.
  const auto reads = [](const std::string& text) {
    try {
      ReadString(text);
      return true;
    } catch (const InputError&) {
      return false;
    }
  };
  std::mt19937_64 rng(11);
  for (const std::string* file : {&ascii, &binary}) {
    int prefixesRead = 0;
    for (std::size_t n = 0; n < file->size(); ++n) prefixesRead += reads(file->substr(0, n));
    // Only the file without its final newline is whole.
    EXPECT_LE(prefixesRead, 1);
    for (int trial = 0; trial < 2000; ++trial) {
      std::string t = *file;
      const int flips = 1 + static_cast<int>(rng() % 3);
      for (int f = 0; f < flips; ++f) t[rng() % t.size()] = static_cast<char>(rng());
      reads(t);
    }
  }
}

TEST(GmshReaderErrors, MissingFile) { EXPECT_THROW(ReadGmsh("/nonexistent/dir/mesh.msh"), InputError); }

// ---------------------------------------------------------------------------
// Meshes generated by the gmsh binary.

bool HaveGmsh() {
  static const bool have = std::system("gmsh -version > /dev/null 2>&1") == 0;
  return have;
}

/// Runs gmsh on a .geo script; returns the output path (empty on failure).
std::string RunGmsh(const std::filesystem::path& dir, const std::string& name, const std::string& geo,
                    const std::string& options) {
  const std::filesystem::path script = dir / (name + ".geo");
  const std::filesystem::path out = dir / (name + ".msh");
  std::ofstream(script) << geo;
  const std::string command = "gmsh " + script.string() + " -format msh41 -v 0 " + options + " -o " + out.string() +
                              " > " + (dir / (name + ".log")).string() + " 2>&1";
  return std::system(command.c_str()) == 0 ? out.string() : std::string();
}

/// Elements of a gmsh ascii MSH 4.1 file, read by the simplest possible
/// parser (no entities, no checks): type and node coordinates per element.
struct RawElement {
  int type = 0;
  std::vector<Vec3> nodes;
};

std::vector<RawElement> ReadRawElements(const std::string& path) {
  std::ifstream in(path);
  std::string token;
  std::map<std::uint64_t, Vec3> nodes;
  std::vector<RawElement> out;
  while (in >> token) {
    if (token == "$Nodes") {
      std::uint64_t blocks, n, lo, hi;
      in >> blocks >> n >> lo >> hi;
      for (std::uint64_t b = 0; b < blocks; ++b) {
        int dim, tag, parametric;
        std::uint64_t count;
        in >> dim >> tag >> parametric >> count;
        std::vector<std::uint64_t> tags(count);
        for (auto& t : tags) in >> t;
        for (const auto t : tags) {
          Vec3& x = nodes[t];
          in >> x[0] >> x[1] >> x[2];
          double skip;
          for (int k = 0; k < (parametric ? dim : 0); ++k) in >> skip;
        }
      }
    } else if (token == "$Elements") {
      std::uint64_t blocks, n, lo, hi;
      in >> blocks >> n >> lo >> hi;
      for (std::uint64_t b = 0; b < blocks; ++b) {
        int dim, tag, type;
        std::uint64_t count;
        in >> dim >> tag >> type >> count;
        const GmshElementType* t = FindGmshElementType(type);
        const int numNodes = t != nullptr ? t->numNodes : 1;
        for (std::uint64_t e = 0; e < count; ++e) {
          RawElement element;
          element.type = type;
          std::uint64_t id, node;
          in >> id;
          for (int k = 0; k < numNodes; ++k) {
            in >> node;
            element.nodes.push_back(nodes.at(node));
          }
          out.push_back(element);
        }
      }
    }
  }
  return out;
}

/// The order-1 map of an element from its vertices (gmsh's vertex order):
/// affine on simplices, multilinear on quads and hexes, affine times linear
/// on prisms. A straight-sided high-order element has exactly this map.
Vec3 VertexMap(CellType cell, const std::vector<Vec3>& v, const Vec3& ref) {
  const double s = ref[0], t = ref[1], r = ref[2];
  std::vector<double> w;
  switch (cell) {
    case CellType::Line:
      w = {1 - s, s};
      break;
    case CellType::Tri:
      w = {1 - s - t, s, t};
      break;
    case CellType::Quad:
      w = {(1 - s) * (1 - t), s * (1 - t), s * t, (1 - s) * t};
      break;
    case CellType::Tet:
      w = {1 - s - t - r, s, t, r};
      break;
    case CellType::Hex:
      w = {(1 - s) * (1 - t) * (1 - r), s * (1 - t) * (1 - r), s * t * (1 - r), (1 - s) * t * (1 - r),
           (1 - s) * (1 - t) * r,       s * (1 - t) * r,       s * t * r,       (1 - s) * t * r};
      break;
    case CellType::Wedge:
      w = {(1 - s - t) * (1 - r), s * (1 - r), t * (1 - r), (1 - s - t) * r, s * r, t * r};
      break;
  }
  Vec3 x{0, 0, 0};
  for (std::size_t i = 0; i < w.size(); ++i) {
    for (int k = 0; k < 3; ++k) x[k] += w[i] * v[i][k];
  }
  return x;
}

/// A family of element types that gmsh meshes a straight-sided domain with.
struct Family {
  const char* name;
  CellType cell;
};

void PrintTo(const Family& f, std::ostream* os) { *os << f.name; }

/// A flat 2 x 1 rectangle meshed with unstructured triangles (or recombined
/// into quads), optionally extruded into one slab of two layers: tets,
/// prisms, hexes. Elements come in many orientations.
std::string RectangleGeo(bool recombine, int extrude, bool recombineVolume) {
  std::string geo =
      "Point(1) = {0, 0, 0}; Point(2) = {2, 0, 0}; Point(3) = {2, 1, 0}; Point(4) = {0, 1, 0};\n"
      "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
      "Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\n"
      "Mesh.MeshSizeMax = 0.6;\n";
  if (recombine) geo += "Recombine Surface{1};\n";
  if (extrude > 0) {
    geo += "Extrude {0, 0, 0.7} { Surface{1}; Layers{" + std::to_string(extrude) + "};" +
           (recombineVolume ? " Recombine;" : "") + " }\n";
  }
  return geo;
}

class GmshGeneratedTest : public ::testing::TestWithParam<Family> {};

TEST_P(GmshGeneratedTest, NodesLandWhereTheNodeOrderingSays) {
  if (!HaveGmsh()) GTEST_SKIP() << "the gmsh binary is not installed (Debian package gmsh)";
  const Family& family = GetParam();
  const std::filesystem::path dir = ScratchDir(std::string("ordering_") + family.name);
  const int paramDim = ParamDim(family.cell);
  const bool recombine = family.cell == CellType::Quad || family.cell == CellType::Hex;
  const std::string geo = RectangleGeo(recombine, paramDim == 3 ? 2 : 0, family.cell != CellType::Tet);
  // The linear element of the family: its nodes are the vertices.
  const GmshElementType* linear = nullptr;
  for (const GmshElementType& type : GmshElementTypes()) {
    if (type.cell == family.cell && type.order == 1) linear = &type;
  }
  std::mt19937_64 rng(3);
  std::map<int, int> seenTypes;
  for (int order = 1; order <= 4; ++order) {
    for (const bool incomplete : {false, true}) {
      if (incomplete && order == 1) continue;
      const std::string name = std::string(family.name) + std::to_string(order) + (incomplete ? "i" : "");
      SCOPED_TRACE(name);
      const std::string path = RunGmsh(dir, name, geo,
                                       "-" + std::to_string(paramDim) + " -order " + std::to_string(order) +
                                           (incomplete ? " -setnumber Mesh.SecondOrderIncomplete 1" : ""));
      ASSERT_FALSE(path.empty()) << "gmsh failed, see " << (dir / (name + ".log"));
      // 1. Every node of every element sits where GmshReferenceNodes puts it
      // under the element's vertex map.
      int checked = 0;
      for (const RawElement& element : ReadRawElements(path)) {
        const GmshElementType* type = FindGmshElementType(element.type);
        if (type == nullptr || type->cell != family.cell) continue;
        ++seenTypes[type->mshType];
        EXPECT_EQ(type->order, order);
        const std::vector<Vec3> refNodes = GmshReferenceNodes(*type);
        for (std::size_t j = 0; j < refNodes.size(); ++j) {
          const Vec3 want = VertexMap(type->cell, element.nodes, refNodes[j]);
          ASSERT_LE(Distance(element.nodes[j], want), 1e-9) << type->name << " node " << j;
        }
        ++checked;
      }
      EXPECT_GT(checked, 3);
      // 2. The reader's cells are the straight-sided elements: the map of
      // the vertices (the cells' values at the reference vertices).
      const Geometry g = ReadGmsh(path);
      ASSERT_FALSE(g.patches.empty());
      for (const Patch& patch : g.patches) {
        for (std::size_t c = 0; c < patch.cellTypes.size(); ++c) {
          ASSERT_EQ(patch.cellTypes[c], family.cell);
          const testing::RefCell cell = CellOf(g, patch, c);
          std::vector<Vec3> vertices;
          for (const Vec3& ref : GmshReferenceNodes(*linear)) vertices.push_back(Evaluate(cell, ref));
          for (int i = 0; i < 5; ++i) {
            const Vec3 ref = testing::RandomRefPoint(cell.type, rng);
            ASSERT_LE(Distance(Evaluate(cell, ref), VertexMap(family.cell, vertices, ref)), 1e-10) << "cell " << c;
          }
        }
      }
    }
  }
  // gmsh produced every type of the family in the table.
  for (const GmshElementType& type : GmshElementTypes()) {
    if (type.cell != family.cell) continue;
    EXPECT_GT(seenTypes[type.mshType], 0) << type.name << " (type " << type.mshType << ") not generated";
  }
  std::filesystem::remove_all(dir);
}

std::string FamilyName(const ::testing::TestParamInfo<Family>& param) { return param.param.name; }

INSTANTIATE_TEST_SUITE_P(Families, GmshGeneratedTest,
                         ::testing::Values(Family{"line", CellType::Line}, Family{"tri", CellType::Tri},
                                           Family{"quad", CellType::Quad}, Family{"tet", CellType::Tet},
                                           Family{"hex", CellType::Hex}, Family{"prism", CellType::Wedge}),
                         FamilyName);

/// A unit ball (OpenCASCADE sphere) with its volume and surface as physical groups.
const char* kBallGeo =
    "SetFactory(\"OpenCASCADE\");\n"
    "Sphere(1) = {0, 0, 0, 1};\n"
    "Physical Volume(\"ball\") = {1};\n"
    "Physical Surface(\"skin\") = {1};\n"
    "Mesh.MeshSizeMax = 0.45;\n";

struct BallCase {
  int order;
  bool incomplete;
  bool binary;
  int volumeType;      ///< gmsh type of the tetrahedra.
  int surfaceType;     ///< gmsh type of the boundary triangles.
  double sphereError;  ///< Bound on | |x| - 1 | over the boundary cells (interpolation error).
};

class GmshBallTest : public ::testing::TestWithParam<BallCase> {};

void PrintTo(const BallCase& c, std::ostream* os) {
  *os << "order " << c.order << (c.incomplete ? " incomplete" : "") << (c.binary ? " binary" : " ascii");
}

std::string BallName(const ::testing::TestParamInfo<BallCase>& param) {
  return "order" + std::to_string(param.param.order) + (param.param.incomplete ? "_incomplete" : "") +
         (param.param.binary ? "_binary" : "_ascii");
}

TEST_P(GmshBallTest, CurvedTetsInvertToThemselves) {
  if (!HaveGmsh()) GTEST_SKIP() << "the gmsh binary is not installed (Debian package gmsh)";
  const BallCase& param = GetParam();
  const std::string name =
      "ball" + std::to_string(param.order) + (param.incomplete ? "i" : "") + (param.binary ? "b" : "");
  const std::filesystem::path dir = ScratchDir(name);
  const std::string path = RunGmsh(dir, name, kBallGeo,
                                   "-3 -order " + std::to_string(param.order) + (param.binary ? " -bin" : "") +
                                       (param.incomplete ? " -setnumber Mesh.SecondOrderIncomplete 1" : ""));
  ASSERT_FALSE(path.empty()) << "gmsh failed, see " << (dir / (name + ".log"));

  std::vector<GmshPatchSource> sources;
  const Geometry g = ReadGmsh(path, &sources);
  ASSERT_EQ(g.dimension, 3);
  // $PhysicalNames order: gmsh writes the surface group first.
  ASSERT_EQ(g.patches.size(), 2u);
  const int volumePatch = sources[0].name == "ball" ? 0 : 1;
  EXPECT_EQ(sources[volumePatch].name, "ball");
  EXPECT_EQ(sources[volumePatch].dim, 3);
  EXPECT_EQ(sources[1 - volumePatch].name, "skin");
  const Patch& volume = g.patches[volumePatch];
  const Patch& skin = g.patches[1 - volumePatch];
  ASSERT_GT(volume.cellTypes.size(), 50u);
  for (std::size_t c = 0; c < volume.cellTypes.size(); ++c) {
    ASSERT_EQ(volume.cellTypes[c], CellType::Tet);
    ASSERT_EQ(volume.cellDegrees[3 * c], param.order);
  }
  if (!param.binary) {
    int tets = 0;
    for (const RawElement& e : ReadRawElements(path)) tets += e.type == param.volumeType;
    EXPECT_EQ(tets, static_cast<int>(volume.cellTypes.size()));
  }

  // The boundary cells follow the sphere: they interpolate their nodes,
  // which gmsh put on it, and stay within the interpolation error between.
  std::mt19937_64 rng(17 + param.order);
  const auto radius = [](const Vec3& x) { return std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]); };
  const std::vector<Vec3> skinNodes = GmshReferenceNodes(*FindGmshElementType(param.surfaceType));
  double nodeError = 0, sphereError = 0;
  for (std::size_t c = 0; c < skin.cellTypes.size(); ++c) {
    const testing::RefCell cell = CellOf(g, skin, c);
    for (const Vec3& ref : skinNodes) nodeError = std::max(nodeError, std::abs(radius(Evaluate(cell, ref)) - 1));
    for (int i = 0; i < 10; ++i) {
      const Vec3 x = Evaluate(cell, testing::RandomRefPoint(cell.type, rng));
      sphereError = std::max(sphereError, std::abs(radius(x) - 1));
    }
  }
  EXPECT_LE(nodeError, 1e-12);
  EXPECT_LE(sphereError, param.sphereError);

  // Neighbouring tetrahedra share their corner control points exactly, so
  // the walk's face adjacency pairs every face inside the ball: only the
  // faces on the skin, one per skin triangle, stay unpaired.
  ASSERT_FALSE(engine::ValidateGeometry(g)) << Describe(engine::ValidateGeometry(g));
  const engine::CellStore store = engine::CellStore::Build(g, 0);
  std::int64_t unpaired = 0;
  for (std::int64_t c = 0; c < store.size(); ++c) {
    if (!store.solver(c).isTetrahedron()) continue;
    for (int face = 0; face < 4; ++face) unpaired += store.faceAdjacency().Neighbor(c, face) < 0 ? 1 : 0;
  }
  EXPECT_EQ(unpaired, static_cast<std::int64_t>(skin.cellTypes.size()));

  // Points mapped from random cells and reference points come back to a cell
  // that maps its reported parameters onto them, at distance 0.
  BuildResult built = Manifold::Build(g);
  ASSERT_TRUE(built.error.empty()) << built.error;
  const int numQueries = 2000;
  std::vector<double> xyz;
  std::vector<std::size_t> sourceCell;
  std::vector<Vec3> sourceRef;
  std::uniform_int_distribution<std::size_t> pick(0, volume.cellTypes.size() - 1);
  for (int i = 0; i < numQueries; ++i) {
    const std::size_t c = pick(rng);
    const Vec3 ref = testing::RandomRefPoint(kernels::CellType::Tet, rng);
    const Vec3 x = Evaluate(CellOf(g, volume, c), ref);
    xyz.insert(xyz.end(), x.begin(), x.end());
    sourceCell.push_back(c);
    sourceRef.push_back(ref);
  }
  Results results;
  ASSERT_EQ(built.manifold.Invert(PointsView::Interleaved(xyz.data(), numQueries, 3), {}, &results), Error::Ok);
  int sameCell = 0;
  for (int i = 0; i < numQueries; ++i) {
    SCOPED_TRACE("query " + std::to_string(i));
    ASSERT_EQ(results.status[i], Status::Found);
    EXPECT_LE(results.distance[i], 1e-9);
    const Vec3 x{xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
    const Patch& patch = g.patches[results.patch[i]];
    const testing::RefCell cell = CellOf(g, patch, static_cast<std::size_t>(results.cell[i]));
    const Vec3 ref{results.params[3 * i], results.params[3 * i + 1],
                   ParamDim(patch.cellTypes[results.cell[i]]) == 3 ? results.params[3 * i + 2] : 0.0};
    EXPECT_TRUE(testing::InReferenceDomain(cell.type, ref.data(), 1e-9));
    EXPECT_LE(Distance(Evaluate(cell, ref), x), 1e-9);
    if (results.patch[i] == volumePatch && static_cast<std::size_t>(results.cell[i]) == sourceCell[i]) {
      ++sameCell;
      EXPECT_LE(Distance(ref, sourceRef[i]), 1e-6);
    }
  }
  // Most points are interior to their own cell; the others lie where cells
  // touch and belong to a neighbour as much.
  EXPECT_GT(sameCell, numQueries * 9 / 10);
  std::filesystem::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Orders, GmshBallTest,
                         ::testing::Values(BallCase{2, false, false, 11, 9, 1e-3},
                                           BallCase{2, false, true, 11, 9, 1e-3},
                                           BallCase{3, false, false, 29, 21, 1e-3},
                                           BallCase{3, true, false, 137, 20, 1e-2},
                                           BallCase{4, false, true, 30, 23, 1e-4}),
                         BallName);

}  // namespace
}  // namespace invmap::io
