// Nothing lost, nothing silently wrong: `lgi` against what people do to files, disks, processes and inputs. One test
// (or more) per defect found by probing the command from outside, each failing on the code before its fix:
//   - outputs and checkpoints never replace or remove what lgi did not write: a --checkpoint path that is a user's
//     file, the output, the scene, a directory or a device; -o /dev/null, /dev/full, a FIFO, stdout (streamed);
//   - a full disk (RLIMIT_FSIZE, and a small tmpfs where it can be mounted) stops the run at the first failed write
//     with the whole rows kept and a checkpoint that resumes to the uninterrupted run's bytes; a kill at every
//     system call of the checkpoint writes (an LD_PRELOAD shim) leaves a checkpoint that resumes to them too;
//   - corrupted checkpoints and sweep parts are refused with one line, exit 1 (test_input_files has the 10⁴
//     random corruptions);
//   - sweeps write rows aligned with their header, the final columns equal to `lgi run`'s, no inf or NaN;
//   - a thread that cannot be started, a checkpoint with an empty target: a message and an exit status;
//   - budgets and SIGTERM are seen within 0.5 s whatever a step costs;
//   - `lgi fit` refuses observation tables missing a declared column and calls a fit that does not explain the
//     data not usable;
//   - one-line errors for the command line, NUL bytes, overflowing inertia; a 250-byte output name; a BOM.
#include "../apps/hashing.hpp"
#include "lgi_process.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <pwd.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <tuple>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;
using lgi::test::slurp;
using lgi::test::split;

namespace {

struct Proc {
  int status;  // exit status, or 128 + signal
  std::string out, err;
  double seconds;       // from the start to the end of the process
  double after_signal;  // from the SIGTERM (when one was sent) to the end
};

bool one_line(const std::string& err) { return !err.empty() && err.find('\n') == err.size() - 1; }

class Reliability : public lgi::test::CommandTest {
 protected:
  Reliability() : CommandTest("rel") {}

  // Runs lgi ARGS in a child: stdout and stderr captured in files, `setup` run in the child before exec (limits,
  // signals, users), `env` added to the environment. `kill_after` > 0: SIGTERM after that many seconds.
  Proc run(const std::vector<std::string>& args, const std::function<void()>& setup = {},
          const std::vector<std::string>& env = {}, double term_after = 0) {
    // stdout to a file, stderr through a pipe (a file-size limit set in `setup` does not cut the message).
    const std::string out = (dir_ / "stdout.txt").string();
    int pipe_fds[2];
    if (::pipe(pipe_fds) != 0) throw std::runtime_error("pipe");
    const auto start = std::chrono::steady_clock::now();
    const pid_t pid = ::fork();
    if (pid == 0) {
      const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0666);
      ::dup2(o, 1);
      ::dup2(pipe_fds[1], 2);
      ::close(pipe_fds[0]);
      ::close(pipe_fds[1]);
      if (setup) setup();
      for (const std::string& v : env) ::putenv(const_cast<char*>(v.c_str()));
      std::vector<std::string> copy = args;
      std::vector<char*> argv;
      std::string exe = LGI_EXE;
      argv.push_back(exe.data());
      for (auto& a : copy) argv.push_back(a.data());
      argv.push_back(nullptr);
      ::execv(LGI_EXE, argv.data());
      ::_exit(127);
    }
    ::close(pipe_fds[1]);
    std::string err;
    std::thread drain([&] {
      char buf[4096];
      for (ssize_t n; (n = ::read(pipe_fds[0], buf, sizeof buf)) != 0;)
        if (n > 0) err.append(buf, static_cast<std::size_t>(n));
        else if (errno != EINTR) break;
      ::close(pipe_fds[0]);
    });
    auto signalled = start;
    if (term_after > 0) {
      std::this_thread::sleep_for(std::chrono::duration<double>(term_after));
      signalled = std::chrono::steady_clock::now();
      ::kill(pid, SIGTERM);
    }
    int raw = 0;
    ::waitpid(pid, &raw, 0);
    const auto end = std::chrono::steady_clock::now();
    drain.join();
    Proc r{WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw), slurp(out), err,
           std::chrono::duration<double>(end - start).count(), std::chrono::duration<double>(end - signalled).count()};
    fs::remove(out);
    return r;
  }

  std::string p(const std::string& name) const { return (dir_ / name).string(); }

  // The seed paper's top (scenes/heavy_top.json) to t_end with rows every `every` steps.
  fs::path top_scene(double t_end, int every, const std::string& name = "top.json", const std::string& method = "lgvi") {
    return write(name, R"({"problem": {"type": "heavy_top", "inertia": [2.0, 2.0, 1.0], "b": 1.0, "k": [0.0, 0.6, 0.8]},
      "initial": {"omega": [0.1, 0.2, 5.0]}, "integrator": {"method": ")" + method + R"(", "dt": 0.001},
      "t_end": )" + std::to_string(t_end) + R"(, "output": {"every": )" + std::to_string(every) + "}}");
  }
};

bool is_char_device(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISCHR(st.st_mode);
}

// Every line ends with '\n' and has the header's number of fields (empty fields included).
void expect_whole_rows(const std::string& csv) {
  ASSERT_FALSE(csv.empty());
  EXPECT_EQ(csv.back(), '\n');
  const auto lines = split(csv, '\n');
  const auto fields = [](const std::string& line) { return std::count(line.begin(), line.end(), ',') + 1; };
  for (std::size_t i = 0; i < lines.size(); ++i)
    ASSERT_EQ(fields(lines[i]), fields(lines.front())) << "line " << i + 1 << ": " << lines[i];
}

