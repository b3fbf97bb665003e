#include "tests/support/reference_cell.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <sstream>
#include <utility>

namespace invmap::testing {

using kernels::CellShape;
using kernels::CellType;
using kernels::CellView;

namespace {

constexpr double kPi = 3.14159265358979323846;

/// Largest simplex factor basis the evaluator supports (degree 8 tet).
constexpr int kMaxBasis = kernels::SimplexBasisSize(3, 8);

/// n! as a double (exact for the degrees used here).
double Factorial(int n) {
  double f = 1.0;
  for (int k = 2; k <= n; ++k) f *= k;
  return f;
}

/// Multi-indices (a0, a1, .., ad) of one simplex factor in docs/formats.md order
/// (a1 fastest, then a2, then a3; a0 = p - sum) with their multinomial
/// coefficients p! / (a0! .. ad!).
struct FactorTable {
  int dim = 1;
  int degree = 0;
  int offset = 0;
  std::vector<std::array<int, 4>> index;
  std::vector<double> coeff;
};

FactorTable MakeFactorTable(int dim, int degree, int offset) {
  FactorTable t;
  t.dim = dim;
  t.degree = degree;
  t.offset = offset;
  const int p = degree;
  auto push = [&](int a1, int a2, int a3) {
    const int a0 = p - a1 - a2 - a3;
    t.index.push_back({{a0, a1, a2, a3}});
    t.coeff.push_back(Factorial(p) / (Factorial(a0) * Factorial(a1) * Factorial(a2) * Factorial(a3)));
  };
  if (dim == 1) {
    for (int a1 = 0; a1 <= p; ++a1) push(a1, 0, 0);
  } else if (dim == 2) {
    for (int a2 = 0; a2 <= p; ++a2)
      for (int a1 = 0; a1 + a2 <= p; ++a1) push(a1, a2, 0);
  } else {
    for (int a3 = 0; a3 <= p; ++a3)
      for (int a2 = 0; a2 + a3 <= p; ++a2)
        for (int a1 = 0; a1 + a2 + a3 <= p; ++a1) push(a1, a2, a3);
  }
  return t;
}

/// Basis values and derivatives of one factor at one point (w.r.t. the
/// factor's own free coordinates).
struct FactorValues {
  double value[kMaxBasis];
  double d1[kMaxBasis][3];
  double d2[kMaxBasis][3][3];
};

/// Direct multinomial evaluation: B_a = C_a prod_k l_k^a_k with l_0 = 1 - sum s
/// and l_k = s_k; derivatives by the product rule through dl/ds.
void EvaluateFactor(const FactorTable& t, const double* s, int order, FactorValues* out) {
  const int d = t.dim, p = t.degree;
  double lambda[4] = {1.0, 0.0, 0.0, 0.0};
  for (int k = 0; k < d; ++k) {
    lambda[k + 1] = s[k];
    lambda[0] -= s[k];
  }
  double pw[4][kernels::kMaxDegree + 1];
  for (int k = 0; k <= d; ++k) {
    pw[k][0] = 1.0;
    for (int e = 1; e <= p; ++e) pw[k][e] = pw[k][e - 1] * lambda[k];
  }
  const int n = static_cast<int>(t.index.size());
  for (int b = 0; b < n; ++b) {
    const std::array<int, 4>& a = t.index[b];
    const double c = t.coeff[b];
    double v = c;
    for (int k = 0; k <= d; ++k) v *= pw[k][a[k]];
    out->value[b] = v;
    if (order < 1) continue;
    // T1[k] = d/dl_k of prod_m l_m^a_m; T2[k][l] likewise twice.
    double t1[4] = {0, 0, 0, 0};
    for (int k = 0; k <= d; ++k) {
      if (a[k] == 0) continue;
      double prod = c * a[k] * pw[k][a[k] - 1];
      for (int m = 0; m <= d; ++m)
        if (m != k) prod *= pw[m][a[m]];
      t1[k] = prod;
    }
    // dl_0/ds_i = -1, dl_{i+1}/ds_i = 1.
    for (int i = 0; i < d; ++i) out->d1[b][i] = t1[i + 1] - t1[0];
    if (order < 2) continue;
    double t2[4][4] = {};
    for (int k = 0; k <= d; ++k) {
      for (int l = k; l <= d; ++l) {
        double prod;
        if (k == l) {
          if (a[k] < 2) continue;
          prod = c * a[k] * (a[k] - 1) * pw[k][a[k] - 2];
        } else {
          if (a[k] == 0 || a[l] == 0) continue;
          prod = c * a[k] * a[l] * pw[k][a[k] - 1] * pw[l][a[l] - 1];
        }
        for (int m = 0; m <= d; ++m)
          if (m != k && m != l) prod *= pw[m][a[m]];
        t2[k][l] = t2[l][k] = prod;
      }
    }
    for (int i = 0; i < d; ++i)
      for (int j = 0; j < d; ++j)
        out->d2[b][i][j] = t2[i + 1][j + 1] - t2[i + 1][0] - t2[0][j + 1] + t2[0][0];
  }
}

/// Number of simplex factors of a cell type (written out again rather than
/// taken from CellShape, to keep the reference independent).
int FactorCount(CellType type) {
  switch (type) {
    case CellType::Line:
    case CellType::Tri:
    case CellType::Tet:
      return 1;
    case CellType::Quad:
    case CellType::Wedge:
      return 2;
    case CellType::Hex:
      return 3;
  }
  return 0;
}

/// Dimension of factor `f` of a cell type.
int FactorDim(CellType type, int f) {
  switch (type) {
    case CellType::Line:
    case CellType::Quad:
    case CellType::Hex:
      return 1;
    case CellType::Tri:
      return 2;
    case CellType::Tet:
      return 3;
    case CellType::Wedge:
      return f == 0 ? 2 : 1;
  }
  return 0;
}

/// Number of Bernstein polynomials of a simplex factor: C(degree + dim, dim).
int BasisSize(int dim, int degree) {
  int n = 1;
  for (int k = 1; k <= dim; ++k) n = n * (degree + k) / k;
  return n;
}

/// Evaluator of one cell with the factor tables built once.
class Evaluator {
 public:
  explicit Evaluator(const RefCell& cell) : cell_(&cell) {
    const int nf = FactorCount(cell.type);
    int offset = 0;
    for (int f = 0; f < nf; ++f) {
      const int dim = FactorDim(cell.type, f);
      factors_.push_back(MakeFactorTable(dim, cell.degrees[f], offset));
      offset += dim;
    }
    paramDim_ = offset;
    int n = 1;
    for (const FactorTable& t : factors_) n *= static_cast<int>(t.index.size());
    numControlPoints_ = n;
  }

  int paramDim() const { return paramDim_; }
  int numControlPoints() const { return numControlPoints_; }

  /// Value only (the lattice sampling path): the same sums as Evaluate
  /// without the derivative bookkeeping.
  void EvaluateValue(const double* ref, double* x) const {
    const RefCell& cell = *cell_;
    const int nf = static_cast<int>(factors_.size());
    const int ad = cell.ambientDim;
    double fv[3][kMaxBasis];
    int sizes[3] = {1, 1, 1};
    FactorValues tmp;
    for (int f = 0; f < nf; ++f) {
      EvaluateFactor(factors_[f], ref + factors_[f].offset, 0, &tmp);
      sizes[f] = static_cast<int>(factors_[f].index.size());
      std::copy(tmp.value, tmp.value + sizes[f], fv[f]);
    }
    for (int f = nf; f < 3; ++f) fv[f][0] = 1.0;
    double h[4] = {0, 0, 0, 0};
    const double* w = cell.isRational() ? cell.weights.data() : nullptr;
    const double* pt = cell.points.data();
    int c = 0;
    for (int i2 = 0; i2 < sizes[2]; ++i2) {
      for (int i1 = 0; i1 < sizes[1]; ++i1) {
        const double b12 = fv[1][i1] * fv[2][i2];
        for (int i0 = 0; i0 < sizes[0]; ++i0, ++c) {
          const double b = fv[0][i0] * b12 * (w ? w[c] : 1.0);
          for (int k = 0; k < ad; ++k) h[k] += b * pt[c * ad + k];
          h[3] += b;
        }
      }
    }
    for (int k = 0; k < ad; ++k) x[k] = h[k] / h[3];
    for (int k = ad; k < 3; ++k) x[k] = 0.0;
  }

