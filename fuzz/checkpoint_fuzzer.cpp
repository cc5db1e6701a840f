// lgi/fuzz/checkpoint_fuzzer.cpp — libFuzzer harness: checkpoint files (apps/checkpoint.cpp parse_checkpoint), then the
// scene they carry (apps/scene.cpp parse_scene).
//
// Inputs whose first byte is odd have that byte dropped and their checksum line recomputed over the rest (when they
// have one) before parsing: a checkpoint that passes its checksum is what reaches the field-by-field reader, so
// half the inputs explore that reader rather than stop at the checksum. Oracle: a rejected input ends in one
// InputError with one printable line naming the file; an accepted one has finite, consistent numbers (cursor counts
// ≥ 0, an adaptive h > 0, a non-empty output target and partial file), and its scene either loads or is refused the
// same way. Any other exception, a sanitizer report or a hang is a finding.
#include "fuzz_common.hpp"
#include "hashing.hpp"
#include "runner_checkpoint.hpp"
#include "scene.hpp"

#include <cmath>
#include <cstdint>
#include <string>

namespace {

constexpr const char* kFile = "ck.json";
constexpr std::string_view marker = ",\n \"checksum\": \"fnv1a64:";

// The checksum line recomputed, as apps/checkpoint.cpp writes it.
std::string resign(std::string text) {
  const std::size_t at = text.rfind(marker);
  if (at == std::string::npos) return text;
  text.resize(at + marker.size());
  text += lgi::app::hex64(lgi::app::fnv1a(text.data(), at + 2));
  text += "\"\n}\n";
  return text;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace lgi::app;
  if (size == 0 || size > max_input_bytes) return 0;
  std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  if (data[0] & 1) text = resign(std::move(text));
  Checkpoint ck;
  try {
    ck = parse_checkpoint(text, kFile);
  } catch (const InputError& e) {
    lgi::fuzz::check_message(e.what(), kFile);
    return 0;
  }
  const Cursor& c = ck.cursor;
  if (c.steps < 0 || c.n < 0 || c.event < 0 || c.attempts < 0 || c.rejected < 0 || c.next < 0)
    lgi::fuzz::contract_violated("a negative count", text);
  if (c.adaptive && !(c.h > 0 && std::isfinite(c.h) && std::isfinite(c.t) && c.err_old > 0))
    lgi::fuzz::contract_violated("adaptive cursor", text);
  if (ck.output.target.empty() || ck.output.partial.empty()) lgi::fuzz::contract_violated("empty output names", text);
  for (const double v : ck.internal)
    if (!std::isfinite(v)) lgi::fuzz::contract_violated("internal number not finite", text);
  try {
    (void)parse_scene(ck.scene, kFile);
  } catch (const InputError& e) {
    lgi::fuzz::check_message(e.what(), kFile);
  }
  return 0;
}
