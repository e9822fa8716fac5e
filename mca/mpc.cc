#include "mca/mpc.h"

#include <unsupported/Eigen/MatrixFunctions>

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/check.h"

namespace pwsim::mca {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr std::array<const char*, 3> kAxisNames{"x", "y", "z"};
/// Share of each actuator's half-stroke, speed and acceleration kept free in the QP's actuator
/// rows for the error of their linearisation about the solve's pose (header).
constexpr double kActuatorMargin = 0.05;
/// Sequential-QP passes of the offline ceiling (its actuator rows about its own plan).
constexpr int kRelinearisations = 2;

/// Exact zero-order-hold discretisation of ẋ = A x + B u over h: exp([[A, B], [0, 0]] h).
void DiscretizeZoh(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, double h, Eigen::MatrixXd& phi,
                   Eigen::MatrixXd& gamma) {
  const Eigen::Index n = a.rows(), m = b.cols();
  Eigen::MatrixXd aug = Eigen::MatrixXd::Zero(n + m, n + m);
  aug.topLeftCorner(n, n) = a * h;
  aug.topRightCorner(n, m) = b * h;
  const Eigen::MatrixXd e = aug.exp();
  phi = e.topLeftCorner(n, n);
  gamma = e.topRightCorner(n, m);
}

/// Places a single-input filter (ẋ = A x + b·input) at rows/cols [offset, offset + order).
void PlaceFilter(const ContinuousSystem& sys, int offset, Eigen::MatrixXd& a) {
  for (int r = 0; r < sys.order; ++r) {
    for (int c = 0; c < sys.order; ++c) a(offset + r, offset + c) = sys.A(r, c);
  }
}

/// Linear couplings of the platform axes into the head's specific-force deviation f and
/// angular velocity ω (see the header): f_j = Kp p + Ku u, ω_j = Kv v.
struct Couplings {
  Eigen::MatrixXd kp, ku, kv;  // 3 × m each
};

Couplings MakeCouplings(const std::vector<Dof>& axes, const std::array<double, 3>& head) {
  const auto m = static_cast<Eigen::Index>(axes.size());
  Couplings k{Eigen::MatrixXd::Zero(3, m), Eigen::MatrixXd::Zero(3, m), Eigen::MatrixXd::Zero(3, m)};
  const double px = head[0], py = head[1], pz = head[2];
  for (Eigen::Index a = 0; a < m; ++a) {
    switch (axes[static_cast<std::size_t>(a)]) {
      case Dof::kSurge: k.ku(0, a) = 1.0; break;
      case Dof::kSway: k.ku(1, a) = 1.0; break;
      case Dof::kHeave: k.ku(2, a) = 1.0; break;
      case Dof::kRoll:  // ω̇ = (φ̈, 0, 0): ω̇ × p = (0, −φ̈ p_z, φ̈ p_y); gravity g φ along y
        k.kp(1, a) = kGravity;
        k.ku(1, a) = -pz;
        k.ku(2, a) = py;
        k.kv(0, a) = 1.0;
        break;
      case Dof::kPitch:  // ω̇ = (0, −θ̈, 0): ω̇ × p = (−θ̈ p_z, 0, θ̈ p_x); gravity g θ along x
        k.kp(0, a) = kGravity;
        k.ku(0, a) = -pz;
        k.ku(2, a) = px;
        k.kv(1, a) = -1.0;
        break;
      case Dof::kYaw:  // ω̇ = (0, 0, ψ̈): ω̇ × p = (−ψ̈ p_y, ψ̈ p_x, 0)
        k.ku(0, a) = -py;
        k.ku(1, a) = px;
        k.kv(2, a) = 1.0;
        break;
    }
  }
  return k;
}

std::string CheckWeight(const char* name, double w) {
  if (!std::isfinite(w) || w < 0.0) return std::string(name) + " must be finite and >= 0";
  return "";
}

}  // namespace

int MpcParams::BlockCount() const {
  if (!(block > 0.0) || !(horizon > control_period)) return 1;
  return 1 + static_cast<int>(std::ceil((horizon - control_period) / block - 1e-9));
}

std::string MpcParams::Validate() const {
  if (!std::isfinite(control_period) || control_period <= 0.0) return "control_period_s must be > 0";
  if (!std::isfinite(block) || block < control_period) return "block_s must be >= control_period_s";
  if (!std::isfinite(horizon) || horizon < 1.0) return "horizon_s must be >= 1 s";
  if (!whole_trial && BlockCount() > kMpcMaxBlocks) {
    return "horizon_s " + std::to_string(horizon) + " at block_s " + std::to_string(block) + " needs " +
           std::to_string(BlockCount()) + " blocks; the solver meets real time with at most " +
           std::to_string(kMpcMaxBlocks) + " (horizon_s <= " +
           std::to_string(control_period + (kMpcMaxBlocks - 1) * block) + ")";
  }
  for (int j = 0; j < 3; ++j) {
    if (auto s = CheckWeight("weight_otolith", weight_otolith[static_cast<std::size_t>(j)]); !s.empty()) return s;
    if (auto s = CheckWeight("weight_canal", weight_canal[static_cast<std::size_t>(j)]); !s.empty()) return s;
  }
  for (auto [name, w] : {std::pair{"weight_neutral", weight_neutral},
                         std::pair{"weight_neutral_rate", weight_neutral_rate}}) {
    if (auto s = CheckWeight(name, w); !s.empty()) return s;
  }
  if (!std::isfinite(weight_effort) || weight_effort <= 0.0) return "weight_effort must be finite and > 0";
  return "";
}

