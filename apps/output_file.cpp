// lgi/apps/output_file.cpp — OutputFile (output_file.hpp).
#include "output_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstring>
#include <filesystem>

namespace lgi::app {

namespace {

// The longest file name the temporary name may carry: "." + name + ".tmp-XXXXXX" within NAME_MAX bytes, cut at a
// UTF-8 character boundary.
std::string temporary_stem(const std::string& name) {
  constexpr std::size_t room = NAME_MAX - 12;
  if (name.size() <= room) return name;
  std::size_t n = room;
  while (n > 0 && (static_cast<unsigned char>(name[n]) & 0xC0) == 0x80) --n;  // not inside a character
  return name.substr(0, n);
}

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

}  // namespace

std::string temporary_prefix(const std::string& target) {
  const std::filesystem::path p(target);
  const std::string dir = p.has_parent_path() ? p.parent_path().string() + "/" : std::string();
  return dir + "." + temporary_stem(p.filename().string()) + ".tmp-";
}

int create_temporary_beside(const std::string& target, std::string& temp) {
  temp = temporary_prefix(target) + "XXXXXX";
  const int fd = mkostemp(temp.data(), O_CLOEXEC);
  if (fd < 0) return -1;
  const mode_t mask = umask(0);  // mkstemp makes 0600; give the file the mode a plain create would
  umask(mask);
  fchmod(fd, 0666 & ~mask);
  return fd;
}

void sync_directory_of(const std::string& path) {
  const std::filesystem::path p(path);
  const std::string dir = p.has_parent_path() ? p.parent_path().string() : std::string(".");
  const int dfd = open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    fsync(dfd);
    close(dfd);
  }
}

bool is_streamed_path(const std::string& path) {
  if (path == "-") return true;
  if (starts_with(path, "/proc/") || (starts_with(path, "/dev/") && !starts_with(path, "/dev/shm/"))) return true;
  struct stat st {};
  return stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode);
}

bool same_file(const std::string& a, const std::string& b) {
  struct stat sa {}, sb {};
  return stat(a.c_str(), &sa) == 0 && stat(b.c_str(), &sb) == 0 && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

OutputFile::OutputFile(const std::string& path) : path_(path) {
  if (path.empty()) throw OutputError("an empty output file name");
  struct stat st {};
  if (path.back() == '/' || (stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)))
    throw OutputError(path + ": cannot write the output file: it is a directory");
  if (is_streamed_path(path)) {
    streamed_ = true;
    if (path == "-") {
      fd_ = STDOUT_FILENO;
    } else {
      // No O_CREAT: a device or FIFO that is not there is an error, not a regular file made in /dev.
      fd_ = open(path.c_str(), O_WRONLY | O_APPEND | O_NOCTTY | O_CLOEXEC);
      if (fd_ < 0) throw OutputError(path + ": cannot open the output: " + std::strerror(errno));
    }
  } else {
    std::error_code ec;
    target_ = path;
    if (std::filesystem::is_symlink(path, ec)) {  // replace the link's target, keep the link
      const auto resolved = std::filesystem::weakly_canonical(path, ec);
      if (!ec) target_ = resolved.string();
    }
    fd_ = create_temporary_beside(target_, temp_);
    if (fd_ < 0) throw OutputError(path + ": cannot create the output file: " + std::strerror(errno));
  }
  buffer_ = std::make_unique_for_overwrite<char[]>(buffer_size);  // not zeroed: only written bytes are read
}

OutputFile::~OutputFile() {
  if (fd_ >= 0 && fd_ != STDOUT_FILENO) close(fd_);
  if (!streamed_ && !committed_ && !keep_ && !temp_.empty()) unlink(temp_.c_str());
}

std::string OutputFile::error_text() const { return error_ ? std::strerror(error_) : std::string(); }

bool OutputFile::write_all(const char* data, std::size_t n) {
  const std::uint64_t start = in_file_;
  std::size_t done = 0;
  while (done < n) {
    const ssize_t w = ::write(fd_, data + done, n - done);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) {
      error_ = w < 0 ? errno : EIO;
      break;
    }
    done += static_cast<std::size_t>(w);
  }
  in_file_ = start + done;
  if (done == n) {
    last_record_ = in_file_;  // the chunk is whole records
    return true;
  }
  for (std::size_t i = done; i-- > 0;)  // the last record of the chunk that arrived whole
    if (data[i] == '\n') {
      last_record_ = start + i + 1;
      break;
    }
  return false;
}

bool OutputFile::write_record(std::string_view record) {
  if (error_) return false;
  if (used_ + record.size() > buffer_size && !flush()) return false;
  if (record.size() > buffer_size) return write_all(record.data(), record.size());
  std::memcpy(buffer_.get() + used_, record.data(), record.size());
  used_ += record.size();
  return true;
}

bool OutputFile::flush() {
  if (error_) return false;
  if (used_ == 0) return true;
  const std::size_t n = used_;
  used_ = 0;
  return write_all(buffer_.get(), n);
}

bool OutputFile::sync() {
  if (!flush()) return false;
  if (streamed_) return true;
  if (fsync(fd_) != 0) {
    error_ = errno;
    return false;
  }
  return true;
}

bool OutputFile::truncate_to_last_record() {
  used_ = 0;  // what the buffer still holds never reached the file: it is lost with the failed write
  if (streamed_) return in_file_ == last_record_;
  if (in_file_ == last_record_) return true;
  if (ftruncate(fd_, static_cast<off_t>(last_record_)) != 0) return false;
  in_file_ = last_record_;
  return true;
}

bool OutputFile::commit() {
  if (streamed_) return flush();
  const bool write_failed = error_ != 0;
  // After a failed write the file holds what truncate_to_last_record() left: salvage it (a failed fsync then does
  // not keep the rows that did arrive from their name). Otherwise every byte must be on disk before the rename.
  bool ok = write_failed || sync();
  if (!ok && !write_failed) return false;
  if (write_failed) fsync(fd_);
  const int fd = fd_;
  fd_ = -1;
  if (close(fd) != 0 && !write_failed) {
    error_ = errno;
    return false;
  }
  if (std::rename(temp_.c_str(), target_.c_str()) != 0) {
    if (!error_) error_ = errno;
    return false;
  }
  committed_ = true;
  sync_directory_of(target_);
  return true;
}

}  // namespace lgi::app
