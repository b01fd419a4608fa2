// `fssim campaign`, `campaign merge` and `campaign check` end to end: kill -9
// and resume, shards merged to the bytes of one run, refusals, the campaign
// file, and the regression check against the reference program's figures.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <thread>

#include "fss/io/png_io.h"
#include "support/test_util.h"

namespace fss {
namespace {

// A 3 GB address-space limit for a child fssim (none under AddressSanitizer,
// whose shadow memory needs terabytes of address space).
std::string address_space_limit() {
  return test::kAddressSanitizer ? std::string() : std::string("ulimit -v 3000000; ");
}

namespace fs = std::filesystem;
using test::quote;
using test::run_fssim;

// A width x height crop of data/camera.png, written into `dir`.
std::string write_crop(const fs::path& dir, int width, int height) {
  const Image camera = read_png(test::source_path("data/camera.png"));
  Image crop(width, height, 1);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) crop.at(0, y, x) = camera.at(0, 200 + y, 150 + x);
  }
  const auto png = encode_png8(crop);
  const fs::path path = dir / "crop.png";
  test::write_file(path, std::string(png.begin(), png.end()));
  return path.string();
}

std::string write_short_code(const fs::path& dir) {
  test::write_file(dir / "short.txt", "1 0 1 1 0 0 1 1\n");
  return (dir / "short.txt").string();
}

std::string outputs(const fs::path& dir) {
  return test::read_file(dir / "results.csv") + test::read_file(dir / "results.jsonl") +
         test::read_file(dir / "campaign.json");
}