MpcParams ParseMpcParams(YamlMap& map, const MpcParams& base) {
  MpcParams p = base;
  p.horizon = map.NumberOr("horizon_s", p.horizon, Range::Closed(1.0, 60.0, "s"));
  p.control_period = map.NumberOr("control_period_s", p.control_period, Range::Positive(1.0, "s"));
  p.block = map.NumberOr("block_s", p.block, Range::Positive(10.0, "s"));
  p.preview = map.BoolOr("preview", p.preview);
  p.prediction_decay = map.NumberOr("prediction_decay_s", p.prediction_decay, Range::Closed(0.0, 60.0, "s"));
  const std::string solver = map.ChoiceOr("solver", std::string(QpAlgorithmName(p.solver)),
                                          {"active_set", "bleic", "dense_aul", "dense_ipm"});
  p.solver = solver == "active_set" ? QpAlgorithm::kActiveSet
             : solver == "bleic"    ? QpAlgorithm::kBleic
             : solver == "dense_aul" ? QpAlgorithm::kDenseAul
                                     : QpAlgorithm::kDenseIpm;
  const Range weight = Range::Closed(0.0, 1e9);
  if (map.Has("weights")) {
    YamlMap w = map.Map("weights");
    for (std::size_t j = 0; j < 3; ++j) {
      p.weight_otolith[j] = w.NumberOr(std::string("otolith_") + kAxisNames[j], p.weight_otolith[j], weight);
      p.weight_canal[j] = w.NumberOr(std::string("canal_") + kAxisNames[j], p.weight_canal[j], weight);
    }
    p.weight_neutral = w.NumberOr("neutral", p.weight_neutral, weight);
    p.weight_neutral_rate = w.NumberOr("neutral_rate", p.weight_neutral_rate, weight);
    p.weight_effort = w.NumberOr("effort", p.weight_effort, Range{0.0, 1e9, true, false, ""});
    w.Finish();
  }
  if (const std::string problem = p.Validate(); !problem.empty()) {
    const char* field = problem.rfind("block_s", 0) == 0 ? "block_s"
                        : problem.rfind("control", 0) == 0 ? "control_period_s"
                        : problem.rfind("horizon", 0) == 0 ? "horizon_s"
                                                           : "weights";
    map.Fail(field, "a valid MPC set-up (" + problem + ")", "invalid values");
  }
  return p;
}

