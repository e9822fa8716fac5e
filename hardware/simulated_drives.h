#pragma once
// The platform's CiA 402 servo drives, simulated, one node per actuator of an mca::Mechanism
// (node id = first_node + actuator index): what `pwsim platform-sim` runs behind the
// CAN-over-UDP link, and what the in-process tests put on the other end of the bus.
//   NMT per node (reset-comm -> boot-up heartbeat, start -> operational), heartbeat producer,
//   RPDO1 (controlword, target) latched on SYNC, TPDO1/TPDO2 answered on every SYNC,
//   CiA 402 state machine, CSP: on each SYNC the plant advances one drive cycle toward the
//   latched targets; following-error trip (EMCY 0x8611, fault), master heartbeat consumer
//   (loss -> quick stop: decelerate and hold, the 0x6007 reaction), injectable faults.
// Plants. The car's rail + yaw (actuator 0 a rotary stage on yaw, actuator 1 a rail on surge:
// seed 001's RP manipulator) runs on the Lagrange model of hardware/platform_model.h; any other
// mechanism runs one ActuatorServo per actuator (hardware/actuator_servo.h), each with its
// actuator's stroke, speed, acceleration and force limits, carrying its share of the payload's
// weight: the static forces f = Mechanism::ActuatorForces(x, PayloadWrench(x)) at the measured
// pose, and as moving mass a leg |f_i|/g, a rail the payload's mass, a rotary stage the payload's
// mass at `payload_gyration_m` (an approximation: the legs' inertial coupling is not modelled).
// Measurement. The plate pose x is measured by forward kinematics (Mechanism::Forward) from the
// actuator positions after every drive cycle; each axis's envelope (extremes of position,
// speed, acceleration and effort) is sampled on every substep of the simulation.
// Time: SYNCs drive the physics; Poll(now) adds the time-based parts (heartbeats, watchdog).
// No allocation after construction (the frames go to the caller's vector); no wall clock.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "hardware/actuator_servo.h"
#include "hardware/can_frame.h"
#include "hardware/canopen.h"
#include "hardware/platform_model.h"
#include "mca/mechanism.h"

namespace pwsim::hw {


struct DriveSimConfig {
  std::uint8_t first_node{1};                     ///< node of actuator i: first_node + i
  std::array<double, mca::kMaxActuators> counts_per_unit{1e6, 1e6, 1e6, 1e6, 1e6, 1e6, 1e6, 1e6};
  double cycle_s{0.004};                          ///< SYNC period the drives expect
  std::int64_t heartbeat_period_ns{100'000'000};  ///< producer heartbeat 0x1017 (100 ms)
  std::int64_t master_timeout_ns{300'000'000};    ///< consumer heartbeat 0x1016 (300 ms)
  /// 0x6065 [rad | m]; 0 = by kind: rotary 0.2 rad, rail 0.05 m, leg 0.02 m.
  std::array<double, mca::kMaxActuators> following_error_window{};
  /// 0x6085 [rad/s² | m/s²]; 0 = the car's 0.5 rad/s² (yaw) and 3 m/s² (rail) on its Lagrange
  /// plant, else half the actuator's acceleration limit.
  std::array<double, mca::kMaxActuators> quick_stop_decel{};
  ServoParams servo;                              ///< position loop of every ActuatorServo
  /// Moving inertia of each actuator without payload: legs and rails [kg], rotary stages [kg m²].
  double leg_mass_kg{20.0};
  double rail_mass_kg{20.0};
  double rotary_inertia_kgm2{5.0};
  /// The payload's radius of gyration about a rotary stage's axis [m] (assumed).
  double payload_gyration_m{0.35};
};

/// What one actuator did, from its simulated states (AxisEnvelope) against its limits.
/// A limit counts as exceeded beyond kLimitTolerance (relative: rounding, not motion).
struct ActuatorMeasurement {
  double q_min{0.0}, q_max{0.0};  ///< extremes of the actual position [m | rad]
  double mid{0.0};                ///< mid-stroke (min + max)/2 (0 for a free rotary stage)
  double peak_offset{0.0};        ///< max |q − mid| [m | rad]
  double stroke_use{0.0};         ///< peak_offset / half stroke (1 = an end; 0 when free)
  double peak_speed{0.0};         ///< [m/s | rad/s]
  double peak_accel{0.0};         ///< [m/s² | rad/s²]
  double peak_effort{0.0};        ///< [N | N m]
  bool stroke_exceeded{false};
  bool speed_exceeded{false};
  bool accel_exceeded{false};
  bool force_exceeded{false};
};
inline constexpr double kLimitTolerance = 1e-9;

class SimulatedDrives {
 public:
  /// The car (seed 001): yaw on node 1, rail on node 2, on the Lagrange plant.
  explicit SimulatedDrives(DriveSimConfig config = {}, PlatformParams params = {});
  /// Any mechanism (1..mca::kMaxActuators actuators, mechanism.Validate() empty): one node per
  /// actuator. The car's rail + yaw (IsCarRailYaw) keeps the Lagrange plant with `car_params`.
  explicit SimulatedDrives(const mca::Mechanism& mechanism, DriveSimConfig config = {},
                           PlatformParams car_params = {});
  /// Actuator 0 a rotary stage on yaw and actuator 1 a rail on surge, nothing else.
  static bool IsCarRailYaw(const mca::Mechanism& mechanism);
  /// The car's mechanism (mca::MakeCar2DofPlatform), yaw first, then rail.
  static mca::Mechanism CarMechanism();

