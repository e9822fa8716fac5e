#include "mca/config.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "engine/input_error.h"

namespace pwsim::mca {

namespace {

/// `algorithm:` and `mpc:` over config (both optional): the keys a scene's mca: section and a
/// platform (file or inline) share.
void ParseAlgorithmKeys(YamlMap& map, McaConfig& config) {
  const std::string algorithm = map.ChoiceOr("algorithm", McaAlgorithmName(config.algorithm), {"washout", "mpc"});
  config.algorithm = algorithm == "mpc" ? McaAlgorithm::kMpc : McaAlgorithm::kWashout;
  if (map.Has("mpc")) {
    YamlMap mpc = map.Map("mpc");
    config.mpc = ParseMpcParams(mpc, config.mpc);
    mpc.Finish();
  }
}

}  // namespace

void ParseMcaSection(const SceneSection& section, McaConfig& config) {
  YamlMap map(section.node, section.file, "mca", section.line);
  ParseAlgorithmKeys(map, config);
  config.washout = ParseWashoutParams(map, config.washout);
  if (map.Has("vestibular")) {
    YamlMap vestibular = map.Map("vestibular");
    config.vestibular = ParseVestibularParams(vestibular, config.vestibular);
    vestibular.Finish();
    if (const std::string problem = config.vestibular.Validate(); !problem.empty()) {
      map.Fail("vestibular", "valid vestibular parameters (" + problem + ")", "invalid ones");
    }
  }
  config.washout.tilt_rate_threshold = config.vestibular.thresholds.tilt_rate;  // one τ for both
  map.Finish();
}

void ReadPlatformConfigFile(const std::filesystem::path& file, McaConfig& config) {
  config.platform = ReadTaggedYamlFile(file, "pwsim-platform/1", [&config](YamlMap& map) {
    ParseAlgorithmKeys(map, config);
    return ParsePlatform(map);
  });
  config.platform_source = file.string();
}

void ParsePlatformSection(const SceneSection& section, McaConfig& config) {
  if (section.node.IsScalar()) {
    const std::filesystem::path target = ResolveRelative(section.file, section.node.Scalar());
    if (!std::filesystem::exists(target)) {
      throw InputError(section.file.string(), section.line, "platform",
                       "a path to a pwsim-platform/1 file or an inline mapping",
                       "\"" + section.node.Scalar() + "\" (" + target.string() + " does not exist)");
    }
    ReadPlatformConfigFile(target, config);
    return;
  }
  YamlMap map(section.node, section.file, "platform", section.line);
  const std::string format = map.StringOr("format", "pwsim-platform/1");
  if (format != "pwsim-platform/1") map.Fail("format", "\"pwsim-platform/1\"", "\"" + format + "\"");
  ParseAlgorithmKeys(map, config);
  config.platform = ParsePlatform(map);
  map.Finish();
  config.platform_source = "inline";
}

const char* McaAlgorithmName(McaAlgorithm algorithm) {
  return algorithm == McaAlgorithm::kMpc ? "mpc" : "washout";
}

std::string CheckMpcStart(const McaConfig& config) {
  // the brake-to-rest plan of mca/mpc.h's feasibility argument stops within a block only when
  // every block is at most 2 V̄/A long on each independent stage with a stroke (the coupled
  // group's envelope constant c_g covers its blocks by construction)
  const ActuatorLimiter actuators(config.platform, config.mpc.control_period);
  for (Dof dof : kAllDofs) {
    DofLimits limits;
    double centre = 0.0;
    if (!config.platform.Has(dof) || !actuators.StageLimits(dof, &limits, &centre)) continue;
    if (!std::isfinite(limits.travel)) continue;
    const double brake = limits.brake_accel();
    const double longest = 2.0 * std::min(limits.speed, std::sqrt(brake * limits.travel)) / brake;
    if (std::max(config.mpc.block, config.mpc.control_period) > longest * (1.0 + 1e-9)) {
      return "block_s " + std::to_string(config.mpc.block) + " exceeds 2 V/A = " + std::to_string(longest) +
             " s of " + std::string(DofName(dof)) + " on platform '" + config.platform.name +
             "' (the MPC's recursive feasibility, mca/mpc.h, needs block_s <= 2 V/A)";
    }
  }
  MpcCueing mpc(config.mpc, config.washout, config.vestibular, config.platform, 1e-3);
  if (!mpc.StartIsFeasible()) {
    return "the MPC's first solve from rest is infeasible on platform '" + config.platform.name + "'";
  }
  return "";
}

void ChooseAlgorithm(McaAlgorithm algorithm, McaConfig& config) {
  config.algorithm = algorithm;
  if (algorithm != McaAlgorithm::kMpc) return;
  if (const std::string problem = CheckMpcStart(config); !problem.empty()) throw std::invalid_argument(problem);
}

McaConfig LoadMcaConfig(const SceneSection* platform, const SceneSection* mca, McaConfig defaults) {
  McaConfig config = std::move(defaults);
  if (platform) ParsePlatformSection(*platform, config);
  if (mca) ParseMcaSection(*mca, config);
  // the algorithm may come from the platform (file or inline) or the scene's mca:, which wins
  const SceneSection* named = mca != nullptr ? mca : platform;
  if (named != nullptr && config.algorithm == McaAlgorithm::kMpc) {
    if (const std::string problem = CheckMpcStart(config); !problem.empty()) {
      throw InputError(named->file.string(), named->line, mca != nullptr ? "mca.mpc" : "platform.mpc",
                       "an MPC set-up feasible from rest", problem);
    }
  }
  return config;
}

McaConfig LoadMcaConfig(const Scene& scene) {
  return LoadMcaConfig(scene.section("platform"), scene.section("mca"), McaConfig{});
}

McaConfig LoadMcaConfig(const Scene& scene, std::optional<McaAlgorithm> choice) {
  McaConfig config = LoadMcaConfig(scene);
  if (choice) ChooseAlgorithm(*choice, config);
  return config;
}

McaConfig CarMcaDefaults() {
  McaConfig config;
  config.platform = MakeCar2DofPlatform();
  config.platform_source = "built-in car2dof";
  return config;
}

}  // namespace pwsim::mca
