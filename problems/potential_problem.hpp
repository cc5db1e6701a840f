/// \file
/// lgi/problems/potential_problem.hpp — problems defined by their potential alone; the torque by
/// automatic differentiation.
///
/// The user writes V as a function template on the scalar S; lgi derives the body-frame torque
///
/// ~~~{.unparsed}
///   M(R) = −∂/∂η V(R exp(η̂)) |_{η = 0}                 (the convention of core/problem.hpp)
/// ~~~
///
/// by forward-mode automatic differentiation: V is evaluated once on the matrix R + R hat(ε) whose entries
/// are dual numbers in the three directions ε = (ε1, ε2, ε3), ε_i ε_j = 0 (∂R/∂η_i = R hat(e_i) at η = 0;
/// second-order terms of exp do not enter a first derivative, so V may be any smooth extension of the
/// potential off SO(3)). Two forms:
///
/// ~~~{.unparsed}
///   PotentialProblem<T, P>       V(R), a function of the attitude: torque M = −∂V/∂η as above.
///   AxisPotentialProblem<T, P>   V(Γ), a function of Γ = Rᵀa only (a a fixed laboratory axis: gravity,
///                                a uniform magnetic field). With R → R exp(η̂), Γ → Γ + Γ × η + O(η²), so
///                                δV = ∇V·(Γ × η) = η·(∇V × Γ) and M = Γ × ∇V(Γ); ∇V by a 3-component dual
///                                on Γ. This is a ReducedAttitudeProblem (core/problem.hpp), so RKMK stages
///                                rotate Γ instead of forming R exp(u). Heavy top: V = b Γ·z0, ∇V = b z0,
///                                M = b Γ × z0 — the seed paper's eq. (s4).
/// ~~~
///
/// Why a dual number of our own, not ceres::Jet: the core and problems depend on Eigen alone (DESIGN.md
/// §2), and users without Ceres get automatic torques too. The dual below is the minimal forward mode
/// (value + 3 derivative components, the arithmetic and the elementary functions a potential uses) and
/// is itself templated on its scalar, so `Dual<ceres::Jet<double, N>>` nests: derivatives of whole
/// trajectories through the automatic torque work (tests/problems/test_problem_library.cpp measures both against
/// finite differences). A potential functor written for any S (as in the tutorial docs/new_problem.md)
/// is called with S = T (the energy), S = `Dual<T>` (the torque).
///
/// Parameters. A functor holding doubles works for every T (the cast to Dual happens inside its
/// arithmetic); for derivatives with respect to its parameters (fitting), give it a member template
/// `template <class S> Functor<S> cast() const`, which `cast<S>()` of the problem then uses.
///
/// Cost: one evaluation of V in dual arithmetic (≈ 4× the flops of V) per torque; V(R) takes the generic path
/// (every stage of RKMK forms R exp(u)), V(Γ) the reduced one. Instructions per step against the hand-written
/// heavy top: docs/performance.md, "Design measurements behind the code".
/// Invariants: the energy (computed by core/invariants.hpp for every problem); a generic potential has
/// no other, so `invariant_names` is empty. No allocation anywhere.
#pragma once

#include "../core/invariants.hpp"
#include "../core/problem.hpp"
#include "../core/so3.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <string_view>
#include <type_traits>

namespace lgi {

// ---------------------------------------------------------------------------------------------------
/// `Dual<T, N>`: forward-mode dual number, value a and derivative components v (ε_i ε_j = 0).
template <class T, int N = 3>
struct Dual;

/// True when X is a `Dual<T, N>`.
template <class X>
inline constexpr bool is_lgi_dual_v = false;
/// True: `Dual<T, N>` is a dual.
template <class T, int N>
inline constexpr bool is_lgi_dual_v<Dual<T, N>> = true;

/// The dual number a + v·ε, ε_i ε_j = 0 (the declaration above). Any scalar T with the usual arithmetic
/// (double, ceres::Jet, Dual itself); a plain value, no allocation.
template <class T, int N>
struct Dual {
  using Vec = Eigen::Matrix<T, N, 1>;  ///< the derivative components' type
  T a;                                 ///< the value
  Vec v;                               ///< the N derivative components

  /// Zero: a = 0, v = 0.
  Dual() : a(T(0)), v(Vec::Zero()) {}
  /// a = value, v = derivative.
  Dual(const T& value, const Vec& derivative) : a(value), v(derivative) {}
  /// A constant (any scalar T can be built from: double, int, T itself).
  template <class U>
    requires(!is_lgi_dual_v<U> && std::is_constructible_v<T, const U&>)
  explicit Dual(const U& value) : a(T(value)), v(Vec::Zero()) {}

