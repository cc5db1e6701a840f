// lgi_sweep_mpi — `lgi sweep` across MPI ranks (optional: built when CMake finds MPI; docs/sweep.md "MPI").
//
//   mpirun -np N lgi_sweep_mpi SWEEPFILE -o OUT.csv [--threads T] [--no-batch] [-q]
//
// Rank r runs the members m with m mod N = r — exactly `lgi sweep --shard r/N`, through the same code — into a
// part file in its temporary directory; the ranks send their parts' bytes to rank 0 (point to point, in chunks of
// at most 2^30 bytes), which checks and merges them as `lgi merge` does and writes OUT.csv atomically: the bytes
// of the serial run. Needs no shared file system. Exit status: `lgi sweep`'s (command.hpp), from rank 0; a rank
// whose members fail (bad sweep file, a member the loader refuses) makes the run exit 1 and no OUT.csv is
// written; only rank 0's message is shown when it has one, else the lowest failing rank's. That rank alone exits
// with the failure, the others with 0: mpirun ends the job at the first non-zero exit, and output of another rank
// still on its way to mpirun could be lost (the message, under load).
#include "command.hpp"
#include "sweep_command.hpp"

#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

int g_reporter = 0;  // the rank whose message a failure shows (run)

namespace fs = std::filesystem;

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

constexpr std::uint64_t chunk = std::uint64_t{1} << 30;

void send_bytes(const std::string& bytes, int to) {
  std::uint64_t size = bytes.size();
  MPI_Send(&size, 1, MPI_UINT64_T, to, 0, MPI_COMM_WORLD);
  for (std::uint64_t at = 0; at < size; at += chunk)
    MPI_Send(bytes.data() + at, static_cast<int>(std::min(chunk, size - at)), MPI_CHAR, to, 1, MPI_COMM_WORLD);
}

std::string receive_bytes(int from) {
  std::uint64_t size = 0;
  MPI_Recv(&size, 1, MPI_UINT64_T, from, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  std::string bytes(size, '\0');
  for (std::uint64_t at = 0; at < size; at += chunk)
    MPI_Recv(bytes.data() + at, static_cast<int>(std::min(chunk, size - at)), MPI_CHAR, from, 1, MPI_COMM_WORLD,
             MPI_STATUS_IGNORE);
  return bytes;
}

int usage() {
  std::fprintf(stderr, "usage: mpirun -np N lgi_sweep_mpi SWEEPFILE -o OUT.csv [--threads T] [--no-batch] [-q]\n");
  return lgi::app::exit_bad_input;
}

int run(int rank, int size, int argc, char** argv) {
  lgi::app::SweepCommandOptions options;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if ((a == "-o" || a == "--output") && i + 1 < argc) options.output = argv[++i];
    else if (a == "--threads" && i + 1 < argc) {
      char* end = nullptr;
      const long t = std::strtol(argv[++i], &end, 10);
      if (*end != '\0' || t < 0 || t > 4096) return rank == 0 ? lgi::app::fail(1, "--threads: expected 0 ... 4096") : 1;
      options.threads = static_cast<int>(t);
    } else if (a == "-q" || a == "--quiet") options.quiet = true;
    else if (a == "--no-batch") options.batch = false;
    else if (options.sweep_file.empty() && !a.empty() && a[0] != '-') options.sweep_file = a;
    else return rank == 0 ? usage() : 1;
  }
  if (options.sweep_file.empty() || options.output.empty()) return rank == 0 ? usage() : 1;
  const bool quiet = options.quiet;
  const std::string output = options.output, sweep_file = options.sweep_file;

  // This rank's share, as `lgi sweep --shard rank/size`, into a part file of its own; its messages to a file,
  // shown only if it is the one to report.
  const fs::path tmp = fs::temp_directory_path() / ("lgi_sweep_mpi_" + std::to_string(::getpid()) + "_" + std::to_string(rank));
  const std::string part = tmp.string() + ".part", messages = tmp.string() + ".err";
  options.output = part;
  options.shard = std::to_string(rank) + "/" + std::to_string(size);
  options.quiet = true;
  std::fflush(stderr);
  const int saved = ::dup(2);
  std::FILE* err = std::freopen(messages.c_str(), "w", stderr);
  int status = err ? lgi::app::sweep_command(options) : lgi::app::exit_io_error;
  std::fflush(stderr);
  ::dup2(saved, 2);
  ::close(saved);
  const std::string said = slurp(messages);
  std::remove(messages.c_str());

  // Who reports: rank 0 if it failed, else the lowest failing rank.
  std::vector<int> statuses(static_cast<std::size_t>(size));
  MPI_Allgather(&status, 1, MPI_INT, statuses.data(), 1, MPI_INT, MPI_COMM_WORLD);
  const auto failed = std::find_if(statuses.begin(), statuses.end(), [](int s) { return s != 0; });
  if (failed != statuses.end()) {
    g_reporter = static_cast<int>(failed - statuses.begin());
    if (g_reporter == rank) std::fputs(said.c_str(), stderr);
    std::remove(part.c_str());
    std::remove(lgi::app::crossings_path(part).c_str());
    return *failed;
  }

  // A sweep that records crossings has a crossings part beside each part (sweep_command.hpp, crossings_path): sent
  // as a second message (empty when there is none).
  const std::string crossings = lgi::app::crossings_path(part);
  if (rank != 0) {
    send_bytes(slurp(part), 0);
    send_bytes(fs::exists(crossings) ? slurp(crossings) : std::string(), 0);
    std::remove(part.c_str());
    std::remove(crossings.c_str());
    return 0;
  }
  lgi::app::MergeCommandOptions merge;
  merge.output = output;
  merge.parts.push_back(part);
  for (int r = 1; r < size; ++r) {
    const std::string path = tmp.string() + ".from_" + std::to_string(r) + ".part";
    std::ofstream(path, std::ios::binary) << receive_bytes(r);
    const std::string c = receive_bytes(r);
    if (!c.empty()) std::ofstream(lgi::app::crossings_path(path), std::ios::binary) << c;
    merge.parts.push_back(path);
  }
  merge.quiet = true;
  const int merged = lgi::app::merge_command(merge);
  for (const std::string& p : merge.parts) {
    std::remove(p.c_str());
    std::remove(lgi::app::crossings_path(p).c_str());
  }
  if (merged == 0 && !quiet)
    std::fprintf(stderr, "%s: %d ranks, merged into %s\n", sweep_file.c_str(), size, output.c_str());
  return merged;
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  int status = lgi::app::exit_internal_error;
  try {
    status = run(rank, size, argc, argv);
  } catch (const std::exception& e) {
    status = lgi::app::fail(lgi::app::exit_internal_error, std::string("internal error: ") + e.what());
  }
  // The run's status is rank 0's; a failure is the reporting rank's exit status alone (header).
  MPI_Bcast(&status, 1, MPI_INT, 0, MPI_COMM_WORLD);
  MPI_Finalize();
  return rank == g_reporter ? status : 0;
}