MpcModel BuildMpcModel(const MpcParams& params, const VestibularParams& vestibular,
                       const PlatformSpec& platform) {
  PWSIM_DEMAND(params.Validate().empty());
  MpcModel model;
  for (Dof dof : kAllDofs) {
    if (platform.Has(dof)) model.axes.push_back(dof);
  }
  const int m = static_cast<int>(model.axes.size());
  PWSIM_DEMAND(m > 0);
  for (int a = 0; a < m; ++a) {
    const Dof d = model.axes[static_cast<std::size_t>(a)];
    if (d == Dof::kRoll || d == Dof::kPitch) {
      model.tilt_axes.push_back(a);
      model.tilt_brake[d == Dof::kPitch ? 1 : 0] = platform.limits(d).brake_accel();
    }
  }
  const Couplings k = MakeCouplings(model.axes, platform.head_from_pivot);

  // platform model: (p, v) per axis, then the perceived channels the platform can move
  const ContinuousSystem otolith = OtolithSystem(vestibular.otolith);
  std::array<ContinuousSystem, 3> canal{};
  for (int j = 0; j < 3; ++j) canal[static_cast<std::size_t>(j)] = CanalSystem(vestibular.canals, j);
  PWSIM_DEMAND(otolith.d == 0.0);
  std::array<int, 6> offset{};  // state offset of channel c (0..2 otolith, 3..5 canal), -1 = absent
  int nx = 2 * m;
  for (int c = 0; c < 6; ++c) {
    const bool moved = c < 3 ? (k.kp.row(c).cwiseAbs().sum() + k.ku.row(c).cwiseAbs().sum() > 0.0)
                             : k.kv.row(c - 3).cwiseAbs().sum() > 0.0;
    offset[static_cast<std::size_t>(c)] = moved ? nx : -1;
    if (moved) nx += c < 3 ? otolith.order : canal[static_cast<std::size_t>(c - 3)].order;
  }
  model.nx = nx;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(nx, nx);
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(nx, m);
  Eigen::MatrixXd c_out = Eigen::MatrixXd::Zero(6, nx);  // perceived outputs of the platform
  for (int i = 0; i < m; ++i) {
    a(2 * i, 2 * i + 1) = 1.0;
    b(2 * i + 1, i) = 1.0;
  }
  for (int c = 0; c < 6; ++c) {
    const int off = offset[static_cast<std::size_t>(c)];
    if (off < 0) continue;
    const ContinuousSystem& sys = c < 3 ? otolith : canal[static_cast<std::size_t>(c - 3)];
    PWSIM_DEMAND(sys.d == 0.0);
    PlaceFilter(sys, off, a);
    for (int r = 0; r < sys.order; ++r) {
      const double br = sys.b[static_cast<std::size_t>(r)];
      c_out(c, off + r) = sys.c[static_cast<std::size_t>(r)];
      for (int i = 0; i < m; ++i) {
        if (c < 3) {
          a(off + r, 2 * i) += br * k.kp(c, i);
          b(off + r, i) += br * k.ku(c, i);
        } else {
          a(off + r, 2 * i + 1) += br * k.kv(c - 3, i);
        }
      }
    }
  }

  // vehicle perceived model: 6 inputs (f_x, f_y, f_z, ω_x, ω_y, ω_z), 3 otolith + 3 canal filters
  const int nv = 3 * otolith.order + canal[0].order + canal[1].order + canal[2].order;
  Eigen::MatrixXd av = Eigen::MatrixXd::Zero(nv, nv), bv = Eigen::MatrixXd::Zero(nv, 6);
  model.vc = Eigen::MatrixXd::Zero(6, nv);
  for (int c = 0, off = 0; c < 6; ++c) {
    const ContinuousSystem& sys = c < 3 ? otolith : canal[static_cast<std::size_t>(c - 3)];
    PlaceFilter(sys, off, av);
    for (int r = 0; r < sys.order; ++r) {
      bv(off + r, c) = sys.b[static_cast<std::size_t>(r)];
      model.vc(c, off + r) = sys.c[static_cast<std::size_t>(r)];
    }
    off += sys.order;
  }

  // blocks
  const int n_blocks = params.BlockCount();
  model.blocks = n_blocks;
  model.block_length.assign(static_cast<std::size_t>(n_blocks), params.block);
  model.block_length[0] = params.control_period;
  double horizon = 0.0;
  for (double h : model.block_length) horizon += h;
  Eigen::MatrixXd phi_block, gamma_block;
  DiscretizeZoh(a, b, params.control_period, model.phi_period, model.gamma_period);
  DiscretizeZoh(a, b, params.block, phi_block, gamma_block);
  DiscretizeZoh(av, bv, params.control_period, model.vphi_period, model.vgamma_period);
  Eigen::MatrixXd vphi_block, vgamma_block;
  DiscretizeZoh(av, bv, params.block, vphi_block, vgamma_block);
  for (int kb = 0; kb < n_blocks; ++kb) {
    model.vphi.push_back(kb == 0 ? model.vphi_period : vphi_block);
    model.vgamma.push_back(kb == 0 ? model.vgamma_period : vgamma_block);
  }

  const int n_tilt = static_cast<int>(model.tilt_axes.size());
  model.nz = m * n_blocks;
  const int nz = model.nz;

  // scales and limits per axis: an independent stage's 1-D limits (its actuator's stroke about
  // its centre, speed, peak and sustained acceleration), or, on the coupled group's axes, Â and
  // V̂ of mca/actuator_limiter.h (the limits then come as actuator rows, filled per solve)
  const ActuatorLimiter mechanism(platform, params.control_period);
  const auto ms = static_cast<std::size_t>(m);
  std::vector<double> travel(ms), centre(ms), pose_scale(ms), speed(ms), accel(ms), peak(ms), brake_c(ms);
  std::vector<bool> coupled(ms);
  for (int i = 0; i < m; ++i) {
    const Dof dof = model.axes[static_cast<std::size_t>(i)];
    const auto s = static_cast<std::size_t>(i);
    const DofLimits& box = platform.limits(dof);
    pose_scale[s] = std::isfinite(box.travel) ? box.travel : kPi;
    coupled[s] = mechanism.coupled(dof);
    if (coupled[s]) {
      accel[s] = mechanism.axis_accel(dof);
      peak[s] = kInf;
      speed[s] = mechanism.axis_speed(dof);
      travel[s] = kInf;
      continue;
    }
    DofLimits stage;
    double mid = 0.0;
    PWSIM_DEMAND(mechanism.StageLimits(dof, &stage, &mid));
    accel[s] = stage.brake_accel();
    peak[s] = stage.accel;
    travel[s] = stage.travel;
    centre[s] = mid;
    speed[s] = std::isfinite(stage.travel) ? std::min(stage.speed, std::sqrt(accel[s] * stage.travel)) : stage.speed;
    brake_c[s] = speed[s] / accel[s];
  }
  double longest_block = 0.0;
  for (double h : model.block_length) longest_block = std::max(longest_block, h);
  model.envelope_c = std::max(mechanism.longest_brake(), 0.5 * longest_block);
  model.actuator_margin = kActuatorMargin;
  model.coupled_actuators = mechanism.coupled_actuators();
  model.axis_pos_c.resize(n_blocks * m, nz);
  model.axis_vel_c.resize(n_blocks * m, nz);
  model.axis_pos_dx.resize(n_blocks * m, nx);
  model.axis_vel_dx.resize(n_blocks * m, nx);

  // condensed prediction: x_k = M_k x0 + L_k z
  std::vector<Eigen::MatrixXd> cost_rows_e, cost_rows_fx;
  Eigen::MatrixXd mk = Eigen::MatrixXd::Identity(nx, nx);
  Eigen::MatrixXd lk = Eigen::MatrixXd::Zero(nx, nz);
  std::vector<Eigen::RowVectorXd> e_rows, fx_rows, c_rows, dx_rows;
  std::vector<double> lo, hi;
  auto add_cost = [&](const Eigen::RowVectorXd& e, const Eigen::RowVectorXd& fx) {
    e_rows.push_back(e);
    fx_rows.push_back(fx);
    return static_cast<int>(e_rows.size()) - 1;
  };
  auto add_con = [&](const Eigen::RowVectorXd& row, const Eigen::RowVectorXd& dx, double l, double h, int tilt_block,
                     int channel) {
    c_rows.push_back(row);
    dx_rows.push_back(dx);
    lo.push_back(l);
    hi.push_back(h);
    model.con_tilt_block.push_back(tilt_block);
    model.con_tilt_channel.push_back(channel);
  };
  const Eigen::RowVectorXd zero_x = Eigen::RowVectorXd::Zero(nx);
  for (int kb = 0; kb < n_blocks; ++kb) {
    const Eigen::MatrixXd& phi = kb == 0 ? model.phi_period : phi_block;
    const Eigen::MatrixXd& gamma = kb == 0 ? model.gamma_period : gamma_block;
    mk = phi * mk;
    lk = phi * lk;
    lk.block(0, kb * m, nx, m) += gamma;
    const double wt = model.block_length[static_cast<std::size_t>(kb)] / horizon;
    // perceived difference
    for (int c = 0; c < 6; ++c) {
      const double w = c < 3 ? params.weight_otolith[static_cast<std::size_t>(c)]
                             : params.weight_canal[static_cast<std::size_t>(c - 3)];
      const double threshold = c < 3 ? vestibular.thresholds.fs[static_cast<std::size_t>(c)]
                                     : vestibular.thresholds.w[static_cast<std::size_t>(c - 3)];
      if (w == 0.0) continue;
      const double scale = std::sqrt(w * wt) / threshold;
      const int row = add_cost(scale * c_out.row(c) * lk, scale * c_out.row(c) * mk);
      model.ref_row.push_back(row);
      model.ref_block.push_back(kb);
      model.ref_channel.push_back(c);
      model.ref_scale.push_back(scale);
    }
    for (int i = 0; i < m; ++i) {
      const auto s = static_cast<std::size_t>(i);
      const double sn = std::sqrt(params.weight_neutral * wt) / pose_scale[s];
      if (sn > 0.0) {
        const int row = add_cost(sn * lk.row(2 * i), sn * mk.row(2 * i));
        const Dof dof = model.axes[s];
        if (dof == Dof::kRoll || dof == Dof::kPitch) {  // neutral is the bank (MpcCueing::Solve)
          model.bank_row.push_back(row);
          model.bank_channel.push_back(dof == Dof::kPitch ? 1 : 0);
          model.bank_scale.push_back(sn);
        }
      }
      const double sr = std::sqrt(params.weight_neutral_rate * wt) / speed[s];
      if (sr > 0.0) add_cost(sr * lk.row(2 * i + 1), sr * mk.row(2 * i + 1));
      Eigen::RowVectorXd effort = Eigen::RowVectorXd::Zero(nz);
      effort(kb * m + i) = std::sqrt(params.weight_effort * wt) / accel[s];
      add_cost(effort, zero_x);
      model.axis_pos_c.row(kb * m + i) = lk.row(2 * i);
      model.axis_vel_c.row(kb * m + i) = lk.row(2 * i + 1);
      model.axis_pos_dx.row(kb * m + i) = mk.row(2 * i);
      model.axis_vel_dx.row(kb * m + i) = mk.row(2 * i + 1);
      if (coupled[s]) continue;
      // an independent stage's constraints at the block's end
      add_con(lk.row(2 * i + 1), mk.row(2 * i + 1), -speed[s], speed[s], -1, 0);
      if (std::isfinite(travel[s])) {
        const double end_lo = centre[s] - travel[s], end_hi = centre[s] + travel[s];
        add_con(lk.row(2 * i), mk.row(2 * i), end_lo, end_hi, -1, 0);
        add_con(lk.row(2 * i) + brake_c[s] * lk.row(2 * i + 1), mk.row(2 * i) + brake_c[s] * mk.row(2 * i + 1),
                end_lo, end_hi, -1, 0);
      }
    }
    // the coupled group's actuator rows at the block's end (placeholders, filled per solve)
    const Eigen::RowVectorXd zero_z = Eigen::RowVectorXd::Zero(nz);
    for (int actuator : model.coupled_actuators) {
      for (const MpcModel::ActuatorRowKind kind :
           {MpcModel::ActuatorRowKind::kStroke, MpcModel::ActuatorRowKind::kEnvelope,
            MpcModel::ActuatorRowKind::kSpeed, MpcModel::ActuatorRowKind::kAccel}) {
        model.actuator_rows.push_back({static_cast<int>(c_rows.size()), actuator, kb, kind});
        add_con(zero_z, zero_x, 0.0, 0.0, -1, 0);
      }
    }
    for (int t = 0; t < n_tilt; ++t) {
      const int i = model.tilt_axes[static_cast<std::size_t>(t)];
      const bool pitch = model.axes[static_cast<std::size_t>(i)] == Dof::kPitch;
      const int channel = pitch ? 1 : 0;  // vehicle rate: roll w_x, pitch nose-up −w_y
      const double thr = vestibular.thresholds.tilt_rate;
      add_con(lk.row(2 * i + 1), mk.row(2 * i + 1), -thr, thr, kb, channel);  // the tilt band, hard
    }
  }
  const auto rows = static_cast<Eigen::Index>(e_rows.size());
  model.cost_e.resize(rows, nz);
  model.cost_fx.resize(rows, nx);
  for (Eigen::Index r = 0; r < rows; ++r) {
    model.cost_e.row(r) = e_rows[static_cast<std::size_t>(r)];
    model.cost_fx.row(r) = fx_rows[static_cast<std::size_t>(r)];
  }
  model.cost_et = model.cost_e.transpose();
  model.hessian = model.cost_et * model.cost_e;
  const auto n_con = static_cast<Eigen::Index>(c_rows.size());
  model.con_c.resize(n_con, nz);
  model.con_dx.resize(n_con, nx);
  model.con_lo.resize(n_con);
  model.con_hi.resize(n_con);
  for (Eigen::Index r = 0; r < n_con; ++r) {
    const auto s = static_cast<std::size_t>(r);
    model.con_c.row(r) = c_rows[s];
    model.con_dx.row(r) = dx_rows[s];
    model.con_lo[r] = lo[s];
    model.con_hi[r] = hi[s];
  }
  model.axis_pos_c_rows = model.axis_pos_c;
  model.axis_vel_c_rows = model.axis_vel_c;
  model.axis_pos_dx_rows = model.axis_pos_dx;
  model.axis_vel_dx_rows = model.axis_vel_dx;
  model.z_lo.resize(nz);
  model.z_hi.resize(nz);
  for (int kb = 0; kb < n_blocks; ++kb) {
    for (int i = 0; i < m; ++i) {
      model.z_lo[kb * m + i] = -peak[static_cast<std::size_t>(i)];  // coupled axes: the actuator rows
      model.z_hi[kb * m + i] = peak[static_cast<std::size_t>(i)];
    }
  }
  return model;
}

