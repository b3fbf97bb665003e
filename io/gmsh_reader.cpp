#include "io/gmsh_reader.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <istream>
#include <limits>
#include <map>
#include <memory>
#include <string_view>
#include <unordered_map>
#include <utility>

#include "io/file_io.h"
#include "io/gmsh_elements.h"
#include "io/input_error.h"
#include "io/lagrange_to_bernstein.h"

namespace invmap::io {
namespace {

/// An elementary entity of $Entities with its physical tags.
struct Entity {
  int dim = 0;
  int tag = 0;
  std::vector<int> physicalTags;
};

/// One block of $Elements that carries cells (point blocks are dropped).
struct ElementBlock {
  int entityDim = 0;
  int entityTag = 0;
  const GmshElementType* type = nullptr;
  std::int64_t count = 0;
  std::size_t firstNode = 0;  ///< Offset of its first element's nodes in MeshData::elementNodes.
};

/// Everything the sections of a file say that the geometry needs.
struct MeshData {
  std::vector<std::pair<int, int>> physicalKeys;  ///< (dim, tag) of $PhysicalNames, file order.
  std::vector<std::string> physicalNames;         ///< Parallel to physicalKeys.
  std::vector<Entity> entities;                   ///< $Entities: points, curves, surfaces, volumes.
  std::vector<double> nodes;                      ///< 3 coordinates per node, file order.
  std::vector<std::int64_t> elementNodes;         ///< Node indices (into nodes / 3) of every cell element.
  std::vector<ElementBlock> blocks;
  bool anyVolume = false;
  std::vector<GmshNodeView> nodeViews;  ///< $NodeData, the last time step of each view.
};

/// Maps node tags to node indices: a dense table when the tags are compact
/// (the usual 1..n), a hash map otherwise, so a huge maximum tag costs no memory.
class NodeIndex {
 public:
  /// `maxTag` bounds every tag. `countChecked`: the caller checked `count`
  /// against the file size; without that bound (a pipe) a claimed count
  /// proves nothing, and only a modest table is allocated up front.
  NodeIndex(std::uint64_t maxTag, std::uint64_t count, bool countChecked) {
    denseMode_ = maxTag <= 2 * count + 1024 && (countChecked || maxTag < (std::uint64_t{1} << 24));
    if (denseMode_) dense_.assign(static_cast<std::size_t>(maxTag) + 1, -1);
  }
  /// False when the tag is already defined.
  bool Insert(std::uint64_t tag, std::int64_t index) {
    if (denseMode_) {
      if (dense_[tag] >= 0) return false;
      dense_[tag] = index;
      return true;
    }
    return sparse_.emplace(tag, index).second;
  }
  /// Index of the node, -1 when no node has that tag.
  std::int64_t Find(std::uint64_t tag) const {
    if (denseMode_) return tag < dense_.size() ? dense_[tag] : -1;
    const auto it = sparse_.find(tag);
    return it == sparse_.end() ? -1 : it->second;
  }

 private:
  bool denseMode_ = false;
  std::vector<std::int64_t> dense_;
  std::unordered_map<std::uint64_t, std::int64_t> sparse_;
};

/// White space between ascii tokens.
bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

/// `s` without leading and trailing white space.
std::string_view Trim(std::string_view s) {
  while (!s.empty() && IsSpace(s.front())) s.remove_prefix(1);
  while (!s.empty() && IsSpace(s.back())) s.remove_suffix(1);
  return s;
}

/// Parses the sections of one MSH 4.1 file. Values are read through one set
/// of functions for both encodings (Int, Size, Real): the 4.1 binary layout
/// stores the same values in the same order as the ascii one.
class GmshParser {
 public:
  /// Reads from `in`, which must outlive the parser.
  explicit GmshParser(InputBuffer& in) : in_(in) {}

  /// Reads the whole input. Throws InputError.
  MeshData Parse() {
    std::string_view token;
    if (!NextToken(&token) || token != "$MeshFormat") {
      Fail("not a gmsh mesh: the file does not start with $MeshFormat");
    }
    ReadMeshFormat();
    bool haveNodes = false, haveElements = false, haveEntities = false, havePhysicalNames = false;
    while (NextToken(&token)) {
      if (token == "$PhysicalNames") {
        Once(&havePhysicalNames, token);
        ReadPhysicalNames();
      } else if (token == "$Entities") {
        Once(&haveEntities, token);
        ReadEntities();
      } else if (token == "$Nodes") {
        Once(&haveNodes, token);
        ReadNodes();
      } else if (token == "$Elements") {
        Once(&haveElements, token);
        if (!haveNodes) Fail("$Elements before $Nodes");
        ReadElements();
      } else if (token == "$NodeData") {
        if (!haveNodes) Fail("$NodeData before $Nodes");
        ReadNodeData();
      } else if (token == "$PartitionedEntities") {
        Fail("partitioned meshes ($PartitionedEntities) are not supported: save the mesh without partitions");
      } else if (token.size() > 1 && token[0] == '$' && token.substr(0, 4) != "$End") {
        SkipSection(std::string(token.substr(1)));
      } else {
        Fail("expected a section name such as $Nodes, found '" + Shorten(token) + "'");
      }
    }
    if (!haveElements) Fail("no $Elements section");
    return std::move(mesh_);
  }