  /// Handles one frame from the bus; responses are appended to `out`.
  void OnFrame(const CanFrame& frame, std::int64_t now_ns, std::vector<CanFrame>* out);
  /// Time-based duties (boot-up, heartbeat, master watchdog, quick-stop motion without SYNCs).
  void Poll(std::int64_t now_ns, std::vector<CanFrame>* out);

  // Fault injection (tests, `platform-sim --fault-at`).
  void InjectFault(int axis, std::uint16_t emcy_code, std::vector<CanFrame>* out);
  void SetSilent(bool silent) { silent_ = silent; }  ///< stop answering (a dead node)

  int axis_count() const { return axes_; }
  std::uint8_t node(int axis) const { return static_cast<std::uint8_t>(config_.first_node + axis); }
  bool uses_car_plant() const { return car_plant_; }
  const mca::Mechanism& mechanism() const { return mechanism_; }
  const DriveSimConfig& config() const { return config_; }

  /// The car's Lagrange plant state (meaningful when uses_car_plant()).
  const PlatformState& platform() const { return plant_.state(); }
  /// Actual position [m | rad], velocity, acceleration and effort [N | N m] of an axis.
  double position(int axis) const;
  double velocity(int axis) const;
  double acceleration(int axis) const;
  double effort(int axis) const;
  /// The static payload force an axis carries [N | N m] (0 on the car's plant).
  double load(int axis) const;
  /// The plate pose measured by forward kinematics from the actual positions, and how the last
  /// solve went; fk_failures() counts cycles whose solve failed (the pose then kept).
  const mca::DofArray& measured_pose() const { return pose_; }
  const mca::KinematicsStatus& fk_status() const { return fk_status_; }
  std::uint64_t fk_failures() const { return fk_failures_; }
  /// What an axis did since start (or since ResetMeasurements).
  ActuatorMeasurement measurement(int axis) const;
  const AxisEnvelope& envelope(int axis) const { return envelope_[static_cast<std::size_t>(axis)]; }
  /// Any stroke, speed, acceleration or force limit exceeded on any axis.
  bool any_limit_exceeded() const;
  void ResetMeasurements();

  canopen::DriveState drive_state(int axis) const { return drive_[static_cast<std::size_t>(axis)]; }
  canopen::NmtState nmt_state(int axis = 0) const { return nmt_[static_cast<std::size_t>(axis)]; }
  /// True when every node is operational with its drive in Operation Enabled.
  bool all_enabled() const;
  std::uint64_t syncs() const { return syncs_; }
  bool master_lost() const { return master_lost_; }
  /// Largest |q| at the end of a drive cycle on each axis since start.
  const std::array<double, mca::kMaxActuators>& peak_abs_position() const { return peak_abs_; }
  /// How many boot-up messages each node has sent (process start and NMT resets).
  std::uint32_t boot_count(int axis) const { return boot_count_[static_cast<std::size_t>(axis)]; }

 private:
  void Init();
  int AxisOf(std::uint8_t node) const;
  bool AnyOperational() const;
  void Boot(int axis, std::int64_t now_ns, std::vector<CanFrame>* out);
  void StepPhysics(std::vector<CanFrame>* out);
  void Measure();

  DriveSimConfig config_;
  mca::Mechanism mechanism_;
  int axes_{0};
  bool car_plant_{false};
  PlatformPlant plant_;
  std::array<ActuatorServo, mca::kMaxActuators> servo_{};
  std::array<double, mca::kMaxActuators> base_mass_{};
  std::array<double, mca::kMaxActuators> window_{};
  std::array<double, mca::kMaxActuators> quick_stop_decel_{};
  std::array<canopen::NmtState, mca::kMaxActuators> nmt_{};
  std::array<canopen::DriveState, mca::kMaxActuators> drive_{};
  std::array<std::uint16_t, mca::kMaxActuators> controlword_{};
  std::array<std::int32_t, mca::kMaxActuators> target_counts_{};
  std::array<double, mca::kMaxActuators> latched_target_{};
  std::array<double, mca::kMaxActuators> quick_stop_velocity_{};
  std::array<AxisEnvelope, mca::kMaxActuators> envelope_{};
  std::array<double, mca::kMaxActuators> peak_abs_{};
  std::array<std::uint32_t, mca::kMaxActuators> boot_count_{};
  mca::DofArray pose_{};
  mca::KinematicsStatus fk_status_{};
  std::uint64_t fk_failures_{0};
  std::int64_t last_heartbeat_ns_{0};
  std::int64_t last_master_ns_{0};
  std::int64_t last_motion_ns_{0};
  bool booted_{false};
  bool master_seen_{false};
  bool master_lost_{false};
  bool silent_{false};
  std::uint64_t syncs_{0};
};

/// What the drives did, in words with units: one line per actuator (stroke use, peak speed,
/// acceleration and effort against the limits, and which limit was exceeded) and one for the
/// plate pose by forward kinematics. (Allocates: at exit, not per cycle.)
std::string DrivesSummaryText(const SimulatedDrives& drives);
/// The same as JSON object members, each on its own line as `  "key": value`, separated by
/// ",\n", without the braces: "plant", "limit_tolerance", "limits_exceeded" (stroke, speed,
/// acceleration, force: on any actuator), "actuators" (one object per actuator), "plate_pose"
/// and "forward_kinematics". Infinite limits are null.
std::string DrivesReportJsonMembers(const SimulatedDrives& drives);

}  // namespace pwsim::hw
