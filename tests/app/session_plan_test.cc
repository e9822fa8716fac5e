// A session that follows a study plan (pwsim study plan -> pwsim session --plan): each planned
// trial replays the planned condition's source, T_r the tracked motion of a measured trial and
// T_m the model driven by the same measured x(t) (report/trial_track.h, hardware/track_streams.h).
// Unit: the measured track is the mocap track itself (at the mocap samples) and the two sources
// differ. End to end: `pwsim platform-sim` and `pwsim session` on loopback, synchronised on
// events only (platform-sim's first output line through a pipe, process exits); every setpoint
// the session logged equals the offline streams of the planned source, bit for bit.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "engine/chair.h"
#include "sysid/measured/measured_trial.h"
#include "engine/number_format.h"
#include "engine/scene.h"
#include "report/trial_track.h"
#include "hardware/session_streams.h"
#include "hardware/track_streams.h"
#include "hardware/udp_socket.h"
#include "study/plan.h"

namespace pwsim::app {
namespace {

namespace fs = std::filesystem;
using report::TrialSource;
using report::TrialTrack;

const std::string kPwsim = std::string(PWSIM_BINARY_DIR) + "/pwsim";
const fs::path kTrial = fs::path(PWSIM_SOURCE_DIR) / "assets/trials-demo/v1.20_m0_cushion_r1";
const fs::path kScene = fs::path(PWSIM_SOURCE_DIR) / "scenes/speed_cushion.yaml";

/// The session's configuration for `scene`: its clock and its platform's drives (pw4dof: 5).
hw::SessionConfig ConfigFor(const Scene& scene) {
  hw::SessionConfig config;
  config.clock_rate_hz = scene.clock.rate_hz;
  const mca::PlatformSpec platform = hw::SessionMcaConfig(scene).platform;
  config.SetPlatform(platform.name, platform.mechanism);
  return config;
}

Chair ModelChair(const MeasuredTrial& trial) {
  return trial.chair.gm && trial.chair.lm ? trial.chair : MakeTableOneChair();
}

TEST(TrialTrack, MeasuredTrackIsTheMocapAndModelDiffers) {
  const MeasuredTrial trial = ReadMeasuredTrial(kTrial);
  const double dt = 1e-3;
  const mca::SagittalTrack measured = TrialTrack(trial, TrialSource::kMeasured, ModelChair(trial), dt);
  const mca::SagittalTrack model = TrialTrack(trial, TrialSource::kModel, ModelChair(trial), dt);
  ASSERT_EQ(measured.x.size(), model.x.size());
  // at tick k the track is the mocap linearly interpolated: check against the mocap samples
  const double t0 = trial.track.t.front();
  int checked = 0;
  for (std::size_t i = 0; i < trial.track.size(); i += 37) {
    const double k = (trial.track.t[i] - t0) / dt;
    if (std::abs(k - std::round(k)) > 1e-9 || std::round(k) >= static_cast<double>(measured.z.size())) continue;
    const auto tick = static_cast<std::size_t>(std::llround(k));
    EXPECT_NEAR(measured.z[tick], trial.track.z[i], 1e-12);
    EXPECT_NEAR(measured.pitch[tick], trial.track.pitch[i], 1e-12);
    ++checked;
  }
  EXPECT_GT(checked, 5);
  double max_dz = 0.0;
  for (std::size_t k = 0; k < model.z.size(); ++k) max_dz = std::max(max_dz, std::abs(model.z[k] - measured.z[k]));
  EXPECT_GT(max_dz, 1e-4);  // two different motions...
  EXPECT_LT(max_dz, 0.1);   // ...of the same drive over the same ground
}

TEST(TrackStreams, OneSetpointPerDriveCycleAndTheTicksMustMatch) {
  const Scene scene = LoadScene(kScene);
  const MeasuredTrial trial = ReadMeasuredTrial(kTrial);
  const hw::SessionConfig config = ConfigFor(scene);
  const double dt = 1.0 / config.clock_rate_hz;
  const mca::SagittalTrack track = TrialTrack(trial, TrialSource::kMeasured, ModelChair(trial), dt);
  std::string description;
  const hw::SessionStreams streams = hw::BuildTrackSessionStreams(scene, config, track, 20, "T", &description);
  const std::size_t n = track.x.size();
  EXPECT_EQ(streams.setpoints.size(), (n + static_cast<std::size_t>(config.drive_cycle_ticks) - 1) /
                                          static_cast<std::size_t>(config.drive_cycle_ticks));
  EXPECT_EQ(streams.cameras.size(), (n + static_cast<std::size_t>(config.frame_ticks) - 1) /
                                        static_cast<std::size_t>(config.frame_ticks));
  EXPECT_EQ(description.rfind("T, MCA", 0), 0u) << description;
  mca::SagittalTrack coarse = track;
  coarse.dt = 2 * dt;
  EXPECT_THROW(hw::BuildTrackSessionStreams(scene, config, coarse, 20, "T", nullptr), std::invalid_argument);
}

/// Runs `args` with stdout+stderr into `log`; returns the pid.
pid_t Spawn(const std::vector<std::string>& args, const fs::path& log, int stdout_pipe = -1) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    FILE* f = std::fopen(log.c_str(), "w");
    if (f != nullptr) ::dup2(::fileno(f), 2);
    ::dup2(stdout_pipe >= 0 ? stdout_pipe : ::fileno(f), 1);
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  return pid;
}

int WaitExit(pid_t pid) {
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return -1;
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -2;
}

std::string ReadText(const fs::path& file) {
  std::ifstream in(file);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// `pwsim session` with `session_args` (after SCENE and the links) through platform-sim, writing
/// into dir/out_name; returns the session's exit status.
int RunSession(const fs::path& dir, const std::string& out_name, const std::vector<std::string>& session_args,
               std::string* outputs) {
  hw::UdpSocket probe;
  if (!probe.Bind(*hw::ParseUdpAddress("127.0.0.1:0")).empty()) return -10;
  const std::string port = std::to_string(probe.local_port());
  probe = hw::UdpSocket();  // free the port for platform-sim
  int fds[2];
  if (::pipe(fds) != 0) return -11;
  // the scene's platform: pw4dof, five drives
  const pid_t platform = Spawn({kPwsim, "platform-sim", "--platform", std::string(PWSIM_SOURCE_DIR) + "/scenes/platforms/pw4dof.yaml",
                                "--listen", "127.0.0.1:" + port, "--idle-exit", "60", "--adopt-first-peer"},
                               dir / "platform.err", fds[1]);
  ::close(fds[1]);
  // event: platform-sim's first line says it is listening
  std::string first;
  char c = 0;
  while (::read(fds[0], &c, 1) == 1 && c != '\n') first += c;
  std::vector<std::string> args{kPwsim, "session", kScene.string(), "--can", "udp:127.0.0.1:" + port, "--hmd", "none",
                                "--duration", "1.0", "--max-stop-s", "10", "--out", (dir / out_name).string()};
  args.insert(args.end(), session_args.begin(), session_args.end());
  const pid_t session = Spawn(args, dir / "session.out");
  const int session_status = WaitExit(session);
  // The session has ended (parked or not): platform-sim is told to stop (an event, not its idle
  // timer: a 1 s idle exit used to end it mid-session when a loaded machine stalled the master).
  ::kill(platform, SIGTERM);
  // drain platform-sim's output so it never blocks on a full pipe, until it exits
  std::string rest;
  while (::read(fds[0], &c, 1) == 1) rest += c;
  ::close(fds[0]);
  const int platform_status = WaitExit(platform);
  *outputs = "--- session\n" + ReadText(dir / "session.out") + "--- platform-sim\n" + first + "\n" + rest +
             ReadText(dir / "platform.err") + "(platform-sim exit " + std::to_string(platform_status) + ")\n";
  return session_status;
}

/// One planned trial through platform-sim + session; returns the session's exit status.
int RunPlannedSession(const fs::path& dir, const std::string& participant, int index, std::string* outputs) {
  return RunSession(dir, "out_" + participant + "_" + std::to_string(index),
                    {"--plan", (dir / "plan.csv").string(), "--participant", participant, "--trial-index",
                     std::to_string(index), "--trial", kTrial.string()},
                    outputs);
}

/// The pose commands a session logged (its "M tick surge sway heave roll pitch yaw" lines), as
/// written: the tick, then the six numbers.
std::vector<std::array<std::string, 7>> LoggedSetpoints(const fs::path& log_file) {
  std::vector<std::array<std::string, 7>> rows;
  std::ifstream log(log_file);
  for (std::string line; std::getline(log, line);) {
    if (line.rfind("M ", 0) != 0) continue;
    std::istringstream in(line.substr(2));
    std::array<std::string, 7> row;
    for (std::string& x : row) in >> x;
    rows.push_back(row);
  }
  return rows;
}

/// The logged pose command is `pose`, bit for bit.
void ExpectLogged(const std::array<std::string, 7>& row, const mca::DofArray& pose) {
  for (std::size_t k = 0; k < pose.size(); ++k) ASSERT_EQ(row[k + 1], FormatDouble(pose[k])) << "tick " << row[0] << " axis " << k;
}

TEST(SessionPlan, EachPlannedTrialReplaysItsConditionsSource) {
  if (!fs::exists(kPwsim)) GTEST_SKIP() << kPwsim << " not built";
  const fs::path dir = fs::path(PWSIM_BINARY_DIR) / "test_out" / "session_plan";
  fs::remove_all(dir);
  fs::create_directories(dir);
  study::PlanOptions options;
  options.participants = 2;
  options.seed = 5;
  const study::StudyPlan plan = study::MakePlan(options);
  std::ofstream(dir / "plan.csv") << study::PlanCsv(plan);

  const Scene scene = LoadScene(kScene);
  const MeasuredTrial trial = ReadMeasuredTrial(kTrial);
  std::vector<std::string> logs;
  for (int index = 1; index <= 2; ++index) {
    const study::PlanTrial& planned = plan.trials[static_cast<std::size_t>(index - 1)];  // P01's trials
    ASSERT_EQ(planned.participant, "P01");
    std::string outputs;
    ASSERT_EQ(RunPlannedSession(dir, "P01", index, &outputs), 0) << outputs;
    const fs::path out = dir / ("out_P01_" + std::to_string(index));
    std::ifstream tj(out / "trial.json");
    const nlohmann::json j = nlohmann::json::parse(tj);
    EXPECT_EQ(j["participant"], "P01");
    EXPECT_EQ(j["trial_index"], index);
    EXPECT_EQ(j["condition"], planned.condition);
    const TrialSource source = planned.condition == "T_r" ? TrialSource::kMeasured : TrialSource::kModel;
    EXPECT_EQ(j["source"], TrialSourceName(source));

    // every logged setpoint is the planned source's, bit for bit
    const hw::SessionConfig config = ConfigFor(scene);
    const double dt = 1.0 / config.clock_rate_hz;
    const hw::SessionStreams streams = hw::BuildTrackSessionStreams(
        scene, config, TrialTrack(trial, source, ModelChair(trial), dt), 20, "", nullptr);
    const TrialSource other_source = source == TrialSource::kMeasured ? TrialSource::kModel : TrialSource::kMeasured;
    const hw::SessionStreams other = hw::BuildTrackSessionStreams(
        scene, config, TrialTrack(trial, other_source, ModelChair(trial), dt), 20, "", nullptr);
    int discriminating = 0;  // logged setpoints the other source would have made differently
    int compared = 0;
    for (const auto& row : LoggedSetpoints(out / "session.log")) {
      const long long tick = std::stoll(row[0]);
      const auto i = std::min(static_cast<std::size_t>(tick / config.drive_cycle_ticks), streams.setpoints.size() - 1);
      ExpectLogged(row, streams.setpoints[i]);
      if (other.setpoints[std::min(i, other.setpoints.size() - 1)] != streams.setpoints[i]) ++discriminating;
      ++compared;
    }
    EXPECT_GT(compared, 100) << outputs;
    EXPECT_GT(discriminating, compared / 2) << "the check would not tell T_r from T_m";
    logs.push_back(ReadText(out / "session.log"));
  }
  // the two trials of P01 are the two conditions
  EXPECT_NE(plan.trials[0].condition, plan.trials[1].condition);
}

TEST(SessionPlan, MeasuredConditionWithoutTrialIsRefused) {
  if (!fs::exists(kPwsim)) GTEST_SKIP() << kPwsim << " not built";
  const fs::path dir = fs::path(PWSIM_BINARY_DIR) / "test_out" / "session_plan_refused";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "plan.csv") << "participant,trial_index,condition\nP01,1,T_r\nP01,2,T_m\n";
  const std::string cmd = kPwsim + " session --can udp:127.0.0.1:9 --hmd none --plan " + (dir / "plan.csv").string() +
                          " --participant P01 --trial-index 1 --out " + (dir / "out").string() + " > " +
                          (dir / "log").string() + " 2>&1";
  const int status = std::system(cmd.c_str());
  EXPECT_EQ(WEXITSTATUS(status), 2);
  EXPECT_NE(ReadText(dir / "log").find("give --trial TRIAL_DIR"), std::string::npos) << ReadText(dir / "log");
  const std::string cmd2 = kPwsim + " session --can udp:127.0.0.1:9 --hmd none --plan " + (dir / "plan.csv").string() +
                           " --participant P07 --out " + (dir / "out").string() + " > " + (dir / "log2").string() + " 2>&1";
  EXPECT_EQ(WEXITSTATUS(std::system(cmd2.c_str())), 1);
  EXPECT_NE(ReadText(dir / "log2").find("field 'participant'"), std::string::npos) << ReadText(dir / "log2");
}


// `pwsim session --mca mpc` on the scene: trial.json names the MPC and every logged setpoint is
// the MPC's offline stream (hw::BuildSessionStreams with the override), bit for bit, which
// differs from the washout's the scene itself names.
TEST(SessionMca, OptionReachesTheLoop) {
  if (!fs::exists(kPwsim)) GTEST_SKIP() << kPwsim << " not built";
  const fs::path dir = fs::path(PWSIM_BINARY_DIR) / "test_out" / "session_mca";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string outputs;
  ASSERT_EQ(RunSession(dir, "out", {"--mca", "mpc"}, &outputs), 0) << outputs;
  std::ifstream tj(dir / "out" / "trial.json");
  const nlohmann::json j = nlohmann::json::parse(tj);
  EXPECT_EQ(j["mca"], "mpc");

  const Scene scene = LoadScene(kScene);
  const hw::SessionConfig config = ConfigFor(scene);
  const hw::SessionStreams mpc = hw::BuildSessionStreams(scene, config, nullptr, mca::McaAlgorithm::kMpc);
  const hw::SessionStreams washout = hw::BuildSessionStreams(scene, config, nullptr);
  EXPECT_EQ(mpc.mca_algorithm, "mpc");
  EXPECT_EQ(washout.mca_algorithm, "washout");
  int compared = 0, discriminating = 0;
  for (const auto& row : LoggedSetpoints(dir / "out" / "session.log")) {
    const long long tick = std::stoll(row[0]);
    const auto i = std::min(static_cast<std::size_t>(tick / config.drive_cycle_ticks), mpc.setpoints.size() - 1);
    ExpectLogged(row, mpc.setpoints[i]);
    if (washout.setpoints[std::min(i, washout.setpoints.size() - 1)] != mpc.setpoints[i]) ++discriminating;
    ++compared;
  }
  EXPECT_GT(compared, 100) << outputs;
  EXPECT_GT(discriminating, compared / 2) << "the check would not tell the MPC from the washout";
}

}  // namespace
}  // namespace pwsim::app
