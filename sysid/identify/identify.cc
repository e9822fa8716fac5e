#include "sysid/identify/identify.h"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "engine/check.h"
#include "sysid/identify/fitness.h"
#include "engine/input_error.h"
#include "engine/interpolate.h"
#include "engine/lumped_model.h"

namespace pwsim {

const char* RoleName(TrialRole role) {
  switch (role) {
    case TrialRole::kGeometric: return "gm";
    case TrialRole::kLumped: return "lm";
    case TrialRole::kValidation: return "validation";
  }
  return "validation";
}

std::vector<TrialRole> AssignRoles(const std::vector<MeasuredTrial>& trials,
                                   const RoleOptions& options) {
  std::vector<TrialRole> roles(trials.size(), TrialRole::kValidation);
  if (trials.empty()) return roles;
  std::vector<double> speeds;
  for (const MeasuredTrial& trial : trials) speeds.push_back(trial.NominalSpeed());
  // Speed levels: clusters of speeds closer than the tolerance.
  std::vector<double> sorted = speeds;
  std::sort(sorted.begin(), sorted.end());
  std::vector<double> levels{sorted.front()};
  for (double s : sorted) {
    if (s - levels.back() > options.speed_tolerance) levels.push_back(s);
  }
  auto level_of = [&](double s) {
    std::size_t best = 0;
    for (std::size_t l = 0; l < levels.size(); ++l) {
      if (std::abs(s - levels[l]) < std::abs(s - levels[best])) best = l;
    }
    return best;
  };
  const std::size_t top = levels.size() - 1;
  int non_gm = 0;
  for (std::size_t k = 0; k < trials.size(); ++k) {
    const std::size_t level = level_of(speeds[k]);
    if (level == 0 && levels.size() > 1) {
      roles[k] = TrialRole::kGeometric;
    } else if (levels.size() > 2) {
      roles[k] = level == top ? TrialRole::kLumped : TrialRole::kValidation;
    } else {
      // One or two levels: hold out every n-th trial of the faster level.
      ++non_gm;
      const bool held_out = options.holdout_every > 0 && non_gm % options.holdout_every == 0;
      roles[k] = held_out ? TrialRole::kValidation : TrialRole::kLumped;
    }
  }
  return roles;
}

namespace {

/// Number of samples in the initial centring window (at least one).
std::size_t WindowCount(std::span<const double> t, double window) {
  std::size_t count = 1;
  while (count < t.size() && t[count] - t.front() <= window) ++count;
  return count;
}

void CheckSameWheels(const std::vector<const MeasuredTrial*>& trials, const Chair& chair) {
  for (const MeasuredTrial* trial : trials) {
    bool same = trial->chair.wheels.size() == chair.wheels.size();
    for (std::size_t i = 0; same && i < chair.wheels.size(); ++i) {
      same = std::abs(trial->chair.wheels[i].x - chair.wheels[i].x) < 1e-9;
    }
    if (!same) {
      throw InputError(trial->chair_file.string(), 0, "wheels",
                       "the same wheels as the other trials' chair (" +
                           std::to_string(chair.wheels.size()) + " wheels at the same x_m)",
                       std::to_string(trial->chair.wheels.size()) + " wheels");
    }
  }
}

std::vector<std::pair<int, int>> FittedPairs(const Chair& chair, bool all_pairs) {
  std::vector<std::pair<int, int>> pairs;
  const int n = chair.wheel_count();
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      if (all_pairs || j == i + 1) pairs.emplace_back(i, j);
    }
  }
  return pairs;
}

/// One LM axis of one trial, ready for simulation.
struct AxisData {
  std::vector<double> input;  ///< GM output on the grid
  double t0{0.0};
  double dt{1e-3};
  std::span<const double> t;
  std::vector<double> y;      ///< measured (raw)
  double inertia{1.0};        ///< this trial's M or J
  double reference_inertia{1.0};
  std::size_t window{1};
  double weight{1.0};
};