std::size_t journal_lines(const fs::path& dir) {
  std::error_code ec;
  if (!fs::exists(dir / "journal.jsonl", ec)) return 0;
  const std::string text = test::read_file(dir / "journal.jsonl");
  return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

class CampaignCli : public ::testing::Test {
 protected:
  void SetUp() override {
    image_ = write_crop(tmp_.path(), 160, 32);
    code_ = write_short_code(tmp_.path());
    base_ = "campaign --no-progress -i " + quote(image_) + " -c " + quote(code_) +
            " snapshot --velocity 0.2:2:0.2 --trials 2 --seed 3 --threads 1 --skip-unrunnable";
    args_ = base_ + " --snr 20:640:x2";
  }
  test::TempDir tmp_;
  std::string image_, code_, base_, args_;
};

// Starts `fssim ARGS` and kills it with SIGKILL once `dir`'s journal has
// `lines` lines; false if it finished first.
bool kill_after(const std::string& args, const fs::path& dir, std::size_t lines) {
  const pid_t pid = fork();
  if (pid == 0) {
    const std::string command =
        "exec " + quote(FSSIM_BINARY_PATH) + " " + args + " >/dev/null 2>&1";
    execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  while (waitpid(pid, &status, WNOHANG) == 0) {
    if (journal_lines(dir) >= lines) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      return true;
    }
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  return false;
}

TEST_F(CampaignCli, KillNineAndResumeGivesTheBytesOfAnUninterruptedRun) {
  const fs::path whole = tmp_ / "whole", killed = tmp_ / "killed";
  const auto full = run_fssim(args_ + " -o " + quote(whole));
  ASSERT_EQ(full.exit_code, 0) << full.err;
  const std::size_t total = journal_lines(whole) - 1;
  ASSERT_EQ(total, 2u * 10u * 6u);
  // Killed twice, at different points; each rerun resumes.
  for (const std::size_t at : {5u, 40u}) {
    ASSERT_TRUE(kill_after(args_ + " -o " + quote(killed), killed, at))
        << "finished before the kill";
    EXPECT_LT(journal_lines(killed), total + 1);
    EXPECT_FALSE(fs::exists(killed / "results.csv"));
  }
  const auto resumed = run_fssim(args_ + " -o " + quote(killed));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_NE(resumed.out.find("from the journal"), std::string::npos);
  EXPECT_EQ(resumed.out.find("(0 run now"), std::string::npos) << resumed.out;
  EXPECT_EQ(outputs(killed), outputs(whole));
  // Nothing left over: no temporary files.
  EXPECT_EQ(test::list_directory(killed), test::list_directory(whole));
}

std::string trial_outputs(const fs::path& dir) {
  return outputs(dir) + test::read_file(dir / "trials.csv") + test::read_file(dir / "trials.jsonl");
}

// Per-trial rows: killed with -9 and resumed, or run in shards and merged,
// the same bytes as one uninterrupted run.
TEST_F(CampaignCli, PerTrialRowsSurviveKillNineAndMergeToTheBytesOfOneRun) {
  const std::string args = args_ + " --per-trial";
  const fs::path whole = tmp_ / "whole", killed = tmp_ / "killed";
  const auto full = run_fssim(args + " -o " + quote(whole));
  ASSERT_EQ(full.exit_code, 0) << full.err;
  // 2 codes x 10 velocities x 6 snr values; the rows that ran have 2 trials.
  const auto trials = test::lines_of(test::read_file(whole / "trials.csv"));
  EXPECT_EQ(trials.front().substr(trials.front().rfind(",trial,")),
            ",trial,trial_seed,rmse,rmse_ci,psnr,ssim");
  EXPECT_EQ((trials.size() - 1) % 2, 0u);
  EXPECT_GT(trials.size(), 1u);
  ASSERT_TRUE(kill_after(args + " -o " + quote(killed), killed, 30)) << "finished before the kill";
  EXPECT_FALSE(fs::exists(killed / "trials.csv"));
  const auto resumed = run_fssim(args + " -o " + quote(killed));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_EQ(trial_outputs(killed), trial_outputs(whole));
  std::string parts;
  for (int i = 1; i <= 3; ++i) {
    const fs::path part = tmp_ / ("part" + std::to_string(i));
    const auto r = run_fssim(args + " --shard " + std::to_string(i) + "/3 -o " + quote(part));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    parts += " " + quote(part);
  }
  const auto merged =
      run_fssim("campaign merge --skip-unrunnable -o " + quote(tmp_ / "merged") + parts);
  ASSERT_EQ(merged.exit_code, 0) << merged.err;
  EXPECT_EQ(trial_outputs(tmp_ / "merged"), trial_outputs(whole));
  // Without --per-trial it is another campaign: refused in that directory.
  const auto changed = run_fssim(args_ + " -o " + quote(whole));
  EXPECT_EQ(changed.exit_code, 2);
  EXPECT_NE(changed.err.find("holds another campaign"), std::string::npos) << changed.err;
}

TEST_F(CampaignCli, AChangedSpecificationIntoTheSameDirectoryIsRefused) {
  const fs::path out = tmp_ / "out";
  ASSERT_EQ(run_fssim(args_ + " -o " + quote(out)).exit_code, 0);
  const std::string before = outputs(out);
  const auto changed = run_fssim(base_ + " --snr 30 -o " + quote(out));
  EXPECT_EQ(changed.exit_code, 2);
  EXPECT_NE(changed.err.find("holds another campaign"), std::string::npos) << changed.err;
  EXPECT_EQ(outputs(out), before);
}

TEST_F(CampaignCli, ShardsMergeToTheBytesOfOneRun) {
  ASSERT_EQ(run_fssim(args_ + " -o " + quote(tmp_ / "single")).exit_code, 0);
  std::string parts;
  for (int i = 1; i <= 4; ++i) {
    const fs::path part = tmp_ / ("part" + std::to_string(i));
    const auto r = run_fssim(args_ + " --shard " + std::to_string(i) + "/4 -o " + quote(part));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    parts += " " + quote(part);
  }
  const auto merged =
      run_fssim("campaign merge --skip-unrunnable -o " + quote(tmp_ / "merged") + parts);
  ASSERT_EQ(merged.exit_code, 0) << merged.err;
  EXPECT_EQ(outputs(tmp_ / "merged"), outputs(tmp_ / "single"));
  // Three parts of four: refused, nothing written.
  const auto missing =
      run_fssim("campaign merge --skip-unrunnable -o " + quote(tmp_ / "m2") + " " +
                quote(tmp_ / "part1") + " " + quote(tmp_ / "part2") + " " + quote(tmp_ / "part4"));
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("shard 3/4 is missing"), std::string::npos) << missing.err;
  EXPECT_FALSE(fs::exists(tmp_ / "m2" / "results.csv"));
}

TEST_F(CampaignCli, CampaignFileAndOptionsGiveTheSameCampaign) {
  const fs::path file = tmp_ / "campaign.json";
  test::write_file(file, "{\"input\": \"" + image_ + "\", \"code\": [\"" + code_ +
                             "\", \"snapshot\"], \"velocity\": \"0.2:2:0.2\", \"snr\": "
                             "\"20:640:x2\", \"trials\": 5, \"seed\": 3}\n");
  const auto from_file = run_fssim("campaign --no-progress --threads 1 --skip-unrunnable -f " +
                                   quote(file) + " --trials 2 -o " + quote(tmp_ / "f"));
  ASSERT_EQ(from_file.exit_code, 0) << from_file.err;
  ASSERT_EQ(run_fssim(args_ + " -o " + quote(tmp_ / "o")).exit_code, 0);
  EXPECT_EQ(outputs(tmp_ / "f"), outputs(tmp_ / "o"));
  test::write_file(file, "{\"inputs\": []}");
  const auto bad = run_fssim("campaign -f " + quote(file) + " -o " + quote(tmp_ / "b"));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("unknown key 'inputs'"), std::string::npos) << bad.err;
  // A field of the file is named as the file names it, not as an option.
  test::write_file(file, "{\"mode\": [\"digital\"], \"noise\": \"loud\"}");
  const auto mode = run_fssim("campaign -f " + quote(file) + " -o " + quote(tmp_ / "b"));
  EXPECT_EQ(mode.exit_code, 2);
  EXPECT_EQ(mode.err, "fssim: error: campaign file '" + file.string() +
                          "': mode 'digital': expected numerical or analog\n");
}