  void Evaluate(const double* ref, int order, RefJet* out) const {
    const RefCell& cell = *cell_;
    const int nf = static_cast<int>(factors_.size());
    const int ad = cell.ambientDim;
    const int pd = paramDim_;
    FactorValues fv[3];
    for (int f = 0; f < nf; ++f) EvaluateFactor(factors_[f], ref + factors_[f].offset, order, &fv[f]);

    // Homogeneous sums: coordinates 0..ad-1 are sum(w B P), coordinate ad is
    // sum(w B) (1 for polynomial cells, whose basis sums to one).
    double h[4] = {0, 0, 0, 0};
    double h1[4][3] = {};
    double h2[4][3][3] = {};
    const bool rational = cell.isRational();
    int idx[3] = {0, 0, 0};
    int sizes[3] = {1, 1, 1};
    for (int f = 0; f < nf; ++f) sizes[f] = static_cast<int>(factors_[f].index.size());
    for (int c = 0; c < numControlPoints_; ++c) {
      double b = 1.0;
      for (int f = 0; f < nf; ++f) b *= fv[f].value[idx[f]];
      double b1[3] = {0, 0, 0};
      double b2[3][3] = {};
      if (order >= 1) {
        for (int f = 0; f < nf; ++f) {
          double others = 1.0;
          for (int g = 0; g < nf; ++g)
            if (g != f) others *= fv[g].value[idx[g]];
          for (int i = 0; i < factors_[f].dim; ++i) b1[factors_[f].offset + i] = others * fv[f].d1[idx[f]][i];
        }
      }
      if (order >= 2) {
        for (int f = 0; f < nf; ++f) {
          for (int g = 0; g < nf; ++g) {
            double others = 1.0;
            for (int q = 0; q < nf; ++q)
              if (q != f && q != g) others *= fv[q].value[idx[q]];
            for (int i = 0; i < factors_[f].dim; ++i) {
              for (int j = 0; j < factors_[g].dim; ++j) {
                const double v = f == g ? fv[f].d2[idx[f]][i][j] : fv[f].d1[idx[f]][i] * fv[g].d1[idx[g]][j];
                b2[factors_[f].offset + i][factors_[g].offset + j] = others * v;
              }
            }
          }
        }
      }
      const double w = rational ? cell.weights[c] : 1.0;
      const double* pt = &cell.points[static_cast<size_t>(c) * ad];
      for (int k = 0; k <= ad; ++k) {
        const double coef = w * (k < ad ? pt[k] : 1.0);
        h[k] += coef * b;
        if (order >= 1)
          for (int i = 0; i < pd; ++i) h1[k][i] += coef * b1[i];
        if (order >= 2)
          for (int i = 0; i < pd; ++i)
            for (int j = 0; j < pd; ++j) h2[k][i][j] += coef * b2[i][j];
      }
      // Advance the factor indices, first factor fastest.
      for (int f = 0; f < nf; ++f) {
        if (++idx[f] < sizes[f]) break;
        idx[f] = 0;
      }
    }

    // Quotient rule x = N / W.
    const double wSum = h[ad];
    for (int k = 0; k < ad; ++k) out->x[k] = h[k] / wSum;
    for (int k = ad; k < 3; ++k) out->x[k] = 0.0;
    if (order >= 1) {
      for (int k = 0; k < ad; ++k)
        for (int i = 0; i < pd; ++i) out->d1[k][i] = (h1[k][i] - out->x[k] * h1[ad][i]) / wSum;
    }
    if (order >= 2) {
      for (int k = 0; k < ad; ++k)
        for (int i = 0; i < pd; ++i)
          for (int j = 0; j < pd; ++j)
            out->d2[k][i][j] = (h2[k][i][j] - out->d1[k][i] * h1[ad][j] - out->d1[k][j] * h1[ad][i] -
                                out->x[k] * h2[ad][i][j]) /
                               wSum;
    }
  }

 private:
  const RefCell* cell_;
  std::vector<FactorTable> factors_;
  int paramDim_ = 0;
  int numControlPoints_ = 0;
};

// ---------------------------------------------------------------------------
// Reference domain as a polytope: constraints c . u <= b.

struct Constraint {
  double c[3] = {0, 0, 0};
  double b = 0.0;
};

std::vector<Constraint> DomainConstraints(CellType type) {
  std::vector<Constraint> out;
  const int nf = FactorCount(type);
  int offset = 0;
  for (int f = 0; f < nf; ++f) {
    const int d = FactorDim(type, f);
    // Barycentric order: l_0 = 1 - sum >= 0 first, then s_k >= 0. The order
    // matters to RandomBoundaryRefPoint, which uses the same numbering.
    Constraint sum;
    for (int k = 0; k < d; ++k) sum.c[offset + k] = 1.0;
    sum.b = 1.0;
    out.push_back(sum);
    for (int k = 0; k < d; ++k) {
      Constraint lower;
      lower.c[offset + k] = -1.0;
      out.push_back(lower);
    }
    offset += d;
  }
  return out;
}

/// Dot product of two n-vectors.
double Dot(const double* a, const double* b, int n) {
  double s = 0.0;
  for (int i = 0; i < n; ++i) s += a[i] * b[i];
  return s;
}

/// Moves `u` into the domain: negative coordinates to 0, then simplex
/// factors whose sum exceeds 1 scaled back onto the facet.
void ProjectIntoDomain(CellType type, double* u) {
  const int nf = FactorCount(type);
  int offset = 0;
  for (int f = 0; f < nf; ++f) {
    const int d = FactorDim(type, f);
    double sum = 0.0;
    for (int k = 0; k < d; ++k) {
      u[offset + k] = std::max(u[offset + k], 0.0);
      sum += u[offset + k];
    }
    if (sum > 1.0) {
      for (int k = 0; k < d; ++k) u[offset + k] /= sum;
    }
    offset += d;
  }
}

/// Cholesky solve of a small SPD system (n <= 3); false when not positive
/// definite (relative pivot test).
bool CholeskySolve(int n, const double a[3][3], const double* rhs, double* x) {
  double l[3][3] = {};
  double scale = 0.0;
  for (int i = 0; i < n; ++i) scale = std::max(scale, std::fabs(a[i][i]));
  if (!(scale > 0.0)) return false;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j <= i; ++j) {
      double s = a[i][j];
      for (int k = 0; k < j; ++k) s -= l[i][k] * l[j][k];
      if (i == j) {
        if (!(s > 1e-14 * scale)) return false;
        l[i][i] = std::sqrt(s);
      } else {
        l[i][j] = s / l[j][j];
      }
    }
  }
  double y[3];
  for (int i = 0; i < n; ++i) {
    double s = rhs[i];
    for (int k = 0; k < i; ++k) s -= l[i][k] * y[k];
    y[i] = s / l[i][i];
  }
  for (int i = n - 1; i >= 0; --i) {
    double s = y[i];
    for (int k = i + 1; k < n; ++k) s -= l[k][i] * x[k];
    x[i] = s / l[i][i];
  }
  return true;
}

