// lgi/apps/sweep_part.cpp — checking part files and `lgi merge` (sweep_part.hpp, sweep_command.hpp).
#include "sweep_part.hpp"

#include "command.hpp"
#include "sweep_command.hpp"
#include "sweep_file.hpp"

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace lgi::app {

// The output file, or nullptr after saying on stderr why it cannot be opened (exit_io_error).
std::unique_ptr<OutputFile> open_output(const std::string& path) {
  try {
    return std::make_unique<OutputFile>(path);
  } catch (const OutputError& e) {
    fail(exit_io_error, e.what());
    return nullptr;
  }
}

// Commits the crossings file (if any), then the main file; when the main file cannot be committed, the crossings
// file just renamed into place is removed again. false: failed, with the message on stderr.
bool commit_outputs(OutputFile& out, OutputFile* crossings) {
  if (crossings && !crossings->commit()) {
    fail(exit_io_error, crossings->display_name() + ": cannot write the crossings file: " + crossings->error_text());
    return false;
  }
  if (!out.commit()) {
    fail(exit_io_error, out.display_name() + ": cannot write the output file: " + out.error_text());
    if (crossings && !crossings->streamed()) std::remove(crossings->target_path().c_str());
    return false;
  }
  return true;
}

std::string verify_part(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return file + ": cannot read the part file: " + std::strerror(errno);
  const std::string unfinished = file + ": the part does not end with its check line (an unfinished shard, or a "
                                        "damaged file)";
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  const auto line_size = static_cast<std::streamoff>(PartHash{}.line().size());
  if (size < line_size) return unfinished;
  const std::streamoff body = size - line_size;
  std::string last(static_cast<std::size_t>(line_size), '\0');
  in.seekg(body);
  in.read(last.data(), line_size);
  if (!in || last.rfind(PartHash::part_end_prefix, 0) != 0 || last.back() != '\n' ||
      (body > 0 && [&] {
        char before = 0;
        in.seekg(body - 1);
        in.get(before);
        return before != '\n';
      }()))
    return unfinished;
  PartHash hash;
  in.seekg(0);
  std::vector<char> buffer(std::size_t{1} << 20);
  for (std::streamoff left = body; left > 0;) {
    const auto n = static_cast<std::streamsize>(std::min<std::streamoff>(left, static_cast<std::streamoff>(buffer.size())));
    if (!in.read(buffer.data(), n)) return file + ": cannot read the part file";
    hash.add(std::string_view(buffer.data(), static_cast<std::size_t>(n)));
    left -= n;
  }
  if (last != hash.line()) return file + ": the part's bytes do not match its check line: the file was changed or damaged";
  return {};
}


namespace {

// "# lgi sweep shard i/N: M members, sweep HASH, lgi VERSION": i, N and M, with 0 ≤ i < N < 10⁹ (what --shard
// accepts) and 1 ≤ M ≤ max_members; false for anything else.
bool parse_shard_line(const std::string& line, std::int64_t& i, std::int64_t& n, std::int64_t& members) {
  const char* p = line.data();
  const char* end = line.data() + line.size();
  const auto literal = [&](std::string_view s) {
    if (static_cast<std::size_t>(end - p) < s.size() || std::string_view(p, s.size()) != s) return false;
    p += s.size();
    return true;
  };
  const auto number = [&](std::int64_t& x, std::int64_t lo, std::int64_t hi) {
    if (p == end || *p < '0' || *p > '9') return false;
    const auto r = std::from_chars(p, end, x);
    if (r.ec != std::errc() || x < lo || x > hi) return false;
    p = r.ptr;
    return true;
  };
  constexpr std::int64_t max_shards = 999'999'999;
  return literal("# lgi sweep shard ") && number(i, 0, max_shards) && literal("/") && number(n, 1, max_shards) &&
         i < n && literal(": ") && number(members, 1, max_members) && literal(" members, sweep ");
}

}  // namespace

int merge_command(const MergeCommandOptions& options) {
  if (options.output.empty()) return fail(exit_bad_input, "merge: -o FILE is required");
  if (options.parts.empty()) return fail(exit_bad_input, "merge: give the part files of a sweep (lgi sweep --shard)");
  struct Part {
    std::string file;
    std::int64_t i = 0, n = 0, members = 0;
    std::string line, header;
    std::unique_ptr<std::ifstream> in;
    std::int64_t line_number = 2;
    // the part's crossings file (when the sweep records crossings)
    std::string cfile;
    std::unique_ptr<std::ifstream> cin;
    std::int64_t cline_number = 2;
  };
  std::vector<Part> parts;
  for (const std::string& file : options.parts) {
    if (!is_streamed_path(options.output) && same_file(options.output, file))
      return fail(exit_bad_input, "-o " + options.output + " is the part file " + file + ": lgi does not replace its input");
    Part p;
    p.file = file;
    p.in = std::make_unique<std::ifstream>(file, std::ios::binary);
    if (!*p.in) return fail(exit_bad_input, file + ": cannot read the part file: " + std::strerror(errno));
    std::getline(*p.in, p.line);
    std::int64_t i = 0, n = 0, members = 0;
    if (!parse_shard_line(p.line, i, n, members))
      return fail(exit_bad_input, file + ":1: not a part file of lgi sweep --shard (expected \"# lgi sweep shard i/N: ...\")");
    p.i = i;
    p.n = n;
    p.members = members;
    if (!std::getline(*p.in, p.header)) return fail(exit_bad_input, file + ":2: the CSV header is missing");
    if (const std::string problem = verify_part(file); !problem.empty()) return fail(exit_bad_input, problem);
    const Part* first = parts.empty() ? nullptr : &parts.front();
    if (first) {
      // Everything but the shard index must be the first part's: the same sweep, split the same way.
      const std::string mine = p.line.substr(p.line.find(':')), theirs = first->line.substr(first->line.find(':'));
      if (mine != theirs || p.n != first->n)
        return fail(exit_bad_input, file + ":1: a shard of another sweep, split or lgi version (\"" + p.line + "\"; " +
                                        first->file + " has \"" + first->line + "\")");
      if (p.header != first->header)
        return fail(exit_bad_input, file + ":2: the CSV header differs from " + first->file + "'s");
      for (const Part& q : parts)
        if (q.i == p.i)
          return fail(exit_bad_input, file + ": shard " + std::to_string(p.i) + "/" + std::to_string(p.n) +
                                          " again (also " + q.file + ")");
    }
    parts.push_back(std::move(p));
  }
  const std::int64_t n = parts.front().n, members = parts.front().members;
  if (static_cast<std::int64_t>(parts.size()) != n) {
    std::string missing;
    int listed = 0;  // the first few (N may be large: --shard 0/1000000 of a small sweep is a valid part)
    for (std::int64_t i = 0; i < n && listed < 10; ++i)
      if (std::none_of(parts.begin(), parts.end(), [&](const Part& p) { return p.i == i; })) {
        missing += (missing.empty() ? "" : ", ") + std::to_string(i) + "/" + std::to_string(n);
        if (++listed == 10 && static_cast<std::int64_t>(parts.size()) + 10 < n) missing += ", ...";
      }
    return fail(exit_bad_input, "merge: shard " + missing + " of the sweep in " + parts.front().file + " is missing");
  }
  std::sort(parts.begin(), parts.end(), [](const Part& a, const Part& b) { return a.i < b.i; });

  // A sweep that records crossings has a "crossings" column (the member's count) and, beside each part, its
  // crossings part: "# lgi sweep crossings shard ..." (the rest as the part's first line), the crossings header,
  // then each member's crossing rows in member order.
  const std::vector<std::string> columns = [&] {
    std::vector<std::string> c;
    std::string cell;
    std::istringstream in(parts.front().header);
    while (std::getline(in, cell, ',')) c.push_back(cell);
    return c;
  }();
  const auto count_column = std::find(columns.begin(), columns.end(), "crossings");
  const bool crossings = count_column != columns.end();
  const std::size_t count_index = static_cast<std::size_t>(count_column - columns.begin());
  if (crossings)
    for (Part& p : parts) {
      p.cfile = crossings_path(p.file);
      p.cin = std::make_unique<std::ifstream>(p.cfile, std::ios::binary);
      if (!*p.cin)
        return fail(exit_bad_input, p.cfile + ": cannot read the crossings part of " + p.file + ": " + std::strerror(errno));
      std::string line, header;
      std::getline(*p.cin, line);
      if (const std::string problem = verify_part(p.cfile); !problem.empty()) return fail(exit_bad_input, problem);
      const std::string expected = "# lgi sweep crossings" + p.line.substr(std::string("# lgi sweep").size());
      if (line != expected)
        return fail(exit_bad_input, p.cfile + ":1: not the crossings part of " + p.file + " (expected \"" + expected + "\")");
      if (!std::getline(*p.cin, header) || header != crossings_header)
        return fail(exit_bad_input, p.cfile + ":2: expected the crossings header \"" + std::string(crossings_header) + "\"");
    }

  if (crossings && is_streamed_path(options.output))
    return fail(exit_bad_input, "-o " + options.output + ": the sweep records crossings, which go to a file beside the "
                                "output: -o must name a file");
  const std::unique_ptr<OutputFile> out = open_output(options.output);
  if (!out) return exit_io_error;
  bool write_failed = !out->write_record(parts.front().header + "\n");
  std::unique_ptr<OutputFile> crossings_out;
  if (crossings) {
    crossings_out = open_output(crossings_path(options.output));
    if (!crossings_out) return exit_io_error;
    write_failed = !crossings_out->write_record(std::string(crossings_header) + "\n") || write_failed;
  }
  const auto fields = [](const std::string& line) { return std::count(line.begin(), line.end(), ',') + 1; };
  const auto header_fields = fields(parts.front().header);
  std::string row, crossing;
  for (std::int64_t m = 0; m < members; ++m) {
    Part& p = parts[static_cast<std::size_t>(m % n)];
    ++p.line_number;
    const std::string expected = std::to_string(m) + ",";
    if (!std::getline(*p.in, row) || row.compare(0, expected.size(), expected) != 0)
      return fail(exit_bad_input, p.file + ":" + std::to_string(p.line_number) + ": expected the row of member " +
                                      std::to_string(m) + (p.in->eof() ? ", the file ends (an unfinished shard?)" : ""));
    if (fields(row) != header_fields)
      return fail(exit_bad_input, p.file + ":" + std::to_string(p.line_number) + ": the row has " +
                                      std::to_string(fields(row)) + " fields, the header " + std::to_string(header_fields));
    if (crossings) {
      // the member's crossing count, then as many rows of its crossings part
      std::size_t at = 0;
      for (std::size_t c = 0; c < count_index && at != std::string::npos; ++c) at = row.find(',', at) + 1;
      const long long count = at != std::string::npos && at > 0 ? std::atoll(row.c_str() + at) : -1;
      if (count < 0)
        return fail(exit_bad_input, p.file + ":" + std::to_string(p.line_number) + ": no crossings count in the row");
      for (long long k = 0; k < count; ++k) {
        ++p.cline_number;
        if (!std::getline(*p.cin, crossing) || crossing.compare(0, expected.size(), expected) != 0)
          return fail(exit_bad_input, p.cfile + ":" + std::to_string(p.cline_number) + ": expected crossing " +
                                          std::to_string(k) + " of member " + std::to_string(m) + " (" +
                                          std::to_string(count) + " in " + p.file + ")" +
                                          (p.cin->eof() ? ", the file ends (an unfinished shard?)" : ""));
        crossing += '\n';
        write_failed = !crossings_out->write_record(crossing) || write_failed;
      }
    }
    row += '\n';
    write_failed = !out->write_record(row) || write_failed;
    if (write_failed) break;
  }
  // After each part's last row, only its check line (verified above).
  const auto check_line = [](std::ifstream& in) {
    std::string line;
    return std::getline(in, line) && line.rfind(PartHash::part_end_prefix, 0) == 0 && !std::getline(in, line);
  };
  for (Part& p : parts) {
    if (!write_failed && !check_line(*p.in))
      return fail(exit_bad_input, p.file + ":" + std::to_string(p.line_number + 1) + ": a row after the shard's last member");
    if (!write_failed && crossings && !check_line(*p.cin))
      return fail(exit_bad_input, p.cfile + ":" + std::to_string(p.cline_number + 1) +
                                      ": a crossing beyond those the part's rows count");
  }
  if (write_failed) {
    const OutputFile& bad = out->failed() || !crossings_out ? *out : *crossings_out;
    return fail(exit_io_error, bad.display_name() + ": write error (" + bad.error_text() + "): nothing kept");
  }
  if (!commit_outputs(*out, crossings_out.get())) return exit_io_error;
  if (!options.quiet)
    std::fprintf(stderr, "merged %lld members from %lld shards into %s\n", static_cast<long long>(members),
                 static_cast<long long>(n), options.output.c_str());
  return 0;
}

}  // namespace lgi::app
