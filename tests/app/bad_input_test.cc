// Bad input through the built binary, one test per kind of issue 42 (the readers' own tests check
// each reader; these check what a user of `pwsim` sees): a clear error naming the file, line
// (where the file has lines), field and what was expected, exit status 1, and nothing left in
// the output folder that could look complete (the folder is not even created).
//
// Kinds here: a key written twice in a scene; a directory where a scene belongs; a misspelt
// sweep override key and a grid value `fast`, refused at `sweep plan`; an empty, a truncated
// and a zero-filled .mat recording; an axis-recording CSV with a non-finite sample and with an
// irregular time step (named by its line); a rating of 1e308. Elsewhere in tests/app: QTM
// FREQUENCY, replay of a corrupt log, --fps before writing, a car run after a chair run
// (cli_test); R-Net logs (drive_command_test).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/app/pwsim_run.h"
#include "tests/sysid/platform/emps_data.h"

namespace pwsim::app {
namespace {

namespace fs = std::filesystem;

using Result = test::PwsimResult;
using test::ReadWholeFile;

fs::path Scratch(const std::string& name) { return test::FreshTestFolder("bad_input", name); }
std::string ReadText(const fs::path& file) { return ReadWholeFile(file); }

/// Runs the built pwsim in `cwd`, quiet (stdout and stderr together).
Result Pwsim(const std::string& args, const fs::path& cwd) { return test::RunPwsim(args + " --quiet", cwd, true); }




/// Expects `args` run in `dir` to fail with status 1, print `message`, and leave no `o`.
void ExpectRefused(const fs::path& dir, const std::string& args, const std::string& message) {
  const Result r = Pwsim(args + " --out o", dir);
  EXPECT_EQ(r.status, 1) << args << "\n" << r.output;
  EXPECT_NE(r.output.find(message), std::string::npos) << args << "\nexpected: " << message << "\ngot: " << r.output;
  EXPECT_FALSE(fs::exists(dir / "o")) << args << " left its output folder";
}

/// `text` with the first `from` replaced by `to` (which must be there).
std::string Replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

/// The 1-based line of the first occurrence of `part` in `text`.
int LineOf(const std::string& text, const std::string& part) {
  const std::size_t at = text.find(part);
  return at == std::string::npos ? -1 : 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
}

const std::string kScenes = std::string(PWSIM_SOURCE_DIR) + "/scenes";

// Tests a scene whose drive: mapping names speed_mps twice: refused at the second, naming the first.
TEST(BadInputEndToEnd, DuplicateKeyInAScene) {
  const fs::path dir = Scratch("duplicate_key");
  const std::string scene = ReadText(kScenes + "/speed_cushion.yaml");
  const int first = LineOf(scene, "  speed_mps: ");
  ASSERT_GT(first, 0);
  std::ofstream(dir / "dup.yaml") << Replaced(scene, "  speed_mps: ", "  speed_mps: 1.0\n  speed_mps: ");
  ExpectRefused(dir, "run dup.yaml --no-video",
                "dup.yaml:" + std::to_string(first + 1) + ": field 'drive.speed_mps': expected each key once in a "
                "mapping, got \"speed_mps\" again (first on line " + std::to_string(first) + ")");
}

// Tests a folder given where a file belongs: a scene, a ratings file, the runs of a study's
// metrics (was "expected a header with participant, condition and report").
TEST(BadInputEndToEnd, DirectoryWhereAFileBelongs) {
  const fs::path dir = Scratch("directory");
  fs::create_directories(dir / "scene.yaml");
  ExpectRefused(dir, "run scene.yaml --no-video",
                "scene.yaml: field '(file)': expected a readable YAML file, got a path that is a directory");
  ExpectRefused(dir, "study scene.yaml", "scene.yaml: field '(file)': expected a ratings CSV, got a path that is a directory");
  ExpectRefused(dir, "study metrics scene.yaml",
                "scene.yaml: field '(file)': expected a runs.csv (pwsim study plan --circuit), got a path that is a directory");
}

/// The shipped speed sweep with its scene given by absolute path and `from` replaced by `to`.
void WriteSweep(const fs::path& file, const std::string& from, const std::string& to) {
  std::string sweep = ReadText(kScenes + "/sweeps/speed_sweep.yaml");
  sweep = Replaced(sweep, "../speed_cushion.yaml", kScenes + "/speed_cushion.yaml");
  std::ofstream(file) << Replaced(sweep, from, to);
}

// Tests that `sweep plan` reads every task's inputs as the swept command would: a grid value
// `fast` for a speed, and a misspelt key in set:, are refused at the sweep file's line and field,
// with the reader's expectation, and no plan is left; so is a misspelt option of the swept
// command in arguments:.
TEST(BadInputEndToEnd, SweepPlanRefusesAGridValueFastAndAMisspeltOverrideKey) {
  const fs::path dir = Scratch("sweep");
  WriteSweep(dir / "fast.yaml", "[0.4, 0.6,", "[0.4, fast,");
  const int grid_line = LineOf(ReadText(dir / "fast.yaml"), "  scene.drive.speed_mps:");
  ExpectRefused(dir, "sweep plan fast.yaml",
                "fast.yaml:" + std::to_string(grid_line) + ": field 'grid.scene.drive.speed_mps': expected a number in "
                "(0, 4] m/s (task 1's scene");
  const Result fast = Pwsim("sweep plan fast.yaml --out o", dir);
  EXPECT_NE(fast.output.find("got \"fast\""), std::string::npos) << fast.output;

  WriteSweep(dir / "typo.yaml", "accel_mps2: 1.5", "acel_mps2: 1.5");
  const int set_line = LineOf(ReadText(dir / "typo.yaml"), "  scene.drive.acel_mps2:");
  ExpectRefused(dir, "sweep plan typo.yaml",
                "typo.yaml:" + std::to_string(set_line) + ": field 'set.scene.drive.acel_mps2': expected a known key");
  const Result typo = Pwsim("sweep plan typo.yaml --out o", dir);
  EXPECT_NE(typo.output.find("got unknown key \"acel_mps2\""), std::string::npos) << typo.output;

  // a misspelt option of the swept command in arguments:, with pwsim run's own suggestion
  WriteSweep(dir / "option.yaml", "--no-video", "--no-vidoe");
  const int arguments_line = LineOf(ReadText(dir / "option.yaml"), "arguments:");
  ExpectRefused(dir, "sweep plan option.yaml",
                "option.yaml:" + std::to_string(arguments_line) + ": field 'arguments[1]': expected an option of pwsim run "
                "(see pwsim run --help), got \"--no-vidoe\"; did you mean --no-video?");
  // a count given in words
  WriteSweep(dir / "count.yaml", "--decimate, \"10\"", "--decimate, ten");
  ExpectRefused(dir, "sweep plan count.yaml",
                "count.yaml:" + std::to_string(arguments_line) + ": field 'arguments[3]': expected an integer for option "
                "--decimate of pwsim run, got \"ten\"");
}

// Tests .mat recordings that cannot be read: empty, cut short (the shipped EMPS file's first
// 100 kB: the element that runs past the end is named), and bytes that are no .mat at all.
TEST(BadInputEndToEnd, EmptyTruncatedAndForeignMatFiles) {
  const fs::path dir = Scratch("mat");
  std::ofstream(dir / "empty.mat").close();
  ExpectRefused(dir, "platform identify empty.mat",
                "empty.mat: field '(file)': expected a MATLAB .mat file (v4, v5 or v7.3), got an empty file (0 bytes)");
  const fs::path shipped = test::EmpsDir() / "DATA_EMPS.mat";  // the EMPS data, where present
  if (fs::exists(shipped)) {
    std::ifstream in(shipped, std::ios::binary);
    std::string bytes(100000, '\0');
    in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    std::ofstream(dir / "cut.mat", std::ios::binary) << bytes;
    ExpectRefused(dir, "platform identify cut.mat",
                  "cut.mat: field '(file)': expected a complete MATLAB v5 .mat file, got a truncated file, cut short: ");
  }
  std::ofstream(dir / "zeros.mat", std::ios::binary) << std::string(1000, '\0');
  ExpectRefused(dir, "platform identify zeros.mat", "zeros.mat: field '(file)': expected a readable MATLAB .mat file");
}

/// An axis recording (pwsim-axis-trial/1) of 50 samples at 1 kHz in run.csv, `cell` (sample
/// index, text) replacing sample i's position, `t_shift` added to the time of samples >= 30.
void WriteRecording(const fs::path& dir, int bad_sample, const std::string& bad_position, double t_shift) {
  std::ofstream csv(dir / "run.csv");
  csv << "# an axis recording\nt,x,r,u\n";
  for (int i = 0; i < 50; ++i) {
    csv << i * 0.001 + (i >= 30 ? t_shift : 0.0) << "," << (i == bad_sample ? bad_position : std::to_string(std::sin(i * 0.01)))
        << ",0,0\n";
  }
  std::ofstream(dir / "run.yaml") << "format: pwsim-axis-trial/1\ndata: {file: run.csv, format: csv}\ntime: t\n"
                                     "experiment: excitation\njoints:\n  - name: rail\n    kind: prismatic\n"
                                     "    position: x\n    reference: r\n    command: u\n"
                                     "    command_to_effort: {value: 2.0}\n";
}

// Tests recording CSVs refused with the line of the sample, not only its number: a non-finite
// position (sample 8 is on line 10: a comment and the header come first) and an irregular time
// step (sample 31 on line 33).
TEST(BadInputEndToEnd, RecordingCsvNamesTheLineOfTheSample) {
  const fs::path dir = Scratch("recording_csv");
  WriteRecording(dir, 7, "nan", 0.0);
  ExpectRefused(dir, "platform identify run.yaml", "run.csv:10: field 'joints[0].position ('x')': expected finite samples, got a non-finite value at sample 8");
  WriteRecording(dir, -1, "", 0.0005);
  ExpectRefused(dir, "platform identify run.yaml", "run.csv:33: field 'time ('t')': expected uniform sampling");
}

// Tests a rating of 1e308 in a ratings file: its line, the field and the scale expected, not a
// parser's message without a file.
TEST(BadInputEndToEnd, RatingOf1e308) {
  const fs::path dir = Scratch("rating");
  std::ofstream(dir / "r.csv") << "participant,condition,rating\nP01,A,1\nP01,B,2\nP02,A,1e308\nP02,B,3\n";
  ExpectRefused(dir, "study r.csv",
                "r.csv:4: field 'rating': expected a number within +-1e6 (a value on a rating scale), got \"1e308\"");
}

}  // namespace
}  // namespace pwsim::app
