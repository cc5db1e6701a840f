# Runs Doxygen on lgi's configured Doxyfile and reports its warnings (the `docs` target and the api_reference test).
#
#   cmake -DDOXYGEN=<doxygen> -DDOXYFILE=<build>/docs/Doxyfile [-DOUTPUT_DIR=<dir>] [-DSTRICT=ON] -P lgiDoxygen.cmake
#
# OUTPUT_DIR: write the HTML and the warning log there instead of the Doxyfile's OUTPUT_DIRECTORY and WARN_LOGFILE
# (through a Doxyfile of its own that @INCLUDEs the configured one), so that the test and the docs target do not
# write over each other. The warnings are printed; STRICT makes any warning an error (the test: an undocumented
# public member, a reference that does not resolve, a malformed command). Run from the source directory.
cmake_minimum_required(VERSION 3.25)
foreach(var DOXYGEN DOXYFILE)
  if(NOT ${var})
    message(FATAL_ERROR "lgiDoxygen.cmake: -D${var}=... is required")
  endif()
endforeach()

set(config ${DOXYFILE})
if(OUTPUT_DIR)
  file(MAKE_DIRECTORY ${OUTPUT_DIR})
  set(config ${OUTPUT_DIR}/Doxyfile)
  file(WRITE ${config} "@INCLUDE = ${DOXYFILE}\nOUTPUT_DIRECTORY = ${OUTPUT_DIR}\n"
                       "WARN_LOGFILE = ${OUTPUT_DIR}/doxygen-warnings.log\n")
endif()
# The log the configuration names (the last WARN_LOGFILE line wins, as in Doxygen).
file(STRINGS ${DOXYFILE} lines REGEX "^WARN_LOGFILE *=")
if(OUTPUT_DIR)
  set(log ${OUTPUT_DIR}/doxygen-warnings.log)
else()
  list(POP_BACK lines line)
  string(REGEX REPLACE "^WARN_LOGFILE *= *" "" log "${line}")
  string(STRIP "${log}" log)
endif()
if(NOT log)
  message(FATAL_ERROR "lgiDoxygen.cmake: ${DOXYFILE} names no WARN_LOGFILE")
endif()
file(REMOVE ${log})

execute_process(COMMAND ${DOXYGEN} ${config} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "doxygen failed (${rc}):\n${out}${err}")
endif()

set(warnings "")
if(EXISTS ${log})
  file(READ ${log} warnings)
endif()
# Doxygen writes a few messages to stderr even with a WARN_LOGFILE (e.g. an unknown configuration tag).
string(STRIP "${err}" err)
if(err)
  string(APPEND warnings "${err}\n")
endif()
string(STRIP "${warnings}" warnings)
if(warnings)
  string(REGEX MATCHALL "\n" newlines "${warnings}\n")
  list(LENGTH newlines count)
  message(NOTICE "${warnings}")  # as Doxygen wrote them: file:line: text
  if(STRICT)
    message(FATAL_ERROR "${count} Doxygen warning lines above (document every public member; docs/Doxyfile.in says "
                        "what is excluded and why)")
  endif()
  message(WARNING "${count} Doxygen warning lines above")
else()
  message(STATUS "API reference: 0 Doxygen warnings")
endif()
