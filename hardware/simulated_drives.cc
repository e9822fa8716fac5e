#include "hardware/simulated_drives.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include "engine/check.h"
#include "engine/number_format.h"
#include "mca/platform.h"

namespace pwsim::hw {

using canopen::DriveState;
using canopen::NmtState;
using mca::ActuatorKind;

namespace {

// The car plant's quick-stop ramps (0x6085), kept from the two-drive simulation.
constexpr std::array<double, 2> kCarQuickStopDecel{0.5, 3.0};  // [rad/s^2, m/s^2]

double DefaultWindow(ActuatorKind kind) {
  switch (kind) {
    case ActuatorKind::kRotary: return 0.2;   // [rad]
    case ActuatorKind::kRail: return 0.05;    // [m]
    case ActuatorKind::kLeg: return 0.02;     // [m]
  }
  return 0.05;
}

}  // namespace

bool SimulatedDrives::IsCarRailYaw(const mca::Mechanism& m) {
  return m.actuator_count() == 2 && m.actuator(0).kind == ActuatorKind::kRotary &&
         m.actuator(0).dof == mca::Dof::kYaw && m.actuator(1).kind == ActuatorKind::kRail &&
         m.actuator(1).dof == mca::Dof::kSurge;
}

mca::Mechanism SimulatedDrives::CarMechanism() {
  const mca::Mechanism m = mca::MakeCar2DofPlatform().mechanism;
  if (IsCarRailYaw(m)) return m;
  // Axis boxes give the actuators in pose-axis order (rail first): node 1 is the yaw.
  PWSIM_DEMAND(m.actuator_count() == 2);
  std::vector<mca::Actuator> actuators{m.actuator(1), m.actuator(0)};
  mca::Mechanism car(m.pivot_height(), std::move(actuators), m.leg_axes(), m.payload());
  PWSIM_DEMAND(IsCarRailYaw(car));
  return car;
}

SimulatedDrives::SimulatedDrives(DriveSimConfig config, PlatformParams params)
    : config_(config), mechanism_(CarMechanism()), plant_(params) {
  Init();
}

SimulatedDrives::SimulatedDrives(const mca::Mechanism& mechanism, DriveSimConfig config,
                                 PlatformParams car_params)
    : config_(config), mechanism_(mechanism), plant_(car_params) {
  Init();
}

void SimulatedDrives::Init() {
  axes_ = mechanism_.actuator_count();
  PWSIM_DEMAND(axes_ >= 1 && axes_ <= mca::kMaxActuators);
  PWSIM_DEMAND(config_.first_node >= 1 && config_.first_node + axes_ - 1 <= 127);
  car_plant_ = IsCarRailYaw(mechanism_);
  const mca::ActuatorVector neutral = mechanism_.Neutral();
  for (int i = 0; i < axes_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const mca::Actuator& a = mechanism_.actuator(i);
    window_[k] = config_.following_error_window[k] > 0.0 ? config_.following_error_window[k]
                                                         : DefaultWindow(a.kind);
    if (config_.quick_stop_decel[k] > 0.0) {
      quick_stop_decel_[k] = config_.quick_stop_decel[k];
    } else {
      quick_stop_decel_[k] = car_plant_ ? kCarQuickStopDecel[k] : 0.5 * a.limits.accel;
    }
    base_mass_[k] = a.kind == ActuatorKind::kRotary ? config_.rotary_inertia_kgm2
                    : a.kind == ActuatorKind::kRail ? config_.rail_mass_kg
                                                     : config_.leg_mass_kg;
    if (!car_plant_) {
      servo_[k] = ActuatorServo(a.limits, base_mass_[k], config_.servo);
      ServoState s;
      s.q = neutral(i);
      servo_[k].set_state(s);
      servo_[k].ResetTarget(s.q);
      latched_target_[k] = s.q;
    }
  }
  nmt_.fill(NmtState::kBootUp);
  drive_.fill(DriveState::kSwitchOnDisabled);
  Measure();
}

int SimulatedDrives::AxisOf(std::uint8_t node) const {
  const int axis = static_cast<int>(node) - static_cast<int>(config_.first_node);
  return axis >= 0 && axis < axes_ ? axis : -1;
}

bool SimulatedDrives::AnyOperational() const {
  for (int i = 0; i < axes_; ++i)
    if (nmt_[static_cast<std::size_t>(i)] == NmtState::kOperational) return true;
  return false;
}

bool SimulatedDrives::all_enabled() const {
  for (int i = 0; i < axes_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (nmt_[k] != NmtState::kOperational || drive_[k] != DriveState::kOperationEnabled) return false;
  }
  return true;
}

double SimulatedDrives::position(int axis) const {
  const auto k = static_cast<std::size_t>(axis);
  return car_plant_ ? plant_.state().q[k] : servo_[k].state().q;
}
double SimulatedDrives::velocity(int axis) const {
  const auto k = static_cast<std::size_t>(axis);
  return car_plant_ ? plant_.state().qd[k] : servo_[k].state().v;
}
double SimulatedDrives::acceleration(int axis) const {
  const auto k = static_cast<std::size_t>(axis);
  return car_plant_ ? plant_.state().qdd[k] : servo_[k].state().a;
}
double SimulatedDrives::effort(int axis) const {
  const auto k = static_cast<std::size_t>(axis);
  return car_plant_ ? plant_.state().tau[k] : servo_[k].state().effort;
}
double SimulatedDrives::load(int axis) const {
  return car_plant_ ? 0.0 : servo_[static_cast<std::size_t>(axis)].load();
}

void SimulatedDrives::Boot(int axis, std::int64_t now_ns, std::vector<CanFrame>* out) {
  const auto k = static_cast<std::size_t>(axis);
  nmt_[k] = NmtState::kPreOperational;
  ++boot_count_[k];
  booted_ = true;
  last_heartbeat_ns_ = now_ns;
  out->push_back(canopen::EncodeHeartbeat(node(axis), NmtState::kBootUp));
}

void SimulatedDrives::InjectFault(int axis, std::uint16_t emcy_code, std::vector<CanFrame>* out) {
  PWSIM_DEMAND(axis >= 0 && axis < axes_);
  const auto k = static_cast<std::size_t>(axis);
  drive_[k] = DriveState::kFault;
  canopen::Emcy e;
  e.code = emcy_code;
  e.error_register = 0x01;
  out->push_back(canopen::EncodeEmcy(node(axis), e));
}

void SimulatedDrives::OnFrame(const CanFrame& frame, std::int64_t now_ns,
                              std::vector<CanFrame>* out) {
  if (silent_) return;
  std::uint8_t node_id = 0;
  switch (canopen::Classify(frame, &node_id)) {
    case canopen::FrameKind::kNmt: {
      canopen::NmtCommand cmd{};
      if (!canopen::DecodeNmt(frame, &cmd, &node_id)) return;
      if (node_id != 0 && AxisOf(node_id) < 0) return;
      for (int i = 0; i < axes_; ++i) {
        if (node_id != 0 && node(i) != node_id) continue;
        const auto k = static_cast<std::size_t>(i);
        if (cmd == canopen::NmtCommand::kResetComm || cmd == canopen::NmtCommand::kResetNode) {
          if (cmd == canopen::NmtCommand::kResetNode) drive_[k] = DriveState::kSwitchOnDisabled;
          Boot(i, now_ns, out);
        } else if (cmd == canopen::NmtCommand::kStart) {
          nmt_[k] = NmtState::kOperational;
        } else if (cmd == canopen::NmtCommand::kStop) {
          nmt_[k] = NmtState::kStopped;
        } else {
          nmt_[k] = NmtState::kPreOperational;
        }
      }
      master_seen_ = true;
      last_master_ns_ = now_ns;
      master_lost_ = false;
      return;
    }
    case canopen::FrameKind::kHeartbeat: {
      NmtState s{};
      if (canopen::DecodeHeartbeat(frame, &node_id, &s) && AxisOf(node_id) < 0) {
        master_seen_ = true;  // the master's heartbeat (any node that is not ours)
        last_master_ns_ = now_ns;
      }
      return;
    }
    case canopen::FrameKind::kRpdo1: {
      const int axis = AxisOf(node_id);
      canopen::CspCommand cmd;
      if (axis < 0 || nmt_[static_cast<std::size_t>(axis)] != NmtState::kOperational ||
          !canopen::DecodeCspCommand(frame, &node_id, &cmd))
        return;
      const auto k = static_cast<std::size_t>(axis);
      const DriveState before = drive_[k];
      if (!master_lost_) drive_[k] = canopen::NextDriveState(before, cmd.controlword, controlword_[k]);
      controlword_[k] = cmd.controlword;
      target_counts_[k] = cmd.target_position;
      if (drive_[k] == DriveState::kOperationEnabled && before != DriveState::kOperationEnabled) {
        // Enabling: the interpolator starts from where the axis is.
        if (car_plant_) {
          std::array<double, 2> hold = plant_.state().q;
          plant_.ResetTarget(hold);
          latched_target_[0] = hold[0];
          latched_target_[1] = hold[1];
        } else {
          servo_[k].ResetTarget(servo_[k].state().q);
          latched_target_[k] = servo_[k].state().q;
        }
      }
      return;
    }
    case canopen::FrameKind::kSync: {
      std::uint8_t counter = 0;
      if (!canopen::DecodeSync(frame, &counter)) return;
      master_seen_ = true;
      last_master_ns_ = now_ns;
      if (!AnyOperational()) return;
      ++syncs_;
      last_motion_ns_ = now_ns;
      StepPhysics(out);
      for (int i = 0; i < axes_; ++i) {
        const auto k = static_cast<std::size_t>(i);
        if (nmt_[k] != NmtState::kOperational) continue;
        const double c = config_.counts_per_unit[k];
        const double q = position(i);
        canopen::CspStatus s;
        const bool reached = std::abs(q - latched_target_[k]) < 1e-3;
        s.statusword = canopen::StatuswordFor(drive_[k], reached);
        s.position_actual = static_cast<std::int32_t>(std::lround(q * c));
        out->push_back(canopen::EncodeCspStatus(node(i), s));
        canopen::CspFeedback f;
        f.velocity_actual = static_cast<std::int32_t>(std::lround(velocity(i) * c));
        const double limit = car_plant_ ? (k == 0 ? plant_.params().tau1_max : plant_.params().tau2_max)
                                        : mechanism_.actuator(i).limits.force;
        const double permille = std::clamp(1000.0 * effort(i) / limit, -32767.0, 32767.0);
        f.torque_actual = static_cast<std::int16_t>(std::lround(permille));
        out->push_back(canopen::EncodeCspFeedback(node(i), f));
      }
      return;
    }
    default:
      return;
  }
}

void SimulatedDrives::StepPhysics(std::vector<CanFrame>* out) {
  const double dt = config_.cycle_s;
  if (car_plant_) {
    std::array<double, 2> target = plant_.state().q;
    bool enabled = false;
    for (std::size_t k = 0; k < 2; ++k) {
      const DriveState s = drive_[k];
      if (s == DriveState::kOperationEnabled) {
        latched_target_[k] = static_cast<double>(target_counts_[k]) / config_.counts_per_unit[k];
        quick_stop_velocity_[k] = plant_.state().qd[k];
        enabled = true;
      } else if (s == DriveState::kQuickStopActive || s == DriveState::kFault ||
                 s == DriveState::kFaultReactionActive) {
        // Decelerate at the quick-stop ramp, then hold (0x605A option 6; 0x605E fault reaction
        // "slow down on quick-stop ramp", the holding brake modelled as position hold).
        double& v = quick_stop_velocity_[k];
        const double dv = quick_stop_decel_[k] * dt;
        v = std::abs(v) <= dv ? 0.0 : v - std::copysign(dv, v);
        latched_target_[k] += v * dt;
        enabled = true;
      } else {
        latched_target_[k] = plant_.state().q[k];
      }
      target[k] = latched_target_[k];
    }
    std::array<AxisEnvelope, 2> env{envelope_[0], envelope_[1]};
    plant_.Advance(dt, target, enabled, &env);
    envelope_[0] = env[0];
    envelope_[1] = env[1];
  } else {
    for (int i = 0; i < axes_; ++i) {
      const auto k = static_cast<std::size_t>(i);
      ActuatorServo& servo = servo_[k];
      const DriveState s = drive_[k];
      bool powered = false;
      if (s == DriveState::kOperationEnabled) {
        latched_target_[k] = static_cast<double>(target_counts_[k]) / config_.counts_per_unit[k];
        quick_stop_velocity_[k] = servo.state().v;
        powered = true;
      } else if (s == DriveState::kQuickStopActive || s == DriveState::kFault ||
                 s == DriveState::kFaultReactionActive) {
        double& v = quick_stop_velocity_[k];  // as above
        const double dv = quick_stop_decel_[k] * dt;
        v = std::abs(v) <= dv ? 0.0 : v - std::copysign(dv, v);
        latched_target_[k] += v * dt;
        powered = true;
      } else {
        latched_target_[k] = servo.state().q;  // disabled: the drive ramps to rest and brakes
      }
      servo.Advance(dt, latched_target_[k], powered, &envelope_[k]);
    }
  }
  for (int i = 0; i < axes_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const double q = position(i);
    peak_abs_[k] = std::max(peak_abs_[k], std::abs(q));
    if (drive_[k] == DriveState::kOperationEnabled && std::abs(q - latched_target_[k]) > window_[k]) {
      InjectFault(i, 0x8611, out);  // following error
    }
  }
  Measure();
}

void SimulatedDrives::Measure() {
  mca::ActuatorVector q(axes_);
  for (int i = 0; i < axes_; ++i) q(i) = position(i);
  mca::DofArray pose = pose_;
  fk_status_ = mechanism_.Forward(q, pose_, &pose);
  if (fk_status_.ok) {
    pose_ = pose;
  } else {
    ++fk_failures_;
  }
  if (car_plant_ || !(mechanism_.payload().mass > 0.0)) return;
  // The payload's share on each actuator at the measured pose (static forces), and the inertia.
  mca::ActuatorVector f(axes_);
  if (!mechanism_.ActuatorForces(pose_, mechanism_.PayloadWrench(pose_), &f)) return;
  const double m = mechanism_.payload().mass;
  for (int i = 0; i < axes_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const ActuatorKind kind = mechanism_.actuator(i).kind;
    const double share = kind == ActuatorKind::kLeg    ? std::abs(f(i)) / mca::kGravity
                         : kind == ActuatorKind::kRail ? m
                                                       : m * config_.payload_gyration_m * config_.payload_gyration_m;
    servo_[k].SetLoad(f(i), base_mass_[k] + share);
  }
}

ActuatorMeasurement SimulatedDrives::measurement(int axis) const {
  const auto k = static_cast<std::size_t>(axis);
  const AxisEnvelope& e = envelope_[k];
  const mca::ActuatorLimits& lim = mechanism_.actuator(axis).limits;
  ActuatorMeasurement m;
  m.q_min = e.samples > 0 ? e.q_min : position(axis);
  m.q_max = e.samples > 0 ? e.q_max : position(axis);
  const bool stroke = std::isfinite(lim.min) && std::isfinite(lim.max);
  m.mid = stroke ? 0.5 * (lim.min + lim.max) : 0.0;
  m.peak_offset = std::max(std::abs(m.q_max - m.mid), std::abs(m.q_min - m.mid));
  const double half = 0.5 * (lim.max - lim.min);
  m.stroke_use = stroke && half > 0.0 ? m.peak_offset / half : 0.0;
  m.peak_speed = e.speed;
  m.peak_accel = e.accel;
  m.peak_effort = e.effort;
  const double stroke_tol = kLimitTolerance * (stroke ? std::max(1.0, lim.max - lim.min) : 1.0);
  m.stroke_exceeded = (std::isfinite(lim.max) && m.q_max > lim.max + stroke_tol) ||
                      (std::isfinite(lim.min) && m.q_min < lim.min - stroke_tol);
  m.speed_exceeded = e.speed > lim.speed * (1.0 + kLimitTolerance);
  m.accel_exceeded = e.accel > lim.accel * (1.0 + kLimitTolerance);
  m.force_exceeded = std::isfinite(lim.force) && e.effort > lim.force * (1.0 + kLimitTolerance);
  return m;
}

bool SimulatedDrives::any_limit_exceeded() const {
  for (int i = 0; i < axes_; ++i) {
    const ActuatorMeasurement m = measurement(i);
    if (m.stroke_exceeded || m.speed_exceeded || m.accel_exceeded || m.force_exceeded) return true;
  }
  return false;
}

void SimulatedDrives::ResetMeasurements() {
  envelope_.fill(AxisEnvelope{});
  peak_abs_.fill(0.0);
}

void SimulatedDrives::Poll(std::int64_t now_ns, std::vector<CanFrame>* out) {
  if (silent_) return;
  if (!booted_) {
    for (int i = 0; i < axes_; ++i) Boot(i, now_ns, out);
    return;
  }
  if (now_ns - last_heartbeat_ns_ >= config_.heartbeat_period_ns) {
    last_heartbeat_ns_ = now_ns;
    for (int i = 0; i < axes_; ++i)
      out->push_back(canopen::EncodeHeartbeat(node(i), nmt_[static_cast<std::size_t>(i)]));
  }
  if (master_seen_ && !master_lost_ && now_ns - last_master_ns_ > config_.master_timeout_ns) {
    master_lost_ = true;  // 0x6007 abort connection: quick stop
    for (DriveState& s : drive_)
      if (s == DriveState::kOperationEnabled) s = DriveState::kQuickStopActive;
  }
  // Without SYNCs the drives still move (quick stop) on their own clock.
  const auto cycle_ns = static_cast<std::int64_t>(config_.cycle_s * 1e9);
  if (master_lost_ && AnyOperational()) {
    while (now_ns - last_motion_ns_ >= cycle_ns) {
      last_motion_ns_ += cycle_ns;
      StepPhysics(out);
    }
  }
}

namespace {

std::string JsonNumber(double v) { return std::isfinite(v) ? FormatDouble(v) : std::string("null"); }
const char* JsonBool(bool b) { return b ? "true" : "false"; }

/// A few significant digits, for text meant to be read.
std::string Short(double v) {
  std::ostringstream o;
  o << std::setprecision(4) << v;
  return o.str();
}

std::string ExceededList(const ActuatorMeasurement& m) {
  std::string s;
  auto add = [&](bool b, const char* what) {
    if (!b) return;
    if (!s.empty()) s += ", ";
    s += what;
  };
  add(m.stroke_exceeded, "stroke");
  add(m.speed_exceeded, "speed");
  add(m.accel_exceeded, "acceleration");
  add(m.force_exceeded, "force");
  return s;
}

}  // namespace

std::string DrivesSummaryText(const SimulatedDrives& drives) {
  std::ostringstream o;
  const mca::Mechanism& mech = drives.mechanism();
  for (int i = 0; i < drives.axis_count(); ++i) {
    const mca::Actuator& a = mech.actuator(i);
    const ActuatorMeasurement m = drives.measurement(i);
    const std::string u = a.unit();
    const std::string f = a.kind == ActuatorKind::kRotary ? "N m" : "N";
    o << "node " << int{drives.node(i)} << " " << a.name << " (" << mca::ActuatorKindName(a.kind)
      << "): position " << Short(m.q_min) << " to " << Short(m.q_max) << " " << u;
    if (std::isfinite(a.limits.min) && std::isfinite(a.limits.max)) {
      o << " in the stroke " << Short(a.limits.min) << " to " << Short(a.limits.max) << " " << u
        << ", at most " << Short(m.peak_offset) << " " << u << " from mid-stroke = "
        << Short(100.0 * m.stroke_use) << " % of the half-stroke";
    } else {
      o << " (no stroke limit)";
    }
    o << "; peak speed " << Short(m.peak_speed) << " " << u << "/s of " << Short(a.limits.speed)
      << "; peak acceleration " << Short(m.peak_accel) << " " << u << "/s^2 of " << Short(a.limits.accel)
      << "; peak effort " << Short(m.peak_effort) << " " << f;
    if (std::isfinite(a.limits.force)) o << " of " << Short(a.limits.force);
    if (std::abs(drives.load(i)) > 1e-6) o << " (payload share now " << Short(drives.load(i)) << " " << f << ")";
    const std::string exceeded = ExceededList(m);
    o << "; " << (exceeded.empty() ? "within its limits" : "EXCEEDED " + exceeded) << "; "
      << canopen::DriveStateName(drives.drive_state(i)) << "\n";
  }
  const mca::DofArray& x = drives.measured_pose();
  o << "plate pose by forward kinematics:";
  for (mca::Dof d : mca::kAllDofs) {
    const double v = x[static_cast<std::size_t>(mca::Index(d))];
    o << " " << mca::DofName(d) << " "
      << (mca::IsRotational(d) ? Short(v / mca::kDegToRad) + " deg" : Short(v) + " m")
      << (d == mca::Dof::kYaw ? "" : ",");
  }
  o << " (last solve " << (drives.fk_status().ok ? "converged" : "failed") << ", residual "
    << Short(drives.fk_status().residual) << "; " << drives.fk_failures() << " failed solves)\n";
  return o.str();
}

std::string DrivesReportJsonMembers(const SimulatedDrives& drives) {
  std::ostringstream o;
  const mca::Mechanism& mech = drives.mechanism();
  auto any = [&](bool ActuatorMeasurement::*flag) {
    for (int i = 0; i < drives.axis_count(); ++i)
      if (drives.measurement(i).*flag) return true;
    return false;
  };
  o << "  \"plant\": \"" << (drives.uses_car_plant() ? "lagrange-rail-yaw" : "actuator-servos") << "\",\n"
    << "  \"limit_tolerance\": " << JsonNumber(kLimitTolerance) << ",\n"
    << "  \"limits_exceeded\": {\"stroke\": " << JsonBool(any(&ActuatorMeasurement::stroke_exceeded))
    << ", \"speed\": " << JsonBool(any(&ActuatorMeasurement::speed_exceeded))
    << ", \"acceleration\": " << JsonBool(any(&ActuatorMeasurement::accel_exceeded))
    << ", \"force\": " << JsonBool(any(&ActuatorMeasurement::force_exceeded)) << "},\n"
    << "  \"actuators\": [";
  for (int i = 0; i < drives.axis_count(); ++i) {
    const mca::Actuator& a = mech.actuator(i);
    const ActuatorMeasurement m = drives.measurement(i);
    o << (i == 0 ? "\n" : ",\n") << "    {\"node\": " << int{drives.node(i)} << ", \"name\": \"" << a.name
      << "\", \"kind\": \"" << mca::ActuatorKindName(a.kind) << "\", \"unit\": \"" << a.unit() << "\",\n"
      << "     \"stroke_min\": " << JsonNumber(a.limits.min) << ", \"stroke_max\": " << JsonNumber(a.limits.max)
      << ", \"speed_limit\": " << JsonNumber(a.limits.speed) << ", \"accel_limit\": " << JsonNumber(a.limits.accel)
      << ", \"force_limit\": " << JsonNumber(a.limits.force) << ",\n"
      << "     \"position_min\": " << JsonNumber(m.q_min) << ", \"position_max\": " << JsonNumber(m.q_max)
      << ", \"mid_stroke\": " << JsonNumber(m.mid) << ", \"peak_offset_from_mid\": " << JsonNumber(m.peak_offset)
      << ", \"stroke_use\": " << JsonNumber(m.stroke_use) << ",\n"
      << "     \"peak_speed\": " << JsonNumber(m.peak_speed) << ", \"peak_accel\": " << JsonNumber(m.peak_accel)
      << ", \"peak_effort\": " << JsonNumber(m.peak_effort) << ", \"payload_load\": " << JsonNumber(drives.load(i))
      << ",\n"
      << "     \"final_position\": " << JsonNumber(drives.position(i))
      << ", \"final_velocity\": " << JsonNumber(drives.velocity(i)) << ", \"state\": \""
      << canopen::DriveStateName(drives.drive_state(i)) << "\", \"nmt\": \""
      << canopen::NmtStateName(drives.nmt_state(i)) << "\",\n"
      << "     \"stroke_exceeded\": " << JsonBool(m.stroke_exceeded) << ", \"speed_exceeded\": "
      << JsonBool(m.speed_exceeded) << ", \"accel_exceeded\": " << JsonBool(m.accel_exceeded)
      << ", \"force_exceeded\": " << JsonBool(m.force_exceeded) << "}";
  }
  o << "\n  ],\n  \"plate_pose\": {";
  const mca::DofArray& x = drives.measured_pose();
  for (mca::Dof d : mca::kAllDofs) {
    o << (d == mca::Dof::kSurge ? "" : ", ") << "\"" << mca::DofName(d)
      << (mca::IsRotational(d) ? "_rad" : "_m") << "\": " << JsonNumber(x[static_cast<std::size_t>(mca::Index(d))]);
  }
  o << "},\n  \"forward_kinematics\": {\"ok\": " << JsonBool(drives.fk_status().ok)
    << ", \"residual\": " << JsonNumber(drives.fk_status().residual)
    << ", \"failures\": " << drives.fk_failures() << "}";
  return o.str();
}

}  // namespace pwsim::hw
