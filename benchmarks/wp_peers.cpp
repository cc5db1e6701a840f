// benchmarks/wp_peers.cpp — the peer libraries on the same right-hand side: Boost.Odeint (header-only,
// libboost-dev), GSL odeiv2 (libgsl-dev) and SUNDIALS CVODE / ARKODE (libsundials-dev), the last two when
// CMake found them (LGI_BENCH_GSL, LGI_BENCH_SUNDIALS).
//
// State y = (q, Π) ∈ R⁷: q = (s, v) the unit quaternion of R (not renormalised: that is the peers' own
// error), Π = JΩ the body momentum. With Ω = J⁻¹Π (diagonal J: three products) and Γ = R(q)ᵀk =
// k − 2s v×k + 2 v×(v×k) (exact for |q| = 1),
//     s' = −½ v·Ω,   v' = ½ (sΩ + v×Ω),   Π' = Π × Ω + b Γ × z0           (b = 0: no torque term).
// About 60 flops with a torque, 35 without, written as scalar code (the form a competent user writes: no small-vector
// temporaries; an Eigen Vec3 form of the same equations compiled to shuffles and unaligned loads and cost about twice
// as much a call, measured in the issue that asked for this). peer_rhs_cost() times it for the suite's report. GSL's implicit
// rk4imp also gets the exact Jacobian (jacobian() below, checked against central differences by the smoke
// run's --check-jacobian).
//
// Fair rules (work_precision.cpp times them): solver objects are allocated when the trial is made; reset()
// (copy of the initial state, GSL driver reset, SUNDIALS ReInit) is outside the timed run(); adaptive
// peers get rtol = atol = tol and the same first step as lgi's adaptive methods (CVODE and ARKODE choose
// their own), and land exactly on each output time (odeint integrate_times, GSL driver_apply, SUNDIALS
// stop time at the last output time and interpolation before it). Fixed-step peers (param = N steps over [0, T],
// h = T/N) are the libraries' own fixed-step paths: odeint's plain steppers through integrate_times (steps of h,
// the last one before each output time shortened to land on it; runge_kutta_fehlberg78's do_step forms no error
// estimate) and GSL's stepper alone, gsl_odeiv2_step_apply (each output interval in ⌈length/h⌉ equal steps; it
// still forms its error estimate, as GSL's steppers always do).
#include "wp_common.hpp"

#include <boost/numeric/odeint.hpp>
#include <boost/version.hpp>

#include <Eigen/Geometry>

#include <array>
#include <ctime>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#ifdef LGI_BENCH_GSL
#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>
#include <gsl/gsl_version.h>
#endif
#ifdef LGI_BENCH_SUNDIALS
#include <arkode/arkode_erkstep.h>
#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_config.h>
#include <sundials/sundials_context.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>
#endif

namespace wp {
namespace {

using Y = std::array<double, 7>;

struct Rhs {
  bool diagonal = true, torque = false;
  Vec3 Jd, Jid;  // diagonal J and J⁻¹
  Mat3 J, Ji;
  double b = 0;
  Vec3 k, z0;
  // The same as plain scalars for operator(): J⁻¹ row by row (diagonal: its diagonal), b k and z0.
  double i00, i01, i02, i10, i11, i12, i20, i21, i22;
  double k1, k2, k3, z1, z2, z3;

  explicit Rhs(const Body& body)
      : diagonal(body.J.isDiagonal(0.0)), torque(body.torque()), Jd(body.J.diagonal()), Jid(Jd.cwiseInverse()),
        J(body.J), Ji(body.J.inverse()), b(body.b), k(body.k), z0(body.z0) {
    const Mat3 A = diagonal ? Mat3(Jid.asDiagonal()) : Ji;
    i00 = A(0, 0), i01 = A(0, 1), i02 = A(0, 2), i10 = A(1, 0), i11 = A(1, 1), i12 = A(1, 2), i20 = A(2, 0),
    i21 = A(2, 1), i22 = A(2, 2);
    k1 = k.x(), k2 = k.y(), k3 = k.z(), z1 = z0.x(), z2 = z0.y(), z3 = z0.z();
  }

