// python/python_torque.cpp — the problem type "python_torque" of the Python package: a rigid body whose torque is a
// Python callable (lgi.TorqueBody), the slow path for torques lgi's scenes do not offer.
//
//   J Ω' = (JΩ) × Ω + M(t, R, Ω),   R' = R hat(Ω),   M = f(t, R, Ω) (body frame), f the callable
//
// (core/problem.hpp, StateTorqueProblem). f takes t (float), R (3 × 3 array, body → laboratory) and Ω (3 array,
// body frame) and returns 3 numbers; it is called once per stage with the GIL taken. No potential: the energy column
// is the kinetic energy ½ Ω·JΩ, changed by the torque's work; the columns after it are the spatial momentum
// m = R J Ω and |JΩ| (rigid_body's). An exception raised by f, or a result that is not 3 finite numbers, makes the
// torque NaN: the step fails (non_finite), the run stops there with its rows, and the package raises RunError with
// f's message (callback_error). Methods: lgvi (its forced form, ∂M/∂Ω by forward differences, integrators/lgvi.hpp),
// rkmk4 and rkmk_vern9_cayley (LGI_ENABLED_METHODS in python/CMakeLists.txt).
#include "problem_model.hpp"
#include "registry.hpp"

#include <lgi/core/invariants.hpp>
#include <lgi/core/problem.hpp>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <string_view>

namespace py = pybind11;

namespace lgi::app {

// The callables scenes name by number (problem.torque), held for the life of the module: a problem's copies (inside
// steppers, on threads without the GIL) carry only the borrowed pointer.
std::map<std::int64_t, py::object>& python_callables() {
  static auto* callables = new std::map<std::int64_t, py::object>();  // never destroyed: no decref at exit
  return *callables;
}

// The first error a callable raised since the last call of take_callback_error (the GIL guards it).
std::string& callback_error() {
  static std::string error;
  return error;
}

std::string take_callback_error() {
  std::string e;
  e.swap(callback_error());
  return e;
}

struct PythonTorqueBody {
  using Scalar = double;
  static constexpr std::string_view name = "python_torque";
  static constexpr bool has_torque = true;

  Mat3<double> inertia = Mat3<double>::Identity();  // J, body frame
  PyObject* function = nullptr;                      // borrowed from python_callables()
  std::int64_t id = 0;

  double potential(const Mat3<double>&) const { return 0.0; }

  [[gnu::noinline]] Vec3<double> torque(const double& t, const Mat3<double>& R, const Vec3<double>& Omega) const {
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    py::gil_scoped_acquire gil;
    try {
      py::array_t<double> Rp({py::ssize_t{3}, py::ssize_t{3}});
      py::array_t<double> wp(py::ssize_t{3});
      double* r = Rp.mutable_data();
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r[3 * i + j] = R(i, j);
      for (int i = 0; i < 3; ++i) wp.mutable_data()[i] = Omega(i);
      const py::object result = py::reinterpret_borrow<py::object>(function)(t, Rp, wp);
      const auto M = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(result);
      if (!M || M.size() != 3) {
        if (callback_error().empty())
          callback_error() = "the torque callable returned " + std::string(py::repr(result)) + " at t = " +
                             format_number(t) + ", not 3 numbers";
        return Vec3<double>::Constant(nan);
      }
      const Vec3<double> out(M.data()[0], M.data()[1], M.data()[2]);
      if (!out.allFinite() && callback_error().empty())
        callback_error() = "the torque callable returned a number that is not finite at t = " + format_number(t);
      return out;
    } catch (py::error_already_set& e) {
      if (callback_error().empty())  // one line: the exception's type and message
        callback_error() = "the torque callable raised at t = " + format_number(t) + ": " +
                           std::string(py::str(e.type().attr("__name__"))) + ": " + std::string(py::str(e.value()));
      return Vec3<double>::Constant(nan);
    }
  }

  // TorquedBody's columns (core/invariants.hpp), none an integral of the motion.
  static constexpr std::array<std::string_view, 4> invariant_names = momentum_column_names;
  static constexpr std::size_t integral_count = 0;
  std::array<double, 4> invariants(const State<double>& x) const { return momentum_columns(inertia, x); }
};

namespace {
PythonTorqueBody parse(const Node& p) {
  PythonTorqueBody body;
  body.inertia = read_inertia(p.at("inertia"));
  const Node torque = p.at("torque");
  body.id = torque.integer(0, std::numeric_limits<std::int64_t>::max());
  const auto& callables = python_callables();
  const auto it = callables.find(body.id);
  if (it == callables.end()) torque.fail("no Python callable has the number " + std::to_string(body.id) + " (lgi.TorqueBody gives it)");
  body.function = it->second.ptr();
  return body;
}
}  // namespace

LGI_DEFINE_PROBLEM(python_torque, PythonTorqueBody,
                   "a rigid body whose torque is a Python callable f(t, R, Omega) (lgi.TorqueBody; the slow path)",
                   ({"type", "inertia", "torque"}), parse)

}  // namespace lgi::app