// ---- 1. --checkpoint never removes or replaces what is not a checkpoint of this run ---------------------------

TEST_F(Reliability, CheckpointPathHoldingAFileIsRefusedAndKept) {
  const fs::path scene = top_scene(1, 100);
  const fs::path notes = write("notes.txt", "keep\n");
  const Proc r = run({"run", scene.string(), "-o", p("out.csv"), "--checkpoint", notes.string()});
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_TRUE(one_line(r.err)) << r.err;
  EXPECT_NE(r.err.find("not a checkpoint"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(notes), "keep\n");
  EXPECT_FALSE(fs::exists(p("out.csv")));
}

TEST_F(Reliability, CheckpointPathNamingTheOutputTheSceneOrADirectoryIsRefused) {
  const fs::path scene = top_scene(1, 100);
  const std::string scene_bytes = slurp(scene);
  const Proc same = run({"run", scene.string(), "-o", p("out.csv"), "--checkpoint", p("out.csv")});
  EXPECT_EQ(same.status, 1) << same.err;
  EXPECT_NE(same.err.find("the same file"), std::string::npos) << same.err;
  const Proc on_scene = run({"run", scene.string(), "-o", p("out.csv"), "--checkpoint", scene.string()});
  EXPECT_EQ(on_scene.status, 1) << on_scene.err;
  EXPECT_EQ(slurp(scene), scene_bytes);
  fs::create_directory(dir_ / "d");
  const Proc on_dir = run({"run", scene.string(), "-o", p("out.csv"), "--checkpoint", p("d")});
  EXPECT_EQ(on_dir.status, 1) << on_dir.err;
  EXPECT_TRUE(fs::is_directory(dir_ / "d"));
  const Proc on_null = run({"run", scene.string(), "-o", p("out.csv"), "--checkpoint", "/dev/null"});
  EXPECT_EQ(on_null.status, 1) << on_null.err;
  EXPECT_TRUE(is_char_device("/dev/null"));
}

TEST_F(Reliability, CheckpointOfAnotherStoppedRunIsNotOverwritten) {
  const fs::path scene = write("s.json", R"({"problem": {"type": "free_body", "inertia": [1, 2, 3]},
    "initial": {"omega": [1, 0.1, 0.1]}, "integrator": {"method": "lgvi", "dt": 0.01}, "t_end": 50,
    "limits": {"max_steps": 1000}})");
  ASSERT_EQ(run({"run", scene.string(), "-o", p("a.csv"), "--checkpoint", p("ck.json")}).status, 6);
  const std::string ck = slurp(dir_ / "ck.json");
  const Proc again = run({"run", scene.string(), "-o", p("b.csv"), "--checkpoint", p("ck.json")});
  EXPECT_EQ(again.status, 1) << again.err;
  EXPECT_NE(again.err.find("--resume"), std::string::npos) << again.err;
  EXPECT_EQ(slurp(dir_ / "ck.json"), ck);
}

TEST_F(Reliability, CompletedRunRemovesItsCheckpointButNotALookalikeFile) {
  const fs::path scene = top_scene(5, 1000);
  const fs::path lookalike = write(".ck.json.tmp-abcdef", "a user's file\n");
  const Proc r = run({"run", scene.string(), "-o", p("out.csv"), "--checkpoint", p("ck.json"), "--checkpoint-every", "1000"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "ck.json"));
  EXPECT_EQ(slurp(lookalike), "a user's file\n");
}

// ---- 2. outputs that are not regular files are streamed to, never replaced -------------------------------------

TEST_F(Reliability, DevNullStaysADeviceForEveryCommand) {
  const fs::path scene = top_scene(1, 100);
  EXPECT_EQ(run({"run", scene.string(), "-o", "/dev/null"}).status, 0);
  EXPECT_TRUE(is_char_device("/dev/null"));
  const fs::path sweep = write("sw.json", R"({"problem": {"type": "free_body", "inertia": [1, 2, 3]},
    "initial": {"omega": [1, 0.1, 0.1]}, "integrator": {"method": "rkmk4", "dt": 0.01}, "t_end": 1,
    "sweep": {"grid": {"/initial/omega/0": [1, 2]}}})");
  EXPECT_EQ(run({"sweep", sweep.string(), "-o", "/dev/null", "-q"}).status, 0);
  EXPECT_TRUE(is_char_device("/dev/null"));
  ASSERT_EQ(run({"sweep", sweep.string(), "-o", p("part0.csv"), "--shard", "0/1", "-q"}).status, 0);
  EXPECT_EQ(run({"merge", p("part0.csv"), "-o", "/dev/null", "-q"}).status, 0);
  EXPECT_TRUE(is_char_device("/dev/null"));
  EXPECT_TRUE(is_char_device("/dev/full"));
  const Proc full = run({"run", scene.string(), "-o", "/dev/full"});
  EXPECT_EQ(full.status, 3) << full.err;
  EXPECT_NE(full.err.find("No space left on device"), std::string::npos) << full.err;
  EXPECT_TRUE(one_line(full.err)) << full.err;
  EXPECT_TRUE(is_char_device("/dev/full"));
}