 private:
  // ----- errors -----

  /// Throws InputError: ascii files name the line of the last token, binary
  /// ones the byte offset (their lines mean nothing).
  [[noreturn]] void Fail(const std::string& message) const {
    if (binary_) throw InputError(in_.name(), 0, message + " (near byte " + std::to_string(in_.offset()) + ")");
    throw InputError(in_.name(), tokenLine_, message);
  }

  /// A token quoted in a message, cut to a readable length.
  static std::string Shorten(std::string_view token) {
    return token.size() <= 40 ? std::string(token) : std::string(token.substr(0, 40)) + "...";
  }

  /// Refuses a section that appears a second time.
  void Once(bool* seen, std::string_view section) {
    if (*seen) Fail("second " + std::string(section) + " section");
    *seen = true;
  }

  /// Refuses a count whose entries, at `minBytes` each, cannot fit in the
  /// rest of the input: such a count comes from a corrupt file and must not
  /// drive an allocation.
  void CheckCount(std::uint64_t count, std::uint64_t minBytes, const std::string& what) const {
    const std::int64_t remaining = in_.remaining();
    if (remaining >= 0 && count > static_cast<std::uint64_t>(remaining) / minBytes) {
      Fail(what + " count " + std::to_string(count) + " exceeds what the remaining " + std::to_string(remaining) +
           " bytes of the file can hold");
    }
  }

  /// How many entries of `count` to reserve for: all when the input size
  /// bounds them (CheckCount passed), a modest start for a pipe.
  std::size_t ReserveFor(std::uint64_t count) const {
    return static_cast<std::size_t>(in_.remaining() >= 0 ? count : std::min<std::uint64_t>(count, 1 << 16));
  }

  /// Smallest encoding of a value: its bytes in binary, one character plus a
  /// separator in ascii.
  std::uint64_t MinBytes(std::uint64_t binaryBytes) const { return binary_ ? binaryBytes : 2; }

  // ----- text -----

  /// Next white-space separated token of the text, across lines. False at
  /// the end of the input.
  bool NextToken(std::string_view* token) {
    for (;;) {
      rest_ = Trim(rest_);
      if (!rest_.empty()) {
        std::size_t n = 0;
        while (n < rest_.size() && !IsSpace(rest_[n])) ++n;
        *token = rest_.substr(0, n);
        rest_.remove_prefix(n);
        tokenLine_ = restLine_;
        return true;
      }
      if (!in_.ReadLine(&rest_)) return false;
      restLine_ = in_.lineNumber();
    }
  }

  /// The next token; `what` names it in the end-of-file error.
  std::string_view Token(const char* what) {
    std::string_view token;
    if (!NextToken(&token)) Fail(std::string("unexpected end of file, expected ") + what);
    return token;
  }

  /// The next token as a decimal integer.
  std::int64_t TextInt(const char* what) {
    const std::string_view token = Token(what);
    std::int64_t value = 0;
    if (!ParseInteger(token, &value)) {
      Fail(std::string("expected ") + what + " (an integer), found '" + Shorten(token) + "'");
    }
    return value;
  }

  /// The next token as a number.
  double TextReal(const char* what) {
    const std::string_view token = Token(what);
    double value = 0;
    if (!ParseDouble(token, &value))
      Fail(std::string("expected ") + what + " (a number), found '" + Shorten(token) + "'");
    return value;
  }

  /// Requires the end marker of `section` (a wrong count shows up here).
  void ExpectEnd(const char* section) {
    const std::string end = std::string("$End") + section;
    std::string_view token;
    if (!NextToken(&token)) Fail("unexpected end of file, expected " + end);
    if (token != end) Fail("expected " + end + ", found '" + Shorten(token) + "' (wrong count?)");
  }

