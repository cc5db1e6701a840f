// benchmarks/wp_lgi.hpp — lgi's steppers as work-precision trials: fixed steps through lgi::integrate_times,
// embedded pairs through lgi::integrate_adaptive (rtol = atol = the tolerance), the observer storing one
// Sample per output time into storage reserved beforehand. The stepper is built when the trial is made
// (outside the timing); run() starts from the case's initial state.
#pragma once

#include "wp_common.hpp"

#include <lgi/core/driver.hpp>
#include <lgi/integrators/adaptive.hpp>
#include <lgi/integrators/projection.hpp>

#include <cmath>
#include <string>
#include <type_traits>
#include <vector>

namespace wp {

template <class S>
class LgiFixed final : public Trial {
 public:
  LgiFixed(const typename S::Problem& p, const State& x0, std::span<const double> times, double n_steps)
      : stepper_(p), x0_(x0), times_(times.begin(), times.end()), h_(times.back() / n_steps) {
    samples_.reserve(times_.size() + 1);
  }
  void reset() override { samples_.clear(); }
  bool run() override {
    samples_.clear();
    State x = x0_;
    const auto observe = [this](double t, const State& y) { samples_.push_back({t, y, orthogonality(y.R)}); };
    const lgi::IntegrationSummary s = lgi::integrate_times(stepper_, x, 0.0, h_, std::span<const double>(times_), observe);
    steps_ = s.steps;
    return s.status == lgi::RunStatus::completed;
  }
  std::int64_t steps() const override { return steps_; }

 private:
  S stepper_;
  State x0_;
  std::vector<double> times_;
  double h_;
  std::int64_t steps_ = 0;
};

template <class S>
class LgiAdaptive final : public Trial {
 public:
  LgiAdaptive(const typename S::Problem& p, const State& x0, std::span<const double> times, double tol, double h0)
      : stepper_(p, options(tol)), x0_(x0), times_(times.begin(), times.end()), h0_(h0) {
    samples_.reserve(times_.size() + 1);
  }
  void reset() override { samples_.clear(); }
  bool run() override {
    samples_.clear();
    State x = x0_;
    const auto observe = [this](double t, const State& y) { samples_.push_back({t, y, orthogonality(y.R)}); };
    const lgi::AdaptiveSummary s =
        lgi::integrate_adaptive(stepper_, x, 0.0, h0_, std::span<const double>(times_), observe);
    steps_ = s.accepted;
    return s.status == lgi::RunStatus::completed;
  }
  std::int64_t steps() const override { return steps_; }

 private:
  static lgi::StepperOptions options(double tol) {
    lgi::StepperOptions o;
    o.rtol = tol;
    o.atol = tol;
    return o;
  }
  S stepper_;
  State x0_;
  std::vector<double> times_;
  double h0_;
  std::int64_t steps_ = 0;
};

template <class S>
struct is_projected : std::false_type {};
template <class S>
struct is_projected<lgi::Projected<S>> : std::true_type {};

// A Method entry for stepper S on problem p (a copy is kept in the factory). A projected stepper
// (lgi::Projected<S>) is named after its method with "_projected".
template <class S>
Method lgi_method(const typename S::Problem& p, bool torque_free, bool adaptive = false) {
  Method m;
  m.name = std::string(S::traits.name) + (is_projected<S>::value ? "_projected" : "");
  m.projected = is_projected<S>::value;
  m.library = "lgi";
  m.description = std::string(S::traits.title);
  m.order = torque_free && S::traits.free_body_order > 0 ? S::traits.free_body_order : S::traits.order;
  m.adaptive = adaptive;
  m.symplectic = S::traits.symplectic;
  if constexpr (lgi::AdaptiveStepper<S>) {
    if (adaptive) {
      m.make = [p](const Case& c, std::span<const double> times, double tol) -> std::unique_ptr<Trial> {
        return std::make_unique<LgiAdaptive<S>>(p, c.x0, times, tol, initial_step(c));
      };
      return m;
    }
  }
  m.adaptive = false;
  m.make = [p](const Case& c, std::span<const double> times, double n) -> std::unique_ptr<Trial> {
      return std::make_unique<LgiFixed<S>>(p, c.x0, times, n);
    };
  return m;
}

}  // namespace wp
