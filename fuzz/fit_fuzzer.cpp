// lgi/fuzz/fit_fuzzer.cpp — libFuzzer harness: fit files (apps/fit_file.cpp parse_fit_document) and observation tables
// (parse_csv, then fit::observations_from_table), chosen by the input's first byte: even — the rest is a
// fit file; odd — the rest is an observation CSV, read with sigma_attitude and/or sigma_omega set by bits 1 and 2.
//
// Oracle: a rejected fit file ends in one InputError (or, for the CSV file it names, one CsvError) with one printable
// line naming the file; a rejected table in one CsvError naming the CSV file, or one fit::FitInputError (which
// `lgi fit` prefixes with the file). Any other exception — a FitInputError escaping the fit-file reader among them,
// which the command would report as an internal error — a sanitizer report or a hang is a finding. Nothing is solved.
#include "fit_file.hpp"
#include "fuzz_common.hpp"

#include <cmath>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace lgi::app;
  if (size == 0 || size > max_input_bytes) return 0;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  if ((data[0] & 1) == 0) {
    constexpr const char* kFile = "fit.json";
    try {
      const FitSpec spec = parse_fit_document(parse_json(text, kFile), kFile);
      if (spec.unknowns.empty()) lgi::fuzz::contract_violated("no unknowns", text);
    } catch (const CsvError& e) {
      const std::string m = e.what();  // names the CSV file the fit file gives (relative to it)
      for (const char c : m)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) lgi::fuzz::contract_violated("control character", m);
    } catch (const InputError& e) {
      lgi::fuzz::check_message(e.what(), kFile);
    }
    return 0;
  }
  constexpr const char* kCsv = "obs.csv";
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  std::vector<int> lines;
  try {
    parse_csv(text, kCsv, header, rows, lines);
  } catch (const CsvError& e) {
    lgi::fuzz::check_message(e.what(), kCsv);
    return 0;
  }
  if (rows.size() != lines.size()) lgi::fuzz::contract_violated("rows and lines", text);
  for (const auto& row : rows) {
    if (row.size() != header.size()) lgi::fuzz::contract_violated("row size", text);
    for (const double v : row)
      if (!std::isfinite(v)) lgi::fuzz::contract_violated("a number not finite", text);
  }
  lgi::fit::TableOptions table;
  table.sigma_attitude = (data[0] & 2) ? 1e-3 : 0;
  table.sigma_omega = (data[0] & 4) ? 1e-2 : 0;
  table.field = kCsv;
  try {
    (void)lgi::fit::observations_from_table(header, rows, table);
  } catch (const lgi::fit::FitInputError&) {
  }
  return 0;
}
