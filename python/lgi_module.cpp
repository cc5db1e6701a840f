// python/lgi_module.cpp — lgi._lgi, the extension module of lgi's Python package (python/lgi/__init__.py wraps it).
//
// run_file(path) / run_text(json, name): a scene loaded and run by the engine of `lgi run` (apps/scene.hpp,
// apps/runner.hpp: the same loader, method, steps and rows), the GIL released while it integrates. The rows are
// written as `lgi run` writes them — 17 significant digits, the standard columns (t, R11 … R33, omega1 … omega3,
// energy, orthogonality_error, the problem's invariants) — into an anonymous memory file, and read back with
// strtod: every number equals the command's CSV to the last digit. The scene's own "output.columns" (quaternion,
// Euler angles, …) are computed from those rows by the command's mapper (apps/output_columns.hpp), and the
// quaternion always. Returned as a dict of numpy arrays and the summary; errors are returned, not raised (the
// package raises them): "error" holds the command's one-line message and "exit_status" its exit status.
//
// methods() / problems(): the registry `lgi list` prints.
#include "output_columns.hpp"
#include "output_file.hpp"
#include "registry.hpp"
#include "run_messages.hpp"
#include "runner.hpp"
#include "scene.hpp"
#include "version.hpp"
#include "view.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace py = pybind11;

namespace lgi::app {
namespace {

// An anonymous memory file (memfd_create) named for OutputFile as /proc/self/fd/N: streamed, never on disk.
class MemoryFile {
 public:
  MemoryFile() : fd_(::memfd_create("lgi-rows", MFD_CLOEXEC)) {
    if (fd_ < 0) throw std::runtime_error(std::string("lgi: memfd_create: ") + std::strerror(errno));
  }
  MemoryFile(const MemoryFile&) = delete;
  MemoryFile& operator=(const MemoryFile&) = delete;
  ~MemoryFile() { ::close(fd_); }
  std::string path() const { return "/proc/self/fd/" + std::to_string(fd_); }
  std::string contents() const {
    std::string text;
    char buf[1 << 16];
    for (off_t at = 0;;) {
      const ssize_t n = ::pread(fd_, buf, sizeof buf, at);
      if (n <= 0) break;
      text.append(buf, static_cast<std::size_t>(n));
      at += n;
    }
    return text;
  }

