# A problem type from a plugin (apps/plugin.hpp, examples/plugin/), end to end as a user meets it: lgi installed,
# the example plugin built against the installed package, then loaded by the installed `lgi`.
#   - `lgi list --plugin` lists its problem types;
#   - plugin_heavy_top (the heavy top under another name) gives the built-in heavy_top's bytes with every method the
#     plugin offers, for `lgi run` (fixed steps and adaptive) and `lgi sweep`; tethered_top runs;
#   - a missing file, a library that is not an lgi plugin, and a plugin built against another version's headers each
#     exit 1 with one line naming the file and the reason.
#   cmake -DLGI_SOURCE_DIR=... -DLGI_BINARY_DIR=... -DWORK_DIR=... -P plugin_test.cmake
cmake_minimum_required(VERSION 3.25)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  set(out "${out}" PARENT_SCOPE)
endfunction()

set(prefix ${WORK_DIR}/prefix)
run(${CMAKE_COMMAND} --install ${LGI_BINARY_DIR} --prefix ${prefix})
run(${CMAKE_COMMAND} -S ${LGI_SOURCE_DIR}/examples/plugin -B ${WORK_DIR}/plugin -DCMAKE_PREFIX_PATH=${prefix})
run(${CMAKE_COMMAND} --build ${WORK_DIR}/plugin)
set(lgi ${prefix}/bin/lgi)
set(plugin ${WORK_DIR}/plugin/libtethered_top.so)
if(NOT EXISTS ${plugin})
  message(FATAL_ERROR "the example did not build ${plugin}")
endif()

# lgi list
run(${lgi} list --plugin ${plugin})
foreach(type tethered_top plugin_heavy_top)
  if(NOT out MATCHES "\n  ${type} ")
    message(FATAL_ERROR "lgi list --plugin does not list ${type}:\n${out}")
  endif()
endforeach()

# The same bytes as the built-in heavy_top: a skew top (non-diagonal inertia, tilted k and z0).
set(problem [=["inertia": [[2, 0.1, 0], [0.1, 2.5, 0.2], [0, 0.2, 1]], "b": 1.3, "k": [0, 0.6, 0.8], "z0": [0.6, 0, 0.8]]=])
set(initial [["initial": {"omega": [0.3, -0.2, 4]}, "t_end": 5, "output": {"every": 50}]])
function(compare name method_json)
  foreach(type heavy_top plugin_heavy_top)
    file(WRITE ${WORK_DIR}/${name}_${type}.json
         "{\"problem\": {\"type\": \"${type}\", ${problem}}, ${initial}, \"integrator\": ${method_json}}")
    run(${lgi} run --plugin ${plugin} -q ${WORK_DIR}/${name}_${type}.json -o ${WORK_DIR}/${name}_${type}.csv)
    file(SHA256 ${WORK_DIR}/${name}_${type}.csv hash_${type})
  endforeach()
  file(STRINGS ${WORK_DIR}/${name}_heavy_top.csv rows)
  list(LENGTH rows n)
  if(NOT hash_heavy_top STREQUAL hash_plugin_heavy_top OR n LESS 5)
    message(FATAL_ERROR "${name}: plugin_heavy_top's rows differ from heavy_top's (or fewer than 5: ${n})")
  endif()
  message(STATUS "${name}: ${n} rows, the same bytes")
endfunction()
compare(lgvi [[{"method": "lgvi", "dt": 0.01}]])
compare(rkmk4 [[{"method": "rkmk4", "dt": 0.01}]])
compare(rkmk4_projected [[{"method": "rkmk4", "dt": 0.01, "projection": true}]])
compare(split_dmv [[{"method": "split_dmv", "dt": 0.01}]])
compare(rkmk_dp5 [[{"method": "rkmk_dp5", "dt": 0.01, "rtol": 1e-9, "atol": 1e-12}]])

# A sweep over b.
foreach(type heavy_top plugin_heavy_top)
  file(WRITE ${WORK_DIR}/sweep_${type}.json
       "{\"problem\": {\"type\": \"${type}\", ${problem}}, ${initial}, \"integrator\": {\"method\": \"lgvi\", \"dt\": 0.01},
         \"sweep\": {\"grid\": {\"/problem/b\": {\"from\": 0.5, \"to\": 2, \"count\": 4}}}}")
  run(${lgi} sweep --plugin ${plugin} -q ${WORK_DIR}/sweep_${type}.json -o ${WORK_DIR}/sweep_${type}.csv)
  file(SHA256 ${WORK_DIR}/sweep_${type}.csv hash_${type})
endforeach()
if(NOT hash_heavy_top STREQUAL hash_plugin_heavy_top)
  message(FATAL_ERROR "lgi sweep: plugin_heavy_top's rows differ from heavy_top's")
endif()

