#include "sysid/platform/axis_diagnose.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <optional>
#include <ostream>
#include <set>
#include <sstream>
#include <stdexcept>

#include <boost/math/tools/minima.hpp>

#include "sysid/platform/block_jackknife.h"
#include "sysid/platform/signal_filters.h"

namespace pwsim::sysid::platform {
namespace {

// One recording (or part of one) ready for regression: full-rate states and decimated rows.
struct Part {
  std::string name;
  const AxisRecording* source{nullptr};  // the whole recording this block was cut from
  std::size_t begin{0};                  // the block's first sample in `source`
  AxisRecording recording;               // the block
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

// Samples [begin, end) of `source`, cut out before filtering.
Part MakePart(const AxisRecording& source, std::size_t begin, std::size_t end,
              const std::string& name, const IdimOptions& o) {
  Part p;
  p.name = name;
  p.source = &source;
  p.begin = begin;
  p.recording = begin == 0 && end == source.size() ? source : source.Slice(begin, end);
  const AxisRecording& r = p.recording;
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


// ---- The effects: each one behind AxisEffectModel, in one place ----
//
// An effect of the axis diagnosis says what it adds to the inverse model and how its
// parameters are found, and nothing else of the diagnosis knows about it:
//   - the base columns it changes (SplitsBaseByDirection, ShiftBase) and the columns it adds
//     (Columns), linear in the coefficients named by CoefficientNames;
//   - its grid parameters (GridParameters: names, units), their starting grid (Grid, Screen)
//     and their refinement by Brent's method around the grid's best point (Refine);
//   - the values it reports (Reported), its force in the forward model (AddForce; a timing or
//     a load-side effect is not a force of (q, q̇): ForceOfMotion false), and its evidence.
// Adding an effect: an AxisEffect id, a class below and its entry in Model().

// What the base model's training residual shows, for the evidence lines.
struct ResidualStats {
  double pos_slope{0.0}, neg_slope{0.0};  // residual against speed, moving + and -
  double slow_rms{0.0}, fast_rms{0.0};    // below and above 10 % of the peak speed
};

struct GridParameter {
  const char* name;  // as reported, e.g. "stribeck_speed"
  const char* unit;  // of the value, e.g. "rad/s" for a load frequency
};

// The grid search of one effect's parameters, as Refine sees it.
struct GridSearch {
  const std::vector<std::vector<double>>& full;  // the whole grid (before screening)
  const Stroke& st;
  // The training SSE at these values of the grid parameters.
  std::function<double(const std::vector<double>&)> sse;
  // The minimum of sse_at(x) for x in [lo, hi], the parameter being value(x); a value only
  // when it beats the best so far (which it then becomes).
  std::function<std::optional<double>(double lo, double hi,
                                      const std::function<double(double)>& value,
                                      const std::function<double(double)>& sse_at)>
      refine;
};

using ColumnSet = std::vector<std::vector<double>>;

class AxisEffectModel {
 public:
  virtual ~AxisEffectModel() = default;
  virtual AxisEffect Id() const = 0;
  virtual const char* Name() const = 0;  // the spec's id
  // The coefficients of the columns it adds, in Columns' order.
  virtual std::vector<std::string> CoefficientNames() const { return {}; }
  virtual std::vector<GridParameter> GridParameters() const { return {}; }
  // The base model with Fv, Fc split by direction (the asymmetric base columns).
  virtual bool SplitsBaseByDirection() const { return false; }
  // Changes the base columns in place (a delay takes them later).
  virtual void ShiftBase(const std::vector<double>& /*values*/, ColumnSet& /*base*/) const {}
  // Full-rate columns added to the model at these grid values.
  virtual ColumnSet Columns(const std::vector<double>& /*values*/, const Part& /*p*/,
                            const Stroke& /*st*/) const {
    return {};
  }
  // The grid of its parameters (empty: none), from the stroke and the training parts.
  virtual std::vector<std::vector<double>> Grid(const Stroke& /*st*/,
                                                const std::vector<Part>& /*train*/,
                                                int /*decimation*/) const {
    return {};
  }
  // The grid points worth a full fit (the base residual may rule most of them out).
  virtual std::vector<std::vector<double>> Screen(std::vector<std::vector<double>> grid,
                                                  const std::vector<Part>& /*train*/,
                                                  const std::vector<Eigen::VectorXd>& /*residual*/) const {
    return grid;
  }
  // Refines the grid's best point `values` between its neighbours.
  virtual void Refine(const GridSearch& /*search*/, std::vector<double>& /*values*/) const {}
  // Its grid parameters as reported (by default each under its name).
  virtual std::vector<NamedValue> Reported(const std::vector<double>& values) const {
    std::vector<NamedValue> out;
    const std::vector<GridParameter> g = GridParameters();
    for (std::size_t i = 0; i < g.size() && i < values.size(); ++i) out.push_back({g[i].name, values[i]});
    return out;
  }
  // False when the effect is not a force of (q, q̇) (the forward model cannot carry it).
  virtual bool ForceOfMotion() const { return true; }
  // Adds its force at (q, q̇ = v) to f, its coefficients starting at th[k].
  virtual void AddForce(const std::vector<double>& /*values*/, const Eigen::VectorXd& /*th*/,
                        Eigen::Index /*k*/, double /*q*/, double /*v*/, const Stroke& /*st*/,
                        double& /*f*/) const {}
  // One line: what in the base residual points at it, at its fitted grid values.
  virtual void Evidence(const std::vector<double>& values, const ResidualStats& s,
                        std::ostream& o) const = 0;
};

// The first grid value, 0 where the effect has none (the evidence lines print it).
double First(const std::vector<double>& values) { return values.empty() ? 0.0 : values[0]; }

class AsymmetricFriction final : public AxisEffectModel {
 public:
  AxisEffect Id() const override { return AxisEffect::kAsymmetricFriction; }
  const char* Name() const override { return "asymmetric_friction"; }
  bool SplitsBaseByDirection() const override { return true; }
  void Evidence(const std::vector<double>&, const ResidualStats& s, std::ostream& o) const override {
    o << "base residual vs speed: slope " << s.pos_slope << " when moving +, " << s.neg_slope
      << " when moving -";
  }
};

// + sign(q̇)·exp(−(q̇/v_s)²), v_s on a geometric grid from 0.2 % to 20 % of the peak speed.
class StribeckFriction final : public AxisEffectModel {
 public:
  AxisEffect Id() const override { return AxisEffect::kStribeckFriction; }
  const char* Name() const override { return "stribeck_friction"; }
  std::vector<std::string> CoefficientNames() const override { return {"stribeck_amplitude"}; }
  std::vector<GridParameter> GridParameters() const override { return {{"stribeck_speed", "rad/s or m/s"}}; }
  ColumnSet Columns(const std::vector<double>& v, const Part& p, const Stroke&) const override {
    const JointStates& s = p.s;
    const double h = v[0];
    ColumnSet c(1, std::vector<double>(s.q.size()));
    for (std::size_t i = 0; i < s.q.size(); ++i) {
      const double r = s.qd[i] / h;
      c[0][i] = Sign(s.qd[i]) * std::exp(-r * r);
    }
    return c;
  }
  std::vector<std::vector<double>> Grid(const Stroke& st, const std::vector<Part>&, int) const override {
    std::vector<std::vector<double>> grid;
    for (int i = 0; i < 16; ++i) grid.push_back({st.v_peak * 0.002 * std::pow(10.0, i * 2.0 / 15.0)});
    return grid;
  }
  void Refine(const GridSearch& g, std::vector<double>& v) const override { RefineGeometric(g, v); }
  void AddForce(const std::vector<double>& v, const Eigen::VectorXd& th, Eigen::Index k, double,
                double q_dot, const Stroke&, double& f) const override {
    const double r = q_dot / v[0];
    f += th(k) * Sign(q_dot) * std::exp(-r * r);
  }
  void Evidence(const std::vector<double>& v, const ResidualStats& s, std::ostream& o) const override {
    o << "base residual RMS " << s.slow_rms << " below 10 % of peak speed vs " << s.fast_rms
      << " above; v_s " << First(v);
  }
  // Geometric grids: the neighbours are a factor r away; refined on a log scale.
  static void RefineGeometric(const GridSearch& g, std::vector<double>& v) {
    const double r = g.full.size() > 1 ? g.full[1][0] / g.full[0][0] : 2.0;
    if (auto h = g.refine(std::log(v[0] / r), std::log(v[0] * r), [](double x) { return std::exp(x); },
                          [&](double x) { return g.sse({std::exp(x)}); }))
      v[0] = *h;
  }
};

// + sign(q̇)·P1(x), sign(q̇)·P2(x), x the stroke mapped to [−1, 1].
class PositionDependentFriction final : public AxisEffectModel {
 public:
  AxisEffect Id() const override { return AxisEffect::kPositionDependentFriction; }
  const char* Name() const override { return "position_dependent_friction"; }
  std::vector<std::string> CoefficientNames() const override { return {"coulomb_p1", "coulomb_p2"}; }
  ColumnSet Columns(const std::vector<double>&, const Part& p, const Stroke& st) const override {
    const JointStates& s = p.s;
    ColumnSet c(2, std::vector<double>(s.q.size()));
    for (std::size_t i = 0; i < s.q.size(); ++i) {
      const double x = 2.0 * (s.q[i] - st.q_min) / (st.q_max - st.q_min) - 1.0;
      c[0][i] = Sign(s.qd[i]) * x;
      c[1][i] = Sign(s.qd[i]) * Legendre2(x);
    }
    return c;
  }
  void AddForce(const std::vector<double>&, const Eigen::VectorXd& th, Eigen::Index k, double q,
                double q_dot, const Stroke& st, double& f) const override {
    const double sg = Sign(q_dot);
    const double x = 2.0 * (q - st.q_min) / (st.q_max - st.q_min) - 1.0;
    f += th(k) * sg * x + th(k + 1) * sg * Legendre2(x);
  }
  void Evidence(const std::vector<double>&, const ResidualStats&, std::ostream& o) const override {
    o << "dry friction as a quadratic along the stroke";
  }
};

// + sin(2πq/p), cos(2πq/p); the period p from 2 cycles over the stroke to what the decimated
// rows carry at the median moving speed, screened on the base residual.
class Cogging final : public AxisEffectModel {
 public:
  AxisEffect Id() const override { return AxisEffect::kCogging; }
  const char* Name() const override { return "cogging"; }
  std::vector<std::string> CoefficientNames() const override { return {"cogging_sin", "cogging_cos"}; }
  std::vector<GridParameter> GridParameters() const override { return {{"cogging_period", "rad or m"}}; }
  ColumnSet Columns(const std::vector<double>& v, const Part& p, const Stroke&) const override {
    const JointStates& s = p.s;
    const double h = v[0];
    ColumnSet c(2, std::vector<double>(s.q.size()));
    for (std::size_t i = 0; i < s.q.size(); ++i) {
      const double a = 2.0 * std::numbers::pi * s.q[i] / h;
      c[0][i] = std::sin(a);
      c[1][i] = std::cos(a);
    }
    return c;
  }
  std::vector<std::vector<double>> Grid(const Stroke& st, const std::vector<Part>& train,
                                        int r) const override {
    // Spatial frequencies from 2 cycles over the stroke to what the decimated rows can carry
    // at the median moving speed, spaced 1/(4·stroke).
    const double span = st.q_max - st.q_min;
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
    std::vector<std::vector<double>> grid;
    for (double f = 2.0 / span; f <= f_max; f += 0.25 / span) grid.push_back({1.0 / f});
    return grid;
  }
  // The three periods with the strongest projection of the base residual on sin/cos.
  std::vector<std::vector<double>> Screen(std::vector<std::vector<double>> grid,
                                          const std::vector<Part>& train,
                                          const std::vector<Eigen::VectorXd>& residual) const override {
    std::vector<std::pair<double, double>> scored;
    for (const std::vector<double>& g : grid) {
      const double p = g[0];
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
    std::vector<std::vector<double>> best;
    for (std::size_t i = 0; i < scored.size() && i < 3; ++i) best.push_back({scored[i].second});
    return best;
  }
  void Refine(const GridSearch& g, std::vector<double>& v) const override {
    // Spatial frequency within half the screening grid's spacing, 0.25/stroke.
    const double f = 1.0 / v[0], df = 0.125 / (g.st.q_max - g.st.q_min);
    if (auto p = g.refine(f - df, f + df, [](double x) { return 1.0 / x; },
                          [&](double x) { return g.sse({1.0 / x}); }))
      v[0] = *p;
  }
  void AddForce(const std::vector<double>& v, const Eigen::VectorXd& th, Eigen::Index k, double q,
                double, const Stroke&, double& f) const override {
    const double a = 2.0 * std::numbers::pi * q / v[0];
    f += th(k) * std::sin(a) + th(k + 1) * std::cos(a);
  }
  void Evidence(const std::vector<double>& v, const ResidualStats&, std::ostream& o) const override {
    o << "strongest position-periodic residual at period " << First(v);
  }
};

// τ = J_m q̈_m + J_l q̈_l + f(q̇_l) = (J_m + J_l) q̈_m + J_l (q̈_l − q̈_m) + f(q̇_m)
//     + [f(q̇_l) − f(q̇_m)]: the base columns plus the load's lag behind the motor, the load
// position q_l from the motor's (LoadPosition of the derived class).
class LoadBehindMotor : public AxisEffectModel {
 public:
  std::vector<std::string> CoefficientNames() const override {
    return {"load_inertia", "load_viscous", "load_coulomb"};
  }
  bool ForceOfMotion() const override { return false; }
  ColumnSet Columns(const std::vector<double>& v, const Part& p, const Stroke&) const override {
    const JointStates& s = p.s;
    const std::vector<double> ql = LoadPosition(v, s.q, s.qd, p.dt);
    const std::vector<double> vl = DiffCentral(ql, p.dt);
    const std::vector<double> al = DiffCentral(vl, p.dt);
    ColumnSet c(3, std::vector<double>(s.q.size()));
    for (std::size_t i = 0; i < s.q.size(); ++i) {
      c[0][i] = al[i] - s.qdd[i];
      c[1][i] = vl[i] - s.qd[i];
      c[2][i] = Sign(vl[i]) - Sign(s.qd[i]);
    }
    return c;
  }

 protected:
  // The load side's position seen through the transmission from the (measured) motor side.
  // A block starts in motion, so the load starts where the motion has brought it.
  virtual std::vector<double> LoadPosition(const std::vector<double>& values,
                                           const std::vector<double>& qm,
                                           const std::vector<double>& qdm, double dt) const = 0;
};

// q_l = H(s) q_m, H = (2ζω s + ω²)/(s² + 2ζω s + ω²) (load J_l on a spring-damper, k/J_l = ω²,
// c/J_l = 2ζω), Tustin at the sampling rate, started on its forced response to the quadratic
// through the first samples (PolynomialSteadyState). ω on a log grid 3 .. 150 Hz, ζ 0.05, 0.15,
// 0.4.
class TransmissionCompliance final : public LoadBehindMotor {
 public:
  AxisEffect Id() const override { return AxisEffect::kTransmissionCompliance; }
  const char* Name() const override { return "transmission_compliance"; }
  std::vector<GridParameter> GridParameters() const override {
    return {{"load_angular_frequency", "rad/s"}, {"load_damping_ratio", "-"}};
  }
  std::vector<std::vector<double>> Grid(const Stroke&, const std::vector<Part>&, int) const override {
    std::vector<std::vector<double>> grid;
    for (int i = 0; i < 14; ++i)
      for (double z : {0.05, 0.15, 0.4})
        grid.push_back({2.0 * std::numbers::pi * 3.0 * std::pow(50.0, i / 13.0), z});
    return grid;
  }
  void Refine(const GridSearch& g, std::vector<double>& v) const override {
    auto exp_of = [](double x) { return std::exp(x); };
    const double r = std::pow(50.0, 1.0 / 13.0);  // the grid's frequency ratio
    if (auto w = g.refine(std::log(v[0] / r), std::log(v[0] * r), exp_of,
                          [&](double x) { return g.sse({std::exp(x), v[1]}); }))
      v[0] = *w;
    if (auto z = g.refine(std::log(v[1] / 3.0), std::log(std::min(1.0, v[1] * 3.0)), exp_of,
                          [&](double x) { return g.sse({v[0], std::exp(x)}); }))
      v[1] = *z;
  }
  std::vector<NamedValue> Reported(const std::vector<double>& v) const override {
    return {{"load_frequency_hz", v[0] / (2.0 * std::numbers::pi)}, {"load_damping_ratio", v[1]}};
  }
  void Evidence(const std::vector<double>& v, const ResidualStats&, std::ostream& o) const override {
    o << "load on a spring-damper at " << First(v) / (2.0 * std::numbers::pi) << " Hz";
  }

 protected:
  std::vector<double> LoadPosition(const std::vector<double>& v, const std::vector<double>& qm,
                                   const std::vector<double>&, double dt) const override {
    std::vector<double> ql(qm.size());
    if (qm.empty()) return ql;
    const double k = 2.0 / dt, w = v[0], z = v[1];
    TransferFunction tf;
    tf.b = {2.0 * z * w * k + w * w, 2.0 * w * w, -2.0 * z * w * k + w * w};
    tf.a = {k * k + 2.0 * z * w * k + w * w, -2.0 * k * k + 2.0 * w * w, k * k - 2.0 * z * w * k + w * w};
    std::vector<double> state = PolynomialSteadyState(tf, qm[0], 0.0, 0.0);
    const std::size_t m = std::min<std::size_t>(qm.size(), 21);
    if (m >= 3) {
      // q_m ≈ c0 + c1·k + c2·k² over the first m samples (least squares).
      Eigen::MatrixXd a(static_cast<Eigen::Index>(m), 3);
      Eigen::VectorXd y(static_cast<Eigen::Index>(m));
      for (std::size_t i = 0; i < m; ++i) {
        const auto r = static_cast<Eigen::Index>(i);
        const double t = static_cast<double>(i);
        a(r, 0) = 1.0;
        a(r, 1) = t;
        a(r, 2) = t * t;
        y(r) = qm[i];
      }
      const Eigen::Vector3d cq = a.colPivHouseholderQr().solve(y);
      state = PolynomialSteadyState(tf, cq(0), cq(1), cq(2));
    }
    Filter(tf, qm, ql, state);
    return ql;
  }
};

// q_l the play operator of q_m, clamp(q_l, q_m − b/2, q_m + b/2) (rigid contact), the load
// trailing the motor by half the gap at the start; b on a geometric grid from 1e-4 to 1e-2 of
// the stroke.
class Backlash final : public LoadBehindMotor {
 public:
  AxisEffect Id() const override { return AxisEffect::kBacklash; }
  const char* Name() const override { return "backlash"; }
  std::vector<GridParameter> GridParameters() const override { return {{"backlash_gap", "rad or m"}}; }
  std::vector<std::vector<double>> Grid(const Stroke& st, const std::vector<Part>&, int) const override {
    const double span = st.q_max - st.q_min;
    std::vector<std::vector<double>> grid;
    for (int i = 0; i < 12; ++i) grid.push_back({span * 1e-4 * std::pow(10.0, i * 2.0 / 11.0)});
    return grid;
  }
  void Refine(const GridSearch& g, std::vector<double>& v) const override {
    StribeckFriction::RefineGeometric(g, v);
  }
  void Evidence(const std::vector<double>& v, const ResidualStats&, std::ostream& o) const override {
    o << "load behind a play of " << First(v) << " (rigid contact)";
  }

 protected:
  std::vector<double> LoadPosition(const std::vector<double>& v, const std::vector<double>& qm,
                                   const std::vector<double>& qdm, double) const override {
    std::vector<double> ql(qm.size());
    if (qm.empty()) return ql;
    const double gap = v[0];
    double l = qm[0] - 0.5 * gap * Sign(qdm.empty() ? 0.0 : qdm[0]);
    for (std::size_t i = 0; i < qm.size(); ++i) {
      l = std::clamp(l, qm[i] - 0.5 * gap, qm[i] + 0.5 * gap);
      ql[i] = l;
    }
    return ql;
  }
};

// The base columns taken d later: τ_rec(t) = τ(t + d) (linear interpolation between samples,
// the last sample held at the end); d on a grid of 0.25 .. 3 samples, no extra coefficient.
class CommandDelay final : public AxisEffectModel {
 public:
  AxisEffect Id() const override { return AxisEffect::kCommandDelay; }
  const char* Name() const override { return "command_delay"; }
  std::vector<GridParameter> GridParameters() const override { return {{"delay_samples", "samples"}}; }
  void ShiftBase(const std::vector<double>& v, ColumnSet& base) const override {
    const auto whole = static_cast<std::size_t>(std::floor(v[0]));
    const double frac = v[0] - static_cast<double>(whole);
    for (auto& col : base) {
      const std::size_t n = col.size();
      std::vector<double> shifted(n);
      for (std::size_t i = 0; i < n; ++i) {
        const std::size_t a = std::min(i + whole, n - 1), b = std::min(i + whole + 1, n - 1);
        shifted[i] = (1.0 - frac) * col[a] + frac * col[b];
      }
      col = std::move(shifted);
    }
  }
  std::vector<std::vector<double>> Grid(const Stroke&, const std::vector<Part>&, int) const override {
    std::vector<std::vector<double>> grid;
    for (int i = 1; i <= 12; ++i) grid.push_back({0.25 * i});  // 0.25 .. 3 samples
    return grid;
  }
  void Refine(const GridSearch& g, std::vector<double>& v) const override {
    if (auto d = g.refine(std::max(0.0, v[0] - 0.25), v[0] + 0.25, [](double x) { return x; },
                          [&](double x) { return g.sse({x}); }))
      v[0] = *d;
  }
  void Evidence(const std::vector<double>& v, const ResidualStats&, std::ostream& o) const override {
    o << "effort recorded " << First(v) << " samples ahead of the force it makes";
  }
};

// Every effect's model, by id.
const AxisEffectModel& Model(AxisEffect effect) {
  static const AsymmetricFriction asymmetric;
  static const StribeckFriction stribeck;
  static const PositionDependentFriction position;
  static const Cogging cogging;
  static const TransmissionCompliance compliance;
  static const Backlash backlash;
  static const CommandDelay delay;
  static const std::array<const AxisEffectModel*, 7> all{&asymmetric, &stribeck, &position, &cogging,
                                                         &compliance, &backlash, &delay};
  return *all.at(static_cast<std::size_t>(effect));
}

// An effect with its grid parameters chosen.
struct Chosen {
  const AxisEffectModel* model{nullptr};
  std::vector<double> values;  // in model->GridParameters() order
  AxisEffect Effect() const { return model->Id(); }
};

int HyperCount(const std::vector<Chosen>& effects) {
  int k = 0;
  for (const Chosen& c : effects) k += static_cast<int>(c.model->GridParameters().size());
  return k;
}

// Decimated regression of `part` for base (+asymmetric) and the chosen effects.
Eigen::MatrixXd Columns(const Part& p, const std::vector<Chosen>& effects, const Stroke& st,
                        int r) {
  bool asym = false;
  for (const Chosen& c : effects) asym = asym || c.model->SplitsBaseByDirection();
  ColumnSet cols = BaseColumns(p.s, asym);
  for (const Chosen& c : effects) c.model->ShiftBase(c.values, cols);
  for (const Chosen& c : effects) {
    ColumnSet extra = c.model->Columns(c.values, p, st);
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

std::vector<NamedValue> NameParameters(const std::vector<Chosen>& effects,
                                       const Eigen::VectorXd& theta) {
  bool asym = false;
  for (const Chosen& c : effects) asym = asym || c.model->SplitsBaseByDirection();
  std::vector<std::string> names =
      asym ? std::vector<std::string>{"inertia", "viscous_pos", "coulomb_pos", "viscous_neg",
                                      "coulomb_neg"}
           : std::vector<std::string>{"inertia", "viscous", "coulomb", "offset"};
  for (const Chosen& c : effects)
    for (const std::string& n : c.model->CoefficientNames()) names.push_back(n);
  std::vector<NamedValue> out;
  for (std::size_t i = 0; i < names.size() && i < static_cast<std::size_t>(theta.size()); ++i)
    out.push_back({names[i], theta(static_cast<Eigen::Index>(i))});
  for (const Chosen& c : effects)
    for (NamedValue& v : c.model->Reported(c.values)) out.push_back(std::move(v));
  return out;
}

// Friction of the forward model for the effects that depend on (q, q̇) only; false otherwise.
bool ForwardFriction(const std::vector<Chosen>& effects, const Eigen::VectorXd& theta,
                     const Stroke& st, AxisForwardModel* model) {
  bool asym = false;
  for (const Chosen& c : effects) {
    asym = asym || c.model->SplitsBaseByDirection();
    if (!c.model->ForceOfMotion()) return false;
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
      c.model->AddForce(c.values, th, k, q, v, st, f);
      k += static_cast<Eigen::Index>(c.model->CoefficientNames().size());
    }
    return f;
  };
  return true;
}

// The base residual's statistics the evidence lines quote, and the effect's line.
std::string Evidence(const Chosen& effect, const std::vector<Part>& train,
                     const std::vector<Eigen::VectorXd>& residual) {
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
  ResidualStats stats;
  stats.pos_slope = pos_sum / std::max(pos_n, 1e-300);
  stats.neg_slope = neg_sum / std::max(neg_n, 1e-300);
  stats.slow_rms = std::sqrt(slow_ss / std::max(slow_n, 1.0));
  stats.fast_rms = std::sqrt(fast_ss / std::max(fast_n, 1.0));
  effect.model->Evidence(effect.values, stats, o);
  return o.str();
}

// E[(e_k − (e_k−1 + e_k+1)/2)²]/σ² for noise that is white below β·Nyquist and zero above
// (what the decimation filter, cut-off 0.8 of the new Nyquist, passes): (1/βπ)∫₀^βπ(1 − cos ω)² dω.
double SmootherFactor(double beta) {
  const double b = beta * std::numbers::pi;
  return (b - 2.0 * std::sin(b) + b / 2.0 + std::sin(2.0 * b) / 4.0) / b;
}

// σ² of the white part of per-part residuals (the local smoother of step 4).
double WhiteNoiseVariance(const std::vector<Eigen::VectorXd>& residual, int decimation) {
  double ss = 0.0, n = 0.0;
  for (const Eigen::VectorXd& e : residual)
    for (Eigen::Index i = 1; i + 1 < e.size(); ++i) {
      const double d = e(i) - 0.5 * (e(i - 1) + e(i + 1));
      ss += d * d;
      n += 1.0;
    }
  return ss / std::max(n, 1.0) / SmootherFactor(decimation > 1 ? 0.8 : 1.0);
}

// What one set of rows holds for the relative errors: Σe², Σy², the number of rows.
struct RowSums {
  double sse{0.0}, yy{0.0}, n{0.0};
  void Add(const RowSums& o) {
    sse += o.sse;
    yy += o.yy;
    n += o.n;
  }
  double RelPct() const { return yy > 0.0 ? 100.0 * std::sqrt(sse / yy) : 0.0; }
  /// Relative error of white noise of variance `var` on these rows.
  double FloorPct(double var) const { return yy > 0.0 ? 100.0 * std::sqrt(var * n / yy) : 0.0; }
};

// ---- 1. The split ----

struct Split {
  std::vector<Part> train, select, report;
  std::vector<AxisBlock> blocks;
};

// Roles for n blocks in turn, each block to the role furthest behind its share (ties: training,
// selection, report): every prefix of the recording keeps the shares, so every role draws
// blocks from the whole recording.
std::vector<AxisRole> DealRoles(std::size_t n, const std::array<double, 3>& share) {
  std::vector<AxisRole> roles;
  std::array<double, 3> count{0.0, 0.0, 0.0};
  for (std::size_t b = 0; b < n; ++b) {
    int best = -1;
    double best_deficit = 0.0;
    for (int r = 0; r < 3; ++r) {
      const double deficit = share[static_cast<std::size_t>(r)] * static_cast<double>(b + 1) -
                             count[static_cast<std::size_t>(r)];
      if (share[static_cast<std::size_t>(r)] > 0.0 && (best < 0 || deficit > best_deficit + 1e-12)) {
        best = r;
        best_deficit = deficit;
      }
    }
    count[static_cast<std::size_t>(best)] += 1.0;
    roles.push_back(static_cast<AxisRole>(best));
  }
  return roles;
}

std::string BlockName(const AxisRecording& r, std::size_t begin, std::size_t end) {
  std::ostringstream o;
  o.setf(std::ios::fixed);
  o.precision(3);
  o << r.file.filename().string() << "[" << r.t[begin] << "-" << r.t[end - 1] << " s]";
  return o.str();
}

// Cuts `r` into blocks of about block_s (at least the filter borders and 20 decimated rows) and
// deals them to the roles with these shares (training, selection, report).
void DealRecording(const AxisRecording& r, const std::array<double, 3>& share,
                   const AxisDiagnoseOptions& options, const IdimOptions& idim, Split* split) {
  const std::size_t n = r.size();
  const auto min_len = static_cast<std::size_t>(
      std::max(1, idim.border_samples + idim.end_border_samples + 20 * idim.decimation));
  const auto wanted = static_cast<std::size_t>(
      std::max(1.0, std::round(options.block_s / std::max(r.dt, 1e-12))));
  const std::size_t len = std::max(wanted, min_len);
  std::size_t roles_needed = 0;
  for (double f : share) roles_needed += f > 0.0 ? 1 : 0;
  const std::size_t blocks = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(
                                                          static_cast<double>(n) / static_cast<double>(len))));
  if (n < roles_needed * min_len)
    throw std::invalid_argument(
        r.file.string() + ": " + std::to_string(n) + " samples, too few for the diagnosis' split into " +
        std::to_string(roles_needed) + " roles; expected at least " +
        std::to_string(roles_needed * min_len) + " (blocks of at least " + std::to_string(min_len) +
        " samples: the filter borders and 20 decimated rows)");
  if (blocks < roles_needed) {
    std::ostringstream o;
    o.precision(3);
    o << r.file.string() << ": " << static_cast<double>(n) * r.dt << " s cut into blocks of "
      << static_cast<double>(len) * r.dt << " s gives " << blocks << " block(s), expected at least "
      << roles_needed << " (one per role); expected a block length (--block-s) of at most "
      << static_cast<double>(n) * r.dt / static_cast<double>(roles_needed) << " s";
    throw std::invalid_argument(o.str());
  }
  const std::vector<AxisRole> roles = DealRoles(blocks, share);
  for (std::size_t b = 0; b < blocks; ++b) {
    const std::size_t begin = b * n / blocks, end = (b + 1) * n / blocks;
    const AxisRole role = roles[b];
    split->blocks.push_back({r.file.filename().string(), begin, end, role});
    Part part = MakePart(r, begin, end, BlockName(r, begin, end), idim);
    (role == AxisRole::kTraining    ? split->train
     : role == AxisRole::kSelection ? split->select
                                    : split->report)
        .push_back(std::move(part));
  }
}

Split MakeSplit(const std::vector<AxisRecording>& recordings,
                const std::vector<AxisRecording>& validation, const AxisDiagnoseOptions& options,
                const IdimOptions& idim) {
  Split split;
  const double report = validation.empty() ? options.holdout_fraction : 0.0;
  const double select = (1.0 - report) * options.selection_fraction;
  const std::array<double, 3> share{1.0 - report - select, select, report};
  for (const AxisRecording& r : recordings) DealRecording(r, share, options, idim, &split);
  for (const AxisRecording& r : validation) {
    split.blocks.push_back({r.file.filename().string(), 0, r.size(), AxisRole::kReport});
    split.report.push_back(MakePart(r, 0, r.size(), r.file.filename().string(), idim));
  }
  return split;
}

// The stroke and the peak speed of the training rows (they map positions and define rest).
Stroke StrokeOf(const std::vector<Part>& train) {
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
  return st;
}

// Rows at rest carry static friction, which no inverse model can predict (any force up to
// breakaway holds the axis): every role keeps its rows with |q̇| ≥ v_min.
void KeepMovingRows(double v_min, Split* split) {
  for (auto* parts : {&split->train, &split->select, &split->report})
    for (Part& p : *parts)
      for (Eigen::Index i = 0; i < p.qddec.size(); ++i)
        if (std::abs(p.qddec(i)) >= v_min) p.keep.push_back(i);
}

// The report rows' series for the figures: time, velocity, measured, base and extended effort.
void FillReportSeries(const std::vector<Part>& report, const std::vector<Chosen>& causes,
                      const Eigen::VectorXd& base_theta, const Eigen::VectorXd& theta,
                      const Stroke& st, int dec, AxisDiagnosis* out) {
  const Stack h2 = StackParts(report, causes, st, dec);
  const Stack h0 = StackParts(report, {}, st, dec);
  const Eigen::VectorXd ext = h2.x * theta, base = h0.x * base_theta;
  for (const Part& p : report)
    for (Eigen::Index i : p.keep) {
      out->heldout_t.push_back(p.tdec[static_cast<std::size_t>(i)]);
      out->heldout_qd.push_back(p.qddec(i));
    }
  out->heldout_tau.assign(h0.y.data(), h0.y.data() + h0.y.size());
  out->heldout_base.assign(base.data(), base.data() + base.size());
  out->heldout_ext.assign(ext.data(), ext.data() + ext.size());
}

// ---- Fits and errors ----

Eigen::VectorXd FitOn(const std::vector<Part>& train, const std::vector<Chosen>& effects,
                      const Stroke& st, int dec) {
  const Stack s = StackParts(train, effects, st, dec);
  return SolveOls(s.x, s.y);
}

// Per-part residuals y − Xθ on the kept rows.
std::vector<Eigen::VectorXd> Residuals(const std::vector<Part>& parts,
                                       const std::vector<Chosen>& effects,
                                       const Eigen::VectorXd& theta, const Stroke& st, int dec) {
  const Stack s = StackParts(parts, effects, st, dec);
  const Eigen::VectorXd e = s.y - s.x * theta;
  std::vector<Eigen::VectorXd> out;
  Eigen::Index at = 0;
  for (const Part& p : parts) {
    out.push_back(e.segment(at, p.Rows()));
    at += p.Rows();
  }
  return out;
}

RowSums SumsOn(const std::vector<Part>& parts, const std::vector<Chosen>& effects,
               const Eigen::VectorXd& theta, const Stroke& st, int dec) {
  const Stack s = StackParts(parts, effects, st, dec);
  return {(s.y - s.x * theta).squaredNorm(), s.y.squaredNorm(), static_cast<double>(s.y.size())};
}

std::vector<Chosen> With(std::vector<Chosen> effects, const Chosen& extra) {
  effects.push_back(extra);
  return effects;
}

// ---- 3. Grid parameters, fitted on the training rows ----

// The minimum of f on [lo, hi] by Brent's method (Boost.Math: golden-section steps with
// parabolic interpolation), at most `evaluations` evaluations, x to about 1e-4 relative.
std::pair<double, double> BrentMinimum(const std::function<double(double)>& f, double lo,
                                       double hi, int evaluations) {
  std::uintmax_t iterations = static_cast<std::uintmax_t>(evaluations);
  return boost::math::tools::brent_find_minima(f, lo, hi, 14, iterations);
}

// Each candidate's nonlinear parameter(s) fitted on the training rows: the best point of the
// grid (HyperGrid; the cogging periods screened on the base residual), then refined between
// the grid's neighbours of that point by Brent's method (the load frequency, then its
// damping ratio, on a log scale; the delay and the cogging frequency on a linear one).
std::vector<Chosen> FitGridParameters(const std::vector<AxisEffect>& candidates,
                                      const std::vector<Part>& train,
                                      const std::vector<Eigen::VectorXd>& train_res,
                                      const Stroke& st, int dec) {
  std::vector<Chosen> out;
  for (AxisEffect e : candidates) {
    const AxisEffectModel& model = Model(e);
    Chosen c{&model, std::vector<double>(model.GridParameters().size(), 0.0)};
    const std::vector<std::vector<double>> full = model.Grid(st, train, dec);
    const std::vector<std::vector<double>> grid =
        full.empty() ? full : model.Screen(full, train, train_res);
    auto sse = [&](const std::vector<double>& values) {
      const std::vector<Chosen> trial{Chosen{&model, values}};
      const Stack s = StackParts(train, trial, st, dec);
      return (s.y - s.x * SolveOls(s.x, s.y)).squaredNorm();
    };
    double best = 1e300;
    for (const std::vector<double>& values : grid) {
      const double v = sse(values);
      if (v < best) {
        best = v;
        c.values = values;
      }
    }
    if (grid.empty()) {
      out.push_back(c);
      continue;
    }
    constexpr int kEvaluations = 16;
    const GridSearch search{
        full, st, sse,
        [&](double lo, double hi, const std::function<double(double)>& value,
            const std::function<double(double)>& sse_at) {
          const auto [x, v] = BrentMinimum(sse_at, lo, hi, kEvaluations);
          if (!(v < best)) return std::optional<double>();
          best = v;
          return std::optional<double>(value(x));
        }};
    model.Refine(search, c.values);
    out.push_back(c);
  }
  return out;
}

// ---- 5. Forward selection on the selection rows ----

struct Selection {
  std::vector<Chosen> causes;               // in the order found
  std::vector<double> selection_gain_pct;   // per cause
  std::vector<Eigen::VectorXd> theta;       // theta[k]: base + the first k causes
  std::vector<EffectResult> first_round;    // every candidate on the base model
  std::vector<Eigen::VectorXd> first_round_theta;
  std::vector<Chosen> first_round_effect;
  bool base_adequate{false};
  double base_pct{0.0}, extended_pct{0.0}, floor_pct{0.0};
};

Selection ForwardSelect(const std::vector<Part>& train, const std::vector<Part>& select,
                        const std::vector<Chosen>& grid_fitted,
                        const std::vector<Eigen::VectorXd>& train_res, double noise_var,
                        const Eigen::VectorXd& base_theta, const Stroke& st,
                        const AxisDiagnoseOptions& options, int dec) {
  Selection out;
  std::vector<Chosen> current;
  Eigen::VectorXd theta = base_theta;
  out.theta.push_back(theta);
  const RowSums base_sums = SumsOn(select, current, theta, st, dec);
  const double floor = base_sums.FloorPct(noise_var);
  out.floor_pct = floor;
  out.base_pct = base_sums.RelPct();
  out.base_adequate = Excess(out.base_pct, floor) <= options.adequate_ratio * floor;
  const Stack base_train = StackParts(train, current, st, dec);
  double current_bic = Bic(base_train.x, base_train.y, theta);
  double current_pct = out.base_pct;
  const double ex_base = Excess(out.base_pct, floor);
  std::set<std::size_t> used;
  bool first_round = true;
  while (true) {
    std::optional<std::size_t> best;
    double best_score = -1e300, best_gain = 0.0;
    Eigen::VectorXd best_theta;
    for (std::size_t i = 0; i < grid_fitted.size(); ++i) {
      if (used.count(i)) continue;
      const std::vector<Chosen> trial = With(current, grid_fitted[i]);
      const Stack t2 = StackParts(train, trial, st, dec);
      const Eigen::VectorXd th = SolveOls(t2.x, t2.y);
      EffectResult r;
      r.effect = grid_fitted[i].Effect();
      r.delta_bic = Bic(t2.x, t2.y, th, HyperCount(trial)) - current_bic;
      r.train_relative_error_pct = RelPct(t2.x, t2.y, th);
      r.selection_relative_error_pct = SumsOn(select, trial, th, st, dec).RelPct();
      // Gain: the share of the BASE model's excess error that this effect removes on top of
      // the effects already found (so later rounds need as much as the first).
      r.selection_gain_pct =
          ex_base > 0.0
              ? 100.0 * (Excess(current_pct, floor) - Excess(r.selection_relative_error_pct, floor)) / ex_base
              : 0.0;
      r.earns = !out.base_adequate && r.delta_bic < options.bic_threshold &&
                r.selection_gain_pct >= options.min_gain_pct;
      r.parameters = NameParameters(trial, th);
      r.evidence = Evidence(grid_fitted[i], train, train_res);
      // Among the effects that earn, the most probable one (lowest training BIC, parameters
      // and grid parameters counted): a delay and a compliant load both add lag, and the
      // simpler explanation must win when both fit.
      if (r.earns && -r.delta_bic > best_score) {
        best_score = -r.delta_bic;
        best_gain = r.selection_gain_pct;
        best = i;
        best_theta = th;
      }
      if (first_round) {
        out.first_round.push_back(std::move(r));
        out.first_round_theta.push_back(th);
        out.first_round_effect.push_back(grid_fitted[i]);
      }
    }
    first_round = false;
    if (!best) break;
    used.insert(*best);
    current.push_back(grid_fitted[*best]);
    theta = best_theta;
    out.causes.push_back(grid_fitted[*best]);
    out.selection_gain_pct.push_back(best_gain);
    out.theta.push_back(theta);
    const Stack t2 = StackParts(train, current, st, dec);
    current_bic = Bic(t2.x, t2.y, theta, HyperCount(current));
    current_pct = SumsOn(select, current, theta, st, dec).RelPct();
    // Explained on the selection rows: nothing above the noise is left to attribute.
    if (Excess(current_pct, floor) <= options.adequate_ratio * floor) break;
  }
  out.extended_pct = current_pct;
  return out;
}

// ---- 6. The report rows ----

// Row sums of `effects`/`theta` per report block: each part cut into round(span/block_s)
// chunks of consecutive rows (one chunk for a block of the split).
std::vector<RowSums> BlockSums(const std::vector<Part>& report, const std::vector<Chosen>& effects,
                               const Eigen::VectorXd& theta, const Stroke& st, int dec,
                               double block_s) {
  const std::vector<Eigen::VectorXd> res = Residuals(report, effects, theta, st, dec);
  std::vector<RowSums> out;
  for (std::size_t k = 0; k < report.size(); ++k) {
    const Part& p = report[k];
    if (p.Rows() == 0) continue;
    const double span = p.tdec[static_cast<std::size_t>(p.keep.back())] -
                        p.tdec[static_cast<std::size_t>(p.keep.front())];
    const auto chunks = static_cast<Eigen::Index>(std::max(1L, std::lround(span / block_s)));
    const std::size_t first = out.size();
    out.resize(first + static_cast<std::size_t>(chunks));
    for (Eigen::Index i = 0; i < p.Rows(); ++i) {
      RowSums& b = out[first + static_cast<std::size_t>(i * chunks / p.Rows())];
      const double y = p.y(p.keep[static_cast<std::size_t>(i)]);
      b.sse += res[k](i) * res[k](i);
      b.yy += y * y;
      b.n += 1.0;
    }
  }
  return out;
}

RowSums Pool(const std::vector<RowSums>& blocks, int excluded) {
  RowSums s;
  for (std::size_t b = 0; b < blocks.size(); ++b)
    if (static_cast<int>(b) != excluded) s.Add(blocks[b]);
  return s;
}

// The gain [%] of going from `before` to `after` as a share of the base's excess, on the report
// blocks without `excluded`.
double ReportGainPct(const std::vector<RowSums>& base, const std::vector<RowSums>& before,
                     const std::vector<RowSums>& after, double noise_var, int excluded) {
  const RowSums b = Pool(base, excluded);
  const double floor = b.FloorPct(noise_var);
  const double ex_base = Excess(b.RelPct(), floor);
  if (!(ex_base > 0.0)) return 0.0;
  return 100.0 *
         (Excess(Pool(before, excluded).RelPct(), floor) - Excess(Pool(after, excluded).RelPct(), floor)) /
         ex_base;
}

std::string UnexplainedEvidence(const AxisDiagnosis& d, const Selection& sel) {
  std::ostringstream o;
  o.precision(3);
  o << "report-row relative error " << d.heldout_extended_pct << " % against a noise floor of "
    << d.noise_floor_pct << " %; ";
  if (sel.base_adequate) {
    o << "the base model was noise-like on the selection rows (" << sel.base_pct << " % against "
      << sel.floor_pct << " %), so no cause was searched";
    return o.str();
  }
  bool unconfirmed = false;
  for (const AxisCause& c : d.causes) {
    if (c.confirmed) continue;
    o << (unconfirmed ? ", " : "not confirmed on the report rows: ") << AxisEffectId(c.effect) << " ("
      << c.heldout_gain_pct << " ± " << c.heldout_gain_se_pct << " %)";
    unconfirmed = true;
  }
  if (unconfirmed) o << "; ";
  o << "no further effect of the table earns its parameters on the selection rows";
  return o.str();
}

// Step 6: the report rows' errors, each cause's gain with its jackknife bound and
// confirmation, the ranking's report figures, the verdict and its evidence. Reads nothing that
// a choice depends on, and decides nothing that a fit or a choice reads.
void ReportOnReportRows(const std::vector<Part>& report, const Selection& sel, double noise_var,
                        const Stroke& st, int dec, const AxisDiagnoseOptions& options,
                        AxisDiagnosis* d) {
  AxisDiagnosis& out = *d;
  std::vector<std::vector<RowSums>> step_sums;  // base, base + first cause, ...
  for (std::size_t k = 0; k < sel.theta.size(); ++k)
    step_sums.push_back(BlockSums(
        report, std::vector<Chosen>(sel.causes.begin(), sel.causes.begin() + static_cast<std::ptrdiff_t>(k)),
        sel.theta[k], st, dec, options.block_s));
  out.report_blocks = static_cast<int>(step_sums.front().size());
  const RowSums base_all = Pool(step_sums.front(), -1);
  out.heldout_base_pct = base_all.RelPct();
  out.heldout_extended_pct = Pool(step_sums.back(), -1).RelPct();
  out.noise_floor_pct = base_all.FloorPct(noise_var);
  std::size_t confirmed = 0;
  for (std::size_t k = 0; k < sel.causes.size(); ++k) {
    const JackknifeBound g = BlockJackknife(
        out.report_blocks,
        [&](int excluded) {
          return ReportGainPct(step_sums.front(), step_sums[k], step_sums[k + 1], noise_var, excluded);
        },
        options.confirm_level);
    AxisCause c;
    c.effect = sel.causes[k].Effect();
    c.selection_gain_pct = sel.selection_gain_pct[k];
    c.heldout_gain_pct = g.estimate;
    c.heldout_gain_se_pct = g.se;
    c.heldout_gain_lower_pct = g.lower;
    c.confirmed = g.lower > 0.0;
    confirmed += c.confirmed ? 1 : 0;
    out.causes.push_back(c);
  }
  for (std::size_t i = 0; i < sel.first_round.size(); ++i) {
    EffectResult r = sel.first_round[i];
    const std::vector<RowSums> with = BlockSums(report, {sel.first_round_effect[i]},
                                                sel.first_round_theta[i], st, dec, options.block_s);
    r.heldout_relative_error_pct = Pool(with, -1).RelPct();
    r.heldout_gain_pct = ReportGainPct(step_sums.front(), step_sums.front(), with, noise_var, -1);
    out.ranking.push_back(std::move(r));
  }
  // The ranking's order is the selection rows': earning first, then by selection gain.
  std::stable_sort(out.ranking.begin(), out.ranking.end(),
                   [](const EffectResult& a, const EffectResult& b) {
                     if (a.earns != b.earns) return a.earns;
                     return a.selection_gain_pct > b.selection_gain_pct;
                   });
  const double floor = out.noise_floor_pct, allowed = options.adequate_ratio * floor;
  out.verdict = diagnose::DecideVerdict(Excess(out.heldout_base_pct, floor) <= allowed, confirmed,
                                        Excess(out.heldout_extended_pct, floor) <= allowed);
  if (out.verdict == diagnose::Verdict::kExplained ||
      out.verdict == diagnose::Verdict::kPartlyExplained)
    for (const AxisCause& c : out.causes)
      if (c.confirmed) {
        out.cause = AxisEffectId(c.effect);
        break;
      }
  if (out.verdict == diagnose::Verdict::kUnexplained ||
      out.verdict == diagnose::Verdict::kPartlyExplained)
    out.unexplained_evidence = UnexplainedEvidence(out, sel);
}

// ---- 7. Closed loop ----

std::vector<ClosedLoopComparison> CompareInClosedLoop(const std::vector<Part>& report,
                                                      const std::vector<Chosen>& causes,
                                                      const Eigen::VectorXd& base_theta,
                                                      const Eigen::VectorXd& theta, const Stroke& st,
                                                      std::size_t border) {
  std::vector<ClosedLoopComparison> out;
  std::vector<const AxisRecording*> sources;
  for (const Part& p : report)
    if (std::find(sources.begin(), sources.end(), p.source) == sources.end()) sources.push_back(p.source);
  for (const AxisRecording* r : sources) {
    ClosedLoopComparison c;
    c.recording = r->file.filename().string();
    if (!r->loop || r->joints[0].reference.empty()) {
      c.why_not = "the recording has no reference or no loop gains";
      out.push_back(c);
      continue;
    }
    AxisForwardModel base_model, ext_model;
    ForwardFriction({}, base_theta, st, &base_model);
    const bool ext_known = ForwardFriction(causes, theta, st, &ext_model);
    if (!ext_known)
      c.why_not = "the extended model's effect is not a force of (q, q') alone; base only";
    // The whole recording is simulated (the model reads only the reference and the gains) and
    // compared on its report samples.
    const ClosedLoopRun base_run = SimulateClosedLoop(*r, base_model);
    const ClosedLoopRun ext_run = ext_known ? SimulateClosedLoop(*r, ext_model) : base_run;
    ClosedLoopSums base_sums, ext_sums;
    for (const Part& p : report) {
      if (p.source != r) continue;
      base_sums.Add(CompareClosedLoopSums(p.recording, p.s.qd, border, base_run, p.begin));
      ext_sums.Add(CompareClosedLoopSums(p.recording, p.s.qd, border, ext_run, p.begin));
    }
    c.base = base_sums.Pct();
    c.extended = ext_sums.Pct();
    c.available = true;
    out.push_back(c);
  }
  return out;
}

}  // namespace

const char* AxisEffectId(AxisEffect effect) { return Model(effect).Name(); }

const std::vector<AxisEffect>& AllAxisEffects() {
  static const std::vector<AxisEffect> all{
      AxisEffect::kAsymmetricFriction, AxisEffect::kStribeckFriction,
      AxisEffect::kPositionDependentFriction, AxisEffect::kCogging,
      AxisEffect::kTransmissionCompliance, AxisEffect::kBacklash, AxisEffect::kCommandDelay};
  return all;
}

const char* AxisRoleName(AxisRole role) {
  switch (role) {
    case AxisRole::kTraining: return "training";
    case AxisRole::kSelection: return "selection";
    case AxisRole::kReport: return "report";
  }
  return "?";
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
  // Blocks start and end in motion: drop the filter border at both ends.
  IdimOptions idim = options.idim;
  if (idim.end_border_samples <= 0) idim.end_border_samples = idim.border_samples;
  Split split = MakeSplit(recordings, validation, options, idim);
  const std::vector<Part>& train = split.train;
  const std::vector<Part>& select = split.select;

  AxisDiagnosis out;
  out.joint = recordings.front().joints.front().name;
  out.blocks = split.blocks;
  for (const Part& p : train) out.training_recordings.push_back(p.name);
  for (const Part& p : select) out.selection_recordings.push_back(p.name);
  for (const Part& p : split.report) out.heldout_recordings.push_back(p.name);

  const Stroke st = StrokeOf(train);
  KeepMovingRows(options.rest_speed_fraction * st.v_peak, &split);

  // 2. Base, 3. grid parameters (training rows).
  const Eigen::VectorXd base_theta = FitOn(train, {}, st, dec);
  out.base_parameters = NameParameters({}, base_theta);
  out.base_train_relative_error_pct = SumsOn(train, {}, base_theta, st, dec).RelPct();
  const std::vector<Eigen::VectorXd> train_res = Residuals(train, {}, base_theta, st, dec);
  const std::vector<Chosen> grid_fitted =
      FitGridParameters(options.candidates, train, train_res, st, dec);

  // 4. Noise model (selection rows): the smoother on the base residual, or on the residual of
  // every candidate at once when that is lower (structure the smoother mistakes for noise,
  // e.g. the sharp pulses of a delay at each acceleration switch, is then taken out first).
  double noise_var =
      WhiteNoiseVariance(Residuals(select, {}, base_theta, st, dec), dec);
  noise_var = std::min(noise_var, WhiteNoiseVariance(Residuals(select, grid_fitted,
                                                               FitOn(train, grid_fitted, st, dec), st, dec),
                                                     dec));
  out.noise_sigma = std::sqrt(noise_var);

  // 5. Forward selection (selection rows).
  const Selection sel =
      ForwardSelect(train, select, grid_fitted, train_res, noise_var, base_theta, st, options, dec);
  out.selection_base_pct = sel.base_pct;
  out.selection_extended_pct = sel.extended_pct;
  out.selection_floor_pct = sel.floor_pct;
  const Eigen::VectorXd& theta = sel.theta.back();
  out.extended_parameters = NameParameters(sel.causes, theta);

  // 6. The report rows, read from here on only to report.
  const std::vector<Part>& report = split.report;
  ReportOnReportRows(report, sel, noise_var, st, dec, options, &out);

  FillReportSeries(report, sel.causes, base_theta, theta, st, dec, &out);

  // 7. Closed loop, compared on the report samples.
  if (options.simulate)
    out.closed_loop = CompareInClosedLoop(report, sel.causes, base_theta, theta, st,
                                          static_cast<std::size_t>(std::max(0, idim.border_samples)));
  return out;
}

}  // namespace pwsim::sysid::platform
