// Fault injection into the publishing of a run's outputs (docs/testing.md,
// "Guarantees"): a run killed (SIGKILL) at every system call of staging,
// committing, publishing and cleaning up; publishing that fails half way (an
// injected error, an immutable file); concurrent runs into one directory.
// After each, the output directory holds one run's complete set (the old or
// the new), or, for a kill inside the publishing renames, a set the next run
// completes; the next good run leaves its own set and no debris; a file that
// is not an output is never touched.
//
// Faults are injected with strace (-e inject=SYSCALL:signal=SIGKILL:when=N,
// or :error=EPERM): the tests skip where strace is missing or cannot trace.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "fss/io/png_io.h"
#include "support/test_util.h"

namespace fss {
namespace {

namespace fs = std::filesystem;
using test::CommandResult;
using test::quote;

// Output name -> size and hash of its bytes: the visible files of a
// directory, the user's notes.txt left out.
using OutputSet = std::map<std::string, std::string>;

std::string fingerprint(const std::string& bytes) {
  return std::to_string(bytes.size()) + " bytes, hash " +
         std::to_string(std::hash<std::string>{}(bytes));
}

OutputSet outputs_in(const fs::path& dir) {
  OutputSet set;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name[0] == '.' || name == "notes.txt") continue;
    set[name] = fingerprint(test::read_file(entry.path()));
  }
  return set;
}

// Hidden entries: what a run left behind.
std::vector<std::string> debris_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name[0] == '.') names.push_back(name);
  }
  return names;
}

constexpr char kNotes[] = "the user's own file, not an output\n";

bool strace_works() {
  static const bool works = test::run_command("strace -f -qq -o /dev/null true").exit_code == 0;
  return works;
}

class FaultInjection : public ::testing::Test {
 protected:
  void SetUp() override {
    test::write_file(input_, as_string(encode_png8(test::make_test_image(600, 48, 1))));
    // Run A writes 7 files, run B 8 (sheet.png is new), with other bytes.
    reference_a_ = reference(args_a_, "ref_a");
    reference_b_ = reference(args_b_, "ref_b");
    ASSERT_EQ(reference_a_.size(), 7u);
    ASSERT_EQ(reference_b_.size(), 8u);
  }

  static std::string as_string(const std::vector<std::uint8_t>& bytes) {
    return {bytes.begin(), bytes.end()};
  }

  std::string command(const std::string& args) const {
    return "--input " + quote(input_) + " --outdir " + quote(out_) + " " + args;
  }