/// Active-set Newton minimization of 0.5 |x(u) - p|^2 over the reference
/// polytope, from `start`. Iterates stay feasible: steps stop at the first
/// constraint they hit (which joins the working set); at a stationary point
/// of the current face, the constraint with the most negative Lagrange
/// multiplier is released, and the first step after a release follows the
/// projected gradient, which provably moves into the released half-space.
RefClosest ActiveSetNewton(const Evaluator& ev, CellType type, int ambientDim, const double* p,
                           const double* start) {
  const int pd = ev.paramDim();
  const int ad = ambientDim;
  const std::vector<Constraint> cons = DomainConstraints(type);
  const int nc = static_cast<int>(cons.size());

  double u[3] = {0, 0, 0};
  for (int i = 0; i < pd; ++i) u[i] = start[i];
  ProjectIntoDomain(type, u);
  bool active[8] = {};
  for (int j = 0; j < nc; ++j) active[j] = cons[j].b - Dot(cons[j].c, u, pd) <= 1e-14;

  auto objective = [&](const double* v, RefJet* jet, int order) {
    ev.Evaluate(v, order, jet);
    double f = 0.0;
    for (int k = 0; k < ad; ++k) {
      const double r = jet->x[k] - p[k];
      f += r * r;
    }
    return 0.5 * f;
  };

  bool justReleased = false;
  int releases = 0;
  RefJet jet;
  for (int iter = 0; iter < 200; ++iter) {
    const double f = objective(u, &jet, 2);
    double r[3] = {0, 0, 0};
    for (int k = 0; k < ad; ++k) r[k] = jet.x[k] - p[k];
    double g[3] = {0, 0, 0}, hess[3][3] = {}, gn[3][3] = {};
    double jScale = 0.0;
    for (int i = 0; i < pd; ++i) {
      for (int k = 0; k < ad; ++k) {
        g[i] += jet.d1[k][i] * r[k];
        jScale += jet.d1[k][i] * jet.d1[k][i];
      }
      for (int j = 0; j < pd; ++j) {
        for (int k = 0; k < ad; ++k) {
          gn[i][j] += jet.d1[k][i] * jet.d1[k][j];
          hess[i][j] += jet.d1[k][i] * jet.d1[k][j] + r[k] * jet.d2[k][i][j];
        }
      }
    }

    // Orthonormal basis Z of the directions that keep the active constraints.
    double q[3][3];
    int nq = 0;
    for (int j = 0; j < nc; ++j) {
      if (!active[j]) continue;
      double v[3] = {cons[j].c[0], cons[j].c[1], cons[j].c[2]};
      for (int m = 0; m < nq; ++m) {
        const double proj = Dot(v, q[m], pd);
        for (int i = 0; i < pd; ++i) v[i] -= proj * q[m][i];
      }
      const double len = std::sqrt(Dot(v, v, pd));
      if (len > 1e-8) {
        for (int i = 0; i < pd; ++i) q[nq][i] = v[i] / len;
        ++nq;
      }
    }
    double z[3][3];
    int nz = 0;
    for (int e = 0; e < pd && nq + nz < pd; ++e) {
      double v[3] = {0, 0, 0};
      v[e] = 1.0;
      for (int m = 0; m < nq; ++m) {
        const double proj = Dot(v, q[m], pd);
        for (int i = 0; i < pd; ++i) v[i] -= proj * q[m][i];
      }
      for (int m = 0; m < nz; ++m) {
        const double proj = Dot(v, z[m], pd);
        for (int i = 0; i < pd; ++i) v[i] -= proj * z[m][i];
      }
      const double len = std::sqrt(Dot(v, v, pd));
      if (len > 0.3) {
        for (int i = 0; i < pd; ++i) z[nz][i] = v[i] / len;
        ++nz;
      }
    }

    double d[3] = {0, 0, 0};
    bool stationary = nz == 0;
    if (!stationary) {
      double gz[3] = {0, 0, 0}, hz[3][3] = {}, gnz[3][3] = {};
      for (int a = 0; a < nz; ++a) {
        gz[a] = Dot(z[a], g, pd);
        for (int b = 0; b < nz; ++b) {
          hz[a][b] = gnz[a][b] = 0.0;
          for (int i = 0; i < pd; ++i)
            for (int j = 0; j < pd; ++j) {
              hz[a][b] += z[a][i] * hess[i][j] * z[b][j];
              gnz[a][b] += z[a][i] * gn[i][j] * z[b][j];
            }
        }
      }
      double dz[3] = {0, 0, 0};
      double minusGz[3] = {-gz[0], -gz[1], -gz[2]};
      if (justReleased) {
        // Projected steepest descent, scaled by the curvature along it when
        // that is positive.
        double curv = 0.0, gg = 0.0;
        for (int a = 0; a < nz; ++a) {
          gg += gz[a] * gz[a];
          for (int b = 0; b < nz; ++b) curv += gz[a] * hz[a][b] * gz[b];
        }
        const double step = curv > 0.0 ? gg / curv : 1.0 / std::max(jScale, 1e-300);
        for (int a = 0; a < nz; ++a) dz[a] = -step * gz[a];
      } else if (!CholeskySolve(nz, hz, minusGz, dz)) {
        // Indefinite reduced Hessian: shift it (Levenberg) until positive
        // definite, which gives a descent direction of sensible length.
        double trace = 0.0;
        for (int a = 0; a < nz; ++a) trace += std::fabs(gnz[a][a]) + std::fabs(hz[a][a]);
        double mu = 1e-8 * std::max(trace, 1e-300);
        bool ok = false;
        for (int tries = 0; tries < 40 && !ok; ++tries, mu *= 4.0) {
          double shifted[3][3];
          for (int a = 0; a < nz; ++a)
            for (int b = 0; b < nz; ++b) shifted[a][b] = hz[a][b] + (a == b ? mu : 0.0);
          ok = CholeskySolve(nz, shifted, minusGz, dz);
        }
        if (!ok) {
          for (int a = 0; a < nz; ++a) dz[a] = -gz[a] / std::max(jScale, 1e-300);
        }
      }
      double dzMax = 0.0;
      for (int a = 0; a < nz; ++a) dzMax = std::max(dzMax, std::fabs(dz[a]));
      for (int i = 0; i < pd; ++i)
        for (int a = 0; a < nz; ++a) d[i] += z[a][i] * dz[a];
      // A Newton step this small is at the rounding level of the gradient.
      stationary = dzMax <= 1e-13;
    }

    if (!stationary) {
      // Largest feasible step along d, and the constraint that limits it.
      double alphaMax = std::numeric_limits<double>::infinity();
      int blocking = -1;
      for (int j = 0; j < nc; ++j) {
        if (active[j]) continue;
        const double cd = Dot(cons[j].c, d, pd);
        if (cd <= 0.0) continue;
        const double slack = std::max(cons[j].b - Dot(cons[j].c, u, pd), 0.0);
        const double a = slack / cd;
        if (a < alphaMax) {
          alphaMax = a;
          blocking = j;
        }
      }
      double alpha = std::min(1.0, alphaMax);
      const double slope = Dot(g, d, pd);
      bool accepted = false;
      double uNew[3] = {0, 0, 0};
      RefJet trial;
      for (int tries = 0; tries < 60 && alpha > 0.0; ++tries) {
        for (int i = 0; i < pd; ++i) uNew[i] = u[i] + alpha * d[i];
        const double fNew = objective(uNew, &trial, 0);
        if (fNew < f && fNew <= f + 1e-4 * alpha * slope) {
          accepted = true;
          break;
        }
        alpha *= 0.5;
      }
      justReleased = false;
      if (accepted) {
        const bool hit = blocking >= 0 && alpha == alphaMax;
        for (int i = 0; i < pd; ++i) u[i] = uNew[i];
        if (hit) {
          // Put u exactly on the blocking constraint; rounding could leave
          // it a few ulps outside.
          const Constraint& c = cons[blocking];
          const double excess = Dot(c.c, u, pd) - c.b;
          const double cc = Dot(c.c, c.c, pd);
          for (int i = 0; i < pd; ++i) u[i] -= excess * c.c[i] / cc;
          ProjectIntoDomain(type, u);
          active[blocking] = true;
        }
        continue;
      }
      // No decrease at this precision: treat as stationary on this face.
    }

    // Stationary on the current face: Lagrange multipliers of the active
    // constraints from g + sum(lambda_j c_j) = 0 (least squares).
    int act[3];
    int na = 0;
    for (int j = 0; j < nc && na < 3; ++j)
      if (active[j]) act[na++] = j;
    if (na == 0) break;
    double ata[3][3] = {}, atg[3] = {0, 0, 0}, lambda[3] = {0, 0, 0};
    for (int a = 0; a < na; ++a) {
      atg[a] = -Dot(cons[act[a]].c, g, pd);
      for (int b = 0; b < na; ++b) ata[a][b] = Dot(cons[act[a]].c, cons[act[b]].c, pd);
    }
    if (!CholeskySolve(na, ata, atg, lambda)) break;
    const double gScale = std::sqrt(jScale) * std::sqrt(2.0 * f) + 1e-300;
    int release = -1;
    double most = -1e-13 * gScale;
    for (int a = 0; a < na; ++a) {
      if (lambda[a] < most) {
        most = lambda[a];
        release = act[a];
      }
    }
    if (release < 0 || ++releases > 12) break;
    active[release] = false;
    justReleased = true;
  }

  RefClosest out;
  RefJet jx;
  ev.Evaluate(u, 0, &jx);
  double dist2 = 0.0;
  for (int k = 0; k < ad; ++k) {
    dist2 += (jx.x[k] - p[k]) * (jx.x[k] - p[k]);
    out.x[k] = jx.x[k];
  }
  out.distance = std::sqrt(dist2);
  for (int i = 0; i < pd; ++i) out.ref[i] = u[i];
  out.starts = 1;
  return out;
}

