#include "sysid/platform/axis_diagnose.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <sstream>
#include <stdexcept>

#include "sysid/platform/signal_filters.h"

namespace pwsim::sysid::platform {
namespace {

// One recording (or part of one) ready for regression: full-rate states and decimated rows.
struct Part {
  std::string name;
  const AxisRecording* source{nullptr};
  AxisRecording recording;
  JointStates s;                 // full rate, after the border
  std::vector<double> t;         // full rate
  std::vector<double> q3, q4;    // third and fourth derivatives of the filtered q
  double dt{0.0};
  Eigen::VectorXd y;             // decimated effort
  Eigen::VectorXd qdec, qddec;   // decimated q, q̇ (for screening)
  std::vector<double> tdec;
  std::vector<Eigen::Index> keep;  // decimated rows used (moving)
  Eigen::Index Rows() const { return static_cast<Eigen::Index>(keep.size()); }
};

struct Stroke {
  double q_min{0.0}, q_max{1.0}, v_peak{1.0};
};

Eigen::VectorXd DecimateColumn(const std::vector<double>& v, int r) {
  const std::vector<double> d = Decimate(v, r);
  return Eigen::Map<const Eigen::VectorXd>(d.data(), static_cast<Eigen::Index>(d.size()));
}

Part MakePart(const AxisRecording& r, const std::string& name, const IdimOptions& o) {
  Part p;
  p.name = name;
  p.recording = r;
  const ProcessedRecording pr = Preprocess(r, o);
  p.s = pr.joints.at(0);
  p.t = pr.t;
  p.dt = pr.dt;
  p.q3 = DiffCentral(p.s.qdd, pr.dt);
  p.q4 = DiffCentral(p.q3, pr.dt);
  p.y = DecimateColumn(p.s.tau, o.decimation);
  p.qdec = DecimateColumn(p.s.q, o.decimation);
  p.qddec = DecimateColumn(p.s.qd, o.decimation);
  const int first = DecimateFirstIndex(static_cast<int>(p.t.size()), o.decimation);
  for (std::size_t i = static_cast<std::size_t>(first); i < p.t.size();
       i += static_cast<std::size_t>(o.decimation))
    p.tdec.push_back(p.t[i]);
  return p;
}

// Full-rate columns of the base (or asymmetric) model.
std::vector<std::vector<double>> BaseColumns(const JointStates& s, bool asymmetric) {
  const std::size_t n = s.q.size();
  std::vector<std::vector<double>> c;
  if (!asymmetric) {
    c.assign(4, std::vector<double>(n));
    for (std::size_t i = 0; i < n; ++i) {
      c[0][i] = s.qdd[i];
      c[1][i] = s.qd[i];
      c[2][i] = Sign(s.qd[i]);
      c[3][i] = 1.0;
    }
  } else {
    c.assign(5, std::vector<double>(n));
    for (std::size_t i = 0; i < n; ++i) {
      const double v = s.qd[i];
      c[0][i] = s.qdd[i];
      c[1][i] = v > 0.0 ? v : 0.0;
      c[2][i] = v > 0.0 ? 1.0 : 0.0;
      c[3][i] = v < 0.0 ? v : 0.0;
      c[4][i] = v < 0.0 ? -1.0 : 0.0;
    }
  }
  return c;
}

double Legendre2(double x) { return 1.5 * x * x - 0.5; }


struct Chosen {
  AxisEffect effect{};
  double h{0.0};   // Stribeck speed, cogging period, backlash gap, load natural frequency
  double h2{0.0};  // load damping ratio (compliance)
};

// The load side's position seen through the transmission from the (measured) motor side:
// compliance: q_l = H(s) q_m, H = (2ζω s + ω²)/(s² + 2ζω s + ω²) (load J_l on a spring-damper,
// k/J_l = ω², c/J_l = 2ζω), Tustin at the sampling rate, started in steady state;
// backlash: the play operator q_l = clamp(q_l, q_m − b/2, q_m + b/2) (rigid contact).
std::vector<double> LoadPosition(const Chosen& c, const std::vector<double>& qm, double dt) {
  std::vector<double> ql(qm.size());
  if (c.effect == AxisEffect::kBacklash) {
    double l = qm.empty() ? 0.0 : qm[0];
    for (std::size_t i = 0; i < qm.size(); ++i) {
      l = std::clamp(l, qm[i] - 0.5 * c.h, qm[i] + 0.5 * c.h);
      ql[i] = l;
    }
    return ql;
  }
  const double k = 2.0 / dt, w = c.h, z = c.h2;
  TransferFunction tf;
  tf.b = {2.0 * z * w * k + w * w, 2.0 * w * w, -2.0 * z * w * k + w * w};
  tf.a = {k * k + 2.0 * z * w * k + w * w, -2.0 * k * k + 2.0 * w * w, k * k - 2.0 * z * w * k + w * w};
  std::vector<double> state = SteadyStateInitial(tf);
  for (double& v : state) v *= qm.empty() ? 0.0 : qm[0];
  Filter(tf, qm, ql, state);
  return ql;
}

// Full-rate extra columns of `effect` with its nonlinear parameter(s).
std::vector<std::vector<double>> EffectColumns(const Chosen& chosen, const Part& p,
                                               const Stroke& st) {
  const AxisEffect effect = chosen.effect;
  const double h = chosen.h;
  const JointStates& s = p.s;
  const std::size_t n = s.q.size();
  std::vector<std::vector<double>> c;
  switch (effect) {
    case AxisEffect::kAsymmetricFriction:
      break;  // handled by the base columns
    case AxisEffect::kStribeckFriction: {
      c.assign(1, std::vector<double>(n));
      for (std::size_t i = 0; i < n; ++i) {
        const double r = s.qd[i] / h;
        c[0][i] = Sign(s.qd[i]) * std::exp(-r * r);
      }
      break;
    }
    case AxisEffect::kPositionDependentFriction: {
      c.assign(2, std::vector<double>(n));
      for (std::size_t i = 0; i < n; ++i) {
        const double x = 2.0 * (s.q[i] - st.q_min) / (st.q_max - st.q_min) - 1.0;
        c[0][i] = Sign(s.qd[i]) * x;
        c[1][i] = Sign(s.qd[i]) * Legendre2(x);
      }
      break;
    }
    case AxisEffect::kCogging: {
      c.assign(2, std::vector<double>(n));
      for (std::size_t i = 0; i < n; ++i) {
        const double a = 2.0 * std::numbers::pi * s.q[i] / h;
        c[0][i] = std::sin(a);
        c[1][i] = std::cos(a);
      }
      break;
    }
    case AxisEffect::kCommandDelay:
      break;  // handled by shifting the base columns (Columns)
    case AxisEffect::kTransmissionCompliance:
    case AxisEffect::kBacklash: {
      // τ = J_m q̈_m + J_l q̈_l + f(q̇_l) = (J_m + J_l) q̈_m + J_l (q̈_l − q̈_m) + f(q̇_m)
      //     + [f(q̇_l) − f(q̇_m)]: the base columns plus the load's lag behind the motor.
      const std::vector<double> ql = LoadPosition(chosen, s.q, p.dt);
      const std::vector<double> vl = DiffCentral(ql, p.dt);
      const std::vector<double> al = DiffCentral(vl, p.dt);
      c.assign(3, std::vector<double>(n));
      for (std::size_t i = 0; i < n; ++i) {
        c[0][i] = al[i] - s.qdd[i];
        c[1][i] = vl[i] - s.qd[i];
        c[2][i] = Sign(vl[i]) - Sign(s.qd[i]);
      }
      break;
    }
  }
  return c;
}

std::vector<std::string> EffectParameterNames(AxisEffect effect) {
  switch (effect) {
    case AxisEffect::kAsymmetricFriction: return {};
    case AxisEffect::kStribeckFriction: return {"stribeck_amplitude"};
    case AxisEffect::kPositionDependentFriction: return {"coulomb_p1", "coulomb_p2"};
    case AxisEffect::kCogging: return {"cogging_sin", "cogging_cos"};
    case AxisEffect::kTransmissionCompliance: return {"load_inertia", "load_viscous", "load_coulomb"};
    case AxisEffect::kCommandDelay: return {};
    case AxisEffect::kBacklash: return {"load_inertia", "load_viscous", "load_coulomb"};
  }
  return {};
}

const char* HyperName(AxisEffect effect) {
  switch (effect) {
    case AxisEffect::kStribeckFriction: return "stribeck_speed";
    case AxisEffect::kCogging: return "cogging_period";
    case AxisEffect::kBacklash: return "backlash_gap";
    case AxisEffect::kCommandDelay: return "delay_samples";
    default: return "";
  }
}


int HyperCount(const std::vector<Chosen>& effects) {
  int k = 0;
  for (const Chosen& c : effects)
    k += c.effect == AxisEffect::kTransmissionCompliance
             ? 2
             : (c.effect == AxisEffect::kStribeckFriction || c.effect == AxisEffect::kCogging ||
                        c.effect == AxisEffect::kBacklash || c.effect == AxisEffect::kCommandDelay
                    ? 1
                    : 0);
  return k;
}

// Decimated regression of `part` for base (+asymmetric) and the chosen effects.
Eigen::MatrixXd Columns(const Part& p, const std::vector<Chosen>& effects, const Stroke& st,
                        int r) {
  bool asym = false;
  for (const Chosen& c : effects) asym = asym || c.effect == AxisEffect::kAsymmetricFriction;
  std::vector<std::vector<double>> cols = BaseColumns(p.s, asym);
  // Command delay d: τ_rec(t) = τ(t + d), so the base columns are taken d later (linear
  // interpolation between samples; the last sample is held at the end).
  for (const Chosen& c : effects) {
    if (c.effect != AxisEffect::kCommandDelay) continue;
    const auto whole = static_cast<std::size_t>(std::floor(c.h));
    const double frac = c.h - static_cast<double>(whole);
    for (auto& col : cols) {
      const std::size_t n = col.size();
      std::vector<double> shifted(n);
      for (std::size_t i = 0; i < n; ++i) {
        const std::size_t a = std::min(i + whole, n - 1), b = std::min(i + whole + 1, n - 1);
        shifted[i] = (1.0 - frac) * col[a] + frac * col[b];
      }
      col = std::move(shifted);
    }
  }
  for (const Chosen& c : effects) {
    auto extra = EffectColumns(c, p, st);
    for (auto& col : extra) cols.push_back(std::move(col));
  }
  Eigen::MatrixXd x(p.y.size(), static_cast<Eigen::Index>(cols.size()));
  for (std::size_t c = 0; c < cols.size(); ++c)
    x.col(static_cast<Eigen::Index>(c)) = DecimateColumn(cols[c], r);
  return x;
}

struct Stack {
  Eigen::MatrixXd x;
  Eigen::VectorXd y;
};

Stack StackParts(const std::vector<Part>& parts, const std::vector<Chosen>& effects,
                 const Stroke& st, int r) {
  Stack s;
  Eigen::Index rows = 0;
  std::vector<Eigen::MatrixXd> xs;
  for (const Part& p : parts) {
    const Eigen::MatrixXd all = Columns(p, effects, st, r);
    Eigen::MatrixXd x(p.Rows(), all.cols());
    for (Eigen::Index i = 0; i < p.Rows(); ++i) x.row(i) = all.row(p.keep[static_cast<std::size_t>(i)]);
    xs.push_back(std::move(x));
    rows += p.Rows();
  }
  s.x.resize(rows, xs.front().cols());
  s.y.resize(rows);
  Eigen::Index at = 0;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    s.x.middleRows(at, xs[i].rows()) = xs[i];
    for (Eigen::Index k = 0; k < parts[i].Rows(); ++k)
      s.y(at + k) = parts[i].y(parts[i].keep[static_cast<std::size_t>(k)]);
    at += xs[i].rows();
  }
  return s;
}

Eigen::VectorXd SolveOls(const Eigen::MatrixXd& x, const Eigen::VectorXd& y) {
  return x.colPivHouseholderQr().solve(y);
}

// BIC with the grid-chosen nonlinear parameters counted as parameters too.
double Bic(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const Eigen::VectorXd& theta,
           int hyper_parameters = 0) {
  const double n = static_cast<double>(y.size());
  const double sse = (y - x * theta).squaredNorm();
  return n * std::log(sse / n) + static_cast<double>(theta.size() + hyper_parameters) * std::log(n);
}

double RelPct(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const Eigen::VectorXd& theta) {
  return 100.0 * (y - x * theta).norm() / y.norm();
}

double Excess(double e, double floor) { return std::sqrt(std::max(e * e - floor * floor, 0.0)); }

std::vector<double> HyperGrid1(AxisEffect effect, const Stroke& st, const std::vector<Part>& train,
                               int r);

// Candidate values of the nonlinear parameter(s); empty = none.
std::vector<std::pair<double, double>> HyperGrid(AxisEffect effect, const Stroke& st,
                                                 const std::vector<Part>& train, int r) {
  std::vector<std::pair<double, double>> grid;
  if (effect == AxisEffect::kTransmissionCompliance) {
    // Load natural frequency 3 .. 150 Hz (log), damping ratio 0.05, 0.15, 0.4.
    for (int i = 0; i < 14; ++i)
      for (double z : {0.05, 0.15, 0.4})
        grid.push_back({2.0 * std::numbers::pi * 3.0 * std::pow(50.0, i / 13.0), z});
    return grid;
  }
  for (double h : HyperGrid1(effect, st, train, r)) grid.push_back({h, 0.0});
  return grid;
}

std::vector<double> HyperGrid1(AxisEffect effect, const Stroke& st, const std::vector<Part>& train,
                               int r) {
  std::vector<double> grid;
  if (effect == AxisEffect::kCommandDelay)
    for (int i = 1; i <= 12; ++i) grid.push_back(0.25 * i);  // 0.25 .. 3 samples
  const double span = st.q_max - st.q_min;
  if (effect == AxisEffect::kStribeckFriction) {
    for (int i = 0; i < 16; ++i) grid.push_back(st.v_peak * 0.002 * std::pow(10.0, i * 2.0 / 15.0));
  } else if (effect == AxisEffect::kBacklash) {
    for (int i = 0; i < 12; ++i) grid.push_back(span * 1e-4 * std::pow(10.0, i * 2.0 / 11.0));
  } else if (effect == AxisEffect::kCogging) {
    // Spatial frequencies from 2 cycles over the stroke to what the decimated rows can carry
    // at the median moving speed, spaced 1/(4·stroke).
    std::vector<double> speeds;
    for (const Part& p : train)
      for (Eigen::Index i = 0; i < p.qddec.size(); ++i)
        if (std::abs(p.qddec(i)) > 0.05 * st.v_peak) speeds.push_back(std::abs(p.qddec(i)));
    double v_med = st.v_peak / 2.0;
    if (!speeds.empty()) {
      std::nth_element(speeds.begin(), speeds.begin() + static_cast<std::ptrdiff_t>(speeds.size() / 2),
                       speeds.end());
      v_med = speeds[speeds.size() / 2];
    }
    const double dt_dec = (train.front().tdec.size() > 1)
                              ? train.front().tdec[1] - train.front().tdec[0]
                              : 0.01 * r;
    const double f_max = std::min(0.8 * 0.5 / dt_dec / v_med, 4000.0 / span);
    for (double f = 2.0 / span; f <= f_max; f += 0.25 / span) grid.push_back(1.0 / f);
  }
  return grid;
}

// Cogging screening on decimated rows: projection of the current residual on sin/cos.
std::vector<double> ScreenCogging(const std::vector<double>& periods, const std::vector<Part>& train,
                                  const std::vector<Eigen::VectorXd>& residual) {
  std::vector<std::pair<double, double>> scored;
  for (double p : periods) {
    double s = 0.0, c = 0.0, ss = 0.0, cc = 0.0;
    for (std::size_t k = 0; k < train.size(); ++k)
      for (Eigen::Index i = 0; i < train[k].Rows(); ++i) {
        const double a =
            2.0 * std::numbers::pi * train[k].qdec(train[k].keep[static_cast<std::size_t>(i)]) / p;
        const double si = std::sin(a), ci = std::cos(a);
        s += residual[k](i) * si;
        c += residual[k](i) * ci;
        ss += si * si;
        cc += ci * ci;
      }
    scored.push_back({s * s / std::max(ss, 1e-300) + c * c / std::max(cc, 1e-300), p});
  }
  std::sort(scored.begin(), scored.end(), [](auto& a, auto& b) { return a.first > b.first; });
  std::vector<double> best;
  for (std::size_t i = 0; i < scored.size() && i < 3; ++i) best.push_back(scored[i].second);
  return best;
}

std::vector<NamedValue> NameParameters(const std::vector<Chosen>& effects,
                                       const Eigen::VectorXd& theta) {
  bool asym = false;
  for (const Chosen& c : effects) asym = asym || c.effect == AxisEffect::kAsymmetricFriction;
  std::vector<std::string> names =
      asym ? std::vector<std::string>{"inertia", "viscous_pos", "coulomb_pos", "viscous_neg",
                                      "coulomb_neg"}
           : std::vector<std::string>{"inertia", "viscous", "coulomb", "offset"};
  for (const Chosen& c : effects)
    for (const std::string& s : EffectParameterNames(c.effect)) names.push_back(s);
  std::vector<NamedValue> out;
  for (std::size_t i = 0; i < names.size() && i < static_cast<std::size_t>(theta.size()); ++i)
    out.push_back({names[i], theta(static_cast<Eigen::Index>(i))});
  for (const Chosen& c : effects) {
    if (*HyperName(c.effect)) out.push_back({HyperName(c.effect), c.h});
    if (c.effect == AxisEffect::kTransmissionCompliance) {
      out.push_back({"load_frequency_hz", c.h / (2.0 * std::numbers::pi)});
      out.push_back({"load_damping_ratio", c.h2});
    }
  }
  return out;
}

// Friction of the forward model for the effects that depend on (q, q̇) only; false otherwise.
bool ForwardFriction(const std::vector<Chosen>& effects, const Eigen::VectorXd& theta,
                     const Stroke& st, AxisForwardModel* model) {
  bool asym = false;
  for (const Chosen& c : effects) {
    asym = asym || c.effect == AxisEffect::kAsymmetricFriction;
    if (c.effect == AxisEffect::kTransmissionCompliance || c.effect == AxisEffect::kBacklash)
      return false;  // not a force of (q, q̇)
  }
  model->inertia = theta(0);
  const Eigen::VectorXd th = theta;
  const std::vector<Chosen> ef = effects;
  model->friction = [th, ef, asym, st](double q, double v) {
    const double sg = Sign(v);
    double f;
    Eigen::Index k;
    if (!asym) {
      f = th(1) * v + th(2) * sg + th(3);
      k = 4;
    } else {
      f = v > 0.0 ? th(1) * v + th(2) : (v < 0.0 ? th(3) * v - th(4) : 0.5 * (th(2) - th(4)));
      k = 5;
    }
    for (const Chosen& c : ef) {
      switch (c.effect) {
        case AxisEffect::kStribeckFriction: {
          const double r = v / c.h;
          f += th(k++) * sg * std::exp(-r * r);
          break;
        }
        case AxisEffect::kPositionDependentFriction: {
          const double x = 2.0 * (q - st.q_min) / (st.q_max - st.q_min) - 1.0;
          f += th(k) * sg * x + th(k + 1) * sg * Legendre2(x);
          k += 2;
          break;
        }
        case AxisEffect::kCogging: {
          const double a = 2.0 * std::numbers::pi * q / c.h;
          f += th(k) * std::sin(a) + th(k + 1) * std::cos(a);
          k += 2;
          break;
        }
        default:  // command_delay: a timing effect, not a force; its coefficient is skipped
          k += static_cast<Eigen::Index>(EffectParameterNames(c.effect).size());
          break;
      }
    }
    return f;
  };
  return true;
}

std::string Evidence(AxisEffect effect, const std::vector<Part>& train,
                     const std::vector<Eigen::VectorXd>& residual, double h) {
  std::ostringstream o;
  o.precision(3);
  // Residual statistics by speed sign / magnitude, position, reversal windows.
  double pos_sum = 0, pos_n = 0, neg_sum = 0, neg_n = 0, slow_ss = 0, slow_n = 0, fast_ss = 0,
         fast_n = 0;
  double v_peak = 0;
  for (const Part& p : train) v_peak = std::max(v_peak, p.qddec.cwiseAbs().maxCoeff());
  for (std::size_t k = 0; k < train.size(); ++k)
    for (Eigen::Index i = 0; i < residual[k].size(); ++i) {
      const double v = train[k].qddec(train[k].keep[static_cast<std::size_t>(i)]), e = residual[k](i);
      if (v > 0) { pos_sum += e * v; pos_n += v * v; }
      if (v < 0) { neg_sum += e * v; neg_n += v * v; }
      if (std::abs(v) < 0.1 * v_peak) { slow_ss += e * e; slow_n += 1; }
      else { fast_ss += e * e; fast_n += 1; }
    }
  switch (effect) {
    case AxisEffect::kAsymmetricFriction:
      o << "base residual vs speed: slope " << pos_sum / std::max(pos_n, 1e-300)
        << " when moving +, " << neg_sum / std::max(neg_n, 1e-300) << " when moving -";
      break;
    case AxisEffect::kStribeckFriction:
      o << "base residual RMS " << std::sqrt(slow_ss / std::max(slow_n, 1.0)) << " below 10 % of peak speed vs "
        << std::sqrt(fast_ss / std::max(fast_n, 1.0)) << " above; v_s " << h;
      break;
    case AxisEffect::kCogging:
      o << "strongest position-periodic residual at period " << h;
      break;
    case AxisEffect::kBacklash:
      o << "load behind a play of " << h << " (rigid contact)";
      break;
    case AxisEffect::kPositionDependentFriction:
      o << "dry friction as a quadratic along the stroke";
      break;
    case AxisEffect::kTransmissionCompliance:
      o << "load on a spring-damper at " << h / (2.0 * std::numbers::pi) << " Hz";
      break;
    case AxisEffect::kCommandDelay:
      o << "effort recorded " << h << " samples ahead of the force it makes";
      break;
  }
  return o.str();
}

// E[(e_k − (e_k−1 + e_k+1)/2)²]/σ² for noise that is white below β·Nyquist and zero above
// (what the decimation filter, cut-off 0.8 of the new Nyquist, passes): (1/βπ)∫₀^βπ(1 − cos ω)² dω.
double SmootherFactor(double beta) {
  const double b = beta * std::numbers::pi;
  return (b - 2.0 * std::sin(b) + b / 2.0 + std::sin(2.0 * b) / 4.0) / b;
}

double NoiseFloorPct(const std::vector<Eigen::VectorXd>& residual, const std::vector<Part>& parts,
                     int decimation) {
  double ss = 0.0, n = 0.0, yy = 0.0;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const Eigen::VectorXd& e = residual[k];
    for (Eigen::Index i = 1; i + 1 < e.size(); ++i) {
      const double d = e(i) - 0.5 * (e(i - 1) + e(i + 1));
      ss += d * d;
      n += 1.0;
    }
    for (Eigen::Index i : parts[k].keep) yy += parts[k].y(i) * parts[k].y(i);
  }
  const double var = ss / std::max(n, 1.0) / SmootherFactor(decimation > 1 ? 0.8 : 1.0);
  double rows = 0;
  for (const Part& p : parts) rows += static_cast<double>(p.Rows());
  return 100.0 * std::sqrt(var * rows / yy);
}

}  // namespace