  Vec3 omega(const double* y) const {
    const Vec3 Pi(y[4], y[5], y[6]);
    return diagonal ? Vec3(Jid.cwiseProduct(Pi)) : Vec3(Ji * Pi);
  }

  void operator()(const double* y, double* d) const {
    const double s = y[0], v1 = y[1], v2 = y[2], v3 = y[3], p1 = y[4], p2 = y[5], p3 = y[6];
    double w1, w2, w3;  // Ω = J⁻¹Π
    if (diagonal) {
      w1 = i00 * p1, w2 = i11 * p2, w3 = i22 * p3;
    } else {
      w1 = i00 * p1 + i01 * p2 + i02 * p3;
      w2 = i10 * p1 + i11 * p2 + i12 * p3;
      w3 = i20 * p1 + i21 * p2 + i22 * p3;
    }
    d[0] = -0.5 * (v1 * w1 + v2 * w2 + v3 * w3);
    d[1] = 0.5 * (s * w1 + (v2 * w3 - v3 * w2));
    d[2] = 0.5 * (s * w2 + (v3 * w1 - v1 * w3));
    d[3] = 0.5 * (s * w3 + (v1 * w2 - v2 * w1));
    double e1 = p2 * w3 - p3 * w2, e2 = p3 * w1 - p1 * w3, e3 = p1 * w2 - p2 * w1;  // Π × Ω
    if (torque) {
      const double a1 = v2 * k3 - v3 * k2, a2 = v3 * k1 - v1 * k3, a3 = v1 * k2 - v2 * k1;  // v × k
      // Γ = k − 2s (v × k) + 2 v × (v × k)
      const double g1 = k1 - 2 * s * a1 + 2 * (v2 * a3 - v3 * a2);
      const double g2 = k2 - 2 * s * a2 + 2 * (v3 * a1 - v1 * a3);
      const double g3 = k3 - 2 * s * a3 + 2 * (v1 * a2 - v2 * a1);
      e1 += b * (g2 * z3 - g3 * z2);
      e2 += b * (g3 * z1 - g1 * z3);
      e3 += b * (g1 * z2 - g2 * z1);
    }
    d[4] = e1, d[5] = e2, d[6] = e3;
  }
  void operator()(const Y& y, Y& d, double /*t*/) const { (*this)(y.data(), d.data()); }

