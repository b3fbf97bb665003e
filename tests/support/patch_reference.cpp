#include "tests/support/patch_reference.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include "tests/support/bspline_reference.h"

namespace invmap::testing {
namespace {

/// Vertices of a linear mesh cell (docs/formats.md section 2).
int MeshCellVertices(CellType type) {
  switch (type) {
    case CellType::Line:
      return 2;
    case CellType::Tri:
      return 3;
    case CellType::Quad:
      return 4;
    case CellType::Tet:
      return 4;
    case CellType::Hex:
      return 8;
    case CellType::Wedge:
      return 6;
  }
  return 0;
}

/// Bernstein polynomial B_{a,p}(s) from its definition.
double Bernstein(int p, int a, double s) {
  double binomial = 1.0;
  for (int k = 1; k <= a; ++k) binomial = binomial * (p - a + k) / k;
  return binomial * std::pow(s, a) * std::pow(1.0 - s, p - a);
}

/// Solves A X = B in place for an n x n row-major A and n x m row-major B
/// (X written to B) by Gaussian elimination with partial pivoting.
void SolveInPlace(int n, int m, std::vector<double>& a, std::vector<double>& b) {
  for (int col = 0; col < n; ++col) {
    int pivot = col;
    for (int r = col + 1; r < n; ++r) {
      if (std::fabs(a[r * n + col]) > std::fabs(a[pivot * n + col])) pivot = r;
    }
    if (pivot != col) {
      for (int c = 0; c < n; ++c) std::swap(a[col * n + c], a[pivot * n + c]);
      for (int c = 0; c < m; ++c) std::swap(b[col * m + c], b[pivot * m + c]);
    }
    for (int r = col + 1; r < n; ++r) {
      const double f = a[r * n + col] / a[col * n + col];
      for (int c = col; c < n; ++c) a[r * n + c] -= f * a[col * n + c];
      for (int c = 0; c < m; ++c) b[r * m + c] -= f * b[col * m + c];
    }
  }
  for (int col = n - 1; col >= 0; --col) {
    for (int c = 0; c < m; ++c) {
      double v = b[col * m + c];
      for (int k = col + 1; k < n; ++k) v -= a[col * n + k] * b[k * m + c];
      b[col * m + c] = v / a[col * n + col];
    }
  }
}

/// The (p + 1) x (p + 1) matrix E (row = Bezier index, column = active
/// control point span - p + j) of one non-empty span: the Bernstein form of
/// the span's Cox-de Boor piece, found by interpolation at the nodes k / p
/// (an exact change of basis for polynomials of degree p).
std::vector<double> SpanToBezier(const std::vector<double>& knots, int p, int span) {
  const int n = p + 1;
  const double lo = knots[span], hi = knots[span + 1];
  std::vector<double> bernstein(n * n), values(n * n);
  for (int k = 0; k < n; ++k) {
    const double s = static_cast<double>(k) / p;
    const std::vector<double> basis = CoxDeBoorBasis(knots, p, span, lo + (hi - lo) * s);
    for (int a = 0; a < n; ++a) bernstein[k * n + a] = Bernstein(p, a, s);
    for (int j = 0; j < n; ++j) values[k * n + j] = basis[span - p + j];
  }
  SolveInPlace(n, n, bernstein, values);
  return values;
}

/// Shape functions of a linear mesh cell at reference coordinates u, in FE
/// vertex order (docs/formats.md section 2), written out per type.
int FeShape(CellType type, const double* u, double* n) {
  const double s = u[0], t = u[1], r = u[2];
  switch (type) {
    case CellType::Line:
      n[0] = 1 - s, n[1] = s;
      return 2;
    case CellType::Tri:
      n[0] = 1 - s - t, n[1] = s, n[2] = t;
      return 3;
    case CellType::Quad:
      n[0] = (1 - s) * (1 - t), n[1] = s * (1 - t), n[2] = s * t, n[3] = (1 - s) * t;
      return 4;
    case CellType::Tet:
      n[0] = 1 - s - t - r, n[1] = s, n[2] = t, n[3] = r;
      return 4;
    case CellType::Hex: {
      const double q[4] = {(1 - s) * (1 - t), s * (1 - t), s * t, (1 - s) * t};
      for (int k = 0; k < 4; ++k) n[k] = q[k] * (1 - r), n[k + 4] = q[k] * r;
      return 8;
    }
    case CellType::Wedge: {
      const double q[3] = {1 - s - t, s, t};
      for (int k = 0; k < 3; ++k) n[k] = q[k] * (1 - r), n[k + 3] = q[k] * r;
      return 6;
    }
  }
  return 0;
}

/// Checks that params[paramDim ..) are NaN (the unused parameters).
std::string CheckUnusedNaN(const double* params, int paramDim) {
  for (int d = paramDim; d < 3; ++d) {
    if (!std::isnan(params[d])) return "params[" + std::to_string(d) + "] is unused but not NaN";
  }
  return "";
}

RefCell BezierRefCell(const Geometry& geometry, const Patch& patch) {
  RefCell cell;
  cell.type = ToRefType(patch.cell);
  for (std::size_t f = 0; f < patch.degrees.size() && f < 3; ++f) cell.degrees[f] = patch.degrees[f];
  cell.ambientDim = geometry.dimension;
  cell.points = patch.points;
  cell.weights = patch.weights;
  return cell;
}

/// Cell c of a BezierCells patch as a reference cell.
RefCell CellOfBezierCells(const Geometry& geometry, const Patch& patch, std::size_t c) {
  RefCell cell;
  const int dim = geometry.dimension;
  cell.type = ToRefType(patch.cellTypes[c]);
  for (int f = 0; f < 3; ++f) cell.degrees[f] = patch.cellDegrees[3 * c + f];
  const std::int64_t first = patch.cellOffsets[c], last = patch.cellOffsets[c + 1];
  cell.ambientDim = dim;
  cell.points.assign(patch.points.begin() + first * dim, patch.points.begin() + last * dim);
  if (!patch.weights.empty()) cell.weights.assign(patch.weights.begin() + first, patch.weights.begin() + last);
  return cell;
}

}  // namespace

kernels::CellType ToRefType(CellType type) {
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

std::vector<int> NonEmptySpans(const std::vector<double>& knots, int degree, int count) {
  std::vector<int> spans;
  for (int i = degree; i < count; ++i) {
    if (knots[i] < knots[i + 1]) spans.push_back(i);
  }
  return spans;
}

std::vector<PatchCell> PatchCells(const Geometry& geometry, int patchIndex) {
  const Patch& patch = geometry.patches[patchIndex];
  const int dim = geometry.dimension;
  std::vector<PatchCell> out;
  switch (patch.kind) {
    case Patch::Kind::TrimmedSurface:
      break;  // CAD faces have their own references (tests/cad)
    case Patch::Kind::Bezier: {
      PatchCell pc;
      pc.cell = BezierRefCell(geometry, patch);
      pc.patch = patchIndex;
      out.push_back(std::move(pc));
      break;
    }
    case Patch::Kind::PouManifold:
      break;  // not Bezier cells: tests/support/pou_reference.h evaluates them
    case Patch::Kind::BezierCells: {
      for (std::size_t c = 0; c < patch.cellTypes.size(); ++c) {
        PatchCell pc;
        pc.cell = CellOfBezierCells(geometry, patch, c);
        pc.patch = patchIndex;
        pc.index = static_cast<std::int64_t>(c);
        out.push_back(std::move(pc));
      }
      break;
    }
    case Patch::Kind::Mesh: {
      // FE order to Bezier (tensor, first coordinate fastest) order.
      static const int kQuad[4] = {0, 1, 3, 2};
      static const int kHex[8] = {0, 1, 3, 2, 4, 5, 7, 6};
      const int nv = MeshCellVertices(patch.cell);
      const std::size_t numCells = patch.cells.size() / nv;
      RefCell proto;
      proto.type = ToRefType(patch.cell);
      proto.ambientDim = dim;
      switch (patch.cell) {
        case CellType::Quad:
        case CellType::Wedge:
          proto.degrees = {{1, 1, 0}};
          break;
        case CellType::Hex:
          proto.degrees = {{1, 1, 1}};
          break;
        default:
          proto.degrees = {{1, 0, 0}};
      }
      out.reserve(numCells);
      for (std::size_t c = 0; c < numCells; ++c) {
        PatchCell pc;
        pc.cell = proto;
        pc.patch = patchIndex;
        pc.index = static_cast<std::int64_t>(c);
        pc.linearSimplex = patch.cell == CellType::Tri || patch.cell == CellType::Line;
        pc.cell.points.resize(static_cast<std::size_t>(nv) * dim);
        for (int b = 0; b < nv; ++b) {
          const int fe = patch.cell == CellType::Quad ? kQuad[b] : patch.cell == CellType::Hex ? kHex[b] : b;
          const std::int64_t v = patch.cells[c * nv + fe];
          for (int k = 0; k < dim; ++k) pc.cell.points[b * dim + k] = patch.points[v * dim + k];
        }
        out.push_back(std::move(pc));
      }
      break;
    }
    case Patch::Kind::BSpline: {
      const int pd = static_cast<int>(patch.degrees.size());
      const bool rational = !patch.weights.empty();
      std::vector<int> spans[3];
      std::vector<std::vector<double>> ops[3];
      int deg[3] = {0, 0, 0}, cnt[3] = {1, 1, 1};
      for (int d = 0; d < 3; ++d) {
        if (d < pd) {
          deg[d] = patch.degrees[d];
          cnt[d] = patch.counts[d];
          spans[d] = NonEmptySpans(patch.knots[d], deg[d], cnt[d]);
          for (int s : spans[d]) ops[d].push_back(SpanToBezier(patch.knots[d], deg[d], s));
        } else {
          spans[d] = {0};
          ops[d] = {{1.0}};
        }
      }
      const int h = dim + 1;  // homogeneous coordinates (w x, w)
      const int n0 = deg[0] + 1, n1 = deg[1] + 1, n2 = deg[2] + 1;
      std::vector<double> local(static_cast<std::size_t>(n0) * n1 * n2 * h), tmp(local.size());
      for (std::size_t sw = 0; sw < spans[2].size(); ++sw) {
        for (std::size_t sv = 0; sv < spans[1].size(); ++sv) {
          for (std::size_t su = 0; su < spans[0].size(); ++su) {
            const int first[3] = {spans[0][su] - deg[0], spans[1][sv] - deg[1], spans[2][sw] - deg[2]};
            for (int l = 0; l < n2; ++l)
              for (int k = 0; k < n1; ++k)
                for (int j = 0; j < n0; ++j) {
                  const std::size_t g =
                      (static_cast<std::size_t>(first[2] + l) * cnt[1] + first[1] + k) * cnt[0] + first[0] + j;
                  const double w = rational ? patch.weights[g] : 1.0;
                  double* dst = &local[((static_cast<std::size_t>(l) * n1 + k) * n0 + j) * h];
                  for (int c = 0; c < dim; ++c) dst[c] = w * patch.points[g * dim + c];
                  dst[dim] = w;
                }
            // Apply the three span operators, one direction at a time.
            const double* eu = ops[0][su].data();
            const double* ev = ops[1][sv].data();
            const double* ew = ops[2][sw].data();
            std::fill(tmp.begin(), tmp.end(), 0.0);
            for (int l = 0; l < n2; ++l)
              for (int k = 0; k < n1; ++k)
                for (int a = 0; a < n0; ++a)
                  for (int j = 0; j < n0; ++j)
                    for (int c = 0; c < h; ++c)
                      tmp[((l * n1 + k) * n0 + a) * h + c] += eu[a * n0 + j] * local[((l * n1 + k) * n0 + j) * h + c];
            std::fill(local.begin(), local.end(), 0.0);
            for (int l = 0; l < n2; ++l)
              for (int b = 0; b < n1; ++b)
                for (int k = 0; k < n1; ++k)
                  for (int a = 0; a < n0; ++a)
                    for (int c = 0; c < h; ++c)
                      local[((l * n1 + b) * n0 + a) * h + c] += ev[b * n1 + k] * tmp[((l * n1 + k) * n0 + a) * h + c];
            std::fill(tmp.begin(), tmp.end(), 0.0);
            for (int e = 0; e < n2; ++e)
              for (int l = 0; l < n2; ++l)
                for (int b = 0; b < n1; ++b)
                  for (int a = 0; a < n0; ++a)
                    for (int c = 0; c < h; ++c)
                      tmp[((e * n1 + b) * n0 + a) * h + c] += ew[e * n2 + l] * local[((l * n1 + b) * n0 + a) * h + c];
            PatchCell pc;
            pc.patch = patchIndex;
            pc.index = static_cast<std::int64_t>(out.size());
            pc.cell.type = pd == 1 ? kernels::CellType::Line : pd == 2 ? kernels::CellType::Quad : kernels::CellType::Hex;
            pc.cell.degrees = {{deg[0], deg[1], deg[2]}};
            pc.cell.ambientDim = dim;
            const int numPoints = n0 * n1 * n2;
            pc.cell.points.resize(static_cast<std::size_t>(numPoints) * dim);
            if (rational) pc.cell.weights.resize(numPoints);
            for (int q = 0; q < numPoints; ++q) {
              const double w = tmp[q * h + dim];
              for (int c = 0; c < dim; ++c) pc.cell.points[q * dim + c] = tmp[q * h + c] / w;
              if (rational) pc.cell.weights[q] = w;
            }
            const int spanIndex[3] = {spans[0][su], spans[1][sv], spans[2][sw]};
            for (int d = 0; d < pd; ++d) {
              const double lo = patch.knots[d][spanIndex[d]], hi = patch.knots[d][spanIndex[d] + 1];
              pc.paramLo[d] = lo;
              pc.paramScale[d] = hi - lo;
            }
            out.push_back(std::move(pc));
          }
        }
      }
      break;
    }
  }
  return out;
}

std::vector<PatchCell> GeometryCells(const Geometry& geometry) {
  std::vector<PatchCell> all;
  for (std::size_t p = 0; p < geometry.patches.size(); ++p) {
    std::vector<PatchCell> cells = PatchCells(geometry, static_cast<int>(p));
    for (PatchCell& c : cells) all.push_back(std::move(c));
  }
  return all;
}

void GeometryControlBox(const Geometry& geometry, double lo[3], double hi[3]) {
  const int dim = geometry.dimension;
  bool any = false;
  for (int k = 0; k < 3; ++k) lo[k] = hi[k] = 0.0;
  for (const Patch& patch : geometry.patches) {
    for (std::size_t i = 0; i + dim <= patch.points.size(); i += dim) {
      for (int k = 0; k < dim; ++k) {
        lo[k] = any ? std::min(lo[k], patch.points[i + k]) : patch.points[i + k];
        hi[k] = any ? std::max(hi[k], patch.points[i + k]) : patch.points[i + k];
      }
      any = true;
    }
  }
}

double GeometrySize(const Geometry& geometry) {
  double lo[3], hi[3];
  GeometryControlBox(geometry, lo, hi);
  double s = 0.0;
  for (int k = 0; k < 3; ++k) s += (hi[k] - lo[k]) * (hi[k] - lo[k]);
  return std::sqrt(s);
}

std::vector<std::int64_t> CellCounts(const Geometry& geometry) {
  std::vector<std::int64_t> counts;
  for (const Patch& patch : geometry.patches) {
    switch (patch.kind) {
      case Patch::Kind::TrimmedSurface:
        counts.push_back(0);  // CAD faces have their own references (tests/cad)
        break;
      case Patch::Kind::Bezier:
        counts.push_back(1);
        break;
      case Patch::Kind::BezierCells:
        counts.push_back(static_cast<std::int64_t>(patch.cellTypes.size()));
        break;
      case Patch::Kind::PouManifold:
        counts.push_back(static_cast<std::int64_t>(patch.degrees.size()));
        break;
      case Patch::Kind::Mesh:
        counts.push_back(static_cast<std::int64_t>(patch.cells.size() / MeshCellVertices(patch.cell)));
        break;
      case Patch::Kind::BSpline: {
        std::int64_t n = 1;
        for (std::size_t d = 0; d < patch.degrees.size(); ++d) {
          n *= static_cast<std::int64_t>(NonEmptySpans(patch.knots[d], patch.degrees[d], patch.counts[d]).size());
        }
        counts.push_back(n);
        break;
      }
    }
  }
  return counts;
}

std::string EvaluateReported(const Geometry& geometry, std::int32_t patchIndex, std::int64_t cell,
                             const double* params, double paramTol, double* x) {
  const int dim = geometry.dimension;
  for (int k = 0; k < 3; ++k) x[k] = 0.0;
  if (patchIndex < 0 || patchIndex >= static_cast<std::int32_t>(geometry.patches.size())) {
    return "patch index out of range";
  }
  const Patch& patch = geometry.patches[patchIndex];
  switch (patch.kind) {
    case Patch::Kind::TrimmedSurface:
      return "trimmed surfaces are checked by tests/cad";
    case Patch::Kind::Bezier: {
      if (cell != 0) return "a Bezier patch has only cell 0";
      const RefCell ref = BezierRefCell(geometry, patch);
      const int pd = ParamDimOf(ref.type);
      if (std::string e = CheckUnusedNaN(params, pd); !e.empty()) return e;
      double u[3] = {0, 0, 0};
      for (int d = 0; d < pd; ++d) u[d] = params[d];
      if (!InReferenceDomain(ref.type, u, paramTol)) return "params outside the reference domain";
      RefEvaluate(ref, u, x);
      return "";
    }
    case Patch::Kind::PouManifold:
      return "pou_manifold patches are checked by tests/support/pou_reference.h";
    case Patch::Kind::BezierCells: {
      if (cell < 0 || cell >= static_cast<std::int64_t>(patch.cellTypes.size())) return "cell index out of range";
      const RefCell ref = CellOfBezierCells(geometry, patch, static_cast<std::size_t>(cell));
      const int pd = ParamDimOf(ref.type);
      if (std::string e = CheckUnusedNaN(params, pd); !e.empty()) return e;
      double u[3] = {0, 0, 0};
      for (int d = 0; d < pd; ++d) u[d] = params[d];
      if (!InReferenceDomain(ref.type, u, paramTol)) return "params outside the reference domain";
      RefEvaluate(ref, u, x);
      return "";
    }
    case Patch::Kind::Mesh: {
      const int nv = MeshCellVertices(patch.cell);
      const std::int64_t numCells = static_cast<std::int64_t>(patch.cells.size() / nv);
      if (cell < 0 || cell >= numCells) return "mesh cell index out of range";
      const int pd = ParamDimOf(ToRefType(patch.cell));
      if (std::string e = CheckUnusedNaN(params, pd); !e.empty()) return e;
      double u[3] = {0, 0, 0};
      for (int d = 0; d < pd; ++d) u[d] = params[d];
      if (!InReferenceDomain(ToRefType(patch.cell), u, paramTol)) return "params outside the reference domain";
      double n[8];
      FeShape(patch.cell, u, n);
      for (int v = 0; v < nv; ++v) {
        const std::int64_t index = patch.cells[cell * nv + v];
        for (int k = 0; k < dim; ++k) x[k] += n[v] * patch.points[index * dim + k];
      }
      return "";
    }
    case Patch::Kind::BSpline: {
      const int pd = static_cast<int>(patch.degrees.size());
      if (std::string e = CheckUnusedNaN(params, pd); !e.empty()) return e;
      if (cell < 0) return "negative cell index";
      std::vector<double> basis[3] = {{1.0}, {1.0}, {1.0}};
      std::int64_t rest = cell;
      std::int64_t total = 1;
      int first[3] = {0, 0, 0};
      for (int d = 0; d < pd; ++d) {
        const std::vector<int> spans = NonEmptySpans(patch.knots[d], patch.degrees[d], patch.counts[d]);
        total *= static_cast<std::int64_t>(spans.size());
        const int span = spans[rest % static_cast<std::int64_t>(spans.size())];
        rest /= static_cast<std::int64_t>(spans.size());
        const double lo = patch.knots[d][span], hi = patch.knots[d][span + 1];
        const double slack = paramTol * (hi - lo);
        if (!(params[d] >= lo - slack && params[d] <= hi + slack)) {
          std::ostringstream os;
          os.precision(17);
          os << "params[" << d << "] = " << params[d] << " outside the cell's knot span [" << lo << ", " << hi << "]";
          return os.str();
        }
        const std::vector<double> all = CoxDeBoorBasis(patch.knots[d], patch.degrees[d], span, params[d]);
        basis[d].assign(all.begin() + (span - patch.degrees[d]), all.begin() + span + 1);
        first[d] = span - patch.degrees[d];
      }
      if (cell >= total) return "B-spline cell index out of range";
      const bool rational = !patch.weights.empty();
      double sum[4] = {0, 0, 0, 0};
      const int cu = patch.counts[0];
      const int cv = pd > 1 ? patch.counts[1] : 1;
      for (std::size_t l = 0; l < basis[2].size(); ++l)
        for (std::size_t k = 0; k < basis[1].size(); ++k)
          for (std::size_t j = 0; j < basis[0].size(); ++j) {
            const std::size_t g = (static_cast<std::size_t>(first[2] + l) * cv + first[1] + k) * cu + first[0] + j;
            const double b = basis[0][j] * basis[1][k] * basis[2][l] * (rational ? patch.weights[g] : 1.0);
            for (int c = 0; c < dim; ++c) sum[c] += b * patch.points[g * dim + c];
            sum[3] += b;
          }
      for (int c = 0; c < dim; ++c) x[c] = rational ? sum[c] / sum[3] : sum[c];
      return "";
    }
  }
  return "unknown patch kind";
}

}  // namespace invmap::testing
