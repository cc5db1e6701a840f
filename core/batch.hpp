/// \file
/// lgi/core/batch.hpp — many bodies in one call: a structure-of-arrays batch and a generic batch driver.
///
/// A batch holds N bodies of one problem type, integrated with one method and one step h from a shared
/// t0 over n steps, each from its own initial state and (optionally) with its own problem parameters:
///
/// ~~~{.unparsed}
///   for each body i:  y = stepper_i.to_internal(x_i, t0);  y ← step(y, t0 + n·h, h), n = 0 … n_steps − 1
///                     x_i = stepper_i.to_state(y),  status_i, steps_i
/// ~~~
///
/// i.e. exactly what a single-body run does (time t_n = t0 + n·h as in core/driver.hpp), so every method is
/// batchable and its batch results equal its single-body results bit for bit. integrate_batch_each runs
/// that loop per body (honestly scalar; threads over bodies); integrators/batch_lgvi.hpp and batch_rkmk.hpp add
/// kernels that vectorise the LGVI and RKMK4 across bodies for the heavy top and the free body (diagonal J) and
/// give the same bits.
///
/// Layout (structure of arrays, so that a kernel loads W consecutive bodies into one vector register):
/// ~~~{.unparsed}
///   R[3r + c][i]   entry (r, c) of body i's attitude        Omega[j][i]   body angular velocity
///   status[i]      StepStatus of the run: ok, or why it stopped
///   steps[i]       good steps taken: n_steps when ok, else the index of the step that failed
/// ~~~
/// On failure the body keeps its last good state (integrator.hpp's contract), the others are unaffected.
/// The batch holds (R, Ω); a method's internal coordinates (Π = JΩ, the LGVI's stored torque) are rebuilt at
/// the start of each call, so two calls of n steps equal one of 2n only up to that round trip, as for the
/// single-body drivers.
///
/// Per-body parameters: integrate_batch takes either one problem (shared) or a function body index →
/// problem; the LGVI and RKMK4 kernels take a per-body b (m g ℓ) for the heavy top (batch_lgvi.hpp,
/// batch_rkmk.hpp).
/// Threads: BatchOptions::threads workers over contiguous ranges of bodies (0: all hardware threads).
/// Bodies are independent, so results do not depend on the number of threads.
#pragma once

#include "driver.hpp"
#include "integrator.hpp"
#include "state.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <thread>
#include <type_traits>
#include <vector>

namespace lgi {

/// N bodies in structure-of-arrays form (double only).
struct BodyBatch {
  std::array<std::vector<double>, 9> R;      ///< R[3r + c][i]
  std::array<std::vector<double>, 3> Omega;  ///< Omega[j][i]
  std::vector<StepStatus> status;            ///< status[i]: ok, or why body i stopped
  std::vector<std::int64_t> steps;           ///< steps[i]: good steps body i took in the last call

  /// No bodies.
  BodyBatch() = default;
  /// n bodies at rest at the identity (resize).
  explicit BodyBatch(std::size_t n) { resize(n); }

  /// n bodies, every one reset to R = I, Ω = 0, status ok, 0 steps (previous contents are lost). Allocates.
  void resize(std::size_t n) {
    for (auto& v : R) v.assign(n, 0.0);
    for (int e = 0; e < 3; ++e) R[static_cast<std::size_t>(4 * e)].assign(n, 1.0);
    for (auto& v : Omega) v.assign(n, 0.0);
    status.assign(n, StepStatus::ok);
    steps.assign(n, 0);
  }
  /// The number of bodies (the length of status; the other arrays must match it when a driver runs).
  std::size_t size() const { return status.size(); }

  /// Body i's state (i < size(), not checked).
  State<double> state(std::size_t i) const {
    State<double> x;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) x.R(r, c) = R[static_cast<std::size_t>(3 * r + c)][i];
    for (int j = 0; j < 3; ++j) x.Omega(j) = Omega[static_cast<std::size_t>(j)][i];
    return x;
  }
  /// Body i = x (i < size(), not checked); its status and steps are left as they are.
  void set_state(std::size_t i, const State<double>& x) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) R[static_cast<std::size_t>(3 * r + c)][i] = x.R(r, c);
    for (int j = 0; j < 3; ++j) Omega[static_cast<std::size_t>(j)][i] = x.Omega(j);
  }
};

/// Options of the batch drivers.
struct BatchOptions {
  int threads = 1;  ///< worker threads; 0: std::thread::hardware_concurrency()
};

