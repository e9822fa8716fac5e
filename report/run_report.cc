#include "report/run_report.h"

#include <cmath>

namespace pwsim::report {

TrialTable ChairColumns(const Scene& scene, const std::vector<ChairSample>& samples) {
  const std::size_t rows = samples.size();
  TrialTable table(rows);
  auto column = [&](auto&& get) {
    std::vector<double> values(rows);
    for (std::size_t r = 0; r < rows; ++r) values[r] = get(samples[r]);
    return values;
  };
  table.Add("t_s", column([&](const ChairSample& s) { return scene.clock.TimeAt(s.tick); }));
  table.Add("x_m", column([](const ChairSample& s) { return s.drive.x; }));
  table.Add("v_mps", column([](const ChairSample& s) { return s.drive.v; }));
  table.Add("a_mps2", column([](const ChairSample& s) { return s.drive.a; }));
  for (int i = 0; i < scene.chair.wheel_count(); ++i) {
    table.Add("z_o" + std::to_string(i + 1) + "_m",
              column([i](const ChairSample& s) { return s.z_O[static_cast<std::size_t>(i)]; }));
  }
  table.Add("z_gm_m", column([](const ChairSample& s) { return s.gm.z; }));
  table.Add("pitch_gm_rad", column([](const ChairSample& s) { return s.gm.pitch; }));
  table.Add("z_m", column([](const ChairSample& s) { return s.lm.z; }));
  table.Add("pitch_rad", column([](const ChairSample& s) { return s.lm.pitch; }));
  table.Add("z_rate_mps", column([](const ChairSample& s) { return s.lm.z_rate; }));
  table.Add("pitch_rate_radps", column([](const ChairSample& s) { return s.lm.pitch_rate; }));
  table.Add("z_acc_mps2", column([](const ChairSample& s) { return s.lm_acc.z; }));
  table.Add("pitch_acc_radps2", column([](const ChairSample& s) { return s.lm_acc.pitch; }));
  table.Add("pitch_torque_nm", column([](const ChairSample& s) { return s.pitch_torque; }));
  return table;
}

nlohmann::ordered_json Peak(const TrialTable& table, const std::string& name, const char* unit) {
  const auto& t = table.Column("t_s");
  const auto& values = table.Column(name);
  std::size_t best = 0;
  for (std::size_t r = 1; r < values.size(); ++r) {
    if (std::abs(values[r] - values[0]) > std::abs(values[best] - values[0])) best = r;
  }
  return {{"column", name},
          {std::string("value_") + unit, values[best]},
          {std::string("excursion_") + unit, values[best] - values[0]},
          {"t_s", t[best]}};
}

nlohmann::ordered_json RunSummary(const Scene& scene, const std::string& scene_path,
                                  const TrialTable& table) {
  nlohmann::ordered_json summary;
  summary["format"] = "pwsim-run-summary/1";
  summary["scene"] = {{"file", scene_path}, {"name", scene.name}};
  summary["clock_rate_hz"] = scene.clock.rate_hz;
  summary["duration_s"] = table.Column("t_s").back();
  summary["ticks"] = table.rows();
  summary["load_kg"] = scene.load_kg;
  summary["speed_mps"] = scene.drive.speed;
  summary["peak_heave"] = Peak(table, "z_m", "m");
  summary["peak_pitch"] = Peak(table, "pitch_rad", "rad");
  return summary;
}

}  // namespace pwsim::report
