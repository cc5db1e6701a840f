#include "json_reader.hpp"

#include <algorithm>
#include <charconv>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <system_error>

namespace lgi::app {

namespace {

// The first `n` bytes of s, backed up to the start of a UTF-8 character.
std::string_view utf8_prefix(std::string_view s, std::size_t n) {
  if (s.size() <= n) return s;
  while (n > 0 && (static_cast<unsigned char>(s[n]) & 0xC0) == 0x80) --n;  // s[n]: a continuation byte
  return s.substr(0, n);
}

constexpr std::size_t max_echo = 40;  // bytes of an input string echoed in a message

std::string cut(std::string_view s) {
  return s.size() <= max_echo ? std::string(s) : std::string(utf8_prefix(s, max_echo - 3)) + "...";
}

// The last bytes of s (at most max_echo - 3), starting at a UTF-8 character.
std::string tail(std::string_view s) {
  std::size_t begin = s.size() > max_echo - 3 ? s.size() - (max_echo - 3) : 0;
  while (begin < s.size() && (static_cast<unsigned char>(s[begin]) & 0xC0) == 0x80) ++begin;
  return std::string(s.substr(begin));
}

// The length of the UTF-8 character at s[i] (2 to 4 bytes, lead and continuation bytes checked), 0 if
// the bytes there are not one.
std::size_t utf8_length(const std::string& s, std::size_t i) {
  const auto u = static_cast<unsigned char>(s[i]);
  const std::size_t n = u >= 0xC2 && u <= 0xDF ? 2 : u >= 0xE0 && u <= 0xEF ? 3 : u >= 0xF0 && u <= 0xF4 ? 4 : 0;
  if (n == 0 || i + n > s.size()) return 0;
  for (std::size_t k = 1; k < n; ++k)
    if ((static_cast<unsigned char>(s[i + k]) & 0xC0) != 0x80) return 0;
  return n;
}

// The message with control characters escaped as in JSON (\n, \t, \u001b, ...) and bytes that are not
// UTF-8 as \xNN (a file name, or nlohmann's "last read" of an ill-formed file): one line of text.
std::string one_line(const std::string& message) {
  std::string out;
  out.reserve(message.size());
  for (std::size_t i = 0; i < message.size(); ++i) {
    const char c = message[i];
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x80) {
      const std::size_t n = utf8_length(message, i);
      if (n == 0) {
        char buf[8];
        std::snprintf(buf, sizeof buf, "\\x%02X", u);
        out += buf;
      } else {
        out.append(message, i, n);
        i += n - 1;
      }
    } else if (u >= 0x20 && u != 0x7f) {
      out += c;
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (c == '\r') {
      out += "\\r";
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", u);
      out += buf;
    }
  }
  return out;
}

}  // namespace

InputError::InputError(const std::string& message) : std::runtime_error(one_line(message)) {}

std::string quoted_input(std::string_view s) { return "\"" + cut(s) + "\""; }

std::string pointer_token(std::string_view key) {
  std::string out;
  for (const char c : cut(key)) {
    if (c == '~')
      out += "~0";
    else if (c == '/')
      out += "~1";
    else
      out += c;
  }
  return out;
}

std::string closest_name(std::string_view given, const std::vector<std::string_view>& candidates) {
  const auto lower = [](std::string_view s) {
    std::string out(s);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
  };
  // Optimal string alignment distance (Damerau–Levenshtein without repeated edits of a substring).
  const auto distance = [](const std::string& a, const std::string& b) {
    std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
    for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
    for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i)
      for (std::size_t j = 1; j <= b.size(); ++j) {
        d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
        if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
          d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
      }
    return d[a.size()][b.size()];
  };
  if (given.size() > 64) return {};  // not a typo of a name
  const std::string g = lower(given);
  const std::size_t limit = given.size() <= 5 ? 1 : 2;
  std::string best;
  std::size_t best_distance = limit + 1;
  for (const std::string_view c : candidates) {
    const std::size_t d = distance(g, lower(c));
    if (d < best_distance && 2 * d < std::max(given.size(), c.size())) {
      best = c;
      best_distance = d;
    }
  }
  return best;
}

std::string did_you_mean(std::string_view given, const std::vector<std::string_view>& candidates) {
  const std::string name = closest_name(given, candidates);
  return name.empty() ? std::string() : "; did you mean \"" + name + "\"?";
}

std::string format_number(double x) {
  char buf[64];
  for (int precision = 6; precision <= 17; ++precision) {  // shortest that reads back exactly
    const auto r = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::general, precision);
    double back = 0;
    std::from_chars(buf, r.ptr, back);
    if (back == x || precision == 17) return std::string(buf, r.ptr);
  }
  return {};
}