TEST_F(Reliability, FifoAndStdoutAreStreamed) {
  const fs::path scene = top_scene(1, 100);
  const Proc expected = run({"run", scene.string(), "-q"});  // stdout
  ASSERT_EQ(expected.status, 0);
  const Proc dash = run({"run", scene.string(), "-q", "-o", "-"});
  EXPECT_EQ(dash.out, expected.out);
  const Proc dev_stdout = run({"run", scene.string(), "-q", "-o", "/dev/stdout"});
  EXPECT_EQ(dev_stdout.status, 0) << dev_stdout.err;
  EXPECT_EQ(dev_stdout.out, expected.out);
  const std::string fifo = p("pipe");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  // The reader: open without blocking, read until the writer closes (or 30 s pass, if lgi never opens it).
  std::string received;
  std::thread reader([&] {
    const int fd = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    char buf[4096];
    while (fd >= 0 && std::chrono::steady_clock::now() < deadline) {
      const ssize_t n = ::read(fd, buf, sizeof buf);
      if (n > 0) received.append(buf, static_cast<std::size_t>(n));
      else if (n == 0 && !received.empty()) break;  // the writer closed
      else std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    if (fd >= 0) ::close(fd);
  });
  const Proc r = run({"run", scene.string(), "-q", "-o", fifo});
  reader.join();
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(received, expected.out);
  struct stat st {};
  ASSERT_EQ(::stat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));
}

TEST_F(Reliability, OutputNamingTheInputIsRefused) {
  const fs::path scene = top_scene(1, 100);
  const std::string bytes = slurp(scene);
  const Proc r = run({"run", scene.string(), "-o", scene.string()});
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_EQ(slurp(scene), bytes);
}

TEST_F(Reliability, LongOutputNameFits) {
  const fs::path scene = top_scene(1, 100);
  const std::string name = std::string(246, 'x') + ".csv";  // 250 bytes, the longest a name may be is 255
  const Proc r = run({"run", scene.string(), "-q", "-o", p(name)});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir_ / name));
}

// ---- 3. a full disk: whole rows kept, a checkpoint that resumes to the same bytes ------------------------------

TEST_F(Reliability, FullDiskKeepsWholeRowsAndAResumableCheckpoint) {
  const fs::path scene = top_scene(20, 1);
  const Proc full = run({"run", scene.string(), "-o", p("ref.csv"), "-q"});
  ASSERT_EQ(full.status, 0) << full.err;
  const std::string reference = slurp(dir_ / "ref.csv");
  ASSERT_GT(reference.size(), std::size_t{4} << 20);
  // The run (a row every step, a checkpoint every 1024 steps) with its files limited to `limit` bytes
  // (RLIMIT_FSIZE: a write past it fails with EFBIG), then resumed without the limit. The limits fall in the header,
  // inside the first buffer, on a buffer's edge plus one byte, and later.
  for (const rlim_t limit : {rlim_t{100}, rlim_t{70000}, rlim_t{65536 * 5 + 1}, rlim_t{1} << 20, rlim_t{3} << 20}) {
    SCOPED_TRACE("file size limit " + std::to_string(limit));
    fs::remove(dir_ / "out.csv");
    fs::remove(dir_ / "ck.json");
    const Proc r = run({"run", scene.string(), "-o", p("out.csv"), "--checkpoint", p("ck.json"), "--checkpoint-every",
                       "1024", "-q"},
                      [limit] {
                        ::signal(SIGXFSZ, SIG_IGN);
                        const rlimit l{limit, limit};
                        ::setrlimit(RLIMIT_FSIZE, &l);
                      });
    EXPECT_EQ(r.status, 3) << r.err;
    EXPECT_TRUE(one_line(r.err)) << r.err;
    EXPECT_NE(r.err.find("File too large"), std::string::npos) << r.err;
    ASSERT_TRUE(fs::exists(dir_ / "out.csv")) << r.err;
    const std::string kept = slurp(dir_ / "out.csv");
    if (limit > 100) expect_whole_rows(kept);
    EXPECT_LE(kept.size(), limit);
    EXPECT_EQ(reference.compare(0, kept.size(), kept), 0) << "the kept rows are the uninterrupted run's";
    if (!fs::exists(dir_ / "ck.json")) continue;  // the disk filled before the first checkpoint: nothing to resume
    const Proc resumed = run({"run", "--resume", p("ck.json"), "-q"});
    EXPECT_EQ(resumed.status, 0) << resumed.err;
    EXPECT_TRUE(slurp(dir_ / "out.csv") == reference) << "the resumed run's bytes differ from the uninterrupted run's";
    EXPECT_FALSE(fs::exists(dir_ / "ck.json"));
  }
}

