/// \file
/// lgi/core/scalar.hpp — what every numeric template in lgi assumes about its scalar.
///
/// Everything numeric in lgi is a template on the scalar T, so that automatic-differentiation types
/// (ceres::Jet) flow through every map and integrator. The core never includes Ceres: a scalar is
/// recognised by duck typing. Branches that depend on the size of a quantity (small-angle Taylor
/// branches, Newton convergence tests) read the *value part* through `value_of`, so the branch taken
/// is the same for a Jet as for its double value.
///
/// Three kinds of scalar: the arithmetic types (float, double, long double); ceres::Jet (a value part x.a
/// and derivatives x.v); and a real class type without derivatives that has std::numeric_limits and finds
/// its sqrt, sin, atan2, isfinite … by argument-dependent lookup (boost::multiprecision::float128 in
/// tests/integrators/test_quad_order.cpp, which runs the RKMK methods in quad precision). The core includes neither.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <concepts>
#include <limits>
#include <type_traits>

// On a step function: inline everything it calls. A step is a few hundred flops over 3-vectors spread
// across small helpers; left to its heuristics GCC 12 sometimes keeps helpers out of line, and the
// decision flips with unrelated code in the translation unit, so the same source costs more, by an amount
// that varies from build to build (docs/performance.md, "Where the instructions go").
// Defined empty by the build of code that needs no speed (the tests: -DLGI_FLATTEN=), where flattening
// every Jet instantiation costs compile time and buys nothing.
#if !defined(LGI_FLATTEN)
#if defined(__GNUC__)
#define LGI_FLATTEN [[gnu::flatten]]
#else
#define LGI_FLATTEN
#endif
#endif

// Runtime-dispatched copies of the hottest steps (integrators/splitting.hpp and integrators/rkmk.hpp, in double):
// each step is compiled for the x86-64 baseline and, under GCC's target("avx2"), for AVX2 (core/integrator.hpp,
// detail::dispatched_step), and the CPU's features, asked once per process, pick one. The AVX2 copy does the
// same IEEE operations in the same order — three-operand VEX encoding and wider registers (RKMK: 4-wide vectors
// for its 3-vectors), no FMA (GCC contracts a·b + c only where FMA instructions are enabled, and "avx2" does not
// enable them) — so results are the same bit for bit (tests/core/test_dispatch.cpp). Off for other compilers and
// targets, and where LGI_NO_DISPATCH is defined (the unit tests, which build without flattening for compile time).
#if !defined(LGI_NO_DISPATCH) && defined(__GNUC__) && !defined(__clang__) && __GNUC__ >= 12 && \
    defined(__x86_64__) && defined(__gnu_linux__)
#define LGI_DISPATCH_CLONES 1
#endif

/// Lie-group integrators for rigid bodies: the state on SO(3) × R³, problems, steppers, drivers, fitting.
namespace lgi {

/// A fixed-size column 3-vector of scalar T (angular velocity, momentum, a body or laboratory axis).
template <class T>
using Vec3 = Eigen::Matrix<T, 3, 1>;
/// A fixed-size 3×3 matrix of scalar T (an attitude, an inertia tensor), column-major as Eigen's default.
template <class T>
using Mat3 = Eigen::Matrix<T, 3, 3>;

namespace detail {
// A real scalar of class type: numeric_limits specialised, no value part (not a Jet), e.g.
// boost::multiprecision::float128. Eigen matrices have no numeric_limits.
template <class T>
inline constexpr bool is_real_class_v =
    !std::is_arithmetic_v<T> && std::numeric_limits<T>::is_specialized && !requires(const T& x) { x.a; };
}  // namespace detail

/// The value part of a scalar: x itself for arithmetic types and real class types, x.a (recursively) for
/// ceres::Jet.
template <class T>
constexpr auto value_of(const T& x) {
  if constexpr (std::is_arithmetic_v<T>) {
    return x;
  } else if constexpr (requires { x.a; }) {
    return value_of(x.a);
  } else if constexpr (detail::is_real_class_v<T>) {
    return x;
  } else {
    static_assert(std::is_arithmetic_v<T>, "lgi::value_of: unsupported scalar type");
    return 0.0;
  }
}

/// True when T carries derivative parts (Jets): Newton loops then take one extra iteration so that
/// the derivative part converges too (implicit function theorem), see NUMERICS.md "Traps".
template <class T>
inline constexpr bool is_dual_v = !std::is_arithmetic_v<T> && !detail::is_real_class_v<T>;

/// Every component finite, value and derivative parts alike (ceres::isfinite checks only the value).
template <class T>
bool all_finite(const T& x) {
  if constexpr (std::is_arithmetic_v<T>) {
    return std::isfinite(x);
  } else if constexpr (requires { x.a; x.v; }) {
    return all_finite(x.a) && x.v.allFinite();
  } else if constexpr (detail::is_real_class_v<T>) {
    using std::isfinite;
    return static_cast<bool>(isfinite(x));
  } else if constexpr (std::is_arithmetic_v<typename T::Scalar>) {
    return x.allFinite();  // vectorised (x − x == x − x)
  } else {                 // a plain Eigen matrix or vector of Jets
    for (Eigen::Index i = 0; i < x.size(); ++i)
      if (!all_finite(x.data()[i])) return false;
    return true;
  }
}

/// True when x is exactly zero, derivative parts of Jets included: a structural zero that a fast path
/// may drop without losing a derivative.
template <class T>
bool is_exact_zero(const T& x) {
  if constexpr (std::is_arithmetic_v<T>)
    return x == T(0);
  else if constexpr (requires { x.a; x.v; })
    return is_exact_zero(x.a) && x.v.isZero(0);
  else
    return value_of(x) == 0;
}

/// The arithmetic type under T (double for `ceres::Jet<double, N>`) and its machine epsilon.
template <class T>
using value_type_t = decltype(value_of(std::declval<T>()));
/// The machine epsilon of `value_type_t<T>` (2⁻⁵² for double and Jets of double).
template <class T>
inline constexpr value_type_t<T> epsilon_v = std::numeric_limits<value_type_t<T>>::epsilon();

}  // namespace lgi
