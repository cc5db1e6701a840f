// The conformance suite: every method the command registers, on a free body, a heavy top with non-diagonal inertia,
// a time-dependent problem (the satellite), a Lagrange top and a rigid_body whose torque reads Ω (every torque term
// of problems/torqued_body.hpp at once: the explicit methods only), through the engine exactly as `lgi run` builds it
// (the scene's problem → its runner → lgi::Integrator, compiled in lgi_scene with the shipped flags). The cases come
// from the registry at run time (ProblemInfo::methods): a method is tested by being registered, and a method that
// is not registered is not tested. For each case:
//   - Order: the error at t = 10 against rkmk_vern9 at h = 10/16384, for h = 10/8 … 10/8192. Of the halvings
//     between the pre-asymptotic steps (error > 0.5) and round-off (error < 30× the sequence's smallest, or
//     < 1e-12), the observed order log2(e(h)/e(h/2)) closest to the declared p (MethodTraits::order,
//     free_body_order on torque-free problems) lies in [p − 0.5, p + 0.5]: a method of another order shows no
//     halving near p. Methods of order 9 and more may show up to p + 1.2: in double, above round-off, their h^(p+1)
//     terms dominate (rkmk_vern9_cayley 9.9-10.0 on the free body, the skew top and the Lagrange top, as
//     integrators/rkmk.hpp says; tests/integrators/test_quad_order.cpp measures 9.002 asymptotically in
//     binary128). The DOP853 family shows 7.5-7.6 on the satellite between h = 10/64 and 10/256 (a finding,
//     docs/findings.md). A method exact to round-off on the problem (every error ≤ 1e-12: split_exact on the free
//     body) conforms; kKnownDeviations lists the cases skipped by design, with the reason.
//   - On the group: methods that declare R on SO(3) keep ‖RᵀR − I‖_F ≤ 1e-12 over 4096 steps.
//   - No allocation: 1000 steps of the engine's loop (run_grid) after a warm-up allocate nothing (malloc counted
//     in this process).
//   - A step from a state with a NaN in Ω reports non_finite and leaves its slot's numbers untouched.
//   - Save and restore: a run saved after 37 steps and restored into a new integrator continues to the same bits as
//     the uninterrupted run.
//   - Declared traits: symplectic methods keep the energy error of 20000 steps of the skew top and the free body
//     bounded (its maximum over the run ≤ 3× its maximum over the first tenth, + 1e-11 |E0| of round-off); methods that declare momentum
//     conservation keep m·k on the heavy and Lagrange tops to 1e-11 (relative).
// Registering a broken method fails it: declaring RKMK4 of order 3 fails the order test (observed 4.00), an
// allocation in the LGVI's step fails the allocation test (1000 in 1000 steps). LGI_CONFORMANCE_DUMP=1 prints each
// case's errors.
#include "allocation_counter.hpp"
#include "fp_traps.hpp"
#include "json_reader.hpp"
#include "registry.hpp"
#include "runner_detail.hpp"
#include "scene.hpp"

#include <lgi/core/engine.hpp>
#include <lgi/core/so3.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <ostream>
#include <string>
#include <vector>


namespace lgi::app {
namespace {

// The problems of the suite: a scene's "problem" and "initial" objects.
struct ProblemCase {
  const char* name;  // the problem type
  const char* problem;
  const char* initial;
};
constexpr ProblemCase kProblems[] = {
    {"free_body", R"({"type": "free_body", "inertia": [1, 2, 3]})", R"({"omega": [1, 0.1, 0.5]})"},
    {"heavy_top",
     R"({"type": "heavy_top", "inertia": [[2, 0.1, 0], [0.1, 2.5, 0.2], [0, 0.2, 1]], "b": 1.3, "k": [0, 0.6, 0.8],
         "z0": [0.6, 0, 0.8]})",
     R"({"omega": [0.3, -0.2, 4]})"},
    {"satellite", R"({"type": "satellite", "inertia": [1, 2, 3], "n": 1, "radial": [1, 0, 0], "normal": [0, 0, 1]})",
     R"({"omega": [0.2, 1.1, 0.3]})"},
    {"lagrange_top", R"({"type": "lagrange_top", "inertia": [2, 2, 1], "b": 1, "k": [0, 0.6, 0.8]})",
     R"({"omega": [0.1, 0.2, 5]})"},
    // Every torque term at once: gravity, damping, a laboratory torque and the PD controller (the torque reads Ω).
    {"rigid_body",
     R"({"type": "rigid_body", "inertia": [[2, 0.1, 0], [0.1, 2.5, 0.2], [0, 0.2, 1]],
         "gravity": {"b": 1.3, "k": [0, 0.6, 0.8], "z0": [0.6, 0, 0.8]},
         "torques": [{"type": "damping", "matrix": [[0.3, 0.05, 0], [0.05, 0.2, 0], [0, 0, 0.1]]},
                     {"type": "constant", "frame": "lab", "torque": [0.2, -0.1, 0.3]},
                     {"type": "attitude_control", "target": {"axis_angle": {"axis": [1, 2, 0], "angle": 0.7}},
                      "target_omega": [0, 0, 0.5], "k_R": 1.5, "k_Omega": 0.4}]})",
     R"({"omega": [0.3, -0.2, 4]})"},
};

