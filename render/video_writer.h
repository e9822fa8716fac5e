#pragma once
// VideoWriter: encodes BGRA frames to a video file through an `ffmpeg` child process fed on a
// pipe, from a writer thread, so rendering frame k+1 overlaps encoding frame k. Constant frame
// rate: frame k is shown at k / fps. The file appears only when Close() succeeds (it is written
// under a ".partial" name and renamed).
//
//   VideoWriter video({.file = dir / "video.mp4", .width = 1280, .height = 720, .fps = 50});
//   for (...) video.Push(renderer.Render(...));
//   video.Close();   // throws if ffmpeg failed

#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "render/offscreen_renderer.h"

namespace pwsim::render {

enum class VideoCodec {
  kH264,      ///< libx264 CRF (yuv420p) in .mp4; MPEG-4 Part 2 where the build lacks libx264
  kLossless,  ///< libx264rgb -qp 0 (exact BGR) in .mkv; FFV1 where the build lacks it
};

struct VideoConfig {
  std::filesystem::path file;
  int width{0};   ///< [px] even
  int height{0};  ///< [px] even
  int fps{50};    ///< [frames/s]
  VideoCodec codec{VideoCodec::kH264};
  int crf{20};                      ///< H.264 quality (lower is better)
  std::string preset{"ultrafast"};  ///< x264 speed preset (ultrafast … veryslow)
  int queue_frames{3};              ///< frames buffered between the renderer and the encoder
};

/// True when this machine's ffmpeg lists `encoder` (e.g. "libx264") under -encoders.
bool FfmpegHasEncoder(const std::string& encoder);

/// Where the writer's time went (wall seconds, summed over frames), for the benchmark breakdown.
struct VideoWriterStats {
  double copy_s{0.0};     ///< Push: copying frames into the queue (caller's thread)
  double convert_s{0.0};  ///< writer thread: BGRA → I420 (H.264 only)
  double write_s{0.0};    ///< writer thread: fwrite to ffmpeg (blocks while ffmpeg encodes)
};

class VideoWriter final {
 public:
  /// Starts ffmpeg. @throws std::runtime_error if ffmpeg cannot be started.
  explicit VideoWriter(VideoConfig config);
  ~VideoWriter();  ///< abandons an unclosed video (no file left behind)
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  /// Copies the frame into the queue (waits while the queue is full). @pre same size as config.
  void Push(const ImageView& frame);
  /// Flushes, waits for ffmpeg, renames the file into place. @throws std::runtime_error.
  void Close();

  const std::string& encoder() const { return encoder_; }  ///< e.g. "libx264"
  std::int64_t frames() const { return pushed_; }
  /// Time spent so far; complete after Close().
  VideoWriterStats stats() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return stats_;
  }

 private:
  void WriterLoop();

  VideoConfig config_;
  std::filesystem::path partial_;
  std::filesystem::path log_;
  std::string encoder_;
  std::FILE* pipe_{nullptr};
  std::thread thread_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::vector<std::uint8_t>> queue_;
  std::vector<std::vector<std::uint8_t>> spare_;
  bool yuv420_{false};                   ///< convert to I420 before the pipe
  std::vector<std::uint8_t> yuv_bytes_;  ///< writer thread's conversion buffer
  bool closing_{false};
  bool write_failed_{false};
  bool closed_{false};
  std::int64_t pushed_{0};
  VideoWriterStats stats_;
};

}  // namespace pwsim::render
