// The figures for people (issue 42, item 3): axes and legends in words with units, no false
// swing drawn through a sign change, a magnified axis said so, equal curves left visible.
// Each check reads what the figure plots (STEM.plot.csv) and how (STEM.gp).

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "mca/omct.h"
#include "plot/labels.h"
#include "plot/plot.h"
#include "report/omct_report.h"
#include "report/sweep_report.h"

namespace pwsim::report {
namespace {

namespace fs = std::filesystem;

fs::path FreshDir(const std::string& name) {
  const fs::path dir = fs::path(PWSIM_BINARY_DIR) / "test_out" / "report_figures" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string Slurp(const fs::path& file) {
  std::ifstream in(file);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// STEM.plot.csv as (panel, series) -> y values in order; the fields hold no commas here.
std::map<std::pair<std::string, std::string>, std::vector<double>> PlottedY(const fs::path& csv) {
  std::map<std::pair<std::string, std::string>, std::vector<double>> out;
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::string cell;
    bool quoted = false;
    for (char c : line) {
      if (c == '"') quoted = !quoted;
      else if (c == ',' && !quoted) cells.push_back(cell), cell.clear();
      else cell += c;
    }
    cells.push_back(cell);
    out[{cells[0], cells[1]}].push_back(std::stod(cells[3]));
  }
  return out;
}

TEST(QuantityFromKey, UnitSuffixBecomesTheUnitAndRadiansAreShownInDegrees) {
  const plot::Quantity speed = plot::QuantityFromKey("scene.drive.speed_mps");
  EXPECT_EQ(plot::AxisLabel(speed), "drive speed [m/s]");
  EXPECT_EQ(speed.scale, 1.0);
  const plot::Quantity pitch = plot::QuantityFromKey("peak_pitch_rad");
  EXPECT_EQ(plot::AxisLabel(pitch), "peak pitch [deg]");
  EXPECT_NEAR(pitch.scale * M_PI, 180.0, 1e-12);
  EXPECT_EQ(plot::AxisLabel(plot::QuantityFromKey("scene.drive.accel_mps2")), "drive accel [m/s²]");
  EXPECT_EQ(plot::AxisLabel(plot::QuantityFromKey("yaw_rate_radps")), "yaw rate [deg/s]");
  EXPECT_EQ(plot::AxisLabel(plot::QuantityFromKey("lift_off_count")), "lift off count");
}

// Two tests with equal responses (a symmetric platform): the second is dashed and says so; a
// cross-coupling gain in (rad/s)/(m/s²) is drawn in (deg/s)/(m/s²); a phase that crosses
// ±180° is unwrapped, not drawn as a jump.
TEST(OmctFigure, WordsUnitsPerPanelEqualCurvesDashedPhaseUnwrapped) {
  const fs::path dir = FreshDir("omct");
  std::vector<mca::OmctPoint> points;
  const auto f = mca::OmctFrequencies();
  for (std::size_t k = 0; k < f.size(); ++k) {
    const double phase = 170.0 + 10.0 * static_cast<double>(k);  // wraps past 180 at k = 1
    const double wrapped = phase > 180.0 ? phase - 360.0 : phase;
    points.push_back({"p_to_p", f[k], 0.5, wrapped, true});
    points.push_back({"q_to_q", f[k], 0.5, wrapped, true});
    points.push_back({"fx_to_q", f[k], 0.1, -10.0, true});
  }
  WriteOmctFigure(dir / "omct", "the test washout", points);
  const auto y = PlottedY(dir / "omct.plot.csv");
  const std::string roll = "roll rate (p→p)", pitch = "pitch rate (q→q), as p→p (dashed)";
  const std::string tilt = "pitch rate from a forward push (fx→q)";
  const std::string rot_gain = "rotations passed on to the occupant: gain";
  const std::string rot_phase = "rotations passed on to the occupant: phase";
  ASSERT_EQ(y.count({rot_gain, roll}), 1u);
  ASSERT_EQ(y.count({rot_gain, pitch}), 1u);
  const std::string tilt_gain = "tilt coordination: the platform rotates to present a sustained push with gravity: gain";
  ASSERT_EQ(y.count({tilt_gain, tilt}), 1u);
  EXPECT_NEAR(y.at({tilt_gain, tilt})[0], 0.1 * 180.0 / M_PI, 1e-9);
  const std::vector<double>& phase = y.at({rot_phase, roll});
  for (std::size_t k = 1; k < phase.size(); ++k) EXPECT_NEAR(phase[k] - phase[k - 1], 10.0, 1e-9) << k;
  const std::string gp = Slurp(dir / "omct.gp");
  EXPECT_NE(gp.find("dt 2 lw 1.5 lc rgb '#D55E00' title 'pitch rate (q→q), as p→p (dashed)'"), std::string::npos);
  EXPECT_NE(gp.find("set ylabel 'gain [(deg/s) per (m/s²)]'"), std::string::npos);
  EXPECT_EQ(gp.find("_to_"), std::string::npos) << "a code name in the figure";
}

// A swept signed peak whose largest excursion flips sign in one task, and a result that moves
// by 1.6 %: the first is drawn as its size with the negative task marked (no V through zero),
// the second on an axis that says it is magnified; axes in words with units.
TEST(SweepPlots, SignChangeDrawsTheSizeAndASmallChangeSaysItIsMagnified) {
  const fs::path dir = FreshDir("sweep");
  sweep::Manifest manifest;
  manifest.dir = dir;
  manifest.name = "speeds";
  sweep::Collection collection;
  collection.variables = {"scene.drive.speed_mps"};
  collection.field_names = {"peak_pitch_rad", "peak_heave_m"};
  const std::vector<double> pitch{0.104, 0.1043, -0.105, 0.1058}, heave{0.0655, 0.0657, 0.0661, 0.0666};
  for (std::size_t i = 0; i < pitch.size(); ++i) {
    sweep::ResultRow row;
    row.index = i;
    row.status = "ok";
    row.values = {std::to_string(0.4 + 0.2 * static_cast<double>(i))};
    row.numbers = {pitch[i], heave[i]};
    collection.rows.push_back(row);
  }
  const std::vector<fs::path> written = WriteSweepPlots(manifest, collection);
  ASSERT_EQ(written.size(), 1u);
  const fs::path csv = plot::FigureFilesFor(written[0]).csv;
  const auto y = PlottedY(csv);
  const std::string pitch_panel = "peak pitch: size (its sign changes across the sweep)";
  ASSERT_EQ(y.count({pitch_panel, "all tasks"}), 1u);
  for (std::size_t i = 0; i < pitch.size(); ++i)
    EXPECT_NEAR(y.at({pitch_panel, "all tasks"})[i], std::abs(pitch[i]) * 180.0 / M_PI, 1e-9);
  ASSERT_EQ(y.count({pitch_panel, "negative in these tasks (size drawn)"}), 1u);
  EXPECT_EQ(y.at({pitch_panel, "negative in these tasks (size drawn)"}).size(), 1u);
  const std::string gp = Slurp(plot::FigureFilesFor(written[0]).gp);
  EXPECT_NE(gp.find("set xlabel 'drive speed [m/s]'"), std::string::npos);
  EXPECT_NE(gp.find("set ylabel 'size of peak pitch [deg]'"), std::string::npos);
  EXPECT_NE(gp.find("set title 'peak heave (y axis magnified: the values vary by only 1.7 %)'"), std::string::npos)
      << gp;
  EXPECT_EQ(gp.find("scene.drive"), std::string::npos) << "a code name in the figure";
  EXPECT_EQ(gp.find("peak_"), std::string::npos) << "a code name in the figure";
}

}  // namespace
}  // namespace pwsim::report