std::string describe(const json& v) {
  switch (v.type()) {
    case json::value_t::null: return "null";
    case json::value_t::boolean: return v.get<bool>() ? "true" : "false";
    case json::value_t::string: return "a string (" + quoted_input(v.get_ref<const std::string&>()) + ")";
    case json::value_t::number_integer:
    case json::value_t::number_unsigned:
    case json::value_t::number_float: return "the number " + format_number(v.get<double>());
    case json::value_t::array: return "an array of " + std::to_string(v.size());
    case json::value_t::object: return "an object";
    default: return "a value of type " + std::string(v.type_name());
  }
}

namespace {

// Line and column (1-based) of byte offset `pos` in `text`.
std::pair<std::size_t, std::size_t> line_column(const std::string& text, std::size_t pos) {
  pos = std::min(pos, text.size());
  std::size_t line = 1, col = 1;
  for (std::size_t i = 0; i < pos; ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return {line, col};
}

// Builds the DOM through nlohmann's own SAX DOM builder while tracking the JSON pointer of the value
// being parsed, so that duplicate keys and number overflows are reported where they are.
class TrackingSax {
 public:
  using number_integer_t = json::number_integer_t;
  using number_unsigned_t = json::number_unsigned_t;
  using number_float_t = json::number_float_t;
  using string_t = json::string_t;
  using binary_t = json::binary_t;

  explicit TrackingSax(json& root) : dom_(root, /*allow_exceptions=*/false) {}

  bool null() { return value(dom_.null()); }
  bool boolean(bool b) { return value(dom_.boolean(b)); }
  bool number_integer(number_integer_t i) { return value(dom_.number_integer(i)); }
  bool number_unsigned(number_unsigned_t u) { return value(dom_.number_unsigned(u)); }
  bool number_float(number_float_t f, const string_t& s) {
    // nlohmann reads 1e-400 as 0 without a word: a literal with a non-zero digit before its exponent
    // that reads as zero underflowed (denormals are kept: they are only less precise).
    if (f == 0 && s.substr(0, s.find_first_of("eE")).find_first_of("123456789") != std::string::npos) {
      error_ = "number " + s + " is too small for a double (it would read as 0)";
      error_pointer_ = pointer();
      located_ = true;
      return false;
    }
    return value(dom_.number_float(f, s));
  }
  bool string(string_t& s) { return value(dom_.string(s)); }
  bool binary(binary_t& b) { return value(dom_.binary(b)); }

  bool start_object(std::size_t n) {
    if (too_deep()) return false;
    frames_.push_back({true, {}, false, 0, {}});
    return dom_.start_object(n);
  }
  bool key(string_t& k) {
    Frame& f = frames_.back();
    f.key = k;
    f.has_key = true;
    if (!f.keys.insert(k).second) {
      error_ = "duplicate key " + quoted_input(k);
      error_pointer_ = pointer(frames_.size() - 1);  // the object holding the key twice
      located_ = true;
      return false;
    }
    return dom_.key(k);
  }
  bool end_object() {
    frames_.pop_back();
    return value(dom_.end_object());
  }
  bool start_array(std::size_t n) {
    if (too_deep()) return false;
    frames_.push_back({false, {}, false, 0, {}});
    return dom_.start_array(n);
  }
  bool end_array() {
    frames_.pop_back();
    return value(dom_.end_array());
  }
  bool parse_error(std::size_t position, const std::string& token, const nlohmann::detail::exception& ex) {
    position_ = position;
    error_pointer_ = pointer();
    std::string what = ex.what();
    // Drop nlohmann's "[json.exception.parse_error.101] parse error at line 1, column 6: " prefix.
    if (const auto colon = what.find(": "); what.rfind("[json.exception.parse_error", 0) == 0 && colon != std::string::npos)
      what = what.substr(colon + 2);
    else if (const auto bracket = what.find("] "); bracket != std::string::npos)
      what = what.substr(bracket + 2);
    if (ex.id == 406) {
      what = "number " + cut(token) + " is out of the range of a double";
      located_ = true;
    }
    // nlohmann quotes the whole last token, which may be megabytes (of whitespace, say): keep its end.
    if (const std::string read = "last read: '" + token + "'"; token.size() > max_echo) {
      if (const auto at = what.find(read); at != std::string::npos)
        what.replace(at, read.size(), "last read: '..." + tail(token) + "'");
    }
    error_ = what;
    return false;
  }

  const std::string& error() const { return error_; }
  // The error belongs to the value at error_pointer() (not a syntax error).
  bool located() const { return located_; }
  const std::string& error_pointer() const { return error_pointer_; }
  std::size_t position() const { return position_; }

 private:
  struct Frame {
    bool object;
    std::string key;
    bool has_key;  // an object: between a key and the end of its value (a syntax error before the next key is
                   // in the object, not in the previous key's value)
    std::size_t index;
    std::set<std::string> keys;
  };

  bool too_deep() {
    if (frames_.size() < max_json_depth) return false;
    error_ = "nesting deeper than " + std::to_string(max_json_depth) + " levels";
    error_pointer_ = pointer();
    located_ = true;
    return true;
  }

  // After a complete value: the enclosing array moves on to its next element.
  bool value(bool ok) {
    if (!frames_.empty() && !frames_.back().object) ++frames_.back().index;
    if (!frames_.empty() && frames_.back().object) frames_.back().has_key = false;
    return ok;
  }
  std::string pointer(std::size_t depth = std::string::npos) const {
    std::string p;
    for (std::size_t i = 0; i < std::min(depth, frames_.size()); ++i) {
      const Frame& f = frames_[i];
      if (f.object && !f.has_key) break;
      p += '/';
      p += f.object ? pointer_token(f.key) : std::to_string(f.index);
    }
    return p;
  }

  nlohmann::detail::json_sax_dom_parser<json> dom_;
  std::vector<Frame> frames_;
  std::string error_, error_pointer_;
  std::size_t position_ = 0;
  bool located_ = false;
};

// What JSON does not have that scene files are written with: a hint from the text where the parser stopped
// and nlohmann's message.
std::string syntax_hint(const std::string& text, std::size_t at, const std::string& error) {
  if (at >= text.size()) return {};
  const auto word_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '+'; };
  std::size_t begin = at, end = at;
  while (begin > 0 && word_char(text[begin - 1])) --begin;
  while (end < text.size() && word_char(text[end])) ++end;
  std::string word;
  for (const char c : text.substr(begin, end - begin))
    if (c != '-' && c != '+') word += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (word == "nan" || word == "inf" || word == "infinity")
    return " (NaN and Infinity are not JSON numbers, and a scene's numbers must be finite)";
  if (text[at] == '/' || text[at] == '#') return " (JSON has no comments)";
  if (text[at] == '\'') return " (JSON strings and keys take double quotes)";
  if (text[at] == '}' || text[at] == ']') {
    const auto before = text.find_last_not_of(" \t\r\n", at == 0 ? 0 : at - 1);
    if (at > 0 && before != std::string::npos && text[before] == ',') return " (JSON has no trailing commas)";
  }
  if (error.find("parsing object key - invalid literal") != std::string::npos)
    return " (JSON keys are strings in double quotes)";
  return {};
}

}  // namespace

