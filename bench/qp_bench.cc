// qp_bench: pwsim's dual active set (mca/qp_active_set.h) on a directory of QPs in the benchmark
// form  min ½ xᵀPx + qᵀx  s.t.  Gx ≤ h  (mca/qp_problem.h; the MPC set in ../shared/data/qp-mpc),
// then R's quadprog on the same problems on the same machine in the same run.
//
//   qp_bench DIR [--batches B] [--per-batch K] [--no-reference]
//
// Prints, after '#' comment lines that say what is measured:
//   one line per problem for pwsim:     NAME STATUS OBJECTIVE SECONDS
//   the same for quadprog (R):          NAME STATUS OBJECTIVE SECONDS
//   per problem:                        detail NAME n m PWSIM_STEPS QUADPROG_ITERATIONS
//   summary lines (counts optimal, median / max seconds, the quadprog/pwsim time ratio, the
//   largest relative objective difference).
// STATUS is `optimal` when solved (else infeasible, iteration_limit, error:...). SECONDS: the
// median over B batches (default 15) of the mean time of K (default 20) cold solves:
//   pwsim     an ActiveSetQp constructed (Cholesky of P, L⁻ᵀ, a copy of G, its row norms) and one
//             Solve from the unconstrained minimum; steady_clock in this process;
//   quadprog  solve.QP(P, −q, −Gᵀ, −h) inside one R process (argument checks, Cholesky of P,
//             solve), Sys.time around each batch; R's start-up and reading excluded
//             (scripts/qp-quadprog.R).
// The inputs of both are prepared outside the timed calls. scripts/qp-bench.sh turns this
// output into the table of docs/qp.md.

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "engine/input_error.h"
#include "mca/qp_active_set.h"
#include "mca/qp_problem.h"