  /// Skips an unknown section up to its end marker. Ascii sections are
  /// skipped by lines (keeping the line count); binary ones by bytes, since
  /// their data need not be lines at all.
  void SkipSection(const std::string& name) {
    const std::string end = "$End" + name;
    if (!binary_) {
      if (Trim(rest_) == end) {
        rest_ = {};
        return;
      }
      std::string_view line;
      while (in_.ReadLine(&line)) {
        tokenLine_ = restLine_ = in_.lineNumber();
        if (Trim(line) == end) {
          rest_ = {};
          return;
        }
      }
      Fail("unexpected end of file, expected " + end);
    }
    StartBinary("$" + name);
    std::size_t matched = 0;
    for (;;) {
      if (in_.available() == 0 && !in_.Fill(1)) Fail("unexpected end of file, expected " + end);
      const char* data = in_.data();
      const std::size_t n = in_.available();
      for (std::size_t i = 0; i < n; ++i) {
        // '$' occurs only at the start of the marker, so a mismatch can
        // restart the match at this very character.
        matched = data[i] == end[matched] ? matched + 1 : (data[i] == end[0] ? 1 : 0);
        if (matched == end.size()) {
          in_.Consume(i + 1);
          return;
        }
      }
      in_.Consume(n);
    }
  }

  // ----- binary -----

  /// Switches from the text of a section header to the binary data after it.
  void StartBinary(const std::string& section) {
    if (!Trim(rest_).empty()) Fail("unexpected text after " + section + ": '" + Shorten(Trim(rest_)) + "'");
    rest_ = {};
  }

  /// A binary value in the file's byte order.
  template <class T>
  T Binary(const char* what) {
    if (!in_.Fill(sizeof(T))) Fail(std::string("unexpected end of file, expected ") + what);
    const T value = LoadValue<T>(in_.data(), bigEndian_);
    in_.Consume(sizeof(T));
    return value;
  }

  // ----- values of either encoding -----

  /// An int field (tags, dimensions, types).
  int Int(const char* what) {
    if (binary_) return Binary<std::int32_t>(what);
    const std::int64_t v = TextInt(what);
    if (v < INT32_MIN || v > INT32_MAX) Fail(std::string(what) + " " + std::to_string(v) + " out of range");
    return static_cast<int>(v);
  }

  /// A size_t field (counts and node or element tags).
  std::uint64_t Size(const char* what) {
    if (binary_) return Binary<std::uint64_t>(what);
    const std::int64_t v = TextInt(what);
    if (v < 0) Fail(std::string(what) + " must not be negative, found " + std::to_string(v));
    return static_cast<std::uint64_t>(v);
  }

  /// A double field (coordinates).
  double Real(const char* what) { return binary_ ? Binary<double>(what) : TextReal(what); }

  // ----- sections -----

  /// The version, encoding and, in binary files, byte order.
  void ReadMeshFormat() {
    const std::string_view version = Token("the MSH version");
    if (version != "4.1") {
      Fail("MSH version " + Shorten(version) +
           " is not supported: invmap reads MSH 4.1 (gmsh option Mesh.MshFileVersion = 4.1, or -format msh41)");
    }
    const std::int64_t fileType = TextInt("the file type");
    const std::int64_t dataSize = TextInt("the data size");
    if (fileType != 0 && fileType != 1)
      Fail("file type must be 0 (ascii) or 1 (binary), found " + std::to_string(fileType));
    if (fileType == 1) {
      if (dataSize != 8) Fail("binary data size " + std::to_string(dataSize) + " is not supported (only 8)");
      StartBinary("the MSH format line");
      binary_ = true;
      // The integer 1 in the writer's byte order tells that order.
      if (!in_.Fill(4)) Fail("unexpected end of file, expected the byte-order integer");
      if (LoadValue<std::int32_t>(in_.data(), false) == 1) {
        bigEndian_ = false;
      } else if (LoadValue<std::int32_t>(in_.data(), true) == 1) {
        bigEndian_ = true;
      } else {
        Fail("the byte-order integer after the MSH format line is not 1 in either byte order");
      }
      in_.Consume(4);
    }
    ExpectEnd("MeshFormat");
  }

  /// $PhysicalNames is text even in binary files.
  void ReadPhysicalNames() {
    const std::int64_t count = TextInt("the number of physical names");
    if (count < 0) Fail("negative number of physical names");
    CheckCount(static_cast<std::uint64_t>(count), 6, "physical name");
    for (std::int64_t i = 0; i < count; ++i) {
      const std::int64_t dim = TextInt("a physical group dimension");
      const std::int64_t tag = TextInt("a physical tag");
      if (dim < 0 || dim > 3) Fail("physical group dimension " + std::to_string(dim) + " not in 0..3");
      if (tag < INT32_MIN || tag > INT32_MAX) Fail("physical tag " + std::to_string(tag) + " out of range");
      std::string_view name = Trim(rest_);
      rest_ = {};
      if (name.size() >= 2 && name.front() == '"' && name.back() == '"') name = name.substr(1, name.size() - 2);
      mesh_.physicalKeys.emplace_back(static_cast<int>(dim), static_cast<int>(tag));
      mesh_.physicalNames.emplace_back(name);
    }
    ExpectEnd("PhysicalNames");
  }

