// lgi/fuzz/sweep_fuzzer.cpp — libFuzzer harness: sweep files (apps/sweep_file.cpp parse_sweep), then some of their
// members (member_values, member_scene).
//
// Oracle: a rejected input ends in one InputError with one printable line naming the file; an accepted sweep has
// between 1 and max_members members, a header that starts with "member", and its first, last and middle members'
// values are finite numbers whose scenes load or are refused the same way. Nothing runs (the runner is not in this
// harness: its methods under ASan would cost the CI minutes of compile time).
#include "fuzz_common.hpp"
#include "json_reader.hpp"
#include "sweep_file.hpp"

#include <cmath>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace lgi::app;
  constexpr const char* kFile = "sweep.json";
  if (size > max_input_bytes) return 0;
  const std::string text(reinterpret_cast<const char*>(data), size);
  Sweep s;
  try {
    s = parse_sweep(parse_json(text, kFile), kFile);
  } catch (const InputError& e) {
    lgi::fuzz::check_message(e.what(), kFile);
    return 0;
  }
  if (s.members < 1 || s.members > max_members) lgi::fuzz::contract_violated("member count", std::to_string(s.members));
  if (s.header.rfind("member", 0) != 0) lgi::fuzz::contract_violated("header", s.header);
  for (const std::int64_t m : {std::int64_t{0}, s.members / 2, s.members - 1}) {
    const std::vector<double> v = member_values(s, m);
    for (const double x : v)
      if (!std::isfinite(x)) lgi::fuzz::contract_violated("a member value not finite", member_label(s, m, v));
    try {
      (void)member_scene(s, v, member_label(s, m, v));
    } catch (const InputError& e) {
      lgi::fuzz::check_message(e.what(), kFile);
    }
  }
  return 0;
}