  /// Compound assignment: *this = *this op y, with the binary operators below.
  ///@{
  Dual& operator+=(const Dual& y) { return *this = *this + y; }
  Dual& operator-=(const Dual& y) { return *this = *this - y; }
  Dual& operator*=(const Dual& y) { return *this = *this * y; }
  Dual& operator/=(const Dual& y) { return *this = *this / y; }
  ///@}
};

/// A plain operand mixed with `Dual<T, N>`: anything T can be built from that is not itself a dual.
template <class U, class T>
concept DualOperand = !is_lgi_dual_v<U> && std::is_constructible_v<T, const U&>;

/// Arithmetic of duals and of a dual with a plain operand: the value's operation, with the derivative components by
/// the sum, product and quotient rules (division by a zero value gives IEEE infinities or NaN, as for T).
///@{
template <class T, int N>
Dual<T, N> operator+(const Dual<T, N>& x) {
  return x;
}
template <class T, int N>
Dual<T, N> operator-(const Dual<T, N>& x) {
  return {-x.a, -x.v};
}
template <class T, int N>
Dual<T, N> operator+(const Dual<T, N>& x, const Dual<T, N>& y) {
  return {x.a + y.a, x.v + y.v};
}
template <class T, int N>
Dual<T, N> operator-(const Dual<T, N>& x, const Dual<T, N>& y) {
  return {x.a - y.a, x.v - y.v};
}
template <class T, int N>
Dual<T, N> operator*(const Dual<T, N>& x, const Dual<T, N>& y) {
  return {x.a * y.a, x.a * y.v + y.a * x.v};
}
template <class T, int N>
Dual<T, N> operator/(const Dual<T, N>& x, const Dual<T, N>& y) {
  const T inv = T(1) / y.a;
  const T q = x.a * inv;
  return {q, (x.v - q * y.v) * inv};
}
template <class T, int N, DualOperand<T> U>
Dual<T, N> operator+(const Dual<T, N>& x, const U& y) {
  return {x.a + T(y), x.v};
}
template <class T, int N, DualOperand<T> U>
Dual<T, N> operator+(const U& x, const Dual<T, N>& y) {
  return {T(x) + y.a, y.v};
}
template <class T, int N, DualOperand<T> U>
Dual<T, N> operator-(const Dual<T, N>& x, const U& y) {
  return {x.a - T(y), x.v};
}
template <class T, int N, DualOperand<T> U>
Dual<T, N> operator-(const U& x, const Dual<T, N>& y) {
  return {T(x) - y.a, -y.v};
}
template <class T, int N, DualOperand<T> U>
Dual<T, N> operator*(const Dual<T, N>& x, const U& y) {
  const T s(y);
  return {x.a * s, x.v * s};
}
template <class T, int N, DualOperand<T> U>
Dual<T, N> operator*(const U& x, const Dual<T, N>& y) {
  const T s(x);
  return {s * y.a, s * y.v};
}
template <class T, int N, DualOperand<T> U>
Dual<T, N> operator/(const Dual<T, N>& x, const U& y) {
  const T inv = T(1) / T(y);
  return {x.a * inv, x.v * inv};
}
template <class T, int N, DualOperand<T> U>
Dual<T, N> operator/(const U& x, const Dual<T, N>& y) {
  const T inv = T(1) / y.a;
  const T q = T(x) * inv;
  return {q, -q * inv * y.v};
}
///@}

/// Comparisons look at the value only (branches in V take the same side for the dual as for its value).
///@{
template <class T, int N>
bool operator<(const Dual<T, N>& x, const Dual<T, N>& y) {
  return x.a < y.a;
}
template <class T, int N>
bool operator>(const Dual<T, N>& x, const Dual<T, N>& y) {
  return x.a > y.a;
}
template <class T, int N>
bool operator<=(const Dual<T, N>& x, const Dual<T, N>& y) {
  return x.a <= y.a;
}
template <class T, int N>
bool operator>=(const Dual<T, N>& x, const Dual<T, N>& y) {
  return x.a >= y.a;
}
template <class T, int N, DualOperand<T> U>
bool operator<(const Dual<T, N>& x, const U& y) {
  return x.a < T(y);
}
template <class T, int N, DualOperand<T> U>
bool operator>(const Dual<T, N>& x, const U& y) {
  return x.a > T(y);
}
template <class T, int N, DualOperand<T> U>
bool operator<(const U& x, const Dual<T, N>& y) {
  return T(x) < y.a;
}
template <class T, int N, DualOperand<T> U>
bool operator>(const U& x, const Dual<T, N>& y) {
  return T(x) > y.a;
}
///@}

/// Elementary functions: f(a) + f'(a) v. Found by argument-dependent lookup, like ceres::Jet's, so a
/// potential written with `using std::sin; sin(x)` works for double, Jet and Dual alike. Outside a function's
/// domain (sqrt and log of a negative value, asin and acos beyond ±1, the derivative of sqrt at 0) the result is
/// NaN or infinite, as T's own function gives it; abs at 0 takes the derivative of +x.
///@{
template <class T, int N>
Dual<T, N> sqrt(const Dual<T, N>& x) {
  using std::sqrt;
  const T s = sqrt(x.a);
  return {s, x.v / (T(2) * s)};
}
template <class T, int N>
Dual<T, N> exp(const Dual<T, N>& x) {
  using std::exp;
  const T e = exp(x.a);
  return {e, e * x.v};
}
template <class T, int N>
Dual<T, N> log(const Dual<T, N>& x) {
  using std::log;
  return {log(x.a), x.v / x.a};
}
template <class T, int N>
Dual<T, N> sin(const Dual<T, N>& x) {
  using std::cos;
  using std::sin;
  return {sin(x.a), cos(x.a) * x.v};
}
template <class T, int N>
Dual<T, N> cos(const Dual<T, N>& x) {
  using std::cos;
  using std::sin;
  return {cos(x.a), -sin(x.a) * x.v};
}
template <class T, int N>
Dual<T, N> tan(const Dual<T, N>& x) {
  using std::tan;
  const T t = tan(x.a);
  return {t, (T(1) + t * t) * x.v};
}
template <class T, int N>
Dual<T, N> asin(const Dual<T, N>& x) {
  using std::asin;
  using std::sqrt;
  return {asin(x.a), x.v / sqrt(T(1) - x.a * x.a)};
}
template <class T, int N>
Dual<T, N> acos(const Dual<T, N>& x) {
  using std::acos;
  using std::sqrt;
  return {acos(x.a), -x.v / sqrt(T(1) - x.a * x.a)};
}
template <class T, int N>
Dual<T, N> atan(const Dual<T, N>& x) {
  using std::atan;
  return {atan(x.a), x.v / (T(1) + x.a * x.a)};
}
template <class T, int N>
Dual<T, N> atan2(const Dual<T, N>& y, const Dual<T, N>& x) {
  using std::atan2;
  const T r2 = x.a * x.a + y.a * y.a;
  return {atan2(y.a, x.a), (x.a * y.v - y.a * x.v) / r2};
}
template <class T, int N>
Dual<T, N> pow(const Dual<T, N>& x, double p) {
  using std::pow;
  const T xp1 = pow(x.a, T(p - 1));
  return {xp1 * x.a, (T(p) * xp1) * x.v};
}
template <class T, int N>
Dual<T, N> abs(const Dual<T, N>& x) {
  return x.a < T(0) ? -x : x;
}
///@}

// ---------------------------------------------------------------------------------------------------
// The automatic torques.

/// M = −∂/∂η V(R exp(η̂)) at η = 0, for V callable on `Mat3<Dual<T>>`.
template <class T, class Potential>
Vec3<T> torque_from_potential(const Potential& V, const Mat3<T>& R) {
  using D = Dual<T, 3>;
  Mat3<D> Rd;
  // ∂R/∂η_i = R hat(e_i): column c of R hat(e_i) is R (e_i × e_c).
  const Vec3<T> c0 = R.col(0), c1 = R.col(1), c2 = R.col(2);
  const Vec3<T> zero = Vec3<T>::Zero();
  const Mat3<T> dcol[3] = {// dcol[c].col(i) = ∂(column c)/∂η_i
                           (Mat3<T>() << zero, -c2, c1).finished(),
                           (Mat3<T>() << c2, zero, -c0).finished(),
                           (Mat3<T>() << -c1, c0, zero).finished()};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) Rd(r, c) = D(R(r, c), Vec3<T>(dcol[c].row(r).transpose()));
  const D v = V(static_cast<const Mat3<D>&>(Rd));
  return -v.v;
}

