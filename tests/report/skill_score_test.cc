// The power-mobility skill items (report/skill_score.h, report/skill_sheet.h, scenes/skills/):
// every shipped item driven by its own script reaches its goal cleanly and scores pass; a drive
// into the door frame and a drive that tips fail with their reason; a contact or a near-tip on
// the way grades pass with difficulty; the score sheet of two sessions of real run outputs and
// its comparison; the sheet through the study's statistics; bad inputs refused with file,
// field and what was expected.
#include "report/skill_score.h"
#include "report/skill_sheet.h"

#include <gtest/gtest.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <cstdio>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "engine/input_error.h"
#include "engine/scene.h"
#include "hardware/chair_drive_source.h"
#include "hardware/rnet_joystick.h"
#include "hardware/session_streams.h"
#include "report/run_circuit.h"
#include "report/training_report.h"

namespace pwsim::report {
namespace {

namespace fs = std::filesystem;

const fs::path kSkills = fs::path(PWSIM_SOURCE_DIR) / "scenes/skills";

fs::path Scratch(const std::string& name) {
  const fs::path dir = fs::path(PWSIM_BINARY_DIR) / "skill_score_test" / (name + "-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string Text(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The item's YAML with `from` replaced by `to` (once), as a scene beside the shipped ones (so
/// its relative paths resolve).
Scene Variant(const std::string& item, const std::string& from, const std::string& to) {
  std::string text = Text(kSkills / (item + ".yaml"));
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return ParseScene(text, kSkills / (item + "_variant.yaml"));
}

struct Scored {
  SkillSpec spec;
  SkillScore score;
};

Scored Drive(const Scene& scene) {
  const std::optional<SkillSpec> spec = SkillOf(scene);
  EXPECT_TRUE(spec.has_value());
  const std::vector<TrainingTick> trace = TrainingTrace(scene, SimulateCircuitScene(scene));
  return {*spec, ScoreSkill(*spec, *scene.circuit, trace, scene.clock.dt())};
}

std::vector<fs::path> ShippedItems() {
  std::vector<fs::path> items;
  for (const auto& entry : fs::directory_iterator(kSkills)) {
    if (entry.path().extension() == ".yaml") items.push_back(entry.path());
  }
  std::sort(items.begin(), items.end());
  return items;
}

TEST(SkillItemsTest, AtLeastTenItemsShipEachAScoredCircuit) {
  const std::vector<fs::path> items = ShippedItems();
  ASSERT_GE(items.size(), 10u);
  for (const fs::path& file : items) {
    const Scene scene = LoadScene(file);
    ASSERT_TRUE(scene.is_circuit()) << file;
    const std::optional<SkillSpec> spec = SkillOf(scene);
    ASSERT_TRUE(spec.has_value()) << file;
    EXPECT_EQ(spec->item, file.stem().string()) << "the item is named after its file";
    EXPECT_NE(spec->source.find("WST"), std::string::npos) << file;
  }
}

// Each item's own script (the closed-loop driver or its joystick table) completes the item
// without touching anything: pass, with the time the goal was reached inside the drive.
TEST(SkillItemsTest, EveryShippedItemsScriptedDriveScoresPass) {
  for (const fs::path& file : ShippedItems()) {
    const Scene scene = LoadScene(file);
    const Scored s = Drive(scene);
    EXPECT_EQ(s.score.level, SkillLevel::kPass) << file.filename() << ": " << s.score.reason;
    ASSERT_TRUE(s.score.time_s.has_value()) << file;
    EXPECT_GT(*s.score.time_s, 0.0);
    EXPECT_LT(*s.score.time_s, scene.circuit->duration);
    EXPECT_EQ(s.score.gates_passed, s.score.gates_total);
    EXPECT_TRUE(s.score.contacts.empty());
    if (s.spec.turn_deg > 0.0) {
      EXPECT_GE(std::abs(s.score.turned_deg), s.spec.turn_deg) << file;
    }
    EXPECT_EQ(SkillScoreLine(s.spec, s.score).rfind("skill " + s.spec.item + ": pass (goal reached at ", 0), 0u);
  }
}

// The doorway driven 0.25 m off its centre line: the chair's 0.34 m half-width meets the left
// frame of the 0.815 m opening, the chair stops there (circuit.h), the goal is not reached.
TEST(SkillItemsTest, DriveIntoTheDoorFrameFailsNamingTheFrame) {
  const Scene scene = Variant("wst_gets_through_doorway", "driver: {speed_mps: 0.8, lookahead_m: 0.9}",
                              "driver: {speed_mps: 0.8, lookahead_m: 0.9, path_m: [[0, 0], [1, 0.25], [7, 0.25]]}");
  const Scored s = Drive(scene);
  EXPECT_EQ(s.score.level, SkillLevel::kFail);
  ASSERT_FALSE(s.score.contacts.empty());
  EXPECT_EQ(s.score.contacts.front().what, "door_frame_left");
  EXPECT_GT(s.score.contacts.front().speed_mps, 0.1);  // driven into it, not brushed
  EXPECT_EQ(s.score.gates_passed, 0);
  EXPECT_NE(s.score.reason.find("not reached"), std::string::npos) << s.score.reason;
  EXPECT_NE(s.score.reason.find("door_frame_left"), std::string::npos) << s.score.reason;
}

// A driver who starts 0.15 m left of the doorway's axis, drives into the left frame at 0.59 m/s,
// backs off 0.9 m, turns right, moves over, turns back and passes: the goal is reached with one
// contact, pass with difficulty, and the reason names the frame, the time and the speed.
TEST(SkillItemsTest, BumpingTheDoorFrameThenPassingIsPassWithDifficulty) {
  const std::string table =
      "table:\n"
      "      - [0.0, 0.0, 0.0]\n      - [0.5, 0.4, 0.0]\n      - [4.4, 0.4, 0.0]\n      - [4.6, 0.0, 0.0]\n"
      "      - [5.0, -0.4, 0.0]\n      - [9.0, -0.4, 0.0]\n      - [9.2, 0.0, 0.0]\n"      // back off
      "      - [9.4, 0.0, -0.3]\n      - [10.0, 0.0, -0.3]\n      - [10.2, 0.0, 0.0]\n"     // turn right
      "      - [10.6, 0.4, 0.0]\n      - [11.6, 0.4, 0.0]\n      - [11.8, 0.0, 0.0]\n"     // move over
      "      - [12.2, 0.0, 0.3]\n      - [12.55, 0.0, 0.3]\n      - [12.75, 0.0, 0.0]\n"    // turn back
      "      - [13.4, 0.4, 0.0]\n      - [20.0, 0.4, 0.0]\n      - [20.3, 0.0, 0.0]";     // through
  std::string text = Text(kSkills / "wst_gets_through_doorway.yaml");
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"driver: {speed_mps: 0.8, lookahead_m: 0.9}", table},
                                 {"position_m: [0, 0]", "position_m: [0, 0.15]"},
                                 {"duration_s: 15", "duration_s: 24"}}) {
    const std::size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  }
  const Scored s = Drive(ParseScene(text, kSkills / "wst_gets_through_doorway_bumped.yaml"));
  EXPECT_EQ(s.score.level, SkillLevel::kPassWithDifficulty) << s.score.reason;
  ASSERT_EQ(s.score.contacts.size(), 1u) << s.score.reason;
  EXPECT_EQ(s.score.contacts[0].what, "door_frame_left");
  EXPECT_GT(s.score.contacts[0].speed_mps, 0.5);
  // the chair's front (0.63 m ahead of O_V) meets the frame's face (2.95 m) after 2.32 m at 0.59 m/s
  EXPECT_NEAR(s.score.contacts[0].t_s, 0.5 + 2.32 / 0.59, 0.5);
  ASSERT_TRUE(s.score.time_s.has_value());
  EXPECT_GT(*s.score.time_s, 13.4);  // after the second approach
  EXPECT_NE(s.score.reason.find("with 1 contact (door_frame_left at t = "), std::string::npos) << s.score.reason;
}

// The 5 cm level change raised to 0.35 m under the left wheels only: the floor rolls the chair by
// asin(0.35 / 0.56) = 39 deg, beyond its static roll limit atan(0.28 / 0.43) = 33 deg (half track
// over the centre of mass height): it tips over, and the item fails for that.
TEST(SkillItemsTest, ATipOverFailsWithItsTime) {
  const Scene scene = Variant("wst_ascends_level_change",
                              "{bump: {name: level_change, x_m: [3, 30], y_m: [-2, 2], height_m: 0.05, ramp_m: 0}}",
                              "{bump: {name: level_change, x_m: [3, 30], y_m: [0, 2], height_m: 0.35, ramp_m: 0.3}}");
  const Scored s = Drive(scene);
  EXPECT_EQ(s.score.level, SkillLevel::kFail);
  ASSERT_TRUE(s.score.tip_over_t_s.has_value()) << s.score.reason;
  EXPECT_EQ(s.score.reason.rfind("the chair tipped over at t = ", 0), 0u) << s.score.reason;
}

// `pwsim run` on an item (RunCircuitScene, without video): score.json beside summary.json, the
// console line, and the same level as the trace scored directly.
TEST(SkillItemsTest, PwsimRunWritesTheScoreAndItsLine) {
  const fs::path out = Scratch("run");
  const Scene scene = LoadScene(kSkills / "wst_turns_180_in_place.yaml");
  RenderStageOptions render;
  render.no_video = true;
  McaChoice mca;
  mca.compare = false;
  std::string line;
  const std::vector<fs::path> written = RunCircuitScene(scene, "scenes/skills/wst_turns_180_in_place.yaml", 10, render,
                                                        out, mca, &line);
  EXPECT_NE(std::find(written.begin(), written.end(), out / "score.json"), written.end());
  EXPECT_EQ(line.rfind("skill wst_turns_180_in_place: pass (goal reached at ", 0), 0u) << line;
  std::ifstream in(out / "score.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["format"], "pwsim-skill-score/1");
  EXPECT_EQ(j["level"], "pass");
  EXPECT_EQ(j["score"], 2);
  EXPECT_EQ(j["scene"], "scenes/skills/wst_turns_180_in_place.yaml");
  EXPECT_GE(j["turned_deg"].get<double>(), 180.0);
  EXPECT_EQ(j["contacts"]["count"], 0);
  EXPECT_TRUE(j["deviation_m"].is_null());  // no gates, no route: turning in place
}

/// A candump log of an R-Net joystick (hardware/rnet_joystick.h: 0x02000000#XxYy, signed
/// percent, every 10 ms) held at (x, y) % for `seconds`, then centred for 2 s.
fs::path RnetLog(const fs::path& dir, const std::string& name, int x, int y, double seconds) {
  const fs::path file = dir / (name + ".log");
  std::ofstream log(file);
  char line[96];
  for (int k = 0; k * 0.01 < seconds + 2.0; ++k) {
    const bool held = k * 0.01 < seconds;
    const int bx = held ? x : 0, by = held ? y : 0;
    const long long us = 1700000000LL * 1000000 + 10000LL * k + 250;
    std::snprintf(line, sizeof line, "(%lld.%06lld) can0 02000000#%02X%02X\n", us / 1000000, us % 1000000, bx & 0xFF,
                  by & 0xFF);
    log << line;
  }
  return file;
}

/// The doorway driven live (hardware/chair_drive_source.h, the drive source of `pwsim drive`)
/// by a recorded R-Net joystick, session steps every 2 ticks; its trace scored as the drive
/// scores it (ScoreSkillItem).
nlohmann::json LiveDoorway(const fs::path& dir, const std::string& name, int x, int y) {
  const Scene scene = LoadScene(kSkills / "wst_gets_through_doorway.yaml");
  const std::int64_t ticks = scene.clock.TicksFor(10.0);
  hw::RnetLogJoystick joystick(hw::ReadCandumpFile(RnetLog(dir, name, x, y, 8.0)), scene.clock.rate_hz, {-1, 100},
                               name);
  hw::ChairDriveSource source(scene, joystick, ticks, hw::SessionMcaConfig(scene));
  for (std::int64_t tick = 0; tick <= ticks; tick += 2) {
    hw::SessionInputs in;
    source.Fill(tick, tick % 4 == 0, false, tick, &in);
  }
  EXPECT_FALSE(ScoreSkillItem(scene, "live", source.trace(), dir / name).empty());
  std::ifstream in(dir / name / "score.json");
  return nlohmann::json::parse(in);
}

// A live drive scores the same way: straight through the doorway at 50 % forward passes; pushed
// 15 % to the right as well, the chair curves into the right frame and fails, naming it.
TEST(SkillItemsTest, LiveDrivesAreScoredTheSameWay) {
  const fs::path dir = Scratch("live");
  const nlohmann::json straight = LiveDoorway(dir, "straight", 0, 50);
  EXPECT_EQ(straight["level"], "pass") << straight["reason"];
  EXPECT_EQ(straight["contacts"]["count"], 0);
  const nlohmann::json veer = LiveDoorway(dir, "veer", 15, 50);
  EXPECT_EQ(veer["level"], "fail") << veer["reason"];
  ASSERT_GE(veer["contacts"]["count"].get<int>(), 1);
  EXPECT_EQ(veer["contacts"]["events"][0]["what"], "door_frame_right") << veer["reason"];
}

/// A trace over a straight route through one gate at x = 2 m (the circuit below), 1 m/s.
std::vector<TrainingTick> StraightTrace(double dt, double end_s) {
  std::vector<TrainingTick> trace;
  for (int k = 0; k * dt <= end_s + 1e-12; ++k) {
    TrainingTick t;
    t.t = k * dt;
    t.x = t.t;
    t.gates_passed = t.x > 2.0 ? 1 : 0;
    trace.push_back(t);
  }
  return trace;
}

CircuitSpec GateCircuit() {
  CircuitSpec circuit;
  circuit.gates.push_back({"line", {2.0, 1.0}, {2.0, -1.0}});
  Wall wall;
  wall.name = "side_wall";
  wall.from = {-1.0, 0.45};
  wall.to = {5.0, 0.45};
  wall.thickness = 0.1;
  circuit.walls.push_back(wall);
  return circuit;
}

// The rule on hand-made traces: a contact or a near-tip before the goal grades pass with
// difficulty and is named in the reason; the same after the goal is outside the window.
TEST(SkillRuleTest, ContactOrNearTipBeforeTheGoalIsPassWithDifficulty) {
  const CircuitSpec circuit = GateCircuit();
  SkillSpec spec{"line", "Crosses a line", "test", 0.0, 0};
  const double dt = 0.01;
  std::vector<TrainingTick> trace = StraightTrace(dt, 4.0);
  EXPECT_EQ(ScoreSkill(spec, circuit, trace, dt).level, SkillLevel::kPass);
  // a contact begins at t = 1 s, the footprint's left edge 5 mm short of the wall's face (the
  // blocked pose: a tick short of the wall)
  std::vector<TrainingTick> touched = trace;
  for (std::size_t k = 100; k < touched.size(); ++k) {
    touched[k].contact_events = 1;
    touched[k].last_contact_speed = 0.37;
  }
  touched[100].y = 0.4 - 0.34 + 0.005;
  const SkillScore s = ScoreSkill(spec, circuit, touched, dt);
  EXPECT_EQ(s.level, SkillLevel::kPassWithDifficulty);
  ASSERT_EQ(s.contacts.size(), 1u);
  EXPECT_DOUBLE_EQ(s.contacts[0].t_s, 1.0);
  EXPECT_DOUBLE_EQ(s.contacts[0].speed_mps, 0.37);
  EXPECT_EQ(s.contacts[0].what, "side_wall");
  EXPECT_NE(s.reason.find("1 contact (side_wall at t = 1.00 s, 0.37 m/s)"), std::string::npos) << s.reason;
  // a near-tip at t = 1.5 s
  std::vector<TrainingTick> tipped = trace;
  for (std::size_t k = 150; k < 160; ++k) tipped[k].on_anti_tip = true;
  const SkillScore n = ScoreSkill(spec, circuit, tipped, dt);
  EXPECT_EQ(n.level, SkillLevel::kPassWithDifficulty);
  EXPECT_NE(n.reason.find("1 near-tip (on the anti-tip wheels at t = 1.50 s)"), std::string::npos) << n.reason;
  // both after the goal (t = 2.01 s): not scored
  std::vector<TrainingTick> late = trace;
  for (std::size_t k = 300; k < late.size(); ++k) {
    late[k].contact_events = 1;
    late[k].on_anti_tip = k < 310;
    late[k].tip_over = true;
  }
  EXPECT_EQ(ScoreSkill(spec, circuit, late, dt).level, SkillLevel::kPass);
  // a tip-over before it: fail, whatever else
  std::vector<TrainingTick> fallen = touched;
  fallen[120].tip_over = true;
  const SkillScore f = ScoreSkill(spec, circuit, fallen, dt);
  EXPECT_EQ(f.level, SkillLevel::kFail);
  EXPECT_NE(f.reason.find("tipped over at t = 1.20 s"), std::string::npos) << f.reason;
}

// A turn goal counts the unwrapped heading, through +-pi, in the direction asked.
TEST(SkillRuleTest, TurnGoalUnwrapsTheHeadingAndKeepsItsDirection) {
  CircuitSpec circuit;
  SkillSpec spec{"turn", "Turns", "test", 180.0, 1};
  const double dt = 0.01;
  std::vector<TrainingTick> left, right;
  for (int k = 0; k <= 400; ++k) {  // 60 deg/s for 4 s: 240 deg
    TrainingTick t;
    t.t = k * dt;
    t.yaw = std::remainder(0.5 * 3.14159265358979 + t.t * 3.14159265358979 / 3.0, 2.0 * 3.14159265358979);
    left.push_back(t);
    t.yaw = -t.yaw;
    right.push_back(t);
  }
  const SkillScore l = ScoreSkill(spec, circuit, left, dt);
  EXPECT_EQ(l.level, SkillLevel::kPass);
  ASSERT_TRUE(l.time_s.has_value());
  EXPECT_NEAR(*l.time_s, 3.0, 0.011);  // 180 deg at 60 deg/s
  const SkillScore r = ScoreSkill(spec, circuit, right, dt);  // 240 deg, but to the right
  EXPECT_EQ(r.level, SkillLevel::kFail);
  EXPECT_NEAR(r.turned_deg, -240.0, 1e-6);
  EXPECT_NE(r.reason.find("turned 240 of 180 deg"), std::string::npos) << r.reason;
  spec.turn_sign = 0;
  EXPECT_EQ(ScoreSkill(spec, circuit, right, dt).level, SkillLevel::kPass);
}

// Two sessions of real run outputs (score.json as pwsim run writes it): before, the doorway
// driven into its frame (fail) and 10 m forward (pass); after, both pass. The sheet, its
// comparison and figures; then three participants' sheets through the study.
TEST(SkillSheetTest, TwoSessionsOfRealRunsGiveTheSheetAndItsComparison) {
  const fs::path dir = Scratch("sheet");
  auto run = [&](const Scene& scene, const std::string& name) {
    const fs::path out = dir / name;
    const std::vector<TrainingTick> trace = TrainingTrace(scene, SimulateCircuitScene(scene));
    EXPECT_FALSE(ScoreSkillItem(scene, scene.file.string(), trace, out).empty());
    return out;
  };
  const Scene door = LoadScene(kSkills / "wst_gets_through_doorway.yaml");
  const Scene door_hit = Variant("wst_gets_through_doorway", "driver: {speed_mps: 0.8, lookahead_m: 0.9}",
                                 "driver: {speed_mps: 0.8, lookahead_m: 0.9, path_m: [[0, 0], [1, 0.25], [7, 0.25]]}");
  const Scene forward = LoadScene(kSkills / "wst_rolls_forward_10m.yaml");
  const fs::path b1 = run(door_hit, "before_door"), b2 = run(forward, "before_forward");
  const fs::path a1 = run(door, "after_door_1"), a2 = run(door, "after_door_2"), a3 = run(forward, "after_forward");
  const std::vector<SkillAttempt> attempts =
      ReadSkillSessions("P07", {{"before", {b1, b2}}, {"after", {a1, a2, a3}}});
  ASSERT_EQ(attempts.size(), 5u);
  EXPECT_EQ(attempts[0].score, 0);
  EXPECT_EQ(attempts[0].level, "fail");
  EXPECT_EQ(attempts[1].score, 2);
  EXPECT_EQ(attempts[3].attempt, 2);  // the doorway's second attempt after
  const fs::path out = dir / "sheet";
  WriteSkillSheet(attempts, out);
  const std::string csv = Text(out / "sheet.csv");
  EXPECT_EQ(csv.rfind("participant,session,item,attempt,level,score,time_s,contacts,", 0), 0u);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 6);
  EXPECT_NE(csv.find("P07,before,wst_gets_through_doorway,1,fail,0,,1,"), std::string::npos) << csv;
  const std::string comparison = Text(out / "comparison.csv");
  EXPECT_NE(comparison.find("P07,wst_gets_through_doorway,score,0,2,2\n"), std::string::npos) << comparison;
  EXPECT_NE(comparison.find("P07,total,percent,50,100,50\n"), std::string::npos) << comparison;
  const std::string md = Text(out / "sheet.md");
  EXPECT_NE(md.find("door_frame_left"), std::string::npos);
  EXPECT_NE(md.find("Total: **50.0 %**"), std::string::npos);
  EXPECT_NE(md.find("Total: **100.0 %**"), std::string::npos);
  EXPECT_TRUE(fs::exists(out / "items/wst_gets_through_doorway.png"));
  EXPECT_TRUE(fs::exists(out / "items/wst_rolls_forward_10m.plot.csv"));

  // three participants (the same runs under three names) through the study
  std::vector<fs::path> sheets;
  for (const std::string p : {"P01", "P02", "P03"}) {
    std::vector<SkillAttempt> copy = attempts;
    for (SkillAttempt& a : copy) a.participant = p;
    sheets.push_back(dir / (p + ".csv"));
    std::ofstream(sheets.back()) << SkillSheetCsv(copy);
  }
  EXPECT_TRUE(IsSkillSheet(sheets[0]));  // `pwsim study SHEET.csv` takes it as a sheet
  std::ofstream(dir / "ratings.csv") << "participant,condition,rating\nP01,a,1\n";
  EXPECT_FALSE(IsSkillSheet(dir / "ratings.csv"));
  EXPECT_FALSE(IsSkillSheet(dir / "no_such.csv"));
  EXPECT_EQ(SkillRatingsCsv(ReadSkillSheets(sheets), ""),
            "participant,condition,rating\nP01,before,50\nP01,after,100\nP02,before,50\nP02,after,100\n"
            "P03,before,50\nP03,after,100\n");
  const std::vector<std::string> analysed = WriteSkillStudy(sheets, {"before", "after"}, dir / "study");
  EXPECT_NE(std::find(analysed.begin(), analysed.end(), "total_percent"), analysed.end());
  std::ifstream in(dir / "study/total_percent/study.json");
  const nlohmann::json study = nlohmann::json::parse(in);
  EXPECT_EQ(study["format"], "pwsim-study/1");
  EXPECT_EQ(study["paired"]["n_pairs"], 3);
  EXPECT_EQ(study["conditions"]["after"]["median"], 100.0);
}

void ExpectInputError(const std::function<void()>& f, const std::string& file_part, const std::string& field,
                      const std::string& expected_part) {
  try {
    f();
    ADD_FAILURE() << "no error; expected one about " << field;
  } catch (const InputError& e) {
    EXPECT_NE(e.file().find(file_part), std::string::npos) << e.what();
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_NE(e.expected().find(expected_part), std::string::npos) << e.what();
  }
}

TEST(SkillInputTest, BadInputsAreRefusedWithFileFieldAndExpectation) {
  const fs::path dir = Scratch("bad");
  // a run folder without a score (a run of a scene that is no skill item)
  fs::create_directories(dir / "plain_run");
  ExpectInputError([&] { ReadSkillAttempt(dir / "plain_run", "P1", "s"); }, "plain_run/score.json", "RUN_DIR",
                   "score.json");
  ExpectInputError([&] { ReadSkillAttempt(dir / "no_such_run", "P1", "s"); }, "no_such_run", "RUN_DIR", "run folder");
  // a score.json with a field misspelt
  fs::create_directories(dir / "typo");
  std::ofstream(dir / "typo/score.json")
      << R"({"format": "pwsim-skill-score/1", "item": "x", "title": "t", "source": "s", "levle": "pass", "score": 2})";
  ExpectInputError([&] { ReadSkillAttempt(dir / "typo", "P1", "s"); }, "typo/score.json", "level", "a string");
  // a score that is not a level
  fs::create_directories(dir / "three");
  std::ofstream(dir / "three/score.json")
      << R"({"format": "pwsim-skill-score/1", "item": "x", "title": "t", "source": "s", "level": "pass", "score": 3})";
  ExpectInputError([&] { ReadSkillAttempt(dir / "three", "P1", "s"); }, "three/score.json", "score", "0, 1 or 2");
  // a sheet with a score of 3 on line 3
  std::ofstream(dir / "sheet.csv") << "participant,session,item,attempt,score\nP1,a,x,1,2\nP1,b,x,1,3\n";
  try {
    ReadSkillSheets({dir / "sheet.csv"});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.field(), "score");
  }
  // a skill: section with a misspelt key, and one without a goal
  ExpectInputError([&] { SkillOf(Variant("wst_turns_180_in_place", "goal: {turn_deg: 180", "goal: {turn_degs: 180")); },
                   "wst_turns_180_in_place_variant.yaml", "skill.goal.turn_degs", "");
  ExpectInputError(
      [&] {
        const Scene s = Variant("wst_turns_180_in_place", "  goal: {turn_deg: 180, direction: left}\n", "");
        SkillOf(s);
      },
      "wst_turns_180_in_place_variant.yaml", "skill.goal", "a goal");
}

}  // namespace
}  // namespace pwsim::report