struct Case {
  std::string method;
  const ProblemCase* problem;
};

// gtest prints a case (and ctest names it) as "method on problem".
void PrintTo(const Case& c, std::ostream* os) { *os << c.method << " on " << c.problem->name; }

std::vector<Case> all_cases() {
  std::vector<Case> cases;
  for (const ProblemCase& p : kProblems) {
    const ProblemInfo* info = find_problem(p.name);
    if (!info) continue;  // a build without it (LGI_PROBLEMS)
    for (const std::string_view m : info->methods) cases.push_back({std::string(m), &p});
  }
  return cases;
}

Scene make_scene(const ProblemCase& p, const std::string& method, double dt) {
  const std::string text = std::string(R"({"problem": )") + p.problem + R"(, "initial": )" + p.initial +
                           R"(, "integrator": {"method": ")" + method + R"(", "dt": )" + format_number(dt) +
                           R"(}, "t_end": 1000})";
  return parse_scene(parse_json(text, "conformance.json"), "conformance.json");
}

class NoSink final : public RunSink {
 public:
  void observe(double, bool) override {}
  std::int64_t check(const lgi::Cursor<double>&) override { return std::int64_t{1} << 40; }
};

// Records the scene's column `column` (state_columns) at every output event.
class ColumnSink final : public RunSink {
 public:
  ColumnSink(const Scene& s, const Integrator& e, std::size_t column) : scene_(s), engine_(e), column_(column) {}
  void observe(double t, bool initial) override {
    cols_.clear();
    scene_.problem->state_columns(t, initial ? scene_.initial : engine_.state(Slot::event), cols_);
    values.push_back(cols_.at(column_));
  }
  std::int64_t check(const lgi::Cursor<double>&) override { return std::int64_t{1} << 40; }
  std::vector<double> values;

 private:
  const Scene& scene_;
  const Integrator& engine_;
  std::size_t column_;
  std::vector<double> cols_;
};

struct Engine {
  Scene scene;
  std::unique_ptr<runner_detail::ProblemRunner> runner;
  std::unique_ptr<Integrator> engine;
  lgi::Cursor<double> cursor;
  IntegrationSummary summary;

  Engine(const ProblemCase& p, const std::string& method, double h) : scene(make_scene(p, method, h)) {
    runner = scene.problem->runner();
    engine = runner->integrator(scene);
    engine->set(Slot::current, scene.initial, 0.0);
  }
  // n more grid steps (the run's loop, drive_grid); true when they all succeeded.
  bool steps(std::int64_t n, RunSink& sink) {
    const GridEvents<double> events = GridEvents<double>::steps(cursor.n + n, 0.0, scene.dt);
    cursor.event = 0;  // this chunk's one event, at its end
    bool moved = false;
    const Halt halt = engine->run_grid(scene.dt, events, std::numeric_limits<std::int64_t>::max(), cursor, summary,
                                       moved, sink);
    return halt == Halt::none && summary.status == RunStatus::completed;
  }
  bool steps(std::int64_t n) {
    NoSink sink;
    return steps(n, sink);
  }
  std::vector<double> numbers(Slot s = Slot::current) const {
    std::vector<double> v(engine->state_size());
    engine->save(s, v);
    return v;
  }
};