json parse_json(const std::string& text, const std::string& file) {
  if (text.find_first_not_of(" \t\r\n") == std::string::npos) throw InputError(file + ": the file is empty");
  // A UTF-8 byte order mark is skipped (RFC 8259 §8.1 allows it); UTF-16 and UTF-32 are not JSON text.
  for (const std::string_view bom : {std::string_view("\xFF\xFE"), std::string_view("\xFE\xFF")})  // UTF-32LE too
    if (std::string_view(text).substr(0, bom.size()) == bom)
      throw InputError(file + ": the file is UTF-16 or UTF-32 (it starts with a byte order mark): save it as UTF-8");
  // nlohmann stops at a NUL byte as at the end of the input: what follows would be ignored unread.
  if (const auto nul = text.find('\0'); nul != std::string::npos) {
    const auto [line, col] = line_column(text, nul);
    throw InputError(file + ":" + std::to_string(line) + ":" + std::to_string(col) +
                     ": invalid JSON: a NUL byte (JSON text has none)");
  }
  json root;
  TrackingSax sax(root);
  const bool ok = json::sax_parse(text, &sax, json::input_format_t::json, /*strict=*/true);
  if (!ok) {
    const std::size_t at = sax.position() > 0 ? sax.position() - 1 : 0;  // the byte the parser stopped at
    const auto [line, col] = line_column(text, at);
    const std::string position = std::to_string(line) + ":" + std::to_string(col);
    if (sax.located())  // a bad value at a known path: "<file>: <path>: <what> (line:column)"
      throw InputError(file + ": " + (sax.error_pointer().empty() ? "/" : sax.error_pointer()) + ": " + sax.error() +
                       (sax.position() > 0 ? " (at " + position + ")" : ""));
    // A syntax error: "<file>:<line>:<column>: invalid JSON [in <path>]: <what>[ (hint)]".
    throw InputError(file + ":" + position + ": invalid JSON" +
                     (sax.error_pointer().empty() ? "" : " in " + sax.error_pointer()) + ": " + sax.error() +
                     syntax_hint(text, at, sax.error()));
  }
  return root;
}

