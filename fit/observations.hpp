/// \file
/// lgi/fit/observations.hpp — what a fit compares the trajectory with, and the residuals it forms.
///
/// Each observation at time t gives a residual block r/σ (σ > 0: its standard deviation), errors on SO(3) and
/// S² taken in the tangent space, never as differences of matrix entries:
///
/// ~~~{.unparsed}
///   attitude          R_obs (rotation matrix, or unit quaternion q = (w, x, y, z) body → laboratory):
///                     r = Log(R_obsᵀ R(t)) ∈ R³ — the rotation, in the body frame, that takes R_obs to R(t);
///                     for R_obs = R(t) Exp(σ n), n ~ N(0, I₃), r/σ = −n + O(σ²): unit-variance residuals.
///   angular_velocity  Ω_obs (gyro, body frame): r = Ω(t) − Ω_obs ∈ R³.
///   body_axis         the laboratory direction d_obs of the body axis a (unit, body frame): with d = R(t) a,
///                     r = θ/sin θ · B(d_obs)ᵀ (d_obs × d) ∈ R², θ = ∠(d_obs, d) — the S² logarithm of
///                     fit/manifolds.hpp in the basis B(d_obs) of d_obs⊥ (so |r| = θ).
/// ~~~
///
/// A shooting target — R(T), Ω(T) or a body-axis direction at the final time T — is an observation at t = T.
/// Robust losses (ceres::HuberLoss, ceres::CauchyLoss with scale s, applied to |r/σ|²) are per observation.
#pragma once

#include <lgi/core/so3.hpp>
#include <lgi/core/state.hpp>

#include "manifolds.hpp"

#include <ceres/loss_function.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

/// lgi::fit: fitting initial conditions and body parameters to observations with Ceres (docs/fitting.md).
namespace lgi::fit {

/// Bad input to the fitting API. what() is "field: message"; field() names the offending input the way a
/// fit file spells it ("observations[3].t", "unknowns[1].name", "initial.R", "integrator.dt"), so that the
/// command line can turn it into a JSON path.
class FitInputError : public std::invalid_argument {
 public:
  /// The error of input `field` (a fit file's spelling), what() = "field: message".
  FitInputError(std::string field, const std::string& message)
      : std::invalid_argument(field + ": " + message), field_(std::move(field)) {}
  /// The offending input, e.g. "observations[3].t".
  const std::string& field() const { return field_; }

 private:
  std::string field_;
};

/// What an observation measures (the header's list): attitude, angular_velocity, body_axis.
enum class ObservationKind { attitude, angular_velocity, body_axis };

/// The robust loss of an observation: none (least squares), huber (ceres::HuberLoss), cauchy (ceres::CauchyLoss).
enum class Loss { none, huber, cauchy };

/// "none" (or ""), "huber", "cauchy"; anything else throws FitInputError naming `field`.
inline Loss loss_from_name(std::string_view name, const std::string& field = "loss") {
  if (name.empty() || name == "none" || name == "trivial") return Loss::none;
  if (name == "huber") return Loss::huber;
  if (name == "cauchy") return Loss::cauchy;
  throw FitInputError(field, "unknown loss '" + std::string(name) + "' (known: none, huber, cauchy)");
}

/// One observation at time t (the header's kinds), with its standard deviation and loss. Build it with the named
/// constructors; check_observations validates a list of them.
struct Observation {
  double t = 0;                                      ///< the time, in [0, t_end] of the fit
  ObservationKind kind = ObservationKind::attitude;  ///< what is observed
  Mat3<double> R = Mat3<double>::Identity();  ///< attitude
  Vec3<double> value = Vec3<double>::Zero();  ///< angular_velocity: Ω_obs; body_axis: d_obs (laboratory)
  Vec3<double> axis = Vec3<double>::UnitZ();  ///< body_axis: the body axis a (body frame)
  double sigma = 1;                           ///< standard deviation (rad, rad/s)
  Loss loss = Loss::none;                     ///< the robust loss (none: least squares)
  double loss_scale = 1;                      ///< in units of σ: the robust loss acts on |r/σ|

