// lgi/apps/csv_reader.cpp — numeric CSV tables (csv_reader.hpp).
#include "csv_reader.hpp"

#include "hashing.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

namespace lgi::app {

namespace {

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

std::string trim(std::string s) {
  const auto not_space = [](unsigned char c) { return !std::isspace(c); };
  s.erase(s.begin(), std::find_if(s.begin(), s.end(), not_space));
  s.erase(std::find_if(s.rbegin(), s.rend(), not_space).base(), s.end());
  return s;
}

}  // namespace

void parse_csv(const std::string& text, const std::string& path, std::vector<std::string>& header,
               std::vector<std::vector<double>>& rows, std::vector<int>& lines, std::string_view what) {
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a UTF-8 byte order mark
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find('\0') != std::string::npos)
      throw CsvError(path + ":" + std::to_string(number) + ": a NUL byte (not a text file?)");
    if (trim(line).empty()) continue;
    std::vector<std::string> cells = split_csv_line(line);
    if (header.empty()) {
      for (std::string& c : cells) header.push_back(trim(c));
      continue;
    }
    if (cells.size() != header.size())
      throw CsvError(path + ":" + std::to_string(number) + ": row has " + std::to_string(cells.size()) +
                     " values, the header " + std::to_string(header.size()));
    std::vector<double> row;
    for (std::size_t i = 0; i < cells.size(); ++i) {
      const std::string c = trim(cells[i]);
      char* end = nullptr;
      const double v = std::strtod(c.c_str(), &end);
      if (c.empty() || end != c.c_str() + c.size() || !std::isfinite(v))
        throw CsvError(path + ":" + std::to_string(number) + ": column " + header[i] + ": not a finite number: " +
                       quoted_input(c));
      row.push_back(v);
    }
    rows.push_back(std::move(row));
    lines.push_back(number);
  }
  if (header.empty()) throw CsvError(path + ": empty " + std::string(what) + " (no header row)");
  if (rows.empty()) throw CsvError(path + ": no data rows after the header");
}

void read_csv(const std::string& path, std::vector<std::string>& header, std::vector<std::vector<double>>& rows,
              std::vector<int>& lines, std::string_view what, std::uint64_t* digest) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw CsvError(path + ": cannot read the " + std::string(what) + ": " + ec.message());
  if (size > max_input_bytes)
    throw CsvError(path + ": file of " + std::to_string(size) + " bytes, more than the " + std::to_string(max_input_bytes) +
                   " a " + std::string(what) + " may have");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CsvError(path + ": cannot read the " + std::string(what));
  std::ostringstream text;
  text << in.rdbuf();
  if (digest) *digest = fnv1a(text.str());
  parse_csv(text.str(), path, header, rows, lines, what);
}

}  // namespace lgi::app
