// lgi/fuzz/scene_fuzzer.cpp — libFuzzer harness: the scene loader, then ten steps of what it accepted.
//
// Every input is parsed as a scene file's bytes (apps/json_reader.cpp parse_json, apps/scene.cpp
// parse_scene). The loader's contract (apps/scene.hpp) is checked as an oracle, not merely "no crash":
//   - a rejected input ends in one InputError whose message is a single printable line starting with
//     the file name ("fuzz.json: …" or "fuzz.json:<line>:<column>: …"); any other exception escapes and
//     libFuzzer reports it as a crash;
//   - an accepted scene is runnable: dt > 0 and finite, 0 ≤ t_end finite, t_end/dt within
//     max_scene_steps, R on SO(3) to 1e-12, Ω finite, output times increasing within [0, t_end].
// Then the accepted scene runs ten steps (t_end clamped to 10·dt, output times beyond it dropped) through
// the engine `lgi run` uses (run_scene), built with the methods of LGI_FUZZ_METHODS (fuzz/CMakeLists.txt):
// the whole method × problem table under ASan would cost the CI minutes of compile time. A step may fail
// (non-finite, Newton not converged): that is a status, not a crash; what it must not do is trip ASan or
// UBSan, throw, or hang.
//
// Build and run: scripts/fuzz.sh (clang++ -fsanitize=fuzzer,address,undefined; fuzz/CMakeLists.txt).
#include "json_reader.hpp"
#include "registry.hpp"
#include "runner.hpp"
#include "scene.hpp"

#include <lgi/core/so3.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
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

// Ten steps of the scene as `lgi run` takes them (apps/runner.hpp run_scene: the engine, the scene's method with
// its options), without rows: t_end clamped to 10·dt, output times beyond it dropped.
void ten_steps(Scene scene) {
  scene.t_end = std::min(scene.t_end, 10 * scene.dt);
  std::erase_if(scene.output_times, [&](double t) { return t > scene.t_end; });
  (void)run_scene(scene, RunOptions{});
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // read_json_file refuses larger files before parsing (tests/cli/test_malformed_scenes.cpp checks that).
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
  ten_steps(std::move(scene));
  return 0;
}