MpcCueing::MpcCueing(const MpcParams& params, const WashoutParams& washout,
                     const VestibularParams& vestibular, const PlatformSpec& platform, double dt)
    : params_(params),
      vestibular_(vestibular),
      platform_(platform),
      dt_(dt),
      period_ticks_(static_cast<int>(std::lround(params.control_period / dt))),
      model_(BuildMpcModel(params, vestibular, platform)),
      washout_(washout, platform, dt),
      limiter_(platform, dt, TiltGuards(platform, vestibular.thresholds.tilt_rate)) {
  PWSIM_DEMAND(dt > 0.0);
  PWSIM_DEMAND(period_ticks_ >= 1 && std::abs(period_ticks_ * dt - params.control_period) < 1e-9);
  const Eigen::MatrixXd hessian = model_.hessian + 1e-10 * Eigen::MatrixXd::Identity(model_.nz, model_.nz);
  if (params.solver == QpAlgorithm::kActiveSet) {
    active_set_ = std::make_unique<ActiveSetQp>(hessian, model_.con_c);
  } else {
    alglib_ = std::make_unique<AlglibQp>(params.solver, hessian, model_.con_c);
  }
  con_c_ = model_.con_c;
  con_dx_ = model_.con_dx;
  row_c_.resize(1, model_.nz);
  row_dx_.resize(1, model_.nx);
  con_lo_ = model_.con_lo;
  con_hi_ = model_.con_hi;
  jacobian_.resize(platform.mechanism.actuator_count(), 6);
  for (double h : model_.block_length) block_ticks_.push_back(static_cast<int>(std::lround(h / dt)));
  predicted_.resize(6, model_.blocks);
  ref_.resize(6, model_.blocks);
  rate_ref_.resize(2, model_.blocks);
  e_.resize(model_.cost_e.rows());
  b_.resize(model_.nz);
  c_lo_.resize(model_.con_c.rows());
  c_hi_.resize(model_.con_c.rows());
  dx_.resize(model_.con_c.rows());
  xv_scratch_.resize(model_.vc.cols());
  xv_next_.resize(model_.vc.cols());
  x_next_.resize(model_.nx);
  for (std::size_t c = 0; c < 2; ++c) band_margin_[c] = 1.5 * model_.tilt_brake[c] * dt;
  Reset();
}

