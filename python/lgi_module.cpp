// python/lgi_module.cpp — lgi._lgi, the extension module of lgi's Python package (python/lgi/__init__.py wraps it).
//
// run_file(path) / run_dict(scene, name, directory): a scene loaded and run by the engine of `lgi run`
// (apps/scene.hpp, apps/runner.hpp: the same loader, method, steps and rows), the GIL released while it integrates;
// a dict is read into JSON by to_json. The rows — the standard columns (t, R11 … R33, omega1 … omega3, energy,
// orthogonality_error, the problem's invariants) — come as the runner's doubles through a RowSink, the numbers
// `lgi run` prints with 17 significant digits: each equals the command's CSV to the last digit. The scene's own
// "output.columns" (quaternion, Euler angles, …) are computed from those rows by the command's mapper
// (apps/output_columns.hpp), and the quaternion always. Returned as a dict of numpy arrays and the summary; errors
// are returned, not raised (the package raises them): "error" holds the command's one-line message and
// "exit_status" its exit status.
//
// view(...): the page of `lgi view`. Batch: many bodies by the batched kernels (core/batch.hpp).
// load_plugin(path): a plugin's problem types (this module is loaded RTLD_GLOBAL so that the plugin finds lgi's
// functions in it, as it finds them in the lgi executable). methods() / problems(): the registry `lgi list` prints.
#include "output_columns.hpp"
#include "plugin_loader.hpp"
#include "output_file.hpp"
#include "registry.hpp"
#include "run_messages.hpp"
#include "runner.hpp"
#include "scene.hpp"
#ifdef LGI_PYTHON_FIT
#include "csv_reader.hpp"
#include "fit_command.hpp"
#include "fit_file.hpp"
#endif
#include "sweep_command.hpp"
#include "sweep_file.hpp"
#include "version.hpp"
#include "view.hpp"

#include <lgi/core/batch.hpp>
#include <lgi/integrators/batch_lgvi.hpp>
#include <lgi/integrators/batch_rkmk.hpp>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace py = pybind11;