/// ∇V(Γ) for V callable on `Vec3<Dual<T>>`; the torque is Γ × ∇V(Γ).
template <class T, class Potential>
Vec3<T> gradient_of_axis_potential(const Potential& V, const Vec3<T>& Gamma) {
  using D = Dual<T, 3>;
  const Vec3<D> G(D(Gamma.x(), Vec3<T>::UnitX()), D(Gamma.y(), Vec3<T>::UnitY()), D(Gamma.z(), Vec3<T>::UnitZ()));
  return V(G).v;
}

namespace detail {
// The functor re-instantiated on S when it knows how (a member template cast<S>()), else itself.
template <class S, class F>
auto rebind_functor(const F& f) {
  if constexpr (requires { f.template cast<S>(); })
    return f.template cast<S>();
  else
    return f;
}
template <class F>
constexpr std::string_view functor_name(std::string_view fallback) {
  if constexpr (requires { F::name; })
    return F::name;
  else
    return fallback;
}
}  // namespace detail

/// A rigid body (inertia J, about the fixed point or the centre of mass) under the potential V(R).
/// `name` is Potential::name when the functor has one, else "potential".
template <class T, class Potential>
struct PotentialProblem {
  using Scalar = T;                                                                     ///< the scalar type
  static constexpr std::string_view name = detail::functor_name<Potential>("potential");  ///< problem.type
  static constexpr bool has_torque = true;                                              ///< M = −∂V/∂η

