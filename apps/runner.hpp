// lgi/apps/runner.hpp — running a loaded scene: CSV rows at the output times, a summary at the end.
//
// CSV (shared/DESIGN.md §3): a header row, then one row per output time with the columns
//   t, R11 … R33 (row-major), omega1 … omega3, energy, orthogonality_error (‖RᵀR − I‖_F),
// followed by the problem's own invariants (heavy_top: momentum_k = m·k; free_body: momentum_1..3 = m,
// momentum_norm = |JΩ|). Numbers carry 17 significant digits.
#pragma once

#include "scene.hpp"

#include <lgi/core/driver.hpp>

#include <csignal>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace lgi::app {

struct RunOptions {
  std::FILE* csv = nullptr;                         // rows go here; nullptr: no rows
  bool progress = false;                            // a progress line on stderr (for terminals)
  const volatile std::sig_atomic_t* stop = nullptr;  // the run stops when *stop becomes non-zero
};

struct InvariantChange {
  std::string name;
  double initial, final;
};

struct RunReport {
  IntegrationSummary summary;
  std::int64_t expected_steps = 0;
  State<double> final_state;
  double energy_initial = 0, energy_final = 0;
  std::vector<InvariantChange> invariants;  // the problem's own, initial and final values
  double wall_seconds = 0;
  std::int64_t newton_iterations = -1;  // implicit methods only
  bool write_failed = false;            // the CSV stream reported an error
};

RunReport run_scene(const Scene& scene, const RunOptions& options);

// The few lines `lgi run` prints on stderr: method, steps, energy error, orthogonality, wall time.
std::string brief_report(const Scene& scene, const RunReport& report);

// The CSV header row for a scene's problem (without the newline).
std::string csv_header(const Scene& scene);

}  // namespace lgi::app
