// The command line's one convention (app/cli.h): suggestions for misspelt options and commands,
// a single "pwsim COMMAND:" prefix, --help without "default: none" or "unit: -", the --out rule
// shared by every command, --version, options checked before anything is written; and bad
// input files refused through the built binary with file, line, field and expectation.

#include "app/cli.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "app/commands.h"
#include "app/output_folder.h"
#include "engine/input_error.h"
#include "tests/app/pwsim_run.h"
#include "tests/hardware/session_world.h"

namespace pwsim::app {
namespace {

namespace fs = std::filesystem;

using Result = test::PwsimResult;

fs::path Scratch(const std::string& name) { return test::FreshTestFolder("cli", name); }

/// Runs the built pwsim in `cwd` (stdout and stderr together).
Result Pwsim(const std::string& args, const fs::path& cwd) { return test::RunPwsim(args, cwd, true); }



std::size_t Count(const std::string& text, const std::string& part) {
  std::size_t n = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

const CommandSpec& SpecOf(const std::string& name) {
  for (const Command& command : AllCommands()) {
    if (command.spec->name == name) return *command.spec;
  }
  throw std::invalid_argument("no command " + name);
}

// Tests the edit distance on pairs whose distance is known by hand: a transposition counts 1
// (optimal string alignment), the classic kitten/sitting is 3, an empty word is its length.
TEST(CliSuggest, EditDistanceCountsATranspositionAsOne) {
  EXPECT_EQ(EditDistance("no-vidoe", "no-video"), 1);
  EXPECT_EQ(EditDistance("kitten", "sitting"), 3);
  EXPECT_EQ(EditDistance("", "abc"), 3);
  EXPECT_EQ(EditDistance("run", "run"), 0);
  EXPECT_EQ(EditDistance("ca", "abc"), 3);  // OSA: no edit of a transposed pair
}

// Tests that a misspelt option or command gets the intended one, a unique prefix completes,
// and a word far from every candidate gets no suggestion.
TEST(CliSuggest, SuggestsTheNearestOrTheUniquePrefixOrNothing) {
  std::vector<std::string> run_options;
  for (const OptionSpec& option : RunSpec().options) run_options.push_back(option.name);
  EXPECT_EQ(Suggest("no-vidoe", run_options), "no-video");
  EXPECT_EQ(Suggest("no-vid", run_options), "no-video");
  EXPECT_EQ(Suggest("decimat", run_options), "decimate");
  EXPECT_EQ(Suggest("xyzzy", run_options), "");
  std::vector<std::string> commands;
  for (const Command& command : AllCommands()) commands.push_back(command.spec->name);
  EXPECT_EQ(Suggest("rn", commands), "run");
  EXPECT_EQ(Suggest("sweeep", commands), "sweep");
  EXPECT_EQ(Suggest("identfy", commands), "identify");
  EXPECT_EQ(DidYouMean("no-vidoe", run_options, "--"), "; did you mean --no-video?");
  EXPECT_EQ(DidYouMean("qqqqqqq", run_options, "--"), "");
}

// Tests the parser's message for an unknown option: the suggestion, and no "pwsim" prefix of
// its own (main adds it once).
TEST(CliParse, UnknownOptionSuggestsAndCarriesNoPrefix) {
  try {
    Parse(RunSpec(), {"--no-vidoe"});
    FAIL() << "no usage error";
  } catch (const UsageError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("unknown option --no-vidoe; did you mean --no-video?"), std::string::npos) << message;
    EXPECT_EQ(message.find("pwsim run:"), std::string::npos) << message;
  }
}

// Tests every command's --help: flags show no unit or default, no option shows "default:
// none", "off" or the unit "-", and an option with a unit and a default shows both.
TEST(CliHelp, FlagsBareNoNoneNoDashUnits) {
  for (const Command& command : AllCommands()) {
    const std::string help = HelpText(*command.spec);
    SCOPED_TRACE(command.spec->name);
    EXPECT_EQ(help.find("default: none"), std::string::npos) << help;
    EXPECT_EQ(help.find("default: off"), std::string::npos) << help;
    EXPECT_EQ(help.find("unit: -]"), std::string::npos) << help;
    EXPECT_EQ(help.find("unit: -;"), std::string::npos) << help;
    std::istringstream lines(help);
    for (std::string line; std::getline(lines, line);) {
      for (const OptionSpec& option : command.spec->options) {
        if (!option.value_name.empty() || line.rfind("  --" + option.name + " ", 0) != 0) continue;
        EXPECT_EQ(line.find('['), std::string::npos) << "flag line: " << line;
      }
    }
  }
  const std::string run = HelpText(RunSpec());
  EXPECT_NE(run.find("[unit: ticks; default: 1]"), std::string::npos) << run;
  EXPECT_NE(run.find("[default: out/run]"), std::string::npos) << run;
}

// Tests the --out rule: every command that takes --out defaults to out/COMMAND (platform, whose
// sub-commands write different things, to out/platform-SUB), --out DIR wins, and an empty
// --out is a usage error.
TEST(CliOut, EveryCommandFollowsOneRule) {
  int with_out = 0;
  for (const Command& command : AllCommands()) {
    const std::string& name = command.spec->name;
    for (const OptionSpec& option : command.spec->options) {
      if (option.name != "out") continue;
      ++with_out;
      SCOPED_TRACE(name);
      EXPECT_EQ(option.value_name, "DIR");
      if (name == "platform") {
        EXPECT_EQ(option.default_value, "");
        EXPECT_EQ(OutDir(Parse(*command.spec, {"identify"}), "identify"), fs::path("out/platform-identify"));
      } else {
        EXPECT_EQ(option.default_value, "out/" + name);
        EXPECT_EQ(OutDir(Parse(*command.spec, {})), fs::path("out/" + name));
      }
      EXPECT_EQ(OutDir(Parse(*command.spec, {"--out", "elsewhere/x"})), fs::path("elsewhere/x"));
      EXPECT_THROW(OutDir(Parse(*command.spec, {"--out="})), UsageError);
    }
  }
  EXPECT_GE(with_out, 12);
  EXPECT_EQ(OutDir(Parse(SpecOf("study"), {"plan"}), "plan"), fs::path("out/study-plan"));
}

// Tests --version: the project version, then git's description and a full commit hash (or
// "unknown" outside a checkout), through the binary as a user types it.
TEST(CliEndToEnd, VersionNamesTheProjectVersionAndCommit) {
  const fs::path dir = Scratch("version");
  const Result result = Pwsim("--version", dir);
  EXPECT_EQ(result.status, 0) << result.output;
  const std::regex form(R"(^pwsim \d+\.\d+\.\d+ \(git [^,]+, commit ([0-9a-f]{40}|unknown)\)\n$)");
  EXPECT_TRUE(std::regex_match(result.output, form)) << result.output;
  // the same version as the library this test links (the git part may be newer in the binary)
  EXPECT_EQ(result.output.substr(0, result.output.find(" (git ")), VersionText().substr(0, VersionText().find(" (git ")));
}

// Tests the issue's own example: one "pwsim run:" prefix, the suggestion, usage status 2; and
// a misspelt command.
TEST(CliEndToEnd, MisspeltOptionAndCommandGetOnePrefixAndASuggestion) {
  const fs::path dir = Scratch("misspelt");
  const Result option = Pwsim("run --no-vidoe", dir);
  EXPECT_EQ(option.status, 2) << option.output;
  EXPECT_EQ(Count(option.output, "pwsim run:"), 1u) << option.output;
  EXPECT_NE(option.output.find("pwsim run: unknown option --no-vidoe; did you mean --no-video?"), std::string::npos)
      << option.output;
  const Result command = Pwsim("rn --no-video", dir);
  EXPECT_EQ(command.status, 2) << command.output;
  EXPECT_NE(command.output.find("unknown command 'rn'; did you mean run?"), std::string::npos) << command.output;
  const Result sub = Pwsim("sweep plna x.yaml", dir);
  EXPECT_EQ(sub.status, 2) << sub.output;
  EXPECT_NE(sub.output.find("did you mean plan?"), std::string::npos) << sub.output;
  const Result study = Pwsim("study metrcs runs.csv", dir);
  EXPECT_EQ(study.status, 2) << study.output;
  EXPECT_NE(study.output.find("pwsim study: no ratings file 'metrcs'; did you mean metrics?"), std::string::npos)
      << study.output;
}

// Tests that `pwsim run --fps 33 --no-video` is refused before anything is simulated or
// written (33 does not divide the scene's 1000 Hz clock), naming the option and the rate.
TEST(CliEndToEnd, RunChecksFpsBeforeWritingAnything) {
  const fs::path dir = Scratch("fps");
  const Result result =
      Pwsim(std::string("run ") + PWSIM_SOURCE_DIR + "/scenes/speed_cushion.yaml --fps 33 --no-video --out o", dir);
  EXPECT_EQ(result.status, 2) << result.output;
  EXPECT_NE(result.output.find("option --fps: expected a divisor of the clock rate 1000 Hz of the scene"),
            std::string::npos)
      << result.output;
  EXPECT_FALSE(fs::exists(dir / "o")) << "the refused run left " << (dir / "o");
}

// Tests the --out default end to end: without --out, `study plan` writes into out/study-plan
// of the working directory.
TEST(CliEndToEnd, DefaultOutFolderIsOutSlashCommand) {
  const fs::path dir = Scratch("default_out");
  const Result result = Pwsim("study plan --participants 4", dir);
  ASSERT_EQ(result.status, 0) << result.output;
  EXPECT_TRUE(fs::exists(dir / "out" / "study-plan" / "plan.csv")) << result.output;
}

void Touch(const fs::path& file, const std::string& text = "x") {
  fs::create_directories(file.parent_path());
  std::ofstream(file) << text;
}

// Tests the output-folder rule: a second command removes every file the first one recorded
// (here a chair run's visual_check.* and a plots/ folder) and nothing else (a file of the
// user's stays), lists exactly what it wrote, and a command that fails leaves no record and
// none of its partial outputs.
TEST(CliOutputFolder, ReplacesWhatTheLastCommandWroteAndNothingElse) {
  const fs::path dir = Scratch("output_folder") / "out";
  Touch(dir / "notes.txt", "the user's own");
  {
    OutputFolder chair(dir, "run");
    Touch(dir / "summary.json", "chair");
    Touch(dir / "visual_check.png");
    Touch(dir / "visual_check.csv");
    Touch(dir / "plots" / "a.png");
    const auto& written = chair.Commit();
    EXPECT_EQ(written, (std::vector<fs::path>{dir / "plots/a.png", dir / "summary.json", dir / "visual_check.csv",
                                              dir / "visual_check.png"}));
  }
  {
    OutputFolder car(dir, "run");
    EXPECT_EQ(car.removed(), (std::vector<fs::path>{"plots/a.png", "summary.json", "visual_check.csv",
                                                    "visual_check.png"}));
    EXPECT_FALSE(fs::exists(dir / "visual_check.png"));
    EXPECT_FALSE(fs::exists(dir / "plots"));
    EXPECT_TRUE(fs::exists(dir / "notes.txt"));
    Touch(dir / "summary.json", "car");
    std::ostringstream printed;
    car.Print(printed, "pwsim run");
    EXPECT_EQ(printed.str(), "pwsim run: wrote 1 file in " + dir.string() + ":\n  " + (dir / "summary.json").string() + "\n");
  }
  std::ifstream record(dir / OutputFolder::kRecord);
  std::stringstream text;
  text << record.rdbuf();
  EXPECT_NE(text.str().find("\"files\": [\n  \"summary.json\"\n ]"), std::string::npos) << text.str();
  try {
    OutputFolder failing(dir, "generate");
    Touch(dir / "trial_1" / "trial.yaml");
    throw std::runtime_error("simulated failure");
  } catch (const std::runtime_error&) {
  }
  EXPECT_FALSE(fs::exists(dir / "trial_1"));
  EXPECT_FALSE(fs::exists(dir / "summary.json"));  // the last complete run's outputs went first
  EXPECT_FALSE(fs::exists(dir / OutputFolder::kRecord));
  EXPECT_TRUE(fs::exists(dir / "notes.txt"));
}

// Tests that a record naming a path outside the folder is refused, not followed.
TEST(CliOutputFolder, ARecordNamingAPathOutsideIsRefused) {
  const fs::path dir = Scratch("output_folder_escape");
  Touch(dir / "keep.txt");
  Touch(dir / "out" / OutputFolder::kRecord, R"({"format": "pwsim-outputs/1", "files": ["../keep.txt"]})");
  EXPECT_THROW(OutputFolder(dir / "out", "run"), InputError);
  EXPECT_TRUE(fs::exists(dir / "keep.txt"));
}

std::string ReadText(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Tests pwsim replay's exit codes on a real session log (the in-process session of the
// hardware tests): 0 when it replays, 3 for a tampered output (a real mismatch), 1 with the
// file and line for a malformed record, 1 for a directory.
TEST(CliEndToEnd, ReplayTellsACorruptLogFromAMismatch) {
  const fs::path dir = Scratch("replay");
  hw::session_testing::World world(1500);
  world.Finish();
  const std::string log = world.LogText();
  std::ofstream(dir / "session.log") << log;
  const Result good = Pwsim("replay session.log", dir);
  EXPECT_EQ(good.status, 0) << good.output;

  std::string tampered = log;
  const std::size_t s_line = tampered.find("\nS 800 ");
  ASSERT_NE(s_line, std::string::npos);
  const std::size_t digit = tampered.find_first_of("123456789", s_line + 10);
  tampered[digit] = tampered[digit] == '9' ? '8' : static_cast<char>(tampered[digit] + 1);
  std::ofstream(dir / "tampered.log") << tampered;
  const Result mismatch = Pwsim("replay tampered.log", dir);
  EXPECT_EQ(mismatch.status, 3) << mismatch.output;
  EXPECT_NE(mismatch.output.find("pwsim replay: MISMATCH in tampered.log: line "), std::string::npos)
      << mismatch.output;

  std::string corrupt = log;
  const std::size_t t_line = corrupt.find("\nT 700 ");
  ASSERT_NE(t_line, std::string::npos);
  corrupt.replace(t_line + 1, 5, "T 7x0");
  const int line = 2 + static_cast<int>(std::count(corrupt.begin(), corrupt.begin() + static_cast<long>(t_line), '\n'));
  std::ofstream(dir / "corrupt.log") << corrupt;
  const Result bad = Pwsim("replay corrupt.log", dir);
  EXPECT_EQ(bad.status, 1) << bad.output;
  EXPECT_NE(bad.output.find("pwsim replay: error: corrupt.log:" + std::to_string(line) +
                            ": field 'record': expected a well-formed session log"),
            std::string::npos)
      << bad.output;
  EXPECT_NE(bad.output.find("bad T record in \"T 7x0"), std::string::npos) << bad.output;
  const Result folder = Pwsim("replay .", dir);
  EXPECT_EQ(folder.status, 1) << folder.output;
  EXPECT_NE(folder.output.find("got a path that is a directory"), std::string::npos) << folder.output;
}

// Tests bad measured-trial input through the binary: a QTM export whose FREQUENCY (50 Hz)
// contradicts its Time column (100 Hz) stops pwsim identify at that header line, and the
// refused run leaves no output folder.
TEST(CliEndToEnd, IdentifyRefusesAQtmFrequencyThatContradictsItsTimeColumn) {
  const fs::path dir = Scratch("qtm_frequency");
  fs::copy(fs::path(PWSIM_SOURCE_DIR) / "assets/trials-demo/qtm_v1.20_m50_cushion_r1", dir / "trial");
  std::string tsv = ReadText(dir / "trial" / "mocap.tsv");
  ASSERT_NE(tsv.find("FREQUENCY\t100\n"), std::string::npos);
  tsv.replace(tsv.find("FREQUENCY\t100\n"), 14, "FREQUENCY\t50\n");
  std::ofstream(dir / "trial" / "mocap.tsv") << tsv;
  const Result result = Pwsim("identify trial --out o", dir);
  EXPECT_EQ(result.status, 1) << result.output;
  EXPECT_NE(result.output.find("mocap.tsv:4: field 'FREQUENCY': expected the frame rate of the Time column, 100 Hz"),
            std::string::npos)
      << result.output;
  EXPECT_FALSE(fs::exists(dir / "o"));
}

// Tests the issue's case end to end: a car run into the folder of a chair run leaves exactly
// the car's files (each listed in the car's record and in its printed list), none of the
// chair's, and the user's own file.
TEST(CliEndToEnd, CarRunAfterAChairRunLeavesOnlyTheCarsOutputs) {
  const fs::path dir = Scratch("chair_then_car");
  fs::create_directories(dir / "o");
  std::ofstream(dir / "o" / "notes.txt") << "mine";
  // a small video, so the chair run writes its visual_check.* (the car writes none)
  const Result chair = Pwsim(std::string("run ") + PWSIM_SOURCE_DIR +
                                 "/scenes/speed_cushion.yaml --size 64x36 --fps 10 --decimate 20 --out o",
                             dir);
  ASSERT_EQ(chair.status, 0) << chair.output;
  ASSERT_TRUE(fs::exists(dir / "o" / "visual_check.png")) << chair.output;

  const Result car = Pwsim(std::string("run ") + PWSIM_SOURCE_DIR + "/scenes/car_launch.yaml --no-video --decimate 20 --out o", dir);
  ASSERT_EQ(car.status, 0) << car.output;
  for (const char* stale : {"visual_check.png", "visual_check.csv", "visual_check.svg", "video.mp4", "frames.csv"}) {
    EXPECT_FALSE(fs::exists(dir / "o" / stale)) << stale << " of the chair run is still there";
  }
  EXPECT_TRUE(fs::exists(dir / "o" / "notes.txt"));
  const std::string car_record = ReadText(dir / "o" / OutputFolder::kRecord);
  int files = 0;
  for (const auto& entry : fs::directory_iterator(dir / "o")) {
    const std::string name = entry.path().filename().string();
    if (name == "notes.txt" || name == OutputFolder::kRecord) continue;
    ++files;
    EXPECT_NE(car_record.find("\"" + name + "\""), std::string::npos) << name << " is not the car's";
    EXPECT_NE(car.output.find("  o/" + name + "\n"), std::string::npos) << name << " not listed:\n" << car.output;
  }
  EXPECT_GE(files, 3);
  EXPECT_NE(car.output.find("pwsim run: wrote " + std::to_string(files) + " files in o:"), std::string::npos)
      << car.output;
}

}  // namespace
}  // namespace pwsim::app
