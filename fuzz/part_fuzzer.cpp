// lgi/fuzz/part_fuzzer.cpp — libFuzzer harness: sweep part files through `lgi merge` (apps/sweep_part.cpp
// merge_command), written to a file and merged to /dev/null.
//
// Inputs whose first byte is odd have that byte dropped and their check line (the part's last line, the FNV-1a hash
// of every byte before it) recomputed, so that half the inputs reach the row-by-row reader behind the hash. Oracle:
// merge_command returns 0 (a part it can merge) or 1 (refused, one line on stderr); never 3 or 4, an exception, a
// sanitizer report or a hang. stderr is sent to /dev/null during the call.
#include "hashing.hpp"
#include "sweep_command.hpp"
#include "sweep_part.hpp"

#include "fuzz_common.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>

namespace {

std::string part_path() {
  const char* dir = std::getenv("TMPDIR");
  return std::string(dir ? dir : "/tmp") + "/lgi_part_fuzzer_" + std::to_string(::getpid()) + ".csv";
}

// The check line recomputed over the bytes before the input's last line.
std::string resign(std::string text) {
  if (text.empty() || text.back() != '\n') text += '\n';
  const std::size_t start = text.rfind('\n', text.size() - 2) + 1;  // the last line (0: the only one)
  text.resize(start);
  lgi::app::PartHash h;
  h.add(text);
  return text + h.line();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0 || size > (std::size_t{1} << 20)) return 0;
  std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  if (data[0] & 1) text = resign(std::move(text));
  static const std::string path = part_path();
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
  lgi::app::MergeCommandOptions options;
  options.parts = {path};
  options.output = "/dev/null";
  options.quiet = true;
  std::fflush(stderr);
  static const int devnull = ::open("/dev/null", O_WRONLY);
  const int saved = ::dup(2);
  ::dup2(devnull, 2);
  const int status = lgi::app::merge_command(options);
  std::fflush(stderr);
  ::dup2(saved, 2);
  ::close(saved);
  if (status != 0 && status != 1) lgi::fuzz::contract_violated("merge's exit status", std::to_string(status));
  return 0;
}
