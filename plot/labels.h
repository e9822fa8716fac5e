#pragma once
// Words and a unit for a quantity known by a key of pwsim's files, for axes and legends that a
// reader understands without the code: the key's unit suffix (docs/notation.md: SI inside,
// the unit as a suffix) becomes the unit, the rest words; radians are shown in degrees.
//
//   QuantityFromKey("scene.drive.speed_mps")   -> {"drive speed", "m/s", 1}
//   QuantityFromKey("peak_pitch_rad")          -> {"peak pitch", "deg", 57.29...}
//   AxisLabel(QuantityFromKey("peak_heave_m")) -> "peak heave [m]"
//
// A dotted key drops its first part when it has more than one (the input file it names, as
// "scene." in a sweep's override keys). A key without a known suffix keeps its words and has no
// unit ("" : a count, a ratio, or unknown).

#include <string>

namespace pwsim::plot {

struct Quantity {
  std::string words;
  std::string unit;    ///< as printed, e.g. "m/s²"; empty when the key carries none
  double scale{1.0};   ///< multiply a value in the key's unit by this to get `unit`
};

Quantity QuantityFromKey(const std::string& key);

/// "words [unit]", or the words alone when there is no unit.
std::string AxisLabel(const Quantity& quantity);

}  // namespace pwsim::plot