// A real full file system where one can be mounted (root): the checkpoints compete for the space too. Once the
// file system is enlarged (space freed), the checkpoint resumes in place to the uninterrupted run's bytes.
TEST_F(Reliability, FullTmpfsKeepsWholeRowsAndAResumableCheckpoint) {
  const fs::path mnt = dir_ / "small";
  fs::create_directory(mnt);
  if (::mount("tmpfs", mnt.c_str(), "tmpfs", 0, "size=1m") != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here (" << std::strerror(errno) << "): the RLIMIT_FSIZE test covers the rows";
  struct Unmount {
    std::string path;
    ~Unmount() { ::umount(path.c_str()); }
  } unmount{mnt.string()};
  const fs::path scene = top_scene(20, 1);
  const Proc full = run({"run", scene.string(), "-o", p("ref.csv"), "-q"});
  ASSERT_EQ(full.status, 0) << full.err;
  const std::string reference = slurp(dir_ / "ref.csv");
  const std::string out = (mnt / "out.csv").string(), ck = (mnt / "ck.json").string();
  const Proc r = run({"run", scene.string(), "-o", out, "--checkpoint", ck, "--checkpoint-every", "1024", "-q"});
  EXPECT_EQ(r.status, 3) << r.err;
  EXPECT_TRUE(one_line(r.err)) << r.err;
  EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
  const std::string kept = slurp(out);
  expect_whole_rows(kept);
  EXPECT_EQ(reference.compare(0, kept.size(), kept), 0);
  ASSERT_TRUE(fs::exists(ck)) << r.err;
  ASSERT_EQ(::mount("tmpfs", mnt.c_str(), "tmpfs", MS_REMOUNT, "size=64m"), 0) << std::strerror(errno);
  const Proc resumed = run({"run", "--resume", ck, "-q"});
  EXPECT_EQ(resumed.status, 0) << resumed.err;
  EXPECT_TRUE(slurp(out) == reference) << "the resumed run's bytes differ from the uninterrupted run's";
  for (const auto& e : fs::directory_iterator(mnt)) EXPECT_EQ(e.path().filename(), "out.csv") << e.path();
}

// ---- SIGKILL at every system call of a checkpointed run's writes ------------------------------------------------

TEST_F(Reliability, KillAtEverySystemCallOfTheCheckpointWritesResumesToTheSameBytes) {
#ifndef LGI_FAULT_SHIM
  GTEST_SKIP() << "the fault-injection shim (tests/cli/fault_shim.cpp) was not built";
#else
  const fs::path scene = top_scene(6, 250);
  ASSERT_EQ(run({"run", scene.string(), "-o", p("ref.csv"), "-q"}).status, 0);
  const std::string reference = slurp(dir_ / "ref.csv");
  // How many interposed calls a whole run makes.
  const Proc counted = run({"run", scene.string(), "-o", p("out.csv"), "--checkpoint", p("ck.json"), "--checkpoint-every",
                           "1024", "-q"},
                          {}, {"LD_PRELOAD=" LGI_FAULT_SHIM, "LGI_FAULT_COUNT=" + p("count.txt")});
  ASSERT_EQ(counted.status, 0) << counted.err;
  const int calls = std::stoi(slurp(dir_ / "count.txt"));
  ASSERT_GT(calls, 20);
  int resumed_runs = 0;
  for (int k = 1; k <= calls; ++k) {
    SCOPED_TRACE("killed at interposed call " + std::to_string(k) + " of " + std::to_string(calls));
    for (const auto& e : fs::directory_iterator(dir_))
      if (e.path().filename() != "top.json" && e.path().filename() != "ref.csv") fs::remove(e.path());
    const Proc killed = run({"run", scene.string(), "-o", p("out.csv"), "--checkpoint", p("ck.json"), "--checkpoint-every",
                            "1024", "-q"},
                           {}, {"LD_PRELOAD=" LGI_FAULT_SHIM, "LGI_FAULT_KILL_AT=" + std::to_string(k)});
    if (killed.status == 0) {  // this run made fewer calls (the monitor's stride follows the clock): it completed
      EXPECT_TRUE(slurp(dir_ / "out.csv") == reference);
      continue;
    }
    ASSERT_EQ(killed.status, 128 + SIGKILL) << killed.err;
    if (!fs::exists(dir_ / "ck.json")) continue;  // killed before the first checkpoint: a fresh run is the remedy
    const Proc resumed = run({"run", "--resume", p("ck.json"), "-q"});
    ASSERT_EQ(resumed.status, 0) << resumed.err;
    EXPECT_TRUE(slurp(dir_ / "out.csv") == reference);
    ++resumed_runs;
    for (const auto& e : fs::directory_iterator(dir_))  // nothing left behind but the files of the test
      EXPECT_TRUE(e.path().filename() == "top.json" || e.path().filename() == "ref.csv" ||
                  e.path().filename() == "out.csv")
          << e.path();
  }
  EXPECT_GT(resumed_runs, calls / 2);
#endif
}

// ---- 4 and 6. sweeps: rows aligned with the header, no inf or NaN ------------------------------------------------

TEST_F(Reliability, EulerAngleSweepRowsMatchTheHeaderAndLgiRun) {
  const fs::path sweep = write("sw.json", R"({"problem": {"type": "lagrange_top_euler_angles", "I2": 2.0, "I3": 1.0,
    "b": 1.0, "k2": 0.0, "k3": 1.0}, "initial": {"euler_angles": [0.0, 0.3, 0.0], "euler_rates": [0.0, 0.0, 4.0]},
    "integrator": {"method": "rkmk4", "dt": 0.01}, "t_end": 1.0,
    "sweep": {"grid": {"/initial/euler_rates/2": [3, 4]}}})");
  const Proc r = run({"sweep", sweep.string(), "-o", p("s.csv"), "-q"});
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string csv = slurp(dir_ / "s.csv");
  expect_whole_rows(csv);
  const auto lines = split(csv, '\n');
  const auto header = split(lines[0], ',');
  EXPECT_EQ(std::count(header.begin(), header.end(), "phi_rel_change"), 0) << lines[0];
  EXPECT_EQ(std::count(header.begin(), header.end(), "momentum_psi_rel_change"), 1) << lines[0];
  // Member 1 (rate 4) is the scene itself: its final columns are lgi run's last row.
  const fs::path scene = write("m1.json", R"({"problem": {"type": "lagrange_top_euler_angles", "I2": 2.0, "I3": 1.0,
    "b": 1.0, "k2": 0.0, "k3": 1.0}, "initial": {"euler_angles": [0.0, 0.3, 0.0], "euler_rates": [0.0, 0.0, 4]},
    "integrator": {"method": "rkmk4", "dt": 0.01}, "t_end": 1.0})");
  const Proc single = run({"run", scene.string(), "-q"});
  ASSERT_EQ(single.status, 0) << single.err;
  const auto rows = split(single.out, '\n');
  const std::string last = rows.back();
  EXPECT_NE(lines[2].find("," + last + ","), std::string::npos) << lines[2] << "\n" << last;
}

