// lgi/apps/runner_checkpoint.hpp — checkpoints of `lgi run`: all a stopped run needs to continue bit for bit.
//
// A run's future depends on (1) the scene, (2) where the driver is, (3) the stepper's internal state, and
// nothing else: steppers keep no state between steps but counters (core/integrator.hpp; checked for every
// method of apps/registry.hpp — no Newton warm start, no FSAL stage reused, no step-size memory; the
// adaptive steps' memory is the driver's, below). A checkpoint (format 2) is a JSON file holding, in this order,
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
//   - the time of the last row written, the checkpoint interval, the scene's JSON document as loaded;
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
#include <span>
#include <string>
#include <type_traits>
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
  bool has_last_row = false;
  double last_row_t = 0;
  std::int64_t every_steps = 0;  // the checkpoint interval of the run (one of the two, or neither)
  double every_seconds = 0;
  double t = 0;  // the time of the state (informational: the cursor is what is read)
  std::vector<double> R, omega;  // informational
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

// ---- the stepper's internal state as numbers --------------------------------------------------------------
// for_each_number(y, f) calls f(double&) on every number of an Internal (core/state.hpp, the steppers of
// integrators/), in a fixed order; internal_size<Y>() counts them. A new Internal type must be added here: the
// static_assert below refuses one whose size is not accounted for (a member this does not know of).

template <class>
inline constexpr bool unknown_internal = false;

template <class U>
constexpr std::size_t internal_size() {
  using std::declval;
  if constexpr (requires { U::SizeAtCompileTime; }) {  // an Eigen vector or matrix of doubles
    static_assert(std::is_same_v<typename U::Scalar, double>);
    return static_cast<std::size_t>(U::SizeAtCompileTime);
  } else if constexpr (requires(U& u) { u.y; u.target.energy; u.target.second; }) {  // Projected<S>::Internal
    return internal_size<decltype(declval<U&>().y)>() + 2;
  } else if constexpr (requires(U& u) { u.w; u.v; }) {  // Quaternion
    return 1 + internal_size<decltype(declval<U&>().v)>();
  } else if constexpr (requires(U& u) { u.q; u.Pi; u.M; u.psi; }) {  // lagrange_split: turning frame and spin angle
    return internal_size<decltype(declval<U&>().q)>() + 7;
  } else if constexpr (requires(U& u) { u.q; u.Pi; u.M; }) {  // Splitting: quaternion, momentum, torque
    return internal_size<decltype(declval<U&>().q)>() + 6;
  } else if constexpr (requires(U& u) { u.R; u.Pi; u.M; }) {  // LGVI, split_exact
    return 15;
  } else if constexpr (requires(U& u) { u.q; u.Omega; }) {  // QuatState
    return internal_size<decltype(declval<U&>().q)>() + 3;
  } else if constexpr (requires(U& u) { u.R; u.Omega; }) {  // State
    return 12;
  } else if constexpr (requires(U& u) { u.R; u.Pi; }) {  // MomentumState
    return 12;
  } else {
    static_assert(unknown_internal<U>, "lgi checkpoints: an Internal type runner_checkpoint.hpp does not know");
    return 0;
  }
}

template <class Y, class F>
void for_each_number(Y& y, F&& f) {
  using U = std::remove_const_t<Y>;
  // All of it is doubles (padding only to the type's alignment): nothing is left out.
  static_assert(sizeof(U) == (internal_size<U>() * sizeof(double) + alignof(U) - 1) / alignof(U) * alignof(U),
                "lgi checkpoints: an Internal type has members runner_checkpoint.hpp does not serialise");
  if constexpr (requires { U::SizeAtCompileTime; }) {
    for (Eigen::Index i = 0; i < y.size(); ++i) f(y.data()[i]);
  } else if constexpr (requires(U& u) { u.y; u.target.energy; u.target.second; }) {
    for_each_number(y.y, f);
    f(y.target.energy);
    f(y.target.second);
  } else if constexpr (requires(U& u) { u.w; u.v; }) {
    f(y.w);
    for_each_number(y.v, f);
  } else if constexpr (requires(U& u) { u.q; u.Pi; u.M; u.psi; }) {
    for_each_number(y.q, f);
    for_each_number(y.Pi, f);
    for_each_number(y.M, f);
    f(y.psi);
  } else if constexpr (requires(U& u) { u.q; u.Pi; u.M; }) {
    for_each_number(y.q, f);
    for_each_number(y.Pi, f);
    for_each_number(y.M, f);
  } else if constexpr (requires(U& u) { u.R; u.Pi; u.M; }) {
    for_each_number(y.R, f);
    for_each_number(y.Pi, f);
    for_each_number(y.M, f);
  } else if constexpr (requires(U& u) { u.q; u.Omega; }) {
    for_each_number(y.q, f);
    for_each_number(y.Omega, f);
  } else if constexpr (requires(U& u) { u.R; u.Omega; }) {
    for_each_number(y.R, f);
    for_each_number(y.Omega, f);
  } else {
    for_each_number(y.R, f);
    for_each_number(y.Pi, f);
  }
}

}  // namespace lgi::app
