// lgi/apps/run_messages.hpp — what `lgi run` says of a run that did not complete, shared by the command (main.cpp) and
// the Python package (python/lgi_module.cpp), so that both say it in the same words.
#pragma once

#include "command.hpp"
#include "runner.hpp"
#include "scene.hpp"

#include <csignal>
#include <string>
#include <utility>

namespace lgi::app {

// Why a run that did not complete stopped — "the step from t = … failed: …", "stopped by /limits/max_steps = …",
// "interrupted by SIGINT at …" — and the exit status `lgi run` takes for it: exit_run_failed, exit_run_stopped, or
// 128 + signal (`signal`: the signal that stopped it, for StopReason::signal). Not for a completed run.
inline std::pair<int, std::string> incomplete_run(const Scene& scene, const RunReport& report, int signal) {
  const IntegrationSummary& s = report.summary;
  const std::string at = "t = " + format_number(s.t) + " after " + std::to_string(s.steps) + " steps";
  std::string message;
  int status = exit_run_failed;
  switch (report.stop_reason) {
    case StopReason::none:  // a failed step
      message = "the step from t = " + format_number(s.t) + " failed: " + std::string(lgi::to_string(s.step_status)) +
                " (step " + std::to_string(s.steps + 1) + " of the run";
      if (s.step_status == StepStatus::not_converged) {
        // The implicit equation of the LGVI (and of its compositions' substeps) has no solution once h|Ω| passes
        // about 1 (exactly 1 about a principal axis: docs/findings.md): no iteration limit helps there.
        const double w = report.final_state.Omega.norm(), hw = scene.dt * w;
        if (hw > 0.5)
          message += "; h|omega| = " + format_number(hw) + " at the last good state, where the implicit equation of " +
                     std::string(scene.method->traits.name) + " may have no solution (none beyond h|omega| = 1 about a principal "
                     "axis): take /integrator/dt below " + format_number(0.5 / w) +
                     ", or split_dmv, which takes substeps there)";
        else
          message += "; try a smaller /integrator/dt, or raise /integrator/max_iterations)";
      }
      else if (s.step_status == StepStatus::non_finite)
        message += "; the solution overflowed or the torque returned NaN; try a smaller /integrator/dt)";
      else if (s.step_status == StepStatus::step_size_underflow)
        message += "; raise /integrator/rtol or /integrator/atol)";
      else
        message += ")";
      break;
    case StopReason::left_domain:
      message = "stopped at " + at + ": the Euler angles left their domain (see the warning)";
      break;
    case StopReason::write_failed:  // handled above
      break;
    case StopReason::signal:
      status = 128 + signal;
      message = std::string("interrupted by ") + (signal == SIGINT ? "SIGINT" : "SIGTERM") + " at " + at;
      break;
    case StopReason::max_steps:
      status = exit_run_stopped;
      message = scene.max_steps > 0 ? "stopped by /limits/max_steps = " + std::to_string(scene.max_steps) + " at " + at
                                    : "stopped at " + at + ": the adaptive driver's limit of 1e9 attempted steps "
                                                           "(set /limits/max_steps)";
      break;
    case StopReason::max_wall_seconds:
      status = exit_run_stopped;
      message = "stopped by /limits/max_wall_seconds = " + format_number(scene.max_wall_seconds) + " at " + at;
      break;
  }
  return {status, message};
}

}  // namespace lgi::app