# The tethered top runs (its own problem: no built-in twin).
file(WRITE ${WORK_DIR}/tethered.json [[{"problem": {"type": "tethered_top", "inertia": [2, 2, 1], "kappa": 20},
  "initial": {"omega": [0.3, -0.2, 4]}, "integrator": {"method": "lgvi", "dt": 0.001}, "t_end": 1}]])
run(${lgi} run --plugin ${plugin} -q ${WORK_DIR}/tethered.json -o ${WORK_DIR}/tethered.csv)
# --plugin takes one FILE: the scene right after it is the scene (lgi fit likewise, through lgi-fit).
run(${lgi} run --plugin ${plugin} ${WORK_DIR}/tethered.json -q -o ${WORK_DIR}/tethered2.csv)
run(${lgi} list --plugin ${plugin} --plugin ${plugin})

# Refusals: exit 1, one line, naming the file and the reason.
function(refused file reason)
  execute_process(COMMAND ${lgi} run --plugin ${file} ${WORK_DIR}/tethered.json RESULT_VARIABLE rc OUTPUT_VARIABLE out
                  ERROR_VARIABLE err)
  string(REGEX MATCHALL "\n" lines "${err}")
  list(LENGTH lines n)
  string(FIND "${err}" "${file}" at_file)
  if(NOT rc EQUAL 1 OR NOT n EQUAL 1 OR at_file LESS 0 OR NOT err MATCHES "${reason}")
    message(FATAL_ERROR "lgi run --plugin ${file}: expected exit 1 and one line naming it and '${reason}', got ${rc}:\n${err}")
  endif()
  message(STATUS "refused: ${err}")
endfunction()
refused(${WORK_DIR}/no_such_plugin.so "cannot load the plugin: No such file")

# A library that is not a plugin, and a plugin built against another version's headers (a copy of the install whose
# version.hpp says 0.0.1).
set(other ${WORK_DIR}/prefix_other)
file(COPY ${prefix}/ DESTINATION ${other})
file(READ ${other}/include/lgi/app/version.hpp version_text)
string(REGEX REPLACE "LGI_VERSION_STRING \"[^\"]*\"" "LGI_VERSION_STRING \"0.0.1\"" version_text "${version_text}")
file(WRITE ${other}/include/lgi/app/version.hpp "${version_text}")
run(${CMAKE_COMMAND} -S ${LGI_SOURCE_DIR}/tests/cli/plugin_fixtures -B ${WORK_DIR}/fixtures -DCMAKE_PREFIX_PATH=${other}
    -DCMAKE_BUILD_TYPE=Release)
run(${CMAKE_COMMAND} --build ${WORK_DIR}/fixtures)
refused(${WORK_DIR}/fixtures/libnot_a_plugin.so "not an lgi plugin")
refused(${WORK_DIR}/fixtures/libminimal_plugin.so "built for another lgi \\(lgi 0.0.1;")

# From Python (the installed package, where the build has it): lgi.load_plugin gives the plugin's types their classes;
# plugin_heavy_top gives the built-in heavy_top's bits; a library that is not a plugin raises InputError naming it.
file(GLOB site LIST_DIRECTORIES true ${prefix}/lib/python3.*/dist-packages)
if(site AND EXISTS ${site}/lgi/__init__.py)
  file(WRITE ${WORK_DIR}/plugin_from_python.py [[
import sys
import numpy as np
import lgi
lgi.load_plugin(sys.argv[1])
kw = dict(inertia=[2, 2, 1], b=1, k=[0, 0.6, 0.8])
a = lgi.integrate(lgi.PluginHeavyTop(**kw), omega0=[0.1, 0.2, 5], t=1.0, method="lgvi", dt=0.001)
b = lgi.integrate(lgi.HeavyTop(**kw), omega0=[0.1, 0.2, 5], t=1.0, method="lgvi", dt=0.001)
assert np.array_equal(a.R, b.R) and np.array_equal(a.omega, b.omega)
assert lgi.integrate(lgi.TetheredTop(inertia=[2, 2, 1], kappa=20), omega0=[0.3, -0.2, 4], t=1.0, method="lgvi",
                     dt=0.001).status == "completed"
try:
    lgi.load_plugin(sys.argv[2])
    raise SystemExit("a library that is not a plugin was loaded")
except ValueError as e:
    assert "not an lgi plugin" in str(e) and sys.argv[2] in str(e), e
print("python plugin ok")
]])
  run(${CMAKE_COMMAND} -E env PYTHONPATH=${site} /usr/bin/python3 ${WORK_DIR}/plugin_from_python.py ${plugin}
      ${WORK_DIR}/fixtures/libnot_a_plugin.so)
  if(NOT out MATCHES "python plugin ok")
    message(FATAL_ERROR "the plugin from Python: ${out}")
  endif()
endif()