/// K, C of an axis from the search vector p (log-parametrised).
inline void Unpack(bool shared, const double* p, double reference_inertia, double& k, double& c) {
  if (!shared) {
    k = std::exp(p[0]);
    c = std::exp(p[1]);
    return;
  }
  const double omega = std::exp(p[0]);
  const double zeta = std::exp(p[1]);
  k = omega * omega * reference_inertia;
  c = 2.0 * zeta * omega * reference_inertia;
}

/// Centred simulation error of one axis of one trial, weighted.
void AxisResiduals(const AxisData& data, double k, double c, double* residuals) {
  const std::vector<double> model =
      SimulateAxisOnGrid(data.inertia, c, k, data.input, data.t0, data.dt, data.t);
  double offset = 0.0;
  for (std::size_t s = 0; s < data.window; ++s) offset += data.y[s] - model[s];
  offset /= static_cast<double>(data.window);
  for (std::size_t s = 0; s < model.size(); ++s) {
    residuals[s] = data.weight * (data.y[s] - offset - model[s]);
  }
}

struct AxisCost {
  const AxisData* data;
  bool shared;
  bool operator()(const double* p, double* residuals) const {
    double k = 0.0;
    double c = 0.0;
    Unpack(shared, p, data->reference_inertia, k, c);
    if (!std::isfinite(k) || !std::isfinite(c) || k <= 0.0 || c <= 0.0) return false;
    AxisResiduals(*data, k, c, residuals);
    return true;
  }
};

double Mean(const std::vector<double>& values) {
  double sum = 0.0;
  for (double v : values) sum += v;
  return sum / static_cast<double>(values.size());
}

struct PreparedLumped {
  std::vector<AxisData> heave;
  std::vector<AxisData> pitch;
};

PreparedLumped PrepareLumped(const std::vector<const MeasuredTrial*>& trials, const Chair& chair,
                             const IdentifyOptions& options, double reference_load_kg) {
  PreparedLumped prepared;
  double dev_z = 0.0;
  double dev_pitch = 0.0;
  std::size_t samples = 0;
  for (const MeasuredTrial* trial : trials) {
    const GeometricTrace trace = TraceGeometricModel(chair, trial->terrain, trial->track.t, trial->track.x,
                                                     options.simulation, trial->contact_height_scale);
    const std::size_t window = WindowCount(trial->track.t, options.offset_window);
    AxisData heave{trace.z_gm, trace.t0, trace.dt, trial->track.t, trial->track.z,
                   MovingMass(chair, trial->load_kg), MovingMass(chair, reference_load_kg),
                   window, 1.0};
    AxisData pitch{trace.pitch_gm, trace.t0, trace.dt, trial->track.t, trial->track.pitch,
                   PitchInertia(chair, trial->load_kg), PitchInertia(chair, reference_load_kg),
                   window, 1.0};
    const double mz = Mean(heave.y);
    const double mp = Mean(pitch.y);
    for (double v : heave.y) dev_z += (v - mz) * (v - mz);
    for (double v : pitch.y) dev_pitch += (v - mp) * (v - mp);
    samples += heave.y.size();
    prepared.heave.push_back(std::move(heave));
    prepared.pitch.push_back(std::move(pitch));
  }
  const double rms_z = std::sqrt(dev_z / static_cast<double>(std::max<std::size_t>(samples, 1)));
  const double rms_p =
      std::sqrt(dev_pitch / static_cast<double>(std::max<std::size_t>(samples, 1)));
  if (!(rms_z > 0.0) || !(rms_p > 0.0)) {
    throw InputError(trials.front()->trial_file.string(), 0, "(lm trials)",
                     "trials whose measured Z and pitch vary (an obstacle on the path)",
                     "constant signals");
  }
  for (AxisData& d : prepared.heave) d.weight = 1.0 / rms_z;
  for (AxisData& d : prepared.pitch) d.weight = 1.0 / rms_p;
  return prepared;
}

/// Linear interpolation of samples (t, y) at the grid times t0 + k dt, k < n.
std::vector<double> ToGrid(std::span<const double> t, std::span<const double> y, double t0,
                           double dt, std::size_t n) {
  std::vector<double> grid(n);
  std::size_t seg = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double time = t0 + static_cast<double>(k) * dt;
    while (seg + 2 < t.size() && time > t[seg + 1]) ++seg;
    const double s = std::clamp((time - t[seg]) / (t[seg + 1] - t[seg]), 0.0, 1.0);
    grid[k] = y[seg] + s * (y[seg + 1] - y[seg]);
  }
  return grid;
}

