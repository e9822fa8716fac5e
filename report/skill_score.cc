#include "report/skill_score.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "engine/atomic_file.h"
#include "engine/input_error.h"
#include "engine/yaml_reader.h"
#include "report/training_report.h"

namespace pwsim::report {
namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;

/// The angle a - b wrapped to (-pi, pi].
double WrappedDifference(double a, double b) {
  double d = std::remainder(a - b, 2.0 * std::numbers::pi);
  if (d <= -std::numbers::pi) d += 2.0 * std::numbers::pi;
  return d;
}

/// The name of the wall or obstacle the chair at `tick` touches ("" when none within the
/// release gap: the blocked pose is a tick short of the wall).
std::string WhatIsHit(const CircuitSpec& circuit, const TrainingTick& tick) {
  const PlanarState pose{tick.x, tick.y, tick.yaw, 0.0, 0.0};
  const int hit = FootprintHit(circuit, pose, kContactReleaseGap);
  if (hit < 0) return "";
  const auto index = static_cast<std::size_t>(hit);
  return index < circuit.walls.size() ? circuit.walls[index].name : circuit.obstacles[index - circuit.walls.size()].name;
}

std::string Seconds(double t) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(2);
  s << t << " s";
  return s.str();
}

std::string Speed(double v) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(2);
  s << v << " m/s";
  return s.str();
}

std::string Plural(std::size_t n, const std::string& one, const std::string& many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

/// "N contacts (WHAT at t = T s, V m/s; ...)".
std::string ContactsText(const std::vector<SkillContact>& contacts) {
  std::ostringstream c;
  c << Plural(contacts.size(), "contact", "contacts") << " (";
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    const SkillContact& contact = contacts[i];
    c << (i ? "; " : "") << (contact.what.empty() ? "a wall" : contact.what) << " at t = " << Seconds(contact.t_s)
      << ", " << Speed(contact.speed_mps);
  }
  c << ")";
  return c.str();
}

}  // namespace

const char* SkillLevelName(SkillLevel level) {
  switch (level) {
    case SkillLevel::kPass: return "pass";
    case SkillLevel::kPassWithDifficulty: return "pass with difficulty";
    case SkillLevel::kFail: break;
  }
  return "fail";
}

std::optional<SkillSpec> SkillOf(const Scene& scene) {
  const SceneSection* section = scene.section("skill");
  if (section == nullptr) return std::nullopt;
  YamlMap map(section->node, section->file, "skill", section->line);
  SkillSpec spec;
  spec.item = map.String("item");
  if (spec.item.empty() || spec.item.find_first_of(" ,/\\\"") != std::string::npos) {
    map.Fail("item", "an identifier without spaces, commas, quotes or slashes (e.g. wst_turns_180_in_place)",
             "\"" + spec.item + "\"");
  }
  spec.title = map.String("title");
  spec.source = map.String("source");
  if (map.Has("goal")) {
    YamlMap goal = map.Map("goal");
    spec.turn_deg = goal.NumberOr("turn_deg", 0.0, Range::Closed(0.0, 3600.0, "deg"));
    const std::string direction = goal.ChoiceOr("direction", "either", {"left", "right", "either"});
    spec.turn_sign = direction == "left" ? 1 : direction == "right" ? -1 : 0;
    goal.Finish();
  }
  if (!scene.is_circuit()) {
    map.Fail("item", "a skill item in a circuit scene (a circuit: section with the item's setting)", "no circuit");
  }
  if (scene.circuit->gates.empty() && spec.turn_deg <= 0.0) {
    map.Fail("goal", "a goal: gates in the circuit (passed in order) or goal.turn_deg > 0", "neither");
  }
  map.Finish();
  return spec;
}

