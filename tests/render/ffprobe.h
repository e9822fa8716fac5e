#pragma once
// Test helper: what ffprobe reads from a video file (codec, decoded frame count, duration).

#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>

namespace pwsim::render::testing {

/// key=value pairs of the first video stream, frames counted by decoding.
inline std::map<std::string, std::string> Ffprobe(const std::filesystem::path& file) {
  const std::string command =
      "ffprobe -v error -count_frames -select_streams v:0 -show_entries "
      "stream=codec_name,nb_read_frames,duration,r_frame_rate,width,height -of default=nw=1 '" +
      file.string() + "' 2>&1";
  std::map<std::string, std::string> out;
  std::FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return out;
  char line[256];
  while (std::fgets(line, sizeof(line), pipe) != nullptr) {
    std::string text(line);
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
    const auto eq = text.find('=');
    if (eq != std::string::npos) out[text.substr(0, eq)] = text.substr(eq + 1);
  }
  ::pclose(pipe);
  return out;
}

}  // namespace pwsim::render::testing