  // ∂f/∂y, row-major 7×7. With Ω = J⁻¹Π:
  //   ∂s'/∂s = 0, ∂s'/∂v = −½Ωᵀ, ∂v'/∂s = ½Ω, ∂v'/∂v = −½ hat(Ω), ∂(s', v')/∂Π = ½ [−vᵀ; sI + hat(v)] J⁻¹,
  //   ∂Π'/∂Π = hat(Π) J⁻¹ − hat(Ω), ∂Π'/∂s = −b hat(z0) (−2 v×k), ∂Π'/∂v = −b hat(z0) (2s hat(k) − 2 hat(v×k) − 2 hat(v) hat(k)).
  void jacobian(const double* y, double* A) const {
    const auto hat = [](const Vec3& a) {
      Mat3 m;
      m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
      return m;
    };
    const double s = y[0];
    const Vec3 v(y[1], y[2], y[3]), Pi(y[4], y[5], y[6]);
    const Vec3 W = omega(y);
    const Mat3 Jinv = diagonal ? Mat3(Jid.asDiagonal()) : Ji;
    Eigen::Matrix<double, 7, 7, Eigen::RowMajor> M = Eigen::Matrix<double, 7, 7, Eigen::RowMajor>::Zero();
    M.block<1, 3>(0, 1) = -0.5 * W.transpose();
    M.block<3, 1>(1, 0) = 0.5 * W;
    M.block<3, 3>(1, 1) = -0.5 * hat(W);
    Eigen::Matrix<double, 4, 3> dq_dW;
    dq_dW.row(0) = -0.5 * v.transpose();
    dq_dW.bottomRows<3>() = 0.5 * (s * Mat3::Identity() + hat(v));
    M.block<4, 3>(0, 4) = dq_dW * Jinv;
    M.block<3, 3>(4, 4) = hat(Pi) * Jinv - hat(W);
    if (torque) {
      const Mat3 Z = -b * hat(z0);
      const Vec3 vk = v.cross(k);
      M.block<3, 1>(4, 0) = Z * (-2 * vk);
      M.block<3, 3>(4, 1) = Z * (2 * s * hat(k) - 2 * hat(vk) - 2 * hat(v) * hat(k));
    }
    Eigen::Map<Eigen::Matrix<double, 7, 7, Eigen::RowMajor>> out(A);
    out = M;
  }
};

Y initial_y(const Case& c) {
  const Eigen::Quaterniond q(c.x0.R);
  const Vec3 Pi = c.body.J * c.x0.Omega;
  return {q.w(), q.x(), q.y(), q.z(), Pi.x(), Pi.y(), Pi.z()};
}

// The sample of a peer's state: R from q normalised; orthogonality of R(q) with q as it is.
Sample sample_of(const Rhs& f, double t, const double* y) {
  const Eigen::Quaterniond q(y[0], y[1], y[2], y[3]);
  const double n2 = q.squaredNorm();
  Sample s;
  s.t = t;
  s.x.R = q.normalized().toRotationMatrix();
  s.x.Omega = f.omega(y);
  s.orthogonality = std::sqrt(3.0) * std::abs(n2 * n2 - 1);  // R(q)ᵀR(q) = |q|⁴ I
  return s;
}

// ---- Boost.Odeint --------------------------------------------------------------------------------------
namespace odeint = boost::numeric::odeint;

enum class OdeintKind { rkf78, dopri5, dopri5_dense, bulirsch_stoer, rk4, rkf78_fixed };

// The steppers are members, built with the trial (outside the timing) and passed by reference; reset()
// clears their memory of the last run (dopri5's first-same-as-last stage, Bulirsch-Stoer's order and step;
// the controlled rkf78 keeps only its maximal step, unset here).
class OdeintTrial final : public Trial {
  using Rkf78 = odeint::controlled_runge_kutta<odeint::runge_kutta_fehlberg78<Y>>;
  using Dopri5 = odeint::controlled_runge_kutta<odeint::runge_kutta_dopri5<Y>>;
  using Dopri5Dense = odeint::dense_output_runge_kutta<Dopri5>;
  using Checker = odeint::default_error_checker<double, odeint::array_algebra, odeint::default_operations>;

 public:
  OdeintTrial(const Case& c, std::span<const double> times, double param, OdeintKind kind)
      : f_(c.body), y0_(initial_y(c)), times_(times.begin(), times.end()), kind_(kind), param_(param),
        h0_(initial_step(c)), rkf78_(Checker(param, param)), dopri5_(Checker(param, param)),
        dense_(Dopri5(Checker(param, param))), bs_(param, param) {
    times0_.push_back(0.0);
    times0_.insert(times0_.end(), times.begin(), times.end());
    samples_.reserve(times0_.size());
  }
  void reset() override {
    samples_.clear();
    dopri5_.reset();
    bs_.reset();
  }
  bool run() override {
    samples_.clear();
    Y y = y0_;
    const auto observe = [this](const Y& x, double t) { samples_.push_back(sample_of(f_, t, x.data())); };
    std::size_t n = 0;
    switch (kind_) {
      case OdeintKind::rkf78:
        n = odeint::integrate_times(std::ref(rkf78_), std::cref(f_), y, times0_.begin(), times0_.end(), h0_, observe);
        break;
      case OdeintKind::dopri5:
        n = odeint::integrate_times(std::ref(dopri5_), std::cref(f_), y, times0_.begin(), times0_.end(), h0_, observe);
        break;
      case OdeintKind::dopri5_dense:
        n = odeint::integrate_times(std::ref(dense_), std::cref(f_), y, times0_.begin(), times0_.end(), h0_, observe);
        break;
      case OdeintKind::bulirsch_stoer:
        n = odeint::integrate_times(std::ref(bs_), std::cref(f_), y, times0_.begin(), times0_.end(), h0_, observe);
        break;
      case OdeintKind::rk4:
        n = odeint::integrate_times(std::ref(rk4_), std::cref(f_), y, times0_.begin(), times0_.end(),
                                    times_.back() / param_, observe);
        break;
      case OdeintKind::rkf78_fixed:
        n = odeint::integrate_times(std::ref(rkf78_plain_), std::cref(f_), y, times0_.begin(), times0_.end(),
                                    times_.back() / param_, observe);
        break;
    }
    steps_ = static_cast<std::int64_t>(n);
    return samples_.size() == times0_.size() && std::isfinite(samples_.back().x.Omega.norm());
  }
  std::int64_t steps() const override { return steps_; }

