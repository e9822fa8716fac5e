#pragma once
// The MCA configuration of a scene: the `mca:` section (washout per axis, `vestibular:`) and
// the `platform:` section (a path relative to the scene file, normally under
// scenes/platforms/, or an inline platform mapping). Both are optional: without them the
// defaults of DefaultWashoutParams() and the 4-DoF PW platform apply.
//
//   McaConfig config = LoadMcaConfig(scene);   // @throws InputError

#include <filesystem>
#include <string>

#include "engine/scene.h"
#include "mca/platform.h"
#include "mca/vestibular.h"
#include "mca/washout.h"

namespace pwsim::mca {

struct McaConfig {
  WashoutParams washout = DefaultWashoutParams();
  PlatformSpec platform = MakePw4DofPlatform();
  VestibularParams vestibular;
  std::string platform_source{"built-in pw4dof"};  ///< file path or "inline"
};

McaConfig LoadMcaConfig(const Scene& scene);
/// Reads `mca:` over `base` from a raw section node.
void ParseMcaSection(const SceneSection& section, McaConfig& config);
/// Reads `platform:` (path or inline) from a raw section node.
void ParsePlatformSection(const SceneSection& section, McaConfig& config);

}  // namespace pwsim::mca
