#include "report/identification_report.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <thread>

#include "engine/atomic_file.h"
#include "plot/plot.h"
#include "report/format.h"
#include "sysid/diagnose/parallel_for.h"

namespace pwsim::report {
namespace {

constexpr double kRadToDeg = 57.29577951308232;

double BetaOf(const GeometricParams& gm, int i, int j) {
  for (const PairWeight& pair : gm.beta) {
    if (pair.i == i && pair.j == j) return pair.weight;
  }
  return 0.0;
}

}  // namespace

std::vector<ParameterRow> ParameterRows(const Chair& identified, const Chair* truth) {
  const Chair table = MakeTableOneChair();
  std::vector<ParameterRow> rows;
  const int n = identified.wheel_count();
  const bool table_applies = n == table.wheel_count();
  auto opt = [&](auto get) -> std::optional<double> {
    if (!truth || !truth->gm || !truth->lm || truth->wheel_count() != n) return std::nullopt;
    return get(*truth);
  };
  for (int i = 0; i < n; ++i) {
    rows.push_back({"alpha_" + std::to_string(i + 1), "-", identified.gm->alpha[i],
                    table_applies ? table.gm->alpha[i] : NAN,
                    opt([i](const Chair& c) { return c.gm->alpha[static_cast<std::size_t>(i)]; })});
  }
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      rows.push_back({"beta_" + std::to_string(i + 1) + std::to_string(j + 1), "-",
                      BetaOf(*identified.gm, i, j), table_applies ? BetaOf(*table.gm, i, j) : NAN,
                      opt([i, j](const Chair& c) { return BetaOf(*c.gm, i, j); })});
    }
  }
  rows.push_back({"K_z", "N/m", identified.lm->k_z, table.lm->k_z,
                  opt([](const Chair& c) { return c.lm->k_z; })});
  rows.push_back({"C_z", "N s/m", identified.lm->c_z, table.lm->c_z,
                  opt([](const Chair& c) { return c.lm->c_z; })});
  rows.push_back({"K_theta", "N m/rad", identified.lm->k_theta, table.lm->k_theta,
                  opt([](const Chair& c) { return c.lm->k_theta; })});
  rows.push_back({"C_theta", "N m s/rad", identified.lm->c_theta, table.lm->c_theta,
                  opt([](const Chair& c) { return c.lm->c_theta; })});
  return rows;
}

namespace {

std::string ErrorText(double value, double reference, bool relative) {
  if (!std::isfinite(reference)) return "";
  if (relative && reference != 0.0) {
    return Fixed(100.0 * (value - reference) / reference, 2) + " %";
  }
  return Fixed(value - reference, 4);
}

}  // namespace

std::string TextTable(const std::vector<ParameterRow>& rows, bool with_truth) {
  std::ostringstream out;
  out << std::left << std::setw(10) << "parameter" << std::setw(11) << "unit" << std::right
      << std::setw(12) << "identified" << std::setw(12) << "Table I";
  if (with_truth) out << std::setw(12) << "truth" << std::setw(12) << "error";
  out << "\n";
  for (const ParameterRow& row : rows) {
    const bool lm = row.unit != "-";
    out << std::left << std::setw(10) << row.name << std::setw(11) << row.unit << std::right
        << std::setw(12) << Significant(row.identified, lm ? 5 : 3) << std::setw(12)
        << Significant(row.table_one, lm ? 5 : 3);
    if (with_truth && row.truth) {
      out << std::setw(12) << Significant(*row.truth, lm ? 5 : 3) << std::setw(12)
          << ErrorText(row.identified, *row.truth, lm);
    }
    out << "\n";
  }
  return out.str();
}