TEST_F(Reliability, SweepRowsHoldNoInfinityOrNaN) {
  const fs::path sweep = write("sw.json", R"({"problem": {"type": "heavy_top", "inertia": [2, 2, 1], "b": 1},
    "initial": {"omega": [0.1, 0.2, 5]}, "integrator": {"method": "lgvi", "dt": 0.01}, "t_end": 0.1,
    "sweep": {"grid": {"/initial/omega/0": [1e308, 1e200, 1e154, 1]}}})");
  for (const char* batch : {"", "--no-batch"}) {
    std::vector<std::string> args{"sweep", sweep.string(), "-o", p("s.csv"), "-q"};
    if (*batch) args.emplace_back(batch);
    const Proc r = run(args);
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string csv = slurp(dir_ / "s.csv");
    expect_whole_rows(csv);
    EXPECT_EQ(csv.find("inf"), std::string::npos) << csv;
    EXPECT_EQ(csv.find("nan"), std::string::npos) << csv;
    const auto lines = split(csv, '\n');
    ASSERT_EQ(lines.size(), 5u);
    for (int m = 0; m < 3; ++m)  // the step fails (non_finite) or the energy overflows (not_finite)
      EXPECT_TRUE(lines[m + 1].find(",non_finite,") != std::string::npos ||
                  lines[m + 1].find(",not_finite,") != std::string::npos)
          << lines[m + 1];
    EXPECT_NE(lines[4].find(",completed,"), std::string::npos) << lines[4];
  }
}

// ---- 5 and 7b. checkpoints are self-verifying --------------------------------------------------------------------

class ReliabilityCheckpoint : public Reliability {
 protected:
  // A run stopped by its step budget with a checkpoint: the free body of the probe (lgvi, dt 0.01, t_end 100,
  // a row every 1000 steps, limits.max_steps 5000).
  void SetUp() override {
    Reliability::SetUp();
    scene_ = write("s.json", R"({"problem": {"type": "free_body", "inertia": [1, 2, 3]},
      "initial": {"omega": [1, 0.1, 0.1]}, "integrator": {"method": "lgvi", "dt": 0.01}, "t_end": 100,
      "output": {"every": 1000}, "limits": {"max_steps": 5000}})");
    ASSERT_EQ(run({"run", scene_.string(), "-o", p("out.csv"), "--checkpoint", p("ck.json"), "-q"}).status, 6);
    ck_ = slurp(dir_ / "ck.json");
  }
  fs::path scene_;
  std::string ck_;
};

TEST_F(ReliabilityCheckpoint, ChangedFieldsAreRefused) {
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {"\"event\": 5", "\"event\": 1000000"}, {"\"n\": 5000", "\"n\": 2000"}, {"\"target\": \"", "\"target\": \"x"}}) {
    SCOPED_TRACE(from + " -> " + to);
    std::string changed = ck_;
    const auto at = changed.find(from);
    ASSERT_NE(at, std::string::npos) << ck_;
    changed.replace(at, from.size(), to);
    write("bad.json", changed);
    const Proc r = run({"run", "--resume", p("bad.json"), "-o", p("other.csv"), "-q"});
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_TRUE(one_line(r.err)) << r.err;
    EXPECT_NE(r.err.find("checksum"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "other.csv"));
  }
}

// A changed checkpoint whose checksum was recomputed (a forgery, or a bug in a writer): the values are still checked
// against the scene, and an empty target name is an error, not a crash.
TEST_F(ReliabilityCheckpoint, ResignedChangesAreCheckedAgainstTheScene) {
  // The checkpoint's own layout (apps/checkpoint.cpp): the document without its checksum, then the checksum line
  // with the FNV-1a hash of every byte before the key.
  const auto resign = [](nlohmann::ordered_json j) {
    j.erase("checksum");
    std::string text = j.dump(1);
    text.resize(text.size() - 2);
    text += ",\n";
    return text + " \"checksum\": \"fnv1a64:" + lgi::app::hex64(lgi::app::fnv1a(text)) + "\"\n}\n";
  };
  const nlohmann::ordered_json good = nlohmann::ordered_json::parse(ck_);
  ASSERT_EQ(resign(good), ck_) << "the test's checksum is the checkpoint's";
  const std::vector<std::pair<std::string, std::function<void(nlohmann::ordered_json&)>>> edits{
      {"/cursor/event", [](nlohmann::ordered_json& j) { j["cursor"]["event"] = 1000000; }},
      {"/cursor: grid index", [](nlohmann::ordered_json& j) { j["cursor"]["n"] = j["cursor"]["steps"] = 20000; }},
      {"/output/target", [](nlohmann::ordered_json& j) { j["output"]["target"] = ""; }},
      {"/internal", [](nlohmann::ordered_json& j) { j["internal"].erase(0); }},
  };
  for (const auto& [where, edit] : edits) {
    SCOPED_TRACE(where);
    nlohmann::ordered_json j = good;
    edit(j);
    write("bad.json", resign(j));
    const Proc r = run({"run", "--resume", p("bad.json"), "-o", p("other.csv"), "-q"});
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_TRUE(one_line(r.err)) << r.err;
    EXPECT_NE(r.err.find(where), std::string::npos) << r.err;
  }
}

