# The README's method table is `lgi list --markdown`, verbatim (the table is generated from the traits).
#   cmake -DLGI=<lgi executable> -DREADME=<README.md> -P readme_methods_test.cmake
execute_process(COMMAND ${LGI} list --markdown OUTPUT_VARIABLE table RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "lgi list --markdown failed (${rc})")
endif()
file(READ ${README} readme)
string(FIND "${readme}" "<!-- methods:begin -->\n${table}<!-- methods:end -->" at)
if(at EQUAL -1)
  message(FATAL_ERROR "README.md's method table is out of date; replace the lines between the methods markers with:\n${table}")
endif()