TEST_F(CampaignCli, UsageErrors) {
  EXPECT_EQ(run_fssim(args_).exit_code, 2);  // no -o
  const auto shard = run_fssim(args_ + " --shard 5/4 -o " + quote(tmp_ / "x"));
  EXPECT_EQ(shard.exit_code, 2);
  EXPECT_NE(shard.err.find("shard '5/4'"), std::string::npos) << shard.err;
  const auto range = run_fssim(base_ + " --snr 1:10:x0.5 -o " + quote(tmp_ / "x"));
  EXPECT_EQ(range.exit_code, 2);
  EXPECT_NE(range.err.find("factor > 1"), std::string::npos) << range.err;
  const auto misplaced =
      run_fssim("campaign --trials 3 merge -o " + quote(tmp_ / "m") + " " + quote(tmp_ / "p"));
  EXPECT_EQ(misplaced.exit_code, 2);
  EXPECT_NE(misplaced.err.find("--trials is an option of 'campaign'"), std::string::npos)
      << misplaced.err;
  const auto noise = run_fssim(args_ + " --noise loud -o " + quote(tmp_ / "x"));
  EXPECT_EQ(noise.exit_code, 2);
  EXPECT_NE(noise.err.find("--noise 'loud'"), std::string::npos) << noise.err;
}

// The sensor options are refused in the same words by every command that
// takes them (cli_common: check_adc_gain, check_sensor_options).
TEST_F(CampaignCli, SensorOptionsAreRefusedInTheSimulationsWords) {
  const std::string adc =
      "fssim: error: --adc-gain: needs --adc-bits (without an ADC there are no counts)\n";
  const auto campaign = run_fssim(args_ + " --adc-gain 2 -o " + quote(tmp_ / "x"));
  EXPECT_EQ(campaign.exit_code, 2);
  EXPECT_EQ(campaign.err, adc);
  const auto simulation = run_fssim("--input " + image_ + " --adc-gain 2 -o " + quote(tmp_ / "y"));
  EXPECT_EQ(simulation.exit_code, 2);
  EXPECT_EQ(simulation.err, adc);
  const auto analyze = run_fssim("code analyze raskar --adc-gain 2");
  EXPECT_EQ(analyze.exit_code, 2);
  EXPECT_EQ(analyze.err, adc);
  const auto sweep = run_fssim("sweep --input " + image_ + " --velocity 1 --adc-gain 2 -o " +
                               quote(tmp_ / "s.csv"));
  EXPECT_EQ(sweep.exit_code, 2);
  EXPECT_EQ(sweep.err, adc);
  const std::string negative = "fssim: error: --read-noise: value -1 must be finite and >= 0\n";
  EXPECT_EQ(run_fssim("--input " + image_ + " --read-noise -1 -o " + quote(tmp_ / "y")).err,
            negative);
  EXPECT_EQ(run_fssim("code analyze raskar --read-noise -1").err, negative);
}