TEST_F(Reliability, EditedSweepPartsAreRefused) {
  const fs::path sweep = write("sw.json", R"({"problem": {"type": "free_body", "inertia": [1, 2, 3]},
    "initial": {"omega": [1, 0.1, 0.1]}, "integrator": {"method": "rkmk4", "dt": 0.01}, "t_end": 1,
    "sweep": {"grid": {"/initial/omega/0": [1, 2, 3, 4]}}})");
  ASSERT_EQ(run({"sweep", sweep.string(), "-o", p("a.csv"), "--shard", "0/2", "-q"}).status, 0);
  ASSERT_EQ(run({"sweep", sweep.string(), "-o", p("b.csv"), "--shard", "1/2", "-q"}).status, 0);
  ASSERT_EQ(run({"merge", p("a.csv"), p("b.csv"), "-o", p("m.csv"), "-q"}).status, 0);
  const std::string part = slurp(dir_ / "b.csv");
  const auto lines = split(part, '\n');
  const std::vector<std::pair<std::string, std::string>> edits{
      {"a value", std::regex_replace(part, std::regex(",completed,"), ",completed,9", std::regex_constants::format_first_only)},
      {"a status", std::regex_replace(part, std::regex(",completed,"), ",non_finite,", std::regex_constants::format_first_only)},
      {"nan", std::regex_replace(part, std::regex(",completed,([0-9]+),[^,]+,"), ",completed,$1,nan,",
                                 std::regex_constants::format_first_only)},
      {"an extra column", std::regex_replace(part, std::regex("\n1,"), "\n1,0,", std::regex_constants::format_first_only)},
      {"cut short", part.substr(0, part.size() - 60)},
  };
  for (const auto& [what, bytes] : edits) {
    SCOPED_TRACE(what);
    ASSERT_NE(bytes, part);
    write("b.csv", bytes);
    const Proc r = run({"merge", p("a.csv"), p("b.csv"), "-o", p("m2.csv"), "-q"});
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_TRUE(one_line(r.err)) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "m2.csv"));
  }
}

// ---- 7a. resources: a thread that cannot be started --------------------------------------------------------------

TEST_F(Reliability, SweepGoesOnWhenThreadsCannotBeStarted) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root, to run the sweep as another user under a process limit";
  const passwd* nobody = ::getpwnam("nobody");
  if (!nobody) GTEST_SKIP() << "no user 'nobody'";
  fs::permissions(dir_, fs::perms::all);
  const fs::path sweep = write("sw.json", R"({"problem": {"type": "free_body", "inertia": [1, 2, 3]},
    "initial": {"omega": [1, 0.1, 0.1]}, "integrator": {"method": "rkmk4", "dt": 0.01}, "t_end": 2,
    "sweep": {"random": {"seed": 3, "count": 64, "ranges": {"/initial/omega/0": [0.5, 2]}}}})");
  ASSERT_EQ(run({"sweep", sweep.string(), "-o", p("one.csv"), "-q"}).status, 0);
  const uid_t uid = nobody->pw_uid;
  const gid_t gid = nobody->pw_gid;
  // The limit counts every process and thread of the user: those 'nobody' has now, plus the sweep's process — so
  // that no thread at all can be started (deterministic: threads that end early would free their slots).
  rlim_t processes = 1;
  for (const auto& e : fs::directory_iterator("/proc")) {
    std::ifstream status(e.path() / "status");
    for (std::string line; std::getline(status, line);)
      if (line.rfind("Uid:", 0) == 0) {
        std::istringstream in(line.substr(4));
        unsigned real = 0;
        if (in >> real && real == uid) ++processes;
        break;
      }
  }
  const Proc r = run({"sweep", sweep.string(), "-o", p("many.csv"), "--threads", "200", "-q"}, [uid, gid, processes] {
    const rlimit l{processes, processes};
    ::setrlimit(RLIMIT_NPROC, &l);
    if (::setgid(gid) != 0 || ::setuid(uid) != 0) ::_exit(126);
  });
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("could not start thread"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(dir_ / "many.csv"), slurp(dir_ / "one.csv"));
  for (const auto& e : fs::directory_iterator(dir_))
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
}

// ---- 8. budgets and SIGTERM within 0.5 s whatever a step costs -------------------------------------------------

