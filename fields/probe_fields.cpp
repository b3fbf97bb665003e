// Fields at inverted points (include/invmap/fields.h).
#include <atomic>
#include <cmath>
#include <memory>
#include <limits>
#include <new>
#include <set>
#include <string>

#include "engine/bezier_nets.h"
#include "engine/cell_store.h"
#include "common/parallel.h"
#include "fields/cell_basis.h"
#include "invmap/fields.h"

namespace invmap {
namespace {

using kernels::CellShape;

/// How many points ahead ProbeFields requests a point's node values.
constexpr std::int64_t kLookAhead = 16;

/// Points (control points or vertices) of a patch.
std::size_t NumPoints(const Geometry& geometry, const Patch& patch) {
  return geometry.dimension > 0 ? patch.points.size() / static_cast<std::size_t>(geometry.dimension) : 0;
}

/// The shape of a Bezier patch or of cell `c` of a BezierCells patch.
CellShape ShapeOf(const Patch& patch, std::int64_t c) {
  std::array<int, kernels::kMaxFactors> degrees{0, 0, 0};
  if (patch.kind == Patch::Kind::BezierCells) {
    for (int f = 0; f < 3; ++f) degrees[f] = patch.cellDegrees[3 * static_cast<std::size_t>(c) + f];
    return CellShape(static_cast<kernels::CellType>(patch.cellTypes[static_cast<std::size_t>(c)]), degrees);
  }
  for (std::size_t f = 0; f < patch.degrees.size() && f < 3; ++f) degrees[f] = patch.degrees[f];
  return CellShape(static_cast<kernels::CellType>(patch.cell), degrees);
}

/// A BezierCells patch whose cells all have one shape and lie back to back
/// (cell c's control points start at c * shape.numControlPoints()), as a
/// mesh of one element type becomes: a point's cell then needs no reads of
/// its type, degrees and offset, which in random point order cost a cache
/// miss each.
struct UniformCells {
  bool uniform = false;
  CellShape shape;
  /// What LinearBasis evaluates for this shape: a linear tetrahedron or
  /// hexahedron (of a polynomial patch), else None.
  enum class Linear { None, Tet, Hex } linear = Linear::None;
};

/// EvaluateCellBasis of a linear tetrahedron or hexahedron (`linear`), in
/// the same operations in the same order (so the same bits), without its
/// loops over factors and degrees: 468 instructions a point instead of
/// 791 on random points in linear hexahedra (callgrind).
int LinearBasis(UniformCells::Linear linear, const double* params, double* out) {
  if (linear == UniformCells::Linear::Tet) {
    out[0] = 1.0;
    for (int i = 0; i < 3; ++i) {
      out[0] -= params[i];
      out[i + 1] = params[i];
    }
    return 4;
  }
  // Earlier factors fastest, each factor's (1 - u, u).
  double f[3][2];
  for (int i = 0; i < 3; ++i) {
    f[i][0] = 1.0;
    f[i][0] -= params[i];
    f[i][1] = params[i];
  }
  for (int c = 0; c < 8; ++c) out[c] = (f[0][c & 1] * f[1][(c >> 1) & 1]) * f[2][c >> 2];
  return 8;
}

/// Finds whether `patch` is uniform. Costs one pass over its cells, so it
/// is asked only when the points are not much fewer than the cells.
UniformCells FindUniformCells(const Patch& patch) {
  UniformCells cells;
  const std::size_t count = patch.cellTypes.size();
  if (patch.kind != Patch::Kind::BezierCells || count == 0 || patch.cellDegrees.size() != 3 * count ||
      patch.cellOffsets.size() != count + 1) {
    return cells;
  }
  for (std::size_t c = 1; c < count; ++c) {
    if (patch.cellTypes[c] != patch.cellTypes[0]) return cells;
  }
  for (std::size_t k = 3; k < patch.cellDegrees.size(); ++k) {
    if (patch.cellDegrees[k] != patch.cellDegrees[k % 3]) return cells;
  }
  const CellShape shape = ShapeOf(patch, 0);
  const std::int64_t stride = shape.numControlPoints();
  for (std::size_t c = 0; c <= count; ++c) {
    if (patch.cellOffsets[c] != static_cast<std::int64_t>(c) * stride) return cells;
  }
  cells.uniform = true;
  cells.shape = shape;
  bool degreeOne = true;
  for (int f = 0; f < shape.numFactors(); ++f) degreeOne = degreeOne && shape.factor(f).degree == 1;
  if (degreeOne && patch.weights.empty()) {
    if (shape.type() == kernels::CellType::Tet) cells.linear = UniformCells::Linear::Tet;
    if (shape.type() == kernels::CellType::Hex) cells.linear = UniformCells::Linear::Hex;
  }
  return cells;
}

/// Evaluates the fields at one found point. Returns false when the point's
/// patch or cell does not exist in the geometry.
class PointProbe {
 public:
  /// `uniformCells`: per patch, as FindUniformCells found it (or all not uniform).
  PointProbe(const Geometry& geometry, const std::vector<const NodeField*>& fields,
             const std::vector<UniformCells>& uniformCells)
      : geometry_(geometry), fields_(fields), uniformCells_(uniformCells) {}