/// State-variable filter F(s) = λ²/(s + λ)² of a grid signal: returns F·v, sF·v, s²F·v,
/// starting at rest at v[0] (semi-implicit Euler on the fine grid).
struct FilteredSignal {
  std::vector<double> d0, d1, d2;
};
FilteredSignal StateVariableFilter(std::span<const double> v, double dt, double lambda) {
  FilteredSignal out;
  out.d0.resize(v.size());
  out.d1.resize(v.size());
  out.d2.resize(v.size());
  double x1 = v[0];
  double x2 = 0.0;
  for (std::size_t k = 0; k < v.size(); ++k) {
    const double x2_rate = lambda * lambda * (v[k] - x1) - 2.0 * lambda * x2;
    out.d0[k] = x1;
    out.d1[k] = x2;
    out.d2[k] = x2_rate;
    x2 += dt * x2_rate;
    x1 += dt * x2;
  }
  return out;
}

/// Equation-error estimate of (K, C) of one axis over several trials with state-variable
/// filtering (the classical continuous-time linear estimate): with e = y - u,
///   I s²F[y] = -C sF[e] - K F[e]
/// where F low-passes the mocap noise before any derivative is taken.
bool LinearAxisEstimate(const std::vector<AxisData>& axes, double& k, double& c) {
  constexpr double kLambda = 2.0 * std::numbers::pi * 8.0;  // [rad/s] filter corner
  Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
  Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
  for (const AxisData& d : axes) {
    const std::vector<double> u = SampleGrid(d.input, d.t0, d.dt, d.t);
    double offset = 0.0;
    for (std::size_t s = 0; s < d.window; ++s) offset += d.y[s] - u[s];
    offset /= static_cast<double>(d.window);
    std::vector<double> y_grid = ToGrid(d.t, d.y, d.t0, d.dt, d.input.size());
    std::vector<double> e_grid(y_grid.size());
    for (std::size_t g = 0; g < y_grid.size(); ++g) {
      y_grid[g] -= offset;
      e_grid[g] = y_grid[g] - d.input[g];
    }
    const FilteredSignal fy = StateVariableFilter(y_grid, d.dt, kLambda);
    const FilteredSignal fe = StateVariableFilter(e_grid, d.dt, kLambda);
    for (std::size_t g = 0; g < y_grid.size(); ++g) {
      const Eigen::Vector2d row(-fe.d1[g], -fe.d0[g]);  // [C, K]
      normal += row * row.transpose();
      rhs += row * (d.inertia * fy.d2[g]);
    }
  }
  const Eigen::Vector2d solution = normal.ldlt().solve(rhs);
  c = solution(0);
  k = solution(1);
  return std::isfinite(k) && std::isfinite(c) && k > 0.0 && c > 0.0;
}

}  // namespace

TrialComparison CompareTrial(const MeasuredTrial& trial, const Chair& chair,
                             const SimulationOptions& simulation, double offset_window) {
  const ModelOutput model = SimulateMeasuredTrial(trial, &chair, simulation);
  TrialComparison out;
  out.t = trial.track.t;
  const double z_offset = InitialOffset(trial.track.t, trial.track.z, model.z, offset_window);
  const double pitch_offset =
      InitialOffset(trial.track.t, trial.track.pitch, model.pitch, offset_window);
  out.z_measured.resize(out.t.size());
  out.pitch_measured.resize(out.t.size());
  for (std::size_t s = 0; s < out.t.size(); ++s) {
    out.z_measured[s] = trial.track.z[s] - z_offset;
    out.pitch_measured[s] = trial.track.pitch[s] - pitch_offset;
  }
  out.z_model = model.z;
  out.pitch_model = model.pitch;
  out.fit_z = FitPercent(out.z_measured, out.z_model);
  out.fit_pitch = FitPercent(out.pitch_measured, out.pitch_model);
  return out;
}

