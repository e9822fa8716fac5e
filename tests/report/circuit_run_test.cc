// `pwsim run` for circuit scenes at the library level (report/run_circuit.h): a small circuit
// (tests/report/testdata/circuit_small.yaml: two gates, a box, a bump, a left turn) driven to
// its end with video, its columns and their units, the video's frame count, the four platform
// axes in use and inside their limits, the head motion against the chair's own rates, the
// summary's circuit fields, and same scene, same bits.
#include "report/run_circuit.h"

#include <gtest/gtest.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "engine/scene.h"
#include "mca/config.h"
#include "tests/render/ffprobe.h"

namespace pwsim::report {
namespace {

namespace fs = std::filesystem;

const fs::path kCircuit = fs::path(PWSIM_SOURCE_DIR) / "tests/report/testdata/circuit_small.yaml";

/// A fresh folder of this process: CTest runs each test of a suite as its own process, in
/// parallel, and each runs the suite's set-up; a shared folder would be removed under another.
fs::path Scratch(const std::string& name) {
  const fs::path dir =
      fs::path(PWSIM_BINARY_DIR) / "circuit_run_test" / (name + "-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

/// A CSV as named columns (numbers only).
std::map<std::string, std::vector<double>> ReadCsv(const fs::path& file, std::vector<std::string>* order = nullptr) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::stringstream header(line);
  for (std::string cell; std::getline(header, cell, ',');) names.push_back(cell);
  std::map<std::string, std::vector<double>> columns;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::size_t i = 0;
    for (std::string cell; std::getline(row, cell, ','); ++i) columns[names.at(i)].push_back(std::stod(cell));
  }
  if (order != nullptr) *order = names;
  return columns;
}

nlohmann::json Summary(const fs::path& dir) {
  std::ifstream in(dir / "summary.json");
  return nlohmann::json::parse(in);
}

std::string Bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

double MaxAbs(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

class CircuitRunTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    out_ = new fs::path(Scratch("small"));
    const Scene scene = LoadScene(kCircuit);
    RenderStageOptions render;  // the scene's 320x180 at 25 fps
    RunCircuitScene(scene, kCircuit.string(), 1, render, *out_);
  }
  static void TearDownTestSuite() { delete out_; }
  static fs::path* out_;
};
fs::path* CircuitRunTest::out_ = nullptr;

// Tests the trial.csv contract: the chair in the plane, every contact's load, every caster's
// angle, the MCA on every axis; a unit in every name that carries one; one row per tick.
TEST_F(CircuitRunTest, TrialColumnsCarryThePlanarChairAndEveryAxis) {
  std::vector<std::string> names;
  const auto csv = ReadCsv(*out_ / "trial.csv", &names);
  for (const char* column :
       {"t_s", "x_m", "y_m", "yaw_rad", "v_mps", "yaw_rate_radps", "ax_mps2", "ay_mps2", "roll_rad", "pitch_rad",
        "z_m", "roll_rate_radps", "pitch_rate_radps", "z_rate_mps", "load_1l_n", "load_3r_n", "caster_1l_rad",
        "caster_3r_rad", "lift_off_count", "gates_passed", "contact_events", "plat_heave_m", "plat_roll_rad",
        "plat_pitch_rad", "plat_yaw_rad", "head_fs_y_mps2", "head_w_z_radps", "vis_x_m", "vis_y_m", "vis_z_m",
        "vis_roll_rad", "vis_pitch_rad", "vis_yaw_rad", "vis_tilt_roll_rad", "vest_plat_scc_z_radps",
        "vest_true_oto_y_mps2"}) {
    EXPECT_TRUE(csv.count(column)) << column;
  }
  EXPECT_FALSE(csv.count("caster_2l_rad")) << "the drive wheels have no swivel";
  const std::vector<std::string> unitless{"joystick_forward", "joystick_turn", "lift_off_count", "tip_over",
                                          "on_anti_tip",      "in_contact",    "contact_events", "gates_passed",
                                          "mca_fault"};
  for (const std::string& name : names) {
    const bool has_unit = name.find('_') != std::string::npos &&
                          (name.ends_with("_s") || name.ends_with("_m") || name.ends_with("_rad") ||
                           name.ends_with("_mps") || name.ends_with("_radps") || name.ends_with("_mps2") ||
                           name.ends_with("_radps2") || name.ends_with("_n"));
    EXPECT_TRUE(has_unit || std::find(unitless.begin(), unitless.end(), name) != unitless.end()) << name;
  }
  EXPECT_EQ(csv.at("t_s").size(), 8001U);  // 8 s at 1 kHz, both ends
}

// Tests the video: frame k = tick k·N, so 8 s at 25 fps is 201 frames in video.mp4 (decoded by
// ffprobe), frames.csv and summary["render"]; the camera turns with the chair.
TEST_F(CircuitRunTest, VideoHasOneFramePerTickStep) {
  const auto probe = render::testing::Ffprobe(*out_ / "video.mp4");
  EXPECT_EQ(probe.at("nb_read_frames"), "201");
  EXPECT_EQ(probe.at("width"), "320");
  const auto frames = ReadCsv(*out_ / "frames.csv");
  EXPECT_EQ(frames.at("frame").size(), 201U);
  const nlohmann::json s = Summary(*out_);
  EXPECT_EQ(s["render"]["frames"].get<int>(), 201);
  const auto trial = ReadCsv(*out_ / "trial.csv");
  // the camera's yaw is the chair's at the frame's tick (no roll or pitch tilt added)
  for (std::size_t k = 0; k < 201; k += 20) {
    EXPECT_NEAR(frames.at("cam_yaw_rad")[k], std::remainder(trial.at("yaw_rad")[k * 40], 2 * M_PI), 0.02) << k;
    // x of Rz(ψ) Ry(−θ) Rx(φ) (0.05, 0, 1.25): the eye on the chair, written out
    const double psi = trial.at("yaw_rad")[k * 40], theta = trial.at("pitch_rad")[k * 40];
    const double phi = trial.at("roll_rad")[k * 40];
    const double eye_x = std::cos(psi) * (0.05 * std::cos(theta) - 1.25 * std::cos(phi) * std::sin(theta)) +
                         std::sin(psi) * 1.25 * std::sin(phi);
    EXPECT_NEAR(frames.at("cam_x_m")[k] - trial.at("x_m")[k * 40], eye_x, 1e-9) << k;
  }
  for (const char* stem : {"top_view", "wheels", "mca", "mca_lateral"}) {
    for (const char* ext : {".png", ".svg", ".plot.csv", ".gp"}) {
      EXPECT_TRUE(fs::exists(*out_ / (std::string(stem) + ext))) << stem << ext;
    }
  }
}

// Tests the pixel check of a circuit: the camera's yaw rate seen in the rendered frames (optical
// flow, essential matrix: walls, table and mat at unknown depths) follows the pose log's on every
// one of the 200 frame pairs, in sign, size (15 %: at 320x180 the flow is coarse; the 480x270
// unit test holds 5 %) and time (half a frame), and agrees in sign and size with what the chair's
// own semicircular canals feel (vest_true_scc_z: a high-pass of the rate, so no lag asked).
TEST_F(CircuitRunTest, PixelsShowTheTurnThePoseLogAndTheChairHave) {
  const nlohmann::json check = Summary(*out_)["visual_check"];
  ASSERT_TRUE(check.contains("yaw_rate_vs_pose")) << check.dump();
  EXPECT_EQ(check["frames_estimated"].get<int>(), 200);
  const nlohmann::json& vs_pose = check["yaw_rate_vs_pose"];
  EXPECT_NEAR(vs_pose["gain"].get<double>(), 1.0, 0.15);
  EXPECT_LT(std::abs(vs_pose["lag_s"].get<double>()), 0.5 / 25);
  EXPECT_GT(vs_pose["correlation"].get<double>(), 0.9);
  const nlohmann::json& vs_chair = check["yaw_rate_vs_vestibular_true"];
  EXPECT_NEAR(vs_chair["gain"].get<double>(), 1.0, 0.25);
  EXPECT_GT(vs_chair["correlation"].get<double>(), 0.85);
  const auto csv = ReadCsv(*out_ / "visual_check.csv");
  for (const char* column : {"est_yaw_rate_radps", "pose_yaw_rate_radps", "est_roll_rate_radps",
                             "pose_pitch_rate_radps", "vestibular_platform_yaw_rate_radps"}) {
    EXPECT_EQ(csv.count(column), 1U) << column;
  }
}

// Tests that all four axes of the PW platform are used, and that every command stays inside the
// platform's limits (pose, and rate and acceleration as differences of the command stream).
TEST_F(CircuitRunTest, EveryPlatformAxisIsUsedWithinItsLimits) {
  const Scene scene = LoadScene(kCircuit);
  const mca::McaConfig config = mca::LoadMcaConfig(scene);
  const auto csv = ReadCsv(*out_ / "trial.csv");
  const double dt = scene.clock.dt();
  for (auto [column, dof, least] : {std::tuple{"plat_roll_rad", mca::Dof::kRoll, 0.5 * mca::kDegToRad},
                                    std::tuple{"plat_yaw_rad", mca::Dof::kYaw, 2.0 * mca::kDegToRad},
                                    std::tuple{"plat_pitch_rad", mca::Dof::kPitch, 0.5 * mca::kDegToRad},
                                    std::tuple{"plat_heave_m", mca::Dof::kHeave, 1e-3}}) {
    const std::vector<double>& pose = csv.at(column);
    const mca::DofLimits& limits = config.platform.limits(dof);
    EXPECT_GT(MaxAbs(pose), least) << column;
    EXPECT_LE(MaxAbs(pose), limits.travel) << column;
    for (std::size_t k = 1; k < pose.size(); ++k) {
      // trial.csv prints 17 significant digits: differences are exact to ~1e-15 / dt
      ASSERT_LE(std::abs(pose[k] - pose[k - 1]) / dt, limits.speed * (1 + 1e-6) + 1e-9) << column << " " << k;
      if (k >= 2) {
        ASSERT_LE(std::abs(pose[k] - 2 * pose[k - 1] + pose[k - 2]) / (dt * dt), limits.accel * (1 + 1e-6) + 1e-6)
            << column << " " << k;
      }
    }
  }
  const nlohmann::json s = Summary(*out_);
  EXPECT_TRUE(s["mca"]["platform"]["within_limits"].get<bool>());
  EXPECT_EQ(s["mca"]["platform"]["axes_in_use"], nlohmann::json::array({"heave", "roll", "pitch", "yaw"}));
  EXPECT_LE(s["mca"]["tilt"]["max_roll_deg"].get<double>(), 10.0 + 1e-9);
  EXPECT_EQ(s["mca"]["false_cues"]["tilt_rate_count"].get<int>(), 0);
}

// Tests the head motion against the chair's own motion: the head's yaw rate is the chair's
// (small roll and pitch), and in the left turn the head feels a leftward specific force that
// the platform's roll tilt reproduces with the same sign (left side up).
TEST_F(CircuitRunTest, HeadMotionAgreesWithTheChairAndTiltFollowsTheTurn) {
  const auto csv = ReadCsv(*out_ / "trial.csv");
  const auto& w_z = csv.at("head_w_z_radps");
  const auto& r = csv.at("yaw_rate_radps");
  double worst = 0.0;
  for (std::size_t k = 1; k + 1 < r.size(); ++k) worst = std::max(worst, std::abs(w_z[k] - r[k]));
  EXPECT_LT(worst, 0.02 * MaxAbs(r));
  // the second of the drive with the largest centripetal acceleration v·ω (a left turn): there
  // the head feels a leftward specific force of at least that (plus g sin φ as the chair rolls
  // out of the turn, left side up), and the platform's roll tilt is left side up too
  const auto& v = csv.at("v_mps");
  std::size_t best = 0;
  double best_centripetal = -1e9;
  for (std::size_t from = 0; from + 1000 <= v.size(); from += 100) {
    double sum = 0.0;
    for (std::size_t k = from; k < from + 1000; ++k) sum += v[k] * r[k] / 1000;
    if (sum > best_centripetal) {
      best_centripetal = sum;
      best = from;
    }
  }
  ASSERT_GT(best_centripetal, 0.05) << "the circuit turns left";
  double fs_y = 0.0, tilt = 0.0;
  for (std::size_t k = best; k < best + 1000; ++k) {
    fs_y += csv.at("head_fs_y_mps2")[k] / 1000;
    tilt += csv.at("vis_tilt_roll_rad")[k] / 1000;
  }
  EXPECT_GT(fs_y, 0.8 * best_centripetal);
  EXPECT_GT(tilt, 0.0);
}

// Tests summary["circuit"]: the route, contacts, lift-offs, per-contact entries.
TEST_F(CircuitRunTest, SummaryCarriesTheCircuit) {
  const nlohmann::json s = Summary(*out_);
  const nlohmann::json& c = s["circuit"];
  EXPECT_EQ(c["gates"]["passed"].get<int>(), 2);
  EXPECT_TRUE(c["gates"]["all_passed"].get<bool>());
  EXPECT_EQ(c["contacts"]["events"].get<int>(), 0);
  EXPECT_TRUE(c["lift_offs"].contains("episodes"));
  EXPECT_EQ(c["lift_offs"]["per_contact"].size(), 6U);
  EXPECT_GT(c["distance_m"].get<double>(), 5.0);
  EXPECT_GT(c["peak_yaw_rate_degps"].get<double>(), 10.0);
  EXPECT_TRUE(s.contains("peak_roll"));
  EXPECT_FALSE(s.contains("speed_mps"));
}

// Tests summary["training"] against summary["circuit"], counted separately from the same run:
// gates, contacts and lift-off episodes agree; the route was completed (both gates) before the
// end; no contact means a positive clearance; the page is written.
TEST_F(CircuitRunTest, SummaryCarriesTheTrainingMetrics) {
  const nlohmann::json s = Summary(*out_);
  const nlohmann::json& c = s["circuit"];
  const nlohmann::json& t = s["training"];
  ASSERT_TRUE(t.is_object());
  EXPECT_EQ(t["gates"]["passed"], c["gates"]["passed"]);
  EXPECT_EQ(t["gates"]["total"], c["gates"]["total"]);
  EXPECT_EQ(t["contacts"]["count"], c["contacts"]["events"]);
  EXPECT_EQ(t["lift_offs"]["episodes"], c["lift_offs"]["episodes"]);
  EXPECT_TRUE(t["completed"].get<bool>());
  EXPECT_GT(t["completion_time_s"].get<double>(), 0.0);
  EXPECT_LE(t["completion_time_s"].get<double>(), c["duration_s"].get<double>());
  EXPECT_GT(t["clearance"]["min_m"].get<double>(), 0.0);
  EXPECT_GE(t["route_deviation_m"]["max"].get<double>(), t["route_deviation_m"]["mean"].get<double>());
  EXPECT_TRUE(fs::exists(*out_ / "training.md"));
}

// Tests same scene, same bits: two runs write identical trial.csv and summary circuit/mca parts.
TEST(CircuitRunRepeat, SameSceneSameBits) {
  const Scene scene = LoadScene(kCircuit);
  RenderStageOptions render;
  render.no_video = true;
  const fs::path a = Scratch("repeat_a"), b = Scratch("repeat_b");
  RunCircuitScene(scene, kCircuit.string(), 7, render, a);
  RunCircuitScene(scene, kCircuit.string(), 7, render, b);
  EXPECT_EQ(Bytes(a / "trial.csv"), Bytes(b / "trial.csv"));
  EXPECT_EQ(Summary(a)["mca"], Summary(b)["mca"]);
  EXPECT_EQ(Summary(a)["circuit"], Summary(b)["circuit"]);
  EXPECT_EQ(Summary(a)["training"], Summary(b)["training"]);
  EXPECT_EQ(Summary(a)["render"]["skipped"], "--no-video");
}

// Tests "done when": every shipped circuit (scenes/circuit_*.yaml) runs headless to its end with
// video, the four platform axes in use and inside their limits.
TEST(ShippedCircuits, EachRunsToItsEndWithVideoAndFourAxes) {
  int circuits = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(PWSIM_SOURCE_DIR) / "scenes")) {
    const std::string name = entry.path().filename().string();
    if (!name.starts_with("circuit_") || entry.path().extension() != ".yaml") continue;
    ++circuits;
    const Scene scene = LoadScene(entry.path());
    ASSERT_TRUE(scene.is_circuit()) << name;
    RenderStageOptions render;
    render.width_px = 160;
    render.height_px = 90;
    render.fps = 10;
    const fs::path out = Scratch(name);
    RunCircuitScene(scene, entry.path().string(), 50, render, out);
    const nlohmann::json s = Summary(out);
    EXPECT_NEAR(s["duration_s"].get<double>(), scene.circuit->duration, 1e-9) << name;
    const int frames = static_cast<int>(std::llround(scene.circuit->duration * 10)) + 1;
    EXPECT_EQ(s["render"]["frames"].get<int>(), frames) << name;
    EXPECT_EQ(render::testing::Ffprobe(out / "video.mp4").at("nb_read_frames"), std::to_string(frames)) << name;
    EXPECT_TRUE(s["mca"]["platform"]["within_limits"].get<bool>()) << name;
    EXPECT_EQ(s["mca"]["platform"]["axes_in_use"], nlohmann::json::array({"heave", "roll", "pitch", "yaw"})) << name;
    EXPECT_TRUE(fs::exists(out / "top_view.png")) << name;
  }
  EXPECT_GE(circuits, 3);
}

}  // namespace
}  // namespace pwsim::report
