// lgi/apps/view.hpp — `lgi view`: one self-contained HTML page that animates a run in 3D (docs/viewer.md).
//
// The page holds everything it shows — three.js (Debian's libjs-three, inlined), the viewer's code
// (apps/viewer/), the run's frames — and opens offline in any browser with WebGL. It draws:
//   - the body: the uniform solid ellipsoid with the body's inertia (semi-axes a_i² = 5/2 (J_j + J_k − J_i) in the
//     principal frame, up to scale), placed so that the fixed point is its tip when the problem has gravity
//     (centre along z0); a box of arbitrary proportions when the inertia is not known (no scene given);
//   - the body axes, the laboratory axes, the unit sphere, the direction of gravity −k;
//   - the trace of a body axis R e_i on the unit sphere up to the current time;
//   - the angular velocity R Ω and the angular momentum R J Ω (J known), scaled to their largest length in the run;
//   - a gyrostat's rotors as discs on their axes outside the body, turned by the angle ∫ rotor_rate_i dt (the
//     trapezoidal rule over every row of the CSV; at the frames' spacing a fast wheel appears stroboscopically);
//   - beside the scene, every column other than t, the attitude and Ω as its change since t = 0 (energy,
//     orthogonality error, the problem's invariants), and Ω against time, with a cursor at the current time.
//
// Frames. A run of n rows is shown as F = min(n, max_frames) frames: the rows round(j (n − 1) / (F − 1)),
// j = 0 … F − 1 (the first and last rows among them, so the page ends at t_end). The curves keep every row: frame j
// carries the smallest and largest value of each curve over the rows since frame j − 1, drawn as a band. The page
// states the decimation.
//
// Input. The CSV of `lgi run` (standard columns, or "output.columns" with "R" or "quaternion"): a column t that
// never decreases, and R11 … R33 or q_w … q_z; omega1 … omega3 optional. Anything else is an InputError (CsvError
// naming the file and line) before any output is opened.
#pragma once

#include "json_reader.hpp"
#include "registry.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace lgi::app {

struct Scene;

// What the page knows of the body beyond the CSV (from the scene, when one is given).
struct ViewBody {
  bool known = false;  // J, k, z0 below come from a scene
  std::string problem;  // the scene's problem type ("" when unknown)
  BodyData data;
};

struct ViewInput {
  std::string csv;    // the run's CSV file
  std::string title;  // the page's title (empty: "lgi view: " and the CSV's file name)
  ViewBody body;
  int axis = 3;  // the body axis e_axis whose trace on the unit sphere is drawn (1, 2 or 3)
  std::size_t max_frames = 20000;  // at most this many frames in the page (≥ 2)
};

// What the page draws of the body of `scene` (its problem's BodyData): its problem type, J, k and z0, gravity only
// where its b is not 0, a gyrostat's rotor axes.
ViewBody view_body(const Scene& scene);

// What make_view_page read and wrote, for the command's summary line.
struct ViewReport {
  std::size_t rows = 0, frames = 0, bytes = 0;
  double t0 = 0, t_end = 0;
};

// The HTML page for `input` (two passes over the CSV, memory independent of its number of rows). Throws
// InputError (CsvError for the file's contents) on bad input; `version` is printed in the page.
std::string make_view_page(const ViewInput& input, const std::string& version, ViewReport* report = nullptr);

// `lgi view` and `lgi run --html`: the page of `input` written to `output` atomically (output_file.hpp). Empty
// `output`: the CSV's path with ".html" for ".csv" (or appended), where an existing file is replaced only when it
// is a page of lgi view (view_page_marker); a given `output` is replaced as `lgi run -o` replaces. `inputs` are
// files the page must not replace (the scene, the CSV is always one). Returns the exit status (command.hpp), after
// one line on stderr for an error, and a line saying what was written unless `quiet`.
int write_view(const ViewInput& input, std::string output, const std::vector<std::string>& inputs,
               const std::string& version, bool quiet);

// True when this lgi was built with the page's libraries (libjs-three); make_view_page throws otherwise.
bool viewer_available();

// The marker every page of make_view_page carries in its first 512 bytes: `lgi view` replaces an existing file at
// its default output only when the file carries it (a page lgi wrote).
inline constexpr const char* view_page_marker = "<meta name=\"generator\" content=\"lgi view\">";

}  // namespace lgi::app
