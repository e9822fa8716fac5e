#include "mca/config.h"

#include "engine/input_error.h"

namespace pwsim::mca {

void ParseMcaSection(const SceneSection& section, McaConfig& config) {
  YamlMap map(section.node, section.file, "mca", section.line);
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

McaConfig LoadMcaConfig(const Scene& scene) {
  McaConfig config;
  if (const SceneSection* platform = scene.section("platform")) ParsePlatformSection(*platform, config);
  if (const SceneSection* mca = scene.section("mca")) ParseMcaSection(*mca, config);
  return config;
}

}  // namespace pwsim::mca
