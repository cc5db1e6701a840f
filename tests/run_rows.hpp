// tests/run_rows.hpp — a scene run by the command's runner with its rows written to a CSV file, and the file's rows
// read back as numbers (csv_reader.hpp): what `lgi run SCENE -o FILE` writes. Shared by test_scene and
// test_error_estimate (they link lgi_scene).
#pragma once

#include <csv_reader.hpp>
#include <output_file.hpp>
#include <runner.hpp>
#include <scene.hpp>

#include <cstdio>
#include <string>
#include <vector>

namespace lgi::test {

// Runs `scene` with its rows written to `path` (committed whether or not the run completed), reads them back without
// the header and removes the file. `report`, when given, receives the run's report.
inline std::vector<std::vector<double>> run_csv_rows(const app::Scene& scene, const std::string& path,
                                                     app::RunReport* report = nullptr) {
  {
    app::OutputFile out(path);
    app::RunOptions options;
    options.csv = &out;
    const app::RunReport r = app::run_scene(scene, options);
    if (report) *report = r;
    if (!out.commit()) return {};
  }
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  std::vector<int> lines;
  app::read_csv(path, header, rows, lines, "run");
  std::remove(path.c_str());
  return rows;
}

}  // namespace lgi::test