  /// An attitude R (rotation body → laboratory, to 1e-9: checked at fit time) at t, σ in rad.
  static Observation attitude(double t, const Mat3<double>& R, double sigma) {
    Observation o;
    o.t = t;
    o.kind = ObservationKind::attitude;
    o.R = R;
    o.sigma = sigma;
    return o;
  }
  /// q = (w, x, y, z), the rotation body → laboratory. Must be a unit quaternion (to 1e-9): checked at fit time.
  static Observation attitude_quaternion(double t, const Eigen::Vector4d& q, double sigma) {
    Observation o = attitude(t, quaternion_to_rotation(q), sigma);
    o.quaternion_norm = q.norm();
    return o;
  }
  /// A gyro reading Ω (body frame, rad per time unit) at t, σ in the same unit.
  static Observation angular_velocity(double t, const Vec3<double>& Omega, double sigma) {
    Observation o;
    o.t = t;
    o.kind = ObservationKind::angular_velocity;
    o.value = Omega;
    o.sigma = sigma;
    return o;
  }
  /// The laboratory direction (unit) of the body axis axis_body (unit, body frame) at t, σ in rad (unit vectors
  /// to 1e-9: checked at fit time).
  static Observation body_axis(double t, const Vec3<double>& axis_body, const Vec3<double>& direction_lab, double sigma) {
    Observation o;
    o.t = t;
    o.kind = ObservationKind::body_axis;
    o.axis = axis_body;
    o.value = direction_lab;
    o.sigma = sigma;
    return o;
  }
  /// Sets the robust loss and its scale (in units of σ, > 0: checked at fit time); returns *this.
  Observation& with_loss(Loss l, double scale = 1) {
    loss = l;
    loss_scale = scale;
    return *this;
  }

  /// The rotation of a quaternion (w, x, y, z), normalised (the check on |q| is separate).
  static Mat3<double> quaternion_to_rotation(const Eigen::Vector4d& q) {
    const Eigen::Quaterniond e(q(0), q(1), q(2), q(3));
    return e.normalized().toRotationMatrix();
  }

  /// The size of the residual block: 2 for body_axis, 3 otherwise.
  int residual_size() const { return kind == ObservationKind::body_axis ? 2 : 3; }

