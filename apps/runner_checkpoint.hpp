// lgi/apps/runner_checkpoint.hpp — checkpoints of `lgi run`: all a stopped run needs to continue bit for bit.
//
// A run's future depends on (1) the scene, (2) where the driver is, (3) the stepper's internal state, and
// nothing else: steppers keep no state between steps but counters (core/integrator.hpp; checked for every
// method of apps/registry.hpp — no Newton warm start, no FSAL stage reused, no step-size memory; the
// adaptive steps' memory is the driver's, below). The stepper's numbers are those its Internal type lists
// (core/state_io.hpp, LGI_NUMBERS), in that order. A checkpoint (format 2) is a JSON file holding, in this order,
//   - "lgi_checkpoint": 2, lgi's version, the scene file's name, the method, "t" and "state" (R, Ω) in decimal
//     for people (not read back);
//   - "cursor": fixed steps — the grid index n (t = n·dt), the index of the next output event, the steps taken;
//     adaptive steps (integrators/adaptive.hpp's loop variables) — t, the step h the controller proposes,
//     err_{n−1} (the PI controller's memory), whether the last trial was rejected, what drove h down, the
//     attempted, accepted and rejected steps, the index of the next output time;
//   - "internal": the stepper's coordinates exactly, as hexadecimal floats ("%a": strtod reads them back bit for
//     bit): R and Π (not Ω) and the torque carried to the next step's first kick for the variational methods,
//     the quaternion for the splittings and the quaternion embedding, the projection's target values;
//   - "output": the target file name, the file holding the rows so far (the temporary file while the run goes,
//     the target once a stopped run renamed it), how many of its bytes belong to the run at this point, and
//     FNV-1a hashes of their first and last 4 KiB (a resume refuses a file that does not match);
//   - the time of the last row written, with its quaternion columns where the scene's "output.columns" has them
//     (their sign continues from it: output_columns.hpp), the checkpoint interval, the scene's JSON document;
//   - "inputs", where the scene reads other files (a torque table): each file's path and the FNV-1a 64 hash of its
//     bytes when the run started (a resume refuses a file that changed since);
//   - "checksum": FNV-1a 64 (hashing.hpp) of the whole document in canonical form without this member. A file
//     changed or damaged anywhere (a flipped byte, a cut, an edited value) is refused with one line before any of
//     it is used; semantic checks (cursor against the scene, the stepper's size) follow when the run resumes.
// Written atomically (a temporary file beside it, fsync, rename, fsync of the directory), after the rows
// it counts were flushed and fsynced: a SIGKILL at any moment leaves the previous or the new checkpoint, and
// the rows it counts.
#pragma once

#include "json_reader.hpp"

#include <lgi/core/driver.hpp>
#include <lgi/core/integrator.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace lgi::app {

// Where a driver is: enough to continue a run bit for bit, with the stepper's state (core/driver.hpp).
using Cursor = lgi::Cursor<double>;

// Where the rows of a run are.
struct CheckpointOutput {
  std::string target;   // the -o FILE of the run
  std::string partial;  // the file holding the rows so far
  std::uint64_t bytes = 0;
  std::uint64_t head_hash = 0, tail_hash = 0;  // FNV-1a of the first and the last min(bytes, 4096) bytes
};

struct Checkpoint {
  std::string scene_file;
  json scene;  // the scene document
  std::string method;
  Cursor cursor;
  std::vector<double> internal;
  CheckpointOutput output;
  std::vector<double> output_quaternion;  // the last row's quaternion columns ("output.columns"; empty: none)
  bool has_last_row = false;
  double last_row_t = 0;
  std::int64_t every_steps = 0;  // the checkpoint interval of the run (one of the two, or neither)
  double every_seconds = 0;
  double t = 0;  // the time of the state (informational: the cursor is what is read)
  std::vector<double> R, omega;  // informational
  std::vector<std::pair<std::string, std::uint64_t>> inputs;  // the files the scene read, with their hashes
};

// The word a checkpoint, a sweep's status column and the summaries use for a step status ("not_converged", ...).
std::string step_status_token(StepStatus s);

// The hashes of the first `bytes` bytes of the open file `fd` (CheckpointOutput::head_hash and tail_hash);
// false if they cannot be read.
bool output_hashes(int fd, std::uint64_t bytes, std::uint64_t& head, std::uint64_t& tail);

// Writes `checkpoint` to `path` atomically; false with `error` set on failure (the previous file is kept). On
// success `*checksum` (when given) receives the file's checksum: what is_own_checkpoint recognises it by.
bool write_checkpoint(const std::string& path, const Checkpoint& checkpoint, const std::string& version,
                      std::string& error, std::string* checksum = nullptr);
// Reads a checkpoint; one that is malformed, of another format, or changed anywhere (its checksum) is an
// InputError naming the file and the JSON path.
Checkpoint read_checkpoint(const std::string& path);
// The same for a checkpoint's bytes; `path` names it in messages.
Checkpoint parse_checkpoint(const std::string& text, const std::string& path);
// True if `path` is a regular file holding exactly the checkpoint whose checksum is `checksum` (one this process
// wrote and nobody changed since): the only checkpoint file lgi removes.
bool is_own_checkpoint(const std::string& path, const std::string& checksum);
// True if `path` is a regular file whose bytes begin as every checkpoint file does (or are a prefix of that:
// empty or cut short) — a temporary file of write_checkpoint that a kill left behind.
bool is_checkpoint_temporary(const std::string& path);

}  // namespace lgi::app