GeometricParams IdentifyGeometric(const std::vector<const MeasuredTrial*>& trials,
                                  const Chair& chair, const IdentifyOptions& options,
                                  const std::optional<LumpedParams>& lm) {
  PWSIM_DEMAND(!trials.empty());
  CheckSameWheels(trials, chair);
  const int n = chair.wheel_count();
  const std::vector<std::pair<int, int>> pairs = FittedPairs(chair, options.all_beta_pairs);
  const int trial_count = static_cast<int>(trials.size());
  std::size_t rows = 0;
  for (const MeasuredTrial* trial : trials) rows += trial->track.size();

  Eigen::MatrixXd a_z = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(rows), n + trial_count);
  Eigen::MatrixXd a_p = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(rows),
                                              static_cast<Eigen::Index>(pairs.size()) + trial_count);
  Eigen::VectorXd y_z(static_cast<Eigen::Index>(rows));
  Eigen::VectorXd y_p(static_cast<Eigen::Index>(rows));
  Eigen::Index row = 0;
  for (int r = 0; r < trial_count; ++r) {
    const MeasuredTrial& trial = *trials[static_cast<std::size_t>(r)];
    const auto& t = trial.track.t;
    const std::vector<std::vector<double>> heights =
        TraceContactHeights(chair, trial.terrain, t, trial.track.x, options.simulation,
                            trial.contact_height_scale);
    const double t0 = t.front();
    const double dt = options.simulation.dt;
    std::optional<LumpedModelParams> filter;
    if (lm) {
      Chair with_lm = chair;
      with_lm.lm = *lm;
      filter = MakeLumpedModelParams(with_lm, trial.load_kg);
    }
    auto regressor = [&](const std::vector<double>& grid, bool heave_axis) {
      if (!filter) return SampleGrid(grid, t0, dt, t);
      const AxisParams& axis = heave_axis ? filter->heave : filter->pitch;
      return SimulateAxisOnGrid(axis.inertia, axis.damping, axis.stiffness, grid, t0, dt, t);
    };
    std::vector<std::vector<double>> z_columns;
    for (int i = 0; i < n; ++i) z_columns.push_back(regressor(heights[static_cast<std::size_t>(i)], true));
    std::vector<std::vector<double>> p_columns;
    for (const auto& [i, j] : pairs) {
      const double inv_dx = 1.0 / (chair.wheels[static_cast<std::size_t>(i)].x -
                                   chair.wheels[static_cast<std::size_t>(j)].x);
      std::vector<double> slope(heights[0].size());
      for (std::size_t k = 0; k < slope.size(); ++k) {
        slope[k] = std::asin(std::clamp(
            (heights[static_cast<std::size_t>(i)][k] - heights[static_cast<std::size_t>(j)][k]) *
                inv_dx,
            -1.0, 1.0));
      }
      p_columns.push_back(regressor(slope, false));
    }
    for (std::size_t s = 0; s < t.size(); ++s, ++row) {
      for (int i = 0; i < n; ++i) a_z(row, i) = z_columns[static_cast<std::size_t>(i)][s];
      a_z(row, n + r) = 1.0;
      for (std::size_t p = 0; p < pairs.size(); ++p) {
        a_p(row, static_cast<Eigen::Index>(p)) = p_columns[p][s];
      }
      a_p(row, static_cast<Eigen::Index>(pairs.size()) + r) = 1.0;
      y_z(row) = trial.track.z[s];
      y_p(row) = trial.track.pitch[s];
    }
  }
  if (options.rigid_heave && n > 1) {
    // α_n = 1 - Σ_{i<n} α_i: the last wheel's column moves to the left-hand side and is taken
    // from the others; its own column is then left out of the regression.
    for (int i = 0; i + 1 < n; ++i) a_z.col(i) -= a_z.col(n - 1);
    y_z -= a_z.col(n - 1);
    Eigen::MatrixXd reduced(a_z.rows(), a_z.cols() - 1);
    reduced << a_z.leftCols(n - 1), a_z.rightCols(trial_count);
    a_z = std::move(reduced);
  }
  const auto qr_z = a_z.colPivHouseholderQr();
  const auto qr_p = a_p.colPivHouseholderQr();
  if (qr_z.rank() < a_z.cols() || qr_p.rank() < a_p.cols()) {
    throw InputError(trials.front()->trial_file.string(), 0, "(gm trials)",
                     "slow trials whose wheels cross an obstacle one after the other "
                     "(the contact heights must be independent regressors)",
                     "a rank-deficient regression");
  }
  const Eigen::VectorXd alpha = qr_z.solve(y_z);
  const Eigen::VectorXd beta = qr_p.solve(y_p);
  GeometricParams params;
  if (options.rigid_heave && n > 1) {
    double rest = 1.0;
    for (int i = 0; i + 1 < n; ++i) {
      params.alpha.push_back(alpha(i));
      rest -= alpha(i);
    }
    params.alpha.push_back(rest);
  } else {
    for (int i = 0; i < n; ++i) params.alpha.push_back(alpha(i));
  }
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      double weight = 0.0;
      for (std::size_t p = 0; p < pairs.size(); ++p) {
        if (pairs[p].first == i && pairs[p].second == j) {
          weight = beta(static_cast<Eigen::Index>(p));
        }
      }
      params.beta.push_back({i, j, weight});
    }
  }
  return params;
}