  double quaternion_norm = 1;  ///< set by attitude_quaternion, checked to be 1 within 1e-9
};

namespace detail {
// ‖RᵀR − I‖_F ≤ 1e-9 and det R > 0.
inline bool is_rotation(const Mat3<double>& R) {
  return R.allFinite() && (R.transpose() * R - Mat3<double>::Identity()).norm() <= 1e-9 && R.determinant() > 0;
}
inline std::string fmt(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}
inline bool is_unit(const Vec3<double>& v) { return v.allFinite() && std::abs(v.norm() - 1) <= 1e-9; }
}  // namespace detail

/// Checks every observation (see docs/fitting.md, "Bad input"); throws FitInputError naming the first bad field.
/// Times must lie in [0, t_end] and be non-decreasing; two observations of the same kind at the same time are
/// an error (a repeated row), observations of different kinds may share a time (a CSV row with R and Ω).
inline void check_observations(std::span<const Observation> obs, double t_end) {
  if (obs.empty()) throw FitInputError("observations", "no observations: a fit needs at least one");
  for (std::size_t i = 0; i < obs.size(); ++i) {
    const Observation& o = obs[i];
    const std::string at = "observations[" + std::to_string(i) + "]";
    if (!std::isfinite(o.t) || o.t < 0 || o.t > t_end)
      throw FitInputError(at + ".t", detail::fmt(o.t) + " is outside [0, " + detail::fmt(t_end) + "]");
    if (i > 0 && o.t < obs[i - 1].t)
      throw FitInputError(at + ".t", detail::fmt(o.t) + " is before observations[" + std::to_string(i - 1) +
                                         "].t = " + detail::fmt(obs[i - 1].t) + ": observation times must be increasing");
    for (std::size_t j = i; j-- > 0 && obs[j].t == o.t;)
      if (obs[j].kind == o.kind)
        throw FitInputError(at + ".t", "repeats the time " + detail::fmt(o.t) + " of observations[" + std::to_string(j) +
                                           "] (same kind): observation times must be increasing");
    if (!(o.sigma > 0) || !std::isfinite(o.sigma))
      throw FitInputError(at + ".sigma", "standard deviation must be a finite number > 0, got " + detail::fmt(o.sigma));
    if (o.loss != Loss::none && (!(o.loss_scale > 0) || !std::isfinite(o.loss_scale)))
      throw FitInputError(at + ".loss_scale", "must be a finite number > 0, got " + detail::fmt(o.loss_scale));
    switch (o.kind) {
      case ObservationKind::attitude:
        if (std::abs(o.quaternion_norm - 1) > 1e-9 || !std::isfinite(o.quaternion_norm))
          throw FitInputError(at + ".q", "not a unit quaternion (|q| = " + detail::fmt(o.quaternion_norm) + ")");
        if (!detail::is_rotation(o.R))
          throw FitInputError(at + ".R", "not a rotation matrix (|R^T R - I| > 1e-9 or det R <= 0)");
        break;
      case ObservationKind::angular_velocity:
        if (!o.value.allFinite()) throw FitInputError(at + ".omega", "entries must be finite numbers");
        break;
      case ObservationKind::body_axis:
        if (!detail::is_unit(o.axis)) throw FitInputError(at + ".axis", "must be a unit vector (to 1e-9)");
        if (!detail::is_unit(o.value)) throw FitInputError(at + ".direction", "must be a unit vector (to 1e-9)");
        break;
    }
  }
}

/// The residual r/σ of one observation for the state x (see the header); r has residual_size() entries.
template <class T>
void observation_residual(const Observation& o, const State<T>& x, T* r) {
  using std::atan2;
  using std::sqrt;
  const T inv_sigma = T(1.0 / o.sigma);
  switch (o.kind) {
    case ObservationKind::attitude: {
      const Vec3<T> e = so3::log(Mat3<T>(o.R.template cast<T>().transpose() * x.R));
      for (int i = 0; i < 3; ++i) r[i] = e(i) * inv_sigma;
      return;
    }
    case ObservationKind::angular_velocity:
      for (int i = 0; i < 3; ++i) r[i] = (x.Omega(i) - T(o.value(i))) * inv_sigma;
      return;
    case ObservationKind::body_axis: {
      const Vec3<T> d = x.R * o.axis.template cast<T>();
      const Vec3<T> d_obs = o.value.template cast<T>();
      const Vec3<T> v = d_obs.cross(d);  // sin θ · axis
      const T c = d_obs.dot(d);
      const T s2 = v.squaredNorm();
      T factor;  // θ / sin θ, as in so3::log: a series in sin²θ near 0, atan2 elsewhere
      if (value_of(c) >= 0 && value_of(s2) < so3::small_angle_theta2) {
        static constexpr double a[] = {1.0,          1.0 / 6,        3.0 / 40,        5.0 / 112,       35.0 / 1152,
                                       63.0 / 2816, 231.0 / 13312, 143.0 / 10240, 6435.0 / 557056};
        factor = so3::detail::horner(s2, a);
      } else {
        const T s = sqrt(s2);
        factor = atan2(s, c) / s;
      }
      const Eigen::Matrix<double, 3, 2> B = s2_basis(Vec3<double>(o.value));
      for (int i = 0; i < 2; ++i) r[i] = factor * B.col(i).template cast<T>().dot(v) * inv_sigma;
      return;
    }
  }
}

/// The ceres loss of an observation (nullptr: plain least squares). Ceres applies ρ to s = |r/σ|², so a scale
/// of c σ is ρ's parameter c (HuberLoss(c): quadratic for |r/σ| < c).
inline ceres::LossFunction* make_loss(const Observation& o) {
  switch (o.loss) {
    case Loss::none: return nullptr;
    case Loss::huber: return new ceres::HuberLoss(o.loss_scale);
    case Loss::cauchy: return new ceres::CauchyLoss(o.loss_scale);
  }
  return nullptr;
}

/// What observations_from_table takes from a table: the standard deviations of its attitude and gyro columns.
struct TableOptions {
  double sigma_attitude = 0;  ///< 0: attitudes not used
  double sigma_omega = 0;     ///< 0: angular velocities not used
  std::string field = "observations";  ///< the name errors carry ("observations.csv" ...)
};

/// Observations from a table whose columns follow `lgi run`'s CSV names: t, R11..R33 (attitude) or, without
/// them, q_w..q_z (an attitude as a quaternion, "output.columns"), omega1..3 (gyro). Each row gives an attitude observation when sigma_attitude > 0 and an angular-velocity observation when
/// sigma_omega > 0. Other columns are ignored. Throws FitInputError for a header that names a column twice, a
/// missing t column, a σ given without all of its columns (the missing ones are named), a row whose size differs
/// from the header's, or a table that yields no observation.
inline std::vector<Observation> observations_from_table(std::span<const std::string> header,
                                                        std::span<const std::vector<double>> rows,
                                                        const TableOptions& options) {
  const auto column = [&](std::string_view name) -> int {
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return static_cast<int>(i);
    return -1;
  };
  // A name twice is ambiguous: refused, whatever the column.
  for (std::size_t i = 0; i < header.size(); ++i)
    for (std::size_t j = i + 1; j < header.size(); ++j)
      if (header[i] == header[j])
        throw FitInputError(options.field, "column '" + header[i] + "' appears twice (columns " + std::to_string(i + 1) +
                                               " and " + std::to_string(j + 1) + " of the header)");
  const int t_col = column("t");
  if (t_col < 0) throw FitInputError(options.field, "no column 't'");
  static constexpr std::string_view R_names[9] = {"R11", "R12", "R13", "R21", "R22", "R23", "R31", "R32", "R33"};
  static constexpr std::string_view Q_names[4] = {"q_w", "q_x", "q_y", "q_z"};
  static constexpr std::string_view W_names[3] = {"omega1", "omega2", "omega3"};
  int R_cols[9], Q_cols[4], W_cols[3];
  std::string R_missing, Q_missing, W_missing;
  for (int i = 0; i < 9; ++i)
    if ((R_cols[i] = column(R_names[i])) < 0) R_missing += (R_missing.empty() ? "" : ", ") + std::string(R_names[i]);
  for (int i = 0; i < 4; ++i)
    if ((Q_cols[i] = column(Q_names[i])) < 0) Q_missing += (Q_missing.empty() ? "" : ", ") + std::string(Q_names[i]);
  // Attitudes from R11..R33, or from the quaternion columns q_w..q_z where the R columns are absent.
  const bool from_q = std::count(std::begin(R_cols), std::end(R_cols), -1) == 9 && Q_missing.empty();
  if (from_q) R_missing.clear();
  for (int i = 0; i < 3; ++i)
    if ((W_cols[i] = column(W_names[i])) < 0) W_missing += (W_missing.empty() ? "" : ", ") + std::string(W_names[i]);
  // A declared observation type (its σ given) needs all of its columns: none is dropped silently.
  if (options.sigma_attitude > 0 && !R_missing.empty())
    throw FitInputError(options.field, "sigma_attitude is given but the attitude columns " + R_missing +
                                           " are missing (need R11..R33, or q_w..q_z)");
  if (options.sigma_omega > 0 && !W_missing.empty())
    throw FitInputError(options.field, "sigma_omega is given but the angular-velocity columns " + W_missing +
                                           " are missing (need omega1..omega3)");
  const bool use_R = options.sigma_attitude > 0, use_W = options.sigma_omega > 0;
  if (!use_R && !use_W)
    throw FitInputError(options.field, "no usable columns: need R11..R33 with a attitude sigma, or omega1..omega3 "
                                       "with an angular-velocity sigma");
  std::vector<Observation> out;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const std::vector<double>& row = rows[r];
    if (row.size() != header.size())
      throw FitInputError(options.field + "[" + std::to_string(r) + "]", "row has " + std::to_string(row.size()) +
                                                                            " values, the header " +
                                                                            std::to_string(header.size()));
    const double t = row[static_cast<std::size_t>(t_col)];
    if (use_R && from_q) {
      Eigen::Vector4d q;
      for (int i = 0; i < 4; ++i) q(i) = row[static_cast<std::size_t>(Q_cols[i])];
      out.push_back(Observation::attitude_quaternion(t, q, options.sigma_attitude));
    } else if (use_R) {
      Mat3<double> R;
      for (int i = 0; i < 9; ++i) R(i / 3, i % 3) = row[static_cast<std::size_t>(R_cols[i])];
      out.push_back(Observation::attitude(t, R, options.sigma_attitude));
    }
    if (use_W) {
      Vec3<double> W;
      for (int i = 0; i < 3; ++i) W(i) = row[static_cast<std::size_t>(W_cols[i])];
      out.push_back(Observation::angular_velocity(t, W, options.sigma_omega));
    }
  }
  return out;
}

}  // namespace lgi::fit