  OutputSet reference(const std::string& args, const std::string& name) {
    const fs::path dir = dir_ / name;
    const CommandResult r =
        test::run_fssim("--input " + quote(input_) + " --outdir " + quote(dir) + " " + args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return outputs_in(dir);
  }

  // The output directory holding run A's set and the user's notes.
  void reset_to_a() {
    fs::remove_all(out_);
    const CommandResult r = test::run_fssim(command(args_a_));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    test::write_file(out_ / "notes.txt", kNotes);
  }

  // Runs B under strace with `inject` (an strace -e inject= value).
  CommandResult run_b_injected(const std::string& syscall, const std::string& inject) {
    return test::run_command("strace -f -qq -o /dev/null -e trace=" + syscall +
                             " -e inject=" + syscall + ":" + inject + " '" + FSSIM_BINARY_PATH +
                             "' " + command(args_b_));
  }

  bool is_a() const { return outputs_in(out_) == reference_a_; }
  bool is_b() const { return outputs_in(out_) == reference_b_; }

  // After any fault: a good run of `args` leaves exactly its set, no debris,
  // the notes untouched.
  void expect_good_run_recovers(const std::string& args, const OutputSet& expected) {
    const CommandResult r = test::run_fssim(command(args));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(outputs_in(out_), expected);
    EXPECT_EQ(debris_in(out_), std::vector<std::string>{});
    EXPECT_EQ(test::read_file(out_ / "notes.txt"), kNotes);
  }

  test::TempDir dir_;
  fs::path input_ = dir_ / "in.png";
  fs::path out_ = dir_ / "out";
  std::string args_a_ = "--no-plots --seed 1";
  std::string args_b_ = "--no-plots --seed 2 --velocity 1.1 --sheet";
  OutputSet reference_a_;
  OutputSet reference_b_;
};

// SIGKILL at the Nth call of each system call the write makes: creating the
// staging directory (mkdir), writing and syncing each file (fsync), the
// commit (renameat), each publishing rename (renameat2), the clean-up
// (unlinkat). A kill outside the renames leaves A or B whole; inside them,
// the next run completes the killed run's set before publishing its own.
TEST_F(FaultInjection, SigkillAtEverySystemCallLeavesOneSet) {
  // What a kill leaves is the same code path with or without the sanitizers; the Release suite
  // runs it, the sanitized binary would take five times as long.
  if (test::kAddressSanitizer) GTEST_SKIP() << "kill points: run in the Release suite";
  if (!strace_works()) GTEST_SKIP() << "strace is missing or cannot trace here";
  const std::map<std::string, int> calls = {
      {"mkdir,mkdirat", 2}, {"fsync", 12}, {"renameat", 2}, {"renameat2", 9}, {"unlinkat", 14}};
  int kills = 0;
  int mixed = 0;
  for (const auto& [syscall, count] : calls) {
    for (int n = 1; n <= count; ++n) {
      reset_to_a();
      const CommandResult r = run_b_injected(syscall, "signal=SIGKILL:when=" + std::to_string(n));
      ++kills;
      const bool whole = is_a() || is_b();
      if (!whole) ++mixed;
      // Only the publishing renames may leave a mix, and only until the next run.
      if (syscall != "renameat2") EXPECT_TRUE(whole) << syscall << " call " << n;
      EXPECT_EQ(test::read_file(out_ / "notes.txt"), kNotes);
      if (r.exit_code == 0) EXPECT_TRUE(is_b()) << syscall << " call " << n;
      // Alternate the next run: A (the old set back) or B again.
      if (n % 2 == 0) {
        expect_good_run_recovers(args_a_, reference_a_);
      } else {
        expect_good_run_recovers(args_b_, reference_b_);
      }
    }
  }
  std::printf("fault injection: %d kills, %d left a mix until the next run\n", kills, mixed);
}

// A kill at random moments of the whole run, without strace.
TEST_F(FaultInjection, SigkillAtRandomMomentsLeavesOneSetAfterTheNextRun) {
  // Its kill moments (0 to 55 ms) span a Release run; an instrumented one is still starting.
  if (test::kAddressSanitizer) GTEST_SKIP() << "kill moments timed for a Release run";
  const std::string binary = FSSIM_BINARY_PATH;
  for (int i = 0; i < 12; ++i) {
    reset_to_a();
    const std::string delay = std::to_string(0.005 * i);
    test::run_command("{ '" + binary + "' " + command(args_b_) +
                      " >/dev/null 2>&1 & pid=$!; sleep " + delay +
                      "; kill -9 $pid 2>/dev/null; wait $pid; }");
    EXPECT_EQ(test::read_file(out_ / "notes.txt"), kNotes);
    expect_good_run_recovers(args_a_, reference_a_);
  }
}

// A rename that fails half way (the third of eight): the two published
// files go back, the old set is whole, exit 1 naming the file.
TEST_F(FaultInjection, PublishingThatFailsHalfWayPutsTheOldSetBack) {
  if (!strace_works()) GTEST_SKIP() << "strace is missing or cannot trace here";
  reset_to_a();
  const CommandResult r = run_b_injected("renameat2", "error=EPERM:when=3");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("fssim: error: cannot replace '"), std::string::npos) << r.err;
  EXPECT_TRUE(is_a());
  EXPECT_EQ(debris_in(out_), std::vector<std::string>{});
  expect_good_run_recovers(args_b_, reference_b_);
}

// Every rename from the third on fails, so even putting back fails: exit 1,
// and the next run completes the set.
TEST_F(FaultInjection, PublishingThatCannotBeUndoneIsCompletedByTheNextRun) {
  if (!strace_works()) GTEST_SKIP() << "strace is missing or cannot trace here";
  reset_to_a();
  const CommandResult r = run_b_injected("renameat2", "error=EPERM:when=3+");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("the next run into"), std::string::npos) << r.err;
  expect_good_run_recovers(args_a_, reference_a_);
}

