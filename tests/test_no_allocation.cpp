// No heap allocation in the step loop, measured: this executable counts every call to malloc, calloc,
// realloc, aligned_alloc and posix_memalign in the process (operator new goes through malloc), and
// checks that stepping and driving every integrator on every problem makes none.
// (Interposing malloc clashes with sanitizer runtimes, which interpose it themselves: under ASan the
// counter is off and the test is skipped.)
#include "test_problems.hpp"

#include <lgi/core/driver.hpp>
#include <lgi/integrators/lgvi.hpp>
#include <lgi/integrators/rkmk.hpp>
#include <lgi/problems/free_body.hpp>
#include <lgi/problems/heavy_top.hpp>

#include <gtest/gtest.h>

#include <atomic>
#include <cstddef>
#include <span>
#include <vector>

#if defined(__SANITIZE_ADDRESS__)
#define LGI_COUNT_ALLOCATIONS 0
#else
#define LGI_COUNT_ALLOCATIONS 1
#endif

namespace {
std::atomic<long> g_allocations{0};
}  // namespace

#if LGI_COUNT_ALLOCATIONS
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);

void* malloc(std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(n);
}
void* calloc(std::size_t n, std::size_t m) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_calloc(n, m);
}
void* realloc(void* p, std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_realloc(p, n);
}
void* aligned_alloc(std::size_t a, std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_memalign(a, n);
}
int posix_memalign(void** p, std::size_t a, std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  *p = __libc_memalign(a, n);
  return *p ? 0 : 12;  // ENOMEM
}
}
#endif

namespace lgi {
namespace {

template <template <class> class Method, class P>
void expect_no_allocation(const P& problem, const State<double>& x0) {
  Method<P> stepper(problem);
  auto y = stepper.to_internal(x0, 0.0);
  std::vector<double> sampled;  // observer storage, reserved before the loop
  sampled.reserve(64);
  auto observe = [&](double t, const State<double>&) { sampled.push_back(t); };
  const double times[] = {0.5, 0.75, 1.0};

  const long before = g_allocations.load();
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(stepper.step(y, 0.001 * i, 0.001), StepStatus::ok);
  State<double> x = x0;
  integrate_times(stepper, x, 0.0, 0.001, std::span<const double>(times), observe);
  integrate_every(stepper, x, 0.0, 0.001, 1.0, 100, observe, [](std::int64_t) { return true; });
  const long after = g_allocations.load();
  EXPECT_EQ(after - before, 0) << Method<P>::traits.name << " on " << P::name;
}

TEST(NoAllocation, CounterWorks) {
  if (!LGI_COUNT_ALLOCATIONS) GTEST_SKIP() << "allocation counter disabled under sanitizers";
  const long before = g_allocations.load();
  std::vector<double> v(100);
  EXPECT_GT(g_allocations.load(), before);  // the counter sees allocations at all
}

TEST(NoAllocation, StepLoopsOfEveryIntegrator) {
  if (!LGI_COUNT_ALLOCATIONS) GTEST_SKIP() << "allocation counter disabled under sanitizers";
  const auto top = test::skew_heavy_top();
  const auto body = FreeBody<double>::hairer_vilmart();
  const State<double> x0 = test::skew_initial_state();
  expect_no_allocation<Lgvi>(top, x0);
  expect_no_allocation<Rkmk4>(top, x0);
  expect_no_allocation<LieEuler>(top, x0);
  expect_no_allocation<Lgvi>(body, x0);
  expect_no_allocation<Rkmk4>(body, x0);
  expect_no_allocation<LieEuler>(body, x0);
}

}  // namespace
}  // namespace lgi