double distance(const State<double>& a, const State<double>& b) {
  return (a.R - b.R).norm() + (a.Omega - b.Omega).norm();
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

constexpr double kT = 10;  // the order test's horizon

// Cases whose measured order is not the declared one for a reason of the method's design, each a skipped case
// listed in the test's output.
struct KnownDeviation {
  std::string_view method, problem, why;
};
constexpr KnownDeviation kKnownDeviations[] = {
    {"split_dmv10", "free_body",
     "the DMV flow takes ceil(h|Pi|/min I) substeps (integrators/free_body_flows.hpp, dmv_substeps): here |Pi| = 1.81, "
     "min I = 1, so h = 10/16 runs 2 substeps of 10/32 and gives the error of h = 10/32 (6.774e-11 both); at 10/64 "
     "the error is round-off, so no halving in range shows order 10"},
};

class Conformance : public ::testing::TestWithParam<Case> {};

TEST_P(Conformance, ObservedOrderIsTheDeclaredOne) {
  const Case& c = GetParam();
  Engine reference(*c.problem, "rkmk_vern9", kT / 16384);
  ASSERT_TRUE(reference.steps(16384));
  const State<double> x_ref = reference.engine->state(Slot::current);

  std::vector<double> errors;
  std::vector<int> N;
  const test::FpTrapsOff no_traps;  // the largest steps may overflow: such a run fails (HUGE_VAL below)
  for (int n = 8; n <= 8192; n *= 2) {
    Engine e(*c.problem, c.method, kT / n);
    const bool ok = e.steps(n);
    errors.push_back(ok ? distance(e.engine->state(Slot::current), x_ref) : HUGE_VAL);  // HUGE_VAL: the run failed
    N.push_back(n);
  }
  for (const KnownDeviation& k : kKnownDeviations)
    if (c.method == k.method && std::string_view(c.problem->name) == k.problem) GTEST_SKIP() << k.why;
  const Engine probe(*c.problem, c.method, 0.1);
  const MethodTraits& traits = probe.engine->traits();
  const bool torque_free = probe.scene.problem->torque_free();
  const int declared = torque_free && traits.free_body_order != 0 ? traits.free_body_order : traits.order;
  // The observed orders of the halvings between the pre-asymptotic steps (errors above 0.5) and round-off (errors
  // below 30 times the smallest error of the sequence, within [1e-12, 1e-9]).
  const double floor = std::clamp(30 * *std::min_element(errors.begin(), errors.end()), 1e-12, 1e-9);
  std::vector<double> observed;
  std::string table;
  for (std::size_t i = 0; i < errors.size(); ++i) {
    table += "  h = T/" + std::to_string(N[i]) + ": " + format_number(errors[i]) + "\n";
    if (i + 1 < errors.size() && errors[i] <= 0.5 && errors[i + 1] >= floor)
      observed.push_back(std::log2(errors[i] / errors[i + 1]));
  }
  if (observed.empty() && *std::max_element(errors.begin(), errors.end()) <= 1e-12)
    return;  // exact to round-off on this problem (split_exact on the free body)
  ASSERT_FALSE(observed.empty()) << c.method << " on " << c.problem->name << ": no halving in range\n" << table;
  // The halving closest to the declared order: a method of another order shows none near it.
  const double p = *std::min_element(observed.begin(), observed.end(), [&](double a, double b) {
    return std::abs(a - declared) < std::abs(b - declared);
  });
  EXPECT_GE(p, declared - 0.5) << c.method << " on " << c.problem->name << " declares order " << declared << "\n"
                               << table;
  EXPECT_LE(p, declared + (declared >= 9 ? 1.2 : 0.5)) << c.method << " on " << c.problem->name << " declares order " << declared << "\n"
                               << table;
}

TEST_P(Conformance, StaysOnTheGroupAndAllocatesNothing) {
  const Case& c = GetParam();
  Engine e(*c.problem, c.method, 1.0 / 256);
  ASSERT_TRUE(e.steps(8));  // warm-up: anything a first step sets up once
  const long before = test::allocations();
  ASSERT_TRUE(e.steps(1000));
  const long allocations = test::allocations() - before;
  if (test::counting_allocations) {
    EXPECT_EQ(allocations, 0) << c.method << " on " << c.problem->name;
  }
  ASSERT_TRUE(e.steps(3088));
  if (e.engine->traits().exact_on_group) {
    EXPECT_LE(so3::orthogonality_error(e.engine->state(Slot::current).R), 1e-12) << c.method;
  }
}

TEST_P(Conformance, AFailedStepLeavesItsSlotUntouched) {
  const Case& c = GetParam();
  Engine e(*c.problem, c.method, 0.01);
  const test::FpTrapsOff no_traps;  // the overflow is the point
  State<double> x = e.scene.initial;
  x.Omega = Vec3<double>(std::nan(""), 0.1, 0.2);
  e.engine->set(Slot::scratch, x, 0.0);
  const std::vector<double> before = e.numbers(Slot::scratch);
  const StepStatus status = e.engine->step(Slot::scratch, 0.0, 0.01);
  EXPECT_EQ(status, StepStatus::non_finite) << c.method << ": a step from Omega = (NaN, 0.1, 0.2)";
  EXPECT_TRUE(same_bits(before, e.numbers(Slot::scratch))) << c.method << ": the failed step changed its slot";
}

TEST_P(Conformance, SaveAndRestoreContinueToTheSameBits) {
  const Case& c = GetParam();
  Engine straight(*c.problem, c.method, 0.01);
  ASSERT_TRUE(straight.steps(37));
  const std::vector<double> saved = straight.numbers();
  const lgi::Cursor<double> at = straight.cursor;
  ASSERT_TRUE(straight.steps(50));

  Engine resumed(*c.problem, c.method, 0.01);  // a new integrator, as a resumed run builds one
  resumed.engine->restore(Slot::current, saved);
  resumed.cursor = at;
  ASSERT_TRUE(resumed.steps(50));
  EXPECT_TRUE(same_bits(straight.numbers(), resumed.numbers())) << c.method << " on " << c.problem->name;
}

TEST_P(Conformance, DeclaredTraitsHold) {
  const Case& c = GetParam();
  const std::string problem = c.problem->name;
  Engine probe(*c.problem, c.method, 0.01);
  const MethodTraits& traits = probe.engine->traits();
  const std::vector<std::string_view> names = probe.scene.problem->invariant_names();
  constexpr std::size_t energy_column = 13;  // t, R (9), Omega (3), energy
  const std::size_t first_invariant = energy_column + 2;
  if (traits.symplectic && (problem == "free_body" || problem == "heavy_top")) {
    Engine e(*c.problem, c.method, 0.01);
    ColumnSink sink(e.scene, *e.engine, energy_column);
    const GridEvents<double> events(std::int64_t{100}, 0.0, 200.0, 0.01);
    bool moved = false;
    ASSERT_EQ(e.engine->run_grid(0.01, events, std::numeric_limits<std::int64_t>::max(), e.cursor, e.summary, moved,
                                 sink),
              Halt::none);
    const double E0 = sink.values.at(0);
    double first = 0, all = 0;
    for (std::size_t i = 1; i < sink.values.size(); ++i) {
      const double d = std::abs(sink.values[i] - E0);
      all = std::max(all, d);
      if (i <= sink.values.size() / 10) first = std::max(first, d);
    }
    EXPECT_LE(all, 3 * first + 1e-11 * std::abs(E0))  // round-off: 20000 steps of ≤ 1e-15 relative
        << c.method << " declares symplectic: energy error " << first << " over t <= 20, " << all << " over t <= 200";
  }
  const auto k = std::find(names.begin(), names.end(), "momentum_k");
  if (traits.preserves_momentum && k != names.end()) {
    Engine e(*c.problem, c.method, 0.01);
    ColumnSink sink(e.scene, *e.engine, first_invariant + static_cast<std::size_t>(k - names.begin()));
    const GridEvents<double> events(std::int64_t{1000}, 0.0, 200.0, 0.01);
    bool moved = false;
    ASSERT_EQ(e.engine->run_grid(0.01, events, std::numeric_limits<std::int64_t>::max(), e.cursor, e.summary, moved,
                                 sink),
              Halt::none);
    const double m0 = sink.values.at(0);
    for (const double m : sink.values)
      ASSERT_LE(std::abs(m - m0), 1e-11 * std::max(1.0, std::abs(m0))) << c.method << " declares m.k conserved";
  }
}

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  return info.param.method + "_" + info.param.problem->name;
}

INSTANTIATE_TEST_SUITE_P(Registered, Conformance, ::testing::ValuesIn(all_cases()), case_name);

}  // namespace
}  // namespace lgi::app
