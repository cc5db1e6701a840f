// Runge–Kutta order conditions, evaluated numerically over all rooted trees (test helper).
//
// A method (A, b) has order p iff Σ_i b_i Φ_i(τ) = 1/γ(τ) for every rooted tree τ with |τ| ≤ p, where the
// elementary weights are Φ_i(τ) = Π_{children σ of the root} (Σ_j a_ij Φ_j(σ)) and the density is
// γ(τ) = |τ| Π γ(σ) (Butcher; Hairer, Nørsett, Wanner, Solving ODEs I, §II.2, Theorem 2.13). A continuous
// extension b(θ) has order q iff Σ_i b_i(θ) Φ_i(τ) = θ^|τ|/γ(τ) for |τ| ≤ q (HNW I, §II.6).
// Trees are generated as multisets of subtrees (each tree once): 1, 1, 2, 4, 9, 20, 48, 115, 286, 719 of orders 1…10.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <vector>

namespace lgi::test {

struct RootedTree {
  int order;
  std::vector<int> children;  // indices into the tree list, non-increasing
  long double gamma;
};

// All rooted trees of order ≤ max_order, in increasing order.
inline std::vector<RootedTree> rooted_trees(int max_order) {
  std::vector<RootedTree> trees{{1, {}, 1.0L}};
  for (int n = 2; n <= max_order; ++n) {
    const std::size_t known = trees.size();  // all trees of order < n
    std::vector<int> children;
    // children: a non-increasing sequence of tree indices with orders summing to n − 1
    const std::function<void(int, int)> extend = [&](int remaining, int max_index) {
      if (remaining == 0) {
        long double gamma = n;
        for (const int c : children) gamma *= trees[static_cast<std::size_t>(c)].gamma;
        trees.push_back({n, children, gamma});
        return;
      }
      for (int i = max_index; i >= 0; --i) {
        const int o = trees[static_cast<std::size_t>(i)].order;
        if (o > remaining) continue;
        children.push_back(i);
        extend(remaining - o, i);
        children.pop_back();
      }
    };
    extend(n - 1, static_cast<int>(known) - 1);
  }
  return trees;
}

// Φ(τ) for every tree, as vectors over the stages (A is s×s, row-major, lower triangular).
inline std::vector<std::vector<long double>> elementary_weights(const std::vector<RootedTree>& trees,
                                                                const std::vector<std::vector<double>>& A) {
  const std::size_t s = A.size();
  std::vector<std::vector<long double>> phi(trees.size(), std::vector<long double>(s, 1.0L));
  for (std::size_t t = 0; t < trees.size(); ++t)
    for (const int c : trees[t].children)
      for (std::size_t i = 0; i < s; ++i) {
        long double sum = 0;
        for (std::size_t j = 0; j < s; ++j) sum += static_cast<long double>(A[i][j]) * phi[static_cast<std::size_t>(c)][j];
        phi[t][i] *= sum;
      }
  return phi;
}

// The coefficients are doubles, so the conditions hold only to within the effect of rounding them: with every
// a_ij and weight w_i off by a relative u = 2⁻⁵³ at most, the residual of tree τ moves by at most (to first
// order in u)
//   u B(τ),   B(τ) = Σ_i (|w|_i |Φ_i(τ)| + |w_i| E_i(τ)),
// where |w|_i bounds the weight's parts (|b_i|; |b_i| + |e_i| for b̂ = b − e; Σ_m |r_im| θ^m for a dense weight
// Σ_m r_im θ^m) and E_i(τ) u bounds |δΦ_i(τ)|: for Φ_i = Π_children g_c, g_c = Σ_j a_ij Φ_j(c),
//   E_i(τ) = Σ_c e_c Π_{c'≠c} |g_c'|,   e_c = Σ_j |a_ij| (|Φ_j(c)| + E_j(c)).
// A residual within u B is what double coefficients allow; a transcription error shows as a residual beyond it.
// (Measured, test_rkmk_family: the residuals stay at or below 0.5 u B for every tableau, 0.31 u B for the pairs.
// Verner's 8(7) pair, whose coefficients reach 123 (a) and 1.35e6 (interpolant), has u B up to 5.4e-12 (b) and
// 1.4e-9 (interpolant at θ = 1) where DOP853 has 2.6e-14 and 1.3e-12; its residuals 1.3e-13 and 3.8e-10 fall to
// 1.7e-17 and 1.7e-13 when the same 40-digit coefficients are evaluated in long double, by about the ratio of the
// two unit roundoffs (2048): rounding, not transcription.)
inline std::vector<std::vector<long double>> elementary_weight_errors(const std::vector<RootedTree>& trees,
                                                                      const std::vector<std::vector<long double>>& phi,
                                                                      const std::vector<std::vector<double>>& A) {
  const std::size_t s = A.size();
  std::vector<std::vector<long double>> E(trees.size(), std::vector<long double>(s, 0.0L));
  std::vector<long double> g, e;
  for (std::size_t t = 0; t < trees.size(); ++t)
    for (std::size_t i = 0; i < s; ++i) {
      g.clear();
      e.clear();
      for (const int c : trees[t].children) {
        const auto k = static_cast<std::size_t>(c);
        long double gc = 0, ec = 0;
        for (std::size_t j = 0; j < s; ++j) {
          gc += static_cast<long double>(A[i][j]) * phi[k][j];
          ec += std::abs(static_cast<long double>(A[i][j])) * (std::abs(phi[k][j]) + E[k][j]);
        }
        g.push_back(gc);
        e.push_back(ec);
      }
      for (std::size_t c = 0; c < g.size(); ++c) {
        long double term = e[c];
        for (std::size_t d = 0; d < g.size(); ++d)
          if (d != c) term *= std::abs(g[d]);
        E[t][i] += term;
      }
    }
  return E;
}

struct OrderResidual {
  long double residual = 0;  // largest |Σ w_i Φ_i(τ) − θ^|τ|/γ(τ)| over the trees of one order
  long double bound = 0;     // largest u B(τ) over them
  long double ratio = 0;     // largest residual / (u B) over them: ≤ 1 for coefficients right to rounding
};

// The residuals of the trees of exactly `order` for weights w (θ = 1: the step), with |w| as above.
inline OrderResidual order_residual(const std::vector<RootedTree>& trees, const std::vector<std::vector<long double>>& phi,
                                    const std::vector<std::vector<long double>>& E, const std::vector<double>& w,
                                    const std::vector<long double>& w_abs, int order, long double theta = 1.0L) {
  constexpr long double u = 0x1p-53L;
  OrderResidual r;
  for (std::size_t t = 0; t < trees.size(); ++t) {
    if (trees[t].order != order) continue;
    long double sum = 0, B = 0;
    for (std::size_t i = 0; i < w.size(); ++i) {
      sum += static_cast<long double>(w[i]) * phi[t][i];
      B += w_abs[i] * std::abs(phi[t][i]) + std::abs(static_cast<long double>(w[i])) * E[t][i];
    }
    const long double residual = std::abs(sum - std::pow(theta, static_cast<long double>(order)) / trees[t].gamma);
    r.residual = std::max(r.residual, residual);
    r.bound = std::max(r.bound, u * B);
    // no room for rounding where B = 0 (a condition the coefficients meet exactly, e.g. Euler's Σ b_i c_i = 0)
    const long double ratio = residual == 0 ? 0.0L : B == 0 ? std::numeric_limits<long double>::infinity() : residual / (u * B);
    r.ratio = std::max(r.ratio, ratio);
  }
  return r;
}

}  // namespace lgi::test
