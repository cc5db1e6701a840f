// lgi/fuzz/scene_fuzzer.cpp — libFuzzer harness: the scene loader, then ten steps of what it accepted.
//
// Every input is parsed as a scene file's bytes (apps/json_reader.cpp parse_json, apps/scene.cpp
// parse_scene). The loader's contract (apps/scene.hpp) is checked as an oracle, not merely "no crash":
//   - a rejected input ends in one InputError whose message is a single printable line starting with
//     the file name ("fuzz.json: …" or "fuzz.json:<line>:<column>: …"); any other exception escapes and
//     libFuzzer reports it as a crash;
//   - an accepted scene is runnable: dt > 0 and finite, 0 ≤ t_end finite, t_end/dt within
//     max_scene_steps, R on SO(3) to 1e-12, Ω finite, output times increasing within [0, t_end].
// Then the accepted scene runs ten steps (t_end clamped to 10·dt, output times beyond it dropped)
// through the same drivers `lgi run` uses, with a small fixed method set rather than the scene's
// method — the whole method × problem table under ASan would cost the CI minutes of compile time
// (apps/runner_detail.hpp): LGVI (implicit, Newton with the scene's tolerance and max_iterations) and
// RKMK4 (explicit; projected when the scene asks for projection) on SO(3) problems, classical RK4 on the
// Euler-angle top's R^6 state. A step may fail (non-finite, Newton not converged): that is a status, not
// a crash; what it must not do is trip ASan or UBSan, throw, or hang.
//
// Build and run: scripts/fuzz.sh (clang++ -fsanitize=fuzzer,address,undefined; fuzz/CMakeLists.txt).
#include "json_reader.hpp"
#include "registry.hpp"
#include "scene.hpp"

#include <lgi/core/driver.hpp>
#include <lgi/core/so3.hpp>
#include <lgi/integrators/euclidean_rk.hpp>
#include <lgi/integrators/lgvi.hpp>
#include <lgi/integrators/projection.hpp>
#include <lgi/integrators/rkmk.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

namespace {

using namespace lgi;
using namespace lgi::app;

constexpr const char* kFile = "fuzz.json";

[[noreturn]] void contract_violated(const char* what, const std::string& detail) {
  std::fprintf(stderr, "scene_fuzzer: contract violated: %s\n%s\n", what, detail.c_str());
  std::abort();
}

// A rejected input: one line, printable, naming the file first.
void check_message(const std::string& m) {
  if (m.rfind(kFile, 0) != 0 || m.size() <= std::string_view(kFile).size() ||
      (m[std::string_view(kFile).size()] != ':'))
    contract_violated("the message does not start with the file name", m);
  for (const char c : m)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) contract_violated("a control character in the message", m);
}

// An accepted scene: what scene.hpp promises ("a Scene that loads is runnable").
void check_scene(const Scene& s) {
  if (!s.method) contract_violated("no method", "");
  if (!(s.dt > 0) || !std::isfinite(s.dt)) contract_violated("dt", format_number(s.dt));
  if (!(s.t_end >= 0) || !std::isfinite(s.t_end)) contract_violated("t_end", format_number(s.t_end));
  if (!(s.t_end / s.dt <= max_scene_steps)) contract_violated("steps", format_number(s.t_end / s.dt));
  if (!s.initial.R.allFinite() || !s.initial.Omega.allFinite()) contract_violated("initial state not finite", "");
  if (!(so3::orthogonality_error(s.initial.R) <= 1e-12) || !(s.initial.R.determinant() > 0))
    contract_violated("initial R not a rotation", format_number(so3::orthogonality_error(s.initial.R)));
  for (std::size_t i = 0; i < s.output_times.size(); ++i)
    if (!(s.output_times[i] >= 0 && s.output_times[i] <= s.t_end) ||
        (i > 0 && !(s.output_times[i] > s.output_times[i - 1])))
      contract_violated("output times", format_number(s.output_times[i]));
  if (s.output_every < 0) contract_violated("output.every", std::to_string(s.output_every));
}

// Ten steps of stepper S on the scene's grid: integrate_times (output times up to the clamped end) or
// integrate_every, as the runner does (apps/runner_impl.hpp).
template <class S>
void ten_steps(S& stepper, const Scene& scene, double t_end) {
  State<double> x = scene.initial;
  if (!scene.output_times.empty()) {
    std::vector<double> times;
    for (const double t : scene.output_times)
      if (t <= t_end) times.push_back(t);
    if (times.empty() || times.back() < t_end) times.push_back(t_end);
    (void)integrate_times(stepper, x, 0.0, scene.dt, std::span<const double>(times));
  } else {
    const std::int64_t every = scene.output_every > 0 ? scene.output_every : std::int64_t{1} << 62;
    (void)integrate_every(stepper, x, 0.0, scene.dt, t_end, every);
  }
}

template <class P>
void run(const P& problem, const Scene& scene, double t_end) {
  if constexpr (std::is_same_v<P, EulerAngleTop<double>>) {
    // The Euler-angle top: the runner's own path (plain RK on R^6), as for "rkmk4" in a scene.
    const EuclideanRk<tableaus::classical_rk4, EulerAngleTop<double>> stepper(problem);
    typename EulerAngleTop<double>::Vector y = problem.from_state(scene.initial);
    if (!problem.admissible(y)) return;  // the runner stops at t = 0 (apps/runner_impl.hpp)
    const std::int64_t every = scene.output_every > 0 ? scene.output_every : std::int64_t{1} << 62;
    (void)integrate_every_euclidean(stepper, y, 0.0, scene.dt, t_end, every);
  } else {
    if constexpr (method_applies_v<Lgvi, P>) {
      Lgvi<P> lgvi(problem, scene.options);
      ten_steps(lgvi, scene, t_end);
    }
    if constexpr (method_applies_v<Rkmk4, P>) {
      if constexpr (ProjectableStepper<Rkmk4<P>>) {
        if (scene.options.projection) {
          Projected<Rkmk4<P>> projected(problem, scene.options);
          ten_steps(projected, scene, t_end);
          return;
        }
      }
      Rkmk4<P> rkmk4(problem, scene.options);
      ten_steps(rkmk4, scene, t_end);
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // read_json_file refuses larger files before parsing (tests/test_malformed_scenes.cpp checks that).
  if (size > max_input_bytes) return 0;
  const std::string text(reinterpret_cast<const char*>(data), size);
  Scene scene;
  try {
    scene = parse_scene(parse_json(text, kFile), kFile);
  } catch (const InputError& e) {
    check_message(e.what());
    return 0;
  }
  check_scene(scene);
  const double t_end = std::min(scene.t_end, 10 * scene.dt);
  std::visit([&](const auto& problem) { run(problem, scene, t_end); }, scene.problem);
  return 0;
}
