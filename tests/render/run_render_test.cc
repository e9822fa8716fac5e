// End-to-end: `pwsim run` renders the default trial headlessly (app/run_render.h), and what it
// writes agrees with itself: ffprobe's frame count and duration, frames.csv's ticks, and the
// pitch rate seen in the pixels against the camera-pose log.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "tests/render/ffprobe.h"
#include "tests/run_command.h"

namespace pwsim::app {
namespace {

const std::string kPwsim = PWSIM_BINARY_DIR "/pwsim";

/// `pwsim run` with `options` into dir/out (returned), its output logged in `dir`.
std::filesystem::path RunPwsim(const pwsim::testing::TempDir& dir, const std::string& options) {
  const pwsim::testing::CommandResult r = pwsim::testing::RunCommand(
      "cd '" PWSIM_SOURCE_DIR "' && '" + kPwsim + "' run --out " + dir.Quoted("out") + " " + options, dir);
  EXPECT_EQ(r.exit_code, 0) << r.command << "\n" << r.output;
  return dir / "out";
}

nlohmann::json ReadJson(const std::filesystem::path& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

/// Column `name` of a CSV file with a header row.
std::vector<double> CsvColumn(const std::filesystem::path& file, const std::string& name) {
  std::ifstream in(file);
  std::string line, cell;
  std::getline(in, line);
  std::stringstream header(line);
  int index = -1;
  for (int i = 0; std::getline(header, cell, ','); ++i) {
    if (cell == name) index = i;
  }
  std::vector<double> out;
  while (index >= 0 && std::getline(in, line)) {
    std::stringstream row(line);
    for (int i = 0; std::getline(row, cell, ','); ++i) {
      if (i == index) out.push_back(std::stod(cell));
    }
  }
  return out;
}

// Tests that the trial video has one frame per N ticks, that ffprobe reads that many frames
// and a duration of frames / fps, and that the pixel check agrees with the pose log.
TEST(RunRenderTest, VideoFramesCsvAndPixelCheckAgree) {
  const pwsim::testing::TempDir temp("run_render_mono");
  const auto dir = RunPwsim(temp, "--size 320x180 --fps 25");
  const nlohmann::json summary = ReadJson(dir / "summary.json");
  const nlohmann::json& render = summary.at("render");
  const int frames = render.at("frames").get<int>();
  const int ticks = summary.at("ticks").get<int>();
  EXPECT_EQ(render.at("ticks_per_frame").get<int>(), 40);
  EXPECT_EQ(frames, (ticks - 1) / 40 + 1);

  const auto probe = render::testing::Ffprobe(dir / "video.mp4");
  EXPECT_EQ(std::stoi(probe.at("nb_read_frames")), frames);
  EXPECT_NEAR(std::stod(probe.at("duration")), frames / 25.0, 1e-6);
  EXPECT_EQ(probe.at("width"), "320");

  const std::vector<double> tick = CsvColumn(dir / "frames.csv", "tick");
  const std::vector<double> time = CsvColumn(dir / "frames.csv", "t_s");
  ASSERT_EQ(static_cast<int>(tick.size()), frames);
  for (int k = 0; k < frames; ++k) {
    ASSERT_EQ(tick[static_cast<std::size_t>(k)], 40.0 * k);  // frame k is tick k·N exactly
    ASSERT_EQ(time[static_cast<std::size_t>(k)], (40.0 * k) / 1000.0);
  }

  const nlohmann::json& pitch = summary.at("visual_check").at("pitch_rate_vs_pose");
  EXPECT_GT(pitch.at("correlation").get<double>(), 0.95);
  EXPECT_NEAR(pitch.at("gain").get<double>(), 1.0, 0.1);
  EXPECT_LT(std::abs(pitch.at("lag_s").get<double>()), 1.0 / 25);
  EXPECT_TRUE(std::filesystem::exists(dir / "visual_check.png"));
}

// Tests that --no-video skips rendering.
TEST(RunRenderTest, NoVideoSkipsRendering) {
  const pwsim::testing::TempDir temp("run_render_novideo");
  const auto dir = RunPwsim(temp, "--no-video");
  EXPECT_FALSE(std::filesystem::exists(dir / "video.mp4"));
  EXPECT_EQ(ReadJson(dir / "summary.json").at("render").at("skipped"), "--no-video");
}

// Tests that a frame rate that does not divide the clock rate is refused with a clear message.
TEST(RunRenderTest, FpsMustDivideClockRate) {
  const pwsim::testing::TempDir dir("run_render_fps");
  EXPECT_TRUE(pwsim::testing::Refused(
      pwsim::testing::RunCommand("'" + kPwsim + "' run --fps 60 --out " + dir.Quoted("out"), dir), 2,
      {"option --fps", "divisor of the clock rate", "got 60"}));
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "video.mp4"));
}

}  // namespace
}  // namespace pwsim::app
