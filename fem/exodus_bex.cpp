#include "fem/exodus_bex.h"

#include <netcdf.h>

#include <cmath>

#include "fem/extraction_cells.h"

namespace invmap::fem {
namespace {

/// The netCDF variables of an Exodus Bezier extraction file that this
/// version of the Exodus API cannot read (blobs, block attributes of
/// Exodus 8), read by name.
class BexVariables {
 public:
  explicit BexVariables(const ExodusFile& file) : file_(file), ncid_(file.ncid()) {}

  /// The text of a character variable or attribute, up to its first NUL.
  std::string Text(int var, const char* attribute) const {
    std::size_t length = 0;
    if (nc_inq_attlen(ncid_, var, attribute, &length) != NC_NOERR) return {};
    std::string text(length, '\0');
    if (length > 0 && nc_get_att_text(ncid_, var, attribute, text.data()) != NC_NOERR) return {};
    return text.substr(0, text.find('\0'));
  }

  /// An integer attribute of variable `var`; empty when it has none.
  std::vector<int> IntAttribute(int var, const char* attribute) const {
    std::size_t length = 0;
    if (nc_inq_attlen(ncid_, var, attribute, &length) != NC_NOERR) return {};
    std::vector<int> values(length);
    if (length > 0 && nc_get_att_int(ncid_, var, attribute, values.data()) != NC_NOERR) {
      file_.Fail(std::string("cannot read attribute ") + attribute);
    }
    return values;
  }

  /// The id of a variable, -1 when the file has none of that name.
  int Find(const std::string& name) const {
    int var = -1;
    return nc_inq_varid(ncid_, name.c_str(), &var) == NC_NOERR ? var : -1;
  }

  /// Every value of a numeric variable (all its dimensions), checked against `limit`.
  std::vector<double> Doubles(int var, const std::string& what) const {
    int numDims = 0;
    if (nc_inq_varndims(ncid_, var, &numDims) != NC_NOERR || numDims > NC_MAX_VAR_DIMS) file_.Fail("cannot read " + what);
    int dims[NC_MAX_VAR_DIMS];
    nc_inq_vardimid(ncid_, var, dims);
    std::size_t count = 1;
    for (int d = 0; d < numDims; ++d) {
      std::size_t length = 0;
      nc_inq_dimlen(ncid_, dims[d], &length);
      count *= length;
    }
    std::vector<double> values(count);
    if (count > 0 && nc_get_var_double(ncid_, var, values.data()) != NC_NOERR) file_.Fail("cannot read " + what);
    return values;
  }

  /// Rows of a character variable (Exodus name lists).
  std::vector<std::string> Names(int var) const {
    int dims[2];
    int numDims = 0;
    if (nc_inq_varndims(ncid_, var, &numDims) != NC_NOERR || numDims != 2) return {};
    nc_inq_vardimid(ncid_, var, dims);
    std::size_t rows = 0, length = 0;
    nc_inq_dimlen(ncid_, dims[0], &rows);
    nc_inq_dimlen(ncid_, dims[1], &length);
    std::string text(rows * length, '\0');
    if (!text.empty() && nc_get_var_text(ncid_, var, text.data()) != NC_NOERR) return {};
    std::vector<std::string> names;
    for (std::size_t r = 0; r < rows; ++r) {
      const std::string row = text.substr(r * length, length);
      names.push_back(row.substr(0, row.find('\0')));
    }
    return names;
  }

