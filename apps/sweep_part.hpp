// lgi/apps/sweep_part.hpp — the part files of `lgi sweep --shard` and their merge (sweep_command.hpp has the
// format): each part ends with a check line, the FNV-1a hash of every byte before it.
#pragma once

#include "hashing.hpp"
#include "output_file.hpp"

#include <memory>

#include <cstdint>
#include <string>
#include <string_view>

namespace lgi::app {

// The last line of a part file (and of its crossings part): the FNV-1a hash of every byte before it. lgi merge
// refuses a part whose bytes do not hash to it (edited, damaged, or cut short: an unfinished shard has no such line).
struct PartHash {
  std::uint64_t h = fnv1a_basis;
  void add(std::string_view bytes) { h = fnv1a(bytes, h); }
  std::string line() const { return std::string(part_end_prefix) + hex64(h) + "\n"; }
  static constexpr std::string_view part_end_prefix = "# lgi sweep part end: fnv1a64 ";
};

// The output file of a sweep or a merge, or nullptr after saying on stderr why it cannot be opened (exit 3).
std::unique_ptr<OutputFile> open_output(const std::string& path);
// Commits the crossings file (if any), then the main file; when the main file cannot be committed, the crossings
// file just renamed into place is removed again. false: failed, with the message on stderr.
bool commit_outputs(OutputFile& out, OutputFile* crossings);

// "" if `file` ends in its PartHash line and the bytes before it hash to it; else why not (one line naming the
// file). Reads the file once, in pieces (a part may be larger than memory).
std::string verify_part(const std::string& file);

}  // namespace lgi::app