  /// Points, curves, surfaces and volumes with their physical tags (their
  /// boxes and bounding entities are read past).
  void ReadEntities() {
    if (binary_) StartBinary("$Entities");
    std::uint64_t counts[4];
    const char* kinds[4] = {"point", "curve", "surface", "volume"};
    const char* countNames[4] = {"the number of point entities", "the number of curve entities",
                                 "the number of surface entities", "the number of volume entities"};
    for (int d = 0; d < 4; ++d) counts[d] = Size(countNames[d]);
    for (int d = 0; d < 4; ++d) {
      // A point is a tag, 3 coordinates and a physical count; the others
      // carry a box (6 numbers) and a bounding-entity count as well.
      CheckCount(counts[d], d == 0 ? MinBytes(4 + 24 + 8) : MinBytes(4 + 48 + 16), std::string(kinds[d]) + " entity");
      for (std::uint64_t i = 0; i < counts[d]; ++i) {
        Entity entity;
        entity.dim = d;
        entity.tag = Int("an entity tag");
        for (int k = 0; k < (d == 0 ? 3 : 6); ++k) Real("an entity coordinate");
        const std::uint64_t numPhysical = Size("the number of physical tags");
        CheckCount(numPhysical, MinBytes(4), "physical tag");
        for (std::uint64_t k = 0; k < numPhysical; ++k) entity.physicalTags.push_back(Int("a physical tag"));
        if (d > 0) {
          const std::uint64_t numBounding = Size("the number of bounding entities");
          CheckCount(numBounding, MinBytes(4), "bounding entity");
          for (std::uint64_t k = 0; k < numBounding; ++k) Int("a bounding entity tag");
        }
        mesh_.entities.push_back(std::move(entity));
      }
    }
    ExpectEnd("Entities");
  }

  /// Node coordinates, indexed by tag.
  void ReadNodes() {
    if (binary_) StartBinary("$Nodes");
    const std::uint64_t numBlocks = Size("the number of node blocks");
    const std::uint64_t numNodes = Size("the number of nodes");
    const std::uint64_t minTag = Size("the minimum node tag");
    const std::uint64_t maxTag = Size("the maximum node tag");
    CheckCount(numBlocks, MinBytes(20), "node block");
    CheckCount(numNodes, MinBytes(8 + 24), "node");
    if (numNodes > 0 && minTag > maxTag) Fail("minimum node tag above the maximum");
    nodeIndex_ = std::make_unique<NodeIndex>(maxTag, numNodes, in_.remaining() >= 0);
    mesh_.nodes.reserve(3 * ReserveFor(numNodes));
    std::uint64_t total = 0;
    std::vector<std::uint64_t> tags;
    for (std::uint64_t b = 0; b < numBlocks; ++b) {
      const int entityDim = Int("a node block's entity dimension");
      Int("a node block's entity tag");
      const int parametric = Int("a node block's parametric flag");
      const std::uint64_t count = Size("the number of nodes in the block");
      if (entityDim < 0 || entityDim > 3)
        Fail("node block entity dimension " + std::to_string(entityDim) + " not in 0..3");
      if (parametric != 0 && parametric != 1) Fail("node block parametric flag must be 0 or 1");
      const int params = parametric ? entityDim : 0;
      CheckCount(count, MinBytes(8 + 8 * (3 + params)), "node");
      if (count > numNodes - total) {
        Fail("node blocks hold more nodes than the " + std::to_string(numNodes) + " of the section header");
      }
      tags.resize(static_cast<std::size_t>(count));
      for (std::uint64_t i = 0; i < count; ++i) {
        const std::uint64_t tag = tags[i] = Size("a node tag");
        if (tag < minTag || tag > maxTag) {
          Fail("node tag " + std::to_string(tag) + " outside the header's range [" + std::to_string(minTag) + ", " +
               std::to_string(maxTag) + "]");
        }
        if (!nodeIndex_->Insert(tag, static_cast<std::int64_t>(total + i))) {
          Fail("node tag " + std::to_string(tag) + " defined twice");
        }
      }
      for (std::uint64_t i = 0; i < count; ++i) {
        for (int k = 0; k < 3; ++k) {
          const double x = Real("a node coordinate");
          if (!std::isfinite(x)) Fail("node " + std::to_string(tags[i]) + " has a coordinate that is not finite");
          mesh_.nodes.push_back(x);
        }
        for (int k = 0; k < params; ++k) Real("a node's parametric coordinate");
      }
      total += count;
    }
    if (total != numNodes) {
      Fail("the section header says " + std::to_string(numNodes) + " nodes, the blocks hold " + std::to_string(total));
    }
    ExpectEnd("Nodes");
  }

