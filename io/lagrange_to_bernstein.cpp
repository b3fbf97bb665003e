#include "io/lagrange_to_bernstein.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace invmap::io {
namespace {

using Real = long double;

/// Simplex factors of a cell type: their dimensions, first factor first.
std::vector<int> FactorDims(CellType type) {
  switch (type) {
    case CellType::Line:
      return {1};
    case CellType::Tri:
      return {2};
    case CellType::Quad:
      return {1, 1};
    case CellType::Tet:
      return {3};
    case CellType::Hex:
      return {1, 1, 1};
    case CellType::Wedge:
      return {2, 1};
  }
  return {};
}

/// Multi-indices (a1, .., ad) of a simplex factor of degree p, a1 fastest.
std::vector<std::array<int, 3>> SimplexIndices(int dim, int p) {
  std::vector<std::array<int, 3>> out;
  for (int a3 = 0; a3 <= (dim >= 3 ? p : 0); ++a3) {
    for (int a2 = 0; a2 <= (dim >= 2 ? p - a3 : 0); ++a2) {
      for (int a1 = 0; a1 <= p - a2 - a3; ++a1) out.push_back({a1, a2, a3});
    }
  }
  return out;
}

/// n!
Real Factorial(int n) {
  Real f = 1;
  for (int k = 2; k <= n; ++k) f *= k;
  return f;
}

/// x^n for n >= 0 (0^0 = 1).
Real Power(Real x, int n) {
  Real y = 1;
  for (int k = 0; k < n; ++k) y *= x;
  return y;
}

/// Values of every Bernstein polynomial of the cell at reference point x, in
/// control point order (tensor products: first factor fastest).
std::vector<Real> BernsteinValues(CellType type, int p, const std::array<double, 3>& x) {
  std::vector<Real> values{1};
  int offset = 0;
  for (const int dim : FactorDims(type)) {
    Real lambda[4];
    lambda[0] = 1;
    for (int k = 0; k < dim; ++k) {
      lambda[k + 1] = x[offset + k];
      lambda[0] -= lambda[k + 1];
    }
    const auto indices = SimplexIndices(dim, p);
    std::vector<Real> factor(indices.size());
    for (std::size_t i = 0; i < indices.size(); ++i) {
      int a0 = p;
      Real v = 1;
      for (int k = 0; k < dim; ++k) {
        a0 -= indices[i][k];
        v *= Power(lambda[k + 1], indices[i][k]) / Factorial(indices[i][k]);
      }
      factor[i] = Factorial(p) * v * Power(lambda[0], a0) / Factorial(a0);
    }
    // Earlier factors vary fastest.
    std::vector<Real> product(values.size() * factor.size());
    for (std::size_t j = 0; j < factor.size(); ++j) {
      for (std::size_t i = 0; i < values.size(); ++i) product[j * values.size() + i] = values[i] * factor[j];
    }
    values.swap(product);
    offset += dim;
  }
  return values;
}

/// Solves A X = B in place (A n x n, B n x m, row-major) by Gaussian
/// elimination with partial pivoting; B receives X. False when A is
/// numerically singular.
bool Solve(std::vector<Real> a, int n, std::vector<Real>* b, int m) {
  Real scale = 0;
  for (const Real v : a) scale = std::max(scale, std::fabs(v));
  for (int col = 0; col < n; ++col) {
    int pivot = col;
    for (int r = col + 1; r < n; ++r) {
      if (std::fabs(a[r * n + col]) > std::fabs(a[pivot * n + col])) pivot = r;
    }
    if (!(std::fabs(a[pivot * n + col]) > 1e-12L * scale)) return false;
    if (pivot != col) {
      for (int k = 0; k < n; ++k) std::swap(a[col * n + k], a[pivot * n + k]);
      for (int k = 0; k < m; ++k) std::swap((*b)[col * m + k], (*b)[pivot * m + k]);
    }
    for (int r = col + 1; r < n; ++r) {
      const Real f = a[r * n + col] / a[col * n + col];
      if (f == 0) continue;
      for (int k = col; k < n; ++k) a[r * n + k] -= f * a[col * n + k];
      for (int k = 0; k < m; ++k) (*b)[r * m + k] -= f * (*b)[col * m + k];
    }
  }
  for (int col = n - 1; col >= 0; --col) {
    for (int k = 0; k < m; ++k) {
      Real v = (*b)[col * m + k];
      for (int j = col + 1; j < n; ++j) v -= a[col * n + j] * (*b)[j * m + k];
      (*b)[col * m + k] = v / a[col * n + col];
    }
  }
  return true;
}

/// s^a t^b r^c at x = (s, t, r).
Real Monomial(const std::array<int, 3>& exponents, const std::array<double, 3>& x) {
  return Power(x[0], exponents[0]) * Power(x[1], exponents[1]) * Power(x[2], exponents[2]);
}

}  // namespace

