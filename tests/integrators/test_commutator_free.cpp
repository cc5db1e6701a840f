// Commutator-free CF4 and Crouch–Grossman CG3, measured: the coefficients' order conditions, observed
// order on a free body (exact solution) and on the skew heavy top (long-double reference), exactness on a
// steady rotation, the generic torque path against the reduced one, R on SO(3) after 10⁶ steps, energy
// drift (they are not symplectic: the drift is reported, and checked to be there), Jets against finite
// differences.
#include "figures.hpp"
#include "jet_check.hpp"
#include "test_problems.hpp"

#include <lgi/core/driver.hpp>
#include <lgi/core/invariants.hpp>
#include <lgi/integrators/commutator_free.hpp>
#include <lgi/problems/free_body.hpp>
#include <lgi/problems/heavy_top.hpp>

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <string_view>
#include <vector>

namespace lgi {
namespace {

// The free symmetric body J = Q diag(I, I, I3) Qᵀ has an elementary solution: in principal axes
// (R_p = R Q, ω = QᵀΩ, M = diag(I, I, I3) ω) with λ = (I3 − I) ω_3 / I,
//   R_p(t) = R_p(0) exp(t M/I) exp(−λ t e3),    ω(t) = exp(λ t e3) ω(0)
// (R_p' = R_p hat(Rz(λt)M/I − λ e3) = R_p hat(ω(t)), since M_3/I − λ = ω_3). Evaluated in long double:
// accurate to ~1e-18, far below every error measured against it.
struct SymmetricBody {
  Mat3<double> Q = so3::exp(Vec3<double>(0.3, -0.2, 0.5));
  double I = 0.8, I3 = 1.3;
  FreeBody<double> problem() const {
    FreeBody<double> p{Q * Vec3<double>(I, I, I3).asDiagonal() * Q.transpose()};
    p.inertia = (0.5 * (p.inertia + p.inertia.transpose())).eval();
    return p;
  }
  State<double> initial() const { return {so3::exp(Vec3<double>(0.2, 0.1, -0.4)), Vec3<double>(0.9, -0.5, 1.2)}; }
  State<double> exact(double t_) const {
    using L = long double;
    const Mat3<L> q = Q.cast<L>();
    const State<double> x0 = initial();
    const Vec3<L> w = q.transpose() * x0.Omega.cast<L>();
    const L i = I, i3 = I3, t = t_;
    const Vec3<L> M(i * w(0), i * w(1), i3 * w(2));
    const L lambda = (i3 - i) * w(2) / i;
    const Mat3<L> Rp = x0.R.cast<L>() * q * so3::exp(Vec3<L>((t / i) * M)) *
                       so3::exp(Vec3<L>(-lambda * t * Vec3<L>::UnitZ()));
    const Vec3<L> wt = so3::exp(Vec3<L>(lambda * t * Vec3<L>::UnitZ())) * w;
    return {Mat3<L>(Rp * q.transpose()).cast<double>(), Vec3<L>(q * wt).cast<double>()};
  }
};

// The exact solution agrees with the independent long-double RK4 of test_problems.hpp (the inertia is
// not exactly symmetric-diagonal after rounding Q: the difference stays at round-off).
TEST(SymmetricBodyReference, AgreesWithLongDoubleRk4) {
  const SymmetricBody b;
  const double d = test::state_distance(b.exact(4.0), test::reference_solution(b.problem(), b.initial(), 4.0, 80000));
  std::printf("symmetric free body: exact vs long-double RK4 at t = 4: %.3e\n", d);
  EXPECT_LT(d, 2e-15);
}

template <template <class> class M, class P>
double error_at(const P& problem, const State<double>& x0, double T, int n, const State<double>& ref) {
  M<P> stepper(problem);
  State<double> x = x0;
  const auto summary = integrate_to(stepper, x, 0.0, T / n, T);
  EXPECT_EQ(summary.status, RunStatus::completed);
  return test::state_distance(x, ref);
}

template <template <class> class M, class P>
double observed_order(const char* label, const P& problem, const State<double>& x0, double T, const State<double>& ref,
                      const std::vector<int>& ns, double floor) {
  std::vector<double> hs, errors;
  for (const int n : ns) {
    hs.push_back(T / n);
    errors.push_back(error_at<M>(problem, x0, T, n, ref));
    EXPECT_GT(errors.back(), floor) << "error too close to the reference's own or to round-off";
  }
  const double p = test::fitted_order(hs, errors);
  std::printf("%s %s: observed order %.3f, errors %.3e (n = %d) .. %.3e (n = %d)\n", M<P>::traits.name.data(), label, p,
              errors.front(), ns.front(), errors.back(), ns.back());
  return p;
}

// The Crouch–Grossman order-3 conditions (Owren & Marthinsen 1999), and RK4 as CF4's Ω part.
TEST(CommutatorFreeTableaus, OrderConditions) {
  constexpr auto& t = tableaus::cg3;
  double b = 0, bc = 0, bcc = 0, bac = 0, nonclassical = 0;
  for (int i = 0; i < 3; ++i) {
    double ci = 0;
    for (int j = 0; j < i; ++j) ci += t.a(i, j);
    EXPECT_NEAR(ci, t.c[i], 1e-15) << "c_i = Σ_j a_ij";
    b += t.b(i);
    bc += t.b(i) * t.c[i];
    bcc += t.b(i) * t.c[i] * t.c[i];
    for (int j = 0; j < i; ++j) bac += t.b(i) * t.a(i, j) * t.c[j];
    nonclassical += t.b(i) * t.b(i) * t.c[i];
    for (int j = i + 1; j < 3; ++j) nonclassical += 2 * t.b(i) * t.c[i] * t.b(j);
  }
  EXPECT_NEAR(b, 1.0, 1e-15);
  EXPECT_NEAR(bc, 0.5, 1e-15);
  EXPECT_NEAR(bcc, 1.0 / 3, 1e-15);
  EXPECT_NEAR(bac, 1.0 / 6, 1e-15);
  EXPECT_NEAR(nonclassical, 1.0 / 3, 1e-15);

  constexpr auto& f = tableaus::cf4;
  const double rk4_a[4][4] = {{0, 0, 0, 0}, {0.5, 0, 0, 0}, {0, 0.5, 0, 0}, {0, 0, 1, 0}};
  const double rk4_b[4] = {1.0 / 6, 1.0 / 3, 1.0 / 3, 1.0 / 6};
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(f.b(i), rk4_b[i], 1e-16);
    for (int j = 0; j < 4; ++j) EXPECT_NEAR(f.a(i, j), rk4_a[i][j], 1e-16) << i << "," << j;
  }
  // Stage 4 starts from stage 2's attitude (the shared factor exp(½hΩ_1)): five exponentials a step.
  static_assert(tableaus::cf4.prefix_stage(3) == 1 && tableaus::cf4.prefix_stage(2) == -1);
  static_assert(tableaus::cg3.prefix_stage(2) == -1);
}

template <template <class> class Method>
struct MethodTag {
  template <class P>
  using type = Method<P>;
};
template <class Tag>
class CommutatorFreeTest : public ::testing::Test {};
using Methods = ::testing::Types<MethodTag<Cf4>, MethodTag<Cg3>>;
TYPED_TEST_SUITE(CommutatorFreeTest, Methods);

// Observed order on the free symmetric body (exact solution) and on the skew heavy top (non-diagonal J,
// k and z0 off the axes; long-double RK4 reference with 10⁵ steps, which agrees with 5·10⁴ to < 1e-16).
TYPED_TEST(CommutatorFreeTest, ObservedOrderMatchesDeclared) {
  constexpr int order = TypeParam::template type<FreeBody<double>>::traits.order;
  const std::vector<int> ns = order == 4 ? std::vector<int>{20, 40, 80, 160, 320} : std::vector<int>{40, 80, 160, 320, 640};
  const SymmetricBody body;
  const double p_free = observed_order<TypeParam::template type>("free body", body.problem(), body.initial(), 4.0,
                                                                 body.exact(4.0), ns, 1e-12);
  EXPECT_NEAR(p_free, order, 0.2);

  const auto top = test::skew_heavy_top();
  const State<double> x0 = test::skew_initial_state();
  const State<double> ref = test::reference_solution(top, x0, 2.0, 100000);
  ASSERT_LT(test::state_distance(ref, test::reference_solution(top, x0, 2.0, 50000)), 1e-15);
  const double p_top = observed_order<TypeParam::template type>("skew heavy top", top, x0, 2.0, ref, ns, 1e-12);
  EXPECT_NEAR(p_top, order, 0.2);
}

// A steady rotation (symmetric free body, Ω along a principal axis) is integrated exactly: every factor
// is exp(γ h Ω) with the same Ω, and the γ of the update sum to 1.
TYPED_TEST(CommutatorFreeTest, SteadyRotationIsExact) {
  using S = typename TypeParam::template type<FreeBody<double>>;
  const Mat3<double> Q = so3::exp(Vec3<double>(0.4, -0.3, 0.9));
  FreeBody<double> body{Q * Vec3<double>(2.0, 2.0, 1.0).asDiagonal() * Q.transpose()};
  body.inertia = (0.5 * (body.inertia + body.inertia.transpose())).eval();
  FreeBody<double> diagonal{Vec3<double>(2.0, 2.0, 1.0).asDiagonal()};
  const Mat3<double> R0 = so3::exp(Vec3<double>(0.3, -1.1, 0.4));
  const double h = 0.01;
  for (int axis = 0; axis < 3; ++axis) {
    for (const bool rotated : {false, true}) {
      const Vec3<double> Omega = 4.0 * (rotated ? Vec3<double>(Q.col(axis)) : Vec3<double>::Unit(axis));
      S stepper(rotated ? body : diagonal);
      State<double> x{R0, Omega};
      ASSERT_EQ(stepper.step(x, 0.0, h), StepStatus::ok);
      const Mat3<double> expected = R0 * so3::exp(Vec3<double>(h * Omega));
      EXPECT_LT((x.R - expected).cwiseAbs().maxCoeff(), 1e-15) << S::traits.name << " axis " << axis;
      EXPECT_LT((x.Omega - Omega).cwiseAbs().maxCoeff(), rotated ? 1e-14 : 4 * 2.3e-16 * 4.0) << S::traits.name;
    }
  }
}

// The heavy top seen only through torque(R): stage attitudes R_i are formed as matrices. Same trajectory
// as the reduced path (Γ_i rotated) to round-off.
struct OpaqueTop {
  using Scalar = double;
  static constexpr std::string_view name = "opaque_top";
  static constexpr bool has_torque = true;
  HeavyTop<double> top;
  Mat3<double> inertia = top.inertia;
  double potential(const Mat3<double>& R) const { return top.potential(R); }
  Vec3<double> torque(const Mat3<double>& R) const { return top.torque(R); }
  static constexpr std::array<std::string_view, 0> invariant_names{};
  std::array<double, 0> invariants(const State<double>&) const { return {}; }
};

TYPED_TEST(CommutatorFreeTest, GenericTorquePathMatchesReducedPath) {
  using SR = typename TypeParam::template type<HeavyTop<double>>;
  using SG = typename TypeParam::template type<OpaqueTop>;
  const auto top = test::skew_heavy_top();
  const OpaqueTop opaque{top, top.inertia};
  State<double> xr = test::skew_initial_state(), xg = xr;
  SR reduced(top);
  SG generic(opaque);
  integrate_to(reduced, xr, 0.0, 0.01, 2.0);
  integrate_to(generic, xg, 0.0, 0.01, 2.0);
  // 2.0e-16 … 2.7e-16: a few roundings of O(1) numbers.
  test::expect_figure(std::string("generic vs reduced torque path over 200 steps, ") + std::string(SR::traits.name),
                      test::state_distance(xr, xg), 1.2e-15);
}

// 10⁶ steps of h = 0.01 on the Hairer–Vilmart heavy top: ‖RᵀR − I‖ ≤ 1e-12 (R on SO(3) by construction).
// Not symplectic: the energy error is measured and reported, and m·k is not conserved — the drift is
// there (above 1e-12 of |m| for CG3 at this step; CF4's error is smaller but grows).
TYPED_TEST(CommutatorFreeTest, MillionStepsStayOnTheGroup) {
  using S = typename TypeParam::template type<HeavyTop<double>>;
  const auto problem = HeavyTop<double>::hairer_vilmart();
  const State<double> x0 = test::hairer_vilmart_state(problem);
  const double E0 = energy(problem, x0), mk0 = problem.invariants(x0)[0];
  const double m0 = spatial_momentum(problem.inertia, x0).norm();
  double orth = 0, energy_first = 0, energy_last = 0, mk = 0;
  const std::int64_t n = 1'000'000;
  std::int64_t seen = 0;
  auto observe = [&](double, const State<double>& x) {
    orth = std::max(orth, so3::orthogonality_error(x.R));
    const double e = std::abs(energy(problem, x) - E0) / std::abs(E0);
    if (seen < 100) energy_first = std::max(energy_first, e);
    if (seen >= 900) energy_last = std::max(energy_last, e);
    mk = std::max(mk, std::abs(problem.invariants(x)[0] - mk0) / m0);
    ++seen;
  };
  S stepper(problem);
  State<double> x = x0;
  const auto summary = integrate_every(stepper, x, 0.0, 0.01, 0.01 * n, n / 1000, observe);
  ASSERT_EQ(summary.status, RunStatus::completed);
  std::printf("%s 1e6 steps h=0.01: max |RtR-I| %.3e, rel. energy error first tenth %.3e, last tenth %.3e, "
              "max m.k error / |m| %.3e\n",
              S::traits.name.data(), orth, energy_first, energy_last, mk);
  EXPECT_LE(orth, 1e-12);
  EXPECT_GT(energy_last, 3 * energy_first) << "a non-symplectic method's energy error grows";
}

// Jets through CF4 and CG3: derivatives after 50 steps with respect to Ω0 and b, against central
// differences, on both torque paths (reduced: the heavy top; generic: stage attitudes as matrices).
TYPED_TEST(CommutatorFreeTest, JetDerivativesMatchFiniteDifferences) {
  test::expect_heavy_top_jets_match<TypeParam::template type>(0.02, 1.0, 4e-15);
}

}  // namespace
}  // namespace lgi