  /// Element blocks with their node tags turned into node indices.
  void ReadElements() {
    if (binary_) StartBinary("$Elements");
    const std::uint64_t numBlocks = Size("the number of element blocks");
    const std::uint64_t numElements = Size("the number of elements");
    Size("the minimum element tag");
    Size("the maximum element tag");
    CheckCount(numBlocks, MinBytes(20), "element block");
    CheckCount(numElements, MinBytes(16), "element");
    std::uint64_t total = 0;
    for (std::uint64_t b = 0; b < numBlocks; ++b) {
      ElementBlock block;
      block.entityDim = Int("an element block's entity dimension");
      block.entityTag = Int("an element block's entity tag");
      const int mshType = Int("an element type");
      const std::uint64_t count = Size("the number of elements in the block");
      if (count > numElements - total) {
        Fail("element blocks hold more elements than the " + std::to_string(numElements) + " of the section header");
      }
      total += count;
      block.type = FindGmshElementType(mshType);
      if (block.type == nullptr && !IsGmshPoint(mshType)) RejectType(mshType, count);
      const int nodesPer = block.type != nullptr ? block.type->numNodes : 1;
      CheckCount(count, MinBytes(8) * (1 + nodesPer), "element");
      block.count = static_cast<std::int64_t>(count);
      block.firstNode = mesh_.elementNodes.size();
      if (block.type == nullptr) {
        // Points carry no cell; their node is not even looked up.
        for (std::uint64_t i = 0; i < 2 * count; ++i) Size("a point element's tag or node");
        continue;
      }
      mesh_.elementNodes.reserve(mesh_.elementNodes.size() + ReserveFor(count) * nodesPer);
      for (std::uint64_t i = 0; i < count; ++i) {
        const std::uint64_t elementTag = Size("an element tag");
        for (int k = 0; k < nodesPer; ++k) {
          const std::uint64_t nodeTag = Size("a node tag of an element");
          const std::int64_t index = nodeIndex_->Find(nodeTag);
          if (index < 0) {
            Fail("element " + std::to_string(elementTag) + " refers to node " + std::to_string(nodeTag) +
                 ", which $Nodes does not define");
          }
          mesh_.elementNodes.push_back(index);
        }
      }
      if (TraitsOf(block.type->cell).paramDim == 3) mesh_.anyVolume = true;
      mesh_.blocks.push_back(block);
    }
    if (total != numElements) {
      Fail("the section header says " + std::to_string(numElements) + " elements, the blocks hold " +
           std::to_string(total));
    }
    ExpectEnd("Elements");
  }

  /// A string tag: a quoted string that may hold spaces (the rest of its
  /// line up to the closing quote), or a bare token.
  std::string StringTag(const char* what) {
    const std::string_view token = Token(what);
    if (token.empty() || token.front() != '"') return std::string(token);
    const std::string_view line(token.data(), static_cast<std::size_t>(rest_.data() + rest_.size() - token.data()));
    const std::size_t close = line.find('"', 1);
    if (close == std::string_view::npos) Fail(std::string(what) + " has no closing quote");
    rest_ = line.substr(close + 1);
    return std::string(line.substr(1, close - 1));
  }

