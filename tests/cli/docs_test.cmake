# The front door's promises, checked against the code:
#   - README.md is at most 200 lines, names no internal issue or session, and every relative link in it resolves;
#   - docs/scenes.md documents every problem type `lgi list` lists, each with a "### `type`" section whose table has
#     a "| `key` |" row for every key the loader takes (and `lgi list` lists no type the reference lacks, nor the
#     reference one the loader does not know);
#   - the comments of core/, integrators/, problems/, apps/ and fit/ (*.hpp, *.cpp, recursively) hold equations,
#     contracts, guarantees and references, not lab notes: measurements and history belong in commit messages and
#     docs/ (performance.md, "Design measurements behind the code"; findings.md). A comment line is rejected, with
#     its file:line and the text matched, when it matches one of these CMake regular expressions (the check reads
#     them from this list, so the list is the rule):
#       `[0-9][0-9,.]* ?(instructions|instr\.)`         an instruction count ("397 instructions a step")
#       `^ *instructions( a | per |/)(step|kick|body)`  the same, its number at the end of the line above
#       `[Cc]allgrind[^0-9]*[0-9]+`                    callgrind followed by a figure
#       `[0-9][0-9.]* ?(→|->) ?[0-9][0-9.]*`           before → after figures ("972 → 1416")
#       `[0-9][0-9.]* ?(µs|ns)([^A-Za-z]|$)`           a timing in µs or ns
#       `[0-9]+\.[0-9]+ ?ms([^A-Za-z]|$)`              a timing in ms with decimals ("every 10 ms of work" is a
#                                                      contract, not a measurement)
#       `[0-9]+ ?s of (compile|CPU)`                   a compile or CPU time
#       `[0-9][0-9.]* ?(%|×) (faster|slower)`          a speed-up
#       `(fell|rose|dropped) from [0-9][0-9.e+-]*`     before and after in words
#       `medians? of [0-9]+`                           medians of N runs
#       `(Zen [0-9]|EPYC|vCPU|[0-9] ?GHz)`             the machine a figure was measured on
#       `20[0-9][0-9]-[01][0-9]-[0-3][0-9]`            a date
#       `(until|as of) 20[0-9][0-9]`                   dated history ("the form this file had until ...")
#       `first estimated`                              an estimate's history
#   This part needs only SOURCE_DIR and reports its findings together with the others, also when lgi fails.
#   cmake -DLGI=<lgi executable> -DSOURCE_DIR=<lgi's source tree> -P docs_test.cmake
cmake_minimum_required(VERSION 3.25)
set(errors "")

# README.md
file(READ ${SOURCE_DIR}/README.md readme)
string(REGEX MATCHALL "\n" newlines "${readme}")
list(LENGTH newlines n)
if(n GREATER 200)
  string(APPEND errors "README.md has ${n} lines (at most 200: what lgi is, the two commands, an example, where to go next)\n")
endif()
string(REGEX MATCHALL "([Ii]ssues? #?[0-9]+|\\(issue[^)]*\\)|[Ss]ession [0-9]|[Ss]top [0-9]+)" internal "${readme}")
if(internal)
  string(APPEND errors "README.md names internal issues or sessions: ${internal}\n")
endif()
# (Markdown links "](path)" to files of the tree; matched without the bracket, which CMake lists treat specially.)
string(REGEX MATCHALL "\\(([A-Za-z0-9_./-]+\\.(md|cff|txt|json|cpp|hpp))[)#]" links "${readme}")
foreach(link ${links})
  string(REGEX REPLACE "^\\(([^)#]+)[)#]$" "\\1" target "${link}")
  if(NOT EXISTS ${SOURCE_DIR}/${target})
    string(APPEND errors "README.md links to ${target}, which does not exist\n")
  endif()
endforeach()

# No lab notes in source comments: the patterns of the header, read from it.
file(STRINGS ${CMAKE_CURRENT_LIST_FILE} header_lines ENCODING UTF-8 REGEX "^#       `[^`]+`")
set(rejected "")
foreach(h IN LISTS header_lines)
  string(REGEX REPLACE "^#       `([^`]+)`.*$" "\\1" pattern "${h}")
  list(APPEND rejected "${pattern}")
endforeach()
list(LENGTH rejected rejected_count)
if(rejected_count LESS 10)
  message(FATAL_ERROR "docs_test.cmake: read ${rejected_count} rejected comment patterns from its header")