LinearEstimate EstimateLumpedLinear(const std::vector<const MeasuredTrial*>& trials,
                                    const Chair& chair, const IdentifyOptions& options) {
  PWSIM_DEMAND(!trials.empty() && chair.gm.has_value());
  const PreparedLumped prepared = PrepareLumped(trials, chair, options, 0.0);
  LinearEstimate estimate;
  // Fallback: 3 Hz, ζ = 0.5 at the first trial's load.
  const double omega = 2.0 * std::numbers::pi * 3.0;
  if (!LinearAxisEstimate(prepared.heave, estimate.lm.k_z, estimate.lm.c_z)) {
    const double m = prepared.heave.front().inertia;
    estimate.lm.k_z = omega * omega * m;
    estimate.lm.c_z = omega * m;
    estimate.fallback_z = true;
  }
  if (!LinearAxisEstimate(prepared.pitch, estimate.lm.k_theta, estimate.lm.c_theta)) {
    const double j = prepared.pitch.front().inertia;
    estimate.lm.k_theta = omega * omega * j;
    estimate.lm.c_theta = omega * j;
    estimate.fallback_pitch = true;
  }
  return estimate;
}

LumpedFitResult IdentifyLumped(const std::vector<const MeasuredTrial*>& trials,
                               const Chair& chair, const LumpedParams& start,
                               const IdentifyOptions& options, double reference_load_kg) {
  PWSIM_DEMAND(!trials.empty() && chair.gm.has_value());
  CheckSameWheels(trials, chair);
  const PreparedLumped prepared = PrepareLumped(trials, chair, options, reference_load_kg);

  ceres::Problem problem;
  double heave_p[2];
  double pitch_p[2];
  const bool shared = options.shared_mode;
  if (shared) {
    const double m_ref = MovingMass(chair, reference_load_kg);
    const double omega = std::sqrt(start.k_z / m_ref);
    heave_p[0] = std::log(omega);
    heave_p[1] = std::log(start.c_z / (2.0 * std::sqrt(start.k_z * m_ref)));
  } else {
    heave_p[0] = std::log(start.k_z);
    heave_p[1] = std::log(start.c_z);
    pitch_p[0] = std::log(start.k_theta);
    pitch_p[1] = std::log(start.c_theta);
  }
  auto add = [&](const AxisData& data, double* block) {
    auto* cost = new ceres::NumericDiffCostFunction<AxisCost, ceres::CENTRAL, ceres::DYNAMIC, 2>(
        new AxisCost{&data, shared}, ceres::TAKE_OWNERSHIP, static_cast<int>(data.t.size()));
    problem.AddResidualBlock(cost, nullptr, block);
  };
  for (const AxisData& data : prepared.heave) add(data, heave_p);
  for (const AxisData& data : prepared.pitch) add(data, shared ? heave_p : pitch_p);

  ceres::Solver::Options solver;
  solver.minimizer_type = ceres::TRUST_REGION;
  solver.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  solver.linear_solver_type = ceres::DENSE_QR;
  solver.max_num_iterations = options.max_iterations;
  solver.function_tolerance = 1e-12;
  solver.gradient_tolerance = 1e-14;
  solver.parameter_tolerance = 1e-10;
  solver.num_threads = 1;
  solver.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);

  LumpedFitResult result;
  result.iterations = static_cast<int>(summary.iterations.size());
  result.summary = summary.BriefReport();
  if (shared) {
    Unpack(true, heave_p, MovingMass(chair, reference_load_kg), result.lm.k_z, result.lm.c_z);
    Unpack(true, heave_p, PitchInertia(chair, reference_load_kg), result.lm.k_theta,
           result.lm.c_theta);
  } else {
    Unpack(false, heave_p, 0.0, result.lm.k_z, result.lm.c_z);
    Unpack(false, pitch_p, 0.0, result.lm.k_theta, result.lm.c_theta);
  }
  return result;
}