// An immutable old output (chattr +i, where the filesystem and the user
// allow it): the run fails, the old set stays whole.
TEST_F(FaultInjection, ImmutableOldOutputLeavesTheOldSet) {
  reset_to_a();
  const fs::path locked = out_ / "groundtruth.png";
  if (test::run_command("chattr +i " + quote(locked)).exit_code != 0) {
    GTEST_SKIP() << "chattr +i is not possible here";
  }
  const CommandResult r = test::run_fssim(command(args_b_));
  test::run_command("chattr -i " + quote(locked));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("groundtruth.png"), std::string::npos) << r.err;
  EXPECT_TRUE(is_a());
  EXPECT_EQ(debris_in(out_), std::vector<std::string>{});
  EXPECT_EQ(test::read_file(out_ / "notes.txt"), kNotes);
}

// 100 pairs of runs into one directory at once: both exit 0 and the
// directory holds one of the two sets, without debris.
TEST_F(FaultInjection, ConcurrentPairsLeaveOneSet) {
  if (test::kAddressSanitizer) GTEST_SKIP() << "100 concurrent pairs: run in the Release suite";
  const std::string binary = FSSIM_BINARY_PATH;
  int mixed = 0;
  for (int pair = 0; pair < 100; ++pair) {
    fs::remove_all(out_);
    const CommandResult r = test::run_command(
        "{ '" + binary + "' " + command(args_a_) + " >/dev/null & a=$!; '" + binary + "' " +
        command(args_b_) + " >/dev/null & b=$!; wait $a || exit 3; wait $b || exit 4; }");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    if (!is_a() && !is_b()) ++mixed;
    EXPECT_EQ(debris_in(out_), std::vector<std::string>{});
  }
  EXPECT_EQ(mixed, 0);
}

// A failed run does not leave a new, empty output directory.
TEST_F(FaultInjection, FailedRunLeavesNoNewDirectory) {
  if (!strace_works()) GTEST_SKIP() << "strace is missing or cannot trace here";
  const CommandResult r = run_b_injected("fsync", "error=EIO:when=2");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_FALSE(fs::exists(out_));
}

// The commands that write one file (code generate, analyze --json,
// optimize -o, sweep -o, spectra -o, campaign check --junit) write it
// through a temporary file synced and renamed into place: when the sync
// fails, the command exits 1 naming the file, the old file stays as it was
// and no temporary is left beside it.
TEST(SingleFileWrite, FailedSyncKeepsTheOldFile) {
  if (!strace_works()) GTEST_SKIP() << "strace is missing or cannot trace here";
  test::TempDir dir;
  const fs::path input = dir / "in.png";
  const std::vector<std::uint8_t> png = encode_png8(test::make_test_image(600, 8, 1));
  test::write_file(input, std::string(png.begin(), png.end()));
  const fs::path campaign = dir / "campaign";
  ASSERT_EQ(test::run_fssim("campaign -i " + quote(input) +
                            " -c raskar --noise none --no-progress -o " + quote(campaign))
                .exit_code,
            0);
  const fs::path out = dir / "out" / "file";
  const std::string results = quote(campaign / "results.csv");
  const std::vector<std::string> commands = {
      "code generate sinc -L 16 -o OUT", "code analyze raskar --json OUT",
      "code optimize -L 6 -v 1 --restarts 1 --iterations 5 -o OUT",
      "sweep -i " + quote(input) + " --noise none -v 1:2:1 -o OUT", "spectra raskar -o OUT",
      // One trial: no standard error, so a given tolerance.
      "campaign check " + results + " " + results + " --abs 0 --junit OUT"};
  for (std::string command : commands) {
    command.replace(command.find("OUT"), 3, quote(out));
    fs::remove_all(out.parent_path());
    fs::create_directories(out.parent_path());
    test::write_file(out, "the old file\n");
    const CommandResult r = test::run_command(
        "strace -f -qq -o /dev/null -e trace=fsync "
        "-e inject=fsync:error=EIO '" +
        std::string(FSSIM_BINARY_PATH) + "' " + command);
    EXPECT_EQ(r.exit_code, 1) << command << "\n" << r.err;
    EXPECT_NE(r.err.find(out.string()), std::string::npos) << command << "\n" << r.err;
    EXPECT_EQ(test::read_file(out), "the old file\n") << command;
    EXPECT_EQ(test::list_directory(out.parent_path()), std::vector<std::string>{"file"}) << command;
  }
}

}  // namespace
}  // namespace fss
