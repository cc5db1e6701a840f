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

bool is_space(char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; }

// The cell [begin, end) of a line without its surrounding white space.
std::string_view trimmed(const char* begin, const char* end) {
  while (begin < end && is_space(*begin)) ++begin;
  while (end > begin && is_space(end[-1])) --end;
  return {begin, static_cast<std::size_t>(end - begin)};
}

}  // namespace

CsvStream::CsvStream(std::istream& in, std::string path, std::string_view what) : in_(in), path_(std::move(path)), text_(what) {
  std::string line;
  if (!next_line(line)) throw CsvError(path_ + ": empty " + text_ + " (no header row)");
  const char* p = line.data();
  const char* const end = p + line.size();
  for (;;) {
    const char* comma = std::find(p, end, ',');
    header_.emplace_back(trimmed(p, comma));
    if (comma == end) break;
    p = comma + 1;
  }
}

bool CsvStream::next_line(std::string& line) {
  while (std::getline(in_, line)) {
    ++line_;
    if (line_ == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a UTF-8 byte order mark
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find('\0') != std::string::npos)
      throw CsvError(path_ + ":" + std::to_string(line_) + ": a NUL byte (not a text file?)");
    if (!trimmed(line.data(), line.data() + line.size()).empty()) return true;
  }
  return false;
}

bool CsvStream::next(std::vector<double>& row) {
  std::string line;
  if (!next_line(line)) return false;
  const std::size_t count = 1 + static_cast<std::size_t>(std::count(line.begin(), line.end(), ','));
  if (count != header_.size())
    throw CsvError(path_ + ":" + std::to_string(line_) + ": row has " + std::to_string(count) + " values, the header " +
                   std::to_string(header_.size()));
  row.resize(count);
  const char* p = line.data();
  const char* const end = p + line.size();
  std::string cell;
  for (std::size_t i = 0; i < count; ++i) {
    const char* comma = std::find(p, end, ',');
    cell.assign(trimmed(p, comma));
    char* stop = nullptr;
    const double v = std::strtod(cell.c_str(), &stop);
    if (cell.empty() || stop != cell.c_str() + cell.size() || !std::isfinite(v))
      throw CsvError(path_ + ":" + std::to_string(line_) + ": column " + header_[i] + ": not a finite number: " +
                     quoted_input(cell));
    row[i] = v;
    p = comma + 1;
  }
  return true;
}

void parse_csv(const std::string& text, const std::string& path, std::vector<std::string>& header,
               std::vector<std::vector<double>>& rows, std::vector<int>& lines, std::string_view what) {
  std::istringstream in(text);
  CsvStream csv(in, path, what);
  header = csv.header();
  std::vector<double> row;
  while (csv.next(row)) {
    rows.push_back(row);
    lines.push_back(csv.line());
  }
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
