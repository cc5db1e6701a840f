// Heap allocations counted in the whole process (allocation_counter.cpp interposes malloc, calloc, realloc,
// aligned_alloc and posix_memalign; operator new goes through malloc), for the tests that check that a loop
// allocates nothing. Link allocation_counter.cpp into the test executable (tests/CMakeLists.txt does it for the
// tests that include this header).
#pragma once

namespace lgi::test {

// Interposing malloc clashes with the sanitizers' runtimes, which interpose it themselves: under ASan nothing is
// counted, and the tests that need the count skip.
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool counting_allocations = false;
#else
inline constexpr bool counting_allocations = true;
#endif

// The allocations of this process so far.
long allocations();

}  // namespace lgi::test