 private:
  Rhs f_;
  Y y0_;
  std::vector<double> times_, times0_;
  OdeintKind kind_;
  double param_, h0_;
  Rkf78 rkf78_;
  Dopri5 dopri5_;
  Dopri5Dense dense_;
  odeint::bulirsch_stoer<Y> bs_;
  odeint::runge_kutta4<Y> rk4_;
  odeint::runge_kutta_fehlberg78<Y> rkf78_plain_;
  std::int64_t steps_ = 0;
};

Method odeint_method(const std::string& name, const std::string& description, int order, OdeintKind kind) {
  Method m;
  m.name = name;
  m.library = "boost_odeint";
  m.description = description;
  m.order = order;
  m.adaptive = kind != OdeintKind::rk4 && kind != OdeintKind::rkf78_fixed;
  m.make = [kind](const Case& c, std::span<const double> times, double param) -> std::unique_ptr<Trial> {
    return std::make_unique<OdeintTrial>(c, times, param, kind);
  };
  return m;
}

// ---- GSL odeiv2 -----------------------------------------------------------------------------------------
#ifdef LGI_BENCH_GSL
int gsl_rhs(double /*t*/, const double y[], double dydt[], void* params) {
  (*static_cast<const Rhs*>(params))(y, dydt);
  return GSL_SUCCESS;
}
int gsl_jac(double /*t*/, const double y[], double* dfdy, double dfdt[], void* params) {
  static_cast<const Rhs*>(params)->jacobian(y, dfdy);
  for (int i = 0; i < 7; ++i) dfdt[i] = 0;
  return GSL_SUCCESS;
}

// param: the tolerance (adaptive: the driver, gsl_odeiv2_driver_apply) or the number of steps over [0, T] (fixed:
// the stepper alone, gsl_odeiv2_step_apply — the driver's fixed-step call would consult its error control and
// fail a step whose estimate exceeds the tolerance).
class GslTrial final : public Trial {
 public:
  GslTrial(const Case& c, std::span<const double> times, double param, const gsl_odeiv2_step_type* type, bool fixed)
      : f_(c.body), y0_(initial_y(c)), times_(times.begin(), times.end()), h0_(initial_step(c)) {
    sys_ = {gsl_rhs, gsl_jac, 7, &f_};
    if (fixed) {
      h_ = times_.back() / param;
      step_ = gsl_odeiv2_step_alloc(type, 7);
      if (step_ == nullptr) throw std::runtime_error("gsl_odeiv2_step_alloc failed");
    } else {
      driver_ = gsl_odeiv2_driver_alloc_y_new(&sys_, type, h0_, param, param);
      if (driver_ == nullptr) throw std::runtime_error("gsl_odeiv2_driver_alloc_y_new failed");
    }
    samples_.reserve(times_.size() + 1);
  }
  ~GslTrial() override {
    if (driver_ != nullptr) gsl_odeiv2_driver_free(driver_);
    if (step_ != nullptr) gsl_odeiv2_step_free(step_);
  }
  GslTrial(const GslTrial&) = delete;
  GslTrial& operator=(const GslTrial&) = delete;

