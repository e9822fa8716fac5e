#include "report/training_report.h"

#include <sstream>

#include "engine/atomic_file.h"
#include "mca/head_motion.h"

namespace pwsim::report {

std::vector<TrainingTick> TrainingTrace(const Scene& scene, const std::vector<FullChairSample>& samples) {
  std::vector<TrainingTick> trace;
  trace.reserve(samples.size());
  for (const FullChairSample& s : samples) {
    const mca::DofArray body{s.planar.x, s.planar.y, s.lm.z, s.roll, s.lm.pitch, s.planar.yaw};
    trace.push_back(TrainingTickOf(s, scene.clock.TimeAt(s.tick), mca::PointOnBody(body, scene.occupant.head_offset).p));
  }
  return trace;
}

nlohmann::ordered_json TrainingJson(const TrainingMetrics& m) {
  auto nullable = [](const std::optional<double>& v) { return v ? nlohmann::ordered_json(*v) : nlohmann::ordered_json(nullptr); };
  nlohmann::ordered_json j;
  j["format"] = "pwsim-training-metrics/1";
  j["duration_s"] = m.duration_s;
  j["completed"] = m.completion_time_s.has_value();
  j["completion_time_s"] = nullable(m.completion_time_s);
  j["gates"] = {{"passed", m.gates_passed}, {"total", m.gates_total}};
  if (m.has_route) {
    j["route_deviation_m"] = {{"mean", m.route_deviation_m.mean}, {"rms", m.route_deviation_m.rms}, {"max", m.route_deviation_m.max}};
  } else {
    j["route_deviation_m"] = nullptr;
  }
  j["contacts"] = {{"count", m.contacts},
                   {"approach_speed_mean_mps", m.contact_speed_mean_mps},
                   {"approach_speed_max_mps", m.contact_speed_max_mps},
                   {"time_s", m.contact_time_s}};
  j["clearance"] = {{"min_m", m.clearance_min_m}, {"min_at_t_s", m.clearance_min_t_s},
                    {"time_closer_than_0_1_m_s", m.time_closer_than_0_1_m_s}, {"search_cap_m", kClearanceCap}};
  j["joystick"] = {{"commands", m.joystick_commands},
                   {"reversals", m.forward_reversals + m.turn_reversals},
                   {"forward_reversals", m.forward_reversals},
                   {"turn_reversals", m.turn_reversals},
                   {"neutral_zone", kJoystickNeutral}};
  j["head_jerk_mps3"] = {{"rms", m.head_jerk_rms_mps3}, {"p95", m.head_jerk_p95_mps3}, {"max", m.head_jerk_max_mps3}};
  j["near_tips"] = m.near_tips;
  j["tip_overs"] = m.tip_overs;
  j["lift_offs"] = {{"episodes", m.lift_offs}, {"time_s", m.lift_off_time_s}};
  return j;
}

std::string TrainingMarkdown(const TrainingMetrics& m, const std::string& title) {
  std::ostringstream md;
  md << "# Training metrics: " << title << "\n\n"
     << "Computed from the run's trace by `ComputeTrainingMetrics` (engine/training_metrics.h, where every\n"
     << "figure is defined).\n\n"
     << "| metric | value |\n|---|---|\n";
  md << "| duration | " << m.duration_s << " s |\n";
  md << "| gates passed | " << m.gates_passed << " of " << m.gates_total << " |\n";
  md << "| completion time | "
     << (m.completion_time_s ? std::to_string(*m.completion_time_s) + " s" : std::string("not completed")) << " |\n";
  if (m.has_route) {
    md << "| deviation from the route (mean / RMS / max) | " << m.route_deviation_m.mean << " / "
       << m.route_deviation_m.rms << " / " << m.route_deviation_m.max << " m |\n";
  } else {
    md << "| deviation from the route | no route (no driver path, no gates) |\n";
  }
  md << "| contacts with walls and obstacles | " << m.contacts << " (approach speed mean " << m.contact_speed_mean_mps
     << " m/s, max " << m.contact_speed_max_mps << " m/s; " << m.contact_time_s << " s in contact) |\n";
  md << "| minimum clearance | " << m.clearance_min_m << " m at t = " << m.clearance_min_t_s << " s ("
     << m.time_closer_than_0_1_m_s << " s closer than 0.1 m) |\n";
  md << "| joystick commands | " << m.joystick_commands << " |\n";
  md << "| joystick reversals (forward / turn) | " << m.forward_reversals << " / " << m.turn_reversals << " |\n";
  md << "| jerk at the head (RMS / p95 / max) | " << m.head_jerk_rms_mps3 << " / " << m.head_jerk_p95_mps3 << " / "
     << m.head_jerk_max_mps3 << " m/s^3 |\n";
  md << "| near-tips (on the anti-tip wheels) | " << m.near_tips << " |\n";
  md << "| tip-overs | " << m.tip_overs << " |\n";
  md << "| lift-offs | " << m.lift_offs << " (" << m.lift_off_time_s << " s) |\n";
  return md.str();
}

void WriteTrainingPage(const TrainingMetrics& m, const std::string& title, const std::filesystem::path& out_dir) {
  WriteFileAtomically(out_dir / "training.md", TrainingMarkdown(m, title));
}

}  // namespace pwsim::report
