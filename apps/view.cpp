// lgi/apps/view.cpp — the page of `lgi view` (view.hpp).
#include "view.hpp"

#include "command.hpp"
#include "csv_reader.hpp"
#include "json_reader.hpp"
#include "output_columns.hpp"
#include "scene.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <string_view>
#include <vector>

// The page's assets, embedded by view_assets.cpp (apps/viewer/ and Debian's libjs-three).
extern "C" {
extern const char lgi_viewer_html[], lgi_viewer_html_end[];
extern const char lgi_viewer_js[], lgi_viewer_js_end[];
extern const char lgi_three_js[], lgi_three_js_end[];
extern const char lgi_orbit_js[], lgi_orbit_js_end[];
}

namespace lgi::app {

namespace {

std::string_view asset(const char* begin, const char* end) { return {begin, static_cast<std::size_t>(end - begin)}; }

// The non-blank lines of the file after the header: the rows of an `lgi run` CSV (CsvStream's count), without
// parsing them.
std::size_t count_rows(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CsvError(path + ": cannot read the run: " + std::strerror(errno));
  std::vector<char> block(std::size_t{1} << 20);
  std::size_t lines = 0;
  bool content = false;  // the current line has a character other than white space
  while (in) {
    in.read(block.data(), static_cast<std::streamsize>(block.size()));
    const auto n = static_cast<std::size_t>(in.gcount());
    for (std::size_t i = 0; i < n; ++i) {
      const char c = block[i];
      if (c == '\n') {
        lines += content;
        content = false;
      } else if (c != ' ' && c != '\t' && c != '\r' && c != '\v' && c != '\f') {
        content = true;
      }
    }
  }
  lines += content;
  return lines == 0 ? 0 : lines - 1;  // the header
}

std::optional<std::size_t> find(const std::vector<std::string>& header, std::string_view name) {
  const auto it = std::find(header.begin(), header.end(), name);
  if (it == header.end()) return std::nullopt;
  return static_cast<std::size_t>(it - header.begin());
}

// The columns of the time, the attitude and the rate groups (output_columns.hpp), which the page does not draw as
// curves.
bool is_attitude_or_rate(std::string_view name) {
  using G = ColumnGroup;
  static constexpr std::array<G, 8> groups{G::t,         G::R,             G::quaternion, G::omega,
                                           G::euler_zxz, G::euler_zxz_deg, G::euler_zyx,  G::euler_zyx_deg};
  static const std::string header = column_header(groups, {});
  for (std::size_t from = 0; from <= header.size();) {
    const std::size_t comma = std::min(header.find(',', from), header.size());
    if (std::string_view(header).substr(from, comma - from) == name) return true;
    from = comma + 1;
  }
  return false;
}

void append_base64(std::string& out, const std::vector<unsigned char>& bytes) {
  static constexpr char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const std::uint32_t v = (std::uint32_t{bytes[i]} << 16) | (std::uint32_t{bytes[i + 1]} << 8) | bytes[i + 2];
    out += digits[v >> 18];
    out += digits[(v >> 12) & 63];
    out += digits[(v >> 6) & 63];
    out += digits[v & 63];
  }
  if (i < bytes.size()) {
    const bool two = i + 1 < bytes.size();
    const std::uint32_t v = (std::uint32_t{bytes[i]} << 16) | (two ? std::uint32_t{bytes[i + 1]} << 8 : 0u);
    out += digits[v >> 18];
    out += digits[(v >> 12) & 63];
    out += two ? digits[(v >> 6) & 63] : '=';
    out += '=';
  }
}

template <class T>
void append_bytes(std::vector<unsigned char>& out, const std::vector<T>& values) {
  const auto* p = reinterpret_cast<const unsigned char*>(values.data());
  out.insert(out.end(), p, p + values.size() * sizeof(T));
}

// Text inlined into a <script> element: "</" written as "<\/" (the same string to JavaScript and JSON, and no
// early end of the element).
std::string script_text(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    out += text[i];
    if (text[i] == '<' && i + 1 < text.size() && text[i + 1] == '/') out += '\\';
  }
  return out;
}

void replace_once(std::string& page, std::string_view placeholder, std::string_view text) {
  const std::size_t at = page.find(placeholder);
  if (at == std::string::npos) throw std::logic_error("viewer template: no " + std::string(placeholder));
  page.replace(at, placeholder.size(), text);
}

json vec_json(const Vec3<double>& v) { return json::array({v(0), v(1), v(2)}); }

