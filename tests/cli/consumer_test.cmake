# Builds and runs examples/consumer against lgi, the way a user's project would: configured without a build type
# (the consumer must then build optimised), one program per exported target — lgi::lgi and lgi::core, lgi::batch
# where lgi has it, lgi::fit after an install (both required when REQUIRE_ALL says this lgi has them) — each run and
# required to succeed.
#   cmake -DMODE=install|subdirectory -DREQUIRE_ALL=ON|OFF -DLGI_SOURCE_DIR=... -DLGI_BINARY_DIR=... -DWORK_DIR=...
#         -P consumer_test.cmake
cmake_minimum_required(VERSION 3.25)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}\n${err}")
  endif()
  message("${out}")
  set(output "${out}" PARENT_SCOPE)
endfunction()

if(MODE STREQUAL "install")
  run(${CMAKE_COMMAND} --install ${LGI_BINARY_DIR} --prefix ${WORK_DIR}/prefix)
  run(${CMAKE_COMMAND} -S ${LGI_SOURCE_DIR}/examples/consumer -B ${WORK_DIR}/build
      -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix -DLGI_CONSUMER_REQUIRE_ALL=${REQUIRE_ALL})
else()
  set(REQUIRE_ALL OFF)  # add_subdirectory builds lgi::fit only when asked (LGI_BUILD_FIT)
  run(${CMAKE_COMMAND} -S ${LGI_SOURCE_DIR}/examples/consumer -B ${WORK_DIR}/build
      -DLGI_SOURCE_DIR=${LGI_SOURCE_DIR})
endif()
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build -j 2)

set(programs consumer consumer_core)
foreach(program consumer_batch consumer_fit)  # built where lgi has the target (required: LGI_CONSUMER_REQUIRE_ALL)
  if(EXISTS ${WORK_DIR}/build/${program})
    list(APPEND programs ${program})
  endif()
endforeach()
# The Python package, where the build has it: installed into PREFIX/lib/python3.X/dist-packages, the directory
# Debian's python3.X searches for PREFIX = /usr/local (checked too); it imports and runs from the installed tree alone.
file(GLOB site LIST_DIRECTORIES true ${WORK_DIR}/prefix/lib/python3.*/dist-packages)
if(MODE STREQUAL "install" AND EXISTS ${LGI_BINARY_DIR}/python/lgi/__init__.py)
  if(NOT site OR NOT EXISTS ${site}/lgi/__init__.py)
    message(FATAL_ERROR "cmake --install put no Python package in ${WORK_DIR}/prefix/lib/python3.X/dist-packages")
  endif()
  string(REGEX REPLACE "^.*/prefix/" "/usr/local/" local_site "${site}")
  file(WRITE ${WORK_DIR}/installed_package.py "
import sys
assert '${local_site}' in sys.path, sys.path  # Debian's python3 and the default prefix
import lgi
assert lgi.__file__.startswith('${site}'), lgi.__file__
print(lgi.run('${LGI_SOURCE_DIR}/scenes/heavy_top.json').status)
")
  run(${CMAKE_COMMAND} -E env PYTHONPATH=${site} /usr/bin/python3 ${WORK_DIR}/installed_package.py)
  if(NOT output MATCHES "completed")
    message(FATAL_ERROR "the installed Python package did not run the heavy top: ${output}")
  endif()
endif()
foreach(program ${programs})
  run(${WORK_DIR}/build/${program})
  if(program STREQUAL "consumer_core" AND NOT output MATCHES "optimised: yes")
    message(FATAL_ERROR "${program}: built without optimisation (a consumer configured without a build type must "
                        "build optimised)")
  endif()
endforeach()
