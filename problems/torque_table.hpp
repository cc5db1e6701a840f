/// \file
/// lgi/problems/torque_table.hpp — a torque given as a table of samples M(t_i), interpolated in time: the replay of a
/// measured or precomputed disturbance (problems/torqued_body.hpp, the scene's "table" torque term), or of the motor
/// torques commanded to a gyrostat's rotors (problems/gyrostat.hpp, the scene's "motor_table"). SampleTable<D> holds
/// samples in R^D; TorqueTable = SampleTable<3>.
///
/// Samples (t_i, M_i), i = 0 … n−1, n ≥ 2, t_i strictly increasing; on [t_i, t_{i+1}] with u = t − t_i, h_i = t_{i+1} − t_i:
///
/// ~~~{.unparsed}
///   linear:  M(t) = M_i + u (M_{i+1} − M_i) / h_i                                     (C⁰; kinks at the t_i)
///   cubic:   M(t) = M_i + u ((M_{i+1} − M_i)/h_i − h_i (2 m_i + m_{i+1})/6) + u² m_i/2 + u³ (m_{i+1} − m_i)/(6 h_i)
/// ~~~
///
/// with m_i = M''(t_i) the natural cubic spline's second derivatives (C²; m_0 = m_{n−1} = 0, the tridiagonal system
/// h_{i−1} m_{i−1} + 2(h_{i−1} + h_i) m_i + h_i m_{i+1} = 6((M_{i+1} − M_i)/h_i − (M_i − M_{i−1})/h_{i−1}) solved by the
/// Thomas algorithm; de Boor, A Practical Guide to Splines, rev. ed. (2001), ch. IV). An integrator of order p sees
/// the interpolant's smoothness: across a kink of the linear table the local error is O(h²) whatever p, so methods
/// above order 2 keep their order only with steps that end on the t_i; the cubic spline's third derivative jumps at
/// the t_i, which bounds the observed order by 4 in the same way.
///
/// Outside [t_0, t_{n−1}] the first or last interval's polynomial continues: the scene loader refuses a run whose
/// [0, t_end] leaves the table, so only sub-steps that probe beyond a step's end (compositions with a first
/// coefficient above 1) reach it, by less than a step.
#pragma once

#include "../core/scalar.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace lgi {

/// How a table's samples are joined (this header's formulas).
enum class TableInterpolation {
  linear,  ///< straight lines, C⁰
  cubic,   ///< the natural cubic spline, C²
};

/// A table of samples in R^D interpolated in time (this header): a body- or laboratory-frame torque (D = 3), a
/// gyrostat's rotor motor torques (D = its rotor slots). Immutable after construction; shared by the copies of a
/// problem (its cast to Jets included: the samples are data, not parameters).
template <int D>
class SampleTable {
 public:
  using Interpolation = TableInterpolation;        ///< how the samples are joined
  using Sample = Eigen::Matrix<double, D, 1>;      ///< one sample M_i
  template <class T>
  using Value = Eigen::Matrix<T, D, 1>;            ///< M(t) in scalar T

