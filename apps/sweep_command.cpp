// lgi/apps/sweep_command.cpp — `lgi sweep` and `lgi merge` (sweep_command.hpp has the contract,
// docs/sweep.md the user's guide).
#include "sweep_command.hpp"

#include "command.hpp"
#include "hashing.hpp"
#include "json_reader.hpp"
#include "runner.hpp"
#include "scene.hpp"
#include "sweep_file.hpp"
#include "sweep_observe.hpp"
#include "sweep_part.hpp"

#include <lgi/core/inertia.hpp>
#include <lgi/core/invariants.hpp>
#include <lgi/core/so3.hpp>
#include <lgi/integrators/batch_lgvi.hpp>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <csignal>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>
#include <iterator>
#include <system_error>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <span>
#include <sstream>
#include <thread>
#include <vector>

namespace lgi::app {

namespace {

double relative_change(double initial, double final) {
  const double scale = std::abs(initial) > 0 ? std::abs(initial) : 1.0;
  return std::abs(final - initial) / scale;
}

enum class Outcome { completed, failed, stopped };

struct MemberResult {
  std::string row;
  std::string crossings;  // the member's rows of the crossings file
  Outcome outcome = Outcome::completed;
};

// Member m's row (and crossing rows) from its run's report: the same for a member run by the runner and one run
// in a batch (run_batch below).
MemberResult member_result(const Sweep& s, std::int64_t m, const std::vector<double>& v, const RunReport& r,
                           MemberObserver* observer) {
  MemberResult result;
  const IntegrationSummary& summary = r.summary;
  if (summary.status == RunStatus::stopped) result.outcome = Outcome::stopped;
  else if (summary.status != RunStatus::completed) result.outcome = Outcome::failed;
  std::string status = "completed";
  if (r.stop_reason == StopReason::left_domain) status = "left_domain";
  else if (r.stop_reason == StopReason::max_steps) status = "max_steps";
  else if (summary.status == RunStatus::step_failed) status = step_status_token(summary.step_status);
  else if (summary.status == RunStatus::stopped) status = "stopped";
  // The recorded numbers, each formatted as `lgi run` formats a column; one that is not finite (an energy that
  // overflowed, ...) is left empty — no NaN or infinity reaches the file, as in `lgi run` — and the member's status
  // says not_finite.
  std::string numbers;
  std::size_t status_at = std::string::npos;  // where the status goes in `numbers`
  for (const Record what : s.record) {
    if (what == Record::status) {
      status_at = numbers.size();
      numbers += ",," + std::to_string(summary.steps);
    }
    if (what == Record::final)
      for (const double x : r.final_columns) append_csv_number(numbers, x);
    if (what == Record::invariants) {
      append_csv_number(numbers, relative_change(r.energy_initial, r.energy_final));
      for (const InvariantChange& inv : r.invariants) append_csv_number(numbers, relative_change(inv.initial, inv.final));
    }
    if (what == Record::extrema) observer->append_extrema(numbers);
    if (what == Record::lyapunov) observer->append_lyapunov(numbers);
    if (what == Record::crossings) observer->append_crossing_count(numbers);
  }
  std::string cleaned;
  bool finite = true;
  for (std::size_t at = 0; at < numbers.size();) {  // ",field,field,...": drop the fields that are not finite
    const std::size_t next = std::min(numbers.find(',', at + 1), numbers.size());
    const std::string_view field(numbers.data() + at + 1, next - at - 1);
    const bool bad = field == "inf" || field == "-inf" || field == "nan" || field == "-nan";
    if (at == status_at) status_at = cleaned.size();
    cleaned += ',';
    if (bad) finite = false;
    else cleaned += field;
    at = next;
  }
  if (!finite && status == "completed") {
    status = "not_finite";
    result.outcome = Outcome::failed;
  }
  if (status_at != std::string::npos) cleaned.insert(status_at + 1, status);
  std::string& row = result.row;
  row = std::to_string(m);
  for (const double x : v) append_csv_number(row, x);
  row += cleaned;
  row += '\n';
  if (observer) result.crossings = std::move(observer->crossing_rows());
  return result;
}

MemberResult run_member(const Sweep& s, std::int64_t m, const volatile std::sig_atomic_t* stop) {
  const std::vector<double> v = member_values(s, m);
  Scene scene = member_scene(s, v, member_label(s, m, v));
  // No rows are written: no side-steps to the scene's output times (the trajectory does not depend on them).
  scene.output_times.clear();
  scene.output_every = 0;
  RunOptions options;  // no rows, no progress, no checkpoints
  options.stop = stop;
  std::optional<MemberObserver> observer;
  if (s.observe.any()) {
    observer.emplace(s.observe, body_data(scene), std::to_string(m) + ",");
    options.observer = &*observer;
  }
  return member_result(s, m, v, run_scene(scene, options), observer ? &*observer : nullptr);
}

// ---- the batched path --------------------------------------------------------------------------------------
// A sweep qualifies when every member is an LGVI run of the same heavy top or free body with diagonal J (the
// kernel's condition; integrators/batch_lgvi.hpp) over the same whole number of steps, the members differing only
// in their initial state and b: its keys are all under /initial/ or /problem/b, t_end is on the grid, no
// limits.max_steps, nothing recorded during the run. Its members then run in blocks through
// integrate_batch_lgvi, whose results equal the single-body Lgvi's bit for bit (tests/integrators/test_batch.cpp); the rows
// are built from them exactly as from the runner's report (tests/cli/test_cli_sweep.cpp compares the bytes with
// --no-batch). Members longer than batch_max_steps run one by one, so that a signal still stops them within a
// monitor call; a block (≤ batch_block_work body-steps, a fraction of a second at the batched kernels' speed:
// docs/performance.md) runs to its end before a signal is seen.
inline constexpr std::int64_t batch_max_steps = std::int64_t{1} << 20;
inline constexpr std::int64_t batch_block_work = std::int64_t{1} << 22;

// The number of steps of each member when the sweep qualifies for the batched path (0 otherwise; `why` says why).
std::int64_t batch_steps(const Sweep& s, const Scene& scene0, std::string& why) {
  const HeavyTop<double>* top = problem_as<HeavyTop<double>>(*scene0.problem);
  const FreeBody<double>* body = problem_as<FreeBody<double>>(*scene0.problem);
  const bool heavy = top != nullptr, free_body = body != nullptr;
  const auto no = [&](const std::string& reason) {
    why = reason;
    return std::int64_t{0};
  };
  if (scene0.method->traits.name != "lgvi") return no("the method is not lgvi");
  if (!heavy && !free_body) return no("the problem is not heavy_top or free_body");
  const Mat3<double>& J = heavy ? top->inertia : body->inertia;
  if (!Inertia<double>(J).diagonal) return no("the inertia tensor is not diagonal");
  for (const SweepKey& key : s.keys)
    if (key.pointer.rfind("/initial/", 0) != 0 && !(heavy && key.pointer == "/problem/b"))
      return no("the members differ in " + key.pointer + " (batched: /initial/... and /problem/b only)");
  if (s.observe.any()) return no("the sweep records extrema, crossings or Lyapunov estimates during the run");
  if (scene0.max_steps > 0) return no("the scene has limits.max_steps");
  const lgi::detail::GridPoint end = lgi::detail::locate(0.0, scene0.dt, scene0.t_end);
  if (!(scene0.t_end > 0) || !end.on_grid) return no("t_end is not a whole number of steps");
  if (end.m > batch_max_steps) return no("the members take more than 2^20 steps each (one by one, signals stop them sooner)");
  return end.m;
}

// Members k_begin … k_end − 1 of this shard (m = shard + k·shards) through the batched LGVI; results in k order.
const char* kernel_name(int kernel) {
  switch (static_cast<BatchKernel>(kernel)) {
    case BatchKernel::baseline: return "baseline";
    case BatchKernel::avx2: return "avx2";
    case BatchKernel::avx512: return "avx512";
    case BatchKernel::per_body: return "per-body";
    case BatchKernel::automatic: break;
  }
  return "none";
}

// `member` follows the member being loaded (a bad one throws), then names the block's first for the kernel.
std::vector<MemberResult> run_batch(const Sweep& s, std::int64_t k_begin, std::int64_t k_end, std::int64_t shard,
                                    std::int64_t shards, std::int64_t n_steps, BatchKernel& kernel, std::int64_t& member) {
  const auto count = static_cast<std::size_t>(k_end - k_begin);
  std::vector<std::vector<double>> values(count);
  std::vector<Scene> scenes;
  scenes.reserve(count);
  BodyBatch batch(count);
  std::vector<double> b;
  for (std::size_t i = 0; i < count; ++i) {
    const std::int64_t m = shard + (k_begin + static_cast<std::int64_t>(i)) * shards;
    member = m;
    values[i] = member_values(s, m);
    scenes.push_back(member_scene(s, values[i], member_label(s, m, values[i])));
    batch.set_state(i, scenes[i].initial);
    if (const auto* top = problem_as<HeavyTop<double>>(*scenes[i].problem)) b.push_back(top->b);
  }
  const Scene& scene0 = scenes.front();
  const double dt = scene0.dt;
  member = shard + k_begin * shards;
  // The two problem types batch_steps admits.
  if (const auto* top = problem_as<HeavyTop<double>>(*scene0.problem))
    kernel = integrate_batch_lgvi(*top, batch, 0.0, dt, n_steps, scene0.options, BatchOptions{1}, std::span<const double>(b));
  else if (const auto* body = problem_as<FreeBody<double>>(*scene0.problem))
    kernel = integrate_batch_lgvi(*body, batch, 0.0, dt, n_steps, scene0.options, BatchOptions{1}, std::span<const double>(b));
  else
    throw std::logic_error("lgi sweep: a batch of problem " + std::string(scene0.problem->type_name()));

  std::vector<MemberResult> results;
  results.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const Scene& scene = scenes[i];
    RunReport r;  // what run_scene reports for the same member (runner_impl.hpp, run_stepper and drive_grid)
    r.summary.steps = batch.steps[i];
    if (batch.status[i] == StepStatus::ok) {
      r.summary.t = scene.t_end;
    } else {
      r.summary.status = RunStatus::step_failed;
      r.summary.step_status = batch.status[i];
      r.summary.t = static_cast<double>(batch.steps[i]) * dt;
    }
    r.final_state = batch.steps[i] > 0 ? batch.state(i) : scene.initial;  // not moved: the state as given
    r.final_columns = state_columns(scene, r.summary.t, r.final_state);
    // The energy and the integrals, initial and final, from the columns (as the session does).
    const std::vector<double> initial = state_columns(scene, 0.0, scene.initial);
    r.energy_initial = initial[13];
    r.energy_final = r.final_columns[13];
    const std::vector<std::string> names = integral_names(scene);
    for (std::size_t j = 0; j < names.size(); ++j)
      r.invariants.push_back({names[j], initial[15 + j], r.final_columns[15 + j]});
    results.push_back(member_result(s, shard + (k_begin + static_cast<std::int64_t>(i)) * shards, values[i], r, nullptr));
  }
  return results;
}

// The first line of a part file; `what`: "" for the rows, " crossings" for the crossings.
std::string shard_line(std::int64_t i, std::int64_t n, std::int64_t members, std::uint64_t hash, const char* what = "") {
  return std::string("# lgi sweep") + what + " shard " + std::to_string(i) + "/" + std::to_string(n) + ": " + std::to_string(members) +
         " members, sweep " + hex64(hash) + ", lgi " + LGI_VERSION;
}

// "i/N" with 0 <= i < N, both decimal integers.
bool parse_shard(const std::string& text, std::int64_t& i, std::int64_t& n) {
  const std::size_t slash = text.find('/');
  if (slash == std::string::npos) return false;
  const auto number = [](const std::string& t, std::int64_t& x) {
    if (t.empty() || t.size() > 9 || t.find_first_not_of("0123456789") != std::string::npos) return false;
    x = std::stoll(t);
    return true;
  };
  return number(text.substr(0, slash), i) && number(text.substr(slash + 1), n) && n >= 1 && i < n;
}

}  // namespace


