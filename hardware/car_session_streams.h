#pragma once
// The session's input streams from a car scene (kind: car): the car of engine/vehicle through
// the scene's controls, the head motion at the driver's head through the MCA on the rail + yaw
// platform (mca/rail_yaw.h), giving the MCA's pose command per drive cycle (the core's inverse
// kinematics: yaw -> q1, surge -> rail q2); the driver's eye pose (position, yaw, pitch, roll of the car) per frame.

#include <optional>
#include <string>

#include "mca/config.h"

#include "engine/vehicle/car_scene.h"
#include "hardware/session.h"
#include "hardware/session_runner.h"

namespace pwsim::hw {

/// @throws InputError (scene sections), std::invalid_argument (clock mismatch, a scene
/// platform without surge and yaw, or a session configured for another platform's drives).
/// `algorithm` (a command line's --mca) overrides the scene's mca.algorithm.
SessionStreams BuildCarSessionStreams(const vehicle::CarScene& scene, const SessionConfig& config,
                                      std::string* description,
                                      std::optional<mca::McaAlgorithm> algorithm = std::nullopt);

/// Camera pose of an eye at p (W) in a car with yaw ψ, nose-up pitch θ and left-up roll φ:
/// q = q_z(ψ) q_y(-θ) q_x(φ).
Pose CarCameraPose(const std::array<double, 3>& p, double yaw, double pitch, double roll);

}  // namespace pwsim::hw