MpcCueing::~MpcCueing() = default;

void MpcCueing::SetPreview(const std::vector<HeadMotion>* trial) { preview_ = trial; }

void MpcCueing::SetPredictor(VehiclePredictor* predictor) { predictor_ = predictor; }

void MpcCueing::Reset() {
  tick_ = 0;
  x_ = Eigen::VectorXd::Zero(model_.nx);
  xv_ = Eigen::VectorXd::Zero(model_.vc.cols());
  z_ = Eigen::VectorXd::Zero(model_.nz);
  u_ = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(model_.axes.size()));
  input_sum_ = {};
  last_input_ = {};
  sustained_ = {};
  limiter_.Reset();
  nominal_pose_ = {};
  nominal_rate_ = {};
  fallback_ = false;
  fault_run_ = 0;
  held_ = HeadMotion{};
  bank_ = {};
  follow_rate_ = {};
  stats_ = MpcStats{};
  command_ = McaCommand{};
  washout_.Reset();
  if (active_set_) active_set_->ResetWarmStart();
}

namespace {

/// The MCA input as the vehicle model's 6 channels: fs − (0, 0, g) and ω.
std::array<double, 6> Channels(const HeadMotion& h) {
  return {h.fs[0], h.fs[1], h.fs[2] - kGravity, h.w[0], h.w[1], h.w[2]};
}

/// The part of the input a vehicle sustains without moving: the gravity at its attitude.
std::array<double, 6> Sustained(const HeadMotion& h) {
  const std::array<double, 3> g = GravityAtAttitude(h.attitude);
  return {g[0], g[1], g[2] - kGravity, 0.0, 0.0, 0.0};
}

bool Finite(const HeadMotion& h) {
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(h.fs[static_cast<std::size_t>(i)]) || !std::isfinite(h.w[static_cast<std::size_t>(i)])) return false;
  }
  return true;
}

}  // namespace

