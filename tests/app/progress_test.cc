// The progress of long commands (app/progress.h): one line per stage when piped, one line
// rewritten in place with an ETA on a terminal, nothing with --quiet; and through the built
// binary, `pwsim run` piped prints one line per stage on stderr and nothing with --quiet.

#include "app/progress.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace pwsim::app {
namespace {

namespace fs = std::filesystem;

/// A clock the test sets.
struct FakeClock {
  double now{0.0};
  std::function<double()> Fn() {
    return [this] { return now; };
  }
};

// Tests the piped form: one line per stage when it starts (with its count when it has one),
// none for the items within a stage, none when a stage reports again.
TEST(Progress, PipedPrintsOneLinePerStage) {
  FakeClock clock;
  std::ostringstream out;
  {
    Progress progress("pwsim x", false, false, out, clock.Fn());
    progress.Stage("read");
    clock.now = 1.0;
    progress.Report("render", 0, 10);
    for (int done = 1; done <= 10; ++done) progress.Report("render", done, 10);
    progress.Stage("write");
    progress.Finish();
  }
  EXPECT_EQ(out.str(), "pwsim x: read\npwsim x: render (0/10)\npwsim x: write\n");
}

// Tests the terminal form: the line is rewritten in place ("\r", erased to its end), the ETA is
// the rate so far, elapsed (total - done) / done = 10 s x 75 / 25 = 30 s; a redraw within
// 0.2 s is skipped, the last item always drawn, a late count of a worker never drawn, and the
// line erased at the end.
TEST(Progress, TerminalRewritesOneLineWithAnEta) {
  FakeClock clock;
  std::ostringstream out;
  Progress progress("pwsim x", false, true, out, clock.Fn());
  progress.Report("render", 0, 100);
  EXPECT_EQ(out.str(), "\rpwsim x: render 0/100\x1b[K");
  out.str("");
  clock.now = 10.0;
  progress.Report("render", 25, 100);
  EXPECT_EQ(out.str(), "\rpwsim x: render 25/100, ETA 30 s\x1b[K");
  out.str("");
  clock.now = 10.1;
  progress.Report("render", 26, 100);  // within 0.2 s of the last redraw
  EXPECT_EQ(out.str(), "");
  clock.now = 70.0;
  progress.Report("render", 40, 100);
  progress.Report("render", 39, 100);  // a worker that finished earlier reports late
  EXPECT_EQ(out.str(), "\rpwsim x: render 40/100, ETA 1 min 45 s\x1b[K");  // 70 x 60 / 40 = 105 s
  out.str("");
  clock.now = 70.05;
  progress.Report("render", 100, 100);  // the last item: drawn at once
  EXPECT_EQ(out.str(), "\rpwsim x: render 100/100, ETA 0 s\x1b[K");
  out.str("");
  clock.now = 75.0;
  progress.Stage("write");  // a stage without a count: its elapsed time
  clock.now = 78.0;
  progress.Report("write", 0, 0);
  EXPECT_EQ(out.str(), "\rpwsim x: write\x1b[K\rpwsim x: write, 3 s\x1b[K");
  out.str("");
  progress.Finish();
  EXPECT_EQ(out.str(), "\r\x1b[K");
}

// Tests that the ETA of a stage counts from when that stage was first seen, with the items it
// had done then: a stage entered at 100 s with 4 of 8 done, 6 done at 110 s: 10 x 2 / 2 = 10 s.
TEST(Progress, EtaCountsFromTheStagesFirstReport) {
  FakeClock clock;
  std::ostringstream out;
  Progress progress("p", false, true, out, clock.Fn());
  clock.now = 100.0;
  progress.Report("step", 4, 8);
  clock.now = 110.0;
  out.str("");
  progress.Report("step", 6, 8);
  EXPECT_EQ(out.str(), "\rp: step 6/8, ETA 10 s\x1b[K");
}

// Tests --quiet: nothing at all, in either form.
TEST(Progress, QuietPrintsNothing) {
  FakeClock clock;
  for (bool terminal : {false, true}) {
    std::ostringstream out;
    {
      Progress progress("p", true, terminal, out, clock.Fn());
      progress.Stage("a", 3);
      clock.now += 5.0;
      progress.callback()("a", 3, 3);
      progress.Finish();
    }
    EXPECT_EQ(out.str(), "") << terminal;
  }
}

// Tests other output while the progress is shown: on a terminal the progress line is erased
// before the other line (written to its own stream) and drawn again after it; piped, the other
// line alone. ProgressLog hands a library's log lines over whole, one per newline.
TEST(Progress, OtherLinesNeverShareTheProgressLine) {
  FakeClock clock;
  std::ostringstream err, out;
  Progress progress("p", false, true, err, clock.Fn());
  progress.Report("run the tasks", 1, 4);
  err.str("");
  {
    ProgressLog log(progress, out);
    log << "local: task 2 ok\n" << "local: task " << 3 << " ok\n";
  }
  EXPECT_EQ(out.str(), "local: task 2 ok\nlocal: task 3 ok\n");
  EXPECT_EQ(err.str(), "\r\x1b[K\rp: run the tasks 1/4\x1b[K\r\x1b[K\rp: run the tasks 1/4\x1b[K");

  std::ostringstream piped_err, piped_out;
  Progress piped("p", false, false, piped_err, clock.Fn());
  piped.Stage("run the tasks", 4);
  piped.Line(piped_out, "local: task 2 ok");
  EXPECT_EQ(piped_out.str(), "local: task 2 ok\n");
  EXPECT_EQ(piped_err.str(), "p: run the tasks (0/4)\n");
}

TEST(Progress, FormatsDurations) {
  EXPECT_EQ(Progress::FormatSeconds(0.4), "0 s");
  EXPECT_EQ(Progress::FormatSeconds(59.4), "59 s");
  EXPECT_EQ(Progress::FormatSeconds(185.0), "3 min 05 s");
  EXPECT_EQ(Progress::FormatSeconds(7800.0), "2 h 10 min");
  EXPECT_EQ(Progress::FormatSeconds(-3.0), "0 s");
}

std::string ReadText(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Runs the built pwsim in `dir` with stdout and stderr to files (a pipe, not a terminal);
/// returns the exit status.
int PwsimTo(const std::string& args, const fs::path& dir) {
  const std::string command = "cd '" + dir.string() + "' && " + std::string(PWSIM_BINARY_DIR) + "/pwsim " + args +
                              " > stdout.txt 2> stderr.txt";
  const int raw = std::system(command.c_str());
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
}

std::size_t Count(const std::string& text, const std::string& part) {
  std::size_t n = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

// Tests `pwsim run` piped: stderr holds exactly one line per stage (simulate, motion cueing,
// render with its frame count: 4 s at 10 frames/s, frames 0..40), no carriage return; with
// --quiet stderr is empty and stdout the same list of written files.
TEST(ProgressEndToEnd, RunPipedPrintsOneLinePerStageAndNothingWithQuiet) {
  const fs::path dir = fs::path(PWSIM_BINARY_DIR) / "test_out" / "progress" / "run";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string run = std::string("run ") + PWSIM_SOURCE_DIR +
                          "/scenes/speed_cushion.yaml --size 64x36 --fps 10 --decimate 20 --no-mca-compare --out o";
  ASSERT_EQ(PwsimTo(run, dir), 0) << ReadText(dir / "stderr.txt");
  const std::string piped = ReadText(dir / "stderr.txt");
  const std::string summary = ReadText(dir / "o" / "summary.json");
  const std::size_t frames_at = summary.find("\"frames\": ");
  ASSERT_NE(frames_at, std::string::npos) << summary;
  const int frames = std::atoi(summary.c_str() + frames_at + 10);
  EXPECT_EQ(piped, "pwsim run: simulate the chair\npwsim run: motion cueing\npwsim run: render (0/" +
                       std::to_string(frames) + ")\n");
  EXPECT_EQ(Count(piped, "\r"), 0U);
  const std::string listed = ReadText(dir / "stdout.txt");

  ASSERT_EQ(PwsimTo(run + " --quiet", dir), 0) << ReadText(dir / "stderr.txt");
  EXPECT_EQ(ReadText(dir / "stderr.txt"), "");
  EXPECT_EQ(ReadText(dir / "stdout.txt"), listed);
}

// Tests two more commands piped and with --quiet: identify (two demo trials) and generate (one
// trial) print exactly their stage lines, and nothing with --quiet.
TEST(ProgressEndToEnd, IdentifyAndGeneratePipedAndQuiet) {
  const fs::path dir = fs::path(PWSIM_BINARY_DIR) / "test_out" / "progress" / "identify_generate";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string trials = std::string(PWSIM_SOURCE_DIR) + "/assets/trials-demo/";
  const struct {
    std::string args, lines;
  } cases[] = {
      {"identify " + trials + "v0.60_m0_cushion_r1 " + trials + "v1.20_m100_cushion_r1 --out o",
       "pwsim identify: read the trials (0/2)\npwsim identify: identify the chair\npwsim identify: write the report\n"},
      {"generate --speeds 0.6 --loads 0 --cushion with --repeats 1 --out g",
       "pwsim generate: simulate the trials\npwsim generate: write the trials (0/1)\n"},
  };
  for (const auto& c : cases) {
    ASSERT_EQ(PwsimTo(c.args, dir), 0) << c.args << "\n" << ReadText(dir / "stderr.txt");
    EXPECT_EQ(ReadText(dir / "stderr.txt"), c.lines) << c.args;
    ASSERT_EQ(PwsimTo(c.args + " --quiet", dir), 0) << c.args;
    EXPECT_EQ(ReadText(dir / "stderr.txt"), "") << c.args;
  }
}

}  // namespace
}  // namespace pwsim::app
