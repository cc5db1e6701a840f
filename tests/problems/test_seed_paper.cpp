// The seed paper reproduced, measured: its Euler-angle formulation (problems/euler_angle_top.hpp) against
// the SO(3) one, the closed-form quadrature (problems/lagrange_quadrature.hpp) against integration, the
// Euclidean Runge–Kutta methods (integrators/euclidean_rk.hpp) — order, Jets, the singularity stop —,
// the scene path of `lgi run`, and that docs/seed_paper.md carries exactly the numbers the reproduction
// program (examples/seed_paper.cpp, included here) computes.
#define LGI_SEED_PAPER_NO_MAIN
#include "../examples/seed_paper.cpp"

#include "test_problems.hpp"

#include <lgi/core/inertia.hpp>
#include <lgi/problems/free_body.hpp>

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

namespace lgi {
namespace {

using seed::Path;
using Vector = EulerAngleTop<double>::Vector;

// ---- (6.3) and the coordinates ---------------------------------------------------------------------

TEST(EulerAngles, RotationIsRzRxRzAndOrthogonal) {
  for (const Vec3<double>& a : {Vec3<double>(0.3, 1.1, -2.0), Vec3<double>(-2.9, 0.2, 0.7), Vec3<double>(1.7, 2.9, 3.1)}) {
    const Mat3<double> R = rotation_from_euler_angles(a[0], a[1], a[2]);
    const Mat3<double> expected = so3::exp(Vec3<double>(0, 0, a[0])) * so3::exp(Vec3<double>(a[1], 0, 0)) *
                                  so3::exp(Vec3<double>(0, 0, a[2]));
    EXPECT_LT((R - expected).cwiseAbs().maxCoeff(), 1e-15);
    EXPECT_LT(so3::orthogonality_error(R), 1e-15);
    // and back: (6.3) inverted gives the same angles (θ in (0, π), φ, ψ in (−π, π]).
    EXPECT_LT((euler_angles_from_rotation(R) - a).cwiseAbs().maxCoeff(), 1e-14) << a.transpose();
  }
}

// Ω of (6.3) is vee(Rᵀ R'), R' by central differences along a path of the angles.
TEST(EulerAngles, BodyRateIsRtRdot) {
  const Vec3<double> a(0.4, 1.0, -0.6), rate(0.7, -0.3, 2.1);
  const double d = 1e-6;
  const auto R = [&](double s) {
    const Vec3<double> b = a + s * rate;
    return rotation_from_euler_angles(b[0], b[1], b[2]);
  };
  const Mat3<double> dR = (R(d) - R(-d)) / (2 * d);
  const Vec3<double> Omega = body_rate_from_euler_rates(a[1], a[2], rate[0], rate[1], rate[2]);
  EXPECT_LT((so3::vee(Mat3<double>(R(0).transpose() * dR)) - Omega).norm(), 1e-9);
}

TEST(EulerAngleTop, StateRoundTrips) {
  const EulerAngleTop<double> top = seed::paper_top();
  Vector y;
  y << 0.5, 1.2, -0.4, 0.3, -0.7, 3.5, 0, 0;
  const Vector back = top.from_state(top.to_state(y));
  EXPECT_LT((back - y).cwiseAbs().maxCoeff(), 1e-14);
  const State<double> x = seed::scenario_b().x0;
  const State<double> x2 = top.to_state(top.from_state(x));
  EXPECT_LT((x2.R - x.R).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((x2.Omega - x.Omega).cwiseAbs().maxCoeff(), 1e-14);
}

// The equations (s6.1)–(s6.3), mapped to Ω' by differentiating Ω(y) along y' (a Jet), are the Euler–Poisson
// equations (s4) of the same top: J Ω' = (JΩ) × Ω + b (Rᵀk) × e3, at several states, to round-off.
TEST(EulerAngleTop, EquationsAreTheEulerPoissonEquations) {
  using J1 = ceres::Jet<double, 1>;
  const EulerAngleTop<double> top = seed::paper_top();
  const EulerAngleTop<J1> topj = top.cast<J1>();
  const HeavyTop<double> so3_top = top.heavy_top();
  for (const Vec3<double>& a : {Vec3<double>(0.5, 1.2, 0.0), Vec3<double>(-2.0, 0.4, 1.0), Vec3<double>(3.0, 2.6, -1.5)}) {
    Vector y;
    y << a[0], a[1], a[2], 0.4, -0.8, 2.5, 0, 0;
    const Vector dy = top.derivative(0.0, y);
    Eigen::Matrix<J1, 8, 1> yj;
    for (int i = 0; i < 8; ++i) {
      yj[i] = J1(y[i]);
      yj[i].v[0] = dy[i];
    }
    const State<J1> xj = topj.to_state(yj);
    Vec3<double> dOmega;
    for (int i = 0; i < 3; ++i) dOmega[i] = xj.Omega[i].v[0];
    const State<double> x = top.to_state(y);
    const Mat3<double>& I = so3_top.inertia;
    const Vec3<double> rhs = I.inverse() * (Vec3<double>(I * x.Omega).cross(x.Omega) + so3_top.torque(x.R));
    EXPECT_LT((dOmega - rhs).norm(), 1e-13) << a.transpose();
  }
}

// Acceptance: the Euler-angle formulation and the SO(3) formulation agree to ≤ 1e-9 over a non-singular
// stretch (scenario B: sin θ ≥ 0.38 over t ∈ [0, 20]).
TEST(EulerAngleTop, AgreesWithSo3FormulationOverNonSingularStretch) {
  const EulerAngleTop<double> top = seed::paper_top();
  const seed::Scenario B = seed::scenario_b();
  Rkmk4<HeavyTop<double>> rkmk4(top.heavy_top());
  const Path so3 = seed::run_so3(rkmk4, B.x0, 1e-3, B.T, 10);
  double t_stop = 0;
  const Path angles = seed::run_angles<tableaus::classical_rk4>(top, top.from_state(B.x0), 0.0, 1e-3, B.T, 10, &t_stop);
  ASSERT_EQ(angles.size(), so3.size());
  EXPECT_EQ(t_stop, B.T);
  const seed::Deviation d = seed::deviation(angles, so3);
  std::printf("Euler angles vs SO(3), t in [0, 20]: max |dR| %.2e, max |dOmega| %.2e\n", d.R, d.Omega);
  EXPECT_LE(d.R, 1e-9);
  EXPECT_LE(d.Omega, 1e-9);
}

// m_ψ is a component with zero derivative: kept exactly. E and m_φ (s12)–(s13) with the consistent p̃_φ
// are conserved to the method's accuracy; with p̃_φ as printed in (s10) they are not (negative control:
// the same test fails by > 0.1 when I2 ≠ 1).
TEST(EulerAngleTop, IntegralsAndThePrintedDefinition) {
  const EulerAngleTop<double> top = seed::paper_top();
  ASSERT_NE(top.I2, 1.0);
  const Vector y0 = top.from_state(seed::scenario_b().x0);
  const Path p = seed::run_angles<tableaus::classical_rk4>(top, y0, 0.0, 1e-3, 20.0, 10);
  double dpsi = 0, dE = 0, dm = 0, dE_printed = 0, dm_printed = 0;
  for (const auto& s : p) {
    dpsi = std::max(dpsi, std::abs(s.y[5] - y0[5]));
    dE = std::max(dE, std::abs(top.energy_s12(s.y) - top.energy_s12(y0)));
    dm = std::max(dm, std::abs(top.m_phi(s.y) - top.m_phi(y0)));
    const double pp = top.p_tilde_phi_as_printed(s.y), pp0 = top.p_tilde_phi_as_printed(y0);
    dE_printed = std::max(dE_printed, std::abs(top.energy_s12(s.y, pp) - top.energy_s12(y0, pp0)));
    dm_printed = std::max(dm_printed, std::abs(top.m_phi(s.y, pp) - top.m_phi(y0, pp0)));
    // (s13) is the footnote's m·k = k·(R I Ω).
    EXPECT_LT(std::abs(top.m_phi(s.y) - top.heavy_top().invariants(s.x)[0]), 1e-14);
  }
  EXPECT_EQ(dpsi, 0.0);
  EXPECT_LT(dE, 1e-11);
  EXPECT_LT(dm, 1e-11);
  EXPECT_GT(dE_printed, 0.1);
  EXPECT_GT(dm_printed, 0.1);
}

// ---- the quadrature -------------------------------------------------------------------------------

// Acceptance: U(t), the azimuth χ(t), R(t), Ω(t) and the paper's angles from the quadrature agree with an
// accurate integration (RKMK4, h = 2.5e-4, error ≈ 1e-13) to ≤ 1e-10, in both scenarios.
TEST(LagrangeQuadrature, AgreesWithIntegration) {
  const EulerAngleTop<double> top = seed::paper_top();
  const HeavyTop<double> so3_top = top.heavy_top();
  for (const seed::Scenario& S : {seed::scenario_a(), seed::scenario_b()}) {
    const LagrangeTopQuadrature q = seed::quadrature(top, S.x0);
    const Mat3<double> Q = q.frame_of_k().cast<double>();
    EXPECT_LT((Q * so3_top.k - Vec3<double>::UnitZ()).norm(), 1e-15);
    Rkmk4<HeavyTop<double>> rkmk4(so3_top);
    const Path ref = seed::run_so3(rkmk4, S.x0, 2.5e-4, S.T, 40);
    double eU = 0, echi = 0, eR = 0, eW = 0;
    for (const auto& s : ref) {
      const State<double> xq = q.state(s.t);
      eU = std::max(eU, std::abs(q.U(s.t) - seed::U_of(so3_top.k, s.x)));
      echi = std::max(echi, std::abs(wrap_angle(q.chi(s.t) - seed::azimuth(Q, s.x))));
      eR = std::max(eR, (xq.R - s.x.R).norm());
      eW = std::max(eW, (xq.Omega - s.x.Omega).norm());
    }
    std::printf("scenario %s: max |dU| %.1e, |dchi| %.1e, |dR| %.1e, |dOmega| %.1e\n", S.name, eU, echi, eR, eW);
    EXPECT_LE(eU, 1e-10) << S.name;
    EXPECT_LE(echi, 1e-10) << S.name;
    EXPECT_LE(eR, 1e-10) << S.name;
    EXPECT_LE(eW, 1e-10) << S.name;
  }
  // The paper's angles (6.3), scenario B, against the Euler-angle integration.
  const seed::Scenario B = seed::scenario_b();
  const LagrangeTopQuadrature q = seed::quadrature(top, B.x0);
  const Path p = seed::run_angles<tableaus::classical_rk4>(top, top.from_state(B.x0), 0.0, 2.5e-4, B.T, 40);
  double e = 0;
  for (const auto& s : p) {
    const Vec3<double> a = euler_angles_from_rotation(q.state(s.t).R);
    e = std::max({e, std::abs(wrap_angle(a[0] - s.y[0])), std::abs(a[1] - s.y[1]), std::abs(wrap_angle(a[2] - s.y[2]))});
  }
  EXPECT_LE(e, 1e-10);
}

// The time between turning points of U, K(k)/λ, against the turning points located in the integration.
TEST(LagrangeQuadrature, NutationHalfPeriodMatchesTurningPoints) {
  const EulerAngleTop<double> top = seed::paper_top();
  for (const seed::Scenario& S : {seed::scenario_a(), seed::scenario_b()}) {
    const LagrangeTopQuadrature q = seed::quadrature(top, S.x0);
    const std::vector<double> tp = seed::turning_points(top.heavy_top(), S.x0, 1e-3, 20.0);
    ASSERT_GE(tp.size(), 5u);
    for (std::size_t i = 1; i < tp.size(); ++i) EXPECT_NEAR(tp[i] - tp[i - 1], q.nutation_half_period(), 1e-10);
    // and U is at a root there
    EXPECT_NEAR(std::min(std::abs(q.U(tp[2]) - q.u1()), std::abs(q.U(tp[2]) - q.u2())), 0.0, 1e-12);
  }
}

TEST(LagrangeQuadrature, RejectsTheExcludedCases) {
  const State<double> x0{rotation_from_euler_angles(0.5, 1.2, 0.0), Vec3<double>(0.3, -0.2, 4.0)};
  EXPECT_THROW(LagrangeTopQuadrature(2, 1, 0, Vec3<double>(0, 0.6, 0.8), x0), std::domain_error);  // b = 0
  // m_φ = m_ψ: D(1) = 0, the axis passes through k (the "awakened" top).
  const State<double> awake{Mat3<double>::Identity(), Vec3<double>(0.5, 0.5, 3.0)};
  EXPECT_THROW(LagrangeTopQuadrature(2, 1, 1, Vec3<double>(0, 0.6, 0.8), awake), std::domain_error);
}

// ---- the Euclidean Runge–Kutta methods ---------------------------------------------------------------

// Error at T = 5 against the quadrature (independent of any integrator) over a step-halving sequence.
template <const auto& Tableau>
double observed_order_on_lagrange_top(int n0) {
  const EulerAngleTop<double> top = seed::paper_top();
  const seed::Scenario B = seed::scenario_b();
  const State<double> exact = seed::quadrature(top, B.x0).state(5.0);
  std::vector<double> hs, errors;
  for (int n = n0; n <= 16 * n0; n *= 2) {
    const Path p = seed::run_angles<Tableau>(top, top.from_state(B.x0), 0.0, 5.0 / n, 5.0, n);
    hs.push_back(5.0 / n);
    errors.push_back((p.back().x.R - exact.R).norm() + (p.back().x.Omega - exact.Omega).norm());
    EXPECT_GT(errors.back(), 1e-12) << Tableau.name << ": below the quadrature's accuracy";
  }
  const double order = test::fitted_order(hs, errors);
  std::printf("%s on the Euler angles: observed order %.3f (declared %d), errors %.2e .. %.2e\n", Tableau.name.data(),
              order, Tableau.order, errors.front(), errors.back());
  return order;
}

TEST(EuclideanRk, ObservedOrderOnTheLagrangeTopInEulerAngles) {
  EXPECT_NEAR(observed_order_on_lagrange_top<tableaus::euler>(2000), 1, 0.2);
  EXPECT_NEAR(observed_order_on_lagrange_top<tableaus::heun>(200), 2, 0.2);
  EXPECT_NEAR(observed_order_on_lagrange_top<tableaus::kutta3>(100), 3, 0.2);
  EXPECT_NEAR(observed_order_on_lagrange_top<tableaus::classical_rk4>(50), 4, 0.2);
  EXPECT_NEAR(observed_order_on_lagrange_top<tableaus::rule38>(50), 4, 0.2);
  EXPECT_NEAR(observed_order_on_lagrange_top<tableaus::dormand_prince5>(25), 5, 0.2);
}

// The same methods on the 12-dimensional embedding (R's nine entries and Ω) of the free body and of the
// skew heavy top (non-diagonal J, k and z0 off the axes), against the long-double reference.
template <RigidBodyProblem P>
struct Embedding {
  using Scalar = double;
  using Vector = Eigen::Matrix<double, 12, 1>;
  P p;
  Mat3<double> J, J_inv;
  explicit Embedding(const P& problem) : p(problem), J(problem.inertia), J_inv(problem.inertia.inverse()) {}
  static Vector pack(const State<double>& x) {
    Vector y;
    for (int i = 0; i < 9; ++i) y[i] = x.R(i / 3, i % 3);
    y.tail<3>() = x.Omega;
    return y;
  }
  static State<double> unpack(const Vector& y) {
    State<double> x;
    for (int i = 0; i < 9; ++i) x.R(i / 3, i % 3) = y[i];
    x.Omega = y.tail<3>();
    return x;
  }
  Vector derivative(double t, const Vector& y) const {
    const State<double> x = unpack(y);
    const Mat3<double> dR = x.R * so3::hat(x.Omega);
    const Vec3<double> dW = J_inv * (Vec3<double>(J * x.Omega).cross(x.Omega) + body_torque(p, t, x.R));
    return pack({dR, dW});
  }
};

template <const auto& Tableau, class P>
double observed_order_on_embedding(const P& problem, const State<double>& x0, int n0) {
  const double T = 2.0;
  const State<double> ref = test::reference_solution(problem, x0, T, 40000);
  const Embedding<P> system(problem);
  const EuclideanRk<Tableau, Embedding<P>> stepper(system);
  std::vector<double> hs, errors;
  for (int n = n0; n <= 16 * n0; n *= 2) {
    auto y = Embedding<P>::pack(x0);
    for (int i = 0; i < n; ++i) EXPECT_EQ(stepper.step(y, i * T / n, T / n), StepStatus::ok);
    const State<double> x = Embedding<P>::unpack(y);
    hs.push_back(T / n);
    errors.push_back((x.R - ref.R).norm() + (x.Omega - ref.Omega).norm());
  }
  return test::fitted_order(hs, errors);
}

TEST(EuclideanRk, ObservedOrderOnTheEmbeddedFreeBodyAndSkewHeavyTop) {
  const auto top = test::skew_heavy_top();
  const auto body = FreeBody<double>::hairer_vilmart();
  const State<double> x0 = test::skew_initial_state();
  const double o1 = observed_order_on_embedding<tableaus::classical_rk4>(top, x0, 20);
  const double o2 = observed_order_on_embedding<tableaus::classical_rk4>(body, test::hairer_vilmart_state(body), 20);
  const double o3 = observed_order_on_embedding<tableaus::dormand_prince5>(top, x0, 10);
  const double o4 = observed_order_on_embedding<tableaus::dormand_prince5>(body, test::hairer_vilmart_state(body), 10);
  std::printf("embedding: RK4 %.3f (skew top), %.3f (free body); DP5 %.3f, %.3f\n", o1, o2, o3, o4);
  EXPECT_NEAR(o1, 4, 0.2);
  EXPECT_NEAR(o2, 4, 0.2);
  EXPECT_NEAR(o3, 5, 0.2);
  EXPECT_NEAR(o4, 5, 0.2);
}

// Jets through the method: derivatives of the Euler-angle state after 200 steps with respect to θ0, φ'0
// and b, carried by ceres::Jet, against central differences.
TEST(EuclideanRk, JetDerivativesMatchFiniteDifferences) {
  using Jet = ceres::Jet<double, 3>;
  const EulerAngleTop<double> top = seed::paper_top();
  const Vector y0 = top.from_state(seed::scenario_b().x0);
  const double h = 0.01;
  const auto run = [&](double dtheta, double ddphi, double db) {
    EulerAngleTop<double> t2 = top;
    t2.b += db;
    Vector y = y0;
    y[1] += dtheta;
    y[3] += ddphi;
    const EuclideanRk<tableaus::classical_rk4, EulerAngleTop<double>> st(t2);
    for (int i = 0; i < 200; ++i) st.step(y, i * h, h);
    return y;
  };
  EulerAngleTop<Jet> topj = top.cast<Jet>();
  topj.b.v[2] = 1;
  Eigen::Matrix<Jet, 8, 1> y = y0.cast<Jet>();
  y[1].v[0] = 1;
  y[3].v[1] = 1;
  const EuclideanRk<tableaus::classical_rk4, EulerAngleTop<Jet>> stj(topj);
  for (int i = 0; i < 200; ++i) ASSERT_EQ(stj.step(y, Jet(i * h), Jet(h)), StepStatus::ok);
  const Vector base = run(0, 0, 0);
  const double d = 1e-6;
  const Vector fd[3] = {(run(d, 0, 0) - run(-d, 0, 0)) / (2 * d), (run(0, d, 0) - run(0, -d, 0)) / (2 * d),
                        (run(0, 0, d) - run(0, 0, -d)) / (2 * d)};
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(y[i].a, base[i], 1e-14);
    for (int j = 0; j < 3; ++j)
      EXPECT_NEAR(y[i].v[j], fd[j][i], 1e-6 * (1 + std::abs(fd[j][i]))) << "component " << i << ", parameter " << j;
  }
}

// Scenario A from t = 1: the symmetry axis comes back near e3 (sin θ = 0.0086 near t = 29). The driver
// stops once sin θ < min_sin_theta, keeping the last admissible state; with the check off it runs through.
TEST(EuclideanRk, DriverStopsNearTheCoordinateSingularity) {
  EulerAngleTop<double> top = seed::paper_top();
  const seed::Scenario A = seed::scenario_a();
  Rkmk4<HeavyTop<double>> rkmk4(top.heavy_top());
  State<double> x = A.x0;
  for (int i = 0; i < 1000; ++i) rkmk4.step(x, i * 1e-3, 1e-3);
  const Vector y1 = top.from_state(x);
  const EuclideanRk<tableaus::classical_rk4, EulerAngleTop<double>> stepper(top);
  Vector y = y1;
  std::vector<double> seen;
  const double times[] = {10.0, 40.0, 59.0};
  const EuclideanSummary s = integrate_times_euclidean(stepper, y, 1.0, 1e-3, std::span<const double>(times),
                                                       [&](double t, const Vector&) { seen.push_back(t); });
  EXPECT_EQ(s.status, RunStatus::stopped);
  EXPECT_TRUE(s.left_domain);
  EXPECT_NEAR(s.t, 28.996, 0.01);
  EXPECT_NEAR(s.t_outside, s.t + 1e-3, 1e-9);
  EXPECT_GE(std::sin(y[1]), top.min_sin_theta);
  EXPECT_EQ(seen, (std::vector<double>{1.0, 10.0}));

  top.min_sin_theta = 0;
  const EuclideanRk<tableaus::classical_rk4, EulerAngleTop<double>> through(top);
  y = y1;
  const EuclideanSummary s2 = integrate_every_euclidean(through, y, 1.0, 1e-3, 59.0, 1000);
  EXPECT_EQ(s2.status, RunStatus::completed);
  EXPECT_EQ(s2.t, 59.0);
}

// ---- the reproduction's report ----------------------------------------------------------------------

std::filesystem::path source_dir() { return std::filesystem::path(__FILE__).parent_path().parent_path().parent_path(); }  // tests/problems/ → the root

// Every table of docs/seed_paper.md between <!-- table:NAME --> markers is exactly what the program
// computes now (scripts/seed_report.sh regenerates them).
TEST(SeedReport, TablesAreThoseTheProgramComputes) {
  std::ifstream in(source_dir() / "docs" / "seed_paper.md");
  ASSERT_TRUE(in) << "docs/seed_paper.md missing";
  std::stringstream buf;
  buf << in.rdbuf();
  const std::string doc = buf.str();
  const seed::Output out = seed::compute();
  ASSERT_GE(out.tables.size(), 8u);
  for (const seed::Table& t : out.tables) {
    const std::string b = seed::block(t);
    EXPECT_NE(doc.find(b), std::string::npos)
        << "docs/seed_paper.md does not carry the current table " << t.name << " (run scripts/seed_report.sh):\n" << b;
  }
}

// ---- `lgi run` on the Euler-angle problem ------------------------------------------------------------

// The lgi binary sits in the build directory above this test's (tests/); a test that needs it fails when it is missing.
std::filesystem::path lgi_binary() {
  char self[4096];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  if (n <= 0) return {};
  self[n] = 0;
  return std::filesystem::path(self).parent_path().parent_path() / "lgi";
}

struct LgiRun {
  int status;
  std::string out, err;
};
LgiRun run_lgi(const std::string& scene_text) {
  const auto dir = std::filesystem::temp_directory_path() / ("lgi_seed_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  { std::ofstream(dir / "scene.json") << scene_text; }
  const std::string cmd = lgi_binary().string() + " run " + (dir / "scene.json").string() + " > " +
                          (dir / "out.csv").string() + " 2> " + (dir / "err.txt").string();
  const int raw = std::system(cmd.c_str());
  const auto slurp = [](const std::filesystem::path& p) {
    std::ifstream f(p);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
  };
  LgiRun r{WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, slurp(dir / "out.csv"), slurp(dir / "err.txt")};
  std::filesystem::remove_all(dir);
  return r;
}

std::vector<std::vector<double>> csv_rows(const std::string& text, std::vector<std::string>* header) {
  std::istringstream in(text);
  std::string line;
  std::vector<std::vector<double>> rows;
  bool first = true;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string cell;
    std::vector<double> row;
    while (std::getline(ls, cell, ',')) {
      if (first)
        header->push_back(cell);
      else
        row.push_back(std::stod(cell));
    }
    if (!first) rows.push_back(row);
    first = false;
  }
  return rows;
}

const char* kEulerScene = R"({
  "problem": {"type": "lagrange_top_euler_angles", "I2": 2, "I3": 1, "b": 1, "k2": 0.6, "k3": 0.8},
  "initial": {"euler_angles": [0.5, 1.2, 0.0], "euler_rates": [%RATES%]},
  "integrator": {"method": "rkmk4", "dt": 0.001},
  "t_end": 20,
  "output": {"times": [5, 10.0005, 20]}
})";