int BernsteinCount(CellType type, int degree) {
  int count = 1;
  for (const int dim : FactorDims(type)) count *= static_cast<int>(SimplexIndices(dim, degree).size());
  return count;
}

std::vector<std::array<double, 3>> BernsteinLattice(CellType type, int degree) {
  std::vector<std::array<double, 3>> points{{0, 0, 0}};
  int offset = 0;
  for (const int dim : FactorDims(type)) {
    const auto indices = SimplexIndices(dim, degree);
    std::vector<std::array<double, 3>> next;
    next.reserve(points.size() * indices.size());
    for (const auto& a : indices) {
      for (auto x : points) {
        for (int k = 0; k < dim; ++k) x[offset + k] = static_cast<double>(a[k]) / degree;
        next.push_back(x);
      }
    }
    points.swap(next);
    offset += dim;
  }
  return points;
}

LagrangeToBernstein::LagrangeToBernstein(CellType type, int degree, const std::vector<std::array<double, 3>>& nodes,
                                         const std::vector<std::array<int, 3>>& monomials)
    : numNodes_(static_cast<int>(nodes.size())), numControl_(BernsteinCount(type, degree)) {
  const int n = numNodes_;
  const int m = numControl_;
  std::vector<Real> result;
  if (monomials.empty()) {
    if (n != m) {
      throw std::invalid_argument(std::to_string(n) + " nodes for a complete element with " + std::to_string(m) +
                                  " control points");
    }
    // Nodal values L = V C with V(i, l) = B_l(node i): C = V^-1 L.
    std::vector<Real> v(static_cast<std::size_t>(n) * n);
    for (int i = 0; i < n; ++i) {
      const std::vector<Real> b = BernsteinValues(type, degree, nodes[i]);
      for (int l = 0; l < n; ++l) v[i * n + l] = b[l];
    }
    result.assign(static_cast<std::size_t>(n) * n, 0);
    for (int i = 0; i < n; ++i) result[i * n + i] = 1;
    if (!Solve(std::move(v), n, &result, n)) throw std::invalid_argument("nodes not unisolvent");
  } else {
    if (static_cast<int>(monomials.size()) != n) {
      throw std::invalid_argument(std::to_string(monomials.size()) + " monomials for " + std::to_string(n) + " nodes");
    }
    // Shape functions N_j = sum_k mono_k M^-1(k, j) with M(i, k) = mono_k(node i).
    std::vector<Real> mono(static_cast<std::size_t>(n) * n);
    for (int i = 0; i < n; ++i) {
      for (int k = 0; k < n; ++k) mono[i * n + k] = Monomial(monomials[k], nodes[i]);
    }
    std::vector<Real> inverse(static_cast<std::size_t>(n) * n, 0);
    for (int i = 0; i < n; ++i) inverse[i * n + i] = 1;
    if (!Solve(std::move(mono), n, &inverse, n)) throw std::invalid_argument("nodes not unisolvent for the monomials");
    // Shape functions at the Bernstein lattice points Y, then C = B(Y)^-1 N(Y).
    const std::vector<std::array<double, 3>> lattice = BernsteinLattice(type, degree);
    result.assign(static_cast<std::size_t>(m) * n, 0);
    std::vector<Real> bernstein(static_cast<std::size_t>(m) * m);
    std::vector<Real> row(n);
    for (int y = 0; y < m; ++y) {
      for (int k = 0; k < n; ++k) row[k] = Monomial(monomials[k], lattice[y]);
      for (int k = 0; k < n; ++k) {
        if (row[k] == 0) continue;
        for (int j = 0; j < n; ++j) result[y * n + j] += row[k] * inverse[k * n + j];
      }
      const std::vector<Real> b = BernsteinValues(type, degree, lattice[y]);
      for (int l = 0; l < m; ++l) bernstein[y * m + l] = b[l];
    }
    if (!Solve(std::move(bernstein), m, &result, n)) throw std::invalid_argument("Bernstein lattice not unisolvent");
  }
  SetMatrix(result);
}

