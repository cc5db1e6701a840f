// Malformed scene files through the real `lgi run`, each against its golden message.
//
// Every case is a valid scene with one thing broken (or a file whose bytes are the point: BOM, invalid
// UTF-8, NUL, a file over the loader's size limit, nesting 100 000 deep — those are generated here into a
// temporary directory). For each, the command must
//   - exit with status 1 (bad input),
//   - print exactly one line on stderr, "lgi: error: <file>: <JSON path>: <message>" (syntax errors:
//     "lgi: error: <file>:<line>:<column>: invalid JSON: …"), equal to the golden line below with the
//     temporary path substituted for {file},
//   - print nothing on stdout, and create neither the -o file nor a temporary file beside it.
// The valid scenes the cases start from are run too (they must exit 0), so each golden message is
// caused by the one edit of its case and nothing else.
#include "lgi_process.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

// ---- the valid scenes every case edits -----------------------------------------------------------

const std::string heavy_top = R"({
  "description": "a valid heavy top: each case below breaks one thing",
  "problem": {"type": "heavy_top", "inertia": [2, 2, 1], "b": 1, "k": [0, 0, 1], "z0": [0, 0, 1]},
  "initial": {"R": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], "omega": [0.1, 0.2, 5]},
  "integrator": {"method": "lgvi", "dt": 0.01, "tolerance": 1e-12, "max_iterations": 30},
  "t_end": 0.1,
  "output": {"every": 2}
}
)";

const std::string adaptive = R"({
  "problem": {"type": "free_body", "inertia": [[2, 0, 0], [0, 3, 0], [0, 0, 4]]},
  "initial": {"omega": [1, 0.1, 0.2]},
  "integrator": {"method": "rkmk_dp5", "dt": 0.01, "rtol": 1e-8, "atol": 1e-10, "projection": true},
  "t_end": 0.1,
  "output": {"times": [0.05, 0.1]}
}
)";

const std::string potential = R"({
  "problem": {"type": "potential", "inertia": [2, 2, 1],
              "fields": [{"b": 1, "k": [0, 0, 1], "z0": [0, 0, 1]}],
              "gradient": {"c": 3, "axis": [1, 0, 0], "tensor": [2, 2, 1]}},
  "initial": {"omega": [0.1, 0.2, 5]},
  "integrator": {"method": "rkmk4", "dt": 0.01},
  "t_end": 0.1
}
)";

const std::string satellite = R"({
  "problem": {"type": "satellite", "inertia": [1, 2, 2.5], "n": 1, "radial": [1, 0, 0], "normal": [0, 0, 1]},
  "initial": {"omega": [0, 0, 1]},
  "integrator": {"method": "rkmk4", "dt": 0.01},
  "t_end": 0.1
}
)";

const std::string rigid_body = R"({
  "problem": {"type": "rigid_body", "inertia": [1, 2, 3], "gravity": {"b": 1, "k": [0, 0, 1], "z0": [0, 0, 1]},
              "torques": [{"type": "damping", "coefficient": 0.1},
                          {"type": "constant", "frame": "lab", "torque": [0, 0, 0.5]},
                          {"type": "attitude_control", "target": {"quaternion": [1, 0, 0, 0]}, "k_R": 2, "k_Omega": 1}]},
  "initial": {"omega": [0.1, 0.2, 1]},
  "integrator": {"method": "rkmk4", "dt": 0.01},
  "t_end": 0.1
}
)";

const std::string gyrostat = R"({
  "problem": {"type": "gyrostat", "inertia": [3, 2, 1],
              "rotors": [{"axis": [1, 0, 0], "inertia": 0.1, "friction": 0.2, "rate": 5},
                         {"axis": [0, 1, 0], "inertia": 0.1}, {"axis": [0, 0, 1], "inertia": 0.1}],
              "wheel_control": {"target": {"quaternion": [1, 0, 0, 0]}, "k_R": 2, "k_Omega": 1}},
  "initial": {"omega": [0.1, 0.2, 1]},
  "integrator": {"method": "lgvi", "dt": 0.01},
  "t_end": 0.1
}
)";

const std::string lagrange = R"({
  "problem": {"type": "lagrange_top", "inertia": [2, 2, 1], "b": 1, "k": [0, 0.6, 0.8]},
  "initial": {"omega": [0.1, 0.2, 5]},
  "integrator": {"method": "lagrange_split", "dt": 0.01},
  "t_end": 0.1
}
)";

const std::string kovalevskaya = R"({
  "problem": {"type": "kovalevskaya_top", "inertia": [2, 2, 1], "b": 1, "z0": [1, 0, 0]},
  "initial": {"omega": [0.1, 0.2, 1]},
  "integrator": {"method": "rkmk4", "dt": 0.01},
  "t_end": 0.1
}
)";

const std::string euler_angles = R"({
  "problem": {"type": "lagrange_top_euler_angles", "I2": 2, "I3": 1, "b": 1, "k2": 0.6, "k3": 0.8},
  "initial": {"euler_angles": [0.5, 1.2, 0], "euler_rates": [-0.2, 0.3, 4]},
  "integrator": {"method": "rkmk4", "dt": 0.01},
  "t_end": 0.1
}
)";

// `base` with its one occurrence of `from` replaced by `to` (an ADD_FAILURE if `from` is not there once).
std::string edit(const std::string& base, const std::string& from, const std::string& to) {
  const auto at = base.find(from);
  if (at == std::string::npos || base.find(from, at + 1) != std::string::npos) {
    ADD_FAILURE() << "edit: \"" << from << "\" is not in the base scene exactly once";
    return base;
  }
  return base.substr(0, at) + to + base.substr(at + from.size());
}

struct Case {
  std::string name;
  std::string text;    // the file's bytes
  std::string golden;  // stderr, {file} for the file's path
};

