/// \file
/// lgi/core/state_io.hpp — the numbers of a stepper's internal state, in a fixed order: what a checkpoint saves and
/// restores bit for bit, and what the engine (core/engine.hpp) copies across its boundary.
///
/// A state type lists its members in its body with LGI_NUMBERS(member, …); fixed-size Eigen matrices (their
/// coefficients in data() order, column-major), arithmetic scalars and such listed types nested are the leaves.
/// visit_numbers(y, f) calls f on every number of y in that order (f(double&), or f(const double&) for a const y);
/// `number_count<Y>()` is their count, at compile time. For Y with double scalars, `numbers_complete<Y>()` says that
/// they are all of Y (its size is their size, rounded up to its alignment): a member left out of LGI_NUMBERS would
/// make it false, and the engine refuses such a type at compile time.
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <tuple>
#include <type_traits>
#include <utility>

/// Inside a struct: its members that carry numbers, in the order they are saved.
#define LGI_NUMBERS(...)                                       \
  auto numbers() { return std::tie(__VA_ARGS__); }             \
  auto numbers() const { return std::tie(__VA_ARGS__); }

namespace lgi {

namespace detail {
template <class Y>
concept EigenFixed = requires { Y::SizeAtCompileTime; } && (Y::SizeAtCompileTime > 0);
template <class Y>
concept ListedNumbers = requires(Y& y) { y.numbers(); };
}  // namespace detail

/// The count of Y's numbers (the header's order), at compile time. Y: an arithmetic type, a fixed-size Eigen matrix,
/// or a type with LGI_NUMBERS (a static_assert names a type without it).
template <class Y>
constexpr std::size_t number_count() {
  using U = std::remove_cvref_t<Y>;
  if constexpr (std::is_arithmetic_v<U>) {
    return 1;
  } else if constexpr (detail::EigenFixed<U>) {
    return static_cast<std::size_t>(U::SizeAtCompileTime);
  } else {
    static_assert(detail::ListedNumbers<U>, "lgi::number_count: a state type without LGI_NUMBERS(...)");
    using Tuple = decltype(std::declval<U&>().numbers());
    return []<std::size_t... I>(std::index_sequence<I...>) {
      return (std::size_t{0} + ... + number_count<std::tuple_element_t<I, Tuple>>());
    }(std::make_index_sequence<std::tuple_size_v<Tuple>>{});
  }
}

/// Calls f on every number of y, in the header's order: f(double&) (f(const double&) for a const y) for double
/// scalars; `number_count<Y>()` calls in all. Allocates nothing; f may write through its argument.
template <class Y, class F>
void visit_numbers(Y& y, F&& f) {
  using U = std::remove_cvref_t<Y>;
  if constexpr (std::is_arithmetic_v<U>) {
    f(y);
  } else if constexpr (detail::EigenFixed<U>) {
    for (Eigen::Index i = 0; i < U::SizeAtCompileTime; ++i) f(y.data()[i]);
  } else {
    std::apply([&](auto&... member) { (visit_numbers(member, f), ...); }, y.numbers());
  }
}

/// True when Y's numbers are all of it: sizeof(Y) is their size rounded up to Y's alignment (double scalars).
template <class Y>
constexpr bool numbers_complete() {
  return sizeof(Y) == (number_count<Y>() * sizeof(double) + alignof(Y) - 1) / alignof(Y) * alignof(Y);
}

}  // namespace lgi
