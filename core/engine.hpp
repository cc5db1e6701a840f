/// \file
/// lgi/core/engine.hpp — one method on one problem behind a small interface: the type-erased integrator.
///
/// An Integrator holds a stepper (any Stepper, or a StepFunction with to_internal/to_state) and the states it
/// steps, in slots. Its virtual functions work in chunks: run_grid and run_adaptive run the library's loops
/// (drive_grid, drive_adaptive, core/driver.hpp) from a cursor until the run completes, fails, or the caller's
/// RunSink stops it — inside, the loop calls the stepper's step directly, as a templated loop does, so a step costs
/// what it costs without the interface. Everything around the loop (rows, observers, budgets, checkpoints, sweeps)
/// is written once against this interface instead of once per (method, problem).
///
/// ~~~{.unparsed}
///   auto engine = lgi::make_integrator<lgi::Lgvi<lgi::HeavyTop<double>>>(top, options);
///   engine->set(lgi::Slot::current, x0, 0.0);
///   lgi::Cursor<double> c;  … engine->run_grid(h, events, limit, c, summary, moved, sink);
/// ~~~
///
/// Slots. current is the trajectory: run_grid and run_adaptive step it; during RunSink::observe, event is the
/// observed state (a grid point, a side-step's result or a dense output); previous, shadow and scratch belong to the
/// caller (side-steps from a previous state, a second trajectory). save/restore give a slot's numbers
/// (core/state_io.hpp) bit for bit: a checkpoint is the cursor plus save(current). step(slot) steps a slot other than
/// current with a copy of the stepper, so the trajectory's stepper (its counters, a domain flag) sees only its own
/// steps.
///
/// Thread safety: one thread per Integrator. The interface allocates nothing once built; state() and save() copy.
#pragma once

#include "driver.hpp"
#include "integrator.hpp"
#include "state.hpp"
#include "state_io.hpp"

#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>

namespace lgi {

/// The states an Integrator holds (this header's "Slots"): current (the trajectory run_grid and run_adaptive step),
/// event (the observed state, readable during RunSink::observe only), and previous, shadow, scratch (the caller's).
enum class Slot : std::uint8_t { current, event, previous, shadow, scratch };

/// The caller's side of a chunk: output events and the monitor.
class RunSink {
 public:
  /// An output event at time t: the state is Integrator::state(Slot::event), or — when `initial` — the run's initial
  /// state as the caller gave it (no step was taken; no round trip through the stepper's coordinates).
  virtual void observe(double t, bool initial) = 0;
  /// The monitor: called after first_check() steps (adaptive: attempted steps), then after as many as each call
  /// returns; 0 stops the run (Halt::monitor). Integrator::save(Slot::current) is the state at the cursor.
  virtual std::int64_t check(const Cursor<double>& at) = 0;
  /// The steps before the first check (default 1).
  virtual std::int64_t first_check() const { return 1; }

 protected:
  ~RunSink() = default;
};

/// One method on one problem, type-erased (this header). Built by make_integrator; one thread at a time.
class Integrator {
 public:
  virtual ~Integrator() = default;

  /// The method's traits (Stepper::traits).
  virtual const MethodTraits& traits() const = 0;
  /// True for an embedded pair (run_adaptive works); its error estimate's order k.
  virtual bool adaptive() const = 0;
  /// The embedded pair's control order k (h ∝ err^(−1/k)); 0 for a method without one.
  virtual int control_order() const = 0;
  /// The count of a slot's numbers (save, restore).
  virtual std::size_t state_size() const = 0;

  /// Slot s = the stepper's coordinates of x at time t (Stepper::to_internal).
  virtual void set(Slot s, const State<double>& x, double t) = 0;
  /// The state of slot s (Stepper::to_state); Slot::event only during RunSink::observe.
  virtual State<double> state(Slot s) const = 0;
  /// The numbers of slot s, numbers.size() == state_size(); std::invalid_argument otherwise.
  virtual void save(Slot s, std::span<double> numbers) const = 0;
  /// Slot s (not Slot::event) = the numbers save wrote, bit for bit; std::invalid_argument unless
  /// numbers.size() == state_size(), std::logic_error for Slot::event.
  virtual void restore(Slot s, std::span<const double> numbers) = 0;
  /// Slot `to` (not Slot::event) = slot `from`.
  virtual void copy(Slot from, Slot to) = 0;
  /// One step of slot s (not current) from t by h, with a copy of the stepper; the slot is untouched unless ok.
  virtual StepStatus step(Slot s, double t, double h) = 0;

  /// Fixed steps from the cursor, the current slot at t0 + c.n·h (drive_grid; t0 = 0).
  virtual Halt run_grid(double h, const GridEvents<double>& events, std::int64_t step_limit, Cursor<double>& c,
                        IntegrationSummary& summary, bool& moved, RunSink& sink) = 0;
  /// Adaptive steps from the cursor to times.back() (drive_adaptive); std::logic_error unless adaptive().
  virtual Halt run_adaptive(std::span<const double> times, double span, const AdaptiveOptions& options,
                            std::int64_t attempt_limit, Cursor<double>& c, IntegrationSummary& summary, bool& moved,
                            RunSink& sink) = 0;

  /// Newton iterations the trajectory's stepper made (implicit methods; −1 for explicit ones).
  virtual std::int64_t newton_iterations() const { return -1; }
  /// For steppers with a domain (CheckedEuclideanStep): true when the trajectory's last failed step left it, with
  /// the time of the rejected state.
  virtual bool left_domain(double& t_outside) const {
    (void)t_outside;
    return false;
  }
};

/// The one implementation: S a StepFunction with Scalar = double, to_internal(x, t) and to_state(y); its Internal
/// lists its numbers (LGI_NUMBERS) completely.
template <class S>
class IntegratorOf final : public Integrator {
 public:
  using Internal = typename S::Internal;  ///< the stepper's coordinates (a slot's type)
  static_assert(numbers_complete<Internal>(), "lgi::IntegratorOf: an Internal type with members its LGI_NUMBERS leaves out");

