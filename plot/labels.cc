#include "plot/labels.h"

#include <cstddef>

namespace pwsim::plot {
namespace {

constexpr double kRadToDeg = 57.295779513082320876798154814105;  // 180 / pi

struct Suffix {
  const char* suffix;
  const char* unit;
  double scale;
};

// Longest first where one ends another (_mps2 before _mps before _s).
constexpr Suffix kSuffixes[] = {
    {"_mps2", "m/s²", 1.0},   {"_radps2", "deg/s²", kRadToDeg}, {"_radps", "deg/s", kRadToDeg},
    {"_degps", "deg/s", 1.0}, {"_mps", "m/s", 1.0},             {"_kmh", "km/h", 1.0},
    {"_rad", "deg", kRadToDeg}, {"_deg", "deg", 1.0},           {"_mm", "mm", 1.0},
    {"_cm", "cm", 1.0},       {"_nm", "N m", 1.0},              {"_ms", "ms", 1.0},
    {"_hz", "Hz", 1.0},       {"_kg", "kg", 1.0},               {"_pct", "%", 1.0},
    {"_rpm", "rpm", 1.0},     {"_m", "m", 1.0},                 {"_s", "s", 1.0},
    {"_n", "N", 1.0},
};

bool EndsWith(const std::string& text, const std::string& end) {
  return text.size() > end.size() && text.compare(text.size() - end.size(), end.size(), end) == 0;
}

}  // namespace

Quantity QuantityFromKey(const std::string& key) {
  std::string name = key;
  if (const std::size_t dot = name.find('.'); dot != std::string::npos && dot + 1 < name.size())
    name = name.substr(dot + 1);
  Quantity q;
  for (const Suffix& s : kSuffixes) {
    if (EndsWith(name, s.suffix)) {
      name.resize(name.size() - std::string(s.suffix).size());
      q.unit = s.unit;
      q.scale = s.scale;
      break;
    }
  }
  for (char& c : name)
    if (c == '_' || c == '.') c = ' ';
  q.words = name;
  return q;
}

std::string AxisLabel(const Quantity& quantity) {
  return quantity.unit.empty() ? quantity.words : quantity.words + " [" + quantity.unit + "]";
}

}  // namespace pwsim::plot
