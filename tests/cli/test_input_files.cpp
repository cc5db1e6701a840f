// The files lgi reads back — checkpoints and sweep parts — are self-verifying: among 10⁴ random corruptions of each
// (single-byte changes, truncations, edited fields) none is accepted, and each is refused with one line naming the
// file. In process, through the same readers `lgi run --resume` and `lgi merge` use (apps/checkpoint.cpp
// read_checkpoint, apps/sweep_command.cpp merge_command).
#include "runner_checkpoint.hpp"
#include "sweep_command.hpp"

#include "lgi_process.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using lgi::test::slurp;

namespace {

class InputFiles : public lgi::test::CommandTest {
 protected:
  InputFiles() : CommandTest("inputs") {}
};

// A corruption of `bytes`: kind 0 changes one byte, 1 cuts the file, 2 changes a digit, letter or quote character
// into another of its kind (an edited field that still looks like one).
std::string corrupt(const std::string& bytes, std::mt19937_64& rng, int kind) {
  std::string b = bytes;
  std::uniform_int_distribution<std::size_t> at(0, b.size() - 1);
  if (kind == 0) {
    const std::size_t i = at(rng);
    b[i] = static_cast<char>(b[i] ^ static_cast<char>(1 + rng() % 255));
  } else if (kind == 1) {
    b.resize(at(rng));
  } else {
    std::size_t i = at(rng);
    while (!std::isalnum(static_cast<unsigned char>(b[i]))) i = (i + 1) % b.size();
    const char c = b[i];
    const std::string pool = std::isdigit(static_cast<unsigned char>(c)) ? "0123456789"
                             : std::islower(static_cast<unsigned char>(c)) ? "abcdefghijklmnopqrstuvwxyz"
                                                                           : "ABCDEFGHIJKLMNOPQRSTUVWXYZ";
    char d = c;
    while (d == c) d = pool[rng() % pool.size()];
    b[i] = d;
  }
  return b;
}

bool one_line(const std::string& s) { return !s.empty() && s.find('\n') == std::string::npos; }

TEST_F(InputFiles, NoCorruptedCheckpointIsAccepted) {
  lgi::app::Checkpoint ck;
  ck.scene_file = "scene.json";
  ck.scene = lgi::app::json::parse(R"({"problem": {"type": "free_body", "inertia": [1, 2, 3]},
    "initial": {"omega": [1, 0.1, 0.1]}, "integrator": {"method": "lgvi", "dt": 0.01}, "t_end": 100})");
  ck.method = "lgvi";
  ck.cursor.steps = ck.cursor.n = 5000;
  ck.cursor.event = 5;
  for (int i = 0; i < 15; ++i) ck.internal.push_back(0.1 * i - 0.3);
  ck.output = {"out.csv", ".out.csv.tmp-abcdef", 1234, 0x0123456789abcdefull, 0xfedcba9876543210ull};
  ck.has_last_row = true;
  ck.last_row_t = 50;
  ck.every_seconds = 60;
  ck.t = 50;
  ck.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  ck.omega = {1, 0.1, 0.1};
  const std::string path = (dir_ / "ck.json").string();
  std::string error;
  ASSERT_TRUE(lgi::app::write_checkpoint(path, ck, "0.1.0", error)) << error;
  const std::string good = slurp(path);
  ASSERT_NO_THROW(lgi::app::read_checkpoint(path));

  std::mt19937_64 rng(20261126);
  int accepted = 0, refused = 0;
  for (int n = 0; n < 12000; ++n) {
    const std::string bad = corrupt(good, rng, n % 3);
    if (bad == good) continue;
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bad;
    try {
      lgi::app::read_checkpoint(path);
      ++accepted;
      ADD_FAILURE() << "accepted corruption " << n << " (kind " << n % 3 << ")";
    } catch (const lgi::app::InputError& e) {
      ++refused;
      const std::string m = e.what();
      EXPECT_TRUE(one_line(m) && m.rfind(path + ":", 0) == 0) << m;
    }
  }
  std::printf("[ measured ] checkpoints: %d corruptions refused, %d accepted\n", refused, accepted);
  EXPECT_EQ(accepted, 0);
  EXPECT_GE(refused, 10000);
}

TEST_F(InputFiles, NoCorruptedSweepPartIsAccepted) {
  const fs::path sweep = write("sw.json", R"({"problem": {"type": "free_body", "inertia": [1, 2, 3]},
    "initial": {"omega": [1, 0.1, 0.1]}, "integrator": {"method": "rkmk4", "dt": 0.01}, "t_end": 0.2,
    "sweep": {"grid": {"/initial/omega/0": [1, 2, 3, 4, 5]}, "extrema": ["omega1"]}})");
  for (const char* shard : {"0/2", "1/2"}) {
    lgi::app::SweepCommandOptions o;
    o.sweep_file = sweep.string();
    o.output = (dir_ / (std::string("part") + shard[0] + ".csv")).string();
    o.shard = shard;
    o.quiet = true;
    ASSERT_EQ(lgi::app::sweep_command(o), 0);
  }
  lgi::app::MergeCommandOptions m;
  m.parts = {(dir_ / "part0.csv").string(), (dir_ / "part1.csv").string()};
  m.output = "/dev/null";
  m.quiet = true;
  ASSERT_EQ(lgi::app::merge_command(m), 0);
  const std::string good = slurp(dir_ / "part1.csv");

  // stderr to a file while the corruptions are merged: one line each.
  const fs::path err = dir_ / "stderr.txt";
  std::fflush(stderr);
  const int saved = ::dup(2);
  std::mt19937_64 rng(7);
  int accepted = 0, refused = 0;
  for (int n = 0; n < 12000; ++n) {
    const std::string bad = corrupt(good, rng, n % 3);
    if (bad == good) continue;
    std::ofstream(dir_ / "part1.csv", std::ios::binary | std::ios::trunc) << bad;
    const int fd = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(fd, 2);
    ::close(fd);
    const int status = lgi::app::merge_command(m);
    std::fflush(stderr);
    ::dup2(saved, 2);
    const std::string message = slurp(err);
    if (status == 0) {
      ++accepted;
      ADD_FAILURE() << "accepted corruption " << n << " (kind " << n % 3 << ")";
    } else {
      ++refused;
      EXPECT_EQ(status, 1) << message;
      EXPECT_TRUE(message.find('\n') == message.size() - 1 && message.rfind("lgi: error: ", 0) == 0) << message;
    }
  }
  ::close(saved);
  std::printf("[ measured ] sweep parts: %d corruptions refused, %d accepted\n", refused, accepted);
  EXPECT_EQ(accepted, 0);
  EXPECT_GE(refused, 10000);
}

}  // namespace
