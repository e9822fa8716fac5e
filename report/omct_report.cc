#include "report/omct_report.h"

#include <cmath>
#include <cstddef>

#include "mca/dof.h"
#include "plot/plot.h"

namespace pwsim::report {
namespace {

using mca::OmctSignal;

const char* SignalWords(OmctSignal s) {
  switch (s) {
    case OmctSignal::kFx: return "forward push";
    case OmctSignal::kFy: return "sideways push";
    case OmctSignal::kFz: return "vertical push";
    case OmctSignal::kP: return "roll rate";
    case OmctSignal::kQ: return "pitch rate";
    case OmctSignal::kR: return "yaw rate";
  }
  return "";
}

const char* SignalSymbol(OmctSignal s) {
  switch (s) {
    case OmctSignal::kFx: return "fx";
    case OmctSignal::kFy: return "fy";
    case OmctSignal::kFz: return "fz";
    case OmctSignal::kP: return "p";
    case OmctSignal::kQ: return "q";
    case OmctSignal::kR: return "r";
  }
  return "";
}

bool IsForce(OmctSignal s) { return static_cast<int>(s) < 3; }

struct Group {
  const char* title;
  const char* gain_label;
  bool (*member)(const mca::OmctTest&);
  double gain_scale;  ///< from the test's SI gain to the axis' unit
};

const Group kGroups[] = {
    {"rotations passed on to the occupant", "gain [-]",
     [](const mca::OmctTest& t) { return !IsForce(t.input) && !IsForce(t.output); }, 1.0},
    {"pushes (specific forces) passed on to the occupant", "gain [-]",
     [](const mca::OmctTest& t) { return IsForce(t.input) && IsForce(t.output); }, 1.0},
    {"tilt coordination: the platform rotates to present a sustained push with gravity",
     "gain [(deg/s) per (m/s²)]",
     [](const mca::OmctTest& t) { return IsForce(t.input) && !IsForce(t.output); }, 1.0 / mca::kDegToRad},
    {"false pushes from rotating the platform", "gain [(m/s²) per (deg/s)]",
     [](const mca::OmctTest& t) { return !IsForce(t.input) && IsForce(t.output); }, mca::kDegToRad},
};

bool SameCurve(const plot::Series& a, const plot::Series& b) {
  if (a.x != b.x || a.y.size() != b.y.size()) return false;
  for (std::size_t i = 0; i < a.y.size(); ++i)
    if (!(std::abs(a.y[i] - b.y[i]) <= 1e-6 * std::max(1.0, std::abs(a.y[i])))) return false;
  return true;
}

}  // namespace

std::string OmctTestLabel(const mca::OmctTest& test) {
  const std::string symbols = std::string("(") + SignalSymbol(test.input) + "→" + SignalSymbol(test.output) + ")";
  if (test.input == test.output) return std::string(SignalWords(test.input)) + " " + symbols;
  return std::string(SignalWords(test.output)) + " from a " + SignalWords(test.input) + " " + symbols;
}

void WriteOmctFigure(const std::filesystem::path& stem, const std::string& what,
                     const std::vector<mca::OmctPoint>& points) {
  plot::Figure figure;
  figure.title = "Objective motion-cueing test: how " + what +
                 " passes a sinusoidal vehicle motion on, frequency by frequency (gain 1, phase 0: unchanged)";
  figure.x_label = "frequency of the vehicle motion [rad/s]";
  figure.log_x = true;
  figure.panel_height_px = 260;
  figure.width_px = 1300;
  for (const Group& group : kGroups) {
    plot::Panel gain, phase;
    gain.title = std::string(group.title) + ": gain";
    gain.y_label = group.gain_label;
    gain.log_y = true;
    phase.title = std::string(group.title) + ": phase";
    phase.y_label = "phase [deg]";
    std::vector<std::string> symbols;  // of the series drawn so far, e.g. "q→q"
    for (const mca::OmctTest& test : mca::OmctTests()) {
      if (!group.member(test)) continue;
      plot::Series g;
      g.label = OmctTestLabel(test);
      g.style = plot::Style::kLinesPoints;
      plot::Series ph = g;
      for (const mca::OmctPoint& p : points) {
        if (p.test != test.name) continue;
        g.x.push_back(p.frequency);
        g.y.push_back(p.gain * group.gain_scale);
        ph.x.push_back(p.frequency);
        ph.y.push_back(p.phase);
      }
      if (g.x.empty()) continue;
      // Unwrapped from the highest frequency down, where every test's phase is near its own.
      for (std::size_t i = ph.y.size() - 1; i-- > 0;) {
        while (ph.y[i] - ph.y[i + 1] > 180.0) ph.y[i] -= 360.0;
        while (ph.y[i] - ph.y[i + 1] < -180.0) ph.y[i] += 360.0;
      }
      for (std::size_t s = 0; s < gain.series.size(); ++s) {
        if (SameCurve(gain.series[s], g) && SameCurve(phase.series[s], ph)) {
          const std::string note = ", as " + symbols[s] + " (dashed)";
          g.label += note;
          ph.label += note;
          g.dash = ph.dash = 2;
          break;
        }
      }
      symbols.push_back(std::string(SignalSymbol(test.input)) + "→" + SignalSymbol(test.output));
      gain.series.push_back(std::move(g));
      phase.series.push_back(std::move(ph));
    }
    if (gain.series.empty()) continue;
    figure.panels.push_back(std::move(gain));
    figure.panels.push_back(std::move(phase));
  }
  plot::WriteFigure(stem, figure);
}

}  // namespace pwsim::report