  void reset() override {
    samples_.clear();
    if (driver_ != nullptr)
      gsl_odeiv2_driver_reset_hstart(driver_, h0_);  // also resets the stepper, control and step count
    else
      gsl_odeiv2_step_reset(step_);
    y_ = y0_;
  }
  bool run() override {
    double t = 0;
    samples_.push_back(sample_of(f_, t, y_.data()));
    std::int64_t steps = 0;
    for (const double ti : times_) {
      if (step_ != nullptr) {  // each output interval in ⌈length/h⌉ equal steps
        const double n = std::ceil((ti - t) / h_ * (1 - 1e-12)), hi = (ti - t) / n;
        for (std::int64_t k = 0; k < static_cast<std::int64_t>(n); ++k, ++steps)
          if (gsl_odeiv2_step_apply(step_, t + static_cast<double>(k) * hi, hi, y_.data(), yerr_.data(), nullptr,
                                    nullptr, &sys_) != GSL_SUCCESS)
            return false;
        t = ti;
      } else if (gsl_odeiv2_driver_apply(driver_, &t, ti, y_.data()) != GSL_SUCCESS) {
        return false;
      }
      samples_.push_back(sample_of(f_, t, y_.data()));
    }
    steps_ = driver_ != nullptr ? static_cast<std::int64_t>(driver_->n) : steps;
    return true;
  }
  std::int64_t steps() const override { return steps_; }