std::string MarkdownTable(const std::vector<ParameterRow>& rows, bool with_truth) {
  std::string text = "| parameter | unit | identified | Table I (paper)";
  text += with_truth ? " | truth | error |\n|---|---|---|---|---|---|\n" : " |\n|---|---|---|---|\n";
  for (const ParameterRow& row : rows) {
    const bool lm = row.unit != "-";
    text += "| " + row.name + " | " + row.unit + " | " + Significant(row.identified, lm ? 5 : 3) +
            " | " + Significant(row.table_one, lm ? 5 : 3);
    if (with_truth) {
      text += row.truth ? " | " + Significant(*row.truth, lm ? 5 : 3) + " | " +
                              ErrorText(row.identified, *row.truth, lm)
                        : " | | ";
    }
    text += " |\n";
  }
  return text;
}

/// The overlay figure of one trial, like Fig. 5: GM input, Z and θ, measured vs model.
void PlotTrial(const MeasuredTrial& trial, const Chair& chair, const TrialComparison& cmp,
               const std::filesystem::path& file) {
  std::vector<double> ground(cmp.t.size());
  std::vector<double> front(cmp.t.size());
  for (std::size_t k = 0; k < cmp.t.size(); ++k) {
    ground[k] = 1e3 * trial.terrain.HeightAt(trial.track.x[k]);
    front[k] = 1e3 * trial.terrain.HeightAt(trial.track.x[k] + chair.wheels.front().x);
  }
  std::vector<double> z_meas, z_model, p_meas, p_model;
  for (std::size_t k = 0; k < cmp.t.size(); ++k) {
    z_meas.push_back(1e3 * cmp.z_measured[k]);
    z_model.push_back(1e3 * cmp.z_model[k]);
    p_meas.push_back(kRadToDeg * cmp.pitch_measured[k]);
    p_model.push_back(kRadToDeg * cmp.pitch_model[k]);
  }
  std::vector<plot::SharedXPanel> panels;
  panels.push_back({"(a) the ground under the chair's reference point and under its front wheel: what the model is driven by",
                    "ground height [mm]",
                    {{"under the reference point", ground, 0x7F7F7F}, {"under the front wheel", front, 0xE69F00}}});
  panels.push_back({"(b) chair height, measured and modelled (fit " + Fixed(cmp.fit_z, 1) + " %)",
                    "height [mm]",
                    {{"measured (motion capture)", z_meas, 0x0072B2}, {"identified model", z_model, 0xD55E00}}});
  panels.push_back({"(c) chair pitch (nose up +), measured and modelled (fit " + Fixed(cmp.fit_pitch, 1) + " %)",
                    "pitch [deg]",
                    {{"measured (motion capture)", p_meas, 0x0072B2}, {"identified model", p_model, 0xD55E00}}});
  plot::WriteSharedXFigure(file, cmp.t, panels, "time [s]", 1100, 280);
}

void RemoveIdentificationReport(const std::filesystem::path& out) {
  for (const char* name : {"fit.json", "identify.md", "identified-chair.yaml"}) {
    std::filesystem::remove(out / name);
  }
}

std::string ModelCheckText(const diagnose::ModelCheck& c, double fit_z, double fit_pitch) {
  const std::string on = c.held_out ? "the " + std::to_string(c.judged.size()) + " validation trials (held out of the fit)"
                                    : "all " + std::to_string(c.judged.size()) + " trials (none was held out)";
  std::string text = "Residual on " + on + " against the measurement noise (estimated from the trials' rests): "
                     "noise Z " + Significant(1e3 * c.noise.z.sigma, 3) + " mm, pitch " +
                     Significant(1e3 * c.noise.pitch.sigma, 3) + " mrad; " +
                     (std::isfinite(fit_z) && std::isfinite(fit_pitch)
                          ? "fitness Z " + Fixed(fit_z, 1) + " % against a noise floor of " + Fixed(c.noise_floor_z, 1) +
                                " %, pitch " + Fixed(fit_pitch, 1) + " % against " + Fixed(c.noise_floor_pitch, 1) + " %"
                          : "noise floor Z " + Fixed(c.noise_floor_z, 1) + " %, pitch " + Fixed(c.noise_floor_pitch, 1) + " %") +
                     "; structured RMS Z " +
                     Fixed(c.check.z.rho, 2) + " σ, pitch " + Fixed(c.check.pitch.rho, 2) + " σ (limit " +
                     Fixed(c.check.options.rho_max, 2) + " σ).\n";
  if (c.MeasurablyWrong()) {
    text += "**The model is measurably wrong on these trials**: its residual is not measurement noise (" +
            c.check.Evidence() + "). Something the trials show is missing from the paper's model, and the "
            "identified K and C may be biased by it. Next step: `pwsim diagnose TRIAL_DIR... --out DIR` on "
            "the same trials names the cause among the catalogue's effects and identifies the model again "
            "with it.";
  } else {
    text += "The residual cannot be told from the measurement noise (the test `pwsim diagnose` calls "
            "`adequate`): the model reproduces these trials as far as the data can tell.";
  }
  return text;
}

