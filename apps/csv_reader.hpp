// lgi/apps/csv_reader.hpp — reading numeric CSV tables (observations for fits, torque tables for scenes) with errors
// that name the file and the line.
#pragma once

#include "json_reader.hpp"

#include <cstdint>
#include <istream>
#include <string>
#include <string_view>
#include <vector>

namespace lgi::app {

// Thrown for bad CSV input (already "file:line: message").
// (An InputError: one line, control characters from the file escaped. Catch it before InputError where the two are
// reported differently.)
struct CsvError : InputError {
  using InputError::InputError;
};

// An `lgi run`-style CSV read row by row from a stream (files of any size: `lgi view` reads runs of 10⁶ rows):
// the header row at construction, then one row per next(). The rules and messages of parse_csv below; `path`
// names the file in messages, `what` its role.
class CsvStream {
 public:
  CsvStream(std::istream& in, std::string path, std::string_view what = "observations file");
  const std::vector<std::string>& header() const { return header_; }
  // The next row's values into `row` (resized to the header's width); false at the end of the stream. Throws
  // CsvError naming the line.
  bool next(std::vector<double>& row);
  int line() const { return line_; }  // the line number of the last row or header read (1-based)

 private:
  bool next_line(std::string& line);  // the next non-blank line, its BOM, CR and NUL bytes checked
  std::istream& in_;
  std::string path_, text_;
  std::vector<std::string> header_;
  int line_ = 0;
};

// The bytes of an `lgi run`-style CSV (`path` for messages, `what` names the file's role: "observations file",
// "torque table"): a header row, then rows of finite numbers, each as many as the header has names; a UTF-8 byte
// order mark, CR line ends and blank lines are accepted. rows[i] was on line lines[i]. Throws CsvError.
void parse_csv(const std::string& text, const std::string& path, std::vector<std::string>& header,
               std::vector<std::vector<double>>& rows, std::vector<int>& lines,
               std::string_view what = "observations file");

// Reads and parses the CSV file at `path` (parse_csv); a file that cannot be read or is larger than max_input_bytes
// is a CsvError. digest, when given, receives the FNV-1a 64 hash of the file's bytes (checkpoints record it).
void read_csv(const std::string& path, std::vector<std::string>& header, std::vector<std::vector<double>>& rows,
              std::vector<int>& lines, std::string_view what = "observations file", std::uint64_t* digest = nullptr);

}  // namespace lgi::app
