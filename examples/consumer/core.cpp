// Uses lgi::core alone (SO(3) maps, the state, the drivers' types): exp and log round trip on SO(3).
#include <lgi/core/so3.hpp>

#include <cstdio>

int main() {
  const lgi::Vec3<double> w(0.3, -1.2, 2.0);
  const lgi::Mat3<double> R = lgi::so3::exp(w);
  const double back = (lgi::so3::log(R) - w).norm();
  const double orthogonality = lgi::so3::orthogonality_error(R);
  std::printf("lgi::core: |log(exp(w)) - w| = %.2e, |R^T R - I| = %.2e\n", back, orthogonality);
#if defined(__OPTIMIZE__)
  std::printf("optimised: yes\n");
#else
  std::printf("optimised: no\n");
#endif
  return back < 1e-14 && orthogonality < 1e-14 ? 0 : 1;
}