std::vector<ParameterRow> WriteIdentificationReport(const std::filesystem::path& out,
                                                    const IdentificationReportInput& in) {
  const std::vector<MeasuredTrial>& trials = *in.trials;
  const std::vector<TrialRole>& roles = *in.roles;
  const IdentifyResult& result = *in.result;
  const IdentifyOptions& options = *in.options;
  const Chair* truth = in.truth;
  const std::filesystem::path& truth_file = in.truth_file;
  const long long max_plots = in.max_plots;
  RemoveIdentificationReport(out);
  std::filesystem::create_directories(out / "plots");
  std::vector<std::size_t> plot_order;
  for (TrialRole want : {TrialRole::kValidation, TrialRole::kLumped, TrialRole::kGeometric}) {
    for (std::size_t k = 0; k < trials.size(); ++k) {
      if (roles[k] == want && trials[k].terrain.MaxHeight() > 0.0) plot_order.push_back(k);
    }
  }
  if (plot_order.size() > static_cast<std::size_t>(std::max(0LL, max_plots))) {
    plot_order.resize(static_cast<std::size_t>(std::max(0LL, max_plots)));
  }
  std::vector<std::string> plot_files(trials.size());
  for (std::size_t k : plot_order) plot_files[k] = "plots/" + trials[k].name + ".png";
  // One gnuplot process per figure: the figures are drawn concurrently (each its own files).
  const int workers = static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 2u, 8u));
  diagnose::ParallelFor(plot_order.size(), workers, [&](std::size_t i) {
    const std::size_t k = plot_order[i];
    const TrialComparison cmp =
        CompareTrial(trials[k], result.chair, options.simulation, options.offset_window);
    PlotTrial(trials[k], result.chair, cmp, out / plot_files[k]);
  });

  const std::vector<ParameterRow> rows = ParameterRows(result.chair, truth);
  WriteFileAtomically(out / "identified-chair.yaml", ChairToYaml(result.chair));

  std::string md = "# Identification report\n\n";
  md += "pwsim identify on " + std::to_string(trials.size()) +
        " trials (seed 000 §IV): the geometric model by linear least squares on the slowest "
        "trials, the lumped model by output-error minimisation (Ceres, Levenberg-Marquardt) on "
        "the fastest, validated on trials held out of both fits. Mode: " +
        std::string(options.shared_mode ? "one natural frequency and damping ratio for Z and "
                                          "pitch at " + Fixed(result.reference_load_kg, 0) + " kg"
                                        : "independent K, C per axis") +
        "; " + std::to_string(options.passes) + " GM/LM pass(es).\n\n";
  md += "## Identified parameters beside Table I\n\n" + MarkdownTable(rows, truth != nullptr);
  if (truth) md += "\n(truth: `" + truth_file.string() + "`, written by `pwsim generate`.)\n";
  md += "\nFitness (MATLAB `compare`, 100 (1 - |y - ŷ| / |y - mean y|), model driven by the "
        "measured x(t), channels centred at the start):\n\n";
  md += "| trial | role | load [kg] | speed [m/s] | untracked frames | fit Z [%] | fit θ [%] |\n";
  md += "|---|---|---|---|---|---|---|\n";
  for (std::size_t k = 0; k < trials.size(); ++k) {
    const TrialFit& fit = result.trials[k];
    md += "| " + fit.trial + " | " + RoleName(fit.role) + " | " + Fixed(trials[k].load_kg, 0) +
          " | " + Fixed(trials[k].NominalSpeed(), 2) + " | " +
          std::to_string(trials[k].track.untracked_frames) + " | " + Fixed(fit.fit_z, 1) +
          " | " + Fixed(fit.fit_pitch, 1) + " |\n";
  }
  md += "\n**Validation (held out, pooled): Z " + Fixed(result.validation_fit_z, 1) +
        " %, θ " + Fixed(result.validation_fit_pitch, 1) +
        " %** (the paper reports 79.3 % and 57.6 % on its real chair).\n\n";
  if (in.check) {
    md += "## Does the model reproduce the trials to the noise?\n\n" +
          ModelCheckText(*in.check, result.validation_fit_z, result.validation_fit_pitch) + "\n\n";
  }
  md += "## Overlays (like Fig. 5)\n\n";
  for (std::size_t k : plot_order) {
    md += "### " + trials[k].name + " (" + RoleName(roles[k]) + ")\n\n![" + trials[k].name +
          "](" + plot_files[k] + ")\n\n";
  }
  md += "## Solver\n\nLinear start: K_z " + Significant(result.start.lm.k_z, 5) + ", C_z " +
        Significant(result.start.lm.c_z, 5) + ", K_θ " + Significant(result.start.lm.k_theta, 5) +
        ", C_θ " + Significant(result.start.lm.c_theta, 5) + (result.start.fallback_z ||
        result.start.fallback_pitch ? " (partly a default: the linear estimate was unusable)" : "") +
        ". Ceres: " + std::to_string(result.solver_iterations) + " iterations in all; last solve: " +
        result.solver_summary + "\n";
  WriteFileAtomically(out / "identify.md", md);

  nlohmann::ordered_json fit;
  fit["format"] = "pwsim-fit/1";
  fit["trials"] = nlohmann::ordered_json::array();
  for (const TrialFit& t : result.trials) {
    fit["trials"].push_back({{"trial", t.trial},
                             {"role", RoleName(t.role)},
                             {"fit_pct", {{"z", JsonNumber(t.fit_z)}, {"pitch", JsonNumber(t.fit_pitch)}}}});
  }
  fit["validation_fit_pct"] = {{"z", JsonNumber(result.validation_fit_z)},
                               {"pitch", JsonNumber(result.validation_fit_pitch)}};
  fit["shared_mode"] = options.shared_mode;
  fit["identified_chair"] = "identified-chair.yaml";
  if (in.check) {  // an addition: the model's residual against the noise (sysid/diagnose/model_check.h)
    const diagnose::ModelCheck& c = *in.check;
    auto channel = [](const diagnose::ChannelCheck& ch, const diagnose::ChannelNoise& n, double floor) {
      return nlohmann::ordered_json{{"noise_sigma", JsonNumber(n.sigma)},
                                    {"noise_floor_fit_pct", JsonNumber(floor)},
                                    {"structured_rms_sigma", JsonNumber(ch.rho)},
                                    {"worst_window_sigma", JsonNumber(ch.rho_local)},
                                    {"noise_like", ch.NoiseLike()}};
    };
    fit["model_check"] = {{"trials", c.judged},
                          {"held_out", c.held_out},
                          {"z", channel(c.check.z, c.noise.z, c.noise_floor_z)},
                          {"pitch", channel(c.check.pitch, c.noise.pitch, c.noise_floor_pitch)},
                          {"measurably_wrong", c.MeasurablyWrong()},
                          {"evidence", c.check.Evidence()},
                          {"next_step", c.MeasurablyWrong() ? "pwsim diagnose" : ""}};
  }
  WriteFileAtomically(out / "fit.json", fit.dump(2) + "\n");

  return rows;
}

}  // namespace pwsim::report
