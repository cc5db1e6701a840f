// Floating-point exception traps in tests (tests/fp_traps.cpp enables them for every test executable).
#pragma once

#include <cfenv>

namespace lgi::test {

inline constexpr int kTrappedExceptions = FE_INVALID | FE_DIVBYZERO | FE_OVERFLOW;

// Turns the traps off for a scope: for the parts of a test that make NaN or ∞ on purpose (to check that the
// library catches them). Restores them, with the flags cleared, at the end of the scope.
class FpTrapsOff {
 public:
  FpTrapsOff() : enabled_(fegetexcept()) { fedisableexcept(FE_ALL_EXCEPT); }
  ~FpTrapsOff() {
    std::feclearexcept(FE_ALL_EXCEPT);
    feenableexcept(enabled_);
  }
  FpTrapsOff(const FpTrapsOff&) = delete;
  FpTrapsOff& operator=(const FpTrapsOff&) = delete;

 private:
  int enabled_;
};

}  // namespace lgi::test