  /// One $NodeData section: string tags (the view's name first), real tags
  /// (its time first), integer tags (time step, components, count, and a
  /// partition), then `count` records of a node tag and its components (in
  /// binary files a 4-byte int and doubles). Keeps the highest time step of
  /// each view; sections of the same step (partitions) add their nodes.
  void ReadNodeData() {
    const std::int64_t numStrings = TextInt("the number of string tags");
    if (numStrings < 1) Fail("$NodeData needs a string tag with the view's name");
    CheckCount(static_cast<std::uint64_t>(numStrings), 3, "string tag");
    const std::string name = StringTag("the view's name");
    for (std::int64_t i = 1; i < numStrings; ++i) StringTag("a string tag");
    const std::int64_t numReals = TextInt("the number of real tags");
    if (numReals < 0) Fail("negative number of real tags");
    CheckCount(static_cast<std::uint64_t>(numReals), 2, "real tag");
    for (std::int64_t i = 0; i < numReals; ++i) TextReal("a real tag");
    const std::int64_t numIntegers = TextInt("the number of integer tags");
    if (numIntegers < 3) Fail("$NodeData needs 3 integer tags (time step, components, count)");
    CheckCount(static_cast<std::uint64_t>(numIntegers), 2, "integer tag");
    const std::int64_t step = TextInt("the time step");
    const std::int64_t components = TextInt("the number of components");
    const std::int64_t count = TextInt("the number of nodes with data");
    for (std::int64_t i = 3; i < numIntegers; ++i) TextInt("an integer tag");
    if (components < 1 || components > 9) Fail("view '" + name + "': " + std::to_string(components) + " components, expected 1 to 9");
    if (count < 0) Fail("view '" + name + "': negative number of nodes");
    CheckCount(static_cast<std::uint64_t>(count), MinBytes(4) + MinBytes(8) * static_cast<std::uint64_t>(components),
               "node data");

    const std::size_t numNodes = mesh_.nodes.size() / 3;
    auto view = std::find_if(mesh_.nodeViews.begin(), mesh_.nodeViews.end(),
                             [&](const GmshNodeView& v) { return v.name == name; });
    if (view == mesh_.nodeViews.end()) {
      view = mesh_.nodeViews.insert(mesh_.nodeViews.end(), GmshNodeView{name, -1, static_cast<int>(components), {}});
    }
    const bool keep = step >= view->timeStep;
    if (step > view->timeStep) {
      view->timeStep = step;
      view->components = static_cast<int>(components);
      view->values.assign(numNodes * static_cast<std::size_t>(components), std::numeric_limits<double>::quiet_NaN());
    } else if (keep && components != view->components) {
      Fail("view '" + name + "': time step " + std::to_string(step) + " has " + std::to_string(components) +
           " components in one section and " + std::to_string(view->components) + " in another");
    }
    if (binary_) StartBinary("$NodeData");
    for (std::int64_t i = 0; i < count; ++i) {
      const std::int64_t tag = binary_ ? Binary<std::int32_t>("a node tag") : TextInt("a node tag");
      const std::int64_t index = tag < 0 ? -1 : nodeIndex_->Find(static_cast<std::uint64_t>(tag));
      if (index < 0) Fail("view '" + name + "' has data for node " + std::to_string(tag) + ", which $Nodes does not define");
      for (std::int64_t k = 0; k < components; ++k) {
        const double value = Real("a node data value");
        if (keep) view->values[static_cast<std::size_t>(index * components + k)] = value;
      }
    }
    ExpectEnd("NodeData");
  }

  /// Error for a block of an element type invmap does not convert, naming its
  /// first element.
  [[noreturn]] void RejectType(int mshType, std::uint64_t count) {
    const std::string element = count > 0 ? "element " + std::to_string(Size("an element tag")) : "an element block";
    if (IsGmshPyramid(mshType)) {
      Fail(element + " is a pyramid (gmsh element type " + std::to_string(mshType) + "): invmap has no pyramid cells");
    }
    Fail(element + " has gmsh element type " + std::to_string(mshType) +
         ", which invmap does not read (it reads lines, triangles, quadrangles, tetrahedra, hexahedra and prisms "
         "of order 1 to 4)");
  }

  InputBuffer& in_;
  MeshData mesh_;
  std::unique_ptr<NodeIndex> nodeIndex_;
  std::string_view rest_;       ///< Unread text of the current line.
  std::int64_t restLine_ = 0;   ///< Line number of rest_.
  std::int64_t tokenLine_ = 0;  ///< Line of the last token (for messages).
  bool binary_ = false;
  bool bigEndian_ = false;
};

/// Turns parsed sections into patches of Bezier cells.
class GeometryBuilder {
 public:
  /// `mesh` must outlive the builder; `name` is the file in messages.
  GeometryBuilder(const MeshData& mesh, std::string name) : mesh_(mesh), name_(std::move(name)) {
    for (const Entity& e : mesh_.entities) entities_.emplace(std::make_pair(e.dim, e.tag), &e);
  }

  /// The geometry; `sources` (optional) receives one entry per patch.
  Geometry Build(std::vector<GmshPatchSource>* sources) {
    Geometry geometry;
    geometry.dimension = 3;
    if (!mesh_.anyVolume) {
      bool flat = true;
      for (std::size_t i = 2; i < mesh_.nodes.size() && flat; i += 3) flat = mesh_.nodes[i] == 0.0;
      if (flat) geometry.dimension = 2;
    }
    dim_ = geometry.dimension;

    std::vector<std::pair<GmshPatchSource, std::vector<const ElementBlock*>>> patches = GroupPatches();
    if (patches.empty()) patches = EntityPatches();
    for (auto& [source, blocks] : patches) {
      geometry.patches.push_back(MakePatch(blocks));
      patchBlocks_.push_back(blocks);
      if (sources != nullptr) sources->push_back(std::move(source));
    }
    if (geometry.patches.empty()) {
      throw InputError(name_, 0, "no cells: the mesh has no line, surface or volume elements");
    }
    return geometry;
  }

