#pragma once
// The MCA configuration of a scene, chair or car (the one loader of both): the `mca:` section
// (`algorithm: washout | mpc`, the washout per axis, `mpc:`, `vestibular:`) and the
// `platform:` section (a path relative to the scene file, normally under scenes/platforms/,
// or an inline platform mapping). A platform (file or inline) may carry `algorithm:` and
// `mpc:` too, the cueing it is tuned for; the scene's `mca:` is read after it and wins, key by
// key (mpc fields one by one). Both are optional: without them the washout with the
// defaults of DefaultWashoutParams() runs on the vehicle's default platform (the chair's 4-DoF
// PW platform, the car's rail + yaw).
//
//   McaConfig config = LoadMcaConfig(scene);                                   // chair
//   McaConfig car = LoadCarMcaConfig(car_scene);                               // car
//   // @throws InputError

#include <filesystem>
#include <optional>
#include <string>

#include "engine/scene.h"
#include "mca/mpc.h"
#include "mca/platform.h"
#include "mca/vestibular.h"
#include "mca/washout.h"

namespace pwsim::mca {

/// Which controller turns the vehicle's head motion into platform commands.
enum class McaAlgorithm { kWashout, kMpc };
/// "washout", "mpc".
const char* McaAlgorithmName(McaAlgorithm algorithm);

struct McaConfig {
  McaAlgorithm algorithm{McaAlgorithm::kWashout};
  WashoutParams washout = DefaultWashoutParams();
  MpcParams mpc;             ///< used when algorithm is kMpc (mca/mpc.h)
  PlatformSpec platform = MakePw4DofPlatform();
  VestibularParams vestibular;
  std::string platform_source{"built-in pw4dof"};  ///< file path or "inline"
};

McaConfig LoadMcaConfig(const Scene& scene);
/// The same with a command line's choice over the scene's algorithm (ChooseAlgorithm), if any.
McaConfig LoadMcaConfig(const Scene& scene, std::optional<McaAlgorithm> choice);
/// Reads `platform:` then `mca:` (either may be null) over `defaults`; with `algorithm: mpc`
/// also checks that the MPC's first solve from rest is feasible on that platform.
McaConfig LoadMcaConfig(const SceneSection* platform, const SceneSection* mca, McaConfig defaults);
/// The car's defaults: seed 001's rail + yaw platform (MakeCar2DofPlatform), the washout.
McaConfig CarMcaDefaults();
/// A car scene's settings: its platform: and mca: sections over CarMcaDefaults(). Any scene type
/// with `const SceneSection* section(const std::string&) const` (vehicle::CarScene).
template <class CarSceneT>
McaConfig LoadCarMcaConfig(const CarSceneT& scene) {
  return LoadMcaConfig(scene.section("platform"), scene.section("mca"), CarMcaDefaults());
}
/// Empty when the MPC can start from rest on config.platform, else why not.
std::string CheckMpcStart(const McaConfig& config);
/// A command line's choice (--mca washout|mpc) over the loaded configuration: sets
/// config.algorithm and, for the MPC, checks its start as LoadMcaConfig does.
/// @throws std::invalid_argument (CheckMpcStart's reason) when the MPC cannot start from rest.
void ChooseAlgorithm(McaAlgorithm algorithm, McaConfig& config);
/// Reads `mca:` over `base` from a raw section node.
void ParseMcaSection(const SceneSection& section, McaConfig& config);
/// Reads `platform:` (path or inline) from a raw section node.
void ParsePlatformSection(const SceneSection& section, McaConfig& config);
/// Reads a pwsim-platform/1 file into config.platform, with its optional `algorithm:` and
/// `mpc:` keys over config (a platform may name the cueing it is tuned for; a scene's `mca:`
/// read afterwards overrides them). ReadPlatformFile (mca/platform.h) takes the platform only.
/// @throws InputError
void ReadPlatformConfigFile(const std::filesystem::path& file, McaConfig& config);

}  // namespace pwsim::mca
