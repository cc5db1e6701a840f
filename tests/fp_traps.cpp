// Floating-point exception traps for every test executable (linked in by lgi_add_test): an invalid
// operation (0/0, ∞ − ∞, sqrt(−1): the operations that make a NaN), a division by zero or an overflow
// anywhere in a test raises SIGFPE at the instruction that did it, instead of a NaN or ∞ that might travel
// silently into a result. Tests that make non-finite values on purpose (to check that they are caught)
// hold an lgi::test::FpTrapsOff for that part (tests/fp_traps.hpp).
#include "fp_traps.hpp"

#include <gtest/gtest.h>

#include <cfenv>

namespace {

class FpTrapEnvironment : public ::testing::Environment {
 public:
  void SetUp() override {
    std::feclearexcept(FE_ALL_EXCEPT);
    feenableexcept(lgi::test::kTrappedExceptions);
  }
};

// Registered before main() runs the tests (gtest_main calls RUN_ALL_TESTS, which sets environments up).
const auto* const environment = ::testing::AddGlobalTestEnvironment(new FpTrapEnvironment);

}  // namespace
