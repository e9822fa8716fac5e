#include "mca/config.h"

#include "engine/input_error.h"

namespace pwsim::mca {

void ParseMcaSection(const SceneSection& section, McaConfig& config) {
  YamlMap map(section.node, section.file, "mca", section.line);
  const std::string algorithm = map.ChoiceOr("algorithm", McaAlgorithmName(config.algorithm), {"washout", "mpc"});
  config.algorithm = algorithm == "mpc" ? McaAlgorithm::kMpc : McaAlgorithm::kWashout;
  if (map.Has("mpc")) {
    YamlMap mpc = map.Map("mpc");
    config.mpc = ParseMpcParams(mpc, config.mpc);
    mpc.Finish();
  }
  config.washout = ParseWashoutParams(map, config.washout);
  if (map.Has("vestibular")) {
    YamlMap vestibular = map.Map("vestibular");
    config.vestibular = ParseVestibularParams(vestibular, config.vestibular);
    vestibular.Finish();
    if (const std::string problem = config.vestibular.Validate(); !problem.empty()) {
      map.Fail("vestibular", "valid vestibular parameters (" + problem + ")", "invalid ones");
    }
  }
  map.Finish();
}

void ParsePlatformSection(const SceneSection& section, McaConfig& config) {
  if (section.node.IsScalar()) {
    const std::filesystem::path target = ResolveRelative(section.file, section.node.Scalar());
    if (!std::filesystem::exists(target)) {
      throw InputError(section.file.string(), section.line, "platform",
                       "a path to a pwsim-platform/1 file or an inline mapping",
                       "\"" + section.node.Scalar() + "\" (" + target.string() + " does not exist)");
    }
    config.platform = ReadPlatformFile(target);
    config.platform_source = target.string();
    return;
  }
  YamlMap map(section.node, section.file, "platform", section.line);
  const std::string format = map.StringOr("format", "pwsim-platform/1");
  if (format != "pwsim-platform/1") map.Fail("format", "\"pwsim-platform/1\"", "\"" + format + "\"");
  config.platform = ParsePlatform(map);
  map.Finish();
  config.platform_source = "inline";
}

const char* McaAlgorithmName(McaAlgorithm algorithm) {
  return algorithm == McaAlgorithm::kMpc ? "mpc" : "washout";
}

std::string CheckMpcStart(const McaConfig& config) {
  MpcCueing mpc(config.mpc, config.washout, config.vestibular, config.platform, 1e-3);
  if (!mpc.StartIsFeasible()) {
    return "the MPC's first solve from rest is infeasible on platform '" + config.platform.name + "'";
  }
  return "";
}

McaConfig LoadMcaConfig(const SceneSection* platform, const SceneSection* mca, McaConfig defaults) {
  McaConfig config = std::move(defaults);
  if (platform) ParsePlatformSection(*platform, config);
  if (mca) {
    ParseMcaSection(*mca, config);
    if (config.algorithm == McaAlgorithm::kMpc) {
      if (const std::string problem = CheckMpcStart(config); !problem.empty()) {
        throw InputError(mca->file.string(), mca->line, "mca.mpc", "an MPC set-up feasible from rest",
                         problem);
      }
    }
  }
  return config;
}

McaConfig LoadMcaConfig(const Scene& scene) {
  return LoadMcaConfig(scene.section("platform"), scene.section("mca"), McaConfig{});
}

McaConfig CarMcaDefaults() {
  McaConfig config;
  config.platform = MakeCar2DofPlatform();
  config.platform_source = "built-in car2dof";
  return config;
}

}  // namespace pwsim::mca