int sweep_command(const SweepCommandOptions& options) {
  std::int64_t shard = 0, shards = 1;
  const bool sharded = !options.shard.empty();
  if (sharded && !parse_shard(options.shard, shard, shards))
    return fail(exit_bad_input, "--shard: expected i/N with 0 <= i < N (e.g. 0/4), got " + quoted_input(options.shard));
  if (options.threads < 0) return fail(exit_bad_input, "--threads: expected 0 (all cores) or a positive number");
  if (options.output.empty()) return fail(exit_bad_input, "sweep: -o FILE is required");
  Sweep s;
  try {
    s = options.document ? parse_sweep(*options.document, options.sweep_file) : read_sweep(options.sweep_file);
  } catch (const InputError& e) {
    return fail(exit_bad_input, e.what());
  }
  // This shard's members: m = shard + k * shards, k = 0 ... count - 1.
  const std::int64_t count = s.members > shard ? (s.members - shard + shards - 1) / shards : 0;
  unsigned threads = options.threads > 0 ? static_cast<unsigned>(options.threads) : std::thread::hardware_concurrency();
  threads = static_cast<unsigned>(std::clamp<std::int64_t>(std::min<std::int64_t>(threads, count), 1, 4096));

  if (!is_streamed_path(options.output) && same_file(options.output, options.sweep_file))
    return fail(exit_bad_input, "-o " + options.output + " is the sweep file itself: lgi does not replace its input");
  if (const std::string why = output_replaces_input(s.scene0, options.output); !why.empty())
    return fail(exit_bad_input, why);
  if (s.records(Record::crossings) && is_streamed_path(options.output))
    return fail(exit_bad_input, "-o " + options.output + ": the sweep records crossings, which go to a file beside the "
                                "output (" + crossings_path("OUT.csv") + "): -o must name a file");
  const std::unique_ptr<OutputFile> out = open_output(options.output);
  if (!out) return exit_io_error;
  // A part file is self-verifying: its last line holds the hash of every byte before it (PartHash).
  PartHash part_hash, crossings_part_hash;
  const auto put = [&](OutputFile& file, PartHash& hash, const std::string& record) {
    if (sharded) hash.add(record);
    return file.write_record(record);
  };
  std::string head;
  if (sharded) head = shard_line(shard, shards, s.members, s.hash) + "\n";
  head += s.header + "\n";
  bool write_failed = !put(*out, part_hash, head);
  // The crossings file beside it (when recorded), written and committed alongside.
  std::unique_ptr<OutputFile> crossings_out;
  if (s.records(Record::crossings)) {
    crossings_out = open_output(crossings_path(options.output));
    if (!crossings_out) return exit_io_error;
    std::string chead;
    if (sharded) chead = shard_line(shard, shards, s.members, s.hash, " crossings") + "\n";
    chead += std::string(crossings_header) + "\n";
    write_failed = !put(*crossings_out, crossings_part_hash, chead) || write_failed;
  }

  const auto start = std::chrono::steady_clock::now();
  std::atomic<std::int64_t> next{0};
  std::atomic<bool> abort{false};
  std::mutex mutex;  // guards everything below
  std::map<std::int64_t, MemberResult> pending;  // finished rows waiting for the ones before them
  std::int64_t written = 0;
  std::int64_t outcomes[3] = {0, 0, 0};
  std::optional<std::pair<std::int64_t, std::string>> error;  // the lowest failing member seen, and its message
  int error_status = exit_bad_input;
  // The batched path (run_batch) when the sweep qualifies and --no-batch is not given: blocks of members.
  std::string why_not = "--no-batch";
  const std::int64_t n_steps = options.batch ? batch_steps(s, s.scene0, why_not) : 0;
  // Blocks of at most batch_block_work body-steps, at least 4 per thread when there are enough members.
  const std::int64_t per_thread = (count + 4 * std::int64_t{threads} - 1) / (4 * std::int64_t{threads});
  const std::int64_t block =
      n_steps > 0 ? std::clamp<std::int64_t>(std::min(batch_block_work / n_steps, per_thread), 4, 1024) : 1;
  std::atomic<int> kernel_used{-1};
  // Progress (ProgressLine): members written, their rate, elapsed and remaining wall time. Called with `mutex` held.
  ProgressLine progress(progress_mode(options.quiet, options.progress));
  const auto show_progress = [&](std::int64_t done) {
    if (!progress.due()) return;
    const double elapsed = progress.elapsed(), rate = static_cast<double>(done) / elapsed;
    char line[200];
    std::snprintf(line, sizeof line, "%lld of %lld members (%.1f %%), %.3g members/s, %.0f s elapsed, about %.0f s left",
                  static_cast<long long>(done), static_cast<long long>(count),
                  100.0 * static_cast<double>(done) / static_cast<double>(count), rate, elapsed,
                  rate > 0 ? static_cast<double>(count - done) / rate : 0.0);
    progress.show(line);
  };
  const auto work = [&] {
    for (;;) {
      const std::int64_t k0 = next.fetch_add(block);
      if (k0 >= count || abort.load() || (options.stop && *options.stop)) return;
      const std::int64_t k1 = std::min(count, k0 + block);
      std::int64_t m = shard + k0 * shards;
      std::vector<MemberResult> results;
      try {
        if (n_steps > 0) {
          BatchKernel kernel = BatchKernel::automatic;
          results = run_batch(s, k0, k1, shard, shards, n_steps, kernel, m);
          kernel_used = static_cast<int>(kernel);
        } else {
          results.push_back(run_member(s, m, options.stop));
        }
      } catch (const std::exception& e) {
        const std::lock_guard lock(mutex);
        if (!error || m < error->first) {
          error.emplace(m, e.what());
          error_status = dynamic_cast<const InputError*>(&e) ? exit_bad_input : exit_internal_error;
        }
        abort = true;
        return;
      }
      const std::lock_guard lock(mutex);
      for (std::size_t i = 0; i < results.size(); ++i) {
        ++outcomes[static_cast<int>(results[i].outcome)];
        pending.emplace(k0 + static_cast<std::int64_t>(i), std::move(results[i]));
      }
      for (auto it = pending.begin(); it != pending.end() && it->first == written; it = pending.erase(it), ++written) {
        write_failed = !put(*out, part_hash, it->second.row) || write_failed;
        const std::string& c = it->second.crossings;
        if (crossings_out && !c.empty()) write_failed = !put(*crossings_out, crossings_part_hash, c) || write_failed;
      }
      if (write_failed) {  // the first failed write stops the sweep
        abort = true;
        return;
      }
      show_progress(written);
    }
  };
  // Workers: as many as the system gives (the file is the same for any number); one that cannot be started is a
  // warning, and the sweep goes on with the others.
  std::vector<std::thread> workers;
  for (unsigned t = 1; t < threads; ++t) {
    try {
      workers.emplace_back(work);
    } catch (const std::system_error& e) {
      std::fprintf(stderr, "lgi: warning: could not start thread %u of %u (%s): the sweep runs on %u\n", t + 1, threads,
                   e.code().message().c_str(), t);
      threads = t;
      break;
    }
  }
  work();
  for (std::thread& t : workers) t.join();
  progress.clear();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  if (options.stop && *options.stop) {  // `out` removes its temporary file: nothing is written
    const int signal = *options.stop;
    return fail(128 + signal, std::string("sweep interrupted by ") + (signal == SIGINT ? "SIGINT" : "SIGTERM") + " after " +
                                  std::to_string(written) + " of " + std::to_string(count) +
                                  " members: nothing written (rerun, or run it in shards with --shard)");
  }
  if (error) {
    if (error_status == exit_internal_error) return fail(exit_internal_error, "internal error: " + error->second);
    return fail(exit_bad_input, error->second);
  }
  if (write_failed || written != count) {
    const OutputFile& bad = out->failed() || !crossings_out ? *out : *crossings_out;
    return fail(exit_io_error, bad.display_name() + ": write error (" +
                                   (bad.failed() ? bad.error_text() : std::string("rows missing")) + ") after " +
                                   std::to_string(written) + " of " + std::to_string(count) +
                                   " members: nothing kept (rerun, or run it in shards with --shard)");
  }
  if (sharded) {
    write_failed = !out->write_record(part_hash.line()) ||
                   (crossings_out && !crossings_out->write_record(crossings_part_hash.line()));
    if (write_failed) return fail(exit_io_error, options.output + ": write error");
  }
  if (!commit_outputs(*out, crossings_out.get())) return exit_io_error;
  if (!options.quiet) {
    char buf[1024];
    std::snprintf(buf, sizeof buf,
                  "%s: %lld members%s, %u thread%s, %s, %.3f s (%.1f members/s): %lld completed, %lld step failed, "
                  "%lld stopped; %s\n",
                  options.sweep_file.c_str(), static_cast<long long>(s.members),
                  sharded ? (" (shard " + options.shard + ": " + std::to_string(count) + ")").c_str() : "", threads,
                  threads == 1 ? "" : "s",
                  n_steps > 0 ? (std::string("batched LGVI (") + kernel_name(kernel_used.load()) + " kernel)").c_str()
                              : ("member by member (not batched: " + why_not + ")").c_str(),
                  seconds, seconds > 0 ? static_cast<double>(count) / seconds : 0.0,
                  static_cast<long long>(outcomes[0]), static_cast<long long>(outcomes[1]),
                  static_cast<long long>(outcomes[2]), options.output.c_str());
    std::fputs(buf, stderr);
  }
  return 0;
}

}  // namespace lgi::app