void MpcCueing::PredictVehicle() {
  // per block: the vehicle's mean input (the preview's, the predictor's, or the present input's
  // transients decaying), then its perceived output and the followable roll and pitch rates ω̂_f
  // at the block's end
  xv_scratch_ = xv_;
  std::array<double, 2> follow = follow_rate_;
  const bool preview = using_preview() && !preview_->empty();
  const bool predicted = !preview && predictor_ != nullptr;
  if (predicted) predictor_->Predict(tick_, block_ticks_, predicted_);
  std::int64_t start = tick_;
  double t_start = 0.0;
  for (int kb = 0; kb < model_.blocks; ++kb) {
    const auto len = static_cast<std::int64_t>(block_ticks_[static_cast<std::size_t>(kb)]);
    const double h = model_.block_length[static_cast<std::size_t>(kb)];
    std::array<double, 6> q{};
    if (preview) {
      const auto last = static_cast<std::int64_t>(preview_->size()) - 1;
      for (std::int64_t t = start; t < start + len; ++t) {
        const HeadMotion& motion = (*preview_)[static_cast<std::size_t>(std::min(t, last))];
        if (!Finite(motion)) continue;  // a gap in the trial counts as rest
        const auto ch = Channels(motion);
        for (std::size_t c = 0; c < 6; ++c) q[c] += ch[c];
      }
      for (double& v : q) v /= static_cast<double>(len);
    } else if (predicted) {
      for (std::size_t c = 0; c < 6; ++c) q[c] = predicted_(static_cast<Eigen::Index>(c), kb);
    } else {
      // the block's mean of e^(−t/τ): the present input's departure from its sustained part
      // (the gravity at the present attitude) dies away at τ; τ = 0 holds it
      const double tau = params_.prediction_decay;
      const double share = tau > 0.0 ? tau * (std::exp(-t_start / tau) - std::exp(-(t_start + h) / tau)) / h : 1.0;
      for (std::size_t c = 0; c < 6; ++c) q[c] = sustained_[c] + share * (last_input_[c] - sustained_[c]);
    }
    t_start += h;
    const Eigen::Map<const Eigen::Matrix<double, 6, 1>> qv(q.data());
    xv_next_.noalias() = model_.vphi[static_cast<std::size_t>(kb)] * xv_scratch_;
    xv_next_.noalias() += model_.vgamma[static_cast<std::size_t>(kb)] * qv;
    xv_scratch_.swap(xv_next_);
    ref_.col(kb).noalias() = model_.vc * xv_scratch_;
    follow[0] = StepFollowRate(follow[0], q[3], model_.tilt_brake[0], h);
    follow[1] = StepFollowRate(follow[1], -q[4], model_.tilt_brake[1], h);
    rate_ref_(0, kb) = follow[0];
    rate_ref_(1, kb) = follow[1];
    start += len;
  }
}

void MpcCueing::FillActuatorRows(const std::vector<DofArray>* about) {
  // q ≈ q0 + J (p − p0) about the platform's pose now (or, `about`, each block's own pose):
  // rows J p (+ c_g J v), J v, J u
  const Mechanism& mechanism = platform_.mechanism;
  const DofArray& now = limiter_.pose();
  const ActuatorVector& q_now = limiter_.position();
  mechanism.Jacobian(now, &jacobian_);
  if (about != nullptr) {  // the offline ceiling only (allocates)
    block_jacobians_.resize(about->size());
    block_positions_.resize(about->size());
    for (std::size_t kb = 0; kb < about->size(); ++kb) {
      mechanism.Jacobian((*about)[kb], &block_jacobians_[kb]);
      block_positions_[kb] = q_now;
      if (!mechanism.Inverse((*about)[kb], &block_positions_[kb])) {
        block_jacobians_[kb] = jacobian_;  // not computable: about the present pose
        block_positions_[kb] = q_now;
      }
    }
  }
  const auto m = static_cast<int>(model_.axes.size());
  const double c = model_.envelope_c;
  const double keep = 1.0 - model_.actuator_margin;
  for (const MpcModel::ActuatorRow& row : model_.actuator_rows) {
    const Eigen::Index r = row.row;
    const int i = row.actuator;
    const auto kb = static_cast<std::size_t>(row.block);
    const bool own = about != nullptr && (*about)[kb] != now;
    const ActuatorJacobian& jac = own ? block_jacobians_[kb] : jacobian_;
    const DofArray& p0 = own ? (*about)[kb] : now;
    const double q0 = own ? block_positions_[kb][i] : q_now[i];
    auto& row_c = row_c_;
    auto& row_dx = row_dx_;
    row_c.setZero();
    row_dx.setZero();
    double jp0 = 0.0, w0 = 0.0;  // J p0, and the actuator's rate now J v0
    for (int a = 0; a < m; ++a) {
      const auto d = static_cast<std::size_t>(Index(model_.axes[static_cast<std::size_t>(a)]));
      const double j = jac(i, static_cast<Eigen::Index>(d));
      jp0 += j * p0[d];
      w0 += jacobian_(i, static_cast<Eigen::Index>(d)) * x_[2 * a + 1];
      if (j == 0.0) continue;
      const Eigen::Index b = row.block * m + a;
      switch (row.kind) {
        case MpcModel::ActuatorRowKind::kStroke:
          row_c += j * model_.axis_pos_c_rows.row(b);
          row_dx += j * model_.axis_pos_dx_rows.row(b);
          break;
        case MpcModel::ActuatorRowKind::kEnvelope:
          row_c += j * model_.axis_pos_c_rows.row(b) + (c * j) * model_.axis_vel_c_rows.row(b);
          row_dx += j * model_.axis_pos_dx_rows.row(b) + (c * j) * model_.axis_vel_dx_rows.row(b);
          break;
        case MpcModel::ActuatorRowKind::kSpeed:
          row_c += j * model_.axis_vel_c_rows.row(b);
          row_dx += j * model_.axis_vel_dx_rows.row(b);
          break;
        case MpcModel::ActuatorRowKind::kAccel:
          row_c(b) = j;
          break;
      }
    }
    con_c_.row(r) = row_c;
    con_dx_.row(r) = row_dx;
    const ActuatorLimits& lim = mechanism.actuator(i).limits;
    switch (row.kind) {
      case MpcModel::ActuatorRowKind::kStroke:
      case MpcModel::ActuatorRowKind::kEnvelope: {
        // the stroke less the margin, in J p; a row the state already stands beyond keeps its
        // present value (braking never makes it grow)
        // (the envelope's present value q0 + c_g w0 also bounds where braking takes q itself)
        const double margin = (1.0 - keep) * 0.5 * (lim.max - lim.min);
        const double envelope = q_now[i] + c * w0;
        const bool stroke = row.kind == MpcModel::ActuatorRowKind::kStroke;
        const double low = stroke ? std::min(q_now[i], envelope) : envelope;
        const double high = stroke ? std::max(q_now[i], envelope) : envelope;
        con_lo_[r] = std::min(lim.min + margin, low) - q0 + jp0;
        con_hi_[r] = std::max(lim.max - margin, high) - q0 + jp0;
        break;
      }
      case MpcModel::ActuatorRowKind::kSpeed:
        con_hi_[r] = std::max(keep * lim.speed, std::abs(w0));
        con_lo_[r] = -con_hi_[r];
        break;
      case MpcModel::ActuatorRowKind::kAccel:
        con_hi_[r] = keep * lim.accel;
        con_lo_[r] = -con_hi_[r];
        break;
    }
  }
  if (active_set_) {
    active_set_->SetConstraintMatrix(con_c_);
  } else {
    alglib_->SetConstraintMatrix(con_c_);
  }
}