// ---------------------------------------------------------------------------
// A small static k-d tree over the lattice samples.

class KdTree {
 public:
  void Build(const std::vector<double>& xyz, int dim) {
    dim_ = dim;
    const int n = static_cast<int>(xyz.size() / 3);
    order_.resize(n);
    std::iota(order_.begin(), order_.end(), 0);
    xyz_ = &xyz;
    nodes_.clear();
    nodes_.reserve(2 * n / kLeaf + 2);
    BuildNode(0, n);
  }

  /// Index and squared distance of the nearest sample.
  int Nearest(const double* q, double* bestDist2) const {
    int best = -1;
    *bestDist2 = std::numeric_limits<double>::infinity();
    NearestRec(0, q, &best, bestDist2);
    return best;
  }

  /// Every sample with squared distance <= r2, appended to `out`.
  void Range(const double* q, double r2, std::vector<std::pair<int, double>>* out) const {
    RangeRec(0, q, r2, out);
  }

 private:
  static constexpr int kLeaf = 8;
  struct Node {
    double lo[3], hi[3];
    int begin, end;
    int left = -1, right = -1;
  };

  const double* P(int i) const { return &(*xyz_)[static_cast<size_t>(i) * 3]; }

  int BuildNode(int begin, int end) {
    const int id = static_cast<int>(nodes_.size());
    nodes_.push_back(Node{});
    Node node;
    node.begin = begin;
    node.end = end;
    for (int k = 0; k < 3; ++k) {
      node.lo[k] = std::numeric_limits<double>::infinity();
      node.hi[k] = -std::numeric_limits<double>::infinity();
    }
    for (int i = begin; i < end; ++i) {
      const double* p = P(order_[i]);
      for (int k = 0; k < dim_; ++k) {
        node.lo[k] = std::min(node.lo[k], p[k]);
        node.hi[k] = std::max(node.hi[k], p[k]);
      }
    }
    if (end - begin > kLeaf) {
      int axis = 0;
      for (int k = 1; k < dim_; ++k)
        if (node.hi[k] - node.lo[k] > node.hi[axis] - node.lo[axis]) axis = k;
      const int mid = (begin + end) / 2;
      std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                       [&](int a, int b) { return P(a)[axis] < P(b)[axis]; });
      node.left = BuildNode(begin, mid);
      node.right = BuildNode(mid, end);
    }
    nodes_[id] = node;
    return id;
  }

  double BoxDist2(const Node& node, const double* q) const {
    double s = 0.0;
    for (int k = 0; k < dim_; ++k) {
      const double e = std::max({node.lo[k] - q[k], 0.0, q[k] - node.hi[k]});
      s += e * e;
    }
    return s;
  }

  double Dist2(int i, const double* q) const {
    const double* p = P(i);
    double s = 0.0;
    for (int k = 0; k < dim_; ++k) s += (p[k] - q[k]) * (p[k] - q[k]);
    return s;
  }

  void NearestRec(int id, const double* q, int* best, double* bestDist2) const {
    const Node& node = nodes_[id];
    if (node.left < 0) {
      for (int i = node.begin; i < node.end; ++i) {
        const double d2 = Dist2(order_[i], q);
        if (d2 < *bestDist2 || (d2 == *bestDist2 && order_[i] < *best)) {
          *bestDist2 = d2;
          *best = order_[i];
        }
      }
      return;
    }
    const double dl = BoxDist2(nodes_[node.left], q);
    const double dr = BoxDist2(nodes_[node.right], q);
    const int first = dl <= dr ? node.left : node.right;
    const int second = dl <= dr ? node.right : node.left;
    if (std::min(dl, dr) <= *bestDist2) NearestRec(first, q, best, bestDist2);
    if (std::max(dl, dr) <= *bestDist2) NearestRec(second, q, best, bestDist2);
  }

  void RangeRec(int id, const double* q, double r2, std::vector<std::pair<int, double>>* out) const {
    const Node& node = nodes_[id];
    if (BoxDist2(node, q) > r2) return;
    if (node.left < 0) {
      for (int i = node.begin; i < node.end; ++i) {
        const double d2 = Dist2(order_[i], q);
        if (d2 <= r2) out->emplace_back(order_[i], d2);
      }
      return;
    }
    RangeRec(node.left, q, r2, out);
    RangeRec(node.right, q, r2, out);
  }

  int dim_ = 3;
  const std::vector<double>* xyz_ = nullptr;
  std::vector<int> order_;
  std::vector<Node> nodes_;
};

// ---------------------------------------------------------------------------
// Random helpers.

/// Uniform draw in [lo, hi).
double Uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

/// Uniformly distributed unit vector of R^dim (normalized Gaussian).
std::array<double, 3> RandomUnitVector(int dim, std::mt19937_64& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  for (;;) {
    std::array<double, 3> v{{0, 0, 0}};
    double len2 = 0.0;
    for (int k = 0; k < dim; ++k) {
      v[k] = normal(rng);
      len2 += v[k] * v[k];
    }
    if (len2 > 1e-6) {
      const double len = std::sqrt(len2);
      for (int k = 0; k < dim; ++k) v[k] /= len;
      return v;
    }
  }
}

/// Random orthonormal frame (rows of a rotation matrix) of R^dim with
/// determinant +1, by Gram-Schmidt on Gaussian vectors.
void RandomRotation(int dim, std::mt19937_64& rng, double rot[3][3]) {
  for (;;) {
    bool ok = true;
    for (int i = 0; i < dim && ok; ++i) {
      std::array<double, 3> v = RandomUnitVector(dim, rng);
      for (int m = 0; m < i; ++m) {
        const double proj = Dot(v.data(), rot[m], dim);
        for (int k = 0; k < dim; ++k) v[k] -= proj * rot[m][k];
      }
      const double len = std::sqrt(Dot(v.data(), v.data(), dim));
      if (len < 0.2) ok = false;
      for (int k = 0; k < dim; ++k) rot[i][k] = v[k] / len;
    }
    if (!ok) continue;
    double det = 1.0;
    if (dim == 2) det = rot[0][0] * rot[1][1] - rot[0][1] * rot[1][0];
    if (dim == 3)
      det = rot[0][0] * (rot[1][1] * rot[2][2] - rot[1][2] * rot[2][1]) -
            rot[0][1] * (rot[1][0] * rot[2][2] - rot[1][2] * rot[2][0]) +
            rot[0][2] * (rot[1][0] * rot[2][1] - rot[1][1] * rot[2][0]);
    if (det < 0)
      for (int k = 0; k < dim; ++k) rot[0][k] = -rot[0][k];
    return;
  }
}

/// sqrt(det(J^T J)) with the sign of det(J) for square J: the signed volume
/// scale of the map at one point.
double JacobianMeasure(const RefJet& jet, int ad, int pd) {
  double g[3][3] = {};
  for (int i = 0; i < pd; ++i)
    for (int j = 0; j < pd; ++j)
      for (int k = 0; k < ad; ++k) g[i][j] += jet.d1[k][i] * jet.d1[k][j];
  if (ad == pd) {
    if (pd == 1) return jet.d1[0][0];
    if (pd == 2) return jet.d1[0][0] * jet.d1[1][1] - jet.d1[0][1] * jet.d1[1][0];
    const auto& a = jet.d1;
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  }
  double det;
  if (pd == 1)
    det = g[0][0];
  else if (pd == 2)
    det = g[0][0] * g[1][1] - g[0][1] * g[1][0];
  else
    det = g[0][0] * (g[1][1] * g[2][2] - g[1][2] * g[2][1]) - g[0][1] * (g[1][0] * g[2][2] - g[1][2] * g[2][0]) +
          g[0][2] * (g[1][0] * g[2][1] - g[1][1] * g[2][0]);
  return std::sqrt(std::max(det, 0.0));
}