  bool Evaluate(std::int32_t patchIndex, std::int64_t cell, const double* params, double* out) {
    if (patchIndex < 0 || static_cast<std::size_t>(patchIndex) >= geometry_.patches.size()) return false;
    const Patch& patch = geometry_.patches[static_cast<std::size_t>(patchIndex)];
    if (patch.kind == Patch::Kind::BSpline) {
      Fill(out, std::numeric_limits<double>::quiet_NaN());
      return true;
    }
    std::int64_t first = 0;
    CellShape shape;
    UniformCells::Linear linear = UniformCells::Linear::None;
    if (patch.kind == Patch::Kind::BezierCells) {
      if (cell < 0 || static_cast<std::size_t>(cell) >= patch.cellTypes.size()) return false;
      const UniformCells& uniform = uniformCells_[static_cast<std::size_t>(patchIndex)];
      if (uniform.uniform) {
        shape = uniform.shape;
        first = cell * shape.numControlPoints();
        linear = uniform.linear;
      } else {
        shape = ShapeOf(patch, cell);
        first = patch.cellOffsets[static_cast<std::size_t>(cell)];
      }
    } else if (patch.kind == Patch::Kind::Bezier) {
      if (cell != 0) return false;
      shape = ShapeOf(patch, 0);
    } else {
      const engine::MeshCellLayout layout = engine::LayoutOf(patch.cell);
      if (cell < 0 || static_cast<std::size_t>(cell + 1) * layout.vertices > patch.cells.size()) return false;
      shape = CellShape(static_cast<kernels::CellType>(patch.cell), {1, 1, 1});
      for (int k = 0; k < layout.vertices; ++k) {
        meshPoints_[k] = patch.cells[static_cast<std::size_t>(cell) * layout.vertices + layout.bezierFromFe[k]];
      }
    }
    const double* weights = patch.weights.empty() ? nullptr : patch.weights.data() + first;
    const int count = linear != UniformCells::Linear::None ? LinearBasis(linear, params, basis_)
                                                           : fields::EvaluateCellBasis(shape, params, weights, basis_);
    for (const NodeField* field : fields_) {
      const std::vector<double>& values = field->patchValues[static_cast<std::size_t>(patchIndex)];
      const int n = field->components;
      for (int j = 0; j < n; ++j) out[j] = values.empty() ? std::numeric_limits<double>::quiet_NaN() : 0.0;
      if (!values.empty()) {
        for (int k = 0; k < count; ++k) {
          const std::size_t point =
              patch.kind == Patch::Kind::Mesh ? static_cast<std::size_t>(meshPoints_[k]) : first + k;
          const double* v = values.data() + point * n;
          for (int j = 0; j < n; ++j) out[j] += basis_[k] * v[j];
        }
      }
      out += n;
    }
    return true;
  }

  /// Requests from memory the node values Evaluate will read for a point
  /// in `cell` of a uniform patch (fields/probe_fields.cpp's block loop
  /// asks kLookAhead points ahead): in the caller's order, which is random
  /// in space, each point's values are a cache miss or two of their own.
  void Prefetch(std::int32_t patchIndex, std::int64_t cell) const {
    if (patchIndex < 0 || static_cast<std::size_t>(patchIndex) >= geometry_.patches.size()) return;
    const UniformCells& uniform = uniformCells_[static_cast<std::size_t>(patchIndex)];
    const Patch& patch = geometry_.patches[static_cast<std::size_t>(patchIndex)];
    if (!uniform.uniform || cell < 0 || static_cast<std::size_t>(cell) >= patch.cellTypes.size()) return;
    const std::size_t count = static_cast<std::size_t>(uniform.shape.numControlPoints());
    for (const NodeField* field : fields_) {
      const std::vector<double>& values = field->patchValues[static_cast<std::size_t>(patchIndex)];
      if (values.empty()) continue;
      const std::size_t n = static_cast<std::size_t>(field->components);
      const char* first = reinterpret_cast<const char*>(values.data() + static_cast<std::size_t>(cell) * count * n);
      const char* last = first + count * n * sizeof(double) - 1;
      for (const char* line = first; line < last; line += 64) __builtin_prefetch(line);
      __builtin_prefetch(last);
    }
  }

  void Fill(double* out, double value) const {
    for (const NodeField* field : fields_) {
      for (int j = 0; j < field->components; ++j) *out++ = value;
    }
  }

