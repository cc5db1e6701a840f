// Runge–Kutta order conditions, evaluated numerically over all rooted trees (test helper).
//
// A method (A, b) has order p iff Σ_i b_i Φ_i(τ) = 1/γ(τ) for every rooted tree τ with |τ| ≤ p, where the
// elementary weights are Φ_i(τ) = Π_{children σ of the root} (Σ_j a_ij Φ_j(σ)) and the density is
// γ(τ) = |τ| Π γ(σ) (Butcher; Hairer, Nørsett, Wanner, Solving ODEs I, §II.2, Theorem 2.13). A continuous
// extension b(θ) has order q iff Σ_i b_i(θ) Φ_i(τ) = θ^|τ|/γ(τ) for |τ| ≤ q (HNW I, §II.6).
// Trees are generated as multisets of subtrees (each tree once): 1, 1, 2, 4, 9, 20, 48, 115 of orders 1…8.
#pragma once

#include <cmath>
#include <functional>
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

// The largest residual |Σ b_i Φ_i(τ) − θ^|τ|/γ(τ)| over trees of exactly `order` (θ = 1: the step).
inline long double order_residual(const std::vector<RootedTree>& trees, const std::vector<std::vector<long double>>& phi,
                                  const std::vector<double>& b, int order, long double theta = 1.0L) {
  long double worst = 0;
  for (std::size_t t = 0; t < trees.size(); ++t) {
    if (trees[t].order != order) continue;
    long double sum = 0;
    for (std::size_t i = 0; i < b.size(); ++i) sum += static_cast<long double>(b[i]) * phi[t][i];
    worst = std::max(worst, std::abs(sum - std::pow(theta, static_cast<long double>(order)) / trees[t].gamma));
  }
  return worst;
}

}  // namespace lgi::test
