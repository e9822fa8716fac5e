// Part of hardware_session_alloc_test (see session_alloc_test.cc): the live drive source's Fill
// with the counting allocator on, from the shipped R-Net log and from R-Net frames on the
// in-process bus; the chair's with either MCA.
#include <atomic>
#include <filesystem>
#include <optional>

#include "engine/check.h"
#include "hardware/car_drive_source.h"
#include "hardware/chair_drive_source.h"
#include "hardware/session_streams.h"
#include "hardware/rnet_joystick.h"

namespace pwsim::hw {

long LiveDriveFillAllocations(std::atomic<bool>& counting, std::atomic<long>& allocations, double* speed) {
  const vehicle::CarScene scene =
      vehicle::LoadCarScene(std::filesystem::path(PWSIM_SOURCE_DIR) / "scenes/car_launch.yaml");
  const mca::McaConfig mca = mca::LoadCarMcaConfig(scene);
  RnetLogJoystick log(ReadCandumpFile(std::filesystem::path(PWSIM_SOURCE_DIR) / "assets/rnet/joystick_synthetic.log"),
                      scene.clock.rate_hz, {-1, 100}, "log");
  InProcessBus hub;
  std::unique_ptr<ICanBus> jsm = hub.Connect("jsm");
  RnetJoystick live(ListenOnly(hub.Connect("reader")), {-1, 100});
  CarDriveSource from_log(scene, mca, log);
  CarDriveSource from_bus(scene, mca, live);
  SessionInputs in;
  counting = false;
  allocations = 0;
  for (std::int64_t tick = 0; tick <= 4200; tick += 2) {
    if (tick % 10 == 0) jsm->Send(EncodeRnetJoystick(0, 10, 50));  // outside the count
    counting = true;
    from_log.Fill(tick, tick % 4 == 0, tick % 10 == 0, tick, &in);
    from_bus.Fill(tick, tick % 4 == 0, tick % 10 == 0, tick, &in);
    counting = false;
  }
  *speed = vehicle::Speed(from_bus.last_tick().sample.state);
  return allocations.load();
}

long ChairDriveFillAllocations(std::atomic<bool>& counting, std::atomic<long>& allocations, double* distance,
                               std::optional<mca::McaAlgorithm> algorithm) {
  const Scene scene = LoadScene(std::filesystem::path(PWSIM_SOURCE_DIR) / "scenes/circuit_course.yaml");
  RnetLogJoystick log(ReadCandumpFile(std::filesystem::path(PWSIM_SOURCE_DIR) / "assets/rnet/joystick_synthetic.log"),
                      scene.clock.rate_hz, {-1, 100}, "log");
  ChairDriveSource source(scene, log, 4200, SessionMcaConfig(scene, algorithm));
  if (algorithm) PWSIM_DEMAND(source.mca().algorithm == *algorithm);
  SessionInputs in;
  counting = false;
  allocations = 0;
  for (std::int64_t tick = 0; tick <= 4400; tick += 2) {  // past max_ticks: the trace stops growing
    counting = true;
    source.Fill(tick, tick % 4 == 0, tick % 10 == 0, tick, &in);
    counting = false;
  }
  *distance = source.last_sample().distance;
  if (algorithm == mca::McaAlgorithm::kMpc) {
    PWSIM_DEMAND(source.mpc_stats().solves > 400);
  }
  return allocations.load();
}

}  // namespace pwsim::hw
