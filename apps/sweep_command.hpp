// lgi/apps/sweep_command.hpp — `lgi sweep SWEEPFILE -o OUT.csv [--threads N] [--shard i/N] [--no-batch] [-q]` and
// `lgi merge PART... -o OUT.csv` (docs/sweep.md has the whole contract).
//
// A sweep file is a scene file (shared/DESIGN.md §3) plus a top-level "sweep" section:
//
//   "sweep": {
//     "grid":   { "/initial/omega/2": [2, 4, 6],                            values, in this order
//                 "/problem/b": {"from": 0.5, "to": 2, "count": 4, "log": false} },
//     or
//     "random": { "seed": 7, "count": 1000, "ranges": { "/initial/omega/0": [-1, 1], ... } },
//     "record": ["status", "final", "invariants"]                           default: all three, this order, and
//                                                                           each of the three below that is given
//     "extrema": ["tilt", ...], "section": {...}, "lyapunov": {...}         records taken during the run
//   }
//
// Members. Each key is a JSON pointer (RFC 6901) into the scene document that must name a number there.
// A grid's members are the Cartesian product of its axes, the keys taken in the order of the JSON object as
// the loader stores it — sorted by key (byte order) — with the LAST key varying fastest: member m has index
// m mod n_last on the last axis, (m / n_last) mod n_prev on the one before, and so on. {"from", "to",
// "count"} gives v_k = from + ((to - from) * k) / (count - 1) (log: v_k = exp(ln from + ((ln to - ln from) * k)
// / (count - 1)), from, to > 0), k = 0 … count - 1, with v_0 = from and v_{count-1} = to exactly; count 1 gives
// from. A random sweep's member m sets key K to lo + (hi - lo) * u, u = (splitmix64 of (seed, m, K)) >> 11
// times 2^-53 in [0, 1) (sweep_uniform below): the value depends only on the seed, the member index and the
// pointer text — not on the other keys, the thread or shard that runs it, or the platform's <random>.
// Each member is the scene with the pointers set to its values, loaded by parse_scene (so the loader
// validates every member: a bad value is exit 1 naming the member and the pointer) and run by run_scene.
//
// Output: one CSV (17 significant digits, as `lgi run` writes): the header
//   member, <the pointers, in member-axis order>, <the recorded columns>
// and one row per member in member order. "status": status (completed, or why the run ended: the step's
// status — not_converged, non_finite, step_size_underflow, ... —, left_domain, max_steps) and steps;
// "final": the columns of `lgi run`'s last row (t, R11…R33, omega1…omega3, energy, orthogonality_error, the
// problem's own columns), computed by the same code as that row and equal to it character for character;
// "invariants": energy_rel_change and <integral>_rel_change for the problem's integrals of the motion, |final −
// initial| / |initial| (/ 1 when initial is 0). A member whose step fails is a row with its status and last good
// state, not an error: the sweep exits 0 and the summary counts them. No row holds an infinity or a NaN: a recorded
// number that is not finite is an empty field, and the member's status says so (non_finite, or not_finite when the
// run completed).
// Nothing in the CSV depends on the wall clock, the thread count or the shard: "limits.max_wall_seconds" is
// refused in a sweep. The scene's "output" is ignored (no rows: no side-steps to output times).
//
// Records taken during the run (sweep_observe.hpp): "extrema" (columns <f>_min, <f>_max), "lyapunov" (lyapunov,
// lyapunov_t), "crossings" (the count; the crossings themselves go to crossings_path(OUT), one row each, in member
// order, sharded and merged like the rows).
//
// The batched path (sweep_command.cpp, batch_steps): LGVI sweeps of one heavy top or free body with diagonal J,
// the members differing only under /initial/ and in /problem/b, t_end a whole number (≤ 2^20) of steps, nothing
// recorded during the run, run in blocks through integrate_batch_lgvi (integrators/batch_lgvi.hpp) — the same
// bytes as member by member (--no-batch, SweepCommandOptions::batch = false).
//
// --threads N (0: all cores; default 1): workers take members in turn; rows are written in member order, so
// the file is byte-identical for every N. --shard i/N runs the members m with m mod N = i and writes a part
// file: its first line "# lgi sweep shard i/N: M members, sweep HASH, lgi VERSION" (HASH: FNV-1a 64 of the
// sweep document as nlohmann::json::dump() writes it), then the header and its rows, and last the check line
// "# lgi sweep part end: fnv1a64 HASH" over every byte before it (sweep_part.hpp). `lgi merge` takes all N
// parts of one sweep (any order), checks them (each part's bytes against its check line; same sweep, version,
// header; every shard once; each part's rows exactly its members, of the header's width) and writes the file the
// serial run writes, byte for byte.
//
// Exit status (command.hpp): 0 done (members whose step failed included); 1 bad command line, sweep file,
// member or part (one message naming the file, the JSON path or line, and the problem; no output file);
// 3 the output could not be written (the first failed write stops the sweep); 4 internal error. -o is required:
// a file is written atomically; -o -, a device or a FIFO is streamed to (not with crossings, whose file goes beside
// the output). A worker thread the system refuses is a warning: the sweep goes on with the others (same bytes).
#pragma once

#include "json_reader.hpp"

#include <cstdint>
#include <csignal>
#include <string>
#include <vector>

namespace lgi::app {

struct SweepCommandOptions {
  std::string sweep_file;
  // When set, the sweep is this document (parse_sweep), not sweep_file's contents: sweep_file then only names it in
  // messages, and file names in it resolve from sweep_file's directory (the current one for a name without one,
  // such as "<dict>"). The Python package's lgi.sweep.
  const json* document = nullptr;
  std::string output;  // required
  int threads = 1;     // 0: std::thread::hardware_concurrency()
  std::string shard;   // "i/N"; empty: all members
  bool quiet = false;  // nothing on stderr but errors
  bool progress = false;  // progress lines also when stderr is not a terminal (on a terminal it always shows)
  // Run qualifying sweeps through the batched LGVI kernel (sweep_command.cpp, batch_steps); false: member by member
  // (the same bytes; for comparison).
  bool batch = true;
  // When *stop becomes non-zero (a signal number: `lgi` sets it on SIGINT and SIGTERM) the sweep stops — a
  // running member at its next monitor call (about every 10 ms of work), the others before they start — and exits
  // 128 + signal with nothing written: a partial sweep is not kept (rerun it, or run shards).
  const volatile std::sig_atomic_t* stop = nullptr;
};

struct MergeCommandOptions {
  std::vector<std::string> parts;
  std::string output;  // required
  bool quiet = false;
};

int sweep_command(const SweepCommandOptions& options);

// The crossings file written beside OUTPUT when a sweep records crossings: OUTPUT with its ".csv" replaced by
// ".crossings.csv" (OUTPUT + ".crossings.csv" when it does not end in ".csv"). Part files have theirs too.
std::string crossings_path(const std::string& output);
int merge_command(const MergeCommandOptions& options);

// The random sweep's uniform number in [0, 1) for (seed, member, pointer): splitmix64 (Steele, Lea & Flood,
// "Fast splittable pseudorandom number generators", OOPSLA 2014; the finaliser of Vigna's splitmix64.c)
// chained over seed, FNV-1a 64 of the pointer text and the member index; the top 53 bits times 2^-53.
double sweep_uniform(std::uint64_t seed, std::uint64_t member, const std::string& pointer);

}  // namespace lgi::app
