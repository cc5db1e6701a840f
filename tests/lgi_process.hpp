// tests/lgi_process.hpp — running the `lgi` command from a test: a temporary directory per test, files
// written into it, and `lgi ARGS` run through the shell with stdout and stderr captured. Shared by the
// tests of the command (test_cli, test_cli_fit, test_malformed_scenes, test_checkpoint); LGI_EXE is the
// path of the binary (a compile definition of those targets, tests/CMakeLists.txt).
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace lgi::test {

namespace fs = std::filesystem;

// The bytes of a file ("" if it cannot be read).
inline std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The fields of s between separators (a trailing separator gives no empty last field): CSV cells, lines.
inline std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream in(s);
  while (std::getline(in, cell, sep)) out.push_back(cell);
  return out;
}

// Runs `lgi ARGS` on a pseudo-terminal (script(1), util-linux), stopped by SIGINT after `seconds` when seconds > 0;
// what the terminal showed (progress lines with their carriage returns included) goes to `screen`. Returns the
// exit status (128 + 2 after the SIGINT).
inline int lgi_on_a_terminal(const std::string& args, const fs::path& screen, double seconds = 0) {
  const std::string limit = seconds > 0 ? "timeout --preserve-status -s INT " + std::to_string(seconds) + " " : "";
  const std::string command = "script -qec '" + limit + std::string(LGI_EXE) + " " + args + "' /dev/null > " + screen.string() + " 2>&1";
  return std::system(command.c_str()) >> 8;
}

struct CommandResult {
  int status;  // exit status (-1 if killed by a signal)
  std::string out, err;
};

// A fixture with its own empty directory dir_ (<tmp>/lgi_<prefix>_<pid>_<test>), removed after the test
// unless it failed (so that a failure's files can be read).
class CommandTest : public ::testing::Test {
 protected:
  explicit CommandTest(std::string prefix) : prefix_(std::move(prefix)) {}

  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("lgi_" + prefix_ + "_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }

  fs::path write(const std::string& name, const std::string& bytes) {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
  }

  // `lgi ARGS > stdout 2> stderr` through the shell; the capture files are removed afterwards, so that
  // dir_ holds only what the test and the command wrote.
  CommandResult lgi(const std::string& args) {
    const fs::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
    const std::string cmd = std::string(LGI_EXE) + " " + args + " > " + out.string() + " 2> " + err.string();
    const int raw = std::system(cmd.c_str());
    CommandResult r{WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, slurp(out), slurp(err)};
    fs::remove(out);
    fs::remove(err);
    return r;
  }

  fs::path dir_;

 private:
  std::string prefix_;
};

}  // namespace lgi::test
