// benchmarks/wp_lgi.cpp — lgi's methods as work-precision trials, run as `lgi run` runs them: the case's scene with
// the trial's method (apps/scene.hpp), its problem's lgi::Integrator (core/engine.hpp) — the methods compiled once,
// in lgi_scene, with the command's flags — fixed steps by run_grid with events at the output times, embedded pairs
// by run_adaptive (rtol = atol = the tolerance, AdaptiveOptions' defaults), the sink storing one Sample per output
// time into storage reserved beforehand. The integrator is built when the trial is made (outside the timing); run()
// starts from the case's initial state. The projected methods are the scene's "projection": true.
#include "wp_common.hpp"

#include "auto_method.hpp"     // apps/: choose_auto
#include "registry.hpp"        // apps/: find_method
#include "runner_detail.hpp"   // apps/: the problem's runner, its integrator
#include "scene.hpp"           // apps/: load_scene

#include <lgi/core/engine.hpp>
#include <lgi/integrators/adaptive.hpp>

#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace wp {
namespace {

// The engine's sink: a Sample per output time (the initial one as the case gives it); the monitor never runs.
class Samples final : public lgi::RunSink {
 public:
  Samples(const lgi::Integrator& engine, const State& x0, std::vector<Sample>& out)
      : engine_(engine), x0_(x0), out_(out) {}
  void observe(double t, bool initial) override {
    const State x = initial ? x0_ : engine_.state(lgi::Slot::event);
    out_.push_back({t, x, orthogonality(x.R)});
  }
  std::int64_t check(const lgi::Cursor<double>&) override { return never; }
  std::int64_t first_check() const override { return never; }

 private:
  static constexpr std::int64_t never = std::numeric_limits<std::int64_t>::max();
  const lgi::Integrator& engine_;
  const State& x0_;
  std::vector<Sample>& out_;
};

// One configured run: `param` is the number of steps over [0, times.back()] (fixed) or the tolerance (adaptive).
class EngineTrial final : public Trial {
 public:
  EngineTrial(const Case& c, const lgi::app::Scene& case_scene, const lgi::app::MethodInfo& method, bool projected,
              bool adaptive, std::span<const double> times, double param)
      : x0_(c.x0), times_(times.begin(), times.end()), adaptive_(adaptive) {
    lgi::app::Scene scene = case_scene;
    scene.method = &method;
    scene.options = lgi::StepperOptions{};
    scene.options.projection = projected;
    if (adaptive) {
      scene.options.rtol = scene.options.atol = param;
      h0_ = initial_step(c);
    } else {
      h_ = times_.back() / param;
      scene.dt = h_;
    }
    engine_ = scene.problem->runner()->integrator(scene);
    samples_.reserve(times_.size() + 1);
  }
  void reset() override { samples_.clear(); }
  bool run() override {
    samples_.clear();
    samples_.push_back({0.0, x0_, orthogonality(x0_.R)});  // t0, as given (the library's drivers observe it)
    engine_->set(lgi::Slot::current, x0_, 0.0);
    Samples sink(*engine_, x0_, samples_);
    lgi::IntegrationSummary summary;
    bool moved = false;
    const std::span<const double> times(times_);
    if (adaptive_) {
      const lgi::AdaptiveOptions options;
      lgi::Cursor<double> c = lgi::adaptive_start(0.0, h0_, options);
      while (static_cast<std::size_t>(c.next) < times.size() && times[static_cast<std::size_t>(c.next)] == 0.0) ++c.next;
      engine_->run_adaptive(times, times.back(), options, options.max_steps, c, summary, moved, sink);
      steps_ = c.steps;
    } else {
      lgi::Cursor<double> c;
      const lgi::GridEvents<double> events(times, 0.0, h_);
      engine_->run_grid(h_, events, std::numeric_limits<std::int64_t>::max(), c, summary, moved, sink);
      steps_ = summary.steps;
    }
    return summary.status == lgi::RunStatus::completed;
  }
  std::int64_t steps() const override { return steps_; }

 private:
  std::unique_ptr<lgi::Integrator> engine_;
  State x0_;
  std::vector<double> times_;
  bool adaptive_;
  double h_ = 0, h0_ = 0;
  std::int64_t steps_ = 0;
};

// "method": "auto" at tolerance `param` (apps/auto_method.hpp): the choice — its probes included — is made in every
// timed run, as `lgi run` makes it for every scene; the chosen method then runs as its EngineTrial runs it (built
// once, outside the timing, like every trial's integrator). The choice sees the case's scene with t_end = the
// evaluation time (choose_auto reads the problem, the initial state and t_end, and sets the rest: each run chooses
// anew on the same Scene object).
class AutoTrial final : public Trial {
 public:
  AutoTrial(const Case& c, const lgi::app::Scene& case_scene, std::span<const double> times, double tolerance)
      : scene_(case_scene), tolerance_(tolerance) {
    scene_.t_end = times.back();
    scene_.output_times.clear();
    const lgi::app::Scene chosen = [&] {
      lgi::app::Scene s = scene_;
      lgi::app::choose_auto(s, tolerance_);
      return s;
    }();
    const bool adaptive = chosen.options.rtol > 0;
    inner_ = std::make_unique<EngineTrial>(c, chosen, *chosen.method, chosen.options.projection, adaptive, times,
                                           adaptive ? chosen.options.rtol : std::round(times.back() / chosen.dt));
    samples_.reserve(times.size() + 1);
  }
  void reset() override { inner_->reset(); }
  bool run() override {
    lgi::app::choose_auto(scene_, tolerance_);
    const bool ok = inner_->run();
    samples_ = inner_->samples();
    return ok;
  }
  std::int64_t steps() const override { return inner_->steps(); }

