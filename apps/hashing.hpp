// lgi/apps/hashing.hpp — the hashes lgi's files carry: 64-bit FNV-1a, written as 16 hexadecimal digits.
//
// FNV-1a (Fowler–Noll–Vo; offset basis 14695981039346656037, prime 1099511628211). Each step
// h ← (h xor byte) · prime is a bijection of h, so two inputs that differ in one byte always hash differently;
// for other changes a collision has probability about 2⁻⁶⁴. A guard against corruption, not against forgery.
#pragma once

#include <cinttypes>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

namespace lgi::app {

inline constexpr std::uint64_t fnv1a_basis = 14695981039346656037ull;

// The FNV-1a hash of `size` bytes, continuing from `hash` (the basis for a fresh hash).
inline std::uint64_t fnv1a(const void* data, std::size_t size, std::uint64_t hash = fnv1a_basis) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= p[i];
    hash *= 1099511628211ull;
  }
  return hash;
}
inline std::uint64_t fnv1a(std::string_view s, std::uint64_t hash = fnv1a_basis) { return fnv1a(s.data(), s.size(), hash); }

// 16 lowercase hexadecimal digits.
inline std::string hex64(std::uint64_t x) {
  char buf[20];
  std::snprintf(buf, sizeof buf, "%016" PRIx64, x);
  return buf;
}

}  // namespace lgi::app