std::vector<Case> cases() {
  const std::string& h = heavy_top;
  return {
      // ---- files that are not JSON, or not one JSON value ----
      {"empty_file", "", "lgi: error: {file}: the file is empty"},
      {"whitespace_only", " \n\t\r\n  \n", "lgi: error: {file}: the file is empty"},
      {"truncated_mid_object", h.substr(0, h.find("\"initial\"")),
       "lgi: error: {file}:4:3: invalid JSON: syntax error while parsing object key - unexpected end "
       "of input; expected string literal"},
      {"truncated_mid_string", h.substr(0, h.find("heavy_top") + 5),
       "lgi: error: {file}:3:29: invalid JSON in /problem/type: syntax error while parsing value - "
       "invalid string: missing closing quote; last read: '\"heavy'"},
      {"truncated_mid_number", h.substr(0, h.find("0.01") + 3),
       "lgi: error: {file}:5:45: invalid JSON in /integrator: syntax error while parsing object - "
       "unexpected end of input; expected '}'"},
      {"trailing_garbage", h + "x\n",
       "lgi: error: {file}:9:1: invalid JSON: syntax error while parsing value - invalid literal; "
       "last read: '2}<U+000A>}<U+000A>x'; expected end of input"},
      {"two_documents", h + "{}\n",
       "lgi: error: {file}:9:1: invalid JSON: syntax error while parsing value - unexpected '{'; expected "
       "end of input"},
      {"trailing_comma", edit(h, "\"every\": 2}", "\"every\": 2,}"),
       "lgi: error: {file}:7:25: invalid JSON in /output: syntax error while parsing object key - "
       "unexpected '}'; expected string literal (JSON has no trailing commas)"},
      {"line_comment", edit(h, "  \"t_end\": 0.1,", "  // one tenth of a second\n  \"t_end\": 0.1,"),
       "lgi: error: {file}:6:3: invalid JSON: syntax error while parsing object key - invalid literal; "
       "last read: '30},<U+000A>  /'; expected string literal (JSON has no comments)"},
      {"block_comment", edit(h, "\"t_end\": 0.1", "\"t_end\": /* s */ 0.1"),
       "lgi: error: {file}:6:12: invalid JSON in /t_end: syntax error while parsing value - invalid "
       "literal; last read: '\"t_end\": /' (JSON has no comments)"},
      {"hash_comment", "# a scene\n" + h,
       "lgi: error: {file}:1:1: invalid JSON: syntax error while parsing value - invalid literal; "
       "last read: '#' (JSON has no comments)"},
      {"utf16_bom", "\xFF\xFE{",
       "lgi: error: {file}: the file is UTF-16 or UTF-32 (it starts with a byte order mark): save "
       "it as UTF-8"},
      {"invalid_utf8_in_string", edit(h, "a valid heavy top", "a valid \xC3\x28 top"),
       "lgi: error: {file}:2:28: invalid JSON in /description: syntax error while parsing value - "
       "invalid string: ill-formed UTF-8 byte; last read: '\"a valid \\xC3('"},
      {"nul_byte", edit(h, "\"t_end\": 0.1", std::string("\"t_end\": 0.1\0", 13)),
       "lgi: error: {file}:6:15: invalid JSON: a NUL byte (JSON text has none)"},
      {"nul_then_garbage", h + std::string(1, '\0') + "garbage",
       "lgi: error: {file}:9:1: invalid JSON: a NUL byte (JSON text has none)"},
      {"control_character_in_string", edit(h, "a valid heavy top", "a valid\theavy top"),
       "lgi: error: {file}:2:26: invalid JSON in /description: syntax error while parsing value - "
       "invalid string: control character U+0009 (HT) must be escaped to \\u0009 or \\t; last read: "
       "'\"a valid<U+0009>'"},
      {"single_quotes", edit(h, "\"type\": \"heavy_top\"", "'type': 'heavy_top'"),
       "lgi: error: {file}:3:15: invalid JSON in /problem: syntax error while parsing object key - "
       "invalid literal; last read: '\"problem\": {''; expected string literal (JSON strings and keys "
       "take double quotes)"},
      {"unquoted_key", edit(h, "\"t_end\"", "t_end"),
       "lgi: error: {file}:6:4: invalid JSON: syntax error while parsing object key - invalid literal; "
       "last read: '30},<U+000A>  t_'; expected string literal (JSON keys are strings in double quotes)"},
      // ---- non-finite numbers ----
      {"overflow_1e400", edit(h, "\"b\": 1", "\"b\": 1e400"),
       "lgi: error: {file}: /problem/b: number 1e400 is out of the range of a double (at 3:67)"},
      {"overflow_negative", edit(h, "[0.1, 0.2, 5]", "[0.1, -1e999, 5]"),
       "lgi: error: {file}: /initial/omega/1: number -1e999 is out of the range of a double (at 4:75)"},
      {"underflow_1e-400", edit(h, "\"dt\": 0.01", "\"dt\": 1e-400"),
       "lgi: error: {file}: /integrator/dt: number 1e-400 is too small for a double (it would read "
       "as 0)"},
      {"NaN", edit(h, "\"dt\": 0.01", "\"dt\": NaN"),
       "lgi: error: {file}:5:42: invalid JSON in /integrator/dt: syntax error while parsing value "
       "- invalid literal; last read: '\"dt\": N' (NaN and Infinity are not JSON numbers, and a scene's "
       "numbers must be finite)"},
      {"nan_lowercase", edit(h, "[0.1, 0.2, 5]", "[0.1, nan, 5]"),
       "lgi: error: {file}:4:71: invalid JSON in /initial/omega/1: syntax error while parsing value "
       "- invalid literal; last read: '0.1, na' (NaN and Infinity are not JSON numbers, and a scene's "
       "numbers must be finite)"},
      {"Infinity", edit(h, "\"t_end\": 0.1", "\"t_end\": Infinity"),
       "lgi: error: {file}:6:12: invalid JSON in /t_end: syntax error while parsing value - invalid "
       "literal; last read: '\"t_end\": I' (NaN and Infinity are not JSON numbers, and a scene's numbers "
       "must be finite)"},
      {"minus_inf", edit(h, "\"b\": 1", "\"b\": -inf"),
       "lgi: error: {file}:3:64: invalid JSON in /problem/b: syntax error while parsing value - invalid "
       "number; expected digit after '-'; last read: '-i' (NaN and Infinity are not JSON numbers, "
       "and a scene's numbers must be finite)"},
      {"NaN_as_string", edit(h, "\"b\": 1", "\"b\": \"NaN\""),
       "lgi: error: {file}: /problem/b: expected a number, got a string (\"NaN\")"},
      {"hex_number", edit(h, "\"b\": 1", "\"b\": 0x1p3"),
       "lgi: error: {file}:3:64: invalid JSON in /problem: syntax error while parsing object - invalid "
       "literal; last read: '0x'; expected '}'"},
      // ---- structure ----
      {"duplicate_top_key", edit(h, "\"t_end\": 0.1,", "\"t_end\": 0.1, \"t_end\": 0.2,"),
       "lgi: error: {file}: /: duplicate key \"t_end\""},
      {"duplicate_nested_key", edit(h, "\"b\": 1,", "\"b\": 1, \"b\": 2,"),
       "lgi: error: {file}: /problem: duplicate key \"b\""},
      {"root_array", "[" + h + "]", "lgi: error: {file}: /: expected an object, got an array of 1"},
      {"root_number", "42\n", "lgi: error: {file}: /: expected an object, got the number 42"},
      // ---- unknown keys at each level ----
      {"unknown_top_key", edit(h, "\"t_end\"", "\"t_final\": 1, \"t_end\""),
       "lgi: error: {file}: /t_final: unknown key (allowed: description, problem, initial, integrator, "
       "t_end, output, limits)"},
      {"unknown_problem_key", edit(h, "\"b\": 1,", "\"b\": 1, \"mass\": 3,"),
       "lgi: error: {file}: /problem/mass: unknown key for heavy_top (allowed: type, inertia, b, k, "
       "z0)"},
      {"unknown_initial_key", edit(h, "\"omega\"", "\"Omega\": [0, 0, 1], \"omega\""),
       "lgi: error: {file}: /initial/Omega: unknown key; did you mean \"omega\"? (allowed: R, quaternion, axis_angle, "
       "euler_angles, omega, euler_rates)"},
      {"unknown_integrator_key", edit(h, "\"dt\": 0.01", "\"dt\": 0.01, \"order\": 4"),
       "lgi: error: {file}: /integrator/order: unknown key for method lgvi (allowed: method, dt, tolerance, "
       "max_iterations)"},
      {"unknown_output_key", edit(h, "{\"every\": 2}", "{\"every\": 2, \"format\": \"csv\"}"),
       "lgi: error: {file}: /output/format: unknown key (allowed: times, every, interval, columns)"},
      {"unknown_field_key", edit(potential, "\"b\": 1, \"k\"", "\"b\": 1, \"strength\": 2, \"k\""),
       "lgi: error: {file}: /problem/fields/0/strength: unknown key for a uniform field (allowed: "
       "b, k, z0)"},
      {"unknown_gradient_key", edit(potential, "\"c\": 3", "\"c\": 3, \"q\": 1"),
       "lgi: error: {file}: /problem/gradient/q: unknown key for a field gradient (allowed: c, axis, "
       "tensor)"},
      // messages stay one line of bounded length whatever the input's strings hold
      {"unknown_key_with_newline", edit(h, "\"t_end\"", "\"t\\nend\": 1, \"t_end\""),
       "lgi: error: {file}: /t\\nend: unknown key; did you mean \"t_end\"? (allowed: description, problem, initial, "
       "integrator, t_end, output, limits)"},
      {"unknown_key_very_long", edit(h, "\"t_end\"", std::string("\"").append(100000, 'k') + "\": 1, \"t_end\""),
       "lgi: error: {file}: /kkkkkkkkkkkkkkkkkkkkkkkkkkkkkkkkkkkkk...: unknown key (allowed: description, "
       "problem, initial, integrator, t_end, output, limits)"},
      {"method_with_escape_sequence", edit(h, "\"lgvi\"", "\"\\u001b[31mlgvi\""),
       "lgi: error: {file}: /integrator/method: unknown method \"\\u001b[31mlgvi\" (known: lgvi, rkmk4, "
       "lie_euler, rkmk_heun, rkmk3, rkmk4_38, rkmk_dp5, rkmk_dp8, rkmk_vern9, rkmk4_cayley, rkmk_dp5_cayley, "
       "rkmk_dp8_cayley, rkmk_vern9_cayley, rk4_quat, rk4_quat_renorm, rk4_mat, "
       "rk4_mat_renorm, dop853_quat, dop853_quat_renorm, dop853_mat, dop853_mat_renorm, split_axes, "
       "split_dmv, split_dmv4, split_dmv6, split_dmv8, split_dmv10, split_exact, cf4, cg3, lgvi_yoshida4, "
       "lgvi_suzuki4, lgvi_yoshida6, lgvi_kahan_li6, lgvi_yoshida8, lgvi_kahan_li8, lgvi_sofroniou_spaletta10, "
       "split_dmv_yoshida4, split_dmv_suzuki4, split_dmv_kahan_li6, split_dmv_kahan_li8, "
       "split_dmv_sofroniou_spaletta10, "
       "lagrange_split, lagrange_split_yoshida4, lagrange_split_kahan_li6, lagrange_split_kahan_li8, "
       "lagrange_split_sofroniou_spaletta10, exact)"},
      // ---- missing required keys ----
      {"missing_problem",
       edit(h, h.substr(h.find("  \"problem\""), h.find("  \"initial\"") - h.find("  \"problem\"")), ""),
       "lgi: error: {file}: /: missing key \"problem\""},
      {"missing_type", edit(h, "\"type\": \"heavy_top\", ", ""), "lgi: error: {file}: /problem: missing key \"type\""},
      {"missing_inertia", edit(h, "\"inertia\": [2, 2, 1], ", ""),
       "lgi: error: {file}: /problem: missing key \"inertia\""},
      {"missing_initial",
       edit(h, h.substr(h.find("  \"initial\""), h.find("  \"integrator\"") - h.find("  \"initial\"")), ""),
       "lgi: error: {file}: /: missing key \"initial\""},
      {"missing_omega", edit(h, ", \"omega\": [0.1, 0.2, 5]", ""),
       "lgi: error: {file}: /initial: missing the angular velocity: omega (body frame, rad per time unit), or "
       "euler_rates with euler_angles"},
      {"missing_method", edit(h, "\"method\": \"lgvi\", ", ""),
       "lgi: error: {file}: /integrator: missing key \"method\""},
      {"missing_dt", edit(h, "\"dt\": 0.01, ", ""), "lgi: error: {file}: /integrator: missing key \"dt\""},
      {"missing_t_end", edit(h, "  \"t_end\": 0.1,\n", ""), "lgi: error: {file}: /: missing key \"t_end\""},
      {"missing_euler_rates", edit(euler_angles, ", \"euler_rates\": [-0.2, 0.3, 4]", ""),
       "lgi: error: {file}: /initial: missing the angular velocity: omega (body frame, rad per time unit), or "
       "euler_rates with euler_angles"},
      // ---- wrong types ----
      {"problem_is_string",
       edit(h,
            h.substr(h.find("{\"type\": \"heavy_top\""),
                     h.find("},\n  \"initial\"") + 1 - h.find("{\"type\": \"heavy_top\"")),
            "\"heavy_top\""),
       "lgi: error: {file}: /problem: expected an object, got a string (\"heavy_top\")"},
      {"type_is_number", edit(h, "\"type\": \"heavy_top\"", "\"type\": 3"),
       "lgi: error: {file}: /problem/type: expected a string, got the number 3"},
      {"dt_is_string", edit(h, "\"dt\": 0.01", "\"dt\": \"0.01\""),
       "lgi: error: {file}: /integrator/dt: expected a number, got a string (\"0.01\")"},
      {"t_end_is_bool", edit(h, "\"t_end\": 0.1", "\"t_end\": true"),
       "lgi: error: {file}: /t_end: expected a number, got true"},
      {"omega_is_object", edit(h, "[0.1, 0.2, 5]", "{\"x\": 0.1}"),
       "lgi: error: {file}: /initial/omega: expected an array of 3 numbers, got an object"},
      {"omega_entry_null", edit(h, "[0.1, 0.2, 5]", "[0.1, null, 5]"),
       "lgi: error: {file}: /initial/omega/1: expected a number, got null"},
      {"omega_two_entries", edit(h, "[0.1, 0.2, 5]", "[0.1, 0.2]"),
       "lgi: error: {file}: /initial/omega: expected an array of 3 numbers, got an array of 2"},
      {"R_entry_string", edit(h, "[0, 1, 0]", "[0, \"1\", 0]"),
       "lgi: error: {file}: /initial/R/1/1: expected a number, got a string (\"1\")"},
      {"inertia_is_number", edit(h, "\"inertia\": [2, 2, 1]", "\"inertia\": 2"),
       "lgi: error: {file}: /problem/inertia: expected an array, got the number 2"},
      {"times_is_number", edit(adaptive, "[0.05, 0.1]", "0.05"),
       "lgi: error: {file}: /output/times: expected an array, got the number 0.05"},
      {"projection_is_string", edit(adaptive, "\"projection\": true", "\"projection\": \"yes\""),
       "lgi: error: {file}: /integrator/projection: expected true or false, got a string (\"yes\")"},
      {"description_is_number", edit(h, "\"a valid heavy top: each case below breaks one thing\"", "7"),
       "lgi: error: {file}: /description: expected a string, got the number 7"},
      // ---- out-of-range values ----
      {"b_negative", edit(h, "\"b\": 1", "\"b\": -1"), "lgi: error: {file}: /problem/b: must be >= 0, got -1"},
      {"max_iterations_zero", edit(h, "\"max_iterations\": 30", "\"max_iterations\": 0"),
       "lgi: error: {file}: /integrator/max_iterations: expected an integer from 1 to 1000, got 0"},
      {"max_iterations_fraction", edit(h, "\"max_iterations\": 30", "\"max_iterations\": 2.5"),
       "lgi: error: {file}: /integrator/max_iterations: expected an integer from 1 to 1000, got 2.5"},
      {"tolerance_too_loose", edit(h, "\"tolerance\": 1e-12", "\"tolerance\": 0.5"),
       "lgi: error: {file}: /integrator/tolerance: must be < 0.01, got 0.5"},
      {"rtol_below_roundoff", edit(adaptive, "\"rtol\": 1e-8", "\"rtol\": 1e-17"),
       "lgi: error: {file}: /integrator/rtol: must be in [2.220446049250313e-15 (10 machine epsilons), "
       "1), got 1e-17"},
      {"every_zero", edit(h, "{\"every\": 2}", "{\"every\": 0}"),
       "lgi: error: {file}: /output/every: expected an integer from 1 to 9007199254740992, got 0"},
      {"every_huge", edit(h, "{\"every\": 2}", "{\"every\": 1e19}"),
       "lgi: error: {file}: /output/every: expected an integer from 1 to 9007199254740992, got 1e+19"},
      {"min_sin_theta_one", edit(euler_angles, "\"k3\": 0.8", "\"k3\": 0.8, \"min_sin_theta\": 1"),
       "lgi: error: {file}: /problem/min_sin_theta: must be in [0, 1), got 1"},
      {"too_many_fields",
       edit(potential, "[{\"b\": 1, \"k\": [0, 0, 1], \"z0\": [0, 0, 1]}]",
            [] {
              std::string f = "[";
              for (int i = 0; i < 9; ++i)
                f.append(i ? ", " : "").append("{\"b\": 1, \"k\": [0, 0, 1], \"z0\": [0, 0, 1]}");
              return f.append("]");
            }()),
       "lgi: error: {file}: /problem/fields: at most 4 uniform fields, got 9"},
      // ---- physically impossible data, units ----
      {"inertia_triangle_inequality", edit(h, "\"inertia\": [2, 2, 1]", "\"inertia\": [1, 1, 2.5]"),
       "lgi: error: {file}: /problem/inertia: principal moments 1, 1, 2.5 violate the triangle inequality "
       "I3 <= I1 + I2 (no rigid body has them)"},
      {"inertia_not_positive_definite",
       edit(h, "\"inertia\": [2, 2, 1]", "\"inertia\": [[1, 2, 0], [2, 1, 0], [0, 0, 1]]"),
       "lgi: error: {file}: /problem/inertia: inertia tensor is not positive definite (principal moments "
       "-1, 1, 3)"},
      {"inertia_not_symmetric", edit(h, "\"inertia\": [2, 2, 1]", "\"inertia\": [[2, 0.5, 0], [0, 2, 0], [0, 0, 1]]"),
       "lgi: error: {file}: /problem/inertia/0/1: inertia tensor is not symmetric: I12 = 0.5 but I21 "
       "= 0"},
      {"inertia_zero", edit(h, "\"inertia\": [2, 2, 1]", "\"inertia\": [0, 0, 0]"),
       "lgi: error: {file}: /problem/inertia: inertia tensor is zero"},
      {"inertia_units_too_small", edit(h, "\"inertia\": [2, 2, 1]", "\"inertia\": [2e-200, 2e-200, 1e-200]"),
       "lgi: error: {file}: /problem/inertia: inertia tensor's scale (principal moments 1e-200 .. "
       "2e-200) is outside [1e-150, 1e150]: its inverse is not representable; change the units"},
      {"R_not_orthogonal", edit(h, "[0, 1, 0]", "[0, 1.01, 0]"),
       "lgi: error: {file}: /initial/R: must be a rotation matrix (to 0.01): |R^T R - I| = 0.020100000000000007, "
       "det R = 1.01"},
      {"R_reflection", edit(h, "[0, 0, 1]], \"omega\"", "[0, 0, -1]], \"omega\""),
       "lgi: error: {file}: /initial/R: must be a rotation matrix (to 0.01): |R^T R - I| = 0, det "
       "R = -1"},
      {"R_all_zero", edit(h, "[[1, 0, 0], [0, 1, 0], [0, 0, 1]]", "[[0, 0, 0], [0, 0, 0], [0, 0, 0]]"),
       "lgi: error: {file}: /initial/R: must be a rotation matrix (to 0.01): |R^T R - I| = 1.7320508075688772, "
       "det R = 0"},
      {"k_zero_vector", edit(h, "\"k\": [0, 0, 1]", "\"k\": [0, 0, 0]"),
       "lgi: error: {file}: /problem/k: must be a unit vector (to 0.01), its length is 0"},
      {"z0_not_unit", edit(h, "\"z0\": [0, 0, 1]", "\"z0\": [0, 0, 9.81]"),
       "lgi: error: {file}: /problem/z0: must be a unit vector (to 0.01), its length is 9.81"},
      {"radial_not_perpendicular", edit(satellite, "\"radial\": [1, 0, 0]", "\"radial\": [0, 0.6, 0.8]"),
       "lgi: error: {file}: /problem/radial: the radial direction must be perpendicular to the orbit "
       "normal (to 1e-9), radial . normal = 0.8"},
      {"damping_negative", edit(rigid_body, "\"coefficient\": 0.1", "\"coefficient\": -0.1"),
       "lgi: error: {file}: /problem/torques/0/coefficient: must be >= 0, got -0.1"},
      {"damping_not_symmetric",
       edit(rigid_body, "\"coefficient\": 0.1", "\"matrix\": [[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]"),
       "lgi: error: {file}: /problem/torques/0/matrix: the damping matrix must be symmetric (largest |C_ij - C_ji| "
       "= 0.5)"},
      {"damping_indefinite",
       edit(rigid_body, "\"coefficient\": 0.1", "\"matrix\": [[1, 0, 0], [0, -1, 0], [0, 0, 1]]"),
       "lgi: error: {file}: /problem/torques/0/matrix: the damping matrix must be positive semi-definite (it would "
       "feed energy in): smallest eigenvalue -1"},
      {"damping_twice", edit(rigid_body, "\"coefficient\": 0.1", "\"coefficient\": 0.1, \"matrix\": [1, 1, 1]"),
       "lgi: error: {file}: /problem/torques/0: give the damping once, as a coefficient c (C = c I) or a matrix C"},
      {"torque_frame_unknown", edit(rigid_body, "\"lab\"", "\"inertial\""),
       "lgi: error: {file}: /problem/torques/1/frame: unknown frame \"inertial\" (known: body, lab)"},
      {"torque_term_unknown", edit(rigid_body, "\"type\": \"damping\"", "\"type\": \"dampng\""),
       "lgi: error: {file}: /problem/torques/0/type: unknown torque term \"dampng\"; did you mean \"damping\"? "
       "(known: constant, table, damping, attitude_control, gravity_gradient)"},
      {"gravity_gradient_radial_in_plane", edit(rigid_body, "\"type\": \"damping\"",
                                                "\"type\": \"gravity_gradient\", \"n\": 1, \"radial\": [0, 0, 1]}, {\"type\": \"damping\""),
       "lgi: error: {file}: /problem/torques/0/radial: the radial direction must be perpendicular to the orbit normal "
       "(to 1e-9), radial . normal = 1"},
      {"gravity_gradient_rate_missing", edit(rigid_body, "\"type\": \"damping\"",
                                             "\"type\": \"gravity_gradient\"}, {\"type\": \"damping\""),
       "lgi: error: {file}: /problem/torques/0: missing key \"n\""},
      {"control_target_not_unit", edit(rigid_body, "[1, 0, 0, 0]", "[1, 0.5, 0, 0]"),
       "lgi: error: {file}: /problem/torques/2/target/quaternion: must be a unit quaternion (to 0.01), its length is "
       "1.118033988749895"},
      {"control_gain_missing", edit(rigid_body, "\"k_R\": 2, ", ""),
       "lgi: error: {file}: /problem/torques/2: missing key \"k_R\""},
      {"rotor_axis_not_unit", edit(gyrostat, "\"axis\": [0, 1, 0]", "\"axis\": [0, 1, 1]"),
       "lgi: error: {file}: /problem/rotors/1/axis: must be a unit vector (to 0.01), its length is 1.4142135623730951"},
      {"rotor_friction_negative", edit(gyrostat, "\"friction\": 0.2", "\"friction\": -0.2"),
       "lgi: error: {file}: /problem/rotors/0/friction: must be >= 0, got -0.2"},
      {"rotor_inertia_too_large", edit(gyrostat, "\"inertia\": 0.1, \"friction\"", "\"inertia\": 3, \"friction\""),
       "lgi: error: {file}: /problem/rotors: the rotors' axial inertias leave the body no inertia about some axis (J - "
       "sum I_s a a^T is not positive definite: its leading 1x1 minor is 0; the problem's inertia is the whole body's "
       "with the rotors locked)"},
      // "method": "auto": a tolerance, nothing else, and no output counted in steps.
      {"auto_without_tolerance", edit(h, "{\"method\": \"lgvi\", \"dt\": 0.01, \"tolerance\": 1e-12, \"max_iterations\": 30}", "{\"method\": \"auto\"}"),
       "lgi: error: {file}: /integrator: missing key \"tolerance\""},
      {"auto_with_dt", edit(h, "{\"method\": \"lgvi\", \"dt\": 0.01, \"tolerance\": 1e-12, \"max_iterations\": 30}", "{\"method\": \"auto\", \"tolerance\": 1e-8, \"dt\": 0.01}"),
       "lgi: error: {file}: /integrator/dt: unknown key for method auto (it chooses dt and the method's settings) "
       "(allowed: method, tolerance)"},
      {"auto_tolerance_too_small", edit(h, "{\"method\": \"lgvi\", \"dt\": 0.01, \"tolerance\": 1e-12, \"max_iterations\": 30}", "{\"method\": \"auto\", \"tolerance\": 1e-15}"),
       "lgi: error: {file}: /integrator/tolerance: must be in [1e-13, 0.1], got 1e-15"},
      {"auto_output_every", edit(h, "{\"method\": \"lgvi\", \"dt\": 0.01, \"tolerance\": 1e-12, \"max_iterations\": 30}", "{\"method\": \"auto\", \"tolerance\": 1e-8}"),
       "lgi: error: {file}: /output/every: counts steps, and method auto chooses them: give \"interval\" or \"times\""},
      {"rotors_none",
       R"({"problem": {"type": "gyrostat", "inertia": [3, 2, 1], "rotors": []},
           "initial": {"omega": [0, 0, 1]}, "integrator": {"method": "lgvi", "dt": 0.01}, "t_end": 0.1})",
       "lgi: error: {file}: /problem/rotors: a gyrostat carries 1 to 6 rotors, got 0"},
      {"wheel_gain_wrong_shape", edit(gyrostat, "\"k_R\": 2", "\"k_R\": [2, 2, 2]"),
       "lgi: error: {file}: /problem/wheel_control/k_R: expected a number, got an array of 3"},
      {"wheel_axes_flat", edit(gyrostat, "\"axis\": [0, 0, 1]", "\"axis\": [0, 1, 0]"),
       "lgi: error: {file}: /problem/wheel_control: the rotors' axes do not span three dimensions (det(A A^T) = 0): the "
       "wheels cannot apply every torque the law asks for"},
      {"auto_on_gyrostat", edit(gyrostat, "{\"method\": \"lgvi\", \"dt\": 0.01}", "{\"method\": \"auto\", \"tolerance\": 1e-8}"),
       "lgi: error: {file}: /integrator/method: method auto chooses for a state (R, Omega) on SO(3) x R^3 alone; problem "
       "gyrostat's state is not: give its method (lgvi, rkmk4, lie_euler, rkmk_heun, rkmk3, rkmk4_38, rkmk_dp5, "
       "rkmk_dp8, rkmk_vern9, lgvi_yoshida4, lgvi_suzuki4, lgvi_yoshida6, lgvi_kahan_li6, lgvi_yoshida8, "
       "lgvi_kahan_li8, lgvi_sofroniou_spaletta10)"},
      {"method_not_for_gyrostat", edit(gyrostat, "\"lgvi\"", "\"cf4\""),
       "lgi: error: {file}: /integrator/method: method \"cf4\" does not apply to problem gyrostat (its rotors are "
       "stepped with the body by the gyrostat's methods: lgvi and its compositions, and the RKMK tableaus in the "
       "exponential chart, with fixed steps); it applies to free_body, heavy_top, lagrange_top, kovalevskaya_top, "
       "satellite, potential, rigid_body (methods that apply to gyrostat: lgvi, rkmk4, lie_euler, rkmk_heun, rkmk3, "
       "rkmk4_38, rkmk_dp5, rkmk_dp8, rkmk_vern9, lgvi_yoshida4, lgvi_suzuki4, lgvi_yoshida6, lgvi_kahan_li6, "
       "lgvi_yoshida8, lgvi_kahan_li8, lgvi_sofroniou_spaletta10)"},
      {"torques_not_an_array",
       R"({"problem": {"type": "rigid_body", "inertia": [1, 2, 3], "torques": {"type": "damping"}},
           "initial": {"omega": [0, 0, 1]}, "integrator": {"method": "rkmk4", "dt": 0.01}, "t_end": 0.1})",
       "lgi: error: {file}: /problem/torques: expected an array of torque terms, got an object"},
      {"projection_on_rigid_body", edit(rigid_body, "\"dt\": 0.01", "\"dt\": 0.01, \"projection\": true"),
       "lgi: error: {file}: /integrator/projection: problem rigid_body's torque reads the angular velocity (damping, "
       "control): its energy is not conserved, nothing to project onto"},
      {"projection_on_forced_lgvi",
       edit(edit(rigid_body, "\"rkmk4\"", "\"lgvi\""), "\"dt\": 0.01", "\"dt\": 0.01, \"projection\": true"),
       "lgi: error: {file}: /integrator/projection: problem rigid_body's torque reads the angular velocity (damping, "
       "control): its energy is not conserved, nothing to project onto"},
      {"projection_on_satellite_lgvi",
       edit(edit(satellite, "\"rkmk4\"", "\"lgvi\""), "\"dt\": 0.01", "\"dt\": 0.01, \"projection\": true"),
       "lgi: error: {file}: /integrator/projection: problem satellite has a time-dependent torque: no energy to "
       "project onto"},
      {"splitting_on_rigid_body", edit(rigid_body, "\"rkmk4\"", "\"split_dmv\""),
       "lgi: error: {file}: /integrator/method: method \"split_dmv\" does not apply to problem rigid_body (its "
       "torque reads the angular velocity, and the splittings and their compositions need a torque of the attitude "
       "alone); it applies to free_body, heavy_top, lagrange_top, kovalevskaya_top, satellite, potential (methods "
       "that apply to rigid_body: lgvi, rkmk4, lie_euler, rkmk_heun, rkmk3, rkmk4_38, rkmk_dp5, rkmk_dp8, rkmk_vern9, "
       "rkmk4_cayley, rkmk_dp5_cayley, rkmk_dp8_cayley, rkmk_vern9_cayley, rk4_quat, rk4_quat_renorm, rk4_mat, "
       "rk4_mat_renorm, dop853_quat, dop853_quat_renorm, dop853_mat, dop853_mat_renorm, cf4, cg3, lgvi_yoshida4, "
       "lgvi_suzuki4, lgvi_yoshida6, lgvi_kahan_li6, lgvi_yoshida8, lgvi_kahan_li8, lgvi_sofroniou_spaletta10)"},
      {"lagrange_not_symmetric", edit(lagrange, "[2, 2, 1]", "[2, 3, 1]"),
       "lgi: error: {file}: /problem/inertia: a Lagrange top has I1 = I2 (symmetry axis e3), got I1 "
       "= 2, I2 = 3"},
      {"kovalevskaya_ratio", edit(kovalevskaya, "[2, 2, 1]", "[2, 2, 1.5]"),
       "lgi: error: {file}: /problem/inertia: a Kovalevskaya top has I1 = I2 = 2 I3, got 2, 2, 1.5"},
      {"kovalevskaya_z0_off_plane", edit(kovalevskaya, "\"z0\": [1, 0, 0]", "\"z0\": [0.6, 0, 0.8]"),
       "lgi: error: {file}: /problem/z0: the centre of mass of a Kovalevskaya top lies in the equatorial "
       "plane: z0[2] must be 0 (to 1e-9), got 0.8"},
      {"euler_top_triangle", edit(euler_angles, "\"I3\": 1", "\"I3\": 5"),
       "lgi: error: {file}: /problem/I3: must not exceed 2*I2 = 4 (triangle inequality of the moments)"},
      {"gradient_tensor_not_symmetric",
       edit(potential, "\"tensor\": [2, 2, 1]", "\"tensor\": [[1, 2, 0], [0, 1, 0], [0, 0, 1]]"),
       "lgi: error: {file}: /problem/gradient/tensor: the tensor must be symmetric: Q12 = 2 but Q21 "
       "= 0"},
      {"omega_and_euler_rates", edit(euler_angles, "\"euler_angles\"", "\"omega\": [0, 0, 1], \"euler_angles\""),
       "lgi: error: {file}: /initial: give the angular velocity once, as omega or euler_rates (not both)"},
      {"R_and_euler_angles", edit(euler_angles, "\"euler_angles\"", "\"R\": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], \"euler_angles\""),
       "lgi: error: {file}: /initial: give the attitude once, as R, quaternion, axis_angle or euler_angles (got R, "
       "euler_angles)"},
      {"euler_rates_without_angles", edit(h, "\"omega\": [0.1, 0.2, 5]", "\"euler_rates\": [0.1, 0.2, 5]"),
       "lgi: error: {file}: /initial/euler_rates: euler_rates need euler_angles (their convention and unit)"},
      {"quaternion_not_unit", edit(h, "\"R\": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]", "\"quaternion\": [1, 0.2, 0, 0]"),
       "lgi: error: {file}: /initial/quaternion: must be a unit quaternion (to 0.01), its length is "
       "1.019803902718557"},
      {"quaternion_of_three", edit(h, "\"R\": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]", "\"quaternion\": [1, 0, 0]"),
       "lgi: error: {file}: /initial/quaternion: expected a quaternion [w, x, y, z] (4 numbers, scalar first), got "
       "an array of 3"},
      {"axis_angle_zero_axis",
       edit(h, "\"R\": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]", "\"axis_angle\": {\"axis\": [0, 0, 0], \"angle\": 1}"),
       "lgi: error: {file}: /initial/axis_angle/axis: must not be zero"},
      {"euler_convention_unknown",
       edit(h, "\"R\": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]",
            "\"euler_angles\": {\"convention\": \"xyz\", \"angles\": [0, 0, 0]}"),
       "lgi: error: {file}: /initial/euler_angles/convention: unknown convention \"xyz\" (known: zxz, the seed "
       "paper's (phi, theta, psi); zyx, (yaw, pitch, roll))"},
      // ---- method and problem ----
      {"unknown_method", edit(h, "\"lgvi\"", "\"rk45\""),
       "lgi: error: {file}: /integrator/method: unknown method \"rk45\" (known: lgvi, rkmk4, lie_euler, "
       "rkmk_heun, rkmk3, rkmk4_38, rkmk_dp5, rkmk_dp8, rkmk_vern9, rkmk4_cayley, rkmk_dp5_cayley, rkmk_dp8_cayley, "
       "rkmk_vern9_cayley, rk4_quat, rk4_quat_renorm, rk4_mat, rk4_mat_renorm, "
       "dop853_quat, dop853_quat_renorm, dop853_mat, dop853_mat_renorm, split_axes, split_dmv, split_dmv4, "
       "split_dmv6, split_dmv8, split_dmv10, split_exact, cf4, cg3, lgvi_yoshida4, lgvi_suzuki4, lgvi_yoshida6, "
       "lgvi_kahan_li6, lgvi_yoshida8, lgvi_kahan_li8, lgvi_sofroniou_spaletta10, split_dmv_yoshida4, "
       "split_dmv_suzuki4, split_dmv_kahan_li6, split_dmv_kahan_li8, split_dmv_sofroniou_spaletta10, "
       "lagrange_split, lagrange_split_yoshida4, lagrange_split_kahan_li6, lagrange_split_kahan_li8, "
       "lagrange_split_sofroniou_spaletta10, exact)"},
      {"method_in_capitals", edit(h, "\"lgvi\"", "\"LGVI\""),
       "lgi: error: {file}: /integrator/method: unknown method \"LGVI\"; did you mean \"lgvi\"? (`lgi list` shows "
       "all 48)"},
      {"problem_misspelt", edit(h, "\"heavy_top\"", "\"heavytop\""),
       "lgi: error: {file}: /problem/type: unknown problem type \"heavytop\"; did you mean \"heavy_top\"? (known: "
       "free_body, heavy_top, lagrange_top, kovalevskaya_top, satellite, potential, rigid_body, gyrostat, "
       "lagrange_top_euler_angles)"},
      {"unknown_problem", edit(h, "\"heavy_top\"", "\"spinning_plate\""),
       "lgi: error: {file}: /problem/type: unknown problem type \"spinning_plate\" (known: free_body, "
       "heavy_top, lagrange_top, kovalevskaya_top, satellite, potential, rigid_body, gyrostat, "
       "lagrange_top_euler_angles)"},
      {"method_not_for_problem", edit(h, "\"lgvi\"", "\"lagrange_split\""),
       "lgi: error: {file}: /integrator/method: method \"lagrange_split\" does not apply to problem "
       "heavy_top; it applies to lagrange_top (methods that apply to heavy_top: lgvi, rkmk4, lie_euler, rkmk_heun, rkmk3, rkmk4_38, rkmk_dp5, "
       "rkmk_dp8, rkmk_vern9, rkmk4_cayley, rkmk_dp5_cayley, rkmk_dp8_cayley, rkmk_vern9_cayley, rk4_quat, "
       "rk4_quat_renorm, rk4_mat, "
       "rk4_mat_renorm, dop853_quat, dop853_quat_renorm, dop853_mat, dop853_mat_renorm, split_axes, split_dmv, split_dmv4, split_dmv6, split_dmv8, "
       "split_dmv10, split_exact, cf4, cg3, lgvi_yoshida4, lgvi_suzuki4, lgvi_yoshida6, lgvi_kahan_li6, "
       "lgvi_yoshida8, lgvi_kahan_li8, lgvi_sofroniou_spaletta10, split_dmv_yoshida4, split_dmv_suzuki4, "
       "split_dmv_kahan_li6, split_dmv_kahan_li8, split_dmv_sofroniou_spaletta10)"},
      {"splitting_on_euler_angles", edit(euler_angles, "\"rkmk4\"", "\"lgvi\""),
       "lgi: error: {file}: /integrator/method: method \"lgvi\" does not apply to problem lagrange_top_euler_angles; "
       "it applies to free_body, heavy_top, lagrange_top, kovalevskaya_top, satellite, potential, rigid_body, gyrostat "
       "(methods that apply to lagrange_top_euler_angles: rkmk4, lie_euler, rkmk_heun, rkmk3, rkmk4_38, rkmk_dp5, rkmk_dp8, rkmk_vern9)"},
      {"tolerance_on_explicit_method", edit(h, "\"lgvi\"", "\"rkmk4\""),
       "lgi: error: {file}: /integrator/max_iterations: unknown key for method rkmk4 (allowed: method, "
       "dt, projection)"},
      {"rtol_on_fixed_step_method", edit(adaptive, "\"rkmk_dp5\"", "\"rkmk4\""),
       "lgi: error: {file}: /integrator/rtol: method rkmk4 has no embedded error estimate: adaptive "
       "steps (rtol, atol) need one of rkmk_dp5, rkmk_dp8, rkmk_vern9, rkmk_dp5_cayley, rkmk_dp8_cayley, "
       "rkmk_vern9_cayley, dop853_quat, "
       "dop853_quat_renorm, dop853_mat, dop853_mat_renorm"},
      {"projection_on_symplectic", edit(h, "\"max_iterations\": 30", "\"max_iterations\": 30, \"projection\": true"),
       "lgi: error: {file}: /integrator/projection: method lgvi is symplectic (its energy error stays "
       "bounded): projection is for non-symplectic methods"},
      {"rtol_without_atol", edit(adaptive, ", \"atol\": 1e-10", ""),
       "lgi: error: {file}: /integrator: an adaptive run needs both \"rtol\" and \"atol\" (fixed steps: "
       "neither)"},
      // ---- time grid and output spec ----
      {"dt_zero", edit(h, "\"dt\": 0.01", "\"dt\": 0"), "lgi: error: {file}: /integrator/dt: must be > 0, got 0"},
      {"dt_negative", edit(h, "\"dt\": 0.01", "\"dt\": -0.01"),
       "lgi: error: {file}: /integrator/dt: must be > 0, got -0.01"},
      {"dt_larger_than_t_end", edit(h, "\"dt\": 0.01", "\"dt\": 0.5"),
       "lgi: error: {file}: /integrator/dt: must be <= t_end = 0.1, got 0.5"},
      {"t_end_negative", edit(h, "\"t_end\": 0.1", "\"t_end\": -1"),
       "lgi: error: {file}: /t_end: must be >= 0, got -1"},
      {"too_many_steps", edit(h, "\"t_end\": 0.1", "\"t_end\": 1e12"),
       "lgi: error: {file}: /integrator/dt: t_end/dt = 1e+14 steps, more than the 1e+13 a scene may "
       "take"},
      {"output_not_object", edit(h, "{\"every\": 2}", "[2]"),
       "lgi: error: {file}: /output: expected an object, got an array of 1"},
      {"output_times_and_every", edit(h, "{\"every\": 2}", "{\"every\": 2, \"times\": [0.05]}"),
       "lgi: error: {file}: /output: give one of \"times\", \"every\" and \"interval\""},
      {"output_time_after_end", edit(adaptive, "[0.05, 0.1]", "[0.05, 0.2]"),
       "lgi: error: {file}: /output/times/1: output time 0.2 is outside [0, t_end = 0.1]"},
      {"output_times_decreasing", edit(adaptive, "[0.05, 0.1]", "[0.1, 0.05]"),
       "lgi: error: {file}: /output/times/1: output times must increase: 0.05 follows 0.1"},
      {"output_time_nonfinite", edit(adaptive, "[0.05, 0.1]", "[0.05, 1e999]"),
       "lgi: error: {file}: /output/times/1: number 1e999 is out of the range of a double (at 6:34)"},
  };
}

