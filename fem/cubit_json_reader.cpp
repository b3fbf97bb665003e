#include "fem/cubit_json_reader.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <fstream>
#include <map>

#include "fem/extraction_cells.h"
#include "io/file_io.h"
#include "io/geometry_file.h"
#include "io/input_error.h"

namespace invmap::fem {
namespace {

using Json = nlohmann::json;

/// Top-level keys of Cubit's current format and of the new one.
constexpr const char* kCubitKeys[] = {"patch_id",     "dim",          "num_elems",       "is_rational",
                                      "num_vertices", "num_nodes",    "nodes",           "elements",
                                      "coefficients", "num_coeff_vecs", "vertex_connectivity", "block_elem_map",
                                      "control_points", "extraction_coefficients", "cell_sets",
                                      "bezier_extraction_patch"};

/// Typed access to a JSON value with its path for messages.
class Node {
 public:
  Node(const Json& value, std::string path, const std::string& file) : value_(value), path_(std::move(path)), file_(file) {}

  bool Has(const char* key) const { return value_.is_object() && value_.contains(key); }
  Node operator[](const char* key) const {
    if (!value_.is_object() || !value_.contains(key)) Fail(Join(key) + ": missing");
    return Node(value_.at(key), Join(key), file_);
  }
  Node operator[](std::size_t i) const { return Node(value_.at(i), path_ + "[" + std::to_string(i) + "]", file_); }
  std::size_t Size() const {
    if (!value_.is_array()) Fail(path_ + ": expected an array");
    return value_.size();
  }
  std::int64_t Int() const {
    if (!value_.is_number_integer()) Fail(path_ + ": expected an integer");
    return value_.get<std::int64_t>();
  }
  double Real() const {
    if (!value_.is_number()) Fail(path_ + ": expected a number");
    const double x = value_.get<double>();
    if (!std::isfinite(x)) Fail(path_ + ": not finite");
    return x;
  }
  bool Bool() const {
    if (!value_.is_boolean()) Fail(path_ + ": expected true or false");
    return value_.get<bool>();
  }
  std::vector<std::int64_t> Ints() const {
    std::vector<std::int64_t> out;
    for (std::size_t i = 0; i < Size(); ++i) out.push_back((*this)[i].Int());
    return out;
  }
  std::vector<double> Reals() const {
    std::vector<double> out;
    for (std::size_t i = 0; i < Size(); ++i) out.push_back((*this)[i].Real());
    return out;
  }
  const std::string& path() const { return path_; }
  [[noreturn]] void Fail(const std::string& what) const { throw io::InputError(file_, 0, what); }

 private:
  std::string Join(const char* key) const { return path_.empty() ? key : path_ + "." + key; }

  const Json& value_;
  std::string path_;
  const std::string& file_;
};

/// The first key of a JSON object text, or empty.
std::string FirstKey(const std::string& head) {
  std::size_t i = head.find_first_not_of(" \t\r\n");
  if (i == std::string::npos || head[i] != '{') return {};
  i = head.find_first_not_of(" \t\r\n", i + 1);
  if (i == std::string::npos || head[i] != '"') return {};
  const std::size_t end = head.find('"', i + 1);
  return end == std::string::npos ? std::string() : head.substr(i + 1, end - i - 1);
}

/// The cell type of a block by its number of degrees (-1 marks unused).
CellType TypeOf(const Node& info, std::array<int, 3>* degrees) {
  int directions = 0;
  for (const char* key : {"deg_s", "deg_t", "deg_u"}) {
    const std::int64_t d = info.Has(key) ? info[key].Int() : -1;
    if (d < 0) break;
    (*degrees)[directions++] = static_cast<int>(d);
  }
  if (directions == 0) info.Fail(info.path() + ": deg_s must be a degree >= 1");
  return directions == 1 ? CellType::Line : directions == 2 ? CellType::Quad : CellType::Hex;
}

FieldGeometry ReadText(const std::string& text, const std::string& name) {
  Json document;
  try {
    document = Json::parse(text);
  } catch (const Json::parse_error& e) {
    const std::size_t offset = std::min<std::size_t>(e.byte, text.size());
    const std::int64_t line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(offset), '\n');
    throw io::InputError(name, line, "not valid JSON");
  } catch (const Json::out_of_range& e) {
    // A number beyond the doubles: the parser names its text, not where it is.
    const std::string what = e.what();
    const std::size_t open = what.find('\''), close = what.rfind('\'');
    std::int64_t line = 0;
    if (open != std::string::npos && close > open + 1) {
      const std::size_t at = text.find(what.substr(open + 1, close - open - 1));
      if (at != std::string::npos) line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n');
    }
    throw io::InputError(name, line, "not valid JSON: a number out of the range of doubles");
  }
  const Node root(document, "", name);
  if (!document.is_object()) root.Fail("expected a JSON object");
  for (const char* key : {"control_points", "extraction_coefficients", "cell_sets", "bezier_extraction_patch"}) {
    if (root.Has(key)) {
      root.Fail(std::string("'") + key + "': Cubit's new Bezier extraction JSON format is not read: the definitions "
                                          "of its fields are not available (docs/fields.md)");
    }
  }
  const bool rational = root.Has("is_rational") && root["is_rational"].Bool();
  ExtractedSpline spline;
  const Node nodes = root["nodes"];
  for (std::size_t i = 0; i < nodes.Size(); ++i) {
    const std::vector<double> xyzw = nodes[i].Reals();
    if (xyzw.size() != 4) nodes[i].Fail(nodes[i].path() + ": expected [x, y, z, w]");
    spline.points.insert(spline.points.end(), xyzw.begin(), xyzw.begin() + 3);
    if (rational && !(xyzw[3] > 0.0)) nodes[i].Fail(nodes[i].path() + ": weight is not positive");
    if (rational) spline.weights.push_back(xyzw[3]);
  }
  const Node coefficients = root["coefficients"];
  if (coefficients.Has("num_sparse_coeff_blocks") && coefficients["num_sparse_coeff_blocks"].Int() != 0) {
    coefficients.Fail("coefficients.num_sparse_coeff_blocks: sparse coefficient vectors are not read");
  }
  const Node vectors = coefficients["dense_coefficient_vectors"];
  for (std::size_t v = 0; v < vectors.Size(); ++v) spline.coefficientVectors.push_back(vectors[v]["components"].Reals());

