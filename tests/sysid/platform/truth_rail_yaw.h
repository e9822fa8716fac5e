#pragma once
// An independent truth of the seed-001 rail + yaw platform for the two-joint identification
// test: the mass matrix comes from the bodies' centre-of-mass Jacobians (M = Σ m JᵀJ + I), the
// Coriolis vector from numerical derivatives of M (Christoffel symbols), friction is smooth
// (tanh), a continuous PD law tracks multi-sine references and semi-implicit Euler integrates
// at 20 µs. No line is shared with sysid/platform/ or hardware/platform_model.

#include "sysid/platform/axis_recording.h"

namespace pwsim::test {

struct RailYawTruth {
  double m1{415.98}, x_g1{0.3}, y_g1{0.268}, izz{4.69};  // body 1 (yaw base), I1zz + I2zz
  double m2{359.32}, x_g2{0.7976}, y_g2{-0.0107};        // body 2 (cabin on the rail)
  double fv1{5.0}, fc1{3.0}, fv2{50.0}, fc2{20.0};        // friction, yaw [N m s/rad, N m], rail [N s/m, N]
  double duration{30.0};
  /// θ of the seed's regressor from the physical parameters (what identification should find).
  double Theta1() const { return m1 * (x_g1 * x_g1 + y_g1 * y_g1) + izz + m2 * (x_g2 * x_g2 + y_g2 * y_g2); }
  double Theta2() const { return 2.0 * m2 * x_g2; }
  double Theta3() const { return m2; }
  double Theta4() const { return -m2 * y_g2; }
};

sysid::platform::AxisRecording SimulateRailYaw(const RailYawTruth& truth);

}  // namespace pwsim::test