// ---- running the command ------------------------------------------------------------------------

using Result = lgi::test::CommandResult;

class MalformedScenes : public lgi::test::CommandTest {
 protected:
  MalformedScenes() : CommandTest("malformed") {}

  // `lgi run FILE -o OUT`, stdout and stderr captured.
  Result run(const fs::path& scene, const fs::path& output) { return lgi("run " + scene.string() + " -o " + output.string()); }

  // The contract for bad input: status 1, the golden line on stderr and nothing else, no output.
  void expect_rejected(const std::string& name, const std::string& bytes, const std::string& golden) {
    SCOPED_TRACE(name);
    const fs::path scene = write(name + ".json", bytes);
    const fs::path output = dir_ / (name + ".csv");
    const Result r = run(scene, output);
    std::string expected = golden;
    for (auto at = expected.find("{file}"); at != std::string::npos; at = expected.find("{file}"))
      expected.replace(at, 6, scene.string());
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(r.err, expected + "\n");
    EXPECT_EQ(r.out, "");
    EXPECT_FALSE(fs::exists(output));
    for (const auto& entry : fs::directory_iterator(dir_))  // no temporary output left either
      EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
    fs::remove(scene);
  }

};

TEST_F(MalformedScenes, TheValidScenesTheCasesEditRun) {
  for (const std::string* scene :
       {&heavy_top, &adaptive, &potential, &satellite, &lagrange, &kovalevskaya, &euler_angles, &gyrostat}) {
    const fs::path file = write("valid.json", *scene);
    const Result r = run(file, dir_ / "valid.csv");
    EXPECT_EQ(r.status, 0) << *scene << r.err;
    EXPECT_TRUE(fs::exists(dir_ / "valid.csv")) << *scene;
    fs::remove(dir_ / "valid.csv");
  }
}

