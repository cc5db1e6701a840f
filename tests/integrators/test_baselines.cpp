// The embedding baselines, measured: observed order of RK4 and DOP853 on the quaternion and on the nine
// entries of R, with and without renormalisation; how far each leaves SO(3); energy drift; Jets; the
// quaternion and polar-factor maps; adaptive DOP853 on the embedding.
#include "jet_check.hpp"
#include "order_measure.hpp"
#include "test_problems.hpp"

#include <lgi/core/driver.hpp>
#include <lgi/core/invariants.hpp>
#include <lgi/integrators/adaptive.hpp>
#include <lgi/integrators/embedding.hpp>
#include <lgi/problems/free_body.hpp>
#include <lgi/problems/heavy_top.hpp>

#include <Eigen/SVD>
#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <limits>

#include <cmath>
#include <cstdio>
#include <span>
#include <vector>

namespace lgi {
namespace {

using namespace lgi::test;

static_assert(Stepper<Rk4Quat<HeavyTop<double>>> && Stepper<Dop853MatRenorm<FreeBody<double>>>);
static_assert(AdaptiveStepper<Dop853Quat<HeavyTop<double>>> && !AdaptiveStepper<Rk4Mat<HeavyTop<double>>>);

template <template <class> class M>
struct MethodTag {
  template <class P>
  using type = M<P>;
};

template <class Tag>
class Baseline : public ::testing::Test {};
using Baselines = ::testing::Types<MethodTag<Rk4Quat>, MethodTag<Rk4QuatRenorm>, MethodTag<Rk4Mat>,
                                   MethodTag<Rk4MatRenorm>, MethodTag<Dop853Quat>, MethodTag<Dop853QuatRenorm>,
                                   MethodTag<Dop853Mat>, MethodTag<Dop853MatRenorm>>;
TYPED_TEST_SUITE(Baseline, Baselines);

TYPED_TEST(Baseline, ObservedOrderOnTheSkewHeavyTop) {
  const double p = observed_order<TypeParam::template type>(skew_top(), test::skew_initial_state(), 2.0,
                                                            skew_reference(), "skew top");
  EXPECT_NEAR(p, (TypeParam::template type<HeavyTop<double>>::traits.order), 0.2);
}

TYPED_TEST(Baseline, ObservedOrderOnTheFreeBody) {
  const double p = observed_order<TypeParam::template type>(gni_body(), gni_state(), 10.0, gni_reference(), "free body");
  EXPECT_NEAR(p, (TypeParam::template type<FreeBody<double>>::traits.order), 0.2);
}

// How far from SO(3) after 10⁵ steps of h = 0.05 on the HV heavy top: the renormalised variants stay at
// round-off (≤ 1e-13), the others drift off by their accumulated truncation error (RK4 measurably).
TYPED_TEST(Baseline, DistanceFromSO3) {
  using S = typename TypeParam::template type<HeavyTop<double>>;
  static_assert(!S::traits.exact_on_group);
  const auto top = HeavyTop<double>::hairer_vilmart();
  S stepper(top);
  State<double> x = test::hairer_vilmart_state(top);
  double worst = 0;
  integrate_every(stepper, x, 0.0, 0.05, 5000.0, 1000,
                  [&](double, const State<double>& xt) { worst = std::max(worst, so3::orthogonality_error(xt.R)); });
  std::printf("%-18s 1e5 steps h = 0.05: max |RtR - I| %.3e\n", S::traits.name.data(), worst);
  const bool renormalised = S::traits.name.ends_with("_renorm");
  if (renormalised) {
    EXPECT_LE(worst, 1e-13);
  } else if (S::traits.order == 4) {
    EXPECT_GT(worst, 1e-8);  // RK4 leaves the group by its truncation error
  }
}

// Not symplectic: the energy drifts (HV top, h = 0.05, 2·10⁵ steps; the mean-shift measure of
// test_rkmk_family.cpp, which reads ≈ 0 for the LGVI there).
TYPED_TEST(Baseline, EnergyDrifts) {
  using S = typename TypeParam::template type<HeavyTop<double>>;
  const auto top = HeavyTop<double>::hairer_vilmart();
  S stepper(top);
  State<double> x = test::hairer_vilmart_state(top);
  const double E0 = energy(top, x);
  std::vector<double> err;
  integrate_every(stepper, x, 0.0, 0.05, 10000.0, 200,
                  [&](double, const State<double>& xt) { err.push_back((energy(top, xt) - E0) / std::abs(E0)); });
  const std::size_t n = err.size(), tenth = n / 10;
  double first = 0, last = 0, largest = 0;
  for (std::size_t i = 0; i < tenth; ++i) {
    first += err[i];
    last += err[n - tenth + i];
  }
  for (const double e : err) largest = std::max(largest, std::abs(e));
  const double shift = std::abs(last - first) / static_cast<double>(tenth) / largest;
  std::printf("%-18s h = 0.05, 2e5 steps: final rel. energy error %.3e, mean shift %.3f\n", S::traits.name.data(),
              err.back(), shift);
  EXPECT_GT(shift, 0.5);
}

TYPED_TEST(Baseline, JetDerivativesMatchFiniteDifferences) {
  test::expect_heavy_top_jets_match<TypeParam::template type>(/*h=*/0.02, /*T=*/1.0, /*value_tol=*/3e-15);
}

TEST(EmbeddingMaps, QuaternionRoundTrip) {
  for (const Vec3<double>& w : {Vec3<double>(0.3, -0.2, 0.1), Vec3<double>(3.0, 0.1, -0.2), Vec3<double>(0.1, -3.1, 0.2),
                                Vec3<double>(0.0, 0.2, 3.1), Vec3<double>(0.0, 0.0, 0.0)}) {
    const Mat3<double> R = so3::exp(w);
    const Eigen::Vector4d q = embedding::quaternion_of(R);
    EXPECT_NEAR(q.norm(), 1.0, 1e-15);
    EXPECT_GE(q(0), 0.0);
    EXPECT_LT((embedding::rotation_of(q) - R).cwiseAbs().maxCoeff(), 1e-15) << w.transpose();
    const Vec3<double> a(0.3, -0.7, 0.2);
    EXPECT_LT((embedding::rotate_back(q, a) - R.transpose() * a).norm(), 1e-15);
  }
}

// The Newton–Schulz polar factor equals the SVD polar factor U Vᵀ to a few ulps (both carry round-off),
// and is orthogonal to round-off. Another orthogonalisation — Gram–Schmidt on the columns — differs from the
// polar factor by O(the perturbation): the comparison can tell them apart.
TEST(EmbeddingMaps, NearestRotationIsThePolarFactor) {
  const Mat3<double> R = so3::exp(Vec3<double>(0.4, -1.2, 2.0));
  Mat3<double> E;
  E << 1, -2, 0.5, 0.3, 0.1, -1, 2, 0.7, -0.4;
  for (const double size : {1e-12, 1e-8, 1e-4, 1e-2}) {
    const Mat3<double> X = R + size * E;
    const Eigen::JacobiSVD<Mat3<double>> svd(X, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Mat3<double> polar = svd.matrixU() * svd.matrixV().transpose();
    const Mat3<double> Y = embedding::nearest_rotation(X);
    EXPECT_LT((Y - polar).cwiseAbs().maxCoeff(), 2e-15) << size;
    EXPECT_LT(so3::orthogonality_error(Y), 1e-15) << size;
    Mat3<double> G = X;  // Gram–Schmidt
    G.col(0).normalize();
    G.col(1) = (G.col(1) - G.col(0).dot(G.col(1)) * G.col(0)).normalized();
    G.col(2) = G.col(0).cross(G.col(1));
    if (size >= 1e-8) {
      EXPECT_GT((G - polar).cwiseAbs().maxCoeff(), 0.1 * size) << size;
    }
  }
}

// DOP853 on the embedding, adaptive: meets the tolerance over T = 2 (≤ 10× tol) like the RKMK pair.
// Past the polar factor's reach (max |XᵀX − I| ≥ 1) there is no rotation to return: polar_factor says so
// and leaves X alone, and a renormalised step fails instead of reporting ok with a matrix off the group.
TEST(EmbeddingMaps, PolarFactorRefusesMatricesFarFromSO3) {
  const Mat3<double> R = so3::exp(Vec3<double>(0.4, -1.2, 2.0));
  for (const double scale : {1.5, 3.0}) {  // XᵀX − I = (scale² − 1) I
    Mat3<double> X = scale * R;
    EXPECT_FALSE(embedding::polar_factor(X)) << scale;
    EXPECT_EQ(X, scale * R) << scale;
  }
  Mat3<double> X = 1.2 * R;  // inside: XᵀX − I = 0.44 I
  EXPECT_TRUE(embedding::polar_factor(X));
  EXPECT_LT((X - R).cwiseAbs().maxCoeff(), 1e-15);
}

// rk4_mat_renorm on the free body at h|Ω| from 0.5 to 4: every step either fails (not_converged /
// non_finite, state untouched) or leaves R orthogonal to round-off. Before the fix, h|Ω| = π returned
// ok with |RᵀR − I| = 5.5e74 (scripts/stability_map.py).
TEST(EmbeddingMaps, RenormalisedMatrixStepNeverReturnsAnOffGroupMatrix) {
  const FreeBody<double> body = gni_body();
  const State<double> x0 = gni_state();
  int failed = 0;
  for (const double hw : {0.5, 1.0, 2.0, 3.14159, 4.0}) {
    const double h = hw / x0.Omega.norm();
    Rk4MatRenorm<FreeBody<double>> stepper(body);
    auto y = stepper.to_internal(x0, 0.0);
    for (int n = 0; n < 200; ++n) {
      const auto before = y;
      const StepStatus s = stepper.step(y, n * h, h);
      if (s != StepStatus::ok) {
        EXPECT_EQ(y.R, before.R) << hw;
        ++failed;
        break;
      }
      ASSERT_LT(so3::orthogonality_error(y.R), 1e-12) << "h|Omega| = " << hw << ", step " << n;
    }
  }
  EXPECT_GE(failed, 1);  // the largest steps do fail
}

TEST(EmbeddingAdaptive, Dop853MeetsTheTolerance) {
  const State<double> x0 = test::skew_initial_state();
  const Reference ref = make_reference(skew_top(), x0, 2.0);
  for (const double tol : {1e-4, 1e-6, 1e-8, 1e-10, 1e-12}) {
    StepperOptions o;
    o.rtol = tol;
    o.atol = tol;
    for (const bool quaternion : {true, false}) {
      State<double> x = x0;
      const double times[] = {2.0};
      AdaptiveSummary s;
      if (quaternion) {
        Dop853QuatRenorm<HeavyTop<double>> stepper(skew_top(), o);
        s = integrate_adaptive(stepper, x, 0.0, 0.01, std::span<const double>(times));
      } else {
        Dop853MatRenorm<HeavyTop<double>> stepper(skew_top(), o);
        s = integrate_adaptive(stepper, x, 0.0, 0.01, std::span<const double>(times));
      }
      const double error = distance(x.cast<L>(), ref.x);
      std::printf("%s tol %.0e: %lld steps, error %.2e (%.2f tol)\n",
                  quaternion ? "dop853_quat_renorm" : "dop853_mat_renorm ", tol, static_cast<long long>(s.accepted),
                  error, error / tol);
      EXPECT_EQ(s.status, RunStatus::completed);
      EXPECT_LE(error, 10 * tol);
    }
  }
}

}  // namespace
}  // namespace lgi