  const Node elements = root["elements"];
  const Node infos = elements["element_block_info"];
  const Node blocks = elements["element_blocks"];
  std::vector<ExtractionElement> all;
  std::map<std::int64_t, std::size_t> byId;  // us_cid -> index in all
  std::size_t next = 0;
  for (std::size_t b = 0; b < infos.Size(); ++b) {
    std::array<int, 3> degrees{0, 0, 0};
    const CellType type = TypeOf(infos[b], &degrees);
    const std::int64_t count = infos[b]["num_elems"].Int();
    if (count < 0 || next + static_cast<std::size_t>(count) > blocks.Size()) {
      infos[b].Fail(infos[b].path() + ".num_elems: more elements than elements.element_blocks lists");
    }
    for (std::int64_t e = 0; e < count; ++e, ++next) {
      const Node entry = blocks[next];
      ExtractionElement element;
      element.type = type;
      element.degrees = degrees;
      element.points = entry["node_ids"].Ints();
      element.coefficientVectors = entry["coeff_vector_ids"].Ints();
      element.where = entry.path();
      const std::int64_t id = entry.Has("us_cid") ? entry["us_cid"].Int() : static_cast<std::int64_t>(next);
      if (!byId.emplace(id, all.size()).second) entry.Fail(entry.path() + ".us_cid: " + std::to_string(id) + " twice");
      all.push_back(std::move(element));
    }
  }
  if (next != blocks.Size()) blocks.Fail("elements.element_blocks: more elements than element_block_info counts");
  if (all.empty()) root.Fail("no elements");

  std::vector<std::vector<std::size_t>> patches;
  if (root.Has("block_elem_map") && root["block_elem_map"].Size() > 0) {
    const Node map = root["block_elem_map"];
    for (std::size_t b = 0; b < map.Size(); ++b) {
      std::vector<std::size_t>& cells = patches.emplace_back();
      const Node ids = map[b]["elem_ids"];
      for (std::size_t i = 0; i < ids.Size(); ++i) {
        const auto it = byId.find(ids[i].Int());
        if (it == byId.end()) ids[i].Fail(ids[i].path() + ": no element has us_cid " + std::to_string(ids[i].Int()));
        cells.push_back(it->second);
      }
    }
  } else {
    std::vector<std::size_t>& cells = patches.emplace_back();
    for (std::size_t i = 0; i < all.size(); ++i) cells.push_back(i);
  }
  FieldGeometry out;
  out.geometry.dimension = ExtractedDimension(spline, all);
  for (const std::vector<std::size_t>& cells : patches) {
    Patch& patch = out.geometry.patches.emplace_back(EmptyCellsPatch());
    for (const std::size_t c : cells) AddExtractedCell(spline, all[c], out.geometry.dimension, name, &patch);
  }
  return out;
}

}  // namespace

bool LooksLikeCubitJson(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::string head(4096, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  const std::string key = FirstKey(head);
  return std::find_if(std::begin(kCubitKeys), std::end(kCubitKeys), [&](const char* k) { return key == k; }) !=
         std::end(kCubitKeys);
}

FieldGeometry ReadCubitJson(const std::string& path) { return ReadText(io::ReadWholeFile(path), path); }

FieldGeometry ReadCubitJson(std::istream& in, const std::string& name) {
  return ReadText(io::ReadWholeStream(in, name), name);
}

}  // namespace invmap::fem