TEST_F(Reliability, BudgetAndSignalAreSeenWithinHalfASecondOfSlowSteps) {
  // h|Ω| = 8e5: every split_dmv step takes a million DMV substeps (about 0.2 s).
  const std::string body = R"({"problem":{"type":"free_body","inertia":[1,2,3]}, "initial":{"omega":[0,8e7,0]},
    "integrator":{"method":"split_dmv","dt":0.01},"t_end":100)";
  const fs::path budget = write("budget.json", body + R"(, "limits":{"max_wall_seconds":1}})");
  const Proc b = run({"run", budget.string(), "-o", p("b.csv"), "-q"});
  EXPECT_EQ(b.status, 6) << b.err;
  EXPECT_LE(b.seconds, 1.5) << b.err;
  const fs::path plain = write("plain.json", body + "}");
  const Proc t = run({"run", plain.string(), "-o", p("t.csv"), "-q"}, {}, {}, 0.5);
  EXPECT_EQ(t.status, 128 + SIGTERM) << t.err;
  EXPECT_LE(t.after_signal, 0.5) << t.err;
  expect_whole_rows(slurp(dir_ / "t.csv"));
}

// A sweep of such members, two threads: SIGTERM stops it within 0.5 s, nothing written.
TEST_F(Reliability, SweepStopsWithinHalfASecondOfSigterm) {
  const fs::path sweep = write("slow.json", R"({"problem":{"type":"free_body","inertia":[1,2,3]},
    "initial":{"omega":[0,8e7,0]}, "integrator":{"method":"split_dmv","dt":0.01}, "t_end":100,
    "sweep": {"grid": {"/initial/omega/0": [0, 1, 2, 3]}}})");
  const Proc r = run({"sweep", sweep.string(), "-o", p("s.csv"), "--threads", "2", "-q"}, {}, {}, 0.5);
  EXPECT_EQ(r.status, 128 + SIGTERM) << r.err;
  EXPECT_LE(r.after_signal, 0.5) << r.err;
  EXPECT_TRUE(one_line(r.err)) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "s.csv"));
}

// ---- 9. lgi fit: declared observation types are complete, and "usable" means the data are explained -------------

class ReliabilityFit : public Reliability {
 protected:
  void SetUp() override {
    Reliability::SetUp();
#ifndef LGI_HAVE_FIT_COMMAND
    GTEST_SKIP() << "lgi was built without lgi fit";
#endif
    const std::string examples = LGI_EXAMPLES_DIR;
    fs::copy_file(examples + "/fit/truth.json", dir_ / "truth.json");
    ASSERT_EQ(run({"run", p("truth.json"), "-q", "-o", p("obs.csv")}).status, 0);
    fit_ = nlohmann::json::parse(slurp(fs::path(examples) / "fit/fit.json"));
  }
  // The example fit with `edit` applied, written to fit.json.
  fs::path fit_file(const std::function<void(nlohmann::json&)>& edit = {}) {
    nlohmann::json j = fit_;
    if (edit) edit(j);
    return write("fit.json", j.dump(1));
  }
  // obs.csv with its header edited.
  void edit_header(const std::function<std::string(std::string)>& f) {
    std::string csv = slurp(dir_ / "obs.csv");
    const auto nl = csv.find('\n');
    write("obs.csv", f(csv.substr(0, nl)) + csv.substr(nl));
  }
  nlohmann::json fit_;
};

TEST_F(ReliabilityFit, MissingOrDuplicatedObservationColumnsAreErrors) {
  const std::string original = slurp(dir_ / "obs.csv");
  const std::vector<std::tuple<std::string, std::function<std::string(std::string)>, std::string>> cases{
      {"R33 deleted",
       [](std::string h) { return std::regex_replace(h, std::regex(",R33"), ",X33"); }, "R33"},
      {"R11 renamed R12", [](std::string h) { return std::regex_replace(h, std::regex("R11"), "R12"); }, "R12"},
      {"t twice", [](std::string h) { return std::regex_replace(h, std::regex(",energy"), ",t"); }, "'t'"},
  };
  for (const auto& [what, edit, named] : cases) {
    SCOPED_TRACE(what);
    write("obs.csv", original);
    edit_header(edit);
    const Proc r = run({"fit", fit_file().string(), "-o", p("result.json"), "-q"});
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_TRUE(one_line(r.err)) << r.err;
    EXPECT_NE(r.err.find(named), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "result.json"));
  }
}

TEST_F(ReliabilityFit, AFitThatDoesNotExplainTheDataIsNotUsable) {
  // Gyros only, no continuation: Ceres converges to a local minimum far from the truth.
  const fs::path fit = fit_file([](nlohmann::json& j) {
    j["fit"].erase("continuation");
    j["fit"]["observations"].erase("sigma_attitude");
  });
  const Proc r = run({"fit", fit.string(), "-o", p("result.json"), "-q"});
  EXPECT_EQ(r.status, 5) << r.err;
  EXPECT_NE(r.err.find("does not explain the data"), std::string::npos) << r.err;
  const nlohmann::json result = nlohmann::json::parse(slurp(dir_ / "result.json"));
  EXPECT_FALSE(result["usable"].get<bool>());
  EXPECT_LT(result["p_value"].get<double>(), 1e-3);
  // With the continuation the same data are explained.
  const Proc good = run({"fit", fit_file().string(), "-o", p("good.json"), "-q"});
  EXPECT_EQ(good.status, 0) << good.err;
}

// A file name with a NUL byte (a JSON "\u0000") in an error message: escaped, the message not cut there.
TEST_F(ReliabilityFit, NulBytesInAMessageDoNotCutIt) {
  const fs::path fit = fit_file([](nlohmann::json& j) { j["fit"]["observations"]["csv"] = std::string("ob\0s_and_more.csv", 17); });
  const Proc r = run({"fit", fit.string(), "-o", p("result.json"), "-q"});
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_TRUE(one_line(r.err)) << r.err;
  EXPECT_NE(r.err.find("ob\\u0000s_and_more.csv"), std::string::npos) << r.err;
}