void MpcCueing::SetBank(const HeadMotion& input) {
  const BankParams& bank = washout_.params().bank;
  for (std::size_t c = 0; c < 2; ++c) {
    bank_[c] = bank.enabled ? std::clamp(input.attitude[c], -bank.max_angle, bank.max_angle) : 0.0;
  }
}

void MpcCueing::Solve() {
  PredictVehicle();
  // cost: e = Fx x0 − scale ∘ ŷ_veh
  e_.noalias() = model_.cost_fx * x_;
  for (std::size_t r = 0; r < model_.ref_row.size(); ++r) {
    e_[model_.ref_row[r]] -= model_.ref_scale[r] * ref_(model_.ref_channel[r], model_.ref_block[r]);
  }
  for (std::size_t r = 0; r < model_.bank_row.size(); ++r) {  // the neutral pull, about the bank
    e_[model_.bank_row[r]] -= model_.bank_scale[r] * bank_[static_cast<std::size_t>(model_.bank_channel[r])];
  }
  b_.noalias() = model_.cost_et * e_;
  QpStatus status = SolveQp(nullptr);
  // the offline ceiling's one plan spans the trial: its actuator rows linearised about the
  // plan itself, block by block, and solved again (sequential QP)
  for (int pass = 0; params_.whole_trial && !model_.actuator_rows.empty() && status.ok && pass < kRelinearisations;
       ++pass) {
    const auto m = static_cast<int>(model_.axes.size());
    block_poses_.assign(static_cast<std::size_t>(model_.blocks), limiter_.pose());
    for (int kb = 0; kb < model_.blocks; ++kb) {
      for (int a = 0; a < m; ++a) {
        const Eigen::Index b = kb * m + a;
        block_poses_[static_cast<std::size_t>(kb)][static_cast<std::size_t>(Index(model_.axes[static_cast<std::size_t>(a)]))] =
            model_.axis_pos_c.row(b).dot(z_) + model_.axis_pos_dx.row(b).dot(x_);
      }
    }
    status = SolveQp(&block_poses_);
  }
  ++stats_.solves;
  stats_.iterations += status.iterations;
  const auto m = static_cast<Eigen::Index>(model_.axes.size());
  if (status.ok) {
    fallback_ = false;
    u_ = z_.head(m);
  } else {
    fallback_ = true;
    ++stats_.fallbacks;
    u_.setZero();
    z_.setZero();
  }
}

QpStatus MpcCueing::SolveQp(const std::vector<DofArray>* about) {
  if (!model_.actuator_rows.empty()) FillActuatorRows(about);
  dx_.noalias() = con_dx_ * x_;
  for (Eigen::Index r = 0; r < c_lo_.size(); ++r) {
    const auto s = static_cast<std::size_t>(r);
    c_lo_[r] = con_lo_[r] - dx_[r];
    c_hi_[r] = con_hi_[r] - dx_[r];
    if (model_.con_tilt_block[s] >= 0) {  // the tilt band about ω̂_f, widened by μ
      const auto channel = static_cast<std::size_t>(model_.con_tilt_channel[s]);
      const double follow = rate_ref_(model_.con_tilt_channel[s], model_.con_tilt_block[s]);
      c_lo_[r] += std::min(0.0, follow) - band_margin_[channel];
      c_hi_[r] += std::max(0.0, follow) + band_margin_[channel];
    }
  }
  return active_set_ ? active_set_->Solve(b_, model_.z_lo, model_.z_hi, c_lo_, c_hi_, z_)
                     : alglib_->Solve(b_, model_.z_lo, model_.z_hi, c_lo_, c_hi_, z_);
}

bool MpcCueing::StartIsFeasible() {
  Reset();
  Solve();
  const bool ok = !fallback_;
  Reset();
  return ok;
}

