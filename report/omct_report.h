#pragma once
// The figure of `pwsim omct`: DIR/omct.{png,svg,plot.csv,gp}, the Objective Motion Cueing Test
// (mca/omct.h) read as a Bode plot in four groups, each a gain panel (logarithmic) over a phase
// panel, so that every gain axis carries one unit:
//   rotations passed on   p→p, q→q, r→r        gain [-]  (deg/s felt per deg/s of the vehicle)
//   pushes passed on      fx→fx, fy→fy, fz→fz  gain [-]  (m/s² felt per m/s²)
//   tilt coordination     fx→q, fy→p           [(deg/s) per (m/s²)]: the platform rotates to
//                                              present a sustained push with gravity
//   pushes from rotating  q→fx, p→fy           [(m/s²) per (deg/s)]: a false cue
// Phases are unwrapped from the highest frequency down (no false jump of 360°). A test whose
// gain and phase equal another's in its panel is drawn dashed over it and says so in the legend.

#include <filesystem>
#include <string>
#include <vector>

#include "mca/omct.h"

namespace pwsim::report {

/// Writes STEM.png, .svg, .plot.csv, .plot.dat, .gp. `what` names the cueing algorithm and the
/// platform for the title, e.g. "the washout on platform pw4dof".
void WriteOmctFigure(const std::filesystem::path& stem, const std::string& what,
                     const std::vector<mca::OmctPoint>& points);

/// Words for an OMCT test, e.g. "pitch rate from a forward push (fx→q)".
std::string OmctTestLabel(const mca::OmctTest& test);

}  // namespace pwsim::report
