#include "kernels/bernstein.h"

#include <array>
#include <initializer_list>
#include <vector>

#include "kernels/simplex_index.h"

namespace invmap::kernels {
namespace {

/// One row of the Bernstein triangle raised from degree n - 1 to n by the de
/// Casteljau recurrence B^n_i = (1 - t) B^{n-1}_i + t B^{n-1}_{i-1}. Running i
/// downwards lets `to` alias `from`.
inline void RaiseLineRow(const double* from, int n, double u, double t, double* to) {
  to[n] = t * from[n - 1];
  for (int i = n - 1; i > 0; --i) to[i] = u * from[i] + t * from[i - 1];
  to[0] = u * from[0];
}

/// Line factor: degrees p - 2, p - 1 and p of the Bernstein triangle; the
/// derivatives come from the two lower degrees. Always inlined so that the
/// per-degree calls below unroll with a constant degree.
[[gnu::always_inline]] inline void EvaluateLineBasis(int degree, double t, JetOrder order, FactorBasis<1>* out) {
  out->size = degree + 1;
  const double u = 1.0 - t;
  double lower2[kMaxDegree + 1], lower1[kMaxDegree + 1];
  lower2[0] = 1.0;
  for (int n = 1; n <= degree - 2; ++n) RaiseLineRow(lower2, n, u, t, lower2);
  if (degree >= 2) {
    RaiseLineRow(lower2, degree - 1, u, t, lower1);
  } else {
    lower1[0] = 1.0;
  }
  if (degree >= 1) {
    RaiseLineRow(lower1, degree, u, t, out->value);
  } else {
    out->value[0] = 1.0;
  }
  if (order == JetOrder::Value) return;
  for (int i = 0; i <= degree; ++i) {
    const double left = i >= 1 ? lower1[i - 1] : 0.0;
    const double right = i < degree ? lower1[i] : 0.0;
    out->d1[i][0] = degree >= 1 ? degree * (left - right) : 0.0;
  }
  if (order != JetOrder::Second) return;
  for (int i = 0; i <= degree; ++i) {
    double d2 = 0.0;
    if (degree >= 2) {
      const double a = i >= 2 ? lower2[i - 2] : 0.0;
      const double b = i >= 1 && i - 1 <= degree - 2 ? lower2[i - 1] : 0.0;
      const double c = i <= degree - 2 ? lower2[i] : 0.0;
      d2 = degree * (degree - 1) * (a - 2.0 * b + c);
    }
    out->d2[i][0] = d2;
  }
}

/// The first `count` Bernstein polynomials of `index`'s degree on a simplex,
/// B_a = multinomial(a) * prod_k lambda_k^a_k, from the table of powers
/// power[k][e] = lambda_k^e.
template <int Dim>
void EvaluateSimplexValues(const SimplexIndex& index, const double (*power)[kMaxDegree + 1], int count, double* value) {
  for (int b = 0; b < count; ++b) {
    const std::array<int, 4>& a = index.multi(b);
    double v = index.multinomial(b);
    for (int k = 0; k <= Dim; ++k) v *= power[k][a[k]];
    value[b] = v;
  }
}

/// What the basis of a simplex factor of one (dim, degree) p needs besides the
/// point: the multi-indices of degrees p, p - 1 and p - 2, and where each
/// polynomial B^p_a finds the lower-degree polynomials of its derivatives,
/// dB^p_a/dlambda_k = p B^{p-1}_{a-e_k} and
/// d2B^p_a/dlambda_k dlambda_l = p (p - 1) B^{p-2}_{a-e_k-e_l}. A multi-index
/// with a negative entry points at the slot just past the lower degree's
/// polynomials, which holds 0, so the hot loop neither branches nor computes
/// positions.
struct SimplexPlan {
  const SimplexIndex* index[3] = {};       ///< Degrees p, p - 1, p - 2; null below 0.
  std::vector<std::array<int, 4>> down1;   ///< [b][k]: position of a - e_k in degree p - 1.
  std::vector<std::array<int, 16>> down2;  ///< [b][4 k + l]: position of a - e_k - e_l in degree p - 2.
};

/// Position in `lower` of the multi-index `a` minus the unit vectors of
/// `steps`, or the zero slot (`lower`'s size) when an entry goes negative.
int LoweredPosition(std::array<int, 4> a, std::initializer_list<int> steps, const SimplexIndex* lower) {
  if (lower == nullptr) return 0;  // no lower degree: its zero slot is the only one
  for (int k : steps) {
    if (--a[k] < 0) return lower->size();
  }
  return lower->Position(a);
}

using SimplexPlans = std::array<std::array<SimplexPlan, kMaxDegree + 1>, 2>;

SimplexPlans BuildSimplexPlans() {
  SimplexPlans plans;
  for (int d = 2; d <= 3; ++d) {
    for (int p = 0; p <= kMaxDegree; ++p) {
      SimplexPlan& plan = plans[d - 2][p];
      for (int drop = 0; drop < 3 && drop <= p; ++drop) plan.index[drop] = &SimplexIndex::Get(d, p - drop);
      for (int b = 0; b < plan.index[0]->size(); ++b) {
        const std::array<int, 4>& a = plan.index[0]->multi(b);
        std::array<int, 4> down1{};
        std::array<int, 16> down2{};
        for (int k = 0; k <= d; ++k) {
          down1[k] = LoweredPosition(a, {k}, plan.index[1]);
          for (int l = 0; l <= d; ++l) down2[4 * k + l] = LoweredPosition(a, {k, l}, plan.index[2]);
        }
        plan.down1.push_back(down1);
        plan.down2.push_back(down2);
      }
    }
  }
  return plans;
}

const SimplexPlan& GetSimplexPlan(int dim, int degree) {
  // A function-local static rather than SimplexIndex::Get's call_once: after
  // the first call its check is one load, and this is on the hot path.
  static const SimplexPlans plans = BuildSimplexPlans();
  return plans[dim - 2][degree];
}

/// The polynomials of degree p - drop (none when that is negative), followed
/// by the zero slot.
template <int Dim>
void EvaluateLowerDegree(const SimplexPlan& plan, int drop, const double (*power)[kMaxDegree + 1], double* value) {
  const SimplexIndex* index = plan.index[drop];
  const int count = index != nullptr ? index->size() : 0;
  if (count > 0) EvaluateSimplexValues<Dim>(*index, power, count, value);
  value[count] = 0.0;
}

/// Simplex factor of dimension 2 or 3. The derivatives come from the lower
/// degrees (see SimplexPlan) with d/ds_i = d/dlambda_i - d/dlambda_0: two
/// smaller sets of polynomials instead of a product per polynomial and
/// direction.
template <int Dim>
void EvaluateSimplexBasis(int degree, const double* s, JetOrder order, FactorBasis<Dim>* out) {
  const SimplexPlan& plan = GetSimplexPlan(Dim, degree);
  const SimplexIndex& index = *plan.index[0];
  out->size = index.size();
  double lambda[Dim + 1];
  lambda[0] = 1.0;
  for (int i = 0; i < Dim; ++i) {
    lambda[i + 1] = s[i];
    lambda[0] -= s[i];
  }
  double power[Dim + 1][kMaxDegree + 1];
  for (int k = 0; k <= Dim; ++k) {
    power[k][0] = 1.0;
    for (int e = 1; e <= degree; ++e) power[k][e] = power[k][e - 1] * lambda[k];
  }
  EvaluateSimplexValues<Dim>(index, power, out->size, out->value);
  if (order == JetOrder::Value) return;

  double lower1[FactorBasis<Dim>::kCapacity + 1];
  EvaluateLowerDegree<Dim>(plan, 1, power, lower1);
  for (int b = 0; b < out->size; ++b) {
    const std::array<int, 4>& down = plan.down1[b];
    for (int i = 0; i < Dim; ++i) out->d1[b][i] = degree * (lower1[down[i + 1]] - lower1[down[0]]);
  }
  if (order != JetOrder::Second) return;

  double lower2[FactorBasis<Dim>::kCapacity + 1];
  EvaluateLowerDegree<Dim>(plan, 2, power, lower2);
  for (int b = 0; b < out->size; ++b) {
    const std::array<int, 16>& down = plan.down2[b];
    for (int i = 0; i < Dim; ++i) {
      for (int j = 0; j <= i; ++j) {
        const double combination =
            lower2[down[4 * (i + 1) + j + 1]] - lower2[down[4 * (i + 1)]] - lower2[down[j + 1]] + lower2[down[0]];
        out->d2[b][i * (i + 1) / 2 + j] = degree * (degree - 1) * combination;
      }
    }
  }
}

}  // namespace

template <int Dim>
void EvaluateFactorBasis(int degree, const double* s, JetOrder order, FactorBasis<Dim>* out) {
  if constexpr (Dim == 1) {
    // One case per degree: each inlines with a constant degree, so the short
    // loops of the recurrence unroll.
    switch (degree) {
      case 0:
        return EvaluateLineBasis(0, s[0], order, out);
      case 1:
        return EvaluateLineBasis(1, s[0], order, out);
      case 2:
        return EvaluateLineBasis(2, s[0], order, out);
      case 3:
        return EvaluateLineBasis(3, s[0], order, out);
      case 4:
        return EvaluateLineBasis(4, s[0], order, out);
      default:
        return EvaluateLineBasis(degree, s[0], order, out);
    }
  } else {
    EvaluateSimplexBasis<Dim>(degree, s, order, out);
  }
}

template void EvaluateFactorBasis<1>(int, const double*, JetOrder, FactorBasis<1>*);
template void EvaluateFactorBasis<2>(int, const double*, JetOrder, FactorBasis<2>*);
template void EvaluateFactorBasis<3>(int, const double*, JetOrder, FactorBasis<3>*);

}  // namespace invmap::kernels
