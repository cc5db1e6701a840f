// lgi/apps/csv_reader.hpp — reading numeric CSV tables (observations for fits, torque tables for scenes) with errors
// that name the file and the line.
#pragma once

#include "json_reader.hpp"

#include <cstdint>
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