/// Solves the (m x m) system a x = b for `numRhs` right-hand sides by Gaussian
/// elimination with partial pivoting; a is row-major, b is m x numRhs
/// row-major and receives x. Used to interpolate curves.
void SolveDense(int m, std::vector<double> a, std::vector<double>* rhsColumns, int numRhs) {
  std::vector<double>& b = *rhsColumns;
  for (int col = 0; col < m; ++col) {
    int piv = col;
    for (int r = col + 1; r < m; ++r)
      if (std::fabs(a[r * m + col]) > std::fabs(a[piv * m + col])) piv = r;
    if (piv != col) {
      for (int c = 0; c < m; ++c) std::swap(a[col * m + c], a[piv * m + c]);
      for (int c = 0; c < numRhs; ++c) std::swap(b[col * numRhs + c], b[piv * numRhs + c]);
    }
    for (int r = col + 1; r < m; ++r) {
      const double fct = a[r * m + col] / a[col * m + col];
      for (int c = col; c < m; ++c) a[r * m + c] -= fct * a[col * m + c];
      for (int c = 0; c < numRhs; ++c) b[r * numRhs + c] -= fct * b[col * numRhs + c];
    }
  }
  for (int r = m - 1; r >= 0; --r) {
    for (int c = 0; c < numRhs; ++c) {
      double s = b[r * numRhs + c];
      for (int k = r + 1; k < m; ++k) s -= a[r * m + k] * b[k * numRhs + c];
      b[r * numRhs + c] = s / a[r * m + r];
    }
  }
}

/// Bezier control points (degree p, `dim` coordinates each) of the polynomial
/// interpolating `curve` at the Chebyshev-Gauss-Lobatto nodes of [0, 1].
std::vector<double> InterpolateCurve(int p, int dim, const std::function<void(double, double*)>& curve) {
  const FactorTable table = MakeFactorTable(1, p, 0);
  std::vector<double> a((p + 1) * (p + 1));
  std::vector<double> rhs((p + 1) * dim);
  FactorValues fv;
  for (int i = 0; i <= p; ++i) {
    const double s = 0.5 * (1.0 - std::cos(kPi * i / p));
    EvaluateFactor(table, &s, 0, &fv);
    for (int j = 0; j <= p; ++j) a[i * (p + 1) + j] = fv.value[j];
    curve(s, &rhs[i * dim]);
  }
  SolveDense(p + 1, a, &rhs, dim);
  return rhs;
}

}  // namespace

// ---------------------------------------------------------------------------
// RefCell and evaluation.

kernels::CellShape RefCell::shape() const { return CellShape(type, degrees); }

kernels::CellView RefCell::view() const {
  CellView v;
  v.shape = shape();
  v.ambientDim = ambientDim;
  v.points = points.data();
  v.weights = weights.empty() ? nullptr : weights.data();
  return v;
}

int RefCell::paramDim() const { return ParamDimOf(type); }

int RefCell::numControlPoints() const {
  int n = 1;
  for (int f = 0; f < FactorCount(type); ++f) n *= BasisSize(FactorDim(type, f), degrees[f]);
  return n;
}

double RefCell::size() const {
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  const int n = static_cast<int>(points.size()) / ambientDim;
  for (int k = 0; k < ambientDim; ++k) {
    lo[k] = std::numeric_limits<double>::infinity();
    hi[k] = -std::numeric_limits<double>::infinity();
  }
  for (int c = 0; c < n; ++c)
    for (int k = 0; k < ambientDim; ++k) {
      lo[k] = std::min(lo[k], points[c * ambientDim + k]);
      hi[k] = std::max(hi[k], points[c * ambientDim + k]);
    }
  double s = 0.0;
  for (int k = 0; k < ambientDim; ++k) s += (hi[k] - lo[k]) * (hi[k] - lo[k]);
  return std::sqrt(s);
}

std::string Describe(const RefCell& cell) {
  std::ostringstream os;
  os.precision(17);
  os << invmap::CellTypeName(cell.type) << " degrees [";
  for (int f = 0; f < FactorCount(cell.type); ++f) os << (f ? ", " : "") << cell.degrees[f];
  os << "] ambientDim " << cell.ambientDim << (cell.isRational() ? " rational" : " polynomial") << ", "
     << cell.numControlPoints() << " control points (x y [z] [w]):\n";
  for (int c = 0; c < cell.numControlPoints(); ++c) {
    os << "  ";
    for (int k = 0; k < cell.ambientDim; ++k) os << cell.points[c * cell.ambientDim + k] << ' ';
    if (cell.isRational()) os << cell.weights[c];
    os << '\n';
  }
  return os.str();
}

int ParamDimOf(CellType type) {
  int d = 0;
  for (int f = 0; f < FactorCount(type); ++f) d += FactorDim(type, f);
  return d;
}

void RefEvaluate(const RefCell& cell, const double* ref, double* x) {
  RefJet jet;
  Evaluator(cell).Evaluate(ref, 0, &jet);
  for (int k = 0; k < cell.ambientDim; ++k) x[k] = jet.x[k];
}

void RefEvaluateJet(const RefCell& cell, const double* ref, int order, RefJet* out) {
  *out = RefJet{};
  Evaluator(cell).Evaluate(ref, order, out);
}

bool InReferenceDomain(CellType type, const double* ref, double tol) {
  const int pd = ParamDimOf(type);
  for (const Constraint& c : DomainConstraints(type)) {
    if (!(Dot(c.c, ref, pd) <= c.b + tol)) return false;  // also rejects NaN
  }
  return true;
}

std::vector<std::array<double, 3>> ControlPointRefLocations(CellType type, const std::array<int, 3>& degrees) {
  const int nf = FactorCount(type);
  std::vector<FactorTable> tables;
  int offset = 0;
  int n = 1;
  for (int f = 0; f < nf; ++f) {
    tables.push_back(MakeFactorTable(FactorDim(type, f), degrees[f], offset));
    offset += FactorDim(type, f);
    n *= static_cast<int>(tables.back().index.size());
  }
  std::vector<std::array<double, 3>> out(n, {{0, 0, 0}});
  int idx[3] = {0, 0, 0};
  for (int c = 0; c < n; ++c) {
    for (int f = 0; f < nf; ++f) {
      const FactorTable& t = tables[f];
      for (int k = 0; k < t.dim; ++k) {
        out[c][t.offset + k] = t.degree > 0 ? static_cast<double>(t.index[idx[f]][k + 1]) / t.degree : 1.0 / (t.dim + 1);
      }
    }
    for (int f = 0; f < nf; ++f) {
      if (++idx[f] < static_cast<int>(tables[f].index.size())) break;
      idx[f] = 0;
    }
  }
  return out;
}

// ---------------------------------------------------------------------------
// Brute force.

struct BruteForceReference::Impl {
  RefCell cell;
  BruteForceOptions options;
  std::unique_ptr<Evaluator> ev;
  int pd = 1, ad = 3, n = 1;
  std::vector<double> sampleRef;  // 3 per sample
  std::vector<double> sampleX;    // 3 per sample
  std::vector<std::array<int, 3>> sampleGrid;
  std::vector<int> grid;  // (n+1)^pd grid -> sample index or -1
  std::vector<std::array<int, 3>> neighborOffsets;
  KdTree tree;
  double resolution = 0.0;
  double cellSize = 0.0;
  std::vector<std::uint32_t> stamp;
  std::vector<double> stampDist2;
  std::uint32_t now = 0;
  std::vector<std::pair<int, double>> hits;
  /// A lattice-local minimum of the sampled distance.
  struct Candidate {
    double dist2;
    int sample;
    bool tied;  ///< Some neighbour has the same distance up to rounding.
  };
  std::vector<Candidate> candidates;
  std::vector<char> stampTied;  ///< Per sample, valid where stamp == now.

  /// Sample at lattice offset `off` from sample `s`, or -1 outside the domain.
  int Neighbor(int s, const std::array<int, 3>& off) const {
    int nb[3] = {sampleGrid[s][0] + off[0], sampleGrid[s][1] + off[1], sampleGrid[s][2] + off[2]};
    for (int i = 0; i < pd; ++i)
      if (nb[i] < 0 || nb[i] > n) return -1;
    return grid[GridIndex(nb)];
  }

  int GridIndex(const int* idx) const {
    int g = 0;
    for (int i = pd - 1; i >= 0; --i) g = g * (n + 1) + idx[i];
    return g;
  }

