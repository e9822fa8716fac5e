#include "report/trial_track.h"

#include <cmath>
#include <stdexcept>

namespace pwsim::report {
namespace {

/// v(t) linearly interpolated at `at` (clamped at the ends); t strictly increasing.
std::vector<double> Interpolate(const std::vector<double>& t, const std::vector<double>& v,
                                const std::vector<double>& at) {
  std::vector<double> out(at.size());
  std::size_t j = 0;
  for (std::size_t i = 0; i < at.size(); ++i) {
    while (j + 2 < t.size() && t[j + 1] < at[i]) ++j;
    if (at[i] <= t.front()) {
      out[i] = v.front();
    } else if (at[i] >= t.back()) {
      out[i] = v.back();
    } else {
      const double w = (at[i] - t[j]) / (t[j + 1] - t[j]);
      out[i] = v[j] + w * (v[j + 1] - v[j]);
    }
  }
  return out;
}

}  // namespace

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
  out.x = Interpolate(track.t, track.x, t);
  if (source == TrialSource::kMeasured) {
    out.z = Interpolate(track.t, track.z, t);
    out.pitch = Interpolate(track.t, track.pitch, t);
  } else {
    const ModelOutput model = SimulateMeasuredTrial(model_chair, trial.terrain, trial.load_kg, t, out.x);
    out.z = model.z;
    out.pitch = model.pitch;
  }
  return out;
}

}  // namespace pwsim::report