// s with its one occurrence of `from` replaced by `to`.
std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const std::size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

std::string euler_scene(const std::string& rates) { return replaced(kEulerScene, "%RATES%", rates); }

TEST(SeedScene, EulerAngleSceneRunsAndMatchesTheHeavyTopScene) {
  ASSERT_TRUE(std::filesystem::exists(lgi_binary())) << lgi_binary() << " not built (build the lgi_exe target)";
  // Rates of scenario B's Ω0 = (0.3, −0.2, 4.0): from_state of its state.
  const EulerAngleTop<double> top = seed::paper_top();
  const Vector y = top.from_state(seed::scenario_b().x0);
  char rates[128];
  std::snprintf(rates, sizeof rates, "%.17g, %.17g, %.17g", y[3], y[4], y[5] / top.I3 - y[3] * std::cos(y[1]));
  const LgiRun a = run_lgi(euler_scene(rates));
  ASSERT_EQ(a.status, 0) << a.err;
  const std::string so3 = replaced(euler_scene(rates),
                                   R"("type": "lagrange_top_euler_angles", "I2": 2, "I3": 1, "b": 1, "k2": 0.6, "k3": 0.8)",
                                   R"("type": "heavy_top", "inertia": [2, 2, 1], "b": 1, "k": [0, 0.6, 0.8])");
  const LgiRun b = run_lgi(so3);
  ASSERT_EQ(b.status, 0) << b.err;
  std::vector<std::string> ha, hb;
  const auto ra = csv_rows(a.out, &ha), rb = csv_rows(b.out, &hb);
  ASSERT_EQ(ra.size(), 4u);
  ASSERT_EQ(rb.size(), 4u);
  // The standard columns come first and in the same order; then m_φ under the heavy top's name.
  for (std::size_t c = 0; c < hb.size(); ++c) EXPECT_EQ(ha[c], hb[c]);
  EXPECT_EQ(std::vector<std::string>(ha.begin() + 16, ha.end()),
            (std::vector<std::string>{"momentum_psi", "sin_theta", "phi", "theta", "psi"}));
  for (std::size_t r = 0; r < 4; ++r) {
    EXPECT_EQ(ra[r][0], rb[r][0]);
    for (std::size_t c = 1; c < 14; ++c) EXPECT_NEAR(ra[r][c], rb[r][c], 1e-9) << ha[c] << " at t = " << ra[r][0];
    EXPECT_NEAR(ra[r][13], rb[r][13], 1e-11);  // energy
    EXPECT_NEAR(ra[r][15], rb[r][15], 1e-11);  // momentum_k
    EXPECT_LT(ra[r][14], 1e-15);              // R from (6.3): orthogonal to round-off
  }
  EXPECT_NE(a.err.find("Runge-Kutta on the Euler angles"), std::string::npos) << a.err;
}

