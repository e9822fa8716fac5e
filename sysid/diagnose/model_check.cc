#include "sysid/diagnose/model_check.h"

#include <algorithm>
#include <utility>

#include "engine/check.h"
#include "sysid/diagnose/diagnose.h"
#include "sysid/diagnose/greybox_fit.h"

namespace pwsim::diagnose {

ModelCheck CheckModelOnTrials(const std::vector<MeasuredTrial>& trials, const Chair& chair,
                              const std::vector<bool>& judged, double rest_window,
                              const VerdictOptions& options) {
  PWSIM_DEMAND(!trials.empty() && judged.size() == trials.size());
  PWSIM_DEMAND(chair.gm.has_value() && chair.lm.has_value());
  ModelCheck out;
  out.held_out = std::find(judged.begin(), judged.end(), true) != judged.end();
  std::vector<effects::TrialRecord> records;
  for (const MeasuredTrial& m : trials) {
    records.push_back(WithoutOutliers(RecordOf(m, chair), rest_window));  // noise_model.h
  }
  out.noise = EstimateNoiseModel(records, rest_window);
  std::vector<FitTrial> fit_trials;
  for (const effects::TrialRecord& r : records) fit_trials.push_back(MakeFitTrial(r, chair, rest_window));
  fit_trials = WithFitStep(fit_trials, std::nullopt);
  effects::ExtendedParams params;
  params.lm = *chair.lm;
  const std::vector<TrialResidual> residuals = ComputeResiduals(fit_trials, params);
  std::vector<ResidualRecord> all(records.size()), checked;
  std::vector<std::vector<double>> z, pitch;
  for (std::size_t i = 0; i < records.size(); ++i) {
    ResidualRecord& rr = all[i];
    rr.name = records[i].name;
    rr.speed = records[i].speed;
    rr.load_kg = records[i].load_kg;
    rr.t = records[i].t;
    rr.x = records[i].x;
    if (residuals[i].finite) {
      rr.e_z = residuals[i].e_z;
      rr.e_pitch = residuals[i].e_pitch;
      rr.gm_z = residuals[i].model.z_gm;
      rr.gm_pitch = residuals[i].model.pitch_gm;
    } else {  // a model that cannot be simulated on a trial fails there by any test
      rr.e_z.assign(rr.t.size(), 1.0);
      rr.e_pitch.assign(rr.t.size(), 1.0);
      rr.gm_z.assign(rr.t.size(), 0.0);
      rr.gm_pitch.assign(rr.t.size(), 0.0);
    }
  }
  AddDrift(all, rest_window, options.drift_budget, out.noise);
  for (std::size_t i = 0; i < records.size(); ++i) {
    if (out.held_out && !judged[i]) continue;
    checked.push_back(all[i]);
    out.judged.push_back(records[i].name);
    z.push_back(records[i].z);
    pitch.push_back(records[i].pitch);
  }
  out.check = CheckResidual(checked, out.noise, options);
  out.noise_floor_z = NoiseFloorFitPct(z, out.noise.z.sigma);
  out.noise_floor_pitch = NoiseFloorFitPct(pitch, out.noise.pitch.sigma);
  return out;
}

}  // namespace pwsim::diagnose
