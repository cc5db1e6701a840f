// lgi/apps/command.hpp — what the subcommands of `lgi` share: exit statuses, error messages, output files
// (output_file.hpp: regular files are written under a temporary name and renamed into place, devices and pipes
// are streamed to).
#pragma once

#include "output_file.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>
#include <system_error>

namespace lgi::app {

// Exit statuses of `lgi` (README "The lgi command").
inline constexpr int exit_bad_input = 1;       // bad command line, scene or fit file; nothing written
inline constexpr int exit_run_failed = 2;      // an integration failed (`lgi run`: the rows to the last good state are written)
inline constexpr int exit_io_error = 3;        // an output could not be written, or the system refused a resource
inline constexpr int exit_internal_error = 4;  // a bug
inline constexpr int exit_fit_unusable = 5;    // `lgi fit`: the solution is not usable (result still written)
inline constexpr int exit_run_stopped = 6;     // `lgi run`: a budget (scene "limits") stopped the run; rows written

// "lgi: error: MESSAGE" on stderr, one line (control characters and NUL bytes in MESSAGE are escaped as in JSON,
// so nothing of it is lost or breaks the line); returns `status`.
inline int fail(int status, const std::string& message) {
  std::string line = "lgi: error: ";
  for (const char c : message) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '\n') line += "\\n";
    else if (c == '\t') line += "\\t";
    else if (c == '\r') line += "\\r";
    else if (u < 0x20 || u == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", u);
      line += buf;
    } else {
      line += c;
    }
  }
  line += '\n';
  std::fwrite(line.data(), 1, line.size(), stderr);
  return status;
}

// command(), with what escapes it as one line and a status: out of memory or a resource the system refused
// exit_io_error, anything else exit_internal_error (a bug).
template <class Command>
int guarded(Command&& command) {
  try {
    return command();
  } catch (const std::bad_alloc&) {
    return fail(exit_io_error, "out of memory (the system refused an allocation); nothing was written");
  } catch (const std::system_error& e) {  // a resource the system refused (threads, ...)
    return fail(exit_io_error, std::string("the system refused a resource: ") + e.what());
  } catch (const std::exception& e) {
    return fail(exit_internal_error, std::string("internal error: ") + e.what());
  }
}

}  // namespace lgi::app