// The body as the page draws it (view.hpp): semi-axes of the uniform ellipsoid of inertia J, largest 1, smallest
// at least 0.06 (a disc stays visible), and the principal directions as the columns of a rotation.
json body_json(const ViewBody& body) {
  json b;
  b["known"] = body.known;
  b["problem"] = body.problem;
  if (!body.known) return b;
  const Eigen::SelfAdjointEigenSolver<Mat3<double>> eigen(body.data.J);
  Mat3<double> V = eigen.eigenvectors();
  if (V.determinant() < 0) V.col(2) = -V.col(2);
  const Vec3<double> l = eigen.eigenvalues();
  Vec3<double> s;
  for (int i = 0; i < 3; ++i) s(i) = std::sqrt(std::max(0.0, l((i + 1) % 3) + l((i + 2) % 3) - l(i)));
  const double largest = s.maxCoeff();
  for (int i = 0; i < 3; ++i) s(i) = largest > 0 ? std::max(s(i) / largest, 0.06) : 1.0;
  b["semi_axes"] = vec_json(s);
  b["principal"] = json::array();
  for (int r = 0; r < 3; ++r) b["principal"].push_back(json::array({V(r, 0), V(r, 1), V(r, 2)}));
  b["J"] = json::array();
  for (int r = 0; r < 3; ++r) b["J"].push_back(json::array({body.data.J(r, 0), body.data.J(r, 1), body.data.J(r, 2)}));
  b["gravity"] = body.data.has_gravity;
  b["k"] = vec_json(body.data.k);
  b["z0"] = vec_json(body.data.z0);
  b["rotors"] = json::array();
  for (const Vec3<double>& a : body.data.rotor_axes) b["rotors"].push_back(vec_json(a));
  return b;
}

}  // namespace

ViewBody view_body(const lgi::app::Scene& scene) {
  ViewBody body;
  body.known = true;
  body.problem = std::string(scene.problem->type_name());
  body.data = scene.problem->body();
  body.data.has_gravity = body.data.has_gravity && body.data.b != 0;  // NaN (a b not named): drawn
  return body;
}

bool viewer_available() { return lgi_three_js_end - lgi_three_js > 0; }