SkillScore ScoreSkill(const SkillSpec& spec, const CircuitSpec& circuit, const std::vector<TrainingTick>& trace,
                      double dt) {
  SkillScore score;
  score.gates_total = static_cast<int>(circuit.gates.size());
  // the goal: gates in order (the runner counts them) and the heading turned
  double turned = 0.0;
  std::size_t end = trace.size() - 1;  // the window's last tick
  for (std::size_t k = 0; k < trace.size(); ++k) {
    if (k > 0) turned += WrappedDifference(trace[k].yaw, trace[k - 1].yaw);
    const bool gates_done = trace[k].gates_passed >= score.gates_total;
    const double toward = spec.turn_sign == 0 ? std::abs(turned) : spec.turn_sign * turned;
    const bool turn_done = spec.turn_deg <= 0.0 || toward * kRadToDeg >= spec.turn_deg;
    if (gates_done && turn_done) {
      score.completed = true;
      score.time_s = trace[k].t;
      end = k;
      break;
    }
  }
  score.turned_deg = turned * kRadToDeg;
  score.window_s = trace[end].t;
  score.duration_s = trace.back().t;
  score.training = ComputeTrainingMetrics(
      circuit, std::vector<TrainingTick>(trace.begin(), trace.begin() + static_cast<std::ptrdiff_t>(end) + 1), dt);
  score.gates_passed = trace[end].gates_passed;
  // the events in the window
  int events = trace.front().contact_events;
  bool anti_tip = trace.front().on_anti_tip, lifted = trace.front().lift_off_count > 0;
  for (std::size_t k = 0; k <= end; ++k) {
    const TrainingTick& tick = trace[k];
    if (tick.contact_events > events) {
      score.contacts.push_back({tick.t, tick.last_contact_speed, WhatIsHit(circuit, tick)});
      events = tick.contact_events;
    }
    if (tick.on_anti_tip && !anti_tip) score.near_tip_t_s.push_back(tick.t);
    anti_tip = tick.on_anti_tip;
    const bool lift = tick.lift_off_count > 0;
    if (lift && !lifted) ++score.lift_offs;
    lifted = lift;
    if (tick.tip_over && !score.tip_over_t_s) score.tip_over_t_s = tick.t;
  }
  // the level and its reason
  std::ostringstream reason;
  if (score.tip_over_t_s) {
    score.level = SkillLevel::kFail;
    reason << "the chair tipped over at t = " << Seconds(*score.tip_over_t_s);
  } else if (!score.completed) {
    score.level = SkillLevel::kFail;
    reason << "the goal was not reached in " << Seconds(trace.back().t);
    std::vector<std::string> parts;
    if (score.gates_total > 0) {
      parts.push_back(std::to_string(score.gates_passed) + " of " + std::to_string(score.gates_total) +
                      " gates passed in order");
    }
    if (spec.turn_deg > 0.0) {
      std::ostringstream turn;
      turn << "turned " << std::lround(std::abs(score.turned_deg)) << " of " << spec.turn_deg << " deg";
      parts.push_back(turn.str());
    }
    for (std::size_t i = 0; i < parts.size(); ++i) reason << (i == 0 ? " (" : "; ") << parts[i];
    if (!parts.empty()) reason << ")";
    if (!score.contacts.empty()) reason << "; " << ContactsText(score.contacts);
  } else {
    reason << "goal reached at " << Seconds(*score.time_s);
    if (score.contacts.empty() && score.near_tip_t_s.empty()) {
      score.level = SkillLevel::kPass;
      reason << " without a contact or a near-tip";
    } else {
      score.level = SkillLevel::kPassWithDifficulty;
      reason << " with ";
      std::vector<std::string> parts;
      if (!score.contacts.empty()) parts.push_back(ContactsText(score.contacts));
      if (!score.near_tip_t_s.empty()) {
        std::ostringstream n;
        n << Plural(score.near_tip_t_s.size(), "near-tip", "near-tips") << " (on the anti-tip wheels at t =";
        for (std::size_t i = 0; i < score.near_tip_t_s.size(); ++i) n << (i ? ", " : " ") << Seconds(score.near_tip_t_s[i]);
        n << ")";
        parts.push_back(n.str());
      }
      for (std::size_t i = 0; i < parts.size(); ++i) reason << (i ? " and " : "") << parts[i];
    }
  }
  score.reason = reason.str();
  return score;
}

nlohmann::ordered_json SkillScoreJson(const SkillSpec& spec, const SkillScore& score, const std::string& scene_path) {
  const double duration_s = score.duration_s;
  auto nullable = [](const std::optional<double>& v) { return v ? nlohmann::ordered_json(*v) : nlohmann::ordered_json(nullptr); };
  nlohmann::ordered_json j;
  j["format"] = "pwsim-skill-score/1";
  j["item"] = spec.item;
  j["title"] = spec.title;
  j["source"] = spec.source;
  j["scene"] = scene_path;
  j["level"] = SkillLevelName(score.level);
  j["score"] = static_cast<int>(score.level);
  j["reason"] = score.reason;
  j["completed"] = score.completed;
  j["time_s"] = nullable(score.time_s);
  double max_speed = 0.0;
  nlohmann::ordered_json events = nlohmann::ordered_json::array();
  for (const SkillContact& c : score.contacts) {
    max_speed = std::max(max_speed, c.speed_mps);
    events.push_back({{"t_s", c.t_s}, {"speed_mps", c.speed_mps}, {"what", c.what}});
  }
  j["contacts"] = {{"count", score.contacts.size()}, {"max_speed_mps", max_speed}, {"events", events}};
  j["near_tips"] = {{"count", score.near_tip_t_s.size()}, {"t_s", score.near_tip_t_s}};
  j["tip_over_t_s"] = nullable(score.tip_over_t_s);
  j["lift_offs"] = score.lift_offs;
  j["gates"] = {{"passed", score.gates_passed}, {"total", score.gates_total}};
  j["turned_deg"] = score.turned_deg;
  j["goal_turn_deg"] = spec.turn_deg;
  if (score.training.has_route) {
    j["deviation_m"] = {{"mean", score.training.route_deviation_m.mean},
                        {"rms", score.training.route_deviation_m.rms},
                        {"max", score.training.route_deviation_m.max}};
  } else {
    j["deviation_m"] = nullptr;
  }
  j["window_s"] = score.window_s;
  j["duration_s"] = duration_s;
  j["training"] = TrainingJson(score.training);
  return j;
}

std::string SkillScoreLine(const SkillSpec& spec, const SkillScore& score) {
  return "skill " + spec.item + ": " + SkillLevelName(score.level) + " (" + score.reason + ")";
}

void WriteSkillScore(const SkillSpec& spec, const SkillScore& score, const std::string& scene_path,
                     const std::filesystem::path& out_dir) {
  std::filesystem::create_directories(out_dir);
  WriteFileAtomically(out_dir / "score.json", SkillScoreJson(spec, score, scene_path).dump(2) + "\n");
}

std::string ScoreSkillItem(const Scene& scene, const std::string& scene_path, const std::vector<TrainingTick>& trace,
                           const std::filesystem::path& out_dir) {
  const std::optional<SkillSpec> spec = SkillOf(scene);
  if (!spec || !scene.is_circuit() || trace.empty()) return "";
  const SkillScore score = ScoreSkill(*spec, *scene.circuit, trace, scene.clock.dt());
  WriteSkillScore(*spec, score, scene_path, out_dir);
  return SkillScoreLine(*spec, score);
}

}  // namespace pwsim::report
