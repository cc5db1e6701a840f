// lgi/fuzz/fuzz_common.hpp — what the libFuzzer harnesses share: the contract of a rejected input (one InputError,
// one printable line that starts with the file's name) checked as an oracle, and an abort that libFuzzer reports.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

namespace lgi::fuzz {

[[noreturn]] inline void contract_violated(const char* what, const std::string& detail) {
  std::fprintf(stderr, "fuzzer: contract violated: %s\n%s\n", what, detail.c_str());
  std::abort();
}

// A rejected input: one line, printable, naming `file` first ("file: ...", "file:<line>..." or, for a sweep's member,
// "file (member ...): ...").
inline void check_message(const std::string& m, std::string_view file) {
  if (m.rfind(file, 0) != 0 || m.size() <= file.size() || (m[file.size()] != ':' && m.compare(file.size(), 2, " (") != 0))
    contract_violated("the message does not start with the file name", m);
  for (const char c : m)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) contract_violated("a control character in the message", m);
}

}  // namespace lgi::fuzz
