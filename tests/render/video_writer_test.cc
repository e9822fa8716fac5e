#include "render/video_writer.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "render/image_io.h"
#include "tests/render/ffprobe.h"
#include "tests/run_command.h"

namespace pwsim::render {
namespace {


/// Frame k: a colour ramp that shifts with k (so every frame differs).
Image TestFrame(int k, int width = 64, int height = 48) {
  Image image{width, height,
              std::vector<std::uint8_t>(static_cast<std::size_t>(width * height * 4))};
  for (int r = 0; r < height; ++r) {
    for (int c = 0; c < width; ++c) {
      std::uint8_t* p = &image.bgra[static_cast<std::size_t>((r * width + c) * 4)];
      p[0] = static_cast<std::uint8_t>(4 * c + 7 * k);
      p[1] = static_cast<std::uint8_t>(5 * r + 3 * k);
      p[2] = static_cast<std::uint8_t>(c * r + k);
      p[3] = 255;
    }
  }
  return image;
}

// Tests that ffprobe reads the H.264 video with every frame and a duration of frames / fps.
TEST(VideoWriterTest, FfprobeReadsFrameCountAndDuration) {
  const pwsim::testing::TempDir temp("video_test_h264");  // its own, removed after
  const std::filesystem::path& dir = temp.path();
  VideoWriter dut({dir / "video.mp4", 64, 48, 25, VideoCodec::kH264, 20});
  for (int k = 0; k < 25; ++k) dut.Push(TestFrame(k).view());
  dut.Close();
  const auto probe = testing::Ffprobe(dir / "video.mp4");
  EXPECT_EQ(probe.at("codec_name"), FfmpegHasEncoder("libx264") ? "h264" : "mpeg4");
  EXPECT_EQ(probe.at("nb_read_frames"), "25");
  EXPECT_NEAR(std::stod(probe.at("duration")), 1.0, 1e-6);
  EXPECT_EQ(probe.at("r_frame_rate"), "25/1");
  EXPECT_FALSE(std::filesystem::exists(dir / "video.mp4.partial"));
}

// Tests that the lossless video decodes to exactly the pixels pushed.
TEST(VideoWriterTest, LosslessIsExact) {
  const pwsim::testing::TempDir temp("video_test_lossless");  // its own, removed after
  const std::filesystem::path& dir = temp.path();
  VideoWriter dut({dir / "video.mkv", 64, 48, 25, VideoCodec::kLossless, 0});
  for (int k = 0; k < 5; ++k) dut.Push(TestFrame(k).view());
  dut.Close();
  const std::string command = "ffmpeg -v error -i '" + (dir / "video.mkv").string() +
                              "' -vf select='eq(n\\,3)' -frames:v 1 '" +
                              (dir / "frame3.png").string() + "'";
  ASSERT_EQ(std::system(command.c_str()), 0);
  const Image decoded = ReadPng(dir / "frame3.png");
  EXPECT_EQ(ComparePixels(decoded.view(), TestFrame(3).view()).max, 0);
}

// Tests that an abandoned (never closed) video leaves no file behind.
TEST(VideoWriterTest, AbandonedLeavesNoFile) {
  const pwsim::testing::TempDir temp("video_test_abandoned");  // its own, removed after
  const std::filesystem::path& dir = temp.path();
  {
    VideoWriter dut({dir / "video.mp4", 64, 48, 25, VideoCodec::kH264, 20});
    dut.Push(TestFrame(0).view());
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "video.mp4"));
  EXPECT_FALSE(std::filesystem::exists(dir / "video.mp4.partial"));
}

}  // namespace
}  // namespace pwsim::render
