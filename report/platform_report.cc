#include "report/platform_report.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <iomanip>
#include <sstream>

#include "engine/atomic_file.h"
#include "plot/plot.h"

namespace pwsim::report {
namespace {

namespace sp = sysid::platform;
using Json = nlohmann::ordered_json;

std::string Fixed(double v, int digits) {
  std::ostringstream o;
  o << std::fixed << std::setprecision(digits) << v;
  return o.str();
}

std::vector<std::filesystem::path> FigureList(const std::filesystem::path& stem) {
  const plot::FigureFiles f = plot::FigureFilesFor(stem);
  return {f.png, f.svg, f.csv, f.gp};
}

// Draws a figure; returns a Markdown line (image link or why it is missing).
std::string TryFigure(const std::filesystem::path& stem, const plot::Figure& figure,
                      std::vector<std::filesystem::path>* written) {
  if (!plot::GnuplotAvailable()) return "_(figure " + stem.filename().string() + " not drawn: gnuplot not found)_";
  plot::WriteFigure(stem, figure);
  for (const auto& f : FigureList(stem)) written->push_back(f);
  return "![" + stem.filename().string() + "](" + stem.filename().string() + ".png)";
}

Json ParameterJson(double value, double sigma, const std::string& unit) {
  Json p;
  p["value"] = value;
  p["sigma"] = sigma;
  p["unit"] = unit;
  return p;
}

}  // namespace

std::vector<std::filesystem::path> PlatformIdentifyOutputs(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> out{dir / "platform-fit.json", dir / "identify.md"};
  for (const auto& f : FigureList(dir / "identify-effort")) out.push_back(f);
  return out;
}
std::vector<std::filesystem::path> PlatformDiagnoseOutputs(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> out{dir / "diagnosis.json", dir / "diagnosis.md"};
  for (const auto& f : FigureList(dir / "diagnosis-heldout")) out.push_back(f);
  for (const auto& f : FigureList(dir / "diagnosis-velocity")) out.push_back(f);
  return out;
}
std::vector<std::filesystem::path> PlatformFrequencyOutputs(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> out{dir / "frequency-response.json",
                                         dir / "frequency-response.md"};
  for (const auto& f : FigureList(dir / "bode")) out.push_back(f);
  return out;
}

std::vector<std::filesystem::path> WritePlatformIdentifyReport(const sp::PlatformFit& fit,
                                                               const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> written;
  Json root;
  root["format"] = "pwsim-platform-fit/1";
  root["model"] = fit.model.name;
  Json joints = Json::array();
  Json shared = Json::object();
  for (const std::string& joint : fit.joints) {
    Json j;
    j["joint"] = joint;
    Json params = Json::object();
    for (std::size_t i = 0; i < fit.model.params.size(); ++i) {
      const sp::ParameterInfo& p = fit.model.params[i];
      const auto k = static_cast<Eigen::Index>(i);
      if (p.joint == joint) params[p.name] = ParameterJson(fit.ls.theta(k), fit.ls.sigma(k), p.unit);
    }
    j["parameters"] = params;
    joints.push_back(j);
  }
  for (std::size_t i = 0; i < fit.model.params.size(); ++i) {
    const sp::ParameterInfo& p = fit.model.params[i];
    const auto k = static_cast<Eigen::Index>(i);
    if (p.joint.empty()) shared[p.name] = ParameterJson(fit.ls.theta(k), fit.ls.sigma(k), p.unit);
  }
  // The inertial parameters θ1..θ4 of rail-yaw belong to both joints' equations: they are
  // listed with the first joint (where the contract looks for them) and under "inertial".
  if (!shared.empty() && !joints.empty())
    for (auto& [name, value] : shared.items()) joints[0]["parameters"][name] = value;
  root["joints"] = joints;
  if (!shared.empty()) root["inertial"] = shared;
  root["relative_error_pct"] = fit.ls.relative_error_pct;
  root["condition_number"] = fit.ls.condition_number;
  root["rows"] = fit.ls.rows;
  Json validation = Json::array();
  for (const sp::ValidationResult& v : fit.validation) {
    Json x;
    x["recording"] = v.recording;
    x["relative_error_pct"] = v.relative_error_pct;
    x["condition_number"] = v.condition_number;
    x["rows"] = v.rows;
    validation.push_back(x);
  }
  root["validation"] = validation;
  root["error_norm"] = fit.ls.error_norm;
  root["error_std"] = fit.ls.error_std;

  // Figure: measured vs predicted effort and residual, per joint block.
  plot::Figure fig;
  fig.title = "Each joint's effort, measured and predicted by the identified model (" + fit.model.name +
              ", inverse-dynamics least squares)";
  fig.x_label = "time [s]";
  const Eigen::VectorXd pred = fit.regression.x * fit.ls.theta;
  for (std::size_t j = 0; j < fit.joints.size(); ++j) {
    plot::Series meas{"measured", {}, {}}, model{"identified model", {}, {}}, res{"measured - model", {}, {}};
    for (Eigen::Index i = 0; i < fit.regression.y.size(); ++i) {
      if (fit.regression.joint_of_row[static_cast<std::size_t>(i)] != static_cast<int>(j)) continue;
      const double t = fit.regression.t[static_cast<std::size_t>(i)];
      meas.x.push_back(t);
      meas.y.push_back(fit.regression.y(i));
      model.x.push_back(t);
      model.y.push_back(pred(i));
      res.x.push_back(t);
      res.y.push_back(fit.regression.y(i) - pred(i));
    }
    if (meas.x.empty()) continue;
    plot::Panel p1;
    const bool rotary = j < fit.joint_kinds.size() && fit.joint_kinds[j] == sysid::platform::JointKind::kRevolute;
    const std::string effort = rotary ? "torque" : "force", unit = rotary ? " [N m]" : " [N]";
    p1.title = "joint " + fit.joints[j] + ": motor " + effort + " (the rows the fit used)";
    p1.y_label = effort + unit;
    p1.series = {meas, model};
    plot::Panel p2;
    p2.title = "joint " + fit.joints[j] + ": what the model misses";
    p2.y_label = effort + " error" + unit;
    p2.series = {res};
    fig.panels.push_back(p1);
    fig.panels.push_back(p2);
  }
  const std::string figure_line = TryFigure(dir / "identify-effort", fig, &written);

  std::ostringstream md;
  md << "# Platform identification (IDIM-LS)\n\n"
     << "Model `" << fit.model.name << "`, " << fit.ls.rows << " rows after decimation.\n\n"
     << "| joint | parameter | value | σ | σ/|value| | unit |\n|---|---|---|---|---|---|\n";
  for (std::size_t i = 0; i < fit.model.params.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    const auto& p = fit.model.params[i];
    md << "| " << (p.joint.empty() ? "(shared)" : p.joint) << " | " << p.name << " | "
       << Fixed(fit.ls.theta(k), 4) << " | " << Fixed(fit.ls.sigma(k), 4) << " | "
       << Fixed(100.0 * fit.ls.sigma(k) / std::max(std::abs(fit.ls.theta(k)), 1e-300), 3)
       << " % | " << p.unit << " |\n";
  }
  md << "\nRelative error ‖τ − Xθ‖/‖τ‖ = " << Fixed(fit.ls.relative_error_pct, 4)
     << " %, condition number " << Fixed(fit.ls.condition_number, 4) << ", error norm "
     << Fixed(fit.ls.error_norm, 4) << ".\n\n";
  if (!fit.validation.empty()) {
    md << "## Cross-test (parameters held fixed)\n\n| recording | relative error | rows |\n|---|---|---|\n";
    for (const auto& v : fit.validation)
      md << "| " << v.recording << " | " << Fixed(v.relative_error_pct, 4) << " % | " << v.rows << " |\n";
    md << "\n";
  }
  md << figure_line << "\n";
  WriteFileAtomically(dir / "identify.md", md.str());
  written.push_back(dir / "identify.md");
  WriteFileAtomically(dir / "platform-fit.json", root.dump(1) + "\n");
  written.push_back(dir / "platform-fit.json");
  return written;
}

std::vector<std::filesystem::path> WritePlatformDiagnosisReport(const sp::AxisDiagnosis& d,
                                                                const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> written;
  Json root;
  root["format"] = "pwsim-diagnosis/1";
  root["joint"] = d.joint;
  root["verdict"] = diagnose::VerdictName(d.verdict);
  root["cause"] = d.cause;
  Json causes = Json::array();
  for (const sp::AxisCause& c : d.causes) {
    Json x;
    x["effect"] = sp::AxisEffectId(c.effect);
    x["heldout_gain_pct"] = c.heldout_gain_pct;
    x["confirmed"] = c.confirmed;
    x["heldout_gain_se_pct"] = c.heldout_gain_se_pct;
    x["heldout_gain_lower_pct"] = c.heldout_gain_lower_pct;
    x["selection_gain_pct"] = c.selection_gain_pct;
    causes.push_back(x);
  }
  root["causes"] = causes;
  Json ranking = Json::array();
  for (const sp::EffectResult& r : d.ranking) {
    Json e;
    e["effect"] = sp::AxisEffectId(r.effect);
    e["evidence"] = r.evidence;
    e["delta_bic"] = r.delta_bic;
    e["earns"] = r.earns;
    e["train_relative_error_pct"] = r.train_relative_error_pct;
    e["selection_relative_error_pct"] = r.selection_relative_error_pct;
    e["selection_gain_pct"] = r.selection_gain_pct;
    e["heldout_relative_error_pct"] = r.heldout_relative_error_pct;
    e["heldout_gain_pct"] = r.heldout_gain_pct;
    Json params = Json::object();
    for (const auto& p : r.parameters) params[p.name] = p.value;
    e["parameters"] = params;
    ranking.push_back(e);
  }
  root["ranking"] = ranking;
  Json held;
  held["base"] = d.heldout_base_pct;
  held["extended"] = d.heldout_extended_pct;
  root["heldout_relative_error_pct"] = held;
  root["noise_floor_relative_error_pct"] = d.noise_floor_pct;
  root["train_relative_error_pct"] = d.base_train_relative_error_pct;
  Json sel;
  sel["base"] = d.selection_base_pct;
  sel["extended"] = d.selection_extended_pct;
  root["selection_relative_error_pct"] = sel;
  root["selection_noise_floor_relative_error_pct"] = d.selection_floor_pct;
  root["noise_sigma"] = d.noise_sigma;
  root["report_blocks"] = d.report_blocks;
  root["heldout_trials"] = d.heldout_recordings;
  root["training_recordings"] = d.training_recordings;
  root["selection_recordings"] = d.selection_recordings;
  Json split = Json::array();
  for (const sp::AxisBlock& b : d.blocks) {
    Json x;
    x["recording"] = b.recording;
    x["begin_sample"] = b.begin;
    x["end_sample"] = b.end;
    x["role"] = sp::AxisRoleName(b.role);
    split.push_back(x);
  }
  root["split"] = split;
  if (!d.unexplained_evidence.empty()) {
    Json u;
    u["heldout_relative_error_pct"] = d.heldout_extended_pct;
    u["evidence"] = d.unexplained_evidence;
    root["unexplained"] = u;
  }
  Json base = Json::object(), ext = Json::object();
  for (const auto& p : d.base_parameters) base[p.name] = p.value;
  for (const auto& p : d.extended_parameters) ext[p.name] = p.value;
  root["base_parameters"] = base;
  root["extended_parameters"] = ext;
  Json loop = Json::array();
  for (const sp::ClosedLoopComparison& c : d.closed_loop) {
    Json x;
    x["recording"] = c.recording;
    x["available"] = c.available;
    if (c.available) {
      for (const auto& [name, e] : {std::pair{"base", c.base}, std::pair{"extended", c.extended}}) {
        Json m;
        m["position_pct"] = e.position_pct;
        m["velocity_pct"] = e.velocity_pct;
        m["effort_pct"] = e.effort_pct;
        x[name] = m;
      }
    }
    if (!c.why_not.empty()) x["note"] = c.why_not;
    loop.push_back(x);
  }
  root["closed_loop"] = loop;

  plot::Figure fig;
  const std::string verdict = diagnose::VerdictName(d.verdict);
  fig.title = "The report rows (held out of every choice; the axis moving): verdict " + verdict + ", cause " + d.cause;
  fig.x_label = "report sample, in recording order [number]";
  std::vector<double> idx(d.heldout_tau.size());
  for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = static_cast<double>(i);
  std::vector<double> rb(idx.size()), re(idx.size());
  for (std::size_t i = 0; i < idx.size(); ++i) {
    rb[i] = d.heldout_tau[i] - d.heldout_base[i];
    re[i] = d.heldout_tau[i] - d.heldout_ext[i];
  }
  plot::Panel p1;
  p1.title = "motor effort, measured and modelled";
  p1.y_label = "effort [N]";
  p1.series = {{"measured", idx, d.heldout_tau}, {"base model", idx, d.heldout_base}, {"model with the cause", idx, d.heldout_ext}};
  plot::Panel p2;
  p2.title = "what each model misses (measured - model)";
  p2.y_label = "effort error [N]";
  p2.series = {{"base model", idx, rb}, {"model with the cause", idx, re}};
  plot::Panel p3;
  p3.title = "what each model misses, against the axis speed";
  p3.y_label = "effort error [N]";
  plot::Series sb{"base model", d.heldout_qd, rb, plot::Style::kPoints};
  plot::Series se{"model with the cause", d.heldout_qd, re, plot::Style::kPoints};
  p3.series = {sb, se};
  fig.panels = {p1, p2};
  std::string figure_line;
  if (!idx.empty()) {
    figure_line = TryFigure(dir / "diagnosis-heldout", fig, &written);
    plot::Figure fv;
    fv.title = "The report rows: each model's effort error against the axis speed";
    fv.x_label = "axis speed [m/s for a rail, rad/s for a rotary joint]";
    fv.panels = {p3};
    figure_line += "\n\n" + TryFigure(dir / "diagnosis-velocity", fv, &written);
  }

  std::ostringstream md;
  md << "# Platform diagnosis: joint `" << d.joint << "`\n\n"
     << "**Verdict: " << verdict << "**, cause `" << d.cause << "`.\n\n"
     << "Training rows fit, selection rows decide, report rows (held out) only report; blocks "
        "of contiguous samples, each filtered on its own.\n\n"
     << "| measure | base | extended |\n|---|---|---|\n"
     << "| training relative error | " << Fixed(d.base_train_relative_error_pct, 3) << " % | |\n"
     << "| selection relative error | " << Fixed(d.selection_base_pct, 3) << " % | "
     << Fixed(d.selection_extended_pct, 3) << " % |\n"
     << "| noise floor (selection) | " << Fixed(d.selection_floor_pct, 3) << " % | |\n"
     << "| report (held-out) relative error | " << Fixed(d.heldout_base_pct, 3) << " % | "
     << Fixed(d.heldout_extended_pct, 3) << " % |\n"
     << "| noise floor (report) | " << Fixed(d.noise_floor_pct, 3) << " % | |\n\n"
     << "Blocks: " << d.training_recordings.size() << " training, " << d.selection_recordings.size()
     << " selection, " << d.heldout_recordings.size() << " report (" << d.report_blocks
     << " blocks for the uncertainty): ";
  for (std::size_t i = 0; i < d.heldout_recordings.size(); ++i)
    md << (i ? ", " : "") << "`" << d.heldout_recordings[i] << "`";
  md << ".\n\n## Causes, in the order found\n\n";
  if (d.causes.empty()) md << "none\n";
  else
    md << "| effect | selection gain | report gain ± se | lower bound | confirmed |\n|---|---|---|---|---|\n";
  for (const sp::AxisCause& c : d.causes)
    md << "| `" << sp::AxisEffectId(c.effect) << "` | " << Fixed(c.selection_gain_pct, 1) << " % | "
       << Fixed(c.heldout_gain_pct, 1) << " ± " << Fixed(c.heldout_gain_se_pct, 1) << " % | "
       << Fixed(c.heldout_gain_lower_pct, 1) << " % | " << (c.confirmed ? "yes" : "no") << " |\n";
  md << "\nGain: the share of the base model's error above the noise that adding the effect "
        "removed. Confirmed: the one-sided lower bound (jackknife over the report blocks, Student "
        "t) is positive.\n";
  md << "\n## Every candidate on the base model\n\n| effect | ΔBIC | selection gain | earns | "
        "report error | report gain | evidence |\n|---|---|---|---|---|---|---|\n";
  for (const auto& r : d.ranking)
    md << "| `" << sp::AxisEffectId(r.effect) << "` | " << Fixed(r.delta_bic, 1) << " | "
       << Fixed(r.selection_gain_pct, 1) << " % | " << (r.earns ? "yes" : "no") << " | "
       << Fixed(r.heldout_relative_error_pct, 3) << " % | " << Fixed(r.heldout_gain_pct, 1)
       << " % | " << r.evidence << " |\n";
  md << "\n## Extended model parameters\n\n";
  for (const auto& p : d.extended_parameters) md << "- " << p.name << " = " << p.value << "\n";
  md << "\n## Closed-loop simulation, compared on the report samples\n\n"
     << "| recording | model | position | velocity | effort |\n|---|---|---|---|---|\n";
  for (const auto& c : d.closed_loop) {
    if (!c.available) {
      md << "| " << c.recording << " | (" << c.why_not << ") | | | |\n";
      continue;
    }
    md << "| " << c.recording << " | base | " << Fixed(c.base.position_pct, 4) << " % | "
       << Fixed(c.base.velocity_pct, 3) << " % | " << Fixed(c.base.effort_pct, 3) << " % |\n"
       << "| " << c.recording << " | extended | " << Fixed(c.extended.position_pct, 4) << " % | "
       << Fixed(c.extended.velocity_pct, 3) << " % | " << Fixed(c.extended.effort_pct, 3)
       << " % |\n";
    if (!c.why_not.empty()) md << "\n_" << c.why_not << "_\n\n";
  }
  if (!d.unexplained_evidence.empty()) md << "\nLeft unexplained: " << d.unexplained_evidence << "\n";
  md << "\n" << figure_line << "\n";
  WriteFileAtomically(dir / "diagnosis.md", md.str());
  written.push_back(dir / "diagnosis.md");
  WriteFileAtomically(dir / "diagnosis.json", root.dump(1) + "\n");
  written.push_back(dir / "diagnosis.json");
  return written;
}

namespace {

double HighestFrequency(const sp::JointFrequencyResponse& j) {
  double w_hi = 0.0;
  for (const auto& p : j.points) w_hi = std::max(w_hi, p.w_rad_s);
  return w_hi;
}

/// Why there is no nonparametric bandwidth (0 in the JSON): the measured gain never fell 3 dB.
std::string NoBandwidthNote(double w_hi) {
  return "not measured: the measured gain never falls 3 dB below its low-frequency value up to " +
         Fixed(w_hi, 1) +
         " rad/s, the highest frequency the recording excites (it is not a chirp reaching beyond the "
         "bandwidth); record a chirp to higher frequencies to measure it";
}

}  // namespace

std::vector<std::filesystem::path> WriteFrequencyResponseReport(
    const std::vector<sp::JointFrequencyResponse>& joints, const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> written;
  Json root;
  root["format"] = "pwsim-frequency-response/1";
  Json arr = Json::array();
  std::ostringstream md;
  md << "# Frequency response (reference → position)\n\n";
  plot::Figure fig;
  fig.title = "Frequency response of each joint's position loop, reference to measured position: measured and fitted";
  fig.x_label = "frequency [rad/s]";
  fig.log_x = true;
  for (const auto& j : joints) {
    Json x;
    x["joint"] = j.joint;
    x["bandwidth_rad_s"] = j.bandwidth_rad_s;
    x["bandwidth_nonparametric_rad_s"] = j.bandwidth_nonparametric_rad_s;
    if (!(j.bandwidth_nonparametric_rad_s > 0.0)) x["bandwidth_nonparametric_note"] = NoBandwidthNote(HighestFrequency(j));
    x["segments"] = j.segments;
    Json fits = Json::array();
    for (const auto& f : j.fits) {
      Json y;
      y["order"] = f.order;
      y["num"] = f.num;
      y["den"] = f.den;
      y["delay_s"] = f.delay_s;
      y["fit_pct"] = f.fit_pct;
      y["bandwidth_rad_s"] = f.bandwidth_rad_s;
      fits.push_back(y);
    }
    x["fits"] = fits;
    Json pts = Json::array();
    plot::Series g{"measured (H1 estimate)", {}, {}, plot::Style::kPoints},
        ph{"measured (H1 estimate)", {}, {}, plot::Style::kPoints},
        coh{"coherence", {}, {}, plot::Style::kLinesPoints};
    g.color = ph.color = plot::color::kBlack;
    coh.color = plot::color::kBlack;
    double w_lo = INFINITY, w_hi = 0.0;
    for (const auto& p : j.points) {
      Json y;
      y["w_rad_s"] = p.w_rad_s;
      y["gain_db"] = p.gain_db;
      y["phase_deg"] = p.phase_deg;
      y["coherence"] = p.coherence;
      y["fitted"] = p.fitted;
      pts.push_back(y);
      g.x.push_back(p.w_rad_s);
      g.y.push_back(p.gain_db);
      ph.x.push_back(p.w_rad_s);
      ph.y.push_back(p.phase_deg);
      coh.x.push_back(p.w_rad_s);
      coh.y.push_back(p.coherence);
      w_lo = std::min(w_lo, p.w_rad_s);
      w_hi = std::max(w_hi, p.w_rad_s);
    }
    x["points"] = pts;
    arr.push_back(x);
    plot::Panel pg, pp, pc;
    pg.title = "joint " + j.joint + ": gain, measured position over reference";
    pg.y_label = "gain [dB]";
    pg.series.push_back(g);
    pp.title = "joint " + j.joint + ": phase of the measured position against the reference";
    pp.y_label = "phase [deg]";
    pp.series.push_back(ph);
    pc.title = "joint " + j.joint + ": coherence (1: the position follows the reference linearly and without noise)";
    pc.y_label = "coherence [-]";
    pc.y_min = 0.0;  // on its whole scale: a dip from 1 to 0.98 is no cause for alarm
    pc.y_max = 1.05;
    pc.series.push_back(coh);
    for (const auto& f : j.fits) {
      const std::string label = "fitted model of order " + std::to_string(f.order) + " (fit " + Fixed(f.fit_pct, 1) + " %)";
      plot::Series fg{label, {}, {}}, fp{label, {}, {}};
      fg.color = fp.color = f.order == 2 ? plot::color::kBlue : plot::color::kVermillion;
      fg.dash = fp.dash = f.order == 2 ? 0 : 2;  // the fits of both orders often coincide
      double prev = 0, unwrap = 0;
      bool first = true;
      // The fit drawn as a smooth curve over the measured band (200 log-spaced frequencies).
      std::vector<double> grid;
      for (int i = 0; i < 200 && w_hi > w_lo; ++i) grid.push_back(w_lo * std::pow(w_hi / w_lo, i / 199.0));
      for (const double w : grid) {
        const std::complex<double> s(0, w);
        std::complex<double> nn(0, 0), dd(0, 0);
        for (double c : f.num) nn = nn * s + c;
        for (double c : f.den) dd = dd * s + c;
        const std::complex<double> h = nn / dd * std::exp(-s * f.delay_s);
        fg.x.push_back(w);
        fg.y.push_back(20.0 * std::log10(std::abs(h)));
        double a = std::arg(h);
        if (!first) {
          while (a + unwrap - prev > M_PI) unwrap -= 2 * M_PI;
          while (a + unwrap - prev < -M_PI) unwrap += 2 * M_PI;
        }
        first = false;
        prev = a + unwrap;
        fp.x.push_back(w);
        fp.y.push_back(prev * 180.0 / M_PI);
      }
      pg.series.push_back(fg);
      pp.series.push_back(fp);
    }
    fig.panels.push_back(pg);
    fig.panels.push_back(pp);
    fig.panels.push_back(pc);
    md << "## Joint `" << j.joint << "`\n\n"
       << "- −3 dB bandwidth (best fit): " << Fixed(j.bandwidth_rad_s, 3) << " rad/s ("
       << Fixed(j.bandwidth_rad_s / (2.0 * M_PI), 3) << " Hz)"
       << (j.bandwidth_rad_s > w_hi ? ", extrapolated beyond the highest measured frequency (" + Fixed(w_hi, 1) + " rad/s)"
                                    : std::string())
       << "\n- −3 dB bandwidth (nonparametric): "
       << (j.bandwidth_nonparametric_rad_s > 0.0 ? Fixed(j.bandwidth_nonparametric_rad_s, 3) + " rad/s"
                                                 : NoBandwidthNote(w_hi))
       << "\n- segments averaged: " << j.segments << "\n\n"
       << "| order | num | den | delay | fit |\n|---|---|---|---|---|\n";
    for (const auto& f : j.fits) {
      md << "| " << f.order << " | ";
      for (double c : f.num) md << c << " ";
      md << "| ";
      for (double c : f.den) md << c << " ";
      md << "| " << Fixed(1000.0 * f.delay_s, 3) << " ms | " << Fixed(f.fit_pct, 2) << " % |\n";
    }
    md << "\n";
  }
  root["joints"] = arr;
  md << TryFigure(dir / "bode", fig, &written) << "\n";
  WriteFileAtomically(dir / "frequency-response.md", md.str());
  written.push_back(dir / "frequency-response.md");
  WriteFileAtomically(dir / "frequency-response.json", root.dump(1) + "\n");
  written.push_back(dir / "frequency-response.json");
  return written;
}

}  // namespace pwsim::report