// A fit's wall-clock budget (limits.max_wall_seconds) holds within 0.5 s: the example fit at dt = 1e-5 (10^6 steps an
// arc, with Jets for every Jacobian) takes 3.1 s unbudgeted.
TEST_F(ReliabilityFit, WallClockBudgetStopsAFitWithinHalfASecond) {
  nlohmann::json truth = nlohmann::json::parse(slurp(dir_ / "truth.json"));
  truth["integrator"]["dt"] = 1e-5;
  truth["output"]["every"] = 20000;
  write("truth.json", truth.dump());
  ASSERT_EQ(run({"run", p("truth.json"), "-q", "-o", p("obs.csv")}).status, 0);
  const fs::path fit = fit_file([](nlohmann::json& j) {
    j["integrator"]["dt"] = 1e-5;
    j["limits"] = {{"max_wall_seconds", 0.3}};
  });
  const Proc r = run({"fit", fit.string(), "-o", p("result.json"), "-q"});
  EXPECT_EQ(r.status, 6) << r.err;
  EXPECT_TRUE(one_line(r.err)) << r.err;
  EXPECT_NE(r.err.find("stopped by /limits/max_wall_seconds = 0.3"), std::string::npos) << r.err;
  EXPECT_LE(r.seconds, 0.3 + 0.5);
  const nlohmann::json result = nlohmann::json::parse(slurp(dir_ / "result.json"));
  EXPECT_FALSE(result["usable"].get<bool>());
}

// A rank-deficient fit (a free body's three moments: only their ratios are observable) says so in one line, without
// Ceres' log lines on stderr.
TEST_F(ReliabilityFit, RankDeficientFitSaysSoInOneLine) {
  write("truth.json", R"({"problem": {"type": "free_body", "inertia": [1, 2, 3]}, "initial": {"omega": [1, 0.2, 0.3]},
    "integrator": {"method": "lgvi", "dt": 0.01}, "t_end": 5, "output": {"every": 20}})");
  ASSERT_EQ(run({"run", p("truth.json"), "-q", "-o", p("obs.csv")}).status, 0);
  const fs::path fit = write("fit.json", R"({"problem": {"type": "free_body", "inertia": [1.1, 2, 3]},
    "initial": {"omega": [1, 0.2, 0.3]}, "integrator": {"method": "lgvi", "dt": 0.01}, "t_end": 5,
    "fit": {"unknowns": ["initial.omega", "problem.inertia"],
            "observations": {"csv": "obs.csv", "sigma_attitude": 1e-3, "sigma_omega": 1e-2}}})");
  const Proc r = run({"fit", fit.string(), "-o", p("result.json"), "-q"});
  EXPECT_EQ(r.status, 5) << r.err;
  EXPECT_TRUE(one_line(r.err)) << r.err;
  EXPECT_NE(r.err.find("rank deficient"), std::string::npos) << r.err;
}

TEST_F(ReliabilityFit, ObservationTableWithAByteOrderMarkIsRead) {
  write("obs.csv", "\xEF\xBB\xBF" + slurp(dir_ / "obs.csv"));
  const Proc r = run({"fit", fit_file().string(), "-o", p("result.json"), "-q"});
  EXPECT_EQ(r.status, 0) << r.err;
}

// ---- minor: messages ----------------------------------------------------------------------------------------------

TEST_F(Reliability, CommandLineErrorsAreOneLine) {
  for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
           {"bogus"}, {}, {"run", "--bogus", "x"}, {"sweep"}, {"run", "a.json", "b.json"}}) {
    const Proc r = run(args);
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_TRUE(one_line(r.err)) << r.err;
    EXPECT_EQ(r.err.rfind("lgi: error: ", 0), 0u) << r.err;
  }
  EXPECT_NE(run({"bogus"}).err.find("unknown command \"bogus\" (commands:"), std::string::npos);
  EXPECT_NE(run({"swep"}).err.find("unknown command \"swep\"; did you mean \"sweep\"?"), std::string::npos);
}

TEST_F(Reliability, NulBytesInInputDoNotCutTheMessage) {
  const fs::path scene = write("nul.json", R"({"problem": {"type": "free_body", "inertia": [1, 2, 3]},
    "initial": {"omega": [1, 0, 0]}, "integrator": {"method": "lg\u0000vi_and_more", "dt": 0.01}, "t_end": 1})");
  const Proc r = run({"run", scene.string()});
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_TRUE(one_line(r.err)) << r.err;
  EXPECT_NE(r.err.find("vi_and_more"), std::string::npos) << r.err;
}

TEST_F(Reliability, OverflowingInertiaIsNamedNotNaN) {
  const fs::path scene = write("big.json", R"({"problem": {"type": "free_body", "inertia": [1e308, 1e308, 1e308]},
    "initial": {"omega": [1, 0, 0]}, "integrator": {"method": "rkmk4", "dt": 0.01}, "t_end": 1})");
  const Proc r = run({"run", scene.string()});
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_TRUE(one_line(r.err)) << r.err;
  EXPECT_EQ(r.err.find("nan"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("/problem/inertia"), std::string::npos) << r.err;
}

}  // namespace