json read_json_file(const std::string& file) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status status = fs::status(file, ec);
  if (ec) throw InputError(file + ": cannot read the file: " + ec.message());
  if (fs::is_directory(status)) throw InputError(file + ": cannot read the file: it is a directory");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file + ": cannot read the file: " + std::strerror(errno));
  // Read at most one byte past the limit, so a huge (or endless) input is refused without reading it all.
  std::string text;
  char buffer[1 << 16];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    text.append(buffer, static_cast<std::size_t>(in.gcount()));
    if (text.size() > max_input_bytes)
      throw InputError(file + ": the file is larger than the limit of " + std::to_string(max_input_bytes) +
                       " bytes for an input file");
  }
  if (in.bad()) throw InputError(file + ": cannot read the file: read error");
  return parse_json(text, file);
}

// ---- Node ---------------------------------------------------------------------------------------

void Node::fail(const std::string& message) const { throw InputError(file_ + ": " + where() + ": " + message); }

Node Node::at(std::string_view key) const {
  if (auto n = find(key)) return *n;
  fail("missing key \"" + std::string(key) + "\"");
}

std::optional<Node> Node::find(std::string_view key) const {
  if (!v_.is_object()) fail("expected an object, got " + describe(v_));
  const auto it = v_.find(std::string(key));
  if (it == v_.end()) return std::nullopt;
  return Node(*it, ptr_ + "/" + pointer_token(key), file_, adjustments_, directory_);
}

Node Node::at(std::size_t index) const {
  return Node(v_.at(index), ptr_ + "/" + std::to_string(index), file_, adjustments_, directory_);
}

std::string Node::directory() const {
  return directory_ ? *directory_ : std::filesystem::path(file_).parent_path().string();
}

std::size_t Node::size() const {
  if (!v_.is_array()) fail("expected an array, got " + describe(v_));
  return v_.size();
}

void Node::allow_only(std::initializer_list<std::string_view> allowed, std::string_view owner) const {
  allow_only(std::vector<std::string_view>(allowed), owner);
}

void Node::allow_only(const std::vector<std::string_view>& allowed, std::string_view owner) const {
  if (!v_.is_object()) fail("expected an object, got " + describe(v_));
  for (const auto& [key, value] : v_.items()) {
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
    Node(value, ptr_ + "/" + pointer_token(key), file_)
        .fail("unknown key" + (owner.empty() ? std::string() : " for " + std::string(owner)) +
              did_you_mean(key, allowed) + " (allowed: " + list + ")");
  }
}

std::string Node::string() const {
  if (!v_.is_string()) fail("expected a string, got " + describe(v_));
  return v_.get<std::string>();
}

double Node::number() const {
  if (!v_.is_number()) fail("expected a number, got " + describe(v_));
  const double x = v_.get<double>();
  if (!std::isfinite(x)) fail("expected a finite number, got " + format_number(x));
  return x;
}

double Node::positive() const {
  const double x = number();
  if (!(x > 0)) fail("must be > 0, got " + format_number(x));
  return x;
}

double Node::non_negative() const {
  const double x = number();
  if (!(x >= 0)) fail("must be >= 0, got " + format_number(x));
  return x;
}

std::int64_t Node::integer(std::int64_t lo, std::int64_t hi) const {
  const double x = number();
  if (std::trunc(x) != x || x < static_cast<double>(lo) || x > static_cast<double>(hi))
    fail("expected an integer from " + std::to_string(lo) + " to " + std::to_string(hi) + ", got " + format_number(x));
  return static_cast<std::int64_t>(x);
}

Vec3<double> Node::vec3() const {
  if (!v_.is_array() || v_.size() != 3) fail("expected an array of 3 numbers, got " + describe(v_));
  return {at(0).number(), at(1).number(), at(2).number()};
}

Mat3<double> Node::mat3() const {
  if (!v_.is_array() || v_.size() != 3) fail("expected a 3x3 array (3 rows of 3 numbers), got " + describe(v_));
  Mat3<double> M;
  for (std::size_t r = 0; r < 3; ++r) {
    const Node row = at(r);
    if (!row.v_.is_array() || row.v_.size() != 3) row.fail("expected a row of 3 numbers, got " + describe(row.v_));
    for (std::size_t c = 0; c < 3; ++c)
      M(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = row.at(c).number();
  }
  return M;
}

}  // namespace lgi::app