 private:
  Rhs f_;
  Y y0_, y_{};
  std::vector<double> times_;
  Y yerr_{};
  double h0_, h_ = 0;
  gsl_odeiv2_system sys_{};
  gsl_odeiv2_driver* driver_ = nullptr;
  gsl_odeiv2_step* step_ = nullptr;
  std::int64_t steps_ = 0;
};

Method gsl_method(const std::string& name, const std::string& description, int order, const gsl_odeiv2_step_type* type,
                  bool fixed = false) {
  Method m;
  m.name = name;
  m.library = "gsl";
  m.description = description;
  m.order = order;
  m.adaptive = !fixed;
  m.make = [type, fixed](const Case& c, std::span<const double> times, double param) -> std::unique_ptr<Trial> {
    return std::make_unique<GslTrial>(c, times, param, type, fixed);
  };
  return m;
}
#endif

// ---- SUNDIALS -------------------------------------------------------------------------------------------
#ifdef LGI_BENCH_SUNDIALS
int sundials_rhs(sunrealtype /*t*/, N_Vector y, N_Vector ydot, void* user_data) {
  (*static_cast<const Rhs*>(user_data))(N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
  return 0;
}

enum class SundialsKind { cvode_adams, arkode_erk4, arkode_erk8 };

class SundialsTrial final : public Trial {
 public:
  SundialsTrial(const Case& c, std::span<const double> times, double tol, SundialsKind kind)
      : f_(c.body), y0_(initial_y(c)), times_(times.begin(), times.end()), kind_(kind) {
    if (SUNContext_Create(nullptr, &ctx_) != 0) throw std::runtime_error("SUNContext_Create failed");
    y_ = N_VNew_Serial(7, ctx_);
    load_initial();
    if (kind == SundialsKind::cvode_adams) {
      mem_ = CVodeCreate(CV_ADAMS, ctx_);
      check(CVodeInit(mem_, sundials_rhs, 0.0, y_), "CVodeInit");
      check(CVodeSStolerances(mem_, tol, tol), "CVodeSStolerances");
      nls_ = SUNNonlinSol_FixedPoint(y_, 0, ctx_);
      check(CVodeSetNonlinearSolver(mem_, nls_), "CVodeSetNonlinearSolver");
      check(CVodeSetUserData(mem_, &f_), "CVodeSetUserData");
      check(CVodeSetMaxNumSteps(mem_, 2'000'000'000L), "CVodeSetMaxNumSteps");
    } else {
      mem_ = ERKStepCreate(sundials_rhs, 0.0, y_, ctx_);
      check(ERKStepSStolerances(mem_, tol, tol), "ERKStepSStolerances");
      check(ERKStepSetOrder(mem_, kind == SundialsKind::arkode_erk8 ? 8 : 4), "ERKStepSetOrder");
      check(ERKStepSetUserData(mem_, &f_), "ERKStepSetUserData");
      check(ERKStepSetMaxNumSteps(mem_, 2'000'000'000L), "ERKStepSetMaxNumSteps");
    }
    if (mem_ == nullptr) throw std::runtime_error("SUNDIALS: solver creation failed");
    samples_.reserve(times_.size() + 1);
  }
  ~SundialsTrial() override {
    if (kind_ == SundialsKind::cvode_adams) {
      CVodeFree(&mem_);
      SUNNonlinSolFree(nls_);
    } else {
      ERKStepFree(&mem_);
    }
    N_VDestroy(y_);
    SUNContext_Free(&ctx_);
  }
  SundialsTrial(const SundialsTrial&) = delete;
  SundialsTrial& operator=(const SundialsTrial&) = delete;

  void reset() override {
    samples_.clear();
    load_initial();
    if (kind_ == SundialsKind::cvode_adams) {
      check(CVodeReInit(mem_, 0.0, y_), "CVodeReInit");
      check(CVodeSetStopTime(mem_, times_.back()), "CVodeSetStopTime");
    } else {
      check(ERKStepReInit(mem_, sundials_rhs, 0.0, y_), "ERKStepReInit");
      check(ERKStepSetStopTime(mem_, times_.back()), "ERKStepSetStopTime");
    }
  }
  bool run() override {
    samples_.push_back(sample_of(f_, 0.0, N_VGetArrayPointer(y_)));
    for (const double ti : times_) {
      double t = 0;
      const int flag = kind_ == SundialsKind::cvode_adams ? CVode(mem_, ti, y_, &t, CV_NORMAL)
                                                          : ERKStepEvolve(mem_, ti, y_, &t, ARK_NORMAL);
      if (flag < 0) return false;
      samples_.push_back(sample_of(f_, t, N_VGetArrayPointer(y_)));
    }
    long n = 0;
    if (kind_ == SundialsKind::cvode_adams)
      CVodeGetNumSteps(mem_, &n);
    else
      ERKStepGetNumSteps(mem_, &n);
    steps_ = n;
    return true;
  }
  std::int64_t steps() const override { return steps_; }

 private:
  static void check(int flag, const char* what) {
    if (flag < 0) throw std::runtime_error(std::string("SUNDIALS: ") + what + " failed");
  }
  void load_initial() {
    double* p = N_VGetArrayPointer(y_);
    for (int i = 0; i < 7; ++i) p[i] = y0_[static_cast<std::size_t>(i)];
  }
  Rhs f_;
  Y y0_;
  std::vector<double> times_;
  SundialsKind kind_;
  SUNContext ctx_ = nullptr;
  N_Vector y_ = nullptr;
  void* mem_ = nullptr;
  SUNNonlinearSolver nls_ = nullptr;
  std::int64_t steps_ = 0;
};

Method sundials_method(const std::string& name, const std::string& description, int order, SundialsKind kind) {
  Method m;
  m.name = name;
  m.library = "sundials";
  m.description = description;
  m.order = order;
  m.adaptive = true;
  m.make = [kind](const Case& c, std::span<const double> times, double tol) -> std::unique_ptr<Trial> {
    return std::make_unique<SundialsTrial>(c, times, tol, kind);
  };
  return m;
}
#endif

}  // namespace

double initial_step(const Case& c) { return 0.1 / std::max(c.x0.Omega.norm(), 1e-3); }

std::vector<Method> peer_methods(const Case& /*c*/) {
  std::vector<Method> m{
      odeint_method("odeint_rkf78", "Boost.Odeint runge_kutta_fehlberg78, controlled", 8, OdeintKind::rkf78),
      odeint_method("odeint_dopri5", "Boost.Odeint runge_kutta_dopri5, controlled", 5, OdeintKind::dopri5),
      odeint_method("odeint_dopri5_dense", "Boost.Odeint runge_kutta_dopri5, dense output", 5, OdeintKind::dopri5_dense),
      odeint_method("odeint_bulirsch_stoer", "Boost.Odeint bulirsch_stoer (extrapolation, variable order)", 0,
                    OdeintKind::bulirsch_stoer),
      odeint_method("odeint_rk4", "Boost.Odeint runge_kutta4, fixed steps", 4, OdeintKind::rk4),
      odeint_method("odeint_rkf78_fixed", "Boost.Odeint runge_kutta_fehlberg78, fixed steps", 8,
                    OdeintKind::rkf78_fixed),
  };
#ifdef LGI_BENCH_GSL
  gsl_set_error_handler_off();  // failures are return codes, not aborts
  m.push_back(gsl_method("gsl_rk8pd", "GSL odeiv2 rk8pd (Prince-Dormand 8(9))", 8, gsl_odeiv2_step_rk8pd));
  m.push_back(gsl_method("gsl_rk8pd_fixed", "GSL odeiv2 rk8pd (Prince-Dormand 8(9)), fixed steps", 8,
                         gsl_odeiv2_step_rk8pd, true));
  m.push_back(gsl_method("gsl_rk4imp", "GSL odeiv2 rk4imp (implicit Gauss 2-stage, exact Jacobian)", 4,
                         gsl_odeiv2_step_rk4imp));
  m.push_back(gsl_method("gsl_msadams", "GSL odeiv2 msadams (variable-order Adams, functional iteration)", 0,
                         gsl_odeiv2_step_msadams));
#endif
#ifdef LGI_BENCH_SUNDIALS
  m.push_back(sundials_method("cvode_adams", "SUNDIALS CVODE Adams-Moulton (orders 1-12), fixed-point iteration", 0,
                              SundialsKind::cvode_adams));
  m.push_back(sundials_method("arkode_erk4", "SUNDIALS ARKODE ERKStep, default order-4 table", 4,
                              SundialsKind::arkode_erk4));
  m.push_back(sundials_method("arkode_erk8", "SUNDIALS ARKODE ERKStep, default order-8 table (Fehlberg 13-7-8)", 8,
                              SundialsKind::arkode_erk8));
#endif
  return m;
}

std::vector<std::pair<std::string, std::string>> peer_versions() {
  std::vector<std::pair<std::string, std::string>> v{
      {"boost_odeint", std::to_string(BOOST_VERSION / 100000) + "." + std::to_string(BOOST_VERSION / 100 % 1000) + "." +
                           std::to_string(BOOST_VERSION % 100)}};
#ifdef LGI_BENCH_GSL
  v.emplace_back("gsl", GSL_VERSION);
#endif
#ifdef LGI_BENCH_SUNDIALS
  v.emplace_back("sundials", SUNDIALS_VERSION);
#endif
  return v;
}

// Max |analytic − central difference| / max(1, |entry|) of the peers' Jacobian at a generic state of the case
// (work_precision --smoke prints it; GSL's rk4imp depends on it).
double jacobian_check(const Case& c) {
  const Rhs f(c.body);
  Y y = initial_y(c);
  y[1] += 0.1, y[2] -= 0.2, y[3] += 0.05, y[4] += 0.3;
  std::array<double, 49> A{};
  f.jacobian(y.data(), A.data());
  double worst = 0;
  for (int j = 0; j < 7; ++j) {
    Y yp = y, ym = y, dp{}, dm{};
    const double e = 1e-6;
    yp[static_cast<std::size_t>(j)] += e;
    ym[static_cast<std::size_t>(j)] -= e;
    f(yp.data(), dp.data());
    f(ym.data(), dm.data());
    for (int i = 0; i < 7; ++i) {
      const double fd = (dp[static_cast<std::size_t>(i)] - dm[static_cast<std::size_t>(i)]) / (2 * e);
      const double a = A[static_cast<std::size_t>(7 * i + j)];
      worst = std::max(worst, std::abs(a - fd) / std::max(1.0, std::abs(a)));
    }
  }
  return worst;
}

// The peers' right-hand side alone: `batches` batches of `calls` calls at the case's initial state through a function
// pointer the compiler cannot see through (GSL and SUNDIALS call it so; Boost.Odeint inlines it), thread CPU time,
// seconds per call of each batch.
namespace {
void call_rhs(const Rhs& f, const double* y, double* d) { f(y, d); }
double thread_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}
}  // namespace

std::vector<double> peer_rhs_seconds(const Case& c, int batches, long calls) {
  const Rhs f(c.body);
  Y y = initial_y(c), d{};
  void (*volatile fn)(const Rhs&, const double*, double*) = call_rhs;
  std::vector<double> out;
  for (int b = 0; b < batches; ++b) {
    const double t0 = thread_seconds();
    for (long i = 0; i < calls; ++i) {
      fn(f, y.data(), d.data());
      asm volatile("" : : "r"(d.data()), "r"(y.data()) : "memory");
    }
    out.push_back((thread_seconds() - t0) / static_cast<double>(calls));
  }
  return out;
}

}  // namespace wp