  /// The samples; std::invalid_argument unless there are ≥ 2, of equal count, finite, with t strictly increasing.
  /// `source` names where they came from (the file's path, for messages and checkpoints); `digest`
  /// is a hash of the bytes they were read from (checkpoints compare it), 0 if none.
  SampleTable(std::vector<double> t, std::vector<Sample> M, Interpolation interpolation, std::string source = {},
              std::uint64_t digest = 0)
      : t_(std::move(t)), M_(std::move(M)), source_(std::move(source)), digest_(digest) {
    if (t_.size() < 2 || t_.size() != M_.size())
      throw std::invalid_argument("lgi::TorqueTable: needs at least 2 samples, as many times as torques");
    for (std::size_t i = 0; i < t_.size(); ++i) {
      if (!std::isfinite(t_[i]) || !M_[i].allFinite())
        throw std::invalid_argument("lgi::TorqueTable: sample " + std::to_string(i) + " is not finite");
      if (i > 0 && !(t_[i] > t_[i - 1]))
        throw std::invalid_argument("lgi::TorqueTable: times must increase strictly (sample " + std::to_string(i) + ")");
    }
    // Each interval's polynomial M_i + u (c1 + u (c2 + u c3)), once: linear c1 = slope, c2 = c3 = 0.
    std::vector<Sample> m(t_.size(), Sample::Zero());
    if (interpolation == Interpolation::cubic && t_.size() > 2) m = spline_second_derivatives();
    for (std::size_t i = 0; i + 1 < t_.size(); ++i) {
      const double h = t_[i + 1] - t_[i];
      const Sample slope = (M_[i + 1] - M_[i]) / h;
      if (interpolation == Interpolation::linear)
        c_.push_back({slope, Sample::Zero(), Sample::Zero()});
      else
        c_.push_back({slope - h * (2 * m[i] + m[i + 1]) / 6, m[i] / 2, (m[i + 1] - m[i]) / (6 * h)});
    }
  }

  /// M(t), in the frame the table's user says (this header's formulas). No allocation; the interval by binary
  /// search on value_of(t).
  template <class T>
  Value<T> operator()(const T& t) const {
    const double tv = static_cast<double>(value_of(t));
    const std::size_t n = t_.size();
    std::size_t i = static_cast<std::size_t>(std::upper_bound(t_.begin(), t_.end(), tv) - t_.begin());
    i = std::clamp<std::size_t>(i == 0 ? 0 : i - 1, 0, n - 2);
    const T u = t - T(t_[i]);
    const std::array<Sample, 3>& c = c_[i];
    return M_[i].template cast<T>() +
           u * (c[0].template cast<T>() + u * (c[1].template cast<T>() + u * c[2].template cast<T>()));
  }

  double t_last() const { return t_.back(); }             ///< t_{n−1}
  const std::string& source() const { return source_; }  ///< where the samples came from (messages)
  std::uint64_t digest() const { return digest_; }        ///< hash of the bytes they were read from, 0 if none

 private:
  // The natural spline's m_0 … m_{n−1} (m_0 = m_{n−1} = 0), Thomas algorithm on the diagonally dominant system.
  std::vector<Sample> spline_second_derivatives() const {
    const std::size_t n = t_.size();
    std::vector<Sample> m(n, Sample::Zero());
    std::vector<double> diag(n, 1.0), upper(n, 0.0);
    std::vector<Sample> rhs(n, Sample::Zero());
    for (std::size_t i = 1; i + 1 < n; ++i) {
      const double h0 = t_[i] - t_[i - 1], h1 = t_[i + 1] - t_[i];
      const double lower = (i == 1) ? 0.0 : h0;  // m_0 = 0 drops out of the first row
      diag[i] = 2 * (h0 + h1);
      upper[i] = (i + 2 == n) ? 0.0 : h1;         // m_{n−1} = 0 drops out of the last row
      rhs[i] = 6 * ((M_[i + 1] - M_[i]) / h1 - (M_[i] - M_[i - 1]) / h0);
      if (i > 1) {  // eliminate m_{i−1}
        const double w = lower / diag[i - 1];
        diag[i] -= w * upper[i - 1];
        rhs[i] -= w * rhs[i - 1];
      }
    }
    for (std::size_t i = n - 2; i >= 1; --i) m[i] = (rhs[i] - upper[i] * m[i + 1]) / diag[i];
    return m;
  }

  std::vector<double> t_;
  std::vector<Sample> M_;
  std::vector<std::array<Sample, 3>> c_;  ///< interval i's c1, c2, c3 (the constructor)
  std::string source_;
  std::uint64_t digest_ = 0;
};

/// A body- or laboratory-frame torque table M(t) ∈ R³.
using TorqueTable = SampleTable<3>;

}  // namespace lgi