namespace {

namespace fs = std::filesystem;
using pwsim::mca::ActiveSetQp;
using pwsim::mca::QpProblem;
using pwsim::mca::QpStatus;
using Clock = std::chrono::steady_clock;

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Result {
  std::string status{"error:not_run"};
  double objective{NAN};
  double seconds{NAN};
  std::string iterations{"NA"};
};

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

std::string StatusName(const QpStatus& s) {
  if (s.ok) return "optimal";
  if (s.termination == -3) return "infeasible";
  if (s.termination == -4) return "iteration_limit";
  return "error:termination_" + std::to_string(s.termination);
}

/// One cold solve: what the timing repeats.
QpStatus ColdSolve(const QpProblem& p, const Eigen::VectorXd& free_lo, const Eigen::VectorXd& free_hi,
                   const Eigen::VectorXd& a_lo, Eigen::VectorXd& x) {
  ActiveSetQp qp(p.p, p.g);
  return qp.Solve(p.q, free_lo, free_hi, a_lo, p.h, x);
}

Result RunPwsim(const QpProblem& p, int batches, int per_batch) {
  const int n = p.variables(), m = p.constraints();
  const Eigen::VectorXd free_lo = Eigen::VectorXd::Constant(n, -kInf), free_hi = Eigen::VectorXd::Constant(n, kInf);
  const Eigen::VectorXd a_lo = Eigen::VectorXd::Constant(m, -kInf);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  const QpStatus status = ColdSolve(p, free_lo, free_hi, a_lo, x);
  Result r;
  r.status = StatusName(status);
  r.iterations = std::to_string(status.iterations);
  if (!status.ok) return r;
  r.objective = p.Objective(x);
  std::vector<double> per_call;
  Eigen::VectorXd y(n);
  for (int b = 0; b < batches; ++b) {
    const Clock::time_point start = Clock::now();
    for (int k = 0; k < per_batch; ++k) {
      if (!ColdSolve(p, free_lo, free_hi, a_lo, y).ok) std::abort();  // solved above: same numbers
    }
    per_call.push_back(std::chrono::duration<double>(Clock::now() - start).count() / per_batch);
  }
  r.seconds = Median(per_call);
  return r;
}

int RunShell(const std::string& command) {
  const int status = std::system(command.c_str());
  if (status == -1) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// quadprog's results by problem name; empty (with a reason on stderr) when R can't run it.
std::map<std::string, Result> RunQuadprog(const std::vector<QpProblem>& problems, int batches, int per_batch,
                                          std::string* version) {
  std::map<std::string, Result> out;
  if (RunShell("Rscript -e 'suppressPackageStartupMessages(library(quadprog))' > /dev/null 2>&1") != 0) {
    std::cerr << "qp_bench: Rscript with the quadprog package not found (Debian r-base-core, r-cran-quadprog; "
                 "scripts/install-deps.sh): no reference\n";
    return out;
  }
  char name[] = "/tmp/pwsim_qp_bench_XXXXXX";
  if (mkdtemp(name) == nullptr) {
    std::cerr << "qp_bench: cannot create a temporary directory\n";
    return out;
  }
  const fs::path dir = name, in = dir / "problems.txt", result = dir / "quadprog.txt", about = dir / "version.txt";
  {
    std::ofstream text(in);
    pwsim::mca::WriteQpTextHeader(text);
    for (const QpProblem& p : problems) pwsim::mca::WriteQpProblemText(p, text);
  }
  const fs::path script = fs::path(PWSIM_SOURCE_DIR) / "scripts" / "qp-quadprog.R";
  const std::string command = "Rscript '" + script.string() + "' '" + in.string() + "' '" + result.string() + "' " +
                              std::to_string(batches) + " " + std::to_string(per_batch);
  if (RunShell(command) != 0) {
    std::cerr << "qp_bench: " << command << " failed\n";
  } else {
    std::ifstream lines(result);
    std::string line;
    while (std::getline(lines, line)) {
      std::istringstream fields(line);
      std::string problem, objective, seconds;
      Result r;
      fields >> problem >> r.status >> objective >> seconds >> r.iterations;
      if (objective != "NA") r.objective = std::stod(objective);
      if (seconds != "NA") r.seconds = std::stod(seconds);
      out[problem] = r;
    }
    RunShell("Rscript -e 'cat(R.version.string, \"quadprog\", as.character(packageVersion(\"quadprog\")))' > '" +
             about.string() + "' 2>/dev/null");
    std::ifstream text(about);
    std::getline(text, *version);
  }
  fs::remove_all(dir);
  return out;
}

void PrintLine(const std::string& name, const Result& r) {
  std::printf("%s %s %.17g %.6e\n", name.c_str(), r.status.c_str(), r.objective, r.seconds);
}

struct Summary {
  int optimal{0};
  double median{NAN}, max{NAN};
};
Summary Summarise(const std::vector<Result>& results) {
  Summary s;
  std::vector<double> times;
  for (const Result& r : results) {
    if (r.status != "optimal") continue;
    ++s.optimal;
    times.push_back(r.seconds);
  }
  if (!times.empty()) {
    s.median = Median(times);
    s.max = *std::max_element(times.begin(), times.end());
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  fs::path dir;
  int batches = 15, per_batch = 20;
  bool reference = true;
  for (int k = 1; k < argc; ++k) {
    const std::string arg = argv[k];
    if (arg == "--batches" && k + 1 < argc) {
      batches = std::max(1, std::atoi(argv[++k]));
    } else if (arg == "--per-batch" && k + 1 < argc) {
      per_batch = std::max(1, std::atoi(argv[++k]));
    } else if (arg == "--no-reference") {
      reference = false;
    } else if (!arg.empty() && arg[0] != '-' && dir.empty()) {
      dir = arg;
    } else {
      std::cerr << "usage: qp_bench DIR [--batches B] [--per-batch K] [--no-reference]\n";
      return 2;
    }
  }
  if (dir.empty()) {
    std::cerr << "usage: qp_bench DIR [--batches B] [--per-batch K] [--no-reference]\n";
    return 2;
  }
  std::vector<QpProblem> problems;
  try {
    for (const fs::path& file : pwsim::mca::QpProblemFiles(dir)) problems.push_back(pwsim::mca::ReadQpProblemJson(file));
  } catch (const pwsim::InputError& e) {
    std::cerr << "qp_bench: " << e.what() << "\n";
    return 2;
  }
  if (problems.empty()) {
    std::cerr << "qp_bench: no *.json problems in " << dir << "\n";
    return 2;
  }

  std::printf("# qp_bench: %zu problems from %s\n", problems.size(), dir.string().c_str());
  std::printf("# SECONDS: median over %d batches of the mean of %d cold solves\n", batches, per_batch);
  std::printf("# pwsim ActiveSetQp: constructor (Cholesky of P, L^-T, a copy of G and its row norms) + Solve; steady_clock\n");
  std::vector<Result> ours;
  for (const QpProblem& p : problems) {
    ours.push_back(RunPwsim(p, batches, per_batch));
    PrintLine(p.name, ours.back());
  }

  std::string version;
  const std::map<std::string, Result> theirs =
      reference ? RunQuadprog(problems, batches, per_batch, &version) : std::map<std::string, Result>{};
  std::vector<Result> quadprog;
  if (!theirs.empty()) {
    std::printf("# quadprog (%s): solve.QP inside R, Sys.time per batch; R start-up and reading excluded\n",
                version.c_str());
    for (const QpProblem& p : problems) {
      const auto it = theirs.find(p.name);
      quadprog.push_back(it != theirs.end() ? it->second : Result{});
      PrintLine(p.name, quadprog.back());
    }
  }
  std::printf("# detail NAME n m PWSIM_STEPS QUADPROG_ITERATIONS (pwsim: constraints added + dropped;"
              " quadprog: its count, which starts at 1)\n");
  for (std::size_t i = 0; i < problems.size(); ++i) {
    std::printf("detail %s %d %d %s %s\n", problems[i].name.c_str(), problems[i].variables(),
                problems[i].constraints(), ours[i].iterations.c_str(),
                quadprog.empty() ? "NA" : quadprog[i].iterations.c_str());
  }

  const Summary a = Summarise(ours);
  std::printf("summary pwsim %d/%zu optimal, median %.3e s, max %.3e s\n", a.optimal, problems.size(), a.median, a.max);
  if (!quadprog.empty()) {
    const Summary b = Summarise(quadprog);
    std::vector<double> ratios;
    double worst_objective = 0.0;
    for (std::size_t i = 0; i < problems.size(); ++i) {
      if (ours[i].status != "optimal" || quadprog[i].status != "optimal") continue;
      ratios.push_back(quadprog[i].seconds / ours[i].seconds);
      worst_objective = std::max(worst_objective, std::abs(ours[i].objective - quadprog[i].objective) /
                                                      std::max(1.0, std::abs(quadprog[i].objective)));
    }
    std::printf("summary quadprog %d/%zu optimal, median %.3e s, max %.3e s\n", b.optimal, problems.size(), b.median,
                b.max);
    if (!ratios.empty()) {
      std::printf("summary ratio quadprog/pwsim per problem: median %.2f, min %.2f, max %.2f; "
                  "largest relative objective difference %.2e\n",
                  Median(ratios), *std::min_element(ratios.begin(), ratios.end()),
                  *std::max_element(ratios.begin(), ratios.end()), worst_objective);
    }
  }
  return a.optimal == static_cast<int>(problems.size()) ? 0 : 1;
}