// A UTF-8 byte order mark is skipped (RFC 8259 §8.1 lets a parser ignore it): the scene runs.
TEST_F(MalformedScenes, Utf8ByteOrderMarkIsSkipped) {
  const fs::path file = write("bom.json", "\xEF\xBB\xBF" + heavy_top);
  const Result r = run(file, dir_ / "bom.csv");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / "bom.csv"));
}

// Generated in the test: one byte over the loader's 64 MiB limit (a valid scene padded with spaces, so
// that only the size is wrong), and nesting 100 000 deep (the loader stops at 64 levels, without
// recursion: no stack overflow).
TEST_F(MalformedScenes, HugeFileAndDeepNesting) {
  constexpr std::size_t limit = std::size_t{64} << 20;
  std::string huge = heavy_top;
  huge.resize(limit + 1, ' ');
  expect_rejected("huge_file", huge,
                  "lgi: error: {file}: the file is larger than the limit of 67108864 bytes for an input file");
  expect_rejected("exactly_at_the_limit_but_invalid", std::string(limit - 1, ' ') + "x",
                  "lgi: error: {file}:1:67108864: invalid JSON: syntax error while parsing value - invalid literal; "
                  "last read: '...                                    x'");

  std::string pointer;
  for (int i = 0; i < 64; ++i) pointer += "/0";  // the 64 arrays open when the 65th starts
  expect_rejected("deep_arrays", std::string(100000, '[') + std::string(100000, ']'),
                  "lgi: error: {file}: " + pointer + ": nesting deeper than 64 levels");
  std::string objects;
  for (int i = 0; i < 100000; ++i) objects += "{\"a\": ";
  std::string keys = "/output";
  for (int i = 0; i < 63; ++i) keys += "/a";  // the root and 63 objects open
  expect_rejected("deep_objects", edit(heavy_top, "{\"every\": 2}", objects + "1" + std::string(100000, '}')),
                  "lgi: error: {file}: " + keys + ": nesting deeper than 64 levels");
}