  /// A view as a field over the patches Build made: each element's nodal
  /// values through its change of basis, in the patch's point order.
  NodeField MakeField(const GmshNodeView& view) {
    NodeField field;
    field.name = view.name;
    field.components = view.components;
    const std::size_t n = static_cast<std::size_t>(view.components);
    std::vector<double> nodal;
    for (const std::vector<const ElementBlock*>& blocks : patchBlocks_) {
      std::vector<double>& out = field.patchValues.emplace_back();
      for (const ElementBlock* block : blocks) {
        const GmshElementType& type = *block->type;
        const LagrangeToBernstein& converter = Converter(type);
        nodal.resize(type.numNodes * n);
        for (std::int64_t e = 0; e < block->count; ++e) {
          const std::int64_t* nodes = mesh_.elementNodes.data() + block->firstNode + e * type.numNodes;
          for (int j = 0; j < type.numNodes; ++j) {
            std::copy_n(view.values.data() + nodes[j] * n, n, nodal.data() + j * n);
          }
          const std::size_t first = out.size();
          out.resize(first + converter.numControlPoints() * n);
          converter.ApplyToValues(nodal.data(), view.components, out.data() + first);
        }
      }
    }
    return field;
  }

 private:
  using PatchBlocks = std::pair<GmshPatchSource, std::vector<const ElementBlock*>>;

  /// The $Entities entry of an entity, null when the file lists none.
  const Entity* FindEntity(int dim, int tag) const {
    const auto it = entities_.find(std::make_pair(dim, tag));
    return it == entities_.end() ? nullptr : it->second;
  }

  /// One patch per physical group with cells; empty when no group has any.
  std::vector<PatchBlocks> GroupPatches() const {
    std::vector<std::pair<int, int>> groups = mesh_.physicalKeys;
    for (const Entity& e : mesh_.entities) {
      for (const int tag : e.physicalTags) {
        if (std::find(groups.begin(), groups.end(), std::make_pair(e.dim, tag)) == groups.end()) {
          groups.emplace_back(e.dim, tag);
        }
      }
    }
    std::vector<PatchBlocks> out;
    for (const auto& [dim, tag] : groups) {
      PatchBlocks patch;
      patch.first.physicalGroup = true;
      patch.first.dim = dim;
      patch.first.tag = tag;
      for (std::size_t i = 0; i < mesh_.physicalKeys.size(); ++i) {
        if (mesh_.physicalKeys[i] == std::make_pair(dim, tag)) patch.first.name = mesh_.physicalNames[i];
      }
      for (const ElementBlock& block : mesh_.blocks) {
        const Entity* entity = block.entityDim == dim ? FindEntity(block.entityDim, block.entityTag) : nullptr;
        if (block.count > 0 && entity != nullptr &&
            std::find(entity->physicalTags.begin(), entity->physicalTags.end(), tag) != entity->physicalTags.end()) {
          patch.second.push_back(&block);
        }
      }
      if (!patch.second.empty()) out.push_back(std::move(patch));
    }
    return out;
  }

  /// One patch per entity of the highest element dimension, $Entities order
  /// first, then entities that $Entities does not list, in block order.
  std::vector<PatchBlocks> EntityPatches() const {
    int top = 0;
    for (const ElementBlock& block : mesh_.blocks) {
      if (block.count > 0) top = std::max(top, TraitsOf(block.type->cell).paramDim);
    }
    std::vector<std::pair<int, int>> order;
    for (const Entity& e : mesh_.entities) order.emplace_back(e.dim, e.tag);
    for (const ElementBlock& block : mesh_.blocks) {
      const auto key = std::make_pair(block.entityDim, block.entityTag);
      if (std::find(order.begin(), order.end(), key) == order.end()) order.push_back(key);
    }
    std::vector<PatchBlocks> out;
    for (const auto& [dim, tag] : order) {
      PatchBlocks patch;
      patch.first.dim = dim;
      patch.first.tag = tag;
      for (const ElementBlock& block : mesh_.blocks) {
        if (block.count > 0 && block.entityDim == dim && block.entityTag == tag &&
            TraitsOf(block.type->cell).paramDim == top) {
          patch.second.push_back(&block);
        }
      }
      if (!patch.second.empty()) out.push_back(std::move(patch));
    }
    return out;
  }