  void Build() {
    ev = std::make_unique<Evaluator>(cell);
    cellSize = cell.size();
    pd = cell.paramDim();
    ad = cell.ambientDim;
    n = options.divisions > 0 ? options.divisions : (pd == 1 ? 256 : pd == 2 ? 64 : 32);
    int gridSize = 1;
    for (int i = 0; i < pd; ++i) gridSize *= n + 1;
    grid.assign(gridSize, -1);
    const int nf = FactorCount(cell.type);
    int idx[3] = {0, 0, 0};
    for (int g = 0; g < gridSize; ++g) {
      int rem = g;
      for (int i = 0; i < pd; ++i) {
        idx[i] = rem % (n + 1);
        rem /= n + 1;
      }
      bool valid = true;
      int offset = 0;
      for (int f = 0; f < nf; ++f) {
        int sum = 0;
        for (int k = 0; k < FactorDim(cell.type, f); ++k) sum += idx[offset + k];
        valid = valid && sum <= n;
        offset += FactorDim(cell.type, f);
      }
      if (!valid) continue;
      double ref[3] = {0, 0, 0};
      for (int i = 0; i < pd; ++i) ref[i] = static_cast<double>(idx[i]) / n;
      double x[3];
      ev->EvaluateValue(ref, x);
      grid[g] = static_cast<int>(sampleGrid.size());
      sampleGrid.push_back({{idx[0], idx[1], idx[2]}});
      for (int k = 0; k < 3; ++k) {
        sampleRef.push_back(ref[k]);
        sampleX.push_back(x[k]);
      }
    }
    // Resolution: a point of a lattice cell is within half its parametric
    // diagonal of a corner, and the image of that diagonal is at most pd/2
    // axis edges long; 1.5 covers the curvature inside one lattice cell.
    double maxEdge = 0.0;
    const int numSamples = static_cast<int>(sampleGrid.size());
    for (int s = 0; s < numSamples; ++s) {
      for (int i = 0; i < pd; ++i) {
        int nb[3] = {sampleGrid[s][0], sampleGrid[s][1], sampleGrid[s][2]};
        if (++nb[i] > n) continue;
        const int t = grid[GridIndex(nb)];
        if (t < 0) continue;
        double e2 = 0.0;
        for (int k = 0; k < ad; ++k) e2 += (sampleX[3 * s + k] - sampleX[3 * t + k]) * (sampleX[3 * s + k] - sampleX[3 * t + k]);
        maxEdge = std::max(maxEdge, std::sqrt(e2));
      }
    }
    resolution = 1.5 * 0.5 * std::max(pd, 1) * maxEdge;
    for (int a = -1; a <= 1; ++a)
      for (int b = (pd >= 2 ? -1 : 0); b <= (pd >= 2 ? 1 : 0); ++b)
        for (int c = (pd >= 3 ? -1 : 0); c <= (pd >= 3 ? 1 : 0); ++c)
          if (a || b || c) neighborOffsets.push_back({{a, b, c}});
    tree.Build(sampleX, ad);
    stamp.assign(numSamples, 0);
    stampDist2.assign(numSamples, 0.0);
    stampTied.assign(numSamples, 0);
  }

  RefClosest Closest(const double* point) {
    if (++now == 0) {
      std::fill(stamp.begin(), stamp.end(), 0);
      now = 1;
    }
    double p[3] = {0, 0, 0};
    for (int k = 0; k < ad; ++k) p[k] = point[k];
    double d02 = 0.0;
    const int nearest = tree.Nearest(p, &d02);
    // Polish the nearest sample first: it usually is in the global basin,
    // and a distance of zero (a point on the cell) cannot be beaten, which
    // spares the range search for points inside volumes.
    RefClosest best = ActiveSetNewton(*ev, cell.type, ad, p, &sampleRef[3 * nearest]);
    int starts = 1;
    if (best.distance <= 1e-15 * cellSize) {
      best.starts = starts;
      return best;
    }
    // The global minimizer's nearest sample is within `resolution` of it,
    // so its distance is at most best + resolution; so is the distance of
    // the lattice-local minimum that descent from that sample reaches.
    const double reach = best.distance + resolution;
    hits.clear();
    tree.Range(p, reach * reach, &hits);
    for (const auto& h : hits) {
      stamp[h.first] = now;
      stampDist2[h.first] = h.second;
    }
    // Lattice-local minima among the hits; samples outside the range are
    // farther than every hit, so they never beat one.
    //
    // Near-ties (equal up to rounding) mark degenerate samples: where the
    // map collapses a row of the lattice onto one point (a collapsed edge, a
    // pole), each of those samples is a stationary point of its own, and the
    // basins of the true minima show in the next row, which the collapsed
    // row would hide from the local-minimum test. So tied samples are
    // ignored when testing the others, and are candidates themselves when
    // no neighbour is closer.
    const double tieTol = 1e-13 * cellSize;
    for (const auto& h : hits) {
      const int s = h.first;
      const double ds = std::sqrt(h.second);
      bool tied = false;
      for (const auto& off : neighborOffsets) {
        const int t = Neighbor(s, off);
        if (t >= 0 && stamp[t] == now && std::fabs(std::sqrt(stampDist2[t]) - ds) <= tieTol) {
          tied = true;
          break;
        }
      }
      stampTied[s] = tied;
    }
    candidates.clear();
    for (const auto& h : hits) {
      const int s = h.first;
      const double ds = std::sqrt(h.second);
      const bool tied = stampTied[s];
      bool isMin = true;
      for (const auto& off : neighborOffsets) {
        const int t = Neighbor(s, off);
        if (t < 0 || stamp[t] != now || (!tied && stampTied[t])) continue;
        if (std::sqrt(stampDist2[t]) < ds - tieTol) {
          isMin = false;
          break;
        }
      }
      // The nearest sample was polished already.
      if (isMin && s != nearest) candidates.push_back({h.second, s, tied});
    }
    // Also the next nearest samples, local minima or not: where two sheets
    // of the cell pass within a lattice step of each other (a fold), the
    // sheet that holds the answer can be hidden behind a closer sample of
    // the other one.
    const int extra = std::min<int>(options.nearestStarts - 1, static_cast<int>(hits.size()) - 1);
    if (extra > 0) {
      std::partial_sort(hits.begin(), hits.begin() + extra + 1, hits.end(),
                        [](const std::pair<int, double>& a, const std::pair<int, double>& b) { return a.second < b.second; });
      int added = 0;
      for (const auto& h : hits) {
        if (added == extra) break;
        if (h.first == nearest) continue;
        bool known = false;
        for (const Candidate& c : candidates) known = known || c.sample == h.first;
        if (!known) candidates.push_back({h.second, h.first, false});
        ++added;
      }
    }
    std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
      return a.dist2 < b.dist2 || (a.dist2 == b.dist2 && a.sample < b.sample);
    });
    // Tied candidates are all polished (up to a cap of a few lattice rows):
    // from a degenerate sample only those whose own direction out of the
    // collapsed set points at the query escape it, and the one that leads
    // to the global minimum may be any of them (often a domain vertex).
    int tiedStarts = 0;
    for (const Candidate& c : candidates) {
      if (std::sqrt(c.dist2) > best.distance + resolution) break;
      if (c.tied ? tiedStarts >= 4 * (n + 1) : starts - tiedStarts >= options.maxStarts) continue;
      const RefClosest r = ActiveSetNewton(*ev, cell.type, ad, p, &sampleRef[3 * c.sample]);
      ++starts;
      tiedStarts += c.tied;
      if (r.distance < best.distance) best = r;
    }
    best.starts = starts;
    return best;
  }
};

BruteForceReference::BruteForceReference(const RefCell& cell, BruteForceOptions options)
    : impl_(std::make_unique<Impl>()) {
  impl_->cell = cell;
  impl_->options = options;
  impl_->Build();
}

BruteForceReference::~BruteForceReference() = default;
BruteForceReference::BruteForceReference(BruteForceReference&&) noexcept = default;
BruteForceReference& BruteForceReference::operator=(BruteForceReference&&) noexcept = default;

RefClosest BruteForceReference::Closest(const double* point) { return impl_->Closest(point); }