  Mat3<T> inertia = Mat3<T>::Identity();  ///< J, body frame, symmetric positive definite (not checked here)
  Potential V{};                          ///< the potential: V(R) callable with `Mat3<S>` for S = T and `Dual<T>`

  /// V(R).
  T potential(const Mat3<T>& R) const { return V(R); }
  /// M(R) = −∂/∂η V(R exp(η̂)) at η = 0 (torque_from_potential): one evaluation of V in dual arithmetic.
  Vec3<T> torque(const Mat3<T>& R) const { return torque_from_potential(V, R); }

  /// No extra output columns (the energy is every problem's).
  static constexpr std::array<std::string_view, 0> invariant_names{};
  /// {}.
  std::array<T, 0> invariants(const State<T>&) const { return {}; }

  /// The same problem in scalar S: V itself, or `V.cast<S>()` when the functor has that member template (header).
  template <class S>
  auto cast() const {
    auto V_s = detail::rebind_functor<S>(V);
    return PotentialProblem<S, decltype(V_s)>{inertia.template cast<S>(), V_s};
  }
};

/// A rigid body under a potential V(Γ) of Γ = Rᵀa alone (a: a unit laboratory vector, default e3).
/// Invariants: m·a = a·(R J Ω), conserved because V is invariant under rotations about a (its column
/// "momentum_a"), and the Casimir |Γ| = 1 (exact while R is orthogonal).
template <class T, class Potential>
struct AxisPotentialProblem {
  using Scalar = T;  ///< the scalar type
  static constexpr std::string_view name = detail::functor_name<Potential>("axis_potential");  ///< problem.type
  static constexpr bool has_torque = true;  ///< M = Γ × ∇V(Γ)

  Mat3<T> inertia = Mat3<T>::Identity();  ///< J, body frame, symmetric positive definite (not checked here)
  Potential V{};                          ///< the potential: V(Γ) callable with `Vec3<S>` for S = T and `Dual<T>`
  Vec3<T> axis = Vec3<T>::UnitZ();        ///< a, unit, laboratory frame (not checked here)

  /// V(Rᵀa).
  T potential(const Mat3<T>& R) const { return V(Vec3<T>(R.transpose() * axis)); }
  /// M(R) = Γ × ∇V(Γ), Γ = Rᵀa.
  Vec3<T> torque(const Mat3<T>& R) const { return reduced_torque(Vec3<T>(R.transpose() * axis)); }
  /// a: the torque depends on R only through Γ = Rᵀa (ReducedAttitudeProblem).
  const Vec3<T>& reduced_axis() const { return axis; }
  /// Γ × ∇V(Γ), the gradient by one evaluation of V in dual arithmetic (gradient_of_axis_potential).
  Vec3<T> reduced_torque(const Vec3<T>& Gamma) const { return Gamma.cross(gradient_of_axis_potential(V, Gamma)); }

  /// The extra output column: m·a.
  static constexpr std::array<std::string_view, 1> invariant_names{"momentum_a"};
  /// {a·(R J Ω)} of x.
  std::array<T, 1> invariants(const State<T>& x) const { return {axis.dot(spatial_momentum(inertia, x))}; }

  /// The same problem in scalar S: V itself, or `V.cast<S>()` when the functor has that member template (header).
  template <class S>
  auto cast() const {
    auto V_s = detail::rebind_functor<S>(V);
    return AxisPotentialProblem<S, decltype(V_s)>{inertia.template cast<S>(), V_s, axis.template cast<S>()};
  }
};