// A torque table (the rigid_body "table" term): each defect of the CSV file gives one line naming the file and the
// line (or the header), of the scene one line naming its JSON path; nothing is written. The valid table runs.
TEST_F(MalformedScenes, TorqueTablesGiveTheirFileAndLine) {
  const std::string good = "t, M1, M2, M3\n0, 0.1, 0, 0\n0.05, 0.2, 0.1, 0\n0.1, 0.1, 0, 0.3\n";
  const auto scene_with = [](const std::string& csv, const std::string& extra = "") {
    return R"({"problem": {"type": "rigid_body", "inertia": [1, 2, 3],
                "torques": [{"type": "table", "file": ")" + csv + R"(", "frame": "body")" + extra + R"(}]},
               "initial": {"omega": [0.1, 0.2, 1]}, "integrator": {"method": "rkmk4", "dt": 0.01}, "t_end": 0.1})";
  };
  write("good.csv", good);
  const fs::path valid = write("table.json", scene_with("good.csv", R"(, "interpolation": "cubic")"));
  const Result ok = run(valid, dir_ / "table.csv");
  EXPECT_EQ(ok.status, 0) << ok.err;
  fs::remove(dir_ / "table.csv");

  struct TableCase {
    std::string name, csv, extra, golden;  // golden: {csv} for the table's path
  };
  const std::vector<TableCase> table_cases = {
      {"table_unsorted", "t,M1,M2,M3\n0,0,0,0\n0.06,0,0,0\n0.05,0,0,0\n0.1,0,0,0\n", "",
       "lgi: error: {csv}:4: t = 0.05 does not come after the previous row's t = 0.06 (a torque table's times increase "
       "strictly)"},
      {"table_repeated_time", "t,M1,M2,M3\n0,0,0,0\n0,1,0,0\n0.1,0,0,0\n", "",
       "lgi: error: {csv}:3: t = 0 does not come after the previous row's t = 0 (a torque table's times increase "
       "strictly)"},
      {"table_nan", "t,M1,M2,M3\n0,0,0,0\n0.05,0,NaN,0\n0.1,0,0,0\n", "",
       "lgi: error: {csv}:3: column M2: not a finite number: \"NaN\""},
      {"table_missing_column", "t,M1,M3\n0,0,0\n0.1,0,0\n", "",
       "lgi: error: {csv}: missing column M2 (the header has t, M1, M3; a torque table has t, M1, M2, M3)"},
      {"table_unknown_column", "t,M1,M2,M3,M4\n0,0,0,0,0\n0.1,0,0,0,0\n", "",
       "lgi: error: {csv}: unknown column \"M4\" in the header (a torque table has the columns t, M1, M2, M3)"},
      {"table_short_row", "t,M1,M2,M3\n0,0,0,0\n0.1,0,0\n", "",
       "lgi: error: {csv}:3: row has 3 values, the header 4"},
      {"table_one_row", "t,M1,M2,M3\n0,0,0,0\n", "",
       "lgi: error: {csv}: a torque table needs at least 2 rows to interpolate, it has 1"},
      {"table_starts_late", "t,M1,M2,M3\n0.01,0,0,0\n0.1,0,0,0\n", "",
       "lgi: error: {csv}:2: the table starts at t = 0.01, after the run's start t = 0 (the torque would be undefined "
       "there)"},
      {"table_ends_early", "t,M1,M2,M3\n0,0,0,0\n0.09,0,0,0\n", "",
       "lgi: error: {file}: /t_end: t_end = 0.1 is beyond the last row of the torque table {csv} (t = 0.09): the "
       "torque is not known there"},
      {"table_empty", "", "", "lgi: error: {csv}: empty torque table (no header row)"},
      {"table_interpolation_unknown", good, R"(, "interpolation": "spline")",
       "lgi: error: {file}: /problem/torques/0/interpolation: unknown interpolation \"spline\" (known: linear, cubic)"},
      {"table_key_unknown", good, R"(, "scale": 2)",
       "lgi: error: {file}: /problem/torques/0/scale: unknown key for a torque table (allowed: type, file, frame, "
       "interpolation)"},
  };
  for (const TableCase& c : table_cases) {
    const fs::path csv = write(c.name + "_table.csv", c.csv);  // not the run's output, name + ".csv"
    std::string golden = c.golden;
    for (auto at = golden.find("{csv}"); at != std::string::npos; at = golden.find("{csv}"))
      golden.replace(at, 5, csv.string());
    expect_rejected(c.name, scene_with(c.name + "_table.csv", c.extra), golden);
  }
  // -o naming the table: refused, the table untouched (lgi does not replace its input).
  const fs::path victim = write("victim.csv", good);
  const Result same = run(write("victim.json", scene_with("victim.csv")), victim);
  EXPECT_EQ(same.status, 1);
  EXPECT_EQ(same.err, "lgi: error: -o " + victim.string() + " is the scene's torque table " + victim.string() +
                          ": lgi does not replace its input\n");
  EXPECT_EQ(lgi::test::slurp(victim), good);

  const fs::path missing = dir_ / "absent.csv";
  expect_rejected("table_file_missing", scene_with("absent.csv"),
                  "lgi: error: {file}: /problem/torques/0/file: cannot read the torque table " + missing.string() +
                      ": No such file or directory");

  // A gyrostat's motor table: the same reader, the columns t, g1 … gN; the one that ends first bounds t_end.
  const auto gyrostat_with = [](const std::string& csv, const std::string& extra = "") {
    return edit(gyrostat, "\"wheel_control\"", R"("motor_table": {"file": ")" + csv + "\"" + extra + "}, \"wheel_control\"");
  };
  write("motors.csv", "t,g1,g2,g3\n0,0.1,0,0\n0.1,0,0.2,0\n");
  const Result motors = run(write("motors.json", gyrostat_with("motors.csv", R"(, "interpolation": "cubic")")),
                            dir_ / "motors_run.csv");
  EXPECT_EQ(motors.status, 0) << motors.err;
  fs::remove(dir_ / "motors_run.csv");
  const std::vector<TableCase> motor_cases = {
      {"motor_table_missing_column", "t,g1,g3\n0,0,0\n0.1,0,0\n", "",
       "lgi: error: {csv}: missing column g2 (the header has t, g1, g3; a motor table has t, g1, g2, g3)"},
      {"motor_table_unsorted", "t,g1,g2,g3\n0,0,0,0\n0.1,0,0,0\n0.05,0,0,0\n", "",
       "lgi: error: {csv}:4: t = 0.05 does not come after the previous row's t = 0.1 (a motor table's times increase "
       "strictly)"},
      {"motor_table_ends_early", "t,g1,g2,g3\n0,0,0,0\n0.08,0,0,0\n", "",
       "lgi: error: {file}: /t_end: t_end = 0.1 is beyond the last row of the torque table {csv} (t = 0.08): the "
       "torque is not known there"},
      {"motor_table_key_unknown", "t,g1,g2,g3\n0,0,0,0\n0.1,0,0,0\n", R"(, "frame": "body")",
       "lgi: error: {file}: /problem/motor_table/frame: unknown key for motor_table (allowed: file, interpolation)"},
  };
  for (const TableCase& c : motor_cases) {
    const fs::path csv = write(c.name + "_table.csv", c.csv);
    std::string golden = c.golden;
    for (auto at = golden.find("{csv}"); at != std::string::npos; at = golden.find("{csv}"))
      golden.replace(at, 5, csv.string());
    expect_rejected(c.name, gyrostat_with(c.name + "_table.csv", c.extra), golden);
  }
}

TEST_F(MalformedScenes, EachGivesItsGoldenMessageAndStatusAndNoOutput) {
  const std::vector<Case> all = cases();
  EXPECT_GE(all.size(), 40u);
  for (const Case& c : all) expect_rejected(c.name, c.text, c.golden);
}

}  // namespace