const McaCommand& MpcCueing::Step(const HeadMotion& raw) {
  const McaCommand& fallback = washout_.Step(raw);  // kept warm for a failed solve
  // the input this tick: finite, or held for hold_time, then rest
  HeadMotion input = raw;
  command_.fault = !Finite(raw);
  if (command_.fault) {
    ++stats_.fault_ticks;
    ++fault_run_;
    input = static_cast<double>(fault_run_) * dt_ <= washout_.params().fault.hold_time ? held_ : HeadMotion{};
  } else {
    fault_run_ = 0;
    held_ = raw;
  }
  // the vehicle's roll and nose-up pitch rates as the platform can follow them (ω_f)
  follow_rate_[0] = StepFollowRate(follow_rate_[0], input.w[0], model_.tilt_brake[0], dt_);
  follow_rate_[1] = StepFollowRate(follow_rate_[1], -input.w[1], model_.tilt_brake[1], dt_);
  const auto m = static_cast<int>(model_.axes.size());
  if (params_.whole_trial) {
    if (tick_ == 0) {
      last_input_ = Channels(input);
      sustained_ = Sustained(input);
      SetBank(input);
      Solve();
    }
    const auto block = std::min<std::int64_t>(tick_ / period_ticks_, model_.blocks - 1);
    if (!fallback_) u_ = z_.segment(block * m, m);
  } else if (tick_ % period_ticks_ == 0) {
    if (tick_ > 0) {
      // advance the models over the last period: vehicle with its mean input, platform with the
      // accelerations it actually had, then the platform's measured (p, v)
      for (double& v : input_sum_) v /= static_cast<double>(period_ticks_);
      const Eigen::Map<const Eigen::Matrix<double, 6, 1>> q(input_sum_.data());
      xv_next_.noalias() = model_.vphi_period * xv_;
      xv_next_.noalias() += model_.vgamma_period * q;
      xv_.swap(xv_next_);
      for (int i = 0; i < m; ++i) {
        const auto d = static_cast<std::size_t>(Index(model_.axes[static_cast<std::size_t>(i)]));
        u_[i] = (nominal_rate_[d] - x_[2 * i + 1]) / params_.control_period;
      }
      x_next_.noalias() = model_.phi_period * x_;
      x_next_.noalias() += model_.gamma_period * u_;
      x_.swap(x_next_);
      for (int i = 0; i < m; ++i) {
        const auto d = static_cast<std::size_t>(Index(model_.axes[static_cast<std::size_t>(i)]));
        x_[2 * i] = nominal_pose_[d];
        x_[2 * i + 1] = nominal_rate_[d];
      }
      input_sum_ = {};
    }
    last_input_ = Channels(input);
    sustained_ = Sustained(input);
    SetBank(input);
    Solve();
  }
  const auto ch = Channels(input);
  for (std::size_t c = 0; c < 6; ++c) input_sum_[c] += ch[c];

  DofArray target{}, target_rate{};
  for (int i = 0; i < m; ++i) {
    const auto d = static_cast<std::size_t>(Index(model_.axes[static_cast<std::size_t>(i)]));
    if (fallback_) {
      target[d] = fallback.pose[d];
      target_rate[d] = fallback.rate[d];
    } else {
      const double u = u_[i];
      target[d] = nominal_pose_[d] + nominal_rate_[d] * dt_ + 0.5 * u * dt_ * dt_;
      target_rate[d] = (target[d] - nominal_pose_[d]) / dt_;
      nominal_rate_[d] += u * dt_;
    }
  }
  std::array<RateWindow, kDofCount> windows{};
  if (platform_.Has(Dof::kRoll)) windows[Index(Dof::kRoll)] = TiltBand(follow_rate_[0], vestibular_.thresholds.tilt_rate);
  if (platform_.Has(Dof::kPitch)) windows[Index(Dof::kPitch)] = TiltBand(follow_rate_[1], vestibular_.thresholds.tilt_rate);
  limiter_.Step(target, target_rate, windows);
  for (int i = 0; i < m; ++i) {
    const auto d = static_cast<std::size_t>(Index(model_.axes[static_cast<std::size_t>(i)]));
    const double pose = limiter_.pose()[d];
    if (params_.whole_trial && !fallback_) {
      nominal_pose_[d] = target[d];  // the whole trial's plan runs open loop; the limiter closes any gap
    } else {
      if (fallback_ || std::abs(pose - target[d]) > 1e-9 * std::max(1.0, std::abs(target[d]))) {
        nominal_rate_[d] = limiter_.rate()[d];  // the limiter acted: resynchronise the plan
      }
      nominal_pose_[d] = pose;
    }
    command_.desired[d] = target[d];
    command_.pose[d] = pose;
    command_.rate[d] = limiter_.rate()[d];
    command_.accel[d] = limiter_.accel()[d];
  }
  // what is not the vehicle's own attitude is tilt (not to be shown); the bank is the attitude
  // the platform is centred on
  command_.tilt_pitch = platform_.Has(Dof::kPitch) ? command_.pose[Index(Dof::kPitch)] - input.attitude[1] : 0.0;
  command_.tilt_roll = platform_.Has(Dof::kRoll) ? command_.pose[Index(Dof::kRoll)] - input.attitude[0] : 0.0;
  command_.bank_pitch = platform_.Has(Dof::kPitch) ? bank_[1] : 0.0;
  command_.bank_roll = platform_.Has(Dof::kRoll) ? bank_[0] : 0.0;
  command_.tilt_rate_pitch =
      platform_.Has(Dof::kPitch) ? TiltCoordinationRate(command_.rate[Index(Dof::kPitch)], follow_rate_[1]) : 0.0;
  command_.tilt_rate_roll =
      platform_.Has(Dof::kRoll) ? TiltCoordinationRate(command_.rate[Index(Dof::kRoll)], follow_rate_[0]) : 0.0;
  ++tick_;
  return command_;
}

}  // namespace pwsim::mca