std::string make_view_page(const ViewInput& input, const std::string& version, ViewReport* report) {
  if (!viewer_available())
    throw InputError("lgi view: this lgi was built without three.js (Debian's libjs-three; scripts/install-deps.sh "
                     "installs it, then build again)");
  if (input.axis < 1 || input.axis > 3) throw InputError("--axis: must be 1, 2 or 3, got " + std::to_string(input.axis));
  if (input.max_frames < 2) throw InputError("--max-frames: must be at least 2, got " + std::to_string(input.max_frames));
  const std::string& path = input.csv;
  if (std::filesystem::is_directory(path)) throw CsvError(path + ": is a directory, not the CSV of a run");
  const std::size_t n = count_rows(path);

  std::ifstream in(path, std::ios::binary);
  if (!in) throw CsvError(path + ": cannot read the run: " + std::strerror(errno));
  CsvStream csv(in, path, "CSV of a run");
  const std::vector<std::string>& header = csv.header();
  const std::string wants = ": lgi view needs the CSV of lgi run, with t and the attitude (R11 ... R33, or q_w ... "
                            "q_z: output.columns \"R\" or \"quaternion\")";
  const auto col_t = find(header, "t");
  if (!col_t) throw CsvError(path + ": no column t" + wants);
  const auto col_R = find(header, "R11");
  const auto col_q = find(header, "q_w");
  if (!col_R && !col_q) throw CsvError(path + ": no column R11 or q_w" + wants);
  std::array<std::size_t, 9> R_at{};
  std::array<std::size_t, 4> q_at{};
  if (col_R) {
    for (int i = 0; i < 9; ++i) {
      const std::string name{'R', static_cast<char>('1' + i / 3), static_cast<char>('1' + i % 3)};
      const auto c = find(header, name);
      if (!c) throw CsvError(path + ": no column " + name + " (R11 is there)" + wants);
      R_at[static_cast<std::size_t>(i)] = *c;
    }
  } else {
    for (const char* name : {"q_w", "q_x", "q_y", "q_z"}) {
      const auto c = find(header, name);
      if (!c) throw CsvError(path + ": no column " + name + " (q_w is there)" + wants);
      q_at[static_cast<std::size_t>(name[2] == 'w' ? 0 : name[2] - 'x' + 1)] = *c;
    }
  }
  std::array<std::size_t, 3> omega_at{};
  bool has_omega = true;
  for (int i = 0; i < 3; ++i) {
    const auto c = find(header, std::string("omega").append(1, static_cast<char>('1' + i)));
    has_omega = has_omega && c.has_value();
    if (c) omega_at[static_cast<std::size_t>(i)] = *c;
  }
  std::vector<std::size_t> rotor_at;  // rotor_rate_1 ... when every rotor of the body has its column
  for (std::size_t r = 0; r < input.body.data.rotor_axes.size(); ++r) {
    const auto c = find(header, "rotor_rate_" + std::to_string(r + 1));
    if (c) rotor_at.push_back(*c);
  }
  if (rotor_at.size() != input.body.data.rotor_axes.size()) rotor_at.clear();
  std::vector<std::size_t> curve_at;
  for (std::size_t c = 0; c < header.size(); ++c)
    if (!is_attitude_or_rate(header[c])) curve_at.push_back(c);
  if (n == 0) throw CsvError(path + ": no data rows after the header");

  const std::size_t frames = std::min(n, input.max_frames);
  const auto frame_row = [&](std::size_t j) {  // the row of frame j (view.hpp)
    return frames == 1 ? std::size_t{0}
                       : static_cast<std::size_t>(std::llround(static_cast<double>(j) * static_cast<double>(n - 1) /
                                                               static_cast<double>(frames - 1)));
  };
  const std::size_t C = curve_at.size();
  std::vector<double> t;
  std::vector<float> q, omega, lo, hi, rotor_angle;
  std::vector<double> angle(rotor_at.size()), previous_rate(rotor_at.size());
  t.reserve(frames);
  q.reserve(4 * frames);
  if (has_omega) omega.reserve(3 * frames);
  lo.reserve(C * frames);
  hi.reserve(C * frames);
  std::vector<double> first(C), band_lo(C, std::numeric_limits<double>::infinity()),
      band_hi(C, -std::numeric_limits<double>::infinity());
  ColumnMapper quaternion({ColumnGroup::quaternion});
  std::array<double, 10> standard{};  // t, R11 ... R33: the standard row's first columns, for quaternion
  std::vector<double> row, mapped;
  std::size_t i = 0, next_frame = 0;
  double previous_t = -std::numeric_limits<double>::infinity();
  while (csv.next(row)) {
    if (i >= n) throw CsvError(path + ": changed while it was read (more rows than a moment ago)");
    const double ti = row[*col_t];
    if (ti < previous_t)
      throw CsvError(path + ":" + std::to_string(csv.line()) + ": t = " + format_number(ti) + " is before the previous " +
                     "row's t = " + format_number(previous_t) + ": not the rows of one run");
    for (std::size_t r = 0; r < rotor_at.size(); ++r) {
      const double rate = row[rotor_at[r]];
      if (i > 0) angle[r] = std::fmod(angle[r] + 0.5 * (previous_rate[r] + rate) * (ti - previous_t), 2 * std::numbers::pi);
      previous_rate[r] = rate;
    }
    previous_t = ti;
    for (std::size_t c = 0; c < C; ++c) {
      const double v = row[curve_at[c]];
      if (i == 0) first[c] = v;
      band_lo[c] = std::min(band_lo[c], v - first[c]);
      band_hi[c] = std::max(band_hi[c], v - first[c]);
    }
    if (i == frame_row(next_frame)) {
      t.push_back(ti);
      if (col_R) {
        standard[0] = ti;
        for (std::size_t k = 0; k < 9; ++k) standard[1 + k] = row[R_at[k]];
        mapped.clear();
        quaternion.map(standard, mapped);
        for (const double v : mapped) q.push_back(static_cast<float>(v));
      } else {
        double norm = 0;
        for (const std::size_t k : q_at) norm += row[k] * row[k];
        norm = std::sqrt(norm);
        if (!(norm > 0.5 && norm < 2))
          throw CsvError(path + ":" + std::to_string(csv.line()) + ": the quaternion has length " + format_number(norm) +
                         ", not 1: not an attitude");
        for (const std::size_t k : q_at) q.push_back(static_cast<float>(row[k] / norm));
      }
      if (has_omega)
        for (const std::size_t k : omega_at) omega.push_back(static_cast<float>(row[k]));
      for (const double a : angle) rotor_angle.push_back(static_cast<float>(a));
      for (std::size_t c = 0; c < C; ++c) {
        lo.push_back(static_cast<float>(band_lo[c]));
        hi.push_back(static_cast<float>(band_hi[c]));
        band_lo[c] = std::numeric_limits<double>::infinity();
        band_hi[c] = -std::numeric_limits<double>::infinity();
      }
      ++next_frame;
    }
    ++i;
  }
  if (i != n || next_frame != frames) throw CsvError(path + ": changed while it was read (fewer rows than a moment ago)");

  json meta;
  meta["generator"] = "lgi view " + version;
  const std::string name = std::filesystem::path(path).filename().string();
  meta["title"] = input.title.empty() ? "lgi view: " + name : input.title;
  meta["source"] = name;
  meta["rows"] = n;
  meta["frames"] = frames;
  meta["t0"] = t.front();
  meta["t_end"] = t.back();
  meta["axis"] = input.axis;
  meta["has_omega"] = has_omega;
  meta["rotor_angles"] = !rotor_at.empty();
  meta["body"] = body_json(input.body);
  meta["curves"] = json::array();
  for (std::size_t c = 0; c < C; ++c) meta["curves"].push_back({{"name", header[curve_at[c]]}, {"v0", first[c]}});

  // The frames' numbers, little-endian as the browser reads them: t (float64), then q (w, x, y, z), Ω, the curves'
  // lows and highs, the rotors' angles (float32, frame-major).
  std::vector<unsigned char> bytes;
  append_bytes(bytes, t);
  append_bytes(bytes, q);
  append_bytes(bytes, omega);
  append_bytes(bytes, lo);
  append_bytes(bytes, hi);
  append_bytes(bytes, rotor_angle);
  std::string data;
  data.reserve(bytes.size() / 3 * 4 + 4);
  append_base64(data, bytes);

  std::string page(asset(lgi_viewer_html, lgi_viewer_html_end));
  replace_once(page, "@LGI_MARKER@", view_page_marker);
  replace_once(page, "/*@LGI_META@*/", script_text(meta.dump()));
  replace_once(page, "@LGI_DATA@", data);
  replace_once(page, "/*@LGI_THREE@*/", script_text(asset(lgi_three_js, lgi_three_js_end)));
  replace_once(page, "/*@LGI_ORBIT@*/", script_text(asset(lgi_orbit_js, lgi_orbit_js_end)));
  replace_once(page, "/*@LGI_VIEWER@*/", script_text(asset(lgi_viewer_js, lgi_viewer_js_end)));
  if (report) *report = {n, frames, page.size(), t.front(), t.back()};
  return page;
}