 private:
  int fd_;
};

struct Table {
  std::vector<std::string> names;
  std::vector<double> values;  // row-major
  std::size_t rows = 0;
};

// The column names of a CSV header row (without its newline).
std::vector<std::string> split_header(std::string_view header) {
  std::vector<std::string> names;
  for (std::size_t from = 0; from <= header.size();) {
    const std::size_t comma = std::min(header.find(',', from), header.size());
    names.emplace_back(header.substr(from, comma - from));
    from = comma + 1;
  }
  return names;
}

Table parse_rows(const std::string& text) {
  Table t;
  std::size_t at = text.find('\n');
  if (at == std::string::npos) return t;
  t.names = split_header(std::string_view(text).substr(0, at));
  const char* p = text.c_str() + at + 1;
  while (*p) {
    for (std::size_t k = 0; k < t.names.size(); ++k) {
      char* end = nullptr;
      t.values.push_back(std::strtod(p, &end));
      p = end + 1;  // past ',' or '\n'
    }
    ++t.rows;
  }
  return t;
}

py::array_t<double> matrix(const std::vector<double>& v, std::size_t rows, std::size_t cols) {
  py::array_t<double> a(std::vector<py::ssize_t>{static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(cols)});
  if (!v.empty()) std::memcpy(a.mutable_data(), v.data(), v.size() * sizeof(double));
  return a;
}

std::string status_name(RunStatus s) {
  switch (s) {
    case RunStatus::completed: return "completed";
    case RunStatus::step_failed: return "step_failed";
    case RunStatus::stopped: return "stopped";
  }
  return "?";
}

// What run() returns for input that does not load: the command's message and exit status.
py::dict input_error(const InputError& e) {
  py::dict out;
  out["error"] = std::string(e.what());
  out["exit_status"] = exit_bad_input;
  return out;
}

py::dict run(const json& document, const std::string& name, const std::string& directory) {
  py::dict out;
  Scene scene;
  try {
    scene = parse_scene(document, name, directory);
  } catch (const InputError& e) {
    return input_error(e);
  }
  const std::vector<ColumnGroup> groups = scene.columns;
  scene.columns.clear();  // the standard row; the scene's columns are mapped from it below
  MemoryFile memory;
  RunReport report;
  std::string text;
  {
    py::gil_scoped_release released;
    OutputFile csv(memory.path());
    RunOptions options;
    options.csv = &csv;
    report = run_scene(scene, options);
    if (!csv.flush()) report.write_failed = true;
    text = memory.contents();
  }
  const Table t = parse_rows(text);
  const std::size_t m = t.names.size();
  out["names"] = t.names;
  out["data"] = matrix(t.values, t.rows, m);
  // The quaternion (sign continuous along the run) and the scene's own columns, by the command's mapper (the standard
  // row of every problem holds R in its columns 1 … 9).
  if (m > 9) {
    ColumnMapper quaternion({ColumnGroup::quaternion});
    std::vector<double> q;
    q.reserve(4 * t.rows);
    for (std::size_t r = 0; r < t.rows; ++r)
      quaternion.map(std::span<const double>(t.values.data() + r * m, m), q);
    out["quaternion"] = matrix(q, t.rows, 4);
  }
  if (!groups.empty()) {
    std::vector<std::string_view> invariants = scene.problem->invariant_names();
    const std::vector<std::string> names = split_header(column_header(groups, invariants));
    ColumnMapper mapper(groups);
    std::vector<double> v;
    for (std::size_t r = 0; r < t.rows; ++r) mapper.map(std::span<const double>(t.values.data() + r * m, m), v);
    out["scene_names"] = names;
    out["scene_data"] = matrix(v, t.rows, names.size());
  }
  out["summary"] = brief_report(scene, report);
  out["status"] = status_name(report.summary.status);
  out["steps"] = report.summary.steps;
  out["t"] = report.summary.t;
  out["wall_seconds"] = report.wall_seconds;
  out["method"] = std::string(scene.method->traits.name);
  out["exit_status"] = 0;
  if (report.write_failed) {
    out["error"] = scene.file + ": the rows could not be written to memory (" + std::string(std::strerror(ENOMEM)) + ")";
    out["exit_status"] = exit_io_error;
  } else if (report.summary.status != RunStatus::completed) {
    auto [status, message] = incomplete_run(scene, report, 0);
    out["error"] = scene.file + ": " + message + "; the result holds the rows to t = " + format_number(report.summary.t);
    out["exit_status"] = status;
  } else if (report.rows_not_finite > 0) {
    out["error"] = scene.file + ": " + std::to_string(report.rows_not_finite) +
                   " rows were not written: a column was not finite (energy or an invariant overflowed), the first at "
                   "t = " + format_number(report.first_not_finite_t);
    out["exit_status"] = exit_run_failed;
  }
  return out;
}

py::dict run_file(const std::string& path) {
  json document;
  try {
    document = read_json_file(path);
  } catch (const InputError& e) {
    return input_error(e);
  }
  return run(document, path, {});
}

py::dict run_text(const std::string& text, const std::string& name, const std::string& directory) {
  json document;
  try {
    document = parse_json(text, name);
  } catch (const InputError& e) {
    return input_error(e);
  }
  return run(document, name, directory);
}

// lgi.view: the page of `lgi view` of the run's CSV at `csv` (view.hpp), written to `output`; the body from the scene
// (`scene_text`, JSON; empty: not known). {"rows", "frames", "bytes"}, or {"error", "exit_status"} as the command.
py::dict view(const std::string& csv, const std::string& scene_text, const std::string& scene_name,
              const std::string& directory, const std::string& output, int axis, std::size_t max_frames) {
  ViewInput input;
  input.csv = csv;
  input.axis = axis;
  input.max_frames = max_frames;
  ViewReport report;
  std::string page;
  try {
    if (!scene_text.empty()) {
      const json document = parse_json(scene_text, scene_name);
      input.body = view_body(parse_scene(document, scene_name, directory), document);
    }
    page = make_view_page(input, LGI_VERSION_STRING, &report) + "\n";
  } catch (const InputError& e) {
    return input_error(e);
  }
  py::dict out;
  try {
    OutputFile file(output);
    if (!file.write_record(page) || !file.commit()) {
      out["error"] = file.display_name() + ": cannot write the page: " + file.error_text();
      out["exit_status"] = exit_io_error;
      return out;
    }
  } catch (const OutputError& e) {
    out["error"] = std::string(e.what());
    out["exit_status"] = exit_io_error;
    return out;
  }
  out["rows"] = report.rows;
  out["frames"] = report.frames;
  out["bytes"] = page.size();
  return out;
}

py::list methods() {
  py::list list;
  for (const MethodInfo& m : method_registry()) {
    const MethodTraits& t = m.traits;
    py::dict d;
    d["name"] = std::string(t.name);
    d["title"] = std::string(t.title);
    d["order"] = t.order;
    d["free_body_order"] = t.free_body_order > 0 ? t.free_body_order : t.order;
    d["symplectic"] = t.symplectic;
    d["symmetric"] = t.symmetric;
    d["explicit"] = t.explicit_method;
    d["exact_on_group"] = t.exact_on_group;
    d["preserves_momentum"] = t.preserves_momentum;
    d["exact_solution"] = t.exact_solution;
    std::vector<std::string> options;
    for (const std::string_view o : t.options)
      if (!o.empty()) options.emplace_back(o);
    d["options"] = options;
    list.append(d);
  }
  return list;
}

py::list problems() {
  py::list list;
  for (const ProblemInfo& p : problem_registry()) {
    py::dict d;
    d["name"] = std::string(p.name);
    d["summary"] = std::string(p.summary);
    d["keys"] = std::vector<std::string>(p.keys.begin(), p.keys.end());
    d["methods"] = std::vector<std::string>(p.methods.begin(), p.methods.end());
    list.append(d);
  }
  return list;
}

}  // namespace
}  // namespace lgi::app

PYBIND11_MODULE(_lgi, m) {
  m.doc() = "lgi's engine (lgi run) for Python; use the package lgi";
  m.def("run_file", &lgi::app::run_file, py::arg("path"));
  m.def("run_text", &lgi::app::run_text, py::arg("text"), py::arg("name"), py::arg("directory"));
  m.def("view", &lgi::app::view, py::arg("csv"), py::arg("scene_text"), py::arg("scene_name"), py::arg("directory"),
        py::arg("output"), py::arg("axis"), py::arg("max_frames"));
  m.def("methods", &lgi::app::methods);
  m.def("problems", &lgi::app::problems);
}
