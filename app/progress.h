#pragma once
// Progress of a long pwsim command, on stderr (docs/command-line.md, "Progress").
//
// A command names each stage as it enters it (Stage); a library stage reports its items through
// a callback of one shape, progress(stage, done, total), that the libraries take in their
// options (report::RenderStageOptions::progress, report::CarRunOptions::progress,
// diagnose::DiagnoseOptions::progress). No library reads a clock: the ETA is computed here.
//
//   - on a terminal (isatty(stderr)): one line, rewritten in place ("\r", erase to the end of
//     the line) at most every `redraw_s`: "pwsim run: render 120/600, ETA 12 s"; erased when the
//     command ends (Finish), so its results follow on a clean line;
//   - piped: one line per stage, when it starts: "pwsim run: render (0/600)";
//   - --quiet: nothing.
//
// ETA of a stage's items at the rate so far: with d0 items done when the stage was first seen
// at time t0, and d done at time t, the rest takes (t - t0) (total - d) / (d - d0). A stage
// without a total, or without an item done since t0, shows its elapsed time instead.
// Thread-safe: a callback may report from a thread pool's workers (a report whose count is
// below the last one of the same stage, a worker that finished earlier but reports later, is
// not drawn).

#include <functional>
#include <map>
#include <mutex>
#include <ostream>
#include <string>
#include <string_view>

#include "app/cli.h"

namespace pwsim::app {

/// The callback shape every library's progress hook has: `stage` names what is being done,
/// `done` of `total` items (total 0: not counted).
using ProgressCallback = std::function<void(std::string_view stage, int done, int total)>;

class Progress {
 public:
  /// `who` prefixes every line ("pwsim run"); quiet: nothing is printed. On std::cerr, a
  /// terminal when isatty(stderr), timed by the steady clock.
  Progress(std::string who, bool quiet);
  /// For tests: `terminal` chosen, lines to `out`, `now_s` the clock in seconds.
  Progress(std::string who, bool quiet, bool terminal, std::ostream& out, std::function<double()> now_s,
           double redraw_s = 0.2);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// Enters `stage` (`total` items to come, 0: not counted).
  void Stage(std::string_view stage, int total = 0) { Report(stage, 0, total); }
  /// `done` of `total` items of `stage`.
  void Report(std::string_view stage, int done, int total);
  /// Report, bound to this object (which must outlive every call).
  ProgressCallback callback();
  /// Erases the terminal line; later reports draw again.
  void Finish();
  /// Writes `line` and a newline to `to` (e.g. std::cout) with the terminal line erased first
  /// and drawn again after it, so that the two never share a line; quiet or piped: `line` alone.
  void Line(std::ostream& to, const std::string& line);

  /// A duration as shown: "12 s", "3 min 05 s", "2 h 10 min".
  static std::string FormatSeconds(double seconds);

 private:
  struct StageClock {
    double t0{0.0};
    int done0{0};
    int last_done{-1};
  };
  void Draw(const std::string& line);

  std::string who_;
  bool quiet_;
  bool terminal_;
  std::ostream& out_;
  std::function<double()> now_s_;
  double redraw_s_;
  std::mutex mutex_;
  std::string stage_;                      ///< the stage shown last
  std::string shown_;                      ///< the terminal line shown last
  std::map<std::string, StageClock> clocks_;
  double last_draw_s_{-1e300};
  bool line_open_{false};  ///< a terminal line is on screen
};

/// --quiet: no progress on stderr (the command's results on stdout are unchanged).
OptionSpec QuietOption();

/// An output stream whose lines go through Progress::Line to `to`: for a library that logs its
/// own lines (sweep::EngineOptions::log) while the progress is shown.
class ProgressLog : public std::ostream {
 public:
  ProgressLog(Progress& progress, std::ostream& to);

 private:
  class Buffer : public std::streambuf {
   public:
    Buffer(Progress& progress, std::ostream& to) : progress_(progress), to_(to) {}

   protected:
    int overflow(int c) override;

   private:
    Progress& progress_;
    std::ostream& to_;
    std::string line_;
  };
  Buffer buffer_;
};

}  // namespace pwsim::app