 private:
  const ExodusFile& file_;
  int ncid_;
};

/// The coefficient vectors of the blob named bex_cv_blob.
std::vector<std::vector<double>> ReadCoefficientVectors(const ExodusFile& file, const BexVariables& vars) {
  for (int blob = 1; vars.Find("blob_entity" + std::to_string(blob)) >= 0; ++blob) {
    const int entity = vars.Find("blob_entity" + std::to_string(blob));
    if (vars.Text(entity, "_name") != "bex_cv_blob") continue;
    const std::vector<int> info = vars.IntAttribute(entity, "bex_dense_cv_info");
    if (info.empty() || info.size() % 2 != 0) file.Fail("bex_cv_blob: bex_dense_cv_info must hold pairs (count, length)");
    const std::vector<std::string> names = vars.Names(vars.Find("name_blob_var"));
    int values = -1;
    for (std::size_t v = 0; v < names.size(); ++v) {
      if (names[v] == "bex_dense_cv_blocks") {
        values = vars.Find("vals_blob_var" + std::to_string(v + 1) + "blob" + std::to_string(blob));
      }
    }
    if (values < 0) file.Fail("bex_cv_blob: no variable bex_dense_cv_blocks");
    // Written once, at the first time step; a later step would repeat it.
    const std::vector<double> all = vars.Doubles(values, "bex_dense_cv_blocks");
    std::vector<std::vector<double>> vectors;
    std::size_t offset = 0;
    for (std::size_t b = 0; b < info.size(); b += 2) {
      const std::int64_t count = info[b], length = info[b + 1];
      if (count < 0 || length < 1 || static_cast<std::size_t>(count * length) > all.size() - offset) {
        file.Fail("bex_cv_blob: dense block " + std::to_string(b / 2) + " of " + std::to_string(count) + " vectors of " +
                  std::to_string(length) + " does not fit the " + std::to_string(all.size()) + " values");
      }
      for (std::int64_t i = 0; i < count; ++i, offset += static_cast<std::size_t>(length)) {
        vectors.emplace_back(all.begin() + static_cast<std::ptrdiff_t>(offset),
                             all.begin() + static_cast<std::ptrdiff_t>(offset + length));
      }
    }
    return vectors;
  }
  file.Fail("no blob named bex_cv_blob (the Bezier extraction coefficient vectors)");
}

/// The cell type of a BEX element type.
CellType BexCellType(const ExodusFile& file, const ExodusBlock& block) {
  if (block.typeName == "BEX_CURVE") return CellType::Line;
  if (block.typeName == "BEX_QUAD") return CellType::Quad;
  if (block.typeName == "BEX_HEX") return CellType::Hex;
  const std::string where = "element block " + std::to_string(block.id) + " (" + block.typeName + ")";
  if (block.typeName == "BEX_TRIANGLE" || block.typeName == "BEX_TETRA" || block.typeName == "BEX_WEDGE") {
    file.Fail(where + ": simplex Bezier extraction elements are not read (the order of their Bernstein "
                      "coefficients is not documented)");
  }
  file.Fail(where + ": not a Bezier extraction element type (BEX_CURVE, BEX_QUAD or BEX_HEX)");
}

}  // namespace

FieldGeometry ReadExodusBezierExtraction(const ExodusFile& file, const std::vector<ExodusBlock>& blocks) {
  const BexVariables vars(file);
  ExtractedSpline spline;
  spline.points = file.Coordinates();
  spline.coefficientVectors = ReadCoefficientVectors(file, vars);
  // Nodal attribute bex_weight: control points are stored times their weight.
  const int attributes = vars.Find("nattrb");
  if (attributes >= 0) {
    const std::vector<std::string> names = vars.Names(vars.Find("nattrib_name"));
    const std::vector<double> values = vars.Doubles(attributes, "nodal attributes");
    for (std::size_t a = 0; a < names.size(); ++a) {
      if (names[a] != "bex_weight") continue;
      const std::size_t n = spline.points.size() / 3;
      if (values.size() != n * names.size()) file.Fail("nodal attribute bex_weight: wrong size");
      spline.weights.resize(n);
      for (std::size_t i = 0; i < n; ++i) {
        const double w = values[i * names.size() + a];
        if (!(w > 0.0) || !std::isfinite(w)) file.Fail("node " + std::to_string(i + 1) + ": bex_weight " + std::to_string(w) + " is not positive");
        spline.weights[i] = w;
        for (int k = 0; k < 3; ++k) spline.points[3 * i + k] /= w;
      }
    }
  }

  std::vector<std::vector<ExtractionElement>> blockElements;
  std::vector<ExtractionElement> all;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const ExodusBlock& block = blocks[b];
    std::vector<ExtractionElement>& elements = blockElements.emplace_back();
    if (block.numElements == 0) continue;
    const CellType type = BexCellType(file, block);
    const std::string where = "element block " + std::to_string(block.id) + " (" + block.typeName + ")";
    const std::vector<int> degrees = vars.IntAttribute(vars.Find("connect" + std::to_string(b + 1)), "bex_elem_degrees");
    const int directions = type == CellType::Line ? 1 : type == CellType::Quad ? 2 : 3;
    if (static_cast<int>(degrees.size()) != directions) {
      file.Fail(where + ": bex_elem_degrees holds " + std::to_string(degrees.size()) + " degrees, expected " +
                std::to_string(directions));
    }
    if (block.nodesPerElement % 2 != 0) file.Fail(where + ": odd connectivity length (control points, then coefficient vectors)");
    const int n = block.nodesPerElement / 2;
    const std::vector<int> connectivity = file.Connectivity(block);
    for (std::int64_t e = 0; e < block.numElements; ++e) {
      ExtractionElement element;
      element.type = type;
      for (int d = 0; d < directions; ++d) element.degrees[d] = degrees[d];
      element.where = where + ", element " + std::to_string(e) + " of the block";
      const int* row = connectivity.data() + e * block.nodesPerElement;
      for (int i = 0; i < n; ++i) {
        element.points.push_back(static_cast<std::int64_t>(row[i]) - 1);
        element.coefficientVectors.push_back(static_cast<std::int64_t>(row[n + i]) - 1);
      }
      all.push_back(element);
      elements.push_back(std::move(element));
    }
  }
  if (all.empty()) file.Fail("no elements");
  FieldGeometry out;
  out.geometry.dimension = ExtractedDimension(spline, all);
  for (const std::vector<ExtractionElement>& elements : blockElements) {
    Patch& patch = out.geometry.patches.emplace_back(EmptyCellsPatch());
    for (const ExtractionElement& element : elements) {
      AddExtractedCell(spline, element, out.geometry.dimension, file.path(), &patch);
    }
  }
  return out;
}

}  // namespace invmap::fem