RefClosest BruteForceReference::Polish(const double* point, const double* start) const {
  double p[3] = {0, 0, 0};
  for (int k = 0; k < impl_->ad; ++k) p[k] = point[k];
  return ActiveSetNewton(*impl_->ev, impl_->cell.type, impl_->ad, p, start);
}

const RefCell& BruteForceReference::cell() const { return impl_->cell; }
int BruteForceReference::numSamples() const { return static_cast<int>(impl_->sampleGrid.size()); }
double BruteForceReference::resolution() const { return impl_->resolution; }

RefClosest BruteForceClosest(const RefCell& cell, const double* point) {
  return BruteForceReference(cell).Closest(point);
}

// ---------------------------------------------------------------------------
// Cell generators.

RefCell AffineCell(CellType type, const std::array<int, 3>& degrees, int ambientDim, const double* a,
                   const double* b) {
  RefCell cell;
  cell.type = type;
  cell.degrees = degrees;
  cell.ambientDim = ambientDim;
  const int pd = ParamDimOf(type);
  for (const auto& loc : ControlPointRefLocations(type, degrees)) {
    for (int k = 0; k < ambientDim; ++k) {
      double v = b[k];
      for (int i = 0; i < pd; ++i) v += a[k * pd + i] * loc[i];
      cell.points.push_back(v);
    }
  }
  return cell;
}

namespace {

/// True when the map's Jacobian measure (signed for full-rank cells) stays
/// above 5% of `scale` (the affine map's measure) on lattices of the domain
/// that include the boundary, where folds and pinches appear first (a coarse
/// lattice first, so that most bad draws are rejected cheaply); and when no
/// two parts of the cell come close to each other: every pair of lattice
/// points is at least 20% of `minStretch` (the affine map's smallest
/// singular value) times their parametric distance apart. The second test
/// rejects surfaces and curves that fold over themselves in 3D, which a
/// Jacobian test cannot see; such near-contacts are a test of their own,
/// not something random cells should stumble into.
bool IsWellShaped(const RefCell& cell, double scale, double minStretch) {
  const Evaluator ev(cell);
  const int pd = cell.paramDim();
  RefJet jet;
  std::vector<std::array<double, 6>> samples;  // ref, then x
  for (int m : {pd == 3 ? 3 : 4, pd == 3 ? 8 : pd == 2 ? 16 : 64}) {
    samples.clear();
    int idx[3] = {0, 0, 0};
    int total = 1;
    for (int i = 0; i < pd; ++i) total *= m + 1;
    for (int g = 0; g < total; ++g) {
      int rem = g;
      for (int i = 0; i < pd; ++i) {
        idx[i] = rem % (m + 1);
        rem /= m + 1;
      }
      double ref[3] = {0, 0, 0};
      for (int i = 0; i < pd; ++i) ref[i] = static_cast<double>(idx[i]) / m;
      if (!InReferenceDomain(cell.type, ref, 1e-12)) continue;
      ev.Evaluate(ref, 1, &jet);
      if (!(JacobianMeasure(jet, cell.ambientDim, pd) >= 0.05 * scale)) return false;
      samples.push_back({{ref[0], ref[1], ref[2], jet.x[0], jet.x[1], jet.x[2]}});
    }
  }
  const double factor2 = 0.2 * 0.2 * minStretch * minStretch;
  for (size_t a = 0; a < samples.size(); ++a) {
    for (size_t b = a + 1; b < samples.size(); ++b) {
      double du2 = 0.0, dx2 = 0.0;
      for (int i = 0; i < 3; ++i) {
        du2 += (samples[a][i] - samples[b][i]) * (samples[a][i] - samples[b][i]);
        dx2 += (samples[a][i + 3] - samples[b][i + 3]) * (samples[a][i + 3] - samples[b][i + 3]);
      }
      if (dx2 < factor2 * du2) return false;
    }
  }
  return true;
}

}  // namespace

RefCell RandomCurvedCell(CellType type, int degree, bool rational, int ambientDim, std::mt19937_64& rng) {
  return RandomCurvedCell(type, {{degree, degree, degree}}, rational, ambientDim, rng);
}

RefCell RandomCurvedCell(CellType type, const std::array<int, 3>& degrees, bool rational, int ambientDim,
                         std::mt19937_64& rng) {
  const int pd = ParamDimOf(type);
  const int ad = ambientDim;
  std::array<int, 3> deg = degrees;
  for (int f = FactorCount(type); f < 3; ++f) deg[f] = 0;
  const std::vector<std::array<double, 3>> locs = ControlPointRefLocations(type, deg);
  for (int attempt = 0;; ++attempt) {
    // Affine part: an orthonormal pd-frame of R^ad times a random anisotropic
    // scaling and a rotation of parameter space (so the simplex is generic),
    // with positive orientation for full-rank cells.
    double rotA[3][3], rotP[3][3];
    RandomRotation(ad, rng, rotA);
    RandomRotation(pd, rng, rotP);
    double scale[3];
    for (int i = 0; i < pd; ++i) scale[i] = std::exp(Uniform(rng, std::log(0.7), std::log(1.4)));
    double a[9] = {}, b[3] = {0, 0, 0};
    for (int k = 0; k < ad; ++k)
      for (int i = 0; i < pd; ++i)
        for (int m = 0; m < pd; ++m) a[k * pd + i] += rotA[m][k] * scale[m] * rotP[m][i];
    for (int k = 0; k < ad; ++k) b[k] = Uniform(rng, -2.0, 2.0);
    RefCell cell = AffineCell(type, deg, ad, a, b);
    RefJet affineJet;
    const double zero[3] = {0, 0, 0};
    RefEvaluateJet(cell, zero, 1, &affineJet);
    const double affineMeasure = JacobianMeasure(affineJet, ad, pd);
    // Later attempts shrink the perturbation so that high degrees (closely
    // spaced control points) still find a valid cell quickly.
    const double relative = Uniform(rng, 0.10, 0.25) * std::pow(0.85, attempt / 8);
    const double amplitude = relative * cell.size();
    for (size_t c = 0; c < locs.size(); ++c) {
      const std::array<double, 3> dir = RandomUnitVector(ad, rng);
      const double len = amplitude * std::cbrt(Uniform(rng, 0.0, 1.0));
      for (int k = 0; k < ad; ++k) cell.points[c * ad + k] += len * dir[k];
    }
    if (rational) {
      for (size_t c = 0; c < locs.size(); ++c) cell.weights.push_back(std::exp(Uniform(rng, std::log(0.5), std::log(2.0))));
    }
    double minScale = scale[0];
    for (int i = 1; i < pd; ++i) minScale = std::min(minScale, scale[i]);
    if (IsWellShaped(cell, affineMeasure, minScale)) return cell;
  }
}

RefCell CShapedQuad(int degree) {
  // Unit arc from 30 to 330 degrees; the annulus is r(t) * arc(s), exactly
  // linear in t, so the t direction needs degree 1.
  const double th0 = kPi / 6.0, th1 = 11.0 * kPi / 6.0;
  const std::vector<double> arc = InterpolateCurve(degree, 2, [&](double s, double* out) {
    const double th = th0 + s * (th1 - th0);
    out[0] = std::cos(th);
    out[1] = std::sin(th);
  });
  RefCell cell;
  cell.type = CellType::Quad;
  cell.degrees = {{degree, 1, 0}};
  cell.ambientDim = 2;
  for (int j = 0; j <= 1; ++j) {
    const double r = j == 0 ? 0.5 : 1.0;
    for (int i = 0; i <= degree; ++i) {
      cell.points.push_back(r * arc[2 * i]);
      cell.points.push_back(r * arc[2 * i + 1]);
    }
  }
  return cell;
}

RefCell SpiralQuad() {
  const int p = 8;
  const double turns = 1.25, pitch = 0.6, width = 0.3;
  auto spiral = [&](double offset) {
    return InterpolateCurve(p, 2, [&](double s, double* out) {
      const double th = s * turns * 2.0 * kPi;
      const double r = 1.0 + pitch * th / (2.0 * kPi) + offset;
      out[0] = r * std::cos(th);
      out[1] = r * std::sin(th);
    });
  };
  const std::vector<double> inner = spiral(0.0), outer = spiral(width);
  RefCell cell;
  cell.type = CellType::Quad;
  cell.degrees = {{p, 1, 0}};
  cell.ambientDim = 2;
  cell.points.insert(cell.points.end(), inner.begin(), inner.end());
  cell.points.insert(cell.points.end(), outer.begin(), outer.end());
  return cell;
}

