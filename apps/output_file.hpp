// lgi/apps/output_file.hpp — the files lgi writes: outputs that never replace what they should not, and that keep
// whole records when a write fails.
//
// Where an output goes (OutputFile's constructor decides once):
//   - "-", or a path that exists and is not a regular file (a character device such as /dev/null or /dev/full, a
//     FIFO, a socket, a terminal), or a path under /dev/ or /proc/ (/dev/stdout, /dev/fd/N, /proc/self/fd/N):
//     streamed — written to directly, never removed, renamed or replaced;
//   - otherwise (a regular file, a symbolic link to one, or nothing yet): atomic — written under a temporary name
//     beside the file the path resolves to (".NAME.tmp-XXXXXX", NAME cut so that the temporary name fits in
//     NAME_MAX) and renamed into place by commit(); until then the path keeps its old contents. A symbolic link
//     stays a link: its target is replaced.
//   - a directory, or a path whose directory does not exist or cannot be written: OutputError, before anything
//     is written.
//
// Records. Data arrive in whole records (a CSV row, a JSON document), each ending in '\n', through
// write_record(); the buffer is flushed to the file only between records, so every write(2) carries whole
// records. After the first failed write (a full disk, EFBIG, EIO, a closed pipe) every later write fails at once,
// error() holds the errno, and truncate_to_last_record() cuts an atomic output to the end of the last record that
// reached the file whole — what commit() then renames into place is a file of complete records.
//
// Thread safety: none; one writer per OutputFile. The object allocates its buffer once, in the constructor.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>

namespace lgi::app {

// An output that cannot be opened; the message names the path and the reason (lgi exits 3).
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class OutputFile {
 public:
  // Opens `path` ("-": standard output). Throws OutputError.
  explicit OutputFile(const std::string& path);
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  // An atomic output that was not committed: its temporary file is removed, unless keep_temporary() was called.
  ~OutputFile();

  const std::string& path() const { return path_; }
  // The name for messages: the path, or "stdout" for "-".
  std::string display_name() const { return path_ == "-" ? std::string("stdout") : path_; }
  bool streamed() const { return streamed_; }
  // An atomic output's temporary file (empty when streamed).
  const std::string& temp_path() const { return temp_; }
  // The file commit() replaces: the path with symbolic links resolved (empty when streamed).
  const std::string& target_path() const { return target_; }
  // The file descriptor written to (for pread of what was written: atomic outputs only).
  int fd() const { return fd_; }

  // Appends one record (its last byte should be '\n'). false once any write has failed.
  bool write_record(std::string_view record);
  // Writes the buffer to the file. false on failure (error() says why).
  bool flush();
  // flush(), then fsync(2) for an atomic output (the bytes are on disk when it returns true).
  bool sync();
  // Bytes in the file so far (flushed; a failed write's partial bytes included until truncate_to_last_record()).
  std::uint64_t bytes_in_file() const { return in_file_; }
  bool failed() const { return error_ != 0; }
  int error() const { return error_; }
  std::string error_text() const;  // strerror(error()), or "" when nothing failed

  // After a failed write, an atomic output is cut to the end of its last whole record; true if it was (or nothing
  // needed cutting). The bytes of that file are then bytes_in_file().
  bool truncate_to_last_record();
  // Atomic: flush, fsync, close and rename into place (then fsync of the directory); false with error() set when
  // any of it fails (the destructor then removes the temporary file, unless keep_temporary()). After a failed write
  // (failed() true) it renames what truncate_to_last_record() left: the whole records that reached the file.
  // Streamed: flush. Call at most once.
  bool commit();
  // An uncommitted atomic output's temporary file is left in place by the destructor (a checkpoint counts its
  // rows).
  void keep_temporary() { keep_ = true; }

 private:
  bool write_all(const char* data, std::size_t n);

  std::string path_;      // as given
  std::string target_;    // atomic: the file that commit() replaces (symbolic links resolved)
  std::string temp_;      // atomic: the temporary file beside target_
  int fd_ = -1;
  bool streamed_ = false;
  bool committed_ = false;
  bool keep_ = false;
  int error_ = 0;
  std::uint64_t in_file_ = 0;       // bytes written to the file
  std::uint64_t last_record_ = 0;   // end of the last record known to be in the file whole
  std::unique_ptr<char[]> buffer_;  // whole records only
  std::size_t used_ = 0;
  static constexpr std::size_t buffer_size = std::size_t{1} << 16;
};

// True for a path lgi streams to rather than replaces (see the header): "-", an existing non-regular file, a path
// under /dev/ or /proc/.
bool is_streamed_path(const std::string& path);

// True if two paths name the same existing file (same device and inode).
bool same_file(const std::string& a, const std::string& b);

// The temporary files beside `target` are named this prefix (".NAME.tmp-", with its directory; NAME cut so that
// the whole name fits in NAME_MAX) and six characters.
std::string temporary_prefix(const std::string& target);
// Creates a new file beside `target` named temporary_prefix(target) + "XXXXXX", with the mode a plain
// creat(2) would give it; returns its descriptor (close-on-exec) and sets `temp`, or -1 with errno.
int create_temporary_beside(const std::string& target, std::string& temp);
// fsync(2) of the directory holding `path` (a rename into it is then on disk); errors are ignored.
void sync_directory_of(const std::string& path);

}  // namespace lgi::app
