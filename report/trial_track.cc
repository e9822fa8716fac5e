#include "report/trial_track.h"

#include <cmath>
#include <stdexcept>

#include "engine/interpolate.h"

namespace pwsim::report {

const char* TrialSourceName(TrialSource source) {
  return source == TrialSource::kMeasured ? "measured" : "model";
}

bool ParseTrialSource(const std::string& text, TrialSource* source) {
  if (text == "measured") {
    *source = TrialSource::kMeasured;
  } else if (text == "model") {
    *source = TrialSource::kModel;
  } else {
    return false;
  }
  return true;
}

mca::SagittalTrack TrialTrack(const MeasuredTrial& trial, TrialSource source, const Chair& model_chair,
                              double dt) {
  const MocapTrack& track = trial.track;
  if (track.size() < 3) throw std::invalid_argument("trial " + trial.name + ": fewer than 3 mocap frames");
  const double t0 = track.t.front();
  const auto ticks = static_cast<std::size_t>(std::floor((track.t.back() - t0) / dt)) + 1;
  std::vector<double> t(ticks);
  for (std::size_t k = 0; k < ticks; ++k) t[k] = t0 + static_cast<double>(k) * dt;
  mca::SagittalTrack out;
  out.dt = dt;
  out.x = InterpolateLinear(track.t, track.x, t);
  if (source == TrialSource::kMeasured) {
    out.z = InterpolateLinear(track.t, track.z, t);
    out.pitch = InterpolateLinear(track.t, track.pitch, t);
  } else {
    const ModelOutput model = SimulateMeasuredTrial(model_chair, trial.terrain, trial.load_kg, t, out.x);
    out.z = model.z;
    out.pitch = model.pitch;
  }
  return out;
}

}  // namespace pwsim::report