 private:
  lgi::app::Scene scene_;
  double tolerance_;
  std::unique_ptr<EngineTrial> inner_;
};

Method auto_method(const std::shared_ptr<const lgi::app::Scene>& scene) {
  Method m;
  m.name = "auto";
  m.library = "lgi";
  m.description = "method auto: lgi's choice for the tolerance (probes included)";
  m.adaptive = true;  // its parameter is the tolerance
  m.make = [scene](const Case& k, std::span<const double> times, double param) -> std::unique_ptr<Trial> {
    return std::make_unique<AutoTrial>(k, *scene, times, param);
  };
  return m;
}

// A Method entry: `name` from the registry; "_projected" with the scene's projection on; adaptive where the method
// is an embedded pair and asked to be.
Method engine_method(const Case& c, const std::shared_ptr<const lgi::app::Scene>& scene, std::string_view name,
                     bool projected = false, bool adaptive = false) {
  const lgi::app::MethodInfo* info = lgi::app::find_method(name);
  if (!info) throw std::logic_error("work_precision: no method " + std::string(name) + " in this build");
  const lgi::MethodTraits& t = info->traits;
  Method m;
  m.name = std::string(t.name) + (projected ? "_projected" : "");
  m.projected = projected;
  m.library = "lgi";
  m.description = std::string(t.title);
  m.order = c.kind == Kind::free_body && t.free_body_order > 0 ? t.free_body_order : t.order;
  m.exact_solution = t.exact_solution;
  m.adaptive = adaptive;
  m.symplectic = t.symplectic;
  m.make = [scene, info, projected, adaptive](const Case& k, std::span<const double> times,
                                              double param) -> std::unique_ptr<Trial> {
    return std::make_unique<EngineTrial>(k, *scene, *info, projected, adaptive, times, param);
  };
  return m;
}

}  // namespace

// The methods of the cases, in the order of the report. Free bodies: `exact` (the exact solution, its constants in
// double; the reference evaluates the same formulas with long-double constants, cross-checked against an
// independent integration: wp_reference.cpp) runs first; split_exact is left out (on a free body it is the exact
// solution again, evaluated step by step), and the preprocessed DMV (split_dmv4 … 10, order 2 with a
// torque) runs there only. A lagrange_top case runs the heavy top's methods (its scene's engine runs them on the
// same body as a heavy top with z0 = e3) and lagrange_split with its compositions.
std::vector<Method> lgi_methods(const Case& c) {
  const auto scene = std::make_shared<const lgi::app::Scene>(lgi::app::load_scene(c.file));
  const bool free = c.kind == Kind::free_body;
  std::vector<Method> m;
  const auto add = [&](std::string_view name, bool projected = false, bool adaptive = false) {
    m.push_back(engine_method(c, scene, name, projected, adaptive));
  };
  if (free) add("exact");
  add("lgvi");
  add("split_dmv");
  add("split_axes");
  if (free) {
    for (const char* name : {"split_dmv4", "split_dmv6", "split_dmv8", "split_dmv10"}) add(name);
  } else {
    add("split_exact");
  }
  for (const char* name : {"lgvi_yoshida4", "lgvi_suzuki4", "lgvi_yoshida6", "lgvi_kahan_li6", "lgvi_yoshida8",
                           "lgvi_kahan_li8", "lgvi_sofroniou_spaletta10", "split_dmv_yoshida4", "split_dmv_suzuki4",
                           "split_dmv_kahan_li6", "split_dmv_kahan_li8", "split_dmv_sofroniou_spaletta10", "rkmk4",
                           "cf4"})
    add(name);
  add("rkmk_dp5", false, true);
  add("rkmk_dp8", false, true);
  add("rkmk4_cayley");
  add("rkmk_dp5_cayley", false, true);
  add("rkmk_dp8_cayley", false, true);
  add("rkmk_vern9", false, true);
  add("rkmk_vern9_cayley", false, true);
  add("rkmk_vern9_cayley");  // the same pair at fixed steps: no error estimate, the update's 15 stages
  m.back().name += "_fixed";
  add("rkmk4", true);
  add("rkmk_dp8_cayley", true, true);
  if (c.kind == Kind::lagrange_top)
    for (const char* name : {"lagrange_split", "lagrange_split_yoshida4", "lagrange_split_kahan_li6",
                             "lagrange_split_kahan_li8", "lagrange_split_sofroniou_spaletta10"})
      add(name);
  m.push_back(auto_method(scene));
  return m;
}

}  // namespace wp
