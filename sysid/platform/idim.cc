#include "sysid/platform/idim.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "sysid/platform/signal_filters.h"

namespace pwsim::sysid::platform {
namespace {

std::string EffortUnit(JointKind k) { return k == JointKind::kRevolute ? "N m" : "N"; }
std::string InertiaUnit(JointKind k) { return k == JointKind::kRevolute ? "kg m^2" : "kg"; }
std::string ViscousUnit(JointKind k) { return k == JointKind::kRevolute ? "N m s/rad" : "N s/m"; }

std::size_t JointIndex(const ProcessedRecording& r, const std::string& name) {
  for (std::size_t i = 0; i < r.joints.size(); ++i)
    if (r.joints[i].name == name) return i;
  throw std::invalid_argument("the recording has no joint named '" + name + "'");
}

}  // namespace

ProcessedRecording Preprocess(const AxisRecording& recording, const IdimOptions& options) {
  ProcessedRecording out;
  out.name = recording.file.filename().string();
  out.dt = recording.dt;
  const double fs = 1.0 / recording.dt;
  const double wn = options.lowpass_cutoff_hz / (fs / 2.0);
  const auto border = static_cast<std::size_t>(std::max(0, options.border_samples));
  if (recording.size() <= border + 32)
    throw std::invalid_argument(recording.file.string() + ": too short for identification (" +
                                std::to_string(recording.size()) + " samples)");
  const TransferFunction lowpass =
      wn < 1.0 ? Butterworth(options.lowpass_order, wn) : TransferFunction{{1.0}, {1.0}};
  std::vector<std::vector<double>> qfs, qds, qdds;
  std::size_t end_border = options.end_border_samples > 0
                               ? static_cast<std::size_t>(options.end_border_samples)
                               : 0;
  for (const JointRecording& j : recording.joints) {
    qfs.push_back(wn < 1.0 ? FiltFilt(lowpass, j.position) : j.position);
    qds.push_back(DiffCentral(qfs.back(), recording.dt));
    qdds.push_back(DiffCentral(qds.back(), recording.dt));
  }
  if (recording.size() <= border + end_border + 32)
    throw std::invalid_argument(recording.file.string() + ": too short for identification");
  const auto last = static_cast<std::ptrdiff_t>(recording.size() - end_border);
  out.t.assign(recording.t.begin() + static_cast<std::ptrdiff_t>(border), recording.t.begin() + last);
  for (std::size_t ji = 0; ji < recording.joints.size(); ++ji) {
    const JointRecording& j = recording.joints[ji];
    JointStates s;
    s.name = j.name;
    s.kind = j.kind;
    const std::vector<double>& qf = qfs[ji];
    const std::vector<double>& qd = qds[ji];
    const std::vector<double>& qdd = qdds[ji];
    auto cut = [&](const std::vector<double>& v) {
      return std::vector<double>(v.begin() + static_cast<std::ptrdiff_t>(border), v.begin() + last);
    };
    s.q = cut(qf);
    s.qd = cut(qd);
    s.qdd = cut(qdd);
    s.tau = cut(j.effort);
    out.joints.push_back(std::move(s));
  }
  return out;
}

LinearModel AxisBaseModel(const std::string& joint, JointKind kind) {
  LinearModel m;
  m.name = "axis-base";
  m.params = {{joint, "inertia", InertiaUnit(kind)}, {joint, "viscous", ViscousUnit(kind)},
              {joint, "coulomb", EffortUnit(kind)}, {joint, "offset", EffortUnit(kind)}};
  m.columns = [joint](const ProcessedRecording& r, std::size_t j, Eigen::MatrixXd& x) {
    const JointStates& s = r.joints[j];
    const auto n = static_cast<Eigen::Index>(s.q.size());
    x.setZero(n, 4);
    if (s.name != joint) return;
    for (Eigen::Index i = 0; i < n; ++i) {
      const auto k = static_cast<std::size_t>(i);
      x(i, 0) = s.qdd[k];
      x(i, 1) = s.qd[k];
      x(i, 2) = Sign(s.qd[k]);
      x(i, 3) = 1.0;
    }
  };
  return m;
}

LinearModel AxisAsymmetricModel(const std::string& joint, JointKind kind) {
  LinearModel m;
  m.name = "axis-asymmetric";
  m.params = {{joint, "inertia", InertiaUnit(kind)},     {joint, "viscous_pos", ViscousUnit(kind)},
              {joint, "coulomb_pos", EffortUnit(kind)},  {joint, "viscous_neg", ViscousUnit(kind)},
              {joint, "coulomb_neg", EffortUnit(kind)}};
  m.columns = [joint](const ProcessedRecording& r, std::size_t j, Eigen::MatrixXd& x) {
    const JointStates& s = r.joints[j];
    const auto n = static_cast<Eigen::Index>(s.q.size());
    x.setZero(n, 5);
    if (s.name != joint) return;
    for (Eigen::Index i = 0; i < n; ++i) {
      const double v = s.qd[static_cast<std::size_t>(i)];
      x(i, 0) = s.qdd[static_cast<std::size_t>(i)];
      x(i, 1) = v > 0.0 ? v : 0.0;
      x(i, 2) = v > 0.0 ? 1.0 : 0.0;
      x(i, 3) = v < 0.0 ? v : 0.0;
      x(i, 4) = v < 0.0 ? -1.0 : 0.0;
    }
  };
  return m;
}

LinearModel FrictionModel(const std::string& joint, const IdimOptions& options, JointKind kind) {
  LinearModel m;
  m.name = "friction";
  m.params = {{joint, "viscous", ViscousUnit(kind)}, {joint, "coulomb", EffortUnit(kind)},
              {joint, "offset", EffortUnit(kind)}};
  m.columns = [joint](const ProcessedRecording& r, std::size_t j, Eigen::MatrixXd& x) {
    const JointStates& s = r.joints[j];
    const auto n = static_cast<Eigen::Index>(s.q.size());
    x.setZero(n, 5);  // 3 parameters + q̇, q̈ carried for the row filter
    if (s.name != joint) return;
    for (Eigen::Index i = 0; i < n; ++i) {
      const auto k = static_cast<std::size_t>(i);
      x(i, 0) = s.qd[k];
      x(i, 1) = Sign(s.qd[k]);
      x(i, 2) = 1.0;
      x(i, 3) = s.qd[k];
      x(i, 4) = s.qdd[k];
    }
  };
  const double v_min = options.speed_threshold, a_max = options.accel_threshold;
  m.keep_rows = [v_min, a_max](const Eigen::MatrixXd& x, const JointStates&) {
    const double v_peak = x.col(3).cwiseAbs().maxCoeff();
    const double a_peak = x.col(4).cwiseAbs().maxCoeff();
    const double v_lo = v_min > 0.0 ? v_min : 0.02 * v_peak;
    const double a_hi = a_max > 0.0 ? a_max : 0.02 * a_peak;
    std::vector<bool> keep(static_cast<std::size_t>(x.rows()));
    for (Eigen::Index i = 0; i < x.rows(); ++i)
      keep[static_cast<std::size_t>(i)] = std::abs(x(i, 3)) > v_lo && std::abs(x(i, 4)) < a_hi;
    return keep;
  };
  return m;
}

LinearModel RailYawModel(const ProcessedRecording& recording) {
  if (recording.joints.size() != 2)
    throw std::invalid_argument("model rail-yaw: expected two joints, the recording has " +
                                std::to_string(recording.joints.size()));
  int yaw = -1, rail = -1;
  for (std::size_t i = 0; i < 2; ++i)
    (recording.joints[i].kind == JointKind::kRevolute ? yaw : rail) = static_cast<int>(i);
  if (yaw < 0 || rail < 0)
    throw std::invalid_argument(
        "model rail-yaw: expected one revolute (yaw) and one prismatic (rail) joint");
  const std::string yn = recording.joints[static_cast<std::size_t>(yaw)].name;
  const std::string rn = recording.joints[static_cast<std::size_t>(rail)].name;
  LinearModel m;
  m.name = "rail-yaw";
  m.params = {{"", "theta1", "kg m^2"},        {"", "theta2", "kg m"},
              {"", "theta3", "kg"},            {"", "theta4", "kg m"},
              {yn, "viscous", "N m s/rad"},    {yn, "coulomb", "N m"},
              {yn, "offset", "N m"},           {rn, "viscous", "N s/m"},
              {rn, "coulomb", "N"},            {rn, "offset", "N"}};
  const auto iy = static_cast<std::size_t>(yaw), ir = static_cast<std::size_t>(rail);
  m.columns = [iy, ir](const ProcessedRecording& r, std::size_t j, Eigen::MatrixXd& x) {
    const JointStates& s1 = r.joints[iy];
    const JointStates& s2 = r.joints[ir];
    const auto n = static_cast<Eigen::Index>(s1.q.size());
    x.setZero(n, 10);
    for (Eigen::Index i = 0; i < n; ++i) {
      const auto k = static_cast<std::size_t>(i);
      const double q2 = s2.q[k], qd1 = s1.qd[k], qd2 = s2.qd[k], qdd1 = s1.qdd[k],
                   qdd2 = s2.qdd[k];
      if (j == iy) {
        x(i, 0) = qdd1;
        x(i, 1) = q2 * qdd1 + qd1 * qd2;
        x(i, 2) = q2 * q2 * qdd1 + 2.0 * q2 * qd1 * qd2;
        x(i, 3) = qdd2;
        x(i, 4) = qd1;
        x(i, 5) = Sign(qd1);
        x(i, 6) = 1.0;
      } else {
        x(i, 1) = -0.5 * qd1 * qd1;
        x(i, 2) = qdd2 - q2 * qd1 * qd1;
        x(i, 3) = qdd1;
        x(i, 7) = qd2;
        x(i, 8) = Sign(qd2);
        x(i, 9) = 1.0;
      }
    }
  };
  return m;
}

LinearModel ModelByName(const std::string& name, const ProcessedRecording& recording,
                        const std::string& experiment, const IdimOptions& options) {
  const std::size_t joints = recording.joints.size();
  std::string chosen = name;
  if (chosen.empty()) {
    if (joints == 2)
      chosen = "rail-yaw";
    else
      chosen = (experiment == "step" || experiment == "ramp") ? "friction" : "axis-base";
  }
  if (chosen == "rail-yaw") return RailYawModel(recording);
  if (joints != 1 && chosen != "friction")
    throw std::invalid_argument("model " + chosen + ": expected one joint, the recording has " +
                                std::to_string(joints));
  const std::string joint = recording.joints.at(0).name;
  const JointKind kind = recording.joints.at(0).kind;
  if (chosen == "axis-base") return AxisBaseModel(joint, kind);
  if (chosen == "axis-asymmetric") return AxisAsymmetricModel(joint, kind);
  if (chosen == "friction") {
    if (joints != 1) throw std::invalid_argument("model friction: expected one joint");
    return FrictionModel(joint, options, kind);
  }
  std::string names;
  for (const std::string& n : ModelNames()) names += (names.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown model '" + name + "' (expected one of " + names + ")");
}

const std::vector<std::string>& ModelNames() {
  static const std::vector<std::string> names{"axis-base", "axis-asymmetric", "friction",
                                              "rail-yaw"};
  return names;
}

Regression BuildRegression(const ProcessedRecording& recording, const LinearModel& model,
                           const IdimOptions& options) {
  Regression out;
  const auto p = static_cast<Eigen::Index>(model.params.size());
  std::vector<Eigen::MatrixXd> blocks;
  std::vector<Eigen::VectorXd> ys;
  std::vector<std::vector<double>> ts;
  for (std::size_t j = 0; j < recording.joints.size(); ++j) {
    Eigen::MatrixXd full;
    model.columns(recording, j, full);
    if (full.cwiseAbs().sum() == 0.0) continue;  // the model has no equation for this joint
    const JointStates& s = recording.joints[j];
    const std::size_t n = s.q.size();
    std::vector<double> column(n);
    std::vector<double> first = Decimate(s.tau, options.decimation);
    const auto rows = static_cast<Eigen::Index>(first.size());
    Eigen::MatrixXd xd(rows, full.cols());
    Eigen::VectorXd yd = Eigen::Map<Eigen::VectorXd>(first.data(), rows);
    for (Eigen::Index c = 0; c < full.cols(); ++c) {
      for (std::size_t i = 0; i < n; ++i) column[i] = full(static_cast<Eigen::Index>(i), c);
      const std::vector<double> d = Decimate(column, options.decimation);
      xd.col(c) = Eigen::Map<const Eigen::VectorXd>(d.data(), rows);
    }
    std::vector<double> td;
    const int start = options.decimation > 1
                          ? DecimateFirstIndex(static_cast<int>(n), options.decimation)
                          : 0;
    for (std::size_t i = static_cast<std::size_t>(start); i < n;
         i += static_cast<std::size_t>(std::max(1, options.decimation)))
      td.push_back(recording.t[i]);
    if (model.keep_rows) {
      const std::vector<bool> keep = model.keep_rows(xd, s);
      Eigen::Index kept = 0;
      for (Eigen::Index i = 0; i < rows; ++i) {
        if (!keep[static_cast<std::size_t>(i)]) continue;
        xd.row(kept) = xd.row(i);
        yd(kept) = yd(i);
        td[static_cast<std::size_t>(kept)] = td[static_cast<std::size_t>(i)];
        ++kept;
      }
      xd.conservativeResize(kept, Eigen::NoChange);
      yd.conservativeResize(kept);
      td.resize(static_cast<std::size_t>(kept));
    }
    blocks.push_back(xd.leftCols(p));
    ys.push_back(yd);
    ts.push_back(td);
    out.joint_of_row.insert(out.joint_of_row.end(), static_cast<std::size_t>(xd.rows()),
                            static_cast<int>(j));
  }
  Eigen::Index total = 0;
  for (const auto& b : blocks) total += b.rows();
  out.x.resize(total, p);
  out.y.resize(total);
  Eigen::Index at = 0;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    out.x.middleRows(at, blocks[b].rows()) = blocks[b];
    out.y.segment(at, blocks[b].rows()) = ys[b];
    out.t.insert(out.t.end(), ts[b].begin(), ts[b].end());
    at += blocks[b].rows();
  }
  return out;
}

void Append(Regression& to, const Regression& from) {
  if (to.x.rows() == 0) {
    to = from;
    return;
  }
  const Eigen::Index n0 = to.x.rows();
  to.x.conservativeResize(n0 + from.x.rows(), Eigen::NoChange);
  to.x.bottomRows(from.x.rows()) = from.x;
  to.y.conservativeResize(n0 + from.y.rows());
  to.y.tail(from.y.rows()) = from.y;
  to.joint_of_row.insert(to.joint_of_row.end(), from.joint_of_row.begin(), from.joint_of_row.end());
  to.t.insert(to.t.end(), from.t.begin(), from.t.end());
}

namespace {

LsFit SolveWeighted(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) {
  LsFit fit;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(x, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& s = svd.singularValues();
  fit.theta = svd.solve(y);
  fit.condition_number = s(0) / s(s.size() - 1);
  const Eigen::VectorXd e = y - x * fit.theta;
  const auto n = static_cast<double>(e.size());
  const double mean = e.mean();
  fit.error_std = std::sqrt((e.array() - mean).square().sum() / (n - 1.0));
  const Eigen::MatrixXd vs = svd.matrixV() * s.cwiseInverse().asDiagonal();
  fit.sigma = fit.error_std * vs.rowwise().norm();  // sqrt(diag(V S^-2 V^T))
  fit.rows = static_cast<int>(e.size());
  return fit;
}

}  // namespace

LsFit SolveLeastSquares(const Regression& regression, int joints) {
  if (regression.x.rows() <= regression.x.cols())
    throw std::invalid_argument("least squares: " + std::to_string(regression.x.rows()) +
                                " rows for " + std::to_string(regression.x.cols()) +
                                " parameters");
  LsFit fit = SolveWeighted(regression.x, regression.y);
  if (joints > 1) {
    Eigen::VectorXd e = regression.y - regression.x * fit.theta;
    std::vector<double> ss(static_cast<std::size_t>(joints), 0.0), count(ss.size(), 0.0);
    for (Eigen::Index i = 0; i < e.size(); ++i) {
      const auto j = static_cast<std::size_t>(regression.joint_of_row[static_cast<std::size_t>(i)]);
      ss[j] += e(i) * e(i);
      count[j] += 1.0;
    }
    Eigen::VectorXd w(e.size());
    for (Eigen::Index i = 0; i < e.size(); ++i) {
      const auto j = static_cast<std::size_t>(regression.joint_of_row[static_cast<std::size_t>(i)]);
      w(i) = 1.0 / std::sqrt(std::max(ss[j] / std::max(count[j], 1.0), 1e-300));
    }
    fit = SolveWeighted(w.asDiagonal() * regression.x, w.asDiagonal() * regression.y);
  }
  fit.residual = regression.y - regression.x * fit.theta;
  fit.error_norm = fit.residual.norm();
  fit.relative_error_pct = 100.0 * fit.error_norm / regression.y.norm();
  return fit;
}

double RelativeErrorPct(const Regression& regression, const Eigen::VectorXd& theta) {
  return 100.0 * (regression.y - regression.x * theta).norm() / regression.y.norm();
}

PlatformFit IdentifyPlatform(const std::vector<AxisRecording>& recordings,
                             const std::vector<AxisRecording>& validate,
                             const std::string& model_name, const IdimOptions& options) {
  if (recordings.empty()) throw std::invalid_argument("identify: no recording given");
  PlatformFit fit;
  bool first = true;
  for (const AxisRecording& r : recordings) {
    const ProcessedRecording p = Preprocess(r, options);
    if (first) {
      fit.model = ModelByName(model_name, p, r.experiment, options);
      for (const JointStates& s : p.joints) {
        fit.joints.push_back(s.name);
        fit.joint_kinds.push_back(s.kind);
      }
      first = false;
    } else {
      if (p.joints.size() != fit.joints.size())
        throw std::invalid_argument(r.file.string() + ": expected the joints of the first recording");
      for (const std::string& name : fit.joints) (void)JointIndex(p, name);
    }
    Append(fit.regression, BuildRegression(p, fit.model, options));
  }
  fit.ls = SolveLeastSquares(fit.regression, static_cast<int>(fit.joints.size()));
  for (const AxisRecording& r : validate) {
    const ProcessedRecording p = Preprocess(r, options);
    if (p.joints.size() != fit.joints.size())
      throw std::invalid_argument(r.file.string() + ": expected the joints of the identification");
    for (const std::string& name : fit.joints) (void)JointIndex(p, name);
    Regression reg = BuildRegression(p, fit.model, options);
    ValidationResult v;
    v.recording = r.file.filename().string();
    v.relative_error_pct = RelativeErrorPct(reg, fit.ls.theta);
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(reg.x);
    v.condition_number = svd.singularValues()(0) /
                         svd.singularValues()(svd.singularValues().size() - 1);
    v.rows = static_cast<int>(reg.x.rows());
    fit.validation.push_back(v);
    fit.validation_regressions.push_back(std::move(reg));
  }
  return fit;
}

}  // namespace pwsim::sysid::platform
