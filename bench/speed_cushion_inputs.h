#pragma once
// The MCA benchmarks' input: the head motion of the speed-cushion trial (the default scene),
// simulated once per process.

#include <vector>

#include "engine/scene.h"
#include "mca/head_motion.h"

namespace pwsim::mca {

inline const std::vector<HeadMotion>& SpeedCushionHeadMotion() {
  static const std::vector<HeadMotion> inputs = [] {
    const Scene scene = LoadScene(DefaultScenePath(PWSIM_SOURCE_DIR));
    std::vector<HeadMotion> out;
    for (const ChairSample& s : SimulateScene(scene)) out.push_back(HeadMotionFromChair(s, scene.occupant.head_offset));
    return out;
  }();
  return inputs;
}

}  // namespace pwsim::mca