namespace lgi::app {
// python_torque.cpp: the problem type "python_torque" and its callables.
const ProblemInfo& problem_info_python_torque();
std::map<std::int64_t, py::object>& python_callables();
std::string take_callback_error();

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

// A run's rows as the runner passes them (runner.hpp, RowSink): the doubles `lgi run` prints with 17 digits.
struct RowTable final : RowSink {
  std::vector<std::string> names;
  std::vector<double> values;  // row-major
  std::size_t rows = 0;
  void row(std::span<const double> columns) override {
    values.insert(values.end(), columns.begin(), columns.end());
    ++rows;
  }
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

// A rows × cols array holding v's numbers (row-major), without copying them: the array owns the vector.
py::array_t<double> matrix(std::vector<double>&& v, std::size_t rows, std::size_t cols) {
  auto owned = std::make_unique<std::vector<double>>(std::move(v));
  const py::capsule owner(owned.get(), [](void* p) { delete static_cast<std::vector<double>*>(p); });
  const double* data = owned.release()->data();
  return py::array_t<double>(std::vector<py::ssize_t>{static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(cols)},
                             data, owner);
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
  RowTable t;
  t.names = split_header(csv_header(scene));
  RunReport report;
  (void)take_callback_error();  // none from an earlier run
  {
    py::gil_scoped_release released;
    RunOptions options;
    options.rows = &t;
    report = run_scene(scene, options);
  }
  const std::size_t m = t.names.size();
  out["names"] = t.names;
  // The quaternion (sign continuous along the run) and the scene's own columns, by the command's mapper (the standard
  // row of every problem holds R in its columns 1 … 9).
  if (m > 9) {
    ColumnMapper quaternion({ColumnGroup::quaternion});
    std::vector<double> q;
    q.reserve(4 * t.rows);
    for (std::size_t r = 0; r < t.rows; ++r)
      quaternion.map(std::span<const double>(t.values.data() + r * m, m), q);
    out["quaternion"] = matrix(std::move(q), t.rows, 4);
  }
  if (!groups.empty()) {
    std::vector<std::string_view> invariants = scene.problem->invariant_names();
    const std::vector<std::string> names = split_header(column_header(groups, invariants));
    ColumnMapper mapper(groups);
    std::vector<double> v;
    for (std::size_t r = 0; r < t.rows; ++r) mapper.map(std::span<const double>(t.values.data() + r * m, m), v);
    out["scene_names"] = names;
    out["scene_data"] = matrix(std::move(v), t.rows, names.size());
  }
  out["data"] = matrix(std::move(t.values), t.rows, m);
  out["summary"] = brief_report(scene, report);
  out["status"] = status_name(report.summary.status);
  out["steps"] = report.summary.steps;
  out["t"] = report.summary.t;
  out["wall_seconds"] = report.wall_seconds;
  out["method"] = std::string(scene.method->traits.name);
  out["exit_status"] = 0;
  if (report.summary.status != RunStatus::completed) {
    auto [status, message] = incomplete_run(scene, report, 0);
    if (const std::string callback = take_callback_error(); !callback.empty()) message = callback;
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

// The JSON value of a Python object given as a document (a scene as a dict): dicts with string keys, lists and
// tuples, strings, bools, ints, finite floats, None, and numpy arrays and scalars (through their tolist()), at most
// max_json_depth deep, as parse_json would read the same document from json.dumps. Anything else is an InputError
// naming `name`, the JSON path (`pointer`) and what is there.
json to_json(py::handle h, const std::string& name, std::string& pointer, std::size_t depth = 0) {
  const auto fail = [&](const std::string& what) -> InputError {
    return InputError(name + ": " + (pointer.empty() ? std::string("/") : pointer) + ": " + what);
  };
  if (depth > max_json_depth) throw fail("nested deeper than " + std::to_string(max_json_depth) + " levels");
  PyObject* o = h.ptr();
  if (o == Py_None) return nullptr;
  if (PyBool_Check(o)) return o == Py_True;
  if (PyLong_Check(o)) {
    int overflow = 0;
    const long long v = PyLong_AsLongLongAndOverflow(o, &overflow);
    if (overflow == 0 && !(v == -1 && PyErr_Occurred())) return v;
    PyErr_Clear();
    throw fail("the integer " + quoted_input(std::string(py::str(h))) + " does not fit in 64 bits");
  }
  if (PyFloat_Check(o)) {
    const double v = PyFloat_AS_DOUBLE(o);
    if (!std::isfinite(v)) throw fail(std::string(std::isnan(v) ? "nan" : "inf") + " is not a number JSON can hold");
    return v;
  }
  if (PyUnicode_Check(o)) {
    Py_ssize_t n = 0;
    const char* s = PyUnicode_AsUTF8AndSize(o, &n);
    if (!s) {
      PyErr_Clear();
      throw fail("a string that is not valid Unicode");
    }
    return std::string(s, static_cast<std::size_t>(n));
  }
  const std::size_t at = pointer.size();
  if (PyDict_Check(o)) {
    json object = json::object();
    PyObject *key = nullptr, *value = nullptr;
    Py_ssize_t position = 0;
    while (PyDict_Next(o, &position, &key, &value)) {
      if (!PyUnicode_Check(key))
        throw fail("a key that is not a string: " + quoted_input(std::string(py::repr(key))));
      const std::string k = py::reinterpret_borrow<py::str>(key);
      pointer += '/';
      pointer += pointer_token(k);
      object[k] = to_json(value, name, pointer, depth + 1);
      pointer.resize(at);
    }
    return object;
  }
  if (PyList_Check(o) || PyTuple_Check(o)) {
    json array = json::array();
    const py::sequence items = py::reinterpret_borrow<py::sequence>(h);
    for (std::size_t i = 0; i < items.size(); ++i) {
      pointer += '/';
      pointer += std::to_string(i);
      array.push_back(to_json(items[i], name, pointer, depth + 1));
      pointer.resize(at);
    }
    return array;
  }
  if (py::hasattr(h, "tolist") && py::hasattr(h, "dtype")) return to_json(h.attr("tolist")(), name, pointer, depth);
  throw fail("a " + std::string(py::str(py::type::handle_of(h).attr("__name__"))) + ", which JSON cannot hold");
}

// lgi.run of a scene given as a dict (to_json), file names in it resolved from `directory`.
py::dict run_dict(const py::dict& scene, const std::string& name, const std::string& directory) {
  json document;
  try {
    std::string pointer;
    document = to_json(scene, name, pointer);
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
      input.body = view_body(parse_scene(document, scene_name, directory));
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

// lgi.Batch: N bodies of one heavy_top or free_body problem (`problem_text`: the scene's "problem" object as JSON)
// held in structure-of-arrays form (core/batch.hpp) between calls, stepped by the batched kernels of `method` (lgvi:
// integrators/batch_lgvi.hpp, rkmk4: batch_rkmk.hpp) with the GIL released. R0 (N × 3 × 3) and omega0 (N × 3) are
// C-ordered float64 (the package checks their shapes and values); b (N, or empty): each body's b (heavy_top).
// Bad arguments raise ValueError with the scene loader's or the kernels' message.
class Batch {
 public:
  Batch(const std::string& problem_text, const py::array_t<double, py::array::c_style | py::array::forcecast>& R0,
        const py::array_t<double, py::array::c_style | py::array::forcecast>& omega0, double h, const std::string& method,
        const py::array_t<double, py::array::c_style | py::array::forcecast>& b, int threads, const std::string& kernel)
      : h_(h), method_(method) {
    const auto n = static_cast<std::size_t>(R0.ndim() > 0 ? R0.shape(0) : 0);
    if (R0.ndim() != 3 || R0.shape(1) != 3 || R0.shape(2) != 3 || omega0.ndim() != 2 ||
        static_cast<std::size_t>(omega0.shape(0)) != n || omega0.shape(1) != 3 ||
        (b.size() != 0 && static_cast<std::size_t>(b.size()) != n))
      throw py::value_error("lgi.Batch: R0 must be N x 3 x 3, omega0 N x 3 and b N (or None)");
    try {
      json document;
      document["problem"] = parse_json(problem_text, "problem");
      document["initial"] = json{{"omega", {0, 0, 0}}};
      document["integrator"] = json{{"method", method}, {"dt", h}};
      document["t_end"] = h;
      scene_ = parse_scene(document, "<batch>", {});
    } catch (const InputError& e) {
      throw py::value_error(e.what());
    }
    top_ = problem_as<HeavyTop<double>>(*scene_.problem);
    free_ = problem_as<FreeBody<double>>(*scene_.problem);
    if (!top_ && !free_)
      throw py::value_error("lgi.Batch: the batched kernels take heavy_top and free_body problems, not " +
                            std::string(scene_.problem->type_name()) + " (run its bodies one by one with lgi.integrate)");
    if (method != "lgvi" && method != "rkmk4")
      throw py::value_error("lgi.Batch: method must be lgvi or rkmk4 (the batched kernels), got " + quoted_input(method));
    bool known = false;
    for (const BatchKernel k : {BatchKernel::automatic, BatchKernel::baseline, BatchKernel::avx2, BatchKernel::avx512,
                                BatchKernel::per_body})
      if (kernel == to_string(k)) {
        kernel_ = k;
        known = true;
      }
    if (!known)
      throw py::value_error("lgi.Batch: kernel must be automatic, baseline, avx2, avx512 or per_body, got " +
                            quoted_input(kernel));
    options_.threads = threads;
    b_.assign(b.data(), b.data() + b.size());
    bodies_.resize(n);
    const double* r = R0.data();
    const double* w = omega0.data();
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t e = 0; e < 9; ++e) bodies_.R[e][i] = r[9 * i + e];
      for (std::size_t j = 0; j < 3; ++j) bodies_.Omega[j][i] = w[3 * i + j];
    }
  }

  // n_steps steps of h for every body that has not stopped (the GIL released); returns the kernels' wall time.
  double step(std::int64_t n_steps) {
    std::string error;
    double seconds = 0;
    {
      py::gil_scoped_release released;
      const auto start = std::chrono::steady_clock::now();
      const std::span<const double> b(b_);
      try {
        if (top_ && method_ == "lgvi") ran_ = integrate_batch_lgvi(*top_, bodies_, t_, h_, n_steps, scene_.options, options_, b, kernel_);
        else if (top_) ran_ = integrate_batch_rkmk4(*top_, bodies_, t_, h_, n_steps, scene_.options, options_, b, kernel_);
        else if (method_ == "lgvi") ran_ = integrate_batch_lgvi(*free_, bodies_, t_, h_, n_steps, scene_.options, options_, b, kernel_);
        else ran_ = integrate_batch_rkmk4(*free_, bodies_, t_, h_, n_steps, scene_.options, options_, b, kernel_);
      } catch (const std::invalid_argument& e) {
        error = e.what();
      }
      seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    if (!error.empty()) throw py::value_error(error);
    t_ += static_cast<double>(n_steps) * h_;
    return seconds;
  }

  std::size_t size() const { return bodies_.size(); }
  double t() const { return t_; }
  std::string kernel() const { return to_string(ran_); }
  py::array_t<double> R() const {
    const std::size_t n = size();
    py::array_t<double> out({static_cast<py::ssize_t>(n), py::ssize_t{3}, py::ssize_t{3}});
    double* p = out.mutable_data();
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t e = 0; e < 9; ++e) p[9 * i + e] = bodies_.R[e][i];
    return out;
  }
  py::array_t<double> omega() const {
    const std::size_t n = size();
    py::array_t<double> out({static_cast<py::ssize_t>(n), py::ssize_t{3}});
    double* p = out.mutable_data();
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < 3; ++j) p[3 * i + j] = bodies_.Omega[j][i];
    return out;
  }
  // StepStatus codes (status_names() names them).
  py::array_t<std::uint8_t> status() const {
    py::array_t<std::uint8_t> out(static_cast<py::ssize_t>(size()));
    std::uint8_t* p = out.mutable_data();
    for (std::size_t i = 0; i < size(); ++i) p[i] = static_cast<std::uint8_t>(bodies_.status[i]);
    return out;
  }
  static std::vector<std::string> status_names() {
    static_assert(static_cast<int>(StepStatus::step_size_underflow) == 3);
    return {"ok", "not_converged", "non_finite", "step_size_underflow"};
  }
  // Good steps each body took in the last step() call.
  py::array_t<std::int64_t> steps() const {
    py::array_t<std::int64_t> out(static_cast<py::ssize_t>(size()));
    std::copy(bodies_.steps.begin(), bodies_.steps.end(), out.mutable_data());
    return out;
  }

 private:
  Scene scene_;  // keeps the problem alive
  const HeavyTop<double>* top_ = nullptr;
  const FreeBody<double>* free_ = nullptr;
  double h_, t_ = 0;
  std::string method_;
  BatchKernel kernel_ = BatchKernel::automatic, ran_ = BatchKernel::automatic;
  BatchOptions options_;
  std::vector<double> b_;
  BodyBatch bodies_;
};

// `command` (sweep_command, fit_command) run on `document` with `options` (its file name and settings), quiet, the
// GIL released, its output written to `output`, or into memory when `output` is empty: its exit status and, written
// into memory, the output's bytes.
template <class Options>
std::pair<int, std::string> run_command(int (*command)(const Options&), Options options, const json& document,
                                        const std::string& output = {}) {
  std::optional<MemoryFile> memory;
  if (output.empty()) memory.emplace();
  options.document = &document;
  options.output = memory ? memory->path() : output;
  options.quiet = true;
  int status = 0;
  {
    py::gil_scoped_release released;
    status = command(options);
  }
  return {status, memory ? memory->contents() : std::string()};
}

// lgi.sweep: the sweep `document` (a sweep file's JSON; `name` names it in messages and its directory resolves file
// names) run by `lgi sweep -o OUTPUT` (sweep_command.hpp) on `threads` threads with the GIL released: its CSV in
// OUTPUT and, when it records crossings, the crossings file beside it (crossings_path). {"crossings": whether it
// wrote one} or {"error", "exit_status"}.
py::dict sweep(const std::string& text, const std::string& name, int threads, const std::string& output) {
  json document;
  bool crossings = false;
  try {
    document = parse_json(text, name);
    // The command's checks, with their messages, before it runs.
    crossings = parse_sweep(document, name).records(Record::crossings);
  } catch (const InputError& e) {
    return input_error(e);
  }
  SweepCommandOptions options;
  options.sweep_file = name;
  options.threads = threads;
  const int status = run_command(sweep_command, options, document, output).first;
  py::dict out;
  if (status != 0) {
    out["error"] = name + ": lgi sweep failed (exit status " + std::to_string(status) + "; its message is on stderr)";
    out["exit_status"] = status;
    return out;
  }
  out["crossings"] = crossings;
  return out;
}

#ifdef LGI_PYTHON_FIT
// lgi.fit: the fit `document` (a fit file's JSON; `name` names it in messages and its directory resolves file names)
// run by `lgi fit` (fit_command.hpp) with the GIL released, its result JSON written into memory. {"result": the
// JSON text, "exit_status": 0, 5 (not usable) or 6 (budget)} or {"error", "exit_status"}.
py::dict fit(const std::string& text, const std::string& name) {
  json document;
  try {
    document = parse_json(text, name);
    (void)parse_fit_document(document, name);  // the command's checks, with their messages, before it runs
  } catch (const CsvError& e) {
    return input_error(InputError(name + ": " + e.what()));
  } catch (const InputError& e) {
    return input_error(e);
  }
  FitCommandOptions options;
  options.fit_file = name;
  const auto [status, result] = run_command(fit_command, options, document);
  py::dict out;
  out["exit_status"] = status;
  if (result.empty())
    out["error"] = name + ": lgi fit failed (exit status " + std::to_string(status) + "; its message is on stderr)";
  else
    out["result"] = result;
  return out;
}
#endif

// lgi.TorqueBody's callable f, under the number `id` scenes name it by (problem.torque).
void register_callable(std::int64_t id, const py::object& f) { python_callables()[id] = f; }

// lgi.load_plugin: the problem types of the plugin at `path` (plugin_loader.hpp); {} or {"error", "exit_status"}.
py::dict plugin(const std::string& path) {
  try {
    load_plugin(path);
  } catch (const InputError& e) {
    return input_error(e);
  }
  return {};
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
  m.def("run_dict", &lgi::app::run_dict, py::arg("scene"), py::arg("name"), py::arg("directory"));
  m.def("view", &lgi::app::view, py::arg("csv"), py::arg("scene_text"), py::arg("scene_name"), py::arg("directory"),
        py::arg("output"), py::arg("axis"), py::arg("max_frames"));
  py::class_<lgi::app::Batch>(m, "Batch")
      .def(py::init<const std::string&, const py::array_t<double, py::array::c_style | py::array::forcecast>&,
                    const py::array_t<double, py::array::c_style | py::array::forcecast>&, double, const std::string&,
                    const py::array_t<double, py::array::c_style | py::array::forcecast>&, int, const std::string&>(),
           py::arg("problem_text"), py::arg("R0"), py::arg("omega0"), py::arg("h"), py::arg("method"), py::arg("b"),
           py::arg("threads"), py::arg("kernel"))
      .def("step", &lgi::app::Batch::step, py::arg("n_steps"))
      .def_property_readonly("size", &lgi::app::Batch::size)
      .def_property_readonly("t", &lgi::app::Batch::t)
      .def_property_readonly("kernel", &lgi::app::Batch::kernel)
      .def_property_readonly("R", &lgi::app::Batch::R)
      .def_property_readonly("omega", &lgi::app::Batch::omega)
      .def_property_readonly("status", &lgi::app::Batch::status)
      .def_property_readonly("steps", &lgi::app::Batch::steps)
      .def_static("status_names", &lgi::app::Batch::status_names);
  m.def("load_plugin", &lgi::app::plugin, py::arg("path"));
  m.def("register_callable", &lgi::app::register_callable, py::arg("id"), py::arg("f"));
  lgi::app::add_problem(lgi::app::problem_info_python_torque());
  m.def("sweep", &lgi::app::sweep, py::arg("text"), py::arg("name"), py::arg("threads"), py::arg("output"));
#ifdef LGI_PYTHON_FIT
  m.def("fit", &lgi::app::fit, py::arg("text"), py::arg("name"));
#endif
  m.def("methods", &lgi::app::methods);
  m.def("problems", &lgi::app::problems);
}