int write_view(const ViewInput& input, std::string output, const std::vector<std::string>& inputs,
               const std::string& version, bool quiet) {
  const bool chosen = output.empty();
  if (chosen) {
    const std::filesystem::path csv(input.csv);
    output = (csv.extension() == ".csv" ? std::filesystem::path(csv).replace_extension(".html")
                                        : std::filesystem::path(input.csv + ".html")).string();
  }
  std::vector<std::string> protect = inputs;
  protect.push_back(input.csv);
  for (const std::string& file : protect)
    if (!is_streamed_path(output) && same_file(output, file))
      return fail(exit_bad_input, "view: " + output + " is " + (file == input.csv ? "the run's CSV " : "the input ") +
                                      file + ": lgi does not replace its input (give -o PAGE.html)");
  if (chosen && std::filesystem::exists(output)) {
    std::ifstream in(output, std::ios::binary);
    std::string head(512, '\0');
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<std::size_t>(in.gcount()));
    if (head.find(view_page_marker) == std::string::npos)
      return fail(exit_bad_input, "view: " + output + " exists and is not a page of lgi view: lgi does not replace it "
                                  "(give -o PAGE.html)");
  }
  ViewReport report;
  std::string page;
  try {
    page = make_view_page(input, version, &report);
  } catch (const InputError& e) {
    return fail(exit_bad_input, e.what());
  }
  page += '\n';
  std::unique_ptr<OutputFile> out;
  try {
    out = std::make_unique<OutputFile>(output);
  } catch (const OutputError& e) {
    return fail(exit_io_error, e.what());
  }
  if (!out->write_record(page) || !out->commit())
    return fail(exit_io_error, out->display_name() + ": cannot write the page: " + out->error_text() +
                                   (out->streamed() ? "" : " (nothing was replaced)"));
  if (!quiet)
    std::fprintf(stderr, "lgi view: %s: %zu rows%s, t = %s ... %s, %.1f MB\n", out->display_name().c_str(), report.rows,
                 report.frames < report.rows ? (" shown as " + std::to_string(report.frames) + " frames").c_str() : "",
                 format_number(report.t0).c_str(), format_number(report.t_end).c_str(),
                 static_cast<double>(page.size()) / 1e6);
  return 0;
}

}  // namespace lgi::app