  /// The change of basis of an element type, built at its first use.
  const LagrangeToBernstein& Converter(const GmshElementType& type) {
    auto it = converters_.find(type.mshType);
    if (it == converters_.end()) {
      it = converters_
               .emplace(type.mshType, LagrangeToBernstein(type.cell, type.order, GmshReferenceNodes(type),
                                                          GmshIncompleteMonomials(type)))
               .first;
    }
    return it->second;
  }

  /// A BezierCells patch of the elements of `blocks`, in block order.
  Patch MakePatch(const std::vector<const ElementBlock*>& blocks) {
    Patch patch;
    patch.kind = Patch::Kind::BezierCells;
    std::int64_t numCells = 0, numPoints = 0;
    for (const ElementBlock* block : blocks) {
      numCells += block->count;
      numPoints += block->count * BernsteinCount(block->type->cell, block->type->order);
    }
    patch.cellTypes.reserve(static_cast<std::size_t>(numCells));
    patch.cellDegrees.reserve(3 * static_cast<std::size_t>(numCells));
    patch.cellOffsets.reserve(static_cast<std::size_t>(numCells) + 1);
    patch.points.resize(static_cast<std::size_t>(numPoints) * dim_);
    patch.cellOffsets.push_back(0);
    std::vector<double> nodal;
    std::int64_t point = 0;
    for (const ElementBlock* block : blocks) {
      const GmshElementType& type = *block->type;
      const LagrangeToBernstein& converter = Converter(type);
      const std::array<int, 3> degrees = UniformDegrees(type.cell, type.order);
      nodal.resize(3 * static_cast<std::size_t>(type.numNodes));
      for (std::int64_t e = 0; e < block->count; ++e) {
        const std::int64_t* nodes = mesh_.elementNodes.data() + block->firstNode + e * type.numNodes;
        for (int j = 0; j < type.numNodes; ++j) {
          std::memcpy(&nodal[3 * j], &mesh_.nodes[3 * static_cast<std::size_t>(nodes[j])], 3 * sizeof(double));
        }
        converter.Apply(nodal.data(), dim_, patch.points.data() + point * dim_);
        point += converter.numControlPoints();
        patch.cellTypes.push_back(type.cell);
        patch.cellDegrees.insert(patch.cellDegrees.end(), degrees.begin(), degrees.end());
        patch.cellOffsets.push_back(point);
      }
    }
    return patch;
  }

  const MeshData& mesh_;
  std::string name_;
  int dim_ = 3;
  std::vector<std::vector<const ElementBlock*>> patchBlocks_;  ///< The blocks of each patch built.
  std::map<std::pair<int, int>, const Entity*> entities_;  ///< By (dim, tag).
  std::map<int, LagrangeToBernstein> converters_;          ///< By gmsh element type.
};

/// Every ReadGmsh and ReadGmshWithFields overload; fields only when asked.
FieldGeometry ReadGmshBuffer(InputBuffer& in, std::vector<GmshPatchSource>* sources, bool withFields) {
  const MeshData mesh = GmshParser(in).Parse();
  if (sources != nullptr) sources->clear();
  GeometryBuilder builder(mesh, in.name());
  FieldGeometry out;
  out.geometry = builder.Build(sources);
  if (withFields) {
    for (const GmshNodeView& view : mesh.nodeViews) out.fields.push_back(builder.MakeField(view));
  }
  return out;
}

/// A second istream over the caller's buffer: InputBuffer owns its stream,
/// the caller keeps theirs.
std::unique_ptr<std::istream> SharedStream(std::istream& in) { return std::make_unique<std::istream>(in.rdbuf()); }

}  // namespace

Geometry ReadGmsh(const std::string& path, std::vector<GmshPatchSource>* sources) {
  InputBuffer in(path);
  return ReadGmshBuffer(in, sources, false).geometry;
}

Geometry ReadGmsh(std::istream& in, const std::string& name, std::vector<GmshPatchSource>* sources) {
  InputBuffer buffer(SharedStream(in), name);
  return ReadGmshBuffer(buffer, sources, false).geometry;
}

FieldGeometry ReadGmshWithFields(const std::string& path, std::vector<GmshPatchSource>* sources) {
  InputBuffer in(path);
  return ReadGmshBuffer(in, sources, true);
}

FieldGeometry ReadGmshWithFields(std::istream& in, const std::string& name, std::vector<GmshPatchSource>* sources) {
  InputBuffer buffer(SharedStream(in), name);
  return ReadGmshBuffer(buffer, sources, true);
}

}  // namespace invmap::io