// ---------------------------------------------------------------------------------------------------
/// FieldPotential: the potential of the scene problem "potential" (apps/problems/potential.cpp), data only,
/// so that a scene file can state it:
///
/// ~~~{.unparsed}
///   V(R) = Σ_j b_j k_j·(R z_j)  +  ½ c a·(R Q Rᵀ a)
/// ~~~
///
/// The linear terms are uniform fields (k_j laboratory, unit) acting on offset masses or dipoles (z_j
/// body, unit; a heavy top is one term with b_j = b); the quadratic term is a field gradient along the
/// laboratory axis a acting on the body tensor Q (symmetric): with c = 3n², a = r̂ and Q = J it is the
/// gravity-gradient potential of a satellite at the instant its radial direction is a (satellite.hpp).
/// At most 4 linear terms (fixed capacity: no allocation). The torque comes from automatic
/// differentiation like any PotentialProblem's.
template <class T = double>
struct FieldPotential {
  static constexpr std::string_view name = "potential";  ///< the scene's problem.type
  static constexpr int max_terms = 4;                    ///< the capacity of the linear terms
  int terms = 0;                                         ///< linear terms in use, 0 … max_terms (not checked)
  std::array<T, max_terms> b{};                          ///< b_j, energy units
  std::array<Vec3<T>, max_terms> k{};                    ///< k_j, unit, laboratory frame
  std::array<Vec3<T>, max_terms> z{};                    ///< z_j, unit, body frame
  T c = T(0);                                            ///< the gradient's strength (0: no quadratic term)
  Vec3<T> a = Vec3<T>::UnitZ();                          ///< the gradient's laboratory axis, unit
  Mat3<T> Q = Mat3<T>::Zero();                           ///< the body tensor, symmetric, body frame

  /// V(R) of the header's formula, for S = T, `Dual<T>` or any scalar the data convert to.
  /// Out of line and flattened itself: every stage of every flattened step calls it, and a copy inlined into each
  /// would multiply the compiled code by the stage count.
  template <class S>
  [[gnu::noinline]] LGI_FLATTEN S operator()(const Mat3<S>& R) const {
    S V(0);
    for (int j = 0; j < terms; ++j) V += S(b[j]) * k[j].template cast<S>().dot(R * z[j].template cast<S>());
    if (!is_exact_zero(c)) {
      const Vec3<S> rho = R.transpose() * a.template cast<S>();  // a seen from the body
      V += S(0.5) * S(c) * rho.dot(Q.template cast<S>() * rho);
    }
    return V;
  }

  /// The same data in scalar S (parameters become differentiable with S = ceres::Jet).
  template <class S>
  FieldPotential<S> cast() const {
    FieldPotential<S> f;
    f.terms = terms;
    for (int j = 0; j < max_terms; ++j) {
      f.b[j] = S(b[j]);
      f.k[j] = k[j].template cast<S>();
      f.z[j] = z[j].template cast<S>();
    }
    f.c = S(c);
    f.a = a.template cast<S>();
    f.Q = Q.template cast<S>();
    return f;
  }
};

/// The scene problem "potential": a body under a FieldPotential.
template <class T = double>
using FieldPotentialBody = PotentialProblem<T, FieldPotential<T>>;

}  // namespace lgi

namespace Eigen {
/// Eigen needs to know the dual is a real scalar (fixed-size products, dot, norm).
template <class T, int N>
struct NumTraits<lgi::Dual<T, N>> : NumTraits<T> {
  ///@{
  /// Eigen's traits of a real scalar: Dual itself as its real, non-integer and literal type, T's limits as
  /// constant duals, costs of N + 1 components.
  using Real = lgi::Dual<T, N>;
  using NonInteger = Real;
  using Nested = Real;
  using Literal = Real;
  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    RequireInitialization = 1,
    ReadCost = (N + 1) * NumTraits<T>::ReadCost,
    AddCost = (N + 1) * NumTraits<T>::AddCost,
    MulCost = (2 * N + 1) * NumTraits<T>::MulCost + N * NumTraits<T>::AddCost,
  };
  static Real epsilon() { return Real(NumTraits<T>::epsilon()); }
  static Real dummy_precision() { return Real(NumTraits<T>::dummy_precision()); }
  static Real highest() { return Real(NumTraits<T>::highest()); }
  static Real lowest() { return Real(NumTraits<T>::lowest()); }
  static int digits10() { return NumTraits<T>::digits10(); }
  ///@}
};
}  // namespace Eigen