namespace detail {

inline int batch_threads(const BatchOptions& options, std::size_t work_items) {
  if (options.threads < 0) throw std::invalid_argument("lgi::BatchOptions: threads must be >= 0");
  int t = options.threads;
  if (t == 0) t = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  return static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(t), std::max<std::size_t>(work_items, 1)));
}

// Calls work(begin, end) on `threads` contiguous slices of [0, count); the calling thread takes the first.
template <class Work>
void parallel_slices(std::size_t count, int threads, const Work& work) {
  const auto bound = [&](int k) { return count * static_cast<std::size_t>(k) / static_cast<std::size_t>(threads); };
  std::vector<std::thread> pool;
  pool.reserve(static_cast<std::size_t>(threads));
  for (int k = 1; k < threads; ++k) pool.emplace_back([&work, b = bound(k), e = bound(k + 1)] { work(b, e); });
  work(bound(0), bound(1));
  for (auto& t : pool) t.join();
}

inline void check_batch_run(const BodyBatch& batch, double h, std::int64_t n_steps) {
  const std::size_t n = batch.size();
  for (const auto& v : batch.R)
    if (v.size() != n) throw std::invalid_argument("lgi::integrate_batch: R arrays and status differ in length");
  for (const auto& v : batch.Omega)
    if (v.size() != n) throw std::invalid_argument("lgi::integrate_batch: Omega arrays and status differ in length");
  if (batch.steps.size() != n) throw std::invalid_argument("lgi::integrate_batch: steps and status differ in length");
  if (!std::isfinite(h) || h == 0) throw std::invalid_argument("lgi::integrate_batch: step h must be finite and non-zero");
  if (n_steps < 0) throw std::invalid_argument("lgi::integrate_batch: n_steps must be >= 0");
}

}  // namespace detail

/// The generic batch driver: body i is stepped by make_stepper(i) (a Stepper), n_steps steps of h from t0,
/// exactly as a single-body run. Works for every method; scalar per body, threads over bodies.
/// std::invalid_argument when the batch's arrays differ in length, h is not finite or is 0, n_steps < 0 or
/// options.threads < 0. make_stepper is called concurrently from the worker threads (one call per body), so it must
/// be safe to call so and must not throw when more than one thread runs (an exception in a worker ends the program).
template <class MakeStepper>
void integrate_batch_each(const MakeStepper& make_stepper, BodyBatch& batch, double t0, double h,
                          std::int64_t n_steps, const BatchOptions& options = {}) {
  using S = std::remove_cvref_t<decltype(make_stepper(std::size_t{0}))>;
  static_assert(Stepper<S> && std::same_as<typename S::Scalar, double>, "make_stepper(i) must return a double Stepper");
  detail::check_batch_run(batch, h, n_steps);
  const int threads = detail::batch_threads(options, batch.size());
  detail::parallel_slices(batch.size(), threads, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      S stepper = make_stepper(i);
      typename S::Internal y = stepper.to_internal(batch.state(i), t0);
      IntegrationSummary summary;  // the drivers' own step loop: t_n = t0 + n·h, stops at a failed step
      Cursor<double> c;
      bool moved = false;
      NoMonitor monitor;
      const auto no_observer = [](double, const typename S::Internal*) {};
      drive_grid(stepper, y, t0, h, GridEvents<double>::steps(n_steps, t0, h), std::numeric_limits<std::int64_t>::max(),
                 c, summary, moved, no_observer, monitor);
      batch.set_state(i, stepper.to_state(y));
      batch.status[i] = summary.step_status;
      batch.steps[i] = c.n;
    }
  });
}

/// `integrate_batch<Method>`(problem, …): `Method<P>` (such as Lgvi, Rkmk4) constructed from `problem` and
/// `options` for every body; `problem` is either one problem shared by all bodies or a function
/// (std::size_t i) → problem giving body i its own parameters.
template <template <class> class Method, class ProblemOrFactory>
void integrate_batch(const ProblemOrFactory& problem, BodyBatch& batch, double t0, double h, std::int64_t n_steps,
                     const StepperOptions& stepper_options = {}, const BatchOptions& options = {}) {
  stepper_options.check();
  if constexpr (RigidBodyProblem<ProblemOrFactory>) {
    integrate_batch_each([&](std::size_t) { return Method<ProblemOrFactory>(problem, stepper_options); }, batch, t0,
                         h, n_steps, options);
  } else {
    using P = std::remove_cvref_t<decltype(problem(std::size_t{0}))>;
    static_assert(RigidBodyProblem<P>, "integrate_batch: pass a problem or a function body index -> problem");
    integrate_batch_each([&](std::size_t i) { return Method<P>(problem(i), stepper_options); }, batch, t0, h,
                         n_steps, options);
  }
}

}  // namespace lgi
