// pwsim mca-validate [TRIAL_DIR...] [options]: the MCA validation of seed 000 (Fig. 6 and 7).
// For each measured trial the MCA runs twice, on the tracked motion (Fig. 6a) and on the model
// driven by the trial's measured x(t) (Fig. 6b); the heave and pitch commands are compared by
// their maximum normalised cross-correlation over lags (the paper reports > 0.98). Without
// TRIAL_DIR, trials are generated in-process (synth: the paper's protocol at 1.2 m/s,
// 100 kg, over the cushion). Writes DIR/mca_validation.json, DIR/<trial>/commands.csv and
// DIR/mca_validation.png (the first trial, as Fig. 7).

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "app/commands.h"
#include "app/output_folder.h"
#include "plot/plot.h"
#include "engine/atomic_file.h"
#include "engine/chair.h"
#include "sysid/effects/effect_catalog.h"
#include "synth/effect_truth_model.h"
#include "sysid/measured/measured_trial.h"
#include "engine/number_format.h"
#include "synth/generate.h"
#include "engine/trial_table.h"
#include "mca/config.h"
#include "mca/cue_analysis.h"
#include "mca/cueing.h"
#include "mca/head_motion.h"

#include "engine/interpolate.h"

namespace pwsim::app {
namespace {


struct TrialResult {
  std::string name;
  std::vector<double> t;
  std::vector<double> heave_model, heave_measured, pitch_model, pitch_measured;
  std::array<double, 2> heave_xcorr{}, pitch_xcorr{};
};

TrialResult ValidateTrial(const MeasuredTrial& trial, const Chair& model_chair,
                          const mca::McaConfig& config, const std::array<double, 3>& head,
                          double dt, int smooth_ticks) {
  TrialResult r;
  r.name = trial.name;
  const MocapTrack& track = trial.track;
  if (track.size() < 3) throw UsageError("trial " + trial.name + ": fewer than 3 frames");
  const double t0 = track.t.front();
  const auto ticks = static_cast<std::size_t>(std::floor((track.t.back() - t0) / dt)) + 1;
  r.t.resize(ticks);
  for (std::size_t k = 0; k < ticks; ++k) r.t[k] = t0 + static_cast<double>(k) * dt;

  // Fig. 6a: the tracked state, resampled on the MCA ticks and differentiated (smoothed)
  mca::SagittalTrack measured{dt, InterpolateLinear(track.t, track.x, r.t), InterpolateLinear(track.t, track.z, r.t),
                              InterpolateLinear(track.t, track.pitch, r.t)};
  // Fig. 6b: the model driven by the same measured x(t)
  const ModelOutput model_out =
      SimulateMeasuredTrial(model_chair, trial.terrain, trial.load_kg, r.t, measured.x);
  mca::SagittalTrack model{dt, measured.x, model_out.z, model_out.pitch};

  const mca::CueingTrace from_measured =
      mca::RunCueing(config, mca::HeadMotionFromTrack(measured, head, smooth_ticks), dt);
  const mca::CueingTrace from_model =
      mca::RunCueing(config, mca::HeadMotionFromTrack(model, head, smooth_ticks), dt);
  const auto heave = static_cast<std::size_t>(mca::Index(mca::Dof::kHeave));
  const auto pitch = static_cast<std::size_t>(mca::Index(mca::Dof::kPitch));
  for (std::size_t k = 0; k < ticks; ++k) {
    r.heave_model.push_back(from_model.commands[k].pose[heave]);
    r.heave_measured.push_back(from_measured.commands[k].pose[heave]);
    r.pitch_model.push_back(from_model.commands[k].pose[pitch]);
    r.pitch_measured.push_back(from_measured.commands[k].pose[pitch]);
  }
  r.heave_xcorr = mca::MaxCrossCorrelation(r.heave_model, r.heave_measured, dt, 0.5);
  r.pitch_xcorr = mca::MaxCrossCorrelation(r.pitch_model, r.pitch_measured, dt, 0.5);
  return r;
}

}  // namespace

const CommandSpec& McaValidateSpec() {
  static const CommandSpec spec{
      "mca-validate",
      "pwsim mca-validate [TRIAL_DIR...] [options]",
      "MCA validation (paper Fig. 6/7): cross-correlate heave/pitch commands, tracked vs model.",
      {
          OutOption("mca-validate", "mca_validation.json, mca_validation.png, TRIAL/commands.csv"),
          {"scene", "SCENE", "-", "", "MCA, platform and head offset from this scene (default: the speed-cushion scene)"},
          {"chair", "FILE", "-", "", "model chair with gm and lm (default: the trial's, else Table I)"},
          {"rate-hz", "HZ", "Hz", "1000", "MCA tick rate"},
          {"smooth-ms", "MS", "ms", "20", "half-width of the moving average on tracked derivatives"},
          {"min-xcorr", "C", "-", "0.98", "exit status 1 when a cross-correlation is below this"},
          {"seed", "N", "-", "1", "seed of the generated trials (no TRIAL_DIR)"},
          {"effect", "ID", "-", "", "generated trials: the real chair has this effect, the model not (e.g. cushion_compliance)"},
          {"strength", "S", "-", "1", "strength of --effect (1 = moderate)"},
      },
      "TRIAL_DIR  measured-trial folders (measured-trials.md); none: generated in-process"};
  return spec;
}

int McaValidateCommand(const ParsedArgs& args) {
  const std::filesystem::path out_dir = OutDir(args);
  const double rate_hz = args.GetDouble("rate-hz");
  if (!(rate_hz >= 50.0 && rate_hz <= 100000.0)) {
    throw UsageError("option --rate-hz: expected a number in [50, 100000] Hz");
  }
  const double dt = 1.0 / rate_hz;
  const double smooth_ms = args.GetDouble("smooth-ms");
  if (!(smooth_ms >= 0.0 && smooth_ms <= 1000.0)) {
    throw UsageError("option --smooth-ms: expected a number in [0, 1000] ms");
  }
  const int smooth_ticks = static_cast<int>(std::lround(smooth_ms * 1e-3 / dt));
  const double min_xcorr = args.GetDouble("min-xcorr", -1.0, 1.0);

  const Scene scene = LoadScene(args.Has("scene") ? std::filesystem::path(args.Get("scene"))
                                                  : DefaultScenePath(PWSIM_SOURCE_DIR));
  const mca::McaConfig config = mca::LoadMcaConfig(scene);
  std::optional<Chair> chair_override;
  if (args.Has("chair")) chair_override = ReadChairFile(args.Get("chair"));
  OutputFolder outputs(out_dir, "mca-validate");  // what the last command wrote there goes

  // the trials: read, or generated in-process
  std::vector<MeasuredTrial> trials;
  std::string source = "measured";
  for (const std::string& folder : args.positional()) trials.push_back(ReadMeasuredTrial(folder));
  if (trials.empty()) {
    GenerateConfig generate;
    generate.speeds = {scene.drive.speed};
    generate.loads = {scene.load_kg};
    generate.without_cushion = false;
    generate.seed = static_cast<std::uint64_t>(args.GetInt("seed", 0, std::numeric_limits<long long>::max()));
    source = "generated (synth, truth = Table I chair)";
    if (args.Has("effect")) {
      const std::optional<effects::EffectId> effect = effects::ParseEffect(args.Get("effect"));
      if (!effect) {
        throw UsageError("option --effect: expected one of " + effects::EffectNameList());
      }
      generate.truth_model =
          effects::MakeEffectTruthModel(*effect, args.GetDouble("strength", 0.0, 100.0), generate.truth);
      source += " with effect " + args.Get("effect") + " at strength " + args.Get("strength");
    }
    trials = GenerateTrialSet(generate).Measured();
  }

  nlohmann::ordered_json report;
  report["format"] = "pwsim-mca-validation/1";
  report["source"] = source;
  report["platform"] = config.platform.name;
  report["rate_hz"] = rate_hz;
  report["min_xcorr"] = min_xcorr;
  report["trials"] = nlohmann::ordered_json::array();
  bool pass = true;
  std::vector<TrialResult> results;
  for (const MeasuredTrial& trial : trials) {
    const Chair* chair = chair_override ? &*chair_override : &trial.chair;
    std::string model_chair = chair_override ? "--chair " + args.Get("chair") : "the trial's chair";
    const Chair table_one = MakeTableOneChair();
    if (!chair->gm || !chair->lm) {
      chair = &table_one;
      model_chair = "Table I (the trial's chair has no gm/lm)";
    }
    TrialResult r = ValidateTrial(trial, *chair, config, scene.occupant.head_offset, dt, smooth_ticks);
    const bool ok = r.heave_xcorr[0] >= min_xcorr && r.pitch_xcorr[0] >= min_xcorr;
    pass = pass && ok;
    report["trials"].push_back({{"trial", r.name},
                                {"heave_xcorr", r.heave_xcorr[0]},
                                {"heave_lag_s", r.heave_xcorr[1]},
                                {"pitch_xcorr", r.pitch_xcorr[0]},
                                {"pitch_lag_s", r.pitch_xcorr[1]},
                                {"model_chair", model_chair},
                                {"pass", ok}});
    TrialTable table(r.t.size());
    table.Add("t_s", r.t);
    table.Add("heave_model_m", r.heave_model);
    table.Add("heave_measured_m", r.heave_measured);
    table.Add("pitch_model_rad", r.pitch_model);
    table.Add("pitch_measured_rad", r.pitch_measured);
    table.WriteCsv(out_dir / r.name / "commands.csv");
    std::cout << "  " << r.name << ": heave xcorr " << r.heave_xcorr[0] << " (lag " << r.heave_xcorr[1]
              << " s), pitch xcorr " << r.pitch_xcorr[0] << " (lag " << r.pitch_xcorr[1] << " s)"
              << (ok ? "" : "  BELOW " + FormatDouble(min_xcorr)) << "\n";
    results.push_back(std::move(r));
  }
  report["pass"] = pass;
  std::filesystem::create_directories(out_dir);
  WriteFileAtomically(out_dir / "mca_validation.json", report.dump(2) + "\n");

  if (!results.empty()) {
    const TrialResult& r = results.front();
    std::vector<double> pitch_model_deg(r.t.size()), pitch_measured_deg(r.t.size());
    for (std::size_t k = 0; k < r.t.size(); ++k) {
      pitch_model_deg[k] = r.pitch_model[k] / mca::kDegToRad;
      pitch_measured_deg[k] = r.pitch_measured[k] / mca::kDegToRad;
    }
    const std::string from_model = "cueing driven by the chair model", from_tracking = "cueing driven by the tracked motion";
    plot::WriteSharedXFigure(
        out_dir / "mca_validation.png", r.t,
        {{"platform heave command (up +), cross-correlation " + FormatDouble(std::round(r.heave_xcorr[0] * 1e4) / 1e4),
          "heave [m]",
          {{from_model, r.heave_model, plot::color::kSimulated}, {from_tracking, r.heave_measured, plot::color::kReference}}},
         {"platform pitch command (nose-up +), cross-correlation " + FormatDouble(std::round(r.pitch_xcorr[0] * 1e4) / 1e4),
          "pitch [deg]",
          {{from_model, pitch_model_deg, plot::color::kSimulated}, {from_tracking, pitch_measured_deg, plot::color::kReference}}}},
        "time [s]", 1100, 300,
        "Platform commands from the chair model against those from the tracked trial (seed 000, Fig. 7; the paper: "
        "cross-correlation > 0.98)");
  }
  std::cout << "pwsim mca-validate: " << results.size() << " trial(s), " << source << ", "
            << (pass ? "all" : "NOT all") << " cross-correlations >= " << min_xcorr << "\n";
  outputs.Print(std::cout, "pwsim mca-validate");  // a failed check is a result: its files stay
  return pass ? 0 : 1;
}

}  // namespace pwsim::app