endif()
set(comment_dirs core integrators problems apps fit)
set(globs "")
foreach(d ${comment_dirs})
  list(APPEND globs ${SOURCE_DIR}/${d}/*.hpp ${SOURCE_DIR}/${d}/*.cpp)
endforeach()
file(GLOB_RECURSE sources LIST_DIRECTORIES false RELATIVE ${SOURCE_DIR} ${globs})
list(SORT sources)
list(LENGTH sources source_count)
if(source_count LESS 50)
  message(FATAL_ERROR "only ${source_count} source files under ${comment_dirs} in ${SOURCE_DIR}")
endif()
set(comment_lines 0)
set(lab_notes "")
foreach(source ${sources})
  file(READ ${SOURCE_DIR}/${source} text)
  if(NOT text MATCHES "//")
    continue()
  endif()
  # One list element per line: backslashes, semicolons and brackets (which CMake lists treat specially) stand in
  # as @B@, @S@, @L@, @R@.
  string(REPLACE "\\" "@B@" text "${text}")
  string(REPLACE ";" "@S@" text "${text}")
  string(REPLACE "[" "@L@" text "${text}")
  string(REPLACE "]" "@R@" text "${text}")
  string(REPLACE "\n" ";" lines "${text}")
  set(number 0)
  foreach(line IN LISTS lines)
    math(EXPR number "${number} + 1")
    # The comment: from the first // of a line whose code before it holds no string literal.
    string(FIND "${line}" "//" at)
    if(at EQUAL -1)
      continue()
    endif()
    string(SUBSTRING "${line}" 0 ${at} code)
    if(code MATCHES "\"")
      continue()
    endif()
    math(EXPR at "${at} + 2")
    string(SUBSTRING "${line}" ${at} -1 comment)
    math(EXPR comment_lines "${comment_lines} + 1")
    foreach(pattern IN LISTS rejected)
      if(comment MATCHES "${pattern}")
        string(REPLACE "@B@" "\\" found "${CMAKE_MATCH_0}")
        string(REPLACE "@S@" ";" found "${found}")
        string(REPLACE "@L@" "[" found "${found}")
        string(REPLACE "@R@" "]" found "${found}")
        string(APPEND lab_notes "  ${source}:${number}: \"${found}\"   (`${pattern}`)\n")
      endif()
    endforeach()
  endforeach()
endforeach()

if(lab_notes)
  string(APPEND errors "Lab notes in source comments (measurements and history go to docs/ or the commit message; "
                       "the patterns: the header of tests/cli/docs_test.cmake):\n${lab_notes}")
endif()

# docs/scenes.md against `lgi list`
execute_process(COMMAND ${LGI} list OUTPUT_VARIABLE listing RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${errors}lgi list failed (${rc})")
endif()
file(READ ${SOURCE_DIR}/docs/scenes.md scenes)
string(REPLACE "\n" ";" listing_lines "${listing}")
set(type "")
set(types "")
foreach(line ${listing_lines})
  if(line MATCHES "^methods \\(")
    break()
  endif()
  if(line MATCHES "^  ([a-z0-9_]+) ")
    set(type ${CMAKE_MATCH_1})
    list(APPEND types ${type})
  elseif(type AND line MATCHES "^ +keys: (.*)$")
    string(REPLACE ", " ";" keys "${CMAKE_MATCH_1}")
    string(FIND "${scenes}" "### `${type}`" at)
    if(at EQUAL -1)
      string(APPEND errors "docs/scenes.md has no section \"### `${type}`\" for the problem type ${type}\n")
      continue()
    endif()
    string(SUBSTRING "${scenes}" ${at} -1 section)
    string(SUBSTRING "${section}" 4 -1 rest)
    string(FIND "${rest}" "\n### " next)
    string(FIND "${rest}" "\n## " next2)
    if(next EQUAL -1 OR (next2 GREATER -1 AND next2 LESS next))
      set(next ${next2})
    endif()
    if(next GREATER -1)
      string(SUBSTRING "${rest}" 0 ${next} section)
    endif()
    foreach(key ${keys})
      string(FIND "${section}" "| `${key}` |" row)
      if(row EQUAL -1)
        string(APPEND errors "docs/scenes.md, section ${type}: no row for its key `${key}`\n")
      endif()
    endforeach()
  endif()
endforeach()
if(NOT types)
  message(FATAL_ERROR "no problem types in `lgi list`:\n${listing}")
endif()
# The reference's problem sections name registered types only.
string(FIND "${scenes}" "\n## Problems" p0)
string(SUBSTRING "${scenes}" ${p0} -1 problems_part)
string(SUBSTRING "${problems_part}" 3 -1 problems_rest)
string(FIND "${problems_rest}" "\n## " p1)
string(SUBSTRING "${problems_rest}" 0 ${p1} problems_part)
string(REGEX MATCHALL "\n### `[a-z0-9_]+`" documented "${problems_part}")
foreach(d ${documented})
  string(REGEX REPLACE "\n### `([a-z0-9_]+)`" "\\1" d "${d}")
  if(NOT d IN_LIST types)
    string(APPEND errors "docs/scenes.md documents a problem type `${d}` that `lgi list` does not list\n")
  endif()
endforeach()

if(errors)
  message(FATAL_ERROR "${errors}")
endif()
list(LENGTH types count)
message(STATUS "README.md: ${n} lines; docs/scenes.md: the ${count} problem types and their keys; "
               "${comment_lines} comment lines in ${source_count} source files, none matching the ${rejected_count} "
               "rejected patterns")
