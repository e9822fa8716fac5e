#pragma once
// Power-mobility skill items (docs/skills.md): a circuit scene (engine/circuit.h) with a
// `skill:` section is one item of a published power-wheelchair skill test (the Wheelchair
// Skills Test's power-chair items), and a drive through it, simulated (`pwsim run`) or live
// (`pwsim drive`), is scored on the test's capacity levels (WST 4.2: 2 pass, 1 pass with
// difficulty, 0 fail):
//
//   goal      every gate of the circuit passed in order (circuit.h) and, for a turning item,
//             the heading turned by at least turn_deg (the unwrapped yaw from the start,
//             either way unless `direction` says left or right); t_goal the first tick at
//             which both hold.
//   window    [0, t_goal] when the goal is reached, else the whole drive: what happens after
//             the item is done (parking, a drift into the end wall) is not scored.
//   fail                  the goal not reached within the drive, or a tip-over in the window
//                         (the centre of pressure outside the support polygon, full_chair.h)
//   pass with difficulty  reached, but with a contact (wall, door frame, obstacle) or a
//                         near-tip (the chair on its anti-tip wheels) in the window
//   pass                  reached with neither
//
// The score carries what the level rests on: the time to the goal, every contact with what
// was hit, when, and the approach speed (circuit.h), the near-tips' times, the deviation from
// the route over the window (engine/training_metrics.h: the training metrics of the window)
// and the reason for the level in words. No number of
// the rule is pwsim's own: the levels are the source's, the events are the simulator's.
//
//   std::optional<SkillSpec> item = SkillOf(scene);           // @throws InputError
//   SkillScore score = ScoreSkill(*item, *scene.circuit, trace, scene.clock.dt());
//   WriteSkillScore(*item, score, "scenes/skills/x.yaml", out_dir);   // DIR/score.json

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/circuit.h"
#include "engine/scene.h"
#include "engine/training_metrics.h"

namespace pwsim::report {

/// What a `skill:` section says.
struct SkillSpec {
  std::string item;            ///< identifier, e.g. "wst_turns_180_in_place"
  std::string title;           ///< the source's wording, e.g. "Turns 180 deg in place"
  std::string source;          ///< test, version and skill number, e.g. "WST 4.1 power, skill 5"
  double turn_deg{0.0};        ///< heading change the goal needs [deg]; 0: none
  int turn_sign{0};            ///< +1 left, -1 right, 0 either way
};

/// The scene's `skill:` section, or none:
///   skill: {item: ID, title: TEXT, source: TEXT, goal: {turn_deg: 180, direction: left|right|either}}
/// @throws InputError naming file, line and field (unknown key, a skill without a circuit, a
/// goal that cannot be reached: no gate and no turn).
std::optional<SkillSpec> SkillOf(const Scene& scene);

enum class SkillLevel { kFail = 0, kPassWithDifficulty = 1, kPass = 2 };

/// "fail", "pass with difficulty", "pass".
const char* SkillLevelName(SkillLevel level);

struct SkillContact {
  double t_s{0.0};          ///< when it began [s]
  double speed_mps{0.0};    ///< approach speed of O_V [m/s]
  std::string what;         ///< the wall or obstacle hit ("" when none is within reach)
};

struct SkillScore {
  SkillLevel level{SkillLevel::kFail};
  std::string reason;                   ///< the level and why, in words
  bool completed{false};
  std::optional<double> time_s;         ///< t_goal [s]
  double window_s{0.0};                 ///< end of the scored window [s]
  int gates_passed{0}, gates_total{0};  ///< by the window's end
  double turned_deg{0.0};               ///< signed heading change by the window's end [deg]
  std::vector<SkillContact> contacts;   ///< in the window
  std::vector<double> near_tip_t_s;     ///< near-tip episodes' starts in the window [s]
  std::optional<double> tip_over_t_s;   ///< first tip-over in the window [s]
  int lift_offs{0};                     ///< wheel lift-off episodes in the window (reported, not graded)
  double duration_s{0.0};               ///< the whole drive [s]
  TrainingMetrics training;             ///< the window's training metrics (deviation, jerk, ...)
};

/// The score of a drive's trace (TrainingTrace of a run, ChairDriveSource::trace of a live
/// drive). @pre trace non-empty, dt > 0.
SkillScore ScoreSkill(const SkillSpec& spec, const CircuitSpec& circuit, const std::vector<TrainingTick>& trace,
                      double dt);

/// score.json: {"format": "pwsim-skill-score/1", "item", "title", "source", "scene", "level",
/// "score" (2/1/0), "reason", "completed", "time_s", "contacts": {"count", "max_speed_mps",
/// "events": [{"t_s", "speed_mps", "what"}]}, "near_tips": {"count", "t_s": [...]},
/// "tip_over_t_s", "lift_offs", "gates", "turned_deg", "deviation_m": {mean, rms, max} or null,
/// "window_s", "duration_s"}.
nlohmann::ordered_json SkillScoreJson(const SkillSpec& spec, const SkillScore& score, const std::string& scene_path);

/// One console line: "skill ITEM: LEVEL (REASON)".
std::string SkillScoreLine(const SkillSpec& spec, const SkillScore& score);

/// Writes DIR/score.json.
void WriteSkillScore(const SkillSpec& spec, const SkillScore& score, const std::string& scene_path,
                     const std::filesystem::path& out_dir);

/// The hook of `pwsim run` and `pwsim drive`: when the scene is a skill item, scores the trace,
/// writes DIR/score.json and returns the console line; "" otherwise.
std::string ScoreSkillItem(const Scene& scene, const std::string& scene_path, const std::vector<TrainingTick>& trace,
                           const std::filesystem::path& out_dir);

}  // namespace pwsim::report
