#include "mca/qp_problem.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>

#include "engine/input_error.h"
#include "mca/qp_active_set.h"

namespace pwsim::mca {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// The 1-based line of the first occurrence of `"key"` in the text (0 when absent).
int LineOfKey(const std::string& text, const std::string& key) {
  const std::size_t at = text.find("\"" + key + "\"");
  if (at == std::string::npos) return 0;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
}

struct Reader {
  const std::string& file;
  const std::string& text;
  const nlohmann::json& root;

  [[noreturn]] void Fail(const std::string& field, const std::string& expected, const std::string& got) const {
    throw InputError(file, LineOfKey(text, field), field, expected, got);
  }
  const nlohmann::json& Field(const std::string& field) const {
    if (!root.contains(field)) Fail(field, "present", "nothing");
    return root.at(field);
  }
  double Number(const nlohmann::json& value, const std::string& field, std::size_t i) const {
    if (!value.is_number()) Fail(field, "a number at index " + std::to_string(i), value.dump());
    const double x = value.get<double>();
    if (!std::isfinite(x)) Fail(field, "a finite number at index " + std::to_string(i), value.dump());
    return x;
  }
  Eigen::VectorXd Vector(const std::string& field) const {
    const nlohmann::json& v = Field(field);
    if (!v.is_array()) Fail(field, "a list of numbers", v.type_name());
    Eigen::VectorXd out(static_cast<Eigen::Index>(v.size()));
    for (std::size_t i = 0; i < v.size(); ++i) out(static_cast<Eigen::Index>(i)) = Number(v[i], field, i);
    return out;
  }
  Eigen::MatrixXd Matrix(const std::string& field, std::size_t cols) const {
    const nlohmann::json& v = Field(field);
    if (!v.is_array()) Fail(field, "a list of rows", v.type_name());
    Eigen::MatrixXd out(static_cast<Eigen::Index>(v.size()), static_cast<Eigen::Index>(cols));
    for (std::size_t r = 0; r < v.size(); ++r) {
      if (!v[r].is_array() || v[r].size() != cols) {
        Fail(field, "row " + std::to_string(r) + " a list of " + std::to_string(cols) + " numbers (n = size of q)",
             v[r].is_array() ? std::to_string(v[r].size()) + " entries" : v[r].dump());
      }
      for (std::size_t c = 0; c < cols; ++c) {
        out(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = Number(v[r][c], field, r * cols + c);
      }
    }
    return out;
  }
};

void WriteNumbers(const double* data, Eigen::Index count, std::ostream& out) {
  for (Eigen::Index i = 0; i < count; ++i) {
    if (i > 0) out << ' ';
    out << data[i];
  }
  out << '\n';
}

}  // namespace

QpProblem ReadQpProblemJson(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), 0, "(file)", "a readable JSON file", "cannot open it");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  nlohmann::json root;
  try {
    root = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    const std::size_t at = std::min<std::size_t>(e.byte, text.size());
    const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
    throw InputError(file.string(), line, "(document)", "valid JSON", e.what());
  }
  if (!root.is_object()) throw InputError(file.string(), 1, "(document)", "a JSON object", root.type_name());
  const Reader reader{file.string(), text, root};
  QpProblem problem;
  problem.name = root.contains("name") && root["name"].is_string() ? root["name"].get<std::string>()
                                                                    : file.stem().string();
  problem.q = reader.Vector("q");
  const auto n = static_cast<std::size_t>(problem.q.size());
  if (n == 0) reader.Fail("q", "at least one entry", "an empty list");
  problem.p = reader.Matrix("P", n);
  if (static_cast<std::size_t>(problem.p.rows()) != n) {
    reader.Fail("P", std::to_string(n) + " rows (n = size of q)", std::to_string(problem.p.rows()));
  }
  const double asymmetry = (problem.p - problem.p.transpose()).cwiseAbs().maxCoeff();
  if (asymmetry > 1e-12 * std::max(1.0, problem.p.cwiseAbs().maxCoeff())) {
    reader.Fail("P", "a symmetric matrix", "max |P - P'| = " + std::to_string(asymmetry));
  }
  problem.h = reader.Vector("h");
  problem.g = reader.Matrix("G", n);
  if (problem.g.rows() != problem.h.size()) {
    reader.Fail("G", std::to_string(problem.h.size()) + " rows (m = size of h)", std::to_string(problem.g.rows()));
  }
  return problem;
}