TEST_F(CampaignCli, FiguresArePngAndSvg) {
  const auto r = run_fssim(args_ + " --figures -o " + quote(tmp_ / "fig"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto files = test::list_directory(tmp_ / "fig" / "figures");
  // Named by what they hold, PNG and SVG: a figure per snr (6) and one per velocity (10) but
  // v 2, which has no ok row (short.txt is not invertible there, snapshot's blur too long).
  EXPECT_EQ(files.size(), 2u * (6 + 9));
  EXPECT_EQ(std::find(files.begin(), files.end(), "rmse_vs_snr__crop__numerical__v2.png"),
            files.end());
  EXPECT_NE(std::find(files.begin(), files.end(), "rmse_vs_snr__crop__numerical__v0.2.png"),
            files.end());
  EXPECT_NE(std::find(files.begin(), files.end(), "rmse_vs_velocity__crop__numerical__snr640.svg"),
            files.end());
  for (const std::string& name : files) {
    EXPECT_TRUE(std::all_of(name.begin(), name.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-';
    })) << name;
    const std::string stem = name.substr(0, name.rfind('.'));
    for (const char* extension : {".png", ".svg"}) {
      EXPECT_TRUE(fs::exists(tmp_ / "fig" / "figures" / (stem + extension))) << name;
    }
  }
}

TEST_F(CampaignCli, ProgressOnATerminalOnly) {
  std::string args = args_;
  args.erase(args.find(" --no-progress"), 14);
  const auto quiet = run_fssim(args + " -o " + quote(tmp_ / "quiet"));
  ASSERT_EQ(quiet.exit_code, 0);
  // stderr is not a terminal here: only the settings that cannot run (snapshot's) are listed.
  EXPECT_EQ(quiet.err.find("settings,"), std::string::npos) << quiet.err;
  EXPECT_EQ(quiet.err.find('\r'), std::string::npos);
  EXPECT_EQ(quiet.err.find("ETA"), std::string::npos);
  // Under a pseudo-terminal (script(1)): settings done, rate and ETA.
  const auto tty = test::run_command(
      "script -qec " +
      quote(std::string(FSSIM_BINARY_PATH) + " " + args + " -o " + (tmp_ / "tty").string()) +
      " /dev/null");
  ASSERT_EQ(tty.exit_code, 0) << tty.out << tty.err;
  EXPECT_NE(tty.out.find("campaign: 120/120 settings"), std::string::npos) << tty.out;
  EXPECT_NE(tty.out.find("ETA"), std::string::npos);
}

// A campaign file whose "trials" is an array nested 100,000 deep: refused
// while it is parsed, in one line naming the file.
TEST_F(CampaignCli, DeeplyNestedCampaignFileIsRefused) {
  const fs::path file = tmp_ / "deep.json";
  test::write_file(
      file, "{\"trials\": " + std::string(100000, '[') + "1" + std::string(100000, ']') + "}");
  const auto r = run_fssim("campaign -f " + quote(file) + " -o " + quote(tmp_ / "x"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.err, "fssim: error: campaign file '" + file.string() +
                       "': arrays and objects nested deeper than 64 levels\n");
  // A value that is not an integer is named by its kind, not printed whole.
  test::write_file(file, "{\"trials\": [\"" + std::string(20000, '7') + "\", 2, 3]}");
  const auto list = run_fssim("campaign -f " + quote(file) + " -o " + quote(tmp_ / "x"));
  EXPECT_EQ(list.exit_code, 2);
  EXPECT_EQ(list.err, "fssim: error: campaign file '" + file.string() +
                          "': 'trials' takes an integer in range, got an array of 3\n");
  EXPECT_FALSE(fs::exists(tmp_ / "x"));
}

// No output of a campaign command replaces one of its inputs.
TEST_F(CampaignCli, OutputsThatAreInputsAreRefused) {
  const std::string csv = "image,code,rmse_mean\ncrop.png,short.txt,1\n";
  test::write_file(tmp_ / "r.csv", csv);
  test::write_file(tmp_ / "e.csv", csv);
  for (const char* input : {"r.csv", "e.csv"}) {
    const auto r = run_fssim("campaign check " + quote(tmp_ / "r.csv") + " " +
                             quote(tmp_ / "e.csv") + " --junit " + quote(tmp_ / "." / input));
    EXPECT_EQ(r.exit_code, 2) << r.out;
    EXPECT_NE(r.err.find("--junit"), std::string::npos) << r.err;
    EXPECT_EQ(test::read_file(tmp_ / input), csv);
  }
  // The campaign file kept in the output directory under an output's name.
  const fs::path out = tmp_ / "out";
  fs::create_directories(out);
  const std::string spec = "{\"input\": \"" + image_ + "\", \"code\": \"" + code_ + "\"}";
  test::write_file(out / "campaign.json", spec);
  const auto file =
      run_fssim("campaign --no-progress -f " + quote(out / "campaign.json") + " -o " + quote(out));
  EXPECT_EQ(file.exit_code, 2);
  EXPECT_NE(file.err.find("would replace the input"), std::string::npos) << file.err;
  EXPECT_EQ(test::read_file(out / "campaign.json"), spec);
  // An input image where --figures draws, refused before anything runs.
  fs::create_directories(tmp_ / "fig" / "figures");
  const fs::path image = tmp_ / "fig" / "figures" / "rmse_vs_snr_1.png";
  fs::copy_file(image_, image);
  const std::string args = "campaign --no-progress -i " + quote(image) + " -c " + quote(code_) +
                           " --snr 20:640:x2 --trials 1 --figures -o " + quote(tmp_ / "fig");
  const auto figures = run_fssim(args);
  EXPECT_EQ(figures.exit_code, 2);
  EXPECT_NE(figures.err.find("where --figures writes"), std::string::npos) << figures.err;
  EXPECT_EQ(test::read_file(image), test::read_file(image_));
  EXPECT_FALSE(fs::exists(tmp_ / "fig" / "journal.jsonl"));
}

// Every file a campaign command reads is bounded before it is read: an
// endless stream, or a file larger than its kind may be, is refused at once
// naming it (under a 3 GB address space, where reading it whole would fail).
TEST_F(CampaignCli, UnboundedInputsAreRefusedNamingTheFile) {
  const auto run = [](const std::string& args) {
    return test::run_command(address_space_limit() + "exec timeout 60 " + quote(FSSIM_BINARY_PATH) +
                             " " + args);
  };
  const std::string out = " -o " + quote(tmp_ / "x");
  const auto file = run("campaign -f /dev/zero" + out);
  EXPECT_EQ(file.exit_code, 1);
  EXPECT_EQ(file.err,
            "fssim: error: campaign file '/dev/zero' is not a text file (it holds a NUL byte)\n");
  // An image is read again to run and to resume: a device, a pipe or a FIFO
  // is refused (a FIFO hung the campaign).
  const auto image = run("campaign -i /dev/zero -c raskar" + out);
  EXPECT_EQ(image.exit_code, 2);
  EXPECT_EQ(image.err,
            "fssim: error: image '/dev/zero' is not a regular file: a campaign reads its images "
            "more than once (to run and to resume); copy it to a file\n");
  const auto piped = test::run_command("{ echo x | timeout 60 " + quote(FSSIM_BINARY_PATH) +
                                       " campaign -i /dev/stdin -c raskar" + out + "; }");
  EXPECT_EQ(piped.exit_code, 2) << piped.err;
  EXPECT_FALSE(fs::exists(tmp_ / "x"));
  test::write_file(tmp_ / "e.csv", "image,rmse_mean\na.png,1\n");
  const auto results = run("campaign check /dev/zero " + quote(tmp_ / "e.csv"));
  EXPECT_EQ(results.exit_code, 1);
  EXPECT_NE(results.err.find("results file '/dev/zero'"), std::string::npos) << results.err;
  // A stream of text past the largest campaign file.
  const auto stream =
      test::run_command("{ yes | (" + address_space_limit() + "exec timeout 60 " +
                        quote(FSSIM_BINARY_PATH) + " campaign -f /dev/stdin" + out + "); }");
  EXPECT_EQ(stream.exit_code, 1);
  EXPECT_EQ(stream.err,
            "fssim: error: campaign file '/dev/stdin' is larger than 16.0 MiB, the most a "
            "campaign file may have\n");
  // Large regular files (sparse: no disk used) are refused by their size.
  test::write_file(tmp_ / "big.json", "");
  fs::resize_file(tmp_ / "big.json", (std::uintmax_t{16} << 20) + 1);
  const auto big = run("campaign -f " + quote(tmp_ / "big.json") + out);
  EXPECT_EQ(big.exit_code, 1);
  EXPECT_EQ(big.err, "fssim: error: campaign file '" + (tmp_ / "big.json").string() +
                         "' is larger than 16.0 MiB, the most a campaign file may have\n");
  test::write_file(tmp_ / "big.csv", "");
  fs::resize_file(tmp_ / "big.csv", (std::uintmax_t{1} << 30) + 1);
  const auto csv = run("campaign check " + quote(tmp_ / "big.csv") + " " + quote(tmp_ / "e.csv"));
  EXPECT_EQ(csv.exit_code, 1);
  EXPECT_EQ(csv.err, "fssim: error: results file '" + (tmp_ / "big.csv").string() +
                         "' is larger than 1.0 GiB, the most a results file may have\n");
  EXPECT_FALSE(fs::exists(tmp_ / "x"));
}

// A part's journal that is not fssim's (empty, no complete header line, a
// directory, an endless stream) is refused by merge and never removed.
TEST_F(CampaignCli, MergeRefusesAndKeepsAJournalThatIsNotFssims) {
  const fs::path part = tmp_ / "part";
  fs::create_directories(part);
  for (const std::string& text : {std::string(), std::string("{\"fssim_campaign_journal\": 1")}) {
    test::write_file(part / "journal.jsonl", text);
    const auto r =
        run_fssim("campaign merge --skip-unrunnable -o " + quote(tmp_ / "m") + " " + quote(part));
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.err.find("not an fssim campaign journal"), std::string::npos) << r.err;
    EXPECT_EQ(test::read_file(part / "journal.jsonl"), text);
    const auto run = run_fssim(args_ + " -o " + quote(part));
    EXPECT_EQ(run.exit_code, 1);
    EXPECT_EQ(test::read_file(part / "journal.jsonl"), text);
  }
  fs::remove(part / "journal.jsonl");
  fs::create_symlink("/dev/zero", part / "journal.jsonl");
  const auto zero = test::run_command(
      address_space_limit() + "exec timeout 60 " + quote(FSSIM_BINARY_PATH) +
      " campaign merge --skip-unrunnable -o " + quote(tmp_ / "m") + " " + quote(part));
  EXPECT_EQ(zero.exit_code, 1);
  EXPECT_NE(zero.err.find((part / "journal.jsonl").string()), std::string::npos) << zero.err;
  EXPECT_FALSE(fs::exists(tmp_ / "m"));
}

// The reference program's Table 1 figures on camera.png (mean of 12 runs)
// and its noise-free Raskar run, checked as CI would.
TEST(CampaignCheck, AgreesWithTheReferenceProgram) {
  test::TempDir tmp;
  const std::string camera = quote(test::source_path("data/camera.png"));
  const auto run =
      run_fssim("campaign --no-progress -i " + camera +
                " -c snapshot raskar random sinc mip --trials 6 -o " + quote(tmp / "table1"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string results = quote(tmp / "table1" / "results.csv");
  const auto check = run_fssim("campaign check " + results + " " +
                               quote(test::fixture_path("table1_reference.csv")) +
                               " --k-se 4 --junit " + quote(tmp / "junit.xml"));
  EXPECT_EQ(check.exit_code, 0) << check.out;
  EXPECT_NE(test::read_file(tmp / "junit.xml").find("tests=\"5\" failures=\"0\""),
            std::string::npos);
  const auto noise_free = run_fssim("campaign --no-progress -i " + camera +
                                    " -c raskar --snr 1e6 -o " + quote(tmp / "nf"));
  ASSERT_EQ(noise_free.exit_code, 0) << noise_free.err;
  const auto check_nf =
      run_fssim("campaign check " + quote(tmp / "nf" / "results.csv") + " " +
                quote(test::fixture_path("reference_noisefree.csv")) + " --abs 1e-3");
  EXPECT_EQ(check_nf.exit_code, 0) << check_nf.out;
  // A regression: a tolerance far below the noise fails, one line per deviation.
  const auto strict = run_fssim("campaign check " + results + " " +
                                quote(test::fixture_path("table1_reference.csv")) +
                                " --rel 1e-6 --junit " + quote(tmp / "strict.xml"));
  EXPECT_EQ(strict.exit_code, 1);
  // 5 deviations, the columns compared and their tolerance, the verdict.
  EXPECT_EQ(test::lines_of(strict.out).size(), 7u) << strict.out;
  EXPECT_NE(strict.out.find("compared rmse_mean: within rel 1e-06\n"), std::string::npos)
      << strict.out;
  EXPECT_NE(test::read_file(tmp / "strict.xml").find("<failure"), std::string::npos);
  // A missing row is a regression too.
  test::write_file(tmp / "extra.csv", "image,code,rmse_mean\ncamera.png,accumulation2,1\n");
  EXPECT_EQ(run_fssim("campaign check " + results + " " + quote(tmp / "extra.csv") + " --abs 1")
                .exit_code,
            1);
}

}  // namespace
}  // namespace fss