TEST(SeedScene, SingularityStopsTheRunWithAWarning) {
  ASSERT_TRUE(std::filesystem::exists(lgi_binary())) << lgi_binary() << " not built (build the lgi_exe target)";
  const std::string s = replaced(euler_scene("0.1, 0.2, 5.0"), "[0.5, 1.2, 0.0]", "[0.5, 0.001, 0.0]");  // sin θ0 < 0.05
  const LgiRun r = run_lgi(s);
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("coordinate singularity"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("at t = 0"), std::string::npos) << r.err;
}

TEST(SeedScene, OptionsTheEuclideanPathDoesNotHaveAreRejected) {
  ASSERT_TRUE(std::filesystem::exists(lgi_binary())) << lgi_binary() << " not built (build the lgi_exe target)";
  const std::string s = replaced(euler_scene("0.3, -0.2, 4.0"), R"("dt": 0.001)", R"("dt": 0.001, "projection": true)");
  const LgiRun r = run_lgi(s);
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("/integrator"), std::string::npos) << r.err;
  const std::string s2 = replaced(euler_scene("0.3, -0.2, 4.0"), R"("method": "rkmk4")", R"("method": "lgvi")");
  const LgiRun r2 = run_lgi(s2);
  EXPECT_EQ(r2.status, 1) << r2.err;
  EXPECT_NE(r2.err.find("does not apply"), std::string::npos) << r2.err;
}

}  // namespace
}  // namespace lgi
