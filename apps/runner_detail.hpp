// lgi/apps/runner_detail.hpp — what the runner's translation units share (internal to apps/).
//
// The runner is compiled in parts, one translation unit per registered problem (runner_part.cpp.in,
// configured by apps/CMakeLists.txt), because every problem instantiates every method that applies to it
// (with and without projection, fixed-step and adaptive drivers): in one translation unit that took over
// seven minutes at -O3. runner.cpp dispatches on the scene's problem to run_problem<P>, which each part
// instantiates for one P; a part missing for a problem is a link error, and runner.cpp checks the count.
#pragma once

#include "runner.hpp"

#include <lgi/core/so3.hpp>

#include <array>
#include <charconv>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <string>

namespace lgi::app {

// Runs `scene` whose problem is `problem` (the scene's variant holds a P): defined in runner_impl.hpp,
// instantiated once per problem in the runner parts.
template <class P>
RunReport run_problem(const P& problem, const Scene& scene, const RunOptions& options);

namespace runner_detail {

using Clock = std::chrono::steady_clock;

// Formats one CSV row into a fixed buffer: no allocation per row.
class RowWriter {
 public:
  explicit RowWriter(std::FILE* out) : out_(out) {}
  void add(double x) {
    if (n_ > 0) buf_[n_++] = ',';
    n_ = static_cast<std::size_t>(
        std::to_chars(buf_.data() + n_, buf_.data() + buf_.size(), x, std::chars_format::general, 17).ptr -
        buf_.data());
  }
  void end_row() {
    buf_[n_++] = '\n';
    if (std::fwrite(buf_.data(), 1, n_, out_) != n_) failed_ = true;
    n_ = 0;
  }
  bool failed() const { return failed_; }

 private:
  std::FILE* out_;
  std::array<char, 2048> buf_{};
  std::size_t n_ = 0;
  bool failed_ = false;
};

template <class P>
std::string header_for() {
  std::string h = "t,R11,R12,R13,R21,R22,R23,R31,R32,R33,omega1,omega2,omega3,energy,orthogonality_error";
  for (const auto& name : P::invariant_names) {
    h += ',';
    h += name;
  }
  return h;
}

// The monitor: stops the run when asked (signals), and shows progress on stderr at most four times a
// second once a run has taken more than a second.
struct Progress {
  bool enabled;
  std::int64_t total;
  const volatile std::sig_atomic_t* stop;
  Clock::time_point start = Clock::now(), last = start;
  bool printed = false;
  bool operator()(std::int64_t steps) {
    if (stop && *stop != 0) return false;
    if (!enabled) return true;
    const auto now = Clock::now();
    if (now - start < std::chrono::seconds(1) || now - last < std::chrono::milliseconds(250)) return true;
    last = now;
    printed = true;
    std::fprintf(stderr, "\r  %5.1f %%  %lld of %lld steps", 100.0 * static_cast<double>(steps) / static_cast<double>(total),
                 static_cast<long long>(steps), static_cast<long long>(total));
    std::fflush(stderr);
    return true;
  }
  void finish() const {
    if (printed) std::fprintf(stderr, "\r%60s\r", "");
  }
};
}  // namespace runner_detail
}  // namespace lgi::app