const char* AxisEffectId(AxisEffect effect) {
  switch (effect) {
    case AxisEffect::kAsymmetricFriction: return "asymmetric_friction";
    case AxisEffect::kStribeckFriction: return "stribeck_friction";
    case AxisEffect::kPositionDependentFriction: return "position_dependent_friction";
    case AxisEffect::kCogging: return "cogging";
    case AxisEffect::kTransmissionCompliance: return "transmission_compliance";
    case AxisEffect::kBacklash: return "backlash";
    case AxisEffect::kCommandDelay: return "command_delay";
  }
  return "?";
}

const std::vector<AxisEffect>& AllAxisEffects() {
  static const std::vector<AxisEffect> all{
      AxisEffect::kAsymmetricFriction, AxisEffect::kStribeckFriction,
      AxisEffect::kPositionDependentFriction, AxisEffect::kCogging,
      AxisEffect::kTransmissionCompliance, AxisEffect::kBacklash, AxisEffect::kCommandDelay};
  return all;
}

AxisDiagnosis DiagnoseAxis(const std::vector<AxisRecording>& recordings,
                           const std::vector<AxisRecording>& validation,
                           const AxisDiagnoseOptions& options) {
  if (recordings.empty()) throw std::invalid_argument("diagnose: no recording given");
  for (const auto* set : {&recordings, &validation})
    for (const AxisRecording& r : *set)
      if (r.joints.size() != 1)
        throw std::invalid_argument(r.file.string() + ": diagnose expects one joint, got " +
                                    std::to_string(r.joints.size()));
  const int dec = options.idim.decimation;
  // Split recordings start and end in motion: drop the filter border at both ends.
  IdimOptions idim = options.idim;
  if (idim.end_border_samples <= 0) idim.end_border_samples = idim.border_samples;
  std::vector<Part> train, held;
  for (const AxisRecording& r : recordings) {
    const std::string name = r.file.filename().string();
    if (validation.empty()) {
      const auto cut = static_cast<std::size_t>(
          std::lround(static_cast<double>(r.size()) * (1.0 - options.holdout_fraction)));
      train.push_back(MakePart(r.Slice(0, cut), name + "[train]", idim));
      held.push_back(MakePart(r.Slice(cut, r.size()), name + "[held-out]", idim));
    } else {
      train.push_back(MakePart(r, name, idim));
    }
  }
  for (const AxisRecording& r : validation)
    held.push_back(MakePart(r, r.file.filename().string(), idim));

  AxisDiagnosis out;
  out.joint = recordings.front().joints.front().name;
  for (const Part& p : train) out.training_recordings.push_back(p.name);
  for (const Part& p : held) out.heldout_recordings.push_back(p.name);

  Stroke st;
  st.q_min = 1e300;
  st.q_max = -1e300;
  st.v_peak = 0.0;
  for (const Part& p : train) {
    st.q_min = std::min(st.q_min, *std::min_element(p.s.q.begin(), p.s.q.end()));
    st.q_max = std::max(st.q_max, *std::max_element(p.s.q.begin(), p.s.q.end()));
    for (double v : p.s.qd) st.v_peak = std::max(st.v_peak, std::abs(v));
  }
  if (!(st.q_max > st.q_min)) st.q_max = st.q_min + 1.0;
  // Rows at rest carry static friction, which no inverse model can predict (any force up to
  // breakaway holds the axis): the diagnosis uses the moving rows.
  for (auto* parts : {&train, &held})
    for (Part& p : *parts)
      for (Eigen::Index i = 0; i < p.qddec.size(); ++i)
        if (std::abs(p.qddec(i)) >= options.rest_speed_fraction * st.v_peak) p.keep.push_back(i);

  // Base.
  std::vector<Chosen> current;
  Stack tr = StackParts(train, current, st, dec);
  Stack ho = StackParts(held, current, st, dec);
  Eigen::VectorXd theta = SolveOls(tr.x, tr.y);
  out.base_parameters = NameParameters(current, theta);
  out.base_train_relative_error_pct = RelPct(tr.x, tr.y, theta);
  out.heldout_base_pct = RelPct(ho.x, ho.y, theta);
  const Eigen::VectorXd base_theta = theta;
  std::vector<Eigen::VectorXd> held_res, train_res;
  {
    Eigen::Index at = 0;
    for (const Part& p : held) {
      held_res.push_back(ho.y.segment(at, p.Rows()) - ho.x.middleRows(at, p.Rows()) * theta);
      at += p.Rows();
    }
    at = 0;
    for (const Part& p : train) {
      train_res.push_back(tr.y.segment(at, p.Rows()) - tr.x.middleRows(at, p.Rows()) * theta);
      at += p.Rows();
    }
  }
  // Nonlinear parameter of each effect: chosen once, on the base residual / training error.
  std::vector<Chosen> hyper;
  for (AxisEffect e : options.candidates) {
    Chosen c{e, 0.0, 0.0};
    std::vector<std::pair<double, double>> grid = HyperGrid(e, st, train, dec);
    if (e == AxisEffect::kCogging && !grid.empty()) {
      std::vector<double> periods;
      for (const auto& g : grid) periods.push_back(g.first);
      grid.clear();
      for (double pp : ScreenCogging(periods, train, train_res)) grid.push_back({pp, 0.0});
    }
    if (!grid.empty()) {
      double best = 1e300;
      for (const auto& [h, h2] : grid) {
        std::vector<Chosen> trial{Chosen{e, h, h2}};
        const Stack s = StackParts(train, trial, st, dec);
        const double sse = (s.y - s.x * SolveOls(s.x, s.y)).squaredNorm();
        if (sse < best) {
          best = sse;
          c.h = h;
          c.h2 = h2;
        }
      }
    }
    hyper.push_back(c);
  }

  // Noise floor: the smoother estimate on the base residual, or on the residual of every
  // candidate at once when that is lower (structure the smoother mistakes for noise, e.g. the
  // sharp pulses of a delay at each acceleration switch, is then taken out first).
  out.noise_floor_pct = NoiseFloorPct(held_res, held, dec);
  {
    const Stack tf = StackParts(train, hyper, st, dec);
    const Stack hf = StackParts(held, hyper, st, dec);
    const Eigen::VectorXd th = SolveOls(tf.x, tf.y);
    std::vector<Eigen::VectorXd> full_res;
    Eigen::Index at = 0;
    for (const Part& p : held) {
      full_res.push_back(hf.y.segment(at, p.Rows()) - hf.x.middleRows(at, p.Rows()) * th);
      at += p.Rows();
    }
    out.noise_floor_pct = std::min(out.noise_floor_pct, NoiseFloorPct(full_res, held, dec));
  }
  const double floor = out.noise_floor_pct;
  double current_bic = Bic(tr.x, tr.y, theta);
  double current_held = out.heldout_base_pct;
  const bool adequate = Excess(out.heldout_base_pct, floor) <= options.adequate_ratio * floor;

  std::set<int> used;
  bool first_round = true;
  while (true) {
    std::vector<EffectResult> round;
    int best_index = -1;
    double best_gain = -1e300, best_score = -1e300;
    Eigen::VectorXd best_theta;
    for (std::size_t i = 0; i < hyper.size(); ++i) {
      if (used.count(static_cast<int>(i))) continue;
      std::vector<Chosen> trial = current;
      trial.push_back(hyper[i]);
      const Stack t2 = StackParts(train, trial, st, dec);
      const Stack h2 = StackParts(held, trial, st, dec);
      const Eigen::VectorXd th = SolveOls(t2.x, t2.y);
      EffectResult r;
      r.effect = hyper[i].effect;
      r.delta_bic = Bic(t2.x, t2.y, th, HyperCount(trial)) - current_bic;
      r.train_relative_error_pct = RelPct(t2.x, t2.y, th);
      r.heldout_relative_error_pct = RelPct(h2.x, h2.y, th);
      // Gain: the share of the BASE model's held-out excess error that this effect removes on
      // top of the effects already found (so later rounds need as much as the first).
      const double ex_base = Excess(out.heldout_base_pct, floor);
      const double ex0 = Excess(current_held, floor);
      const double ex1 = Excess(r.heldout_relative_error_pct, floor);
      r.heldout_gain = ex_base > 0.0 ? (ex0 - ex1) / ex_base : 0.0;
      r.earns = !adequate && r.delta_bic < options.bic_threshold &&
                r.heldout_gain >= options.min_heldout_gain;
      r.parameters = NameParameters(trial, th);
      r.evidence = Evidence(hyper[i].effect, train, train_res, hyper[i].h);
      // Among the effects that earn, the most probable one (lowest training BIC, parameters
      // and grid parameters counted): a delay and a compliant load both add lag, and the
      // simpler explanation must win when both fit.
      if (r.earns && -r.delta_bic > best_score) {
        best_score = -r.delta_bic;
        best_gain = r.heldout_gain;
        best_index = static_cast<int>(i);
        best_theta = th;
      }
      round.push_back(std::move(r));
    }
    if (first_round) {
      std::sort(round.begin(), round.end(), [](const EffectResult& a, const EffectResult& b) {
        if (a.earns != b.earns) return a.earns;
        return a.heldout_gain > b.heldout_gain;
      });
      out.ranking = round;
      first_round = false;
    }
    if (best_index < 0) break;

    used.insert(best_index);
    current.push_back(hyper[static_cast<std::size_t>(best_index)]);
    out.causes.push_back({hyper[static_cast<std::size_t>(best_index)].effect, best_gain});
    theta = best_theta;
    const Stack t2 = StackParts(train, current, st, dec);
    const Stack h2 = StackParts(held, current, st, dec);
    current_bic = Bic(t2.x, t2.y, theta, HyperCount(current));
    current_held = RelPct(h2.x, h2.y, theta);
    // Explained: nothing above the noise is left to attribute to a further effect.
    if (Excess(current_held, floor) <= options.adequate_ratio * floor) break;
  }
  out.extended_parameters = NameParameters(current, theta);
  out.heldout_extended_pct = current_held;
  if (adequate) {
    out.verdict = "adequate";
  } else if (out.causes.empty()) {
    out.verdict = "unexplained";
  } else {
    out.cause = AxisEffectId(out.causes.front().first);
    out.verdict = Excess(current_held, floor) <= options.adequate_ratio * floor
                      ? "explained"
                      : "partly_explained";
  }
  if (out.verdict == "unexplained" || out.verdict == "partly_explained") {
    std::ostringstream o;
    o.precision(3);
    o << "held-out relative error " << current_held << " % against a noise floor of " << floor
      << " %; no further effect of the table earns its parameters";
    out.unexplained_evidence = o.str();
  }

  // Held-out series for plots.
  {
    const Stack h2 = StackParts(held, current, st, dec);
    const Eigen::VectorXd ext = h2.x * theta, base = ho.x * base_theta;
    for (const Part& p : held)
      for (Eigen::Index i : p.keep) {
        out.heldout_t.push_back(p.tdec[static_cast<std::size_t>(i)]);
        out.heldout_qd.push_back(p.qddec(i));
      }
    out.heldout_tau.assign(ho.y.data(), ho.y.data() + ho.y.size());
    out.heldout_base.assign(base.data(), base.data() + base.size());
    out.heldout_ext.assign(ext.data(), ext.data() + ext.size());
  }

  // Closed loop on the held-out recordings.
  if (options.simulate) {
    const auto border = static_cast<std::size_t>(std::max(0, idim.border_samples));
    for (const Part& p : held) {
      ClosedLoopComparison c;
      c.recording = p.name;
      const AxisRecording& r = p.recording;
      if (!r.loop || r.joints[0].reference.empty()) {
        c.why_not = "the recording has no reference or no loop gains";
        out.closed_loop.push_back(c);
        continue;
      }
      AxisForwardModel base_model, ext_model;
      ForwardFriction({}, base_theta, st, &base_model);
      c.base = CompareClosedLoop(r, p.s.qd, border, SimulateClosedLoop(r, base_model));
      if (ForwardFriction(current, theta, st, &ext_model)) {
        c.extended = CompareClosedLoop(r, p.s.qd, border, SimulateClosedLoop(r, ext_model));
      } else {
        c.extended = c.base;
        c.why_not = "the extended model's effect is not a force of (q, q') alone; base only";
      }
      c.available = true;
      out.closed_loop.push_back(c);
    }
  }
  return out;
}

}  // namespace pwsim::sysid::platform
