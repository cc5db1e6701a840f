// lgi/apps/json_reader.hpp — reading JSON input files with errors that name the file and the JSON path.
//
// Every error is an InputError whose message reads "<file>: <JSON pointer>: <what is wrong>" (or
// "<file>:<line>:<column>: ..." for syntax errors), thrown before any output is produced. The parser
// rejects duplicate keys (nlohmann accepts them silently), reports numbers that overflow a double (or
// underflow to 0) with their path and position, NUL bytes (nlohmann would stop reading there) and UTF-16/32
// files, and refuses files larger than `max_input_bytes` or nested deeper than `max_json_depth`. A UTF-8
// byte order mark is skipped. Syntax errors name the JSON path they occur in and, for NaN, comments,
// single quotes and trailing commas, say what JSON lacks. Numbers are read as doubles
// and range-checked, integers included (a JSON 1e300 or 2.7 is never cast to an integer).
#pragma once

#include <lgi/core/scalar.hpp>

#include <nlohmann/json.hpp>

#include <cstdint>
#include <initializer_list>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace lgi::app {

using json = nlohmann::json;

// Bad input: the message names the file, the JSON path and the problem. It is one line: control
// characters that came from the input (a key "a\nb", a string with a tab) are escaped as in JSON.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message);
};

inline constexpr std::size_t max_input_bytes = 64u << 20;
inline constexpr std::size_t max_json_depth = 64;

// Parses `text` (the contents of `file`) with duplicate-key detection and positioned errors.
json parse_json(const std::string& text, const std::string& file);
// Reads and parses a file; unreadable, oversized and malformed files are InputErrors.
json read_json_file(const std::string& file);

// A change a reader made to the input to make it exact — a rotation projected onto SO(3), a unit vector or a
// quaternion normalised: where (the JSON path), what was done, and the size of the defect it removed.
struct InputAdjustment {
  std::string where;
  std::string what;
  double defect = 0;
};

// A JSON value with its location, and typed accessors that fail with the location in the message.
class Node {
 public:
  // `adjustments`: where readers record what they changed (adjusted()); null: not recorded. `directory`: where the
  // file names the document holds are resolved (null: the directory of `file`; a sweep member's `file` is a label).
  // Nodes reached from this one share both.
  Node(const json& value, std::string pointer, const std::string& file,
       std::vector<InputAdjustment>* adjustments = nullptr, const std::string* directory = nullptr)
      : v_(value), ptr_(std::move(pointer)), file_(file), adjustments_(adjustments), directory_(directory) {}

  const json& value() const { return v_; }
  const std::string& pointer() const { return ptr_; }  // "" for the document root
  std::string where() const { return ptr_.empty() ? std::string("/") : ptr_; }
  const std::string& file() const { return file_; }  // the file the value was read from (for messages)
  std::string directory() const;                      // where a relative file name in the document points from
  bool is_object() const { return v_.is_object(); }
  bool is_array() const { return v_.is_array(); }

  [[noreturn]] void fail(const std::string& message) const;

  Node at(std::string_view key) const;                  // a required key of an object
  std::optional<Node> find(std::string_view key) const;  // an optional key of an object
  Node at(std::size_t index) const;                     // an element of an array
  std::size_t size() const;                             // of an array (fails if not an array)

  // Fails on the first key of this object not in `allowed` (listing the allowed ones).
  void allow_only(std::initializer_list<std::string_view> allowed, std::string_view owner = {}) const;
  void allow_only(const std::vector<std::string_view>& allowed, std::string_view owner = {}) const;

  std::string string() const;
  double number() const;  // a finite number
  double positive() const;
  double non_negative() const;
  // An integer in [lo, hi], given as a JSON number with no fractional part.
  std::int64_t integer(std::int64_t lo, std::int64_t hi) const;
  Vec3<double> vec3() const;
  Mat3<double> mat3() const;

  // Records that this value was changed by `what`, removing a defect of size `defect` (see the constructor).
  void adjusted(std::string what, double defect) const {
    if (adjustments_) adjustments_->push_back({where(), std::move(what), defect});
  }

 private:
  const json& v_;
  std::string ptr_;
  const std::string& file_;
  std::vector<InputAdjustment>* adjustments_ = nullptr;
  const std::string* directory_ = nullptr;
};

// A JSON pointer token with '~' and '/' escaped (RFC 6901), for messages: a key longer than 40 bytes is
// cut as by quoted_input().
std::string pointer_token(std::string_view key);
// A short description of a JSON value for messages: "a string (\"fast\")", "an array of 2", ...
std::string describe(const json& v);
// A string from the input, quoted for a message and cut to at most 40 bytes (at a UTF-8 character
// boundary, "..." appended): a key or name of a megabyte gives a message of one line, not a megabyte.
std::string quoted_input(std::string_view s);
// A double formatted with up to 17 significant digits, shortest form that reads back the same.
std::string format_number(double x);
// The name among `candidates` that a mistyped `given` most likely meant: one spelled with the same letters in
// another case, else the nearest in lower case by optimal-string-alignment distance (an insertion, a deletion, a
// substitution or a transposition of neighbours counts 1) when that distance is at most 1 for `given` of up to 5
// characters and at most 2 beyond, and less than half the longer name's length ("q" suggests no "c"); the first of
// equally near names. Empty when none is that near.
std::string closest_name(std::string_view given, const std::vector<std::string_view>& candidates);
// "; did you mean \"NAME\"?" for closest_name(given, candidates), or "" when it is empty.
std::string did_you_mean(std::string_view given, const std::vector<std::string_view>& candidates);

}  // namespace lgi::app
