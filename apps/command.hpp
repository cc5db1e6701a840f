// lgi/apps/command.hpp — what the subcommands of `lgi` share: exit statuses, error messages, output files.
//
// AtomicOutput writes under a temporary name beside the target (".NAME.tmp-XXXXXX") and renames into
// place only on commit(): bad input or an output error leaves no file under the target name. (`lgi run`
// commits an incomplete run's rows too — a failed step, a budget, a signal — and says so in its exit status.)
#pragma once

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

namespace lgi::app {

// Exit statuses of `lgi` (README "The lgi command").
inline constexpr int exit_bad_input = 1;       // bad command line, scene or fit file; nothing written
inline constexpr int exit_run_failed = 2;      // an integration failed (`lgi run`: the rows to the last good state are written)
inline constexpr int exit_io_error = 3;        // an output could not be written
inline constexpr int exit_internal_error = 4;  // a bug
inline constexpr int exit_fit_unusable = 5;    // `lgi fit`: the solution is not usable (result still written)
inline constexpr int exit_run_stopped = 6;     // `lgi run`: a budget (scene "limits") stopped the run; rows written

// "lgi: error: MESSAGE" on stderr; returns `status`.
inline int fail(int status, const std::string& message) {
  std::fprintf(stderr, "lgi: error: %s\n", message.c_str());
  return status;
}

// An output file written under a temporary name beside the target and renamed into place only when
// everything succeeded: a failed run leaves no partial file.
class AtomicOutput {
 public:
  explicit AtomicOutput(const std::string& target) : target_(target) {
    const std::filesystem::path p(target);
    std::error_code ec;
    if (std::filesystem::is_directory(p, ec) || (!target.empty() && target.back() == '/'))
      throw std::runtime_error(target + ": cannot write the output file: it is a directory");
    temp_ = (p.has_parent_path() ? p.parent_path() / "" : std::filesystem::path()).string() + "." +
            p.filename().string() + ".tmp-XXXXXX";
    const int fd = mkstemp(temp_.data());
    if (fd < 0) throw std::runtime_error(target + ": cannot create the output file: " + std::strerror(errno));
    const mode_t mask = umask(0);  // mkstemp makes 0600; give the file the mode a plain create would
    umask(mask);
    fchmod(fd, 0666 & ~mask);
    file_ = fdopen(fd, "w");
    if (!file_) throw std::runtime_error(target + ": cannot open the output file: " + std::strerror(errno));
    buffer_ = std::make_unique<char[]>(buffer_size);  // its own: two outputs may be open at once
    std::setvbuf(file_, buffer_.get(), _IOFBF, buffer_size);
  }
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;
  ~AtomicOutput() {
    if (file_) std::fclose(file_);
    if (!committed_) std::remove(temp_.c_str());
  }
  std::FILE* file() const { return file_; }
  const std::string& temp_path() const { return temp_; }
  // Closes and renames into place; false (with errno) on failure.
  bool commit() {
    const bool ok = std::fflush(file_) == 0 && std::ferror(file_) == 0 && fsync(fileno(file_)) == 0;
    const bool closed = std::fclose(file_) == 0;
    file_ = nullptr;
    if (!ok || !closed) return false;
    if (std::rename(temp_.c_str(), target_.c_str()) != 0) return false;
    committed_ = true;
    return true;
  }

 private:
  static constexpr std::size_t buffer_size = 1 << 16;
  std::string target_, temp_;
  std::FILE* file_ = nullptr;
  std::unique_ptr<char[]> buffer_;
  bool committed_ = false;
};

}  // namespace lgi::app
