#include "app/progress.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>

namespace pwsim::app {
namespace {

double SteadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

Progress::Progress(std::string who, bool quiet)
    : Progress(std::move(who), quiet, ::isatty(2) != 0, std::cerr, SteadySeconds) {}

Progress::Progress(std::string who, bool quiet, bool terminal, std::ostream& out, std::function<double()> now_s,
                   double redraw_s)
    : who_(std::move(who)), quiet_(quiet), terminal_(terminal), out_(out), now_s_(std::move(now_s)),
      redraw_s_(redraw_s) {}

Progress::~Progress() { Finish(); }

std::string Progress::FormatSeconds(double seconds) {
  const long s = std::lround(std::max(0.0, seconds));
  char text[48];
  if (s < 60) {
    std::snprintf(text, sizeof text, "%ld s", s);
  } else if (s < 3600) {
    std::snprintf(text, sizeof text, "%ld min %02ld s", s / 60, s % 60);
  } else {
    std::snprintf(text, sizeof text, "%ld h %02ld min", s / 3600, (s % 3600) / 60);
  }
  return text;
}

void Progress::Report(std::string_view stage, int done, int total) {
  if (quiet_) return;
  const std::lock_guard<std::mutex> lock(mutex_);
  const double now = now_s_();
  const std::string name(stage);
  auto [found, fresh] = clocks_.try_emplace(name);
  StageClock& clock = found->second;
  if (fresh) {
    clock.t0 = now;
    clock.done0 = done;
  } else if (done < clock.last_done) {
    return;  // a worker that finished earlier reports late: the count shown stays
  }
  clock.last_done = done;
  const bool new_stage = name != stage_;
  stage_ = name;
  std::string counted = total > 0 ? std::to_string(done) + "/" + std::to_string(total) : "";
  if (!terminal_) {  // one line per stage
    if (new_stage) out_ << who_ << ": " << name << (counted.empty() ? "" : " (" + counted + ")") << "\n" << std::flush;
    return;
  }
  if (!new_stage && done != total && now - last_draw_s_ < redraw_s_) return;
  last_draw_s_ = now;
  std::string line = who_ + ": " + name;
  if (!counted.empty()) line += " " + counted;
  if (total > 0 && done > clock.done0) {
    line += ", ETA " + FormatSeconds((now - clock.t0) * (total - done) / (done - clock.done0));
  } else if (now > clock.t0) {
    line += ", " + FormatSeconds(now - clock.t0);
  }
  Draw(line);
}

void Progress::Draw(const std::string& line) {
  out_ << "\r" << line << "\x1b[K" << std::flush;  // the line rewritten in place, its old tail erased
  shown_ = line;
  line_open_ = true;
}

void Progress::Line(std::ostream& to, const std::string& line) {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (line_open_) out_ << "\r\x1b[K" << std::flush;
  to << line << "\n" << std::flush;
  if (line_open_) out_ << "\r" << shown_ << "\x1b[K" << std::flush;
}

ProgressCallback Progress::callback() {
  return [this](std::string_view stage, int done, int total) { Report(stage, done, total); };
}

void Progress::Finish() {
  if (quiet_) return;
  const std::lock_guard<std::mutex> lock(mutex_);
  if (line_open_) out_ << "\r\x1b[K" << std::flush;
  line_open_ = false;
  stage_.clear();
}

ProgressLog::ProgressLog(Progress& progress, std::ostream& to) : std::ostream(&buffer_), buffer_(progress, to) {}

int ProgressLog::Buffer::overflow(int c) {
  if (c == traits_type::eof()) return traits_type::not_eof(c);
  if (c == '\n') {
    progress_.Line(to_, line_);
    line_.clear();
  } else {
    line_ += static_cast<char>(c);
  }
  return c;
}

OptionSpec QuietOption() {
  return {"quiet", "", "", "", "no progress lines on stderr (results and errors are still printed)"};
}

}  // namespace pwsim::app