 private:
  const Geometry& geometry_;
  const std::vector<const NodeField*>& fields_;
  const std::vector<UniformCells>& uniformCells_;
  double basis_[fields::kMaxCellBasis];
  std::int64_t meshPoints_[8];
};

}  // namespace

std::string CheckFields(const Geometry& geometry, const std::vector<NodeField>& fields) {
  std::set<std::string> names;
  for (const NodeField& field : fields) {
    const std::string where = "field '" + field.name + "': ";
    if (field.name.empty()) return "a field has an empty name";
    if (!names.insert(field.name).second) return where + "defined twice";
    if (field.components < 1) return where + "components must be at least 1";
    if (field.patchValues.size() != geometry.patches.size()) {
      return where + std::to_string(field.patchValues.size()) + " patch arrays for " +
             std::to_string(geometry.patches.size()) + " patches";
    }
    for (std::size_t p = 0; p < geometry.patches.size(); ++p) {
      const std::vector<double>& values = field.patchValues[p];
      if (values.empty()) continue;
      const Patch& patch = geometry.patches[p];
      if (patch.kind == Patch::Kind::BSpline) return where + "patch " + std::to_string(p) + ": a B-spline patch has no nodes";
      const std::size_t expected = NumPoints(geometry, patch) * static_cast<std::size_t>(field.components);
      if (values.size() != expected) {
        return where + "patch " + std::to_string(p) + ": " + std::to_string(values.size()) + " values, expected " +
               std::to_string(expected);
      }
    }
  }
  return {};
}

int FieldWidth(const std::vector<const NodeField*>& fields) {
  int width = 0;
  for (const NodeField* field : fields) width += field->components;
  return width;
}

std::vector<std::string> FieldColumnNames(const std::vector<const NodeField*>& fields) {
  std::vector<std::string> names;
  for (const NodeField* field : fields) {
    if (field->components == 1) {
      names.push_back(field->name);
      continue;
    }
    for (int j = 0; j < field->components; ++j) names.push_back(field->name + "_" + std::to_string(j));
  }
  return names;
}

Error ProbeFields(const Geometry& geometry, const std::vector<const NodeField*>& fields, const Results& results,
                  std::vector<double>* values, std::string* message, int threads) {
  try {
    const std::size_t n = results.status.size();
    const std::size_t width = static_cast<std::size_t>(FieldWidth(fields));
    for (const NodeField* field : fields) {
      if (field == nullptr || field->components < 1 || field->patchValues.size() != geometry.patches.size()) {
        if (message != nullptr) *message = "ProbeFields: a field does not fit the geometry (see CheckFields)";
        return Error::InvalidArgument;
      }
    }
    values->assign(n * width, std::numeric_limits<double>::quiet_NaN());
    std::vector<UniformCells> uniformCells(geometry.patches.size());
    for (std::size_t p = 0; p < geometry.patches.size(); ++p) {
      if (8 * n >= geometry.patches[p].cellTypes.size()) uniformCells[p] = FindUniformCells(geometry.patches[p]);
    }
    // Points are independent: blocks in parallel, each with its own scratch;
    // the first point (in input order) the geometry lacks a cell for is reported.
    std::atomic<std::int64_t> firstBad{static_cast<std::int64_t>(n)};
    ForEachBlock(
        ExecutionPolicy::Par, static_cast<std::int64_t>(n), 4096,
        [&](std::int64_t begin, std::int64_t end) {
          auto probe = std::make_unique<PointProbe>(geometry, fields, uniformCells);
          for (std::int64_t i = begin; i < end; ++i) {
            const std::int64_t ahead = i + kLookAhead;
            if (ahead < end && results.status[ahead] == Status::Found) {
              probe->Prefetch(results.patch[ahead], results.cell[ahead]);
            }
            if (results.status[i] != Status::Found) continue;
            if (!probe->Evaluate(results.patch[i], results.cell[i], &results.params[3 * i],
                                 values->data() + i * width)) {
              std::int64_t expected = firstBad.load();
              while (i < expected && !firstBad.compare_exchange_weak(expected, i)) {
              }
              return;
            }
          }
        },
        threads);
    const std::int64_t bad = firstBad.load();
    if (bad < static_cast<std::int64_t>(n)) {
      if (message != nullptr) {
        *message = "ProbeFields: point " + std::to_string(bad) + " is in patch " + std::to_string(results.patch[bad]) +
                   ", cell " + std::to_string(results.cell[bad]) + ", which the geometry does not have";
      }
      return Error::InvalidArgument;
    }
    return Error::Ok;
  } catch (const std::bad_alloc&) {
    if (message != nullptr) *message = "out of memory";
    return Error::OutOfMemory;
  } catch (const std::exception& e) {
    if (message != nullptr) *message = e.what();
    return Error::Internal;
  }
}

}  // namespace invmap
