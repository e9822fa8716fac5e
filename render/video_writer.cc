#include "render/video_writer.h"

#include <fcntl.h>

#include <chrono>
#include <csignal>
#include <cstring>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <stdexcept>

#include "engine/check.h"

namespace pwsim::render {
namespace {

std::string Quoted(const std::filesystem::path& path) {
  std::string out = "'";
  for (const char c : path.string()) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string ReadTail(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  return s.size() > 800 ? s.substr(s.size() - 800) : s;
}

}  // namespace

bool FfmpegHasEncoder(const std::string& encoder) {
  std::FILE* pipe = ::popen("ffmpeg -hide_banner -encoders 2>/dev/null", "r");
  if (pipe == nullptr) return false;
  char line[512];
  bool found = false;
  while (std::fgets(line, sizeof(line), pipe) != nullptr) {
    std::istringstream words(line);
    std::string flags, name;
    words >> flags >> name;
    if (name == encoder) found = true;
  }
  ::pclose(pipe);
  return found;
}

VideoWriter::VideoWriter(VideoConfig config) : config_(std::move(config)) {
  PWSIM_DEMAND(config_.width > 0 && config_.height > 0 && config_.width % 2 == 0 &&
               config_.height % 2 == 0 && config_.fps > 0 && config_.queue_frames >= 1);
  // Pick the encoder this ffmpeg build has; name the container explicitly (the partial file's
  // extension says nothing).
  std::string codec_args, container;
  // H.264 is fed yuv420p converted here (OpenCV's SIMD BGRA→I420, in the writer thread): a
  // third of the bytes through the pipe and no swscale in ffmpeg. Lossless stays BGRA.
  yuv420_ = config_.codec == VideoCodec::kH264;
  if (config_.codec == VideoCodec::kH264) {
    container = "mp4";
    if (FfmpegHasEncoder("libx264")) {
      encoder_ = "libx264";
      codec_args = "-c:v libx264 -preset " + config_.preset + " -crf " +
                   std::to_string(config_.crf) + " -movflags +faststart";
    } else {
      encoder_ = "mpeg4";
      codec_args = "-c:v mpeg4 -q:v 3";
    }
  } else {
    container = "matroska";
    if (FfmpegHasEncoder("libx264rgb")) {
      encoder_ = "libx264rgb";
      codec_args = "-c:v libx264rgb -preset ultrafast -qp 0 -pix_fmt bgr24";
    } else {
      encoder_ = "ffv1";
      codec_args = "-c:v ffv1 -pix_fmt bgr0";
    }
  }
  std::filesystem::create_directories(
      config_.file.parent_path().empty() ? std::filesystem::path(".") : config_.file.parent_path());
  partial_ = config_.file;
  partial_ += ".partial";
  log_ = config_.file;
  log_ += ".ffmpeg.log";
  const std::string command =
      "ffmpeg -hide_banner -loglevel error -nostdin -y -f rawvideo -pix_fmt " +
      std::string(yuv420_ ? "yuv420p" : "bgra") + " -s " + std::to_string(config_.width) + "x" +
      std::to_string(config_.height) + " -framerate " + std::to_string(config_.fps) + " -i - -an " +
      codec_args + " -f " + container + " " + Quoted(partial_) + " 2>" + Quoted(log_);
  // A dead ffmpeg must surface as a write error, not kill pwsim with SIGPIPE.
  std::signal(SIGPIPE, SIG_IGN);
  pipe_ = ::popen(command.c_str(), "w");
  if (pipe_ == nullptr) throw std::runtime_error("render: could not start ffmpeg: " + command);
  // A 1 MiB pipe instead of the default 64 KiB: a stereo I420 frame (6.9 MB) then crosses in
  // 7 writes instead of 105, with fewer wake-ups of ffmpeg. Best effort (the size is capped by
  // /proc/sys/fs/pipe-max-size); failure leaves the default.
  (void)::fcntl(::fileno(pipe_), F_SETPIPE_SZ, 1 << 20);
  thread_ = std::thread([this] { WriterLoop(); });
}

VideoWriter::~VideoWriter() {
  if (closed_) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closing_ = true;
  }
  changed_.notify_all();
  if (thread_.joinable()) thread_.join();
  if (pipe_ != nullptr) ::pclose(pipe_);
  std::error_code ignored;
  std::filesystem::remove(partial_, ignored);
}

void VideoWriter::Push(const ImageView& frame) {
  PWSIM_DEMAND(!closed_ && frame.width == config_.width && frame.height == config_.height);
  const std::size_t bytes = static_cast<std::size_t>(frame.width) * frame.height * 4;
  std::vector<std::uint8_t> buffer;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] {
      return static_cast<int>(queue_.size()) < config_.queue_frames || write_failed_;
    });
    if (!spare_.empty()) {
      buffer = std::move(spare_.back());
      spare_.pop_back();
    }
  }
  const auto copy_start = std::chrono::steady_clock::now();
  buffer.resize(bytes);
  std::memcpy(buffer.data(), frame.bgra, bytes);
  const double copy_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - copy_start).count();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    queue_.push_back(std::move(buffer));
    ++pushed_;
    stats_.copy_s += copy_s;
  }
  changed_.notify_all();
}

void VideoWriter::WriterLoop() {
  for (;;) {
    std::vector<std::uint8_t> frame;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait(lock, [&] { return !queue_.empty() || closing_; });
      if (queue_.empty()) return;
      frame = std::move(queue_.front());
      queue_.pop_front();
    }
    const std::vector<std::uint8_t>* bytes = &frame;
    const auto convert_start = std::chrono::steady_clock::now();
    if (yuv420_) {
      yuv_bytes_.resize(static_cast<std::size_t>(config_.width) * config_.height * 3 / 2);
      const cv::Mat bgra(config_.height, config_.width, CV_8UC4, frame.data());
      cv::Mat yuv(config_.height * 3 / 2, config_.width, CV_8UC1, yuv_bytes_.data());
      cv::cvtColor(bgra, yuv, cv::COLOR_BGRA2YUV_I420);  // fills yuv_bytes_ in place
      bytes = &yuv_bytes_;
    }
    const auto write_start = std::chrono::steady_clock::now();
    const bool ok =
        !write_failed_ && std::fwrite(bytes->data(), 1, bytes->size(), pipe_) == bytes->size();
    const auto write_end = std::chrono::steady_clock::now();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stats_.convert_s += std::chrono::duration<double>(write_start - convert_start).count();
      stats_.write_s += std::chrono::duration<double>(write_end - write_start).count();
      if (!ok) write_failed_ = true;
      spare_.push_back(std::move(frame));
    }
    changed_.notify_all();
  }
}

void VideoWriter::Close() {
  PWSIM_DEMAND(!closed_);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closing_ = true;
  }
  changed_.notify_all();
  thread_.join();
  const int status = ::pclose(pipe_);
  pipe_ = nullptr;
  closed_ = true;
  if (write_failed_ || status != 0) {
    std::error_code ignored;
    std::filesystem::remove(partial_, ignored);
    throw std::runtime_error("render: ffmpeg failed writing " + config_.file.string() +
                             " (exit status " + std::to_string(status) + "): " + ReadTail(log_));
  }
  std::filesystem::rename(partial_, config_.file);
  std::error_code ignored;
  std::filesystem::remove(log_, ignored);
}

}  // namespace pwsim::render
