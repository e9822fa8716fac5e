#pragma once
// The rail + yaw platform of seed 001 as it is built: an RP chain, the turntable (yaw ψ) at the
// base carrying the 1.2 m rail, the cabin sliding on the rail (surge x). The generic platform
// kinematics of cue_analysis.h put translations in the lab frame; on this platform the rail
// turns with the turntable, so the cabin off the yaw axis feels the turntable's own motion:
// with d = (x + h_x, h_y) the head in the turntable frame (p_PH = head_from_pivot),
//   a_H,x = ẍ - ψ̈ h_y - ψ̇² (x + h_x)
//   a_H,y = ψ̈ (x + h_x) + 2 ψ̇ ẋ - ψ̇² h_y
//   fs_H = (a_H,x, a_H,y, g),  w_H = (0, 0, ψ̇)
// The false cue is the part that the rail position and speed add (zero when the cabin is at the
// yaw axis): Δfs_x = -ψ̇² x (centripetal, along the rail), Δfs_y = ψ̈ x + 2 ψ̇ ẋ (tangential and
// Coriolis, across the rail, where the platform has no axis to cancel it).
//
//   CueingTrace trace = RunRailYawCueing(config, truth, dt);   // delivered with the false cues
//   RailYawFalseCues cues = RailYawFalseCue(config.platform, trace.commands, dt);

#include <vector>

#include "mca/config.h"
#include "mca/cueing.h"

namespace pwsim::mca {

/// Head position in the lab [m] and R (row-major) for one pose of the rail + yaw platform.
PlatformHeadPose HeadPoseOnRailYaw(const PlatformSpec& platform, const DofArray& pose);

/// Head motion delivered by the rail + yaw chain (central differences of the head pose).
std::vector<HeadMotion> DeliveredRailYawHeadMotion(const PlatformSpec& platform,
                                                   const std::vector<DofArray>& poses, double dt);

/// The rail's false cue per tick and its summary.
struct RailYawFalseCues {
  std::vector<double> surge;  ///< Δfs_x = -ψ̇² x [m/s^2]
  std::vector<double> sway;   ///< Δfs_y = ψ̈ x + 2 ψ̇ ẋ [m/s^2]
  double peak_surge{0.0}, peak_sway{0.0};  ///< max |.| [m/s^2]
  double rms_surge{0.0}, rms_sway{0.0};    ///< [m/s^2]
  /// Episodes and time with |Δfs| above the otolith threshold of that axis.
  int surge_above_threshold_count{0}, sway_above_threshold_count{0};
  double surge_above_threshold_s{0.0}, sway_above_threshold_s{0.0};
};
/// From the command stream (pose, rate and acceleration of surge and yaw).
RailYawFalseCues RailYawFalseCue(const VestibularParams& vestibular,
                                 const std::vector<McaCommand>& commands, double dt);

/// RunCueing with the delivered motion of the rail + yaw chain (perceived platform motion
/// recomputed from it). @pre the platform has surge and yaw only.
CueingTrace RunRailYawCueing(const McaConfig& config, const std::vector<HeadMotion>& truth, double dt,
                             VehiclePredictor* predictor = nullptr);

}  // namespace pwsim::mca
