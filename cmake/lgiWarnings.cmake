# lgi_set_warnings(target): the warning set for lgi's own compiled targets (tests, apps, benchmarks).
function(lgi_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
                                           -Wold-style-cast -Woverloaded-virtual -Wnull-dereference
                                           -Wimplicit-fallthrough -Wmisleading-indentation)
  if(LGI_WARNINGS_AS_ERRORS)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