RefCell CollapsedEdgeQuad() {
  RefCell cell;
  cell.type = CellType::Quad;
  cell.degrees = {{2, 2, 0}};
  cell.ambientDim = 2;
  cell.points = {0.0, 0.0, 0.5, -0.15, 1.0, 0.0,   // t = 0
                 0.05, 0.5, 0.55, 0.6, 0.95, 0.45,  // t = 1/2
                 0.5, 1.0, 0.5, 1.0, 0.5, 1.0};     // t = 1: one point
  return cell;
}

RefCell ZeroAreaTriangle() {
  // Positions along the line through (0.2, -0.1) with direction (1, 0.5), in
  // FORMATS order (0,0) (1,0) (2,0) (0,1) (1,1) (0,2); not monotone, so the
  // image folds over itself.
  const double along[6] = {0.0, 0.6, 1.0, 0.4, 1.3, -0.2};
  RefCell cell;
  cell.type = CellType::Tri;
  cell.degrees = {{2, 0, 0}};
  cell.ambientDim = 2;
  for (double a : along) {
    cell.points.push_back(0.2 + a);
    cell.points.push_back(-0.1 + 0.5 * a);
  }
  return cell;
}

RefCell PoleQuad() {
  const double h = std::sqrt(0.5);
  // Around the z axis (first parameter) and along the meridian (second):
  // both the standard rational quadratic quarter circle.
  const double rev[3][2] = {{1, 0}, {1, 1}, {0, 1}};
  const double prof[3][2] = {{1, 0}, {1, 1}, {0, 1}};  // (rho, z)
  const double w[3] = {1.0, h, 1.0};
  RefCell cell;
  cell.type = CellType::Quad;
  cell.degrees = {{2, 2, 0}};
  cell.ambientDim = 3;
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) {
      cell.points.push_back(kPoleQuadCenter[0] + kPoleQuadRadius * prof[j][0] * rev[i][0]);
      cell.points.push_back(kPoleQuadCenter[1] + kPoleQuadRadius * prof[j][0] * rev[i][1]);
      cell.points.push_back(kPoleQuadCenter[2] + kPoleQuadRadius * prof[j][1]);
      cell.weights.push_back(w[i] * w[j]);
    }
  }
  return cell;
}

RefCell QuarterCircleArc(const std::array<double, 2>& center, double radius) {
  RefCell cell;
  cell.type = CellType::Line;
  cell.degrees = {{2, 0, 0}};
  cell.ambientDim = 2;
  cell.points = {center[0] + radius, center[1], center[0] + radius, center[1] + radius, center[0],
                 center[1] + radius};
  cell.weights = {1.0, std::sqrt(0.5), 1.0};
  return cell;
}

// ---------------------------------------------------------------------------
// Queries.

const char* QueryKindName(QueryKind kind) {
  switch (kind) {
    case QueryKind::Inside:
      return "inside";
    case QueryKind::Near:
      return "near";
    case QueryKind::Far:
      return "far";
    case QueryKind::Boundary:
      return "boundary";
  }
  return "?";
}

namespace {

/// Uniform point of the d-simplex as d free barycentric coordinates
/// (normalized exponentials are uniform on the simplex).
void RandomSimplexPoint(int d, const bool* zero, std::mt19937_64& rng, double* s) {
  std::exponential_distribution<double> expo(1.0);
  double l[4];
  double sum = 0.0;
  for (int k = 0; k <= d; ++k) {
    l[k] = zero && zero[k] ? 0.0 : expo(rng);
    sum += l[k];
  }
  for (int k = 0; k < d; ++k) s[k] = l[k + 1] / sum;
}

}  // namespace

std::array<double, 3> RefDomainCenter(CellType type) {
  switch (type) {
    case CellType::Tri:
      return {1.0 / 3, 1.0 / 3, 0.0};
    case CellType::Tet:
      return {0.25, 0.25, 0.25};
    case CellType::Wedge:
      return {1.0 / 3, 1.0 / 3, 0.5};
    default:
      return {0.5, 0.5, 0.5};
  }
}

std::array<double, 3> RandomRefPoint(CellType type, std::mt19937_64& rng) {
  std::array<double, 3> u{{0, 0, 0}};
  int offset = 0;
  for (int f = 0; f < FactorCount(type); ++f) {
    const int d = FactorDim(type, f);
    RandomSimplexPoint(d, nullptr, rng, &u[offset]);
    offset += d;
  }
  return u;
}

std::array<double, 3> RandomBoundaryRefPoint(CellType type, std::mt19937_64& rng, std::array<double, 3>* outwardRef) {
  const int nf = FactorCount(type);
  for (;;) {
    // Per factor, a random set of vanishing barycentric coordinates (never
    // all of them); at least one factor must have one.
    bool zero[3][4] = {};
    int totalZero = 0;
    for (int f = 0; f < nf; ++f) {
      const int d = FactorDim(type, f);
      const int count = std::uniform_int_distribution<int>(0, d)(rng);
      int order[4] = {0, 1, 2, 3};
      std::shuffle(order, order + d + 1, rng);
      for (int c = 0; c < count; ++c) zero[f][order[c]] = true;
      totalZero += count;
    }
    if (totalZero == 0) continue;
    std::array<double, 3> u{{0, 0, 0}}, outward{{0, 0, 0}};
    int offset = 0;
    for (int f = 0; f < nf; ++f) {
      const int d = FactorDim(type, f);
      RandomSimplexPoint(d, zero[f], rng, &u[offset]);
      // l_0 = 0 is the facet sum = 1 (outward normal +1 in every coordinate);
      // l_k = 0 is s_k = 0 (outward normal -e_k).
      if (zero[f][0])
        for (int k = 0; k < d; ++k) outward[offset + k] += 1.0;
      for (int k = 1; k <= d; ++k)
        if (zero[f][k]) outward[offset + k - 1] -= 1.0;
      offset += d;
    }
    if (outwardRef) *outwardRef = outward;
    return u;
  }
}

Query RandomQuery(const RefCell& cell, QueryKind kind, std::mt19937_64& rng) {
  const int ad = cell.ambientDim;
  const int pd = cell.paramDim();
  const double size = cell.size();
  Query q;
  q.kind = kind;
  std::array<double, 3> outward{{0, 0, 0}};
  q.sourceRef = kind == QueryKind::Boundary ? RandomBoundaryRefPoint(cell.type, rng, &outward)
                                            : RandomRefPoint(cell.type, rng);
  RefJet jet;
  RefEvaluateJet(cell, q.sourceRef.data(), 1, &jet);
  for (int k = 0; k < ad; ++k) q.point[k] = jet.x[k];
  std::array<double, 3> dir = RandomUnitVector(ad, rng);
  double offset = 0.0;
  switch (kind) {
    case QueryKind::Inside:
      break;
    case QueryKind::Near:
      offset = size * std::pow(10.0, Uniform(rng, -9.0, std::log10(0.2)));
      break;
    case QueryKind::Far:
      offset = size * Uniform(rng, 1.0, 4.0);
      break;
    case QueryKind::Boundary: {
      // Image of the outward reference direction, blurred a little so that
      // both the face itself and its neighbourhood get hit.
      double v[3] = {0, 0, 0};
      double len2 = 0.0;
      for (int k = 0; k < ad; ++k) {
        for (int i = 0; i < pd; ++i) v[k] += jet.d1[k][i] * outward[i];
        len2 += v[k] * v[k];
      }
      if (len2 > 1e-24 * size * size) {
        const double len = std::sqrt(len2);
        double d2 = 0.0;
        for (int k = 0; k < ad; ++k) {
          dir[k] = v[k] / len + 0.3 * dir[k];
          d2 += dir[k] * dir[k];
        }
        for (int k = 0; k < ad; ++k) dir[k] /= std::sqrt(d2);
      }
      offset = Uniform(rng, 0.0, 1.0) < 0.15 ? 0.0 : size * std::pow(10.0, Uniform(rng, -9.0, std::log10(0.3)));
      break;
    }
  }
  for (int k = 0; k < ad; ++k) q.point[k] += offset * dir[k];
  return q;
}

}  // namespace invmap::testing