  /// S constructed from args (S's constructor arguments; S's exceptions propagate); every slot value-initialised.
  template <class... Args>
  explicit IntegratorOf(Args&&... args) : stepper_(std::forward<Args>(args)...), side_(stepper_) {}

  /// The trajectory's stepper (its counters, its options).
  const S& stepper() const { return stepper_; }

  const MethodTraits& traits() const override { return traits_; }
  bool adaptive() const override { return AdaptiveStepper<S>; }
  int control_order() const override {
    if constexpr (AdaptiveStepper<S>) return S::control_order;
    else return 0;
  }
  std::size_t state_size() const override { return numbers(); }

  void set(Slot s, const State<double>& x, double t) override { put(s) = stepper_.to_internal(x, t); }
  State<double> state(Slot s) const override { return stepper_.to_state(get(s)); }
  void save(Slot s, std::span<double> numbers) const override {
    check_size(numbers.size());
    std::size_t i = 0;
    visit_numbers(get(s), [&](const double& v) {
      if (i < numbers.size()) numbers[i] = v;
      ++i;
    });
  }
  void restore(Slot s, std::span<const double> numbers) override {
    check_size(numbers.size());
    std::size_t i = 0;
    visit_numbers(put(s), [&](double& v) {
      if (i < numbers.size()) v = numbers[i];
      ++i;
    });
  }
  void copy(Slot from, Slot to) override { put(to) = get(from); }
  StepStatus step(Slot s, double t, double h) override {
    if (s == Slot::current) throw std::logic_error("lgi::Integrator::step: the current slot is stepped by run_*");
    return step_side(put(s), t, h);
  }

  Halt run_grid(double h, const GridEvents<double>& events, std::int64_t step_limit, Cursor<double>& c,
                IntegrationSummary& summary, bool& moved, RunSink& sink) override {
    Bridge bridge{*this, sink};
    return drive_grid(stepper_, slots_[0], 0.0, h, events, step_limit, c, summary, moved, bridge, bridge);
  }
  Halt run_adaptive(std::span<const double> times, double span, const AdaptiveOptions& options,
                    std::int64_t attempt_limit, Cursor<double>& c, IntegrationSummary& summary, bool& moved,
                    RunSink& sink) override {
    if constexpr (AdaptiveStepper<S>) {
      Bridge bridge{*this, sink};
      return drive_adaptive(stepper_, slots_[0], times, span, options, attempt_limit, c, summary, moved, bridge, bridge);
    } else {
      throw std::logic_error("lgi::Integrator::run_adaptive: method " + std::string(traits_.name) +
                             " has no embedded pair");
    }
  }

  std::int64_t newton_iterations() const override {
    if constexpr (requires { stepper_.newton_iterations(); }) return stepper_.newton_iterations();
    else return -1;
  }
  bool left_domain(double& t_outside) const override {
    if constexpr (requires { stepper_.left(); stepper_.t_outside(); }) {
      t_outside = stepper_.t_outside();
      return stepper_.left();
    } else {
      (void)t_outside;
      return false;
    }
  }

 private:
  /// The drivers' observer and monitor, forwarding to the sink.
  struct Bridge {
    IntegratorOf& self;
    RunSink& sink;
    void operator()(double t, const Internal* y) {
      self.event_ = y;
      sink.observe(t, y == nullptr);
      self.event_ = nullptr;
    }
    std::int64_t first(const Cursor<double>&) const { return sink.first_check(); }
    std::int64_t operator()(const Cursor<double>& c, const Internal&) { return sink.check(c); }
  };

  /// One call site of the (large, flattened) step for the side slots: compile time.
  [[gnu::noinline]] StepStatus step_side(Internal& z, double t, double h) { return side_.step(z, t, h); }

  /// A slot to read (Slot::event: the observed state, during RunSink::observe only).
  const Internal& get(Slot s) const {
    if (s == Slot::event) {
      if (!event_) throw std::logic_error("lgi::Integrator: Slot::event outside RunSink::observe");
      return *event_;
    }
    return slots_[index(s)];
  }
  /// A slot to write (not Slot::event: that is the driver's).
  Internal& put(Slot s) {
    if (s == Slot::event) throw std::logic_error("lgi::Integrator: Slot::event is read-only");
    return slots_[index(s)];
  }
  static std::size_t index(Slot s) { return static_cast<std::size_t>(s) - (s > Slot::event ? 1 : 0); }
  /// The numbers of a slot: the leading numbers_in_use() of its Internal when the stepper says (Projected switched
  /// off), else all of them.
  std::size_t numbers() const {
    if constexpr (requires { stepper_.numbers_in_use(); }) return stepper_.numbers_in_use();
    else return number_count<Internal>();
  }
  void check_size(std::size_t n) const {
    if (n != numbers())
      throw std::invalid_argument("lgi::Integrator: " + std::to_string(n) + " numbers for a state of " +
                                  std::to_string(numbers()));
  }

  S stepper_;
  S side_;  ///< steps the side slots (its counters and flags are not the trajectory's)
  Internal slots_[4]{};  ///< current, previous, shadow, scratch
  const Internal* event_ = nullptr;
  static constexpr MethodTraits traits_ = S::traits;
};

/// An Integrator for stepper S built from args (S's constructor arguments: a problem and StepperOptions, …).
template <class S, class... Args>
std::unique_ptr<Integrator> make_integrator(Args&&... args) {
  return std::make_unique<IntegratorOf<S>>(std::forward<Args>(args)...);
}

}  // namespace lgi