IdentifyResult IdentifyChair(const std::vector<MeasuredTrial>& trials,
                             const std::vector<TrialRole>& roles,
                             const IdentifyOptions& options) {
  PWSIM_DEMAND(trials.size() == roles.size());
  if (trials.empty()) {
    throw InputError("(command line)", 0, "TRIAL_DIR", "at least one trial folder", "none");
  }
  std::vector<const MeasuredTrial*> gm_trials;
  std::vector<const MeasuredTrial*> lm_trials;
  for (std::size_t k = 0; k < trials.size(); ++k) {
    if (roles[k] == TrialRole::kGeometric) gm_trials.push_back(&trials[k]);
    if (roles[k] == TrialRole::kLumped) lm_trials.push_back(&trials[k]);
  }
  if (gm_trials.empty() || lm_trials.empty()) {
    throw InputError(trials.front().trial_file.string(), 0, "(trials)",
                     "slow trials for the GM and faster trials for the LM (at least two speeds)",
                     std::to_string(gm_trials.size()) + " gm and " +
                         std::to_string(lm_trials.size()) + " lm trials");
  }
  IdentifyResult result;
  result.chair = trials.front().chair;
  result.reference_load_kg = 0.0;
  for (const MeasuredTrial* trial : lm_trials) {
    result.reference_load_kg = std::max(result.reference_load_kg, trial->load_kg);
  }
  if (options.reference_load_kg) result.reference_load_kg = *options.reference_load_kg;

  Chair& chair = result.chair;
  chair.gm = IdentifyGeometric(gm_trials, chair, options);
  result.start = EstimateLumpedLinear(lm_trials, chair, options);
  LumpedFitResult fit =
      IdentifyLumped(lm_trials, chair, result.start.lm, options, result.reference_load_kg);
  result.solver_iterations = fit.iterations;
  for (int pass = 2; pass <= options.passes; ++pass) {
    chair.gm = IdentifyGeometric(gm_trials, chair, options, fit.lm);
    fit = IdentifyLumped(lm_trials, chair, fit.lm, options, result.reference_load_kg);
    result.solver_iterations += fit.iterations;
  }
  chair.lm = fit.lm;
  result.solver_summary = fit.summary;

  PooledFit pooled_z;
  PooledFit pooled_pitch;
  for (std::size_t k = 0; k < trials.size(); ++k) {
    const TrialComparison comparison =
        CompareTrial(trials[k], chair, options.simulation, options.offset_window);
    result.trials.push_back({trials[k].name, roles[k], comparison.fit_z, comparison.fit_pitch});
    if (roles[k] == TrialRole::kValidation) {
      pooled_z.Add(comparison.z_measured, comparison.z_model);
      pooled_pitch.Add(comparison.pitch_measured, comparison.pitch_model);
    }
  }
  result.validation_fit_z = pooled_z.Percent();
  result.validation_fit_pitch = pooled_pitch.Percent();
  return result;
}

}  // namespace pwsim