LagrangeToBernstein LagrangeToBernstein::FromShapeValues(CellType type, int degree, int numNodes,
                                                         const std::vector<double>& values) {
  LagrangeToBernstein out;
  out.numNodes_ = numNodes;
  out.numControl_ = BernsteinCount(type, degree);
  const int m = out.numControl_;
  const int n = numNodes;
  if (n < 1 || values.size() != static_cast<std::size_t>(m) * n) {
    throw std::invalid_argument(std::to_string(values.size()) + " shape function values for " + std::to_string(m) +
                                " lattice points and " + std::to_string(n) + " nodes");
  }
  const std::vector<std::array<double, 3>> lattice = BernsteinLattice(type, degree);
  std::vector<Real> result(values.begin(), values.end());
  std::vector<Real> bernstein(static_cast<std::size_t>(m) * m);
  for (int y = 0; y < m; ++y) {
    const std::vector<Real> b = BernsteinValues(type, degree, lattice[y]);
    for (int l = 0; l < m; ++l) bernstein[y * m + l] = b[l];
  }
  if (!Solve(std::move(bernstein), m, &result, n)) throw std::invalid_argument("Bernstein lattice not unisolvent");
  out.SetMatrix(result);
  return out;
}

std::array<int, 3> UniformDegrees(CellType type, int degree) {
  std::array<int, 3> degrees{0, 0, 0};
  const std::size_t factors = FactorDims(type).size();
  for (std::size_t f = 0; f < factors; ++f) degrees[f] = degree;
  return degrees;
}

std::vector<double> BernsteinBasisAt(CellType type, int degree, const std::array<double, 3>& x) {
  const std::vector<Real> b = BernsteinValues(type, degree, x);
  return std::vector<double>(b.begin(), b.end());
}

void LagrangeToBernstein::SetMatrix(const std::vector<Real>& result) {
  const int m = numControl_;
  const int n = numNodes_;
  matrix_.resize(result.size());
  for (std::size_t i = 0; i < result.size(); ++i) matrix_[i] = static_cast<double>(result[i]);
  // A vertex's Bernstein coefficient is its nodal value; the solve leaves
  // that row a unit vector up to long double rounding.
  constexpr Real kUnitTolerance = 1e-12;
  copiedNode_.assign(m, -1);
  for (int i = 0; i < m; ++i) {
    int one = -1;
    bool unit = true;
    for (int j = 0; j < n && unit; ++j) {
      const Real c = result[static_cast<std::size_t>(i) * n + j];
      if (std::abs(c - 1) <= kUnitTolerance && one < 0) {
        one = j;
      } else {
        unit = std::abs(c) <= kUnitTolerance;
      }
    }
    if (unit) copiedNode_[i] = one;
  }
}

void LagrangeToBernstein::Apply(const double* nodes, int dim, double* control) const {
  // Every row sums to 1 (constants are reproduced), so the map commutes with
  // a shift: applying it to positions relative to the first node keeps the
  // cancellation between large alternating coefficients at the scale of the
  // element, not of its distance from the origin.
  for (int i = 0; i < numControl_; ++i) {
    if (copiedNode_[i] >= 0) {
      std::copy(nodes + 3 * copiedNode_[i], nodes + 3 * copiedNode_[i] + dim, control + i * dim);
      continue;
    }
    const double* row = matrix_.data() + static_cast<std::size_t>(i) * numNodes_;
    double sum[3] = {0, 0, 0};
    for (int j = 1; j < numNodes_; ++j) {
      for (int k = 0; k < dim; ++k) sum[k] += row[j] * (nodes[3 * j + k] - nodes[k]);
    }
    for (int k = 0; k < dim; ++k) control[i * dim + k] = nodes[k] + sum[k];
  }
}

void LagrangeToBernstein::ApplyToValues(const double* nodal, int components, double* control) const {
  for (int i = 0; i < numControl_; ++i) {
    const double* row = matrix_.data() + static_cast<std::size_t>(i) * numNodes_;
    for (int k = 0; k < components; ++k) {
      double sum = 0.0;
      for (int j = 0; j < numNodes_; ++j) {
        if (row[j] != 0.0) sum += row[j] * nodal[static_cast<std::size_t>(j) * components + k];
      }
      control[static_cast<std::size_t>(i) * components + k] = sum;
    }
  }
}

}  // namespace invmap::io
