// `pwsim drive` on a circuit through the built binary: the defaults its help shows are the ones
// it uses (--can need not be given), a recorded joystick (an R-Net candump log) ends the drive
// when the log ends, no headset latency is printed for --hmd none, the drive writes the figures
// `pwsim run` writes for a circuit; and bad R-Net logs (empty, going back in time, a directory)
// are refused with file, line, field and expectation before any link opens.
// The drive runs against `pwsim platform-sim` on loopback (pw4dof's five drives); the test
// waits for events (the line naming its port, the exits), never for a time, and the session
// runs in lockstep with the drives (--drive-wait-ms), so it holds with both cores busy.

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "tests/hardware/child_process.h"

namespace pwsim::app {
namespace {

namespace fs = std::filesystem;
using test::ChildProcess;

const std::string kPwsim = std::string(PWSIM_BINARY_DIR) + "/pwsim";
const std::string kCircuit = std::string(PWSIM_SOURCE_DIR) + "/scenes/circuit_course.yaml";
const std::string kLog = std::string(PWSIM_SOURCE_DIR) + "/assets/rnet/joystick_synthetic.log";

fs::path Scratch(const std::string& name) {
  const fs::path dir = fs::path(PWSIM_BINARY_DIR) / "test_out" / "drive" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// The log's span [s]: its last timestamp less its first (read here from the file's text).
double LogSpanS(const std::string& file) {
  std::ifstream in(file);
  std::string line;
  double first = -1.0, last = -1.0;
  while (std::getline(in, line)) {
    double t = 0.0;
    if (std::sscanf(line.c_str(), "(%lf)", &t) != 1) continue;
    if (first < 0.0) first = t;
    last = t;
  }
  return last - first;
}

const CommandSpec& DriveSpecOf() {
  for (const Command& command : AllCommands())
    if (command.spec->name == "drive") return *command.spec;
  throw std::invalid_argument("no drive command");
}

// Tests that a circuit drive needs only --joystick: the usage error without it names --can's
// default, the one the help shows.
TEST(DriveCommand, CircuitNeedsOnlyAJoystickAndNamesTheCanDefaultOfItsHelp) {
  std::string can_default;
  for (const OptionSpec& option : DriveSpecOf().options)
    if (option.name == "can") can_default = option.default_value;
  ASSERT_FALSE(can_default.empty());
  const fs::path dir = Scratch("usage");
  ChildProcess drive({kPwsim, "drive", kCircuit, "--out", (dir / "o").string()});
  EXPECT_EQ(drive.Wait(), 2) << drive.Output();
  EXPECT_NE(drive.Output().find("give --joystick SPEC (the live session goes to --can, default " + can_default + ")"),
            std::string::npos)
      << drive.Output();
  EXPECT_EQ(drive.Output().find("and --can"), std::string::npos) << drive.Output();
  EXPECT_FALSE(fs::exists(dir / "o"));
}

// Tests the three R-Net logs that used to "drive" 4.5 s and exit 0: each is refused (exit 1)
// with its file, line, field and expectation, before any link opens or anything is written.
TEST(DriveCommand, RefusesEmptyBackwardsAndDirectoryLogsBeforeAnyLink) {
  const fs::path dir = Scratch("bad_logs");
  std::ofstream(dir / "empty.log").close();
  std::ofstream(dir / "back.log") << "(1700000000.000000) can0 02000000#0000\n"
                                     "(1700000000.010000) can0 02000000#0064\n"
                                     "(1699999999.990000) can0 02000000#0000\n";
  fs::create_directories(dir / "folder.log");
  const struct {
    std::string file, message;
  } cases[] = {
      {"empty.log", "empty.log: field 'frame': expected at least one frame line"},
      {"back.log", "back.log:3: field 'timestamp': expected time that never goes back (line 2 is at "
                   "(1700000000.010000)), got (1699999999.990000)"},
      {"folder.log", "folder.log: field '(file)': expected a candump log (candump -l), got a path that is a directory"},
  };
  for (const auto& c : cases) {
    // a port nobody serves: reaching a link would be a timeout, not this error
    ChildProcess drive({kPwsim, "drive", kCircuit, "--joystick", "rnet-log:" + (dir / c.file).string(), "--hmd",
                        "none", "--can", "udp:127.0.0.1:9", "--out", (dir / "o").string()});
    EXPECT_EQ(drive.Wait(), 1) << c.file << "\n" << drive.Output();
    EXPECT_NE(drive.Output().find(c.message), std::string::npos) << drive.Output();
    EXPECT_EQ(drive.Output().find("platform '"), std::string::npos) << "a link was opened:\n" << drive.Output();
    EXPECT_FALSE(fs::exists(dir / "o")) << c.file;
  }
}

// Tests the circuit drive from a recorded joystick against platform-sim: it ends when the log
// ends (the log's span read from its text, within a tick; the scene runs 60 s), exits 0 parked,
// prints the joystick -> platform latency but no headset latency (--hmd none), counts invalid
// polls only within the log, writes the figures of `pwsim run` beside report.json (the
// joystick track replayed through the chair model is the drive exactly) and its report's
// motion is the log's span.
TEST(DriveCommand, RecordedJoystickEndsTheCircuitDriveAndItsFiguresAreWritten) {
  const fs::path dir = Scratch("circuit");
  ChildProcess platform({kPwsim, "platform-sim", "--platform", std::string(PWSIM_SOURCE_DIR) + "/scenes/platforms/pw4dof.yaml",
                         "--listen", "127.0.0.1:0", "--adopt-first-peer", "--idle-exit", "1"});
  const std::optional<std::string> can_at = platform.WaitForLine("pwsim platform-sim: listening on ");
  ASSERT_TRUE(can_at) << platform.Output();
  ChildProcess drive({kPwsim, "drive", kCircuit, "--joystick", "rnet-log:" + kLog, "--hmd", "none", "--can",
                      "udp:" + *can_at, "--drive-wait-ms", "1000", "--max-stop-s", "10", "--out", (dir / "o").string()});
  const int status = drive.Wait();
  const std::string output = drive.Output();
  platform.Wait();
  ASSERT_EQ(status, 0) << output << "\n--- platform-sim\n" << platform.Output();

  const double span = LogSpanS(kLog);
  ASSERT_GT(span, 1.0);
  const std::size_t ends_at = output.find(" ends at ");
  ASSERT_NE(ends_at, std::string::npos) << output;
  EXPECT_NEAR(std::stod(output.substr(ends_at + 9)), span, 1e-3 + 1e-9) << output;
  EXPECT_NE(output.find("the drive ends with it"), std::string::npos);
  EXPECT_NE(output.find("joystick -> platform command p50 "), std::string::npos) << output;
  EXPECT_EQ(output.find("HMD frame"), std::string::npos) << output;
  EXPECT_NE(output.find("no headset: --hmd none"), std::string::npos) << output;
  EXPECT_NE(output.find("(the joystick track replayed: the drive exactly)"), std::string::npos) << output;

  std::ifstream report_file(dir / "o" / "report.json");
  const nlohmann::json report = nlohmann::json::parse(report_file);
  // the trace covers the drive only: ticks 0..span at 1 kHz
  EXPECT_NEAR(report["chair"]["engine_ticks"].get<double>(), span * 1000.0 + 1.0, 1.5) << report["chair"].dump();
  std::ifstream joystick_file(dir / "o" / "joystick.json");
  const nlohmann::json joystick = nlohmann::json::parse(joystick_file);
  // lost polls only where the log has gaps (its watchdog timeouts), far fewer than the drive's polls
  EXPECT_LT(joystick["invalid_polls"].get<double>(), 0.2 * span * 250.0) << joystick.dump();
  for (const char* figure : {"top_view.png", "wheels.png", "mca.png", "mca_lateral.png", "top_view.plot.csv"}) {
    EXPECT_TRUE(fs::exists(dir / "o" / figure)) << figure << "\n" << output;
    if (std::string(figure).find(".png") != std::string::npos) {
      EXPECT_NE(output.find((dir / "o" / figure).string()), std::string::npos) << figure << " not listed";
    }
  }
}

/// The rows of a CSV file with a header, as name -> text.
std::vector<std::map<std::string, std::string>> ReadCsvRows(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::vector<std::string> names;
  std::vector<std::map<std::string, std::string>> rows;
  auto split = [](const std::string& text) {
    std::vector<std::string> cells;
    std::string cell;
    bool quoted = false;
    for (char c : text) {
      if (c == '"') quoted = !quoted;
      else if (c == ',' && !quoted) cells.push_back(std::exchange(cell, ""));
      else cell += c;
    }
    cells.push_back(cell);
    return cells;
  };
  if (std::getline(in, line)) names = split(line);
  while (std::getline(in, line)) {
    const std::vector<std::string> cells = split(line);
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < names.size() && i < cells.size(); ++i) row[names[i]] = cells[i];
    rows.push_back(std::move(row));
  }
  return rows;
}

// Tests that a car drive (the scene's own controls, not real time) draws the figure `pwsim run`
// draws for a car, of the car as driven: mca.png's rail position is drive.csv's platform
// command at every plotted time, exactly; into a folder where `study plan` wrote, the drive
// leaves none of the plan's files and lists its own.
TEST(DriveCommand, CarDriveDrawsTheCueingFigureOfTheDrive) {
  const fs::path dir = Scratch("car");
  ChildProcess plan({kPwsim, "study", "plan", "--out", (dir / "o").string()});  // another command's outputs there
  ASSERT_EQ(plan.Wait(), 0) << plan.Output();
  ASSERT_TRUE(fs::exists(dir / "o" / "plan.csv"));
  ChildProcess drive({kPwsim, "drive", std::string(PWSIM_SOURCE_DIR) + "/scenes/car_launch.yaml", "--no-realtime",
                      "--duration", "6", "--out", (dir / "o").string()});
  ASSERT_EQ(drive.Wait(), 0) << drive.Output();
  ASSERT_TRUE(fs::exists(dir / "o" / "mca.png")) << drive.Output();
  // the drive replaced the plan's files and lists its own (app/output_folder.h)
  EXPECT_FALSE(fs::exists(dir / "o" / "plan.csv"));
  EXPECT_FALSE(fs::exists(dir / "o" / "ratings_template.csv"));
  for (const char* file : {"drive.csv", "mca.png", "mca.svg"})
    EXPECT_NE(drive.Output().find("  " + (dir / "o" / file).string() + "\n"), std::string::npos) << file << drive.Output();
  std::map<long, double> command;  // by tick (1 kHz)
  for (const auto& row : ReadCsvRows(dir / "o" / "drive.csv"))
    command[std::lround(std::stod(row.at("t_s")) * 1000.0)] = std::stod(row.at("plat_surge_m"));
  int compared = 0;
  double largest = 0.0, moved = 0.0;
  for (const auto& row : ReadCsvRows(dir / "o" / "mca.plot.csv")) {
    if (row.at("series") != "rail position") continue;
    const auto at = command.find(std::lround(std::stod(row.at("x")) * 1000.0));
    ASSERT_NE(at, command.end()) << row.at("x");
    largest = std::max(largest, std::abs(std::stod(row.at("y")) - at->second));
    moved = std::max(moved, std::abs(at->second));
    ++compared;
  }
  EXPECT_GT(compared, 500);
  EXPECT_GT(moved, 0.05);  // the launch moves the rail: the comparison is not of zeros
  EXPECT_EQ(largest, 0.0);
}

}  // namespace
}  // namespace pwsim::app