std::vector<std::filesystem::path> QpProblemFiles(const std::filesystem::path& dir) {
  if (!std::filesystem::is_directory(dir)) {
    throw InputError(dir.string(), 0, "(directory)", "a directory of *.json QP problems", "no such directory");
  }
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.is_regular_file() && entry.path().extension() == ".json") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

void WriteQpTextHeader(std::ostream& out) { out << "pwsim-qp-text/1\n"; }

void WriteQpProblemText(const QpProblem& problem, std::ostream& out) {
  const std::streamsize precision = out.precision(17);
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> p = problem.p, g = problem.g;
  out << "problem " << problem.name << ' ' << problem.variables() << ' ' << problem.constraints() << '\n';
  WriteNumbers(p.data(), p.size(), out);
  WriteNumbers(problem.q.data(), problem.q.size(), out);
  WriteNumbers(g.data(), g.size(), out);
  WriteNumbers(problem.h.data(), problem.h.size(), out);
  out.precision(precision);
}

QpSolution SolveQpProblem(const QpProblem& problem) {
  const int n = problem.variables(), m = problem.constraints();
  ActiveSetQp qp(problem.p, problem.g);
  const Eigen::VectorXd free_lo = Eigen::VectorXd::Constant(n, -kInf), free_hi = Eigen::VectorXd::Constant(n, kInf);
  const Eigen::VectorXd a_lo = Eigen::VectorXd::Constant(m, -kInf);
  QpSolution solution;
  solution.x = Eigen::VectorXd::Zero(n);
  solution.status = qp.Solve(problem.q, free_lo, free_hi, a_lo, problem.h, solution.x);
  Eigen::VectorXd bounds(n);
  solution.multipliers.resize(m);
  qp.Multipliers(solution.multipliers, bounds);
  return solution;
}

QpResiduals KktResiduals(const QpProblem& problem, const Eigen::VectorXd& x, const Eigen::VectorXd& multipliers) {
  QpResiduals r;
  const Eigen::VectorXd gx_h = problem.g * x - problem.h;
  const Eigen::VectorXd px = problem.p * x, gl = problem.g.transpose() * multipliers;
  r.primal = std::max(0.0, gx_h.size() > 0 ? gx_h.maxCoeff() : 0.0);
  r.dual = std::max(0.0, multipliers.size() > 0 ? -multipliers.minCoeff() : 0.0);
  r.stationarity = (px + problem.q + gl).cwiseAbs().maxCoeff();
  r.complementarity = multipliers.size() > 0 ? (multipliers.array() * gx_h.array().abs()).maxCoeff() : 0.0;
  const double scale = std::max({px.cwiseAbs().maxCoeff(), problem.q.cwiseAbs().maxCoeff(),
                                 gl.size() > 0 ? gl.cwiseAbs().maxCoeff() : 0.0});
  r.stationarity_relative = scale > 0.0 ? r.stationarity / scale : r.stationarity;
  // per row: (G x − h)_i against |h_i| + Σ_j |G_ij x_j|, the sizes the rounding of G x − h scales with
  const Eigen::VectorXd row_scale = problem.h.cwiseAbs() + problem.g.cwiseAbs() * x.cwiseAbs();
  for (Eigen::Index i = 0; i < gx_h.size(); ++i) {
    const double violation = std::max(0.0, gx_h(i));
    r.primal_relative = std::max(r.primal_relative, row_scale(i) > 0.0 ? violation / row_scale(i) : violation);
  }
  return r;
}

double ConstraintViolation(const QpProblem& problem, const Eigen::VectorXd& x) {
  if (problem.h.size() == 0) return 0.0;
  return std::max(0.0, (problem.g * x - problem.h).maxCoeff());
}

}  // namespace pwsim::mca
