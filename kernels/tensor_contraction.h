// Contraction of a tensor-product Bezier net with the Bernstein bases of its
// simplex factors: the homogeneous sums of a cell's map and their derivatives.
// Everything that sizes a loop is a template parameter, so each cell type,
// ambient dimension, weighting and order compiles to straight-line code.
#pragma once

#include <cstddef>
#include <utility>

#include "kernels/bernstein.h"
#include "kernels/cell_shape.h"

namespace invmap::kernels {

/// Value and derivatives of Comps homogeneous sums (w x_k for each ambient
/// coordinate, then w when rational) with respect to the first Params
/// parameters, up to Order. Second derivatives are the lower triangle, (i, j)
/// with j <= i at i * (i + 1) / 2 + j.
template <int Comps, int Params, JetOrder Order>
struct PartialJet {
  static constexpr int kFirst = Order == JetOrder::Value ? 0 : Params;
  static constexpr int kSecond = Order == JetOrder::Second ? Params * (Params + 1) / 2 : 0;

  double value[Comps];
  double d1[kFirst > 0 ? kFirst : 1][Comps];
  double d2[kSecond > 0 ? kSecond : 1][Comps];

  void Clear() {
    for (int k = 0; k < Comps; ++k) value[k] = 0.0;
    for (int i = 0; i < kFirst; ++i) {
      for (int k = 0; k < Comps; ++k) d1[i][k] = 0.0;
    }
    for (int i = 0; i < kSecond; ++i) {
      for (int k = 0; k < Comps; ++k) d2[i][k] = 0.0;
    }
  }
};

/// jet += basis function b of a factor of dimension Dim times `part`, a jet
/// over the Before parameters of the factors contracted earlier (the factor's
/// own parameters follow them).
template <int Comps, int Before, int Dim, JetOrder Order>
inline void AccumulateFactor(const PartialJet<Comps, Before, Order>& part, const FactorBasis<Dim>& basis, int b,
                             PartialJet<Comps, Before + Dim, Order>* jet) {
  const double v = basis.value[b];
  for (int k = 0; k < Comps; ++k) jet->value[k] += part.value[k] * v;
  if constexpr (Order != JetOrder::Value) {
    for (int i = 0; i < Before; ++i) {
      for (int k = 0; k < Comps; ++k) jet->d1[i][k] += part.d1[i][k] * v;
    }
    for (int i = 0; i < Dim; ++i) {
      for (int k = 0; k < Comps; ++k) jet->d1[Before + i][k] += part.value[k] * basis.d1[b][i];
    }
  }
  if constexpr (Order == JetOrder::Second) {
    for (int i = 0; i < Before * (Before + 1) / 2; ++i) {
      for (int k = 0; k < Comps; ++k) jet->d2[i][k] += part.d2[i][k] * v;
    }
    for (int a = 0; a < Dim; ++a) {
      const int row = (Before + a) * (Before + a + 1) / 2;
      for (int j = 0; j < Before; ++j) {
        for (int k = 0; k < Comps; ++k) jet->d2[row + j][k] += part.d1[j][k] * basis.d1[b][a];
      }
      for (int j = 0; j <= a; ++j) {
        for (int k = 0; k < Comps; ++k)
          jet->d2[row + Before + j][k] += part.value[k] * basis.d2[b][a * (a + 1) / 2 + j];
      }
    }
  }
}

/// The bases of simplex factors of dimensions Dims, in order. Unlike
/// std::tuple, which value-initializes (zero-fills) its elements, this leaves
/// the bases' arrays (up to 13 KB each) untouched until they are evaluated.
template <int... Dims>
struct FactorBases {};

template <int Dim, int... Rest>
struct FactorBases<Dim, Rest...> {
  FactorBasis<Dim> head;
  FactorBases<Rest...> tail;
};

/// Basis of factor F of `bases` (a possibly const FactorBases).
template <int F, class Bases>
auto& BasisOf(Bases& bases) {
  if constexpr (F == 0) {
    return bases.head;
  } else {
    return BasisOf<F - 1>(bases.tail);
  }
}

/// The bases of a cell whose simplex factors have dimensions Dims (first
/// factor fastest in the net), and the contraction of its control net
/// (Ambient coordinates per point, plus weights when Rational) with them.
/// LineDegree > 0: every line factor has that degree, so the loops over
/// their bases have a constant length and unroll (0: any degrees).
template <int Ambient, bool Rational, JetOrder Order, int LineDegree, int... Dims>
class TensorContraction {
 public:
  static constexpr int kComps = Ambient + (Rational ? 1 : 0);
  static constexpr int kFactors = sizeof...(Dims);
  static constexpr int kDims[kFactors] = {Dims...};

  /// Parameters of the first `factors` factors.
  static constexpr int ParamsOf(int factors) {
    int n = 0;
    for (int f = 0; f < factors; ++f) n += kDims[f];
    return n;
  }
  static constexpr int kParams = ParamsOf(kFactors);
  using Jet = PartialJet<kComps, kParams, Order>;

  /// Evaluates every factor's basis at `ref`; `shape` has the factors Dims.
  TensorContraction(const CellShape& shape, const double* ref, const double* points, const double* weights)
      : points_(points), weights_(weights) {
    EvaluateBases(shape, ref, std::make_index_sequence<kFactors>());
  }

  /// The homogeneous sums of the whole net.
  void Run(Jet* out) const { Contract<kFactors>(0, out); }

 private:
  template <std::size_t... F>
  void EvaluateBases(const CellShape& shape, const double* ref, std::index_sequence<F...>) {
    (EvaluateFactorBasis<kDims[F]>(shape.factor(F).degree, ref + shape.factor(F).offset, Order, &BasisOf<F>(bases_)),
     ...);
  }

  /// Jet of the first K factors for net block `block` (the control points
  /// block * (their basis sizes' product) onwards): a sum over the basis of
  /// factor K - 1 of the jets of the first K - 1 factors.
  template <int K>
  void Contract(int block, PartialJet<kComps, ParamsOf(K), Order>* out) const {
    if constexpr (K == 0) {
      const double* p = points_ + static_cast<std::size_t>(block) * Ambient;
      if constexpr (Rational) {
        const double w = weights_[block];
        for (int k = 0; k < Ambient; ++k) out->value[k] = w * p[k];
        out->value[Ambient] = w;
      } else {
        for (int k = 0; k < Ambient; ++k) out->value[k] = p[k];
      }
    } else {
      const auto& basis = BasisOf<K - 1>(bases_);
      constexpr int kFixedSize = kDims[K - 1] == 1 && LineDegree > 0 ? LineDegree + 1 : 0;
      out->Clear();
      PartialJet<kComps, ParamsOf(K - 1), Order> part;
      // The bound stays in the loop condition: hoisted into a local, GCC 12
      // compiled the general case 8-10% slower (rational quads, degrees 1-2).
      for (int b = 0; b < (kFixedSize > 0 ? kFixedSize : basis.size); ++b) {
        Contract<K - 1>(block * basis.size + b, &part);
        AccumulateFactor(part, basis, b, out);
      }
    }
  }

  const double* points_;
  const double* weights_;
  FactorBases<Dims...> bases_;
};

}  // namespace invmap::kernels
