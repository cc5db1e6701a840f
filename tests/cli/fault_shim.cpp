// tests/cli/fault_shim.cpp — an LD_PRELOAD library for fault injection in the `lgi` process (test_reliability).
//
// It interposes the system calls through which lgi writes files — write, fsync, close, rename, mkostemp, ftruncate —
// and counts them. With LGI_FAULT_KILL_AT=k in the environment, the k-th interposed call raises SIGKILL before it
// runs (a kill at that point of a checkpoint or an output write); with LGI_FAULT_COUNT=FILE the number of calls is
// written to FILE when the process exits. Calls on standard output and standard error are not counted.
#include <dlfcn.h>
#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>

namespace {

std::atomic<long> calls{0};
long kill_at = -1;

struct Setup {
  Setup() {
    if (const char* k = std::getenv("LGI_FAULT_KILL_AT")) kill_at = std::atol(k);
  }
  ~Setup() {
    if (const char* path = std::getenv("LGI_FAULT_COUNT")) {
      if (std::FILE* f = std::fopen(path, "w")) {
        std::fprintf(f, "%ld\n", calls.load());
        std::fclose(f);
      }
    }
  }
} setup;

void count() {
  if (++calls == kill_at) ::raise(SIGKILL);
}

template <class F>
F next(const char* name) {
  return reinterpret_cast<F>(::dlsym(RTLD_NEXT, name));
}

}  // namespace

extern "C" {

ssize_t write(int fd, const void* buf, size_t n) {
  static const auto real = next<ssize_t (*)(int, const void*, size_t)>("write");
  if (fd > 2) count();
  return real(fd, buf, n);
}

int fsync(int fd) {
  static const auto real = next<int (*)(int)>("fsync");
  count();
  return real(fd);
}

int close(int fd) {
  static const auto real = next<int (*)(int)>("close");
  if (fd > 2) count();
  return real(fd);
}

int rename(const char* from, const char* to) {
  static const auto real = next<int (*)(const char*, const char*)>("rename");
  count();
  return real(from, to);
}

int mkostemp(char* name, int flags) {
  static const auto real = next<int (*)(char*, int)>("mkostemp");
  count();
  return real(name, flags);
}

int ftruncate(int fd, off_t length) {
  static const auto real = next<int (*)(int, off_t)>("ftruncate");
  count();
  return real(fd, length);
}

}  // extern "C"
