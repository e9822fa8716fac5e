// pwsim omct [--platform FILE] [--scene SCENE] [--mca washout|mpc] [--out DIR]: the Objective
// Motion Cueing Test of the MCA and platform limits (mca/omct.h), through the washout or the MPC. Writes DIR/omct.csv (test,frequency,gain,phase;
// frequency in rad/s, phase in degrees) and the Bode plot DIR/omct.png.

#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "app/commands.h"
#include "app/output_folder.h"
#include "app/progress.h"
#include "app/session_setup.h"
#include "engine/atomic_file.h"
#include "engine/number_format.h"
#include "engine/scene.h"
#include "mca/config.h"
#include "mca/omct.h"
#include "report/omct_report.h"

namespace pwsim::app {

const CommandSpec& OmctSpec() {
  static const CommandSpec spec{
      "omct",
      "pwsim omct [options]",
      "Objective Motion Cueing Test: gain and phase of the cueing chain at 12 frequencies.",
      {
          {"platform", "FILE", "-", "", "pwsim-platform/1 file (default: the scene's, else pw4dof)"},
          {"scene", "SCENE", "-", "", "take the washout (mca:) and platform sections of this scene"},
          McaAlgorithmOptionSpec(),
          OutOption("omct", "omct.csv and the Bode plot omct.png"),
          {"rate-hz", "HZ", "Hz", "1000", "MCA tick rate"},
          {"force-amplitude", "A", "m/s^2", "0.1", "input amplitude of the specific-force tests"},
          {"rate-amplitude", "A", "deg/s", "1", "input amplitude of the angular-rate tests"},
          QuietOption(),
      },
      ""};
  return spec;
}

int OmctCommand(const ParsedArgs& args) {
  if (!args.positional().empty()) throw UsageError("expected no positional arguments");
  mca::McaConfig config;
  if (args.Has("scene")) config = mca::LoadMcaConfig(LoadScene(args.Get("scene")));
  if (args.Has("platform")) {
    mca::ReadPlatformConfigFile(args.Get("platform"), config);
  }
  if (const std::optional<mca::McaAlgorithm> algorithm = McaAlgorithmOption(args)) config.algorithm = *algorithm;
  mca::OmctOptions options;
  options.rate_hz = args.GetDouble("rate-hz");
  options.force_amplitude = args.GetDouble("force-amplitude", 1e-6, 100.0);
  options.rate_amplitude = args.GetDouble("rate-amplitude", 1e-6, 1000.0) * mca::kDegToRad;
  if (!(options.rate_hz >= 50.0 && options.rate_hz <= 100000.0)) {
    throw UsageError("option --rate-hz: expected a number in [50, 100000] Hz");
  }
  if (config.algorithm == mca::McaAlgorithm::kMpc) {
    const double ticks = config.mpc.control_period * options.rate_hz;
    if (!(ticks >= 1.0 && std::abs(ticks - std::round(ticks)) < 1e-9)) {
      throw UsageError("option --rate-hz: the MPC's control period (" + FormatDouble(config.mpc.control_period) +
                       " s) must be a whole number of ticks");
    }
    if (const std::string problem = mca::CheckMpcStart(config); !problem.empty()) throw UsageError(problem);
  }
  const std::filesystem::path out_dir = OutDir(args);
  OutputFolder folder(out_dir, "omct");  // what the last command wrote there goes

  Progress progress("pwsim omct", args.Flag("quiet"));  // stages on stderr (app/progress.h)
  progress.Stage("run the tests");
  const std::vector<mca::OmctPoint> points = mca::RunOmct(config, options);
  progress.Stage("write the table and figure");

  std::ostringstream csv;
  csv << "test,frequency,gain,phase\n";
  for (const mca::OmctPoint& p : points) {
    csv << p.test << "," << FormatDouble(p.frequency) << "," << FormatDouble(p.gain) << ","
        << FormatDouble(p.phase) << "\n";
  }
  std::filesystem::create_directories(out_dir);
  WriteFileAtomically(out_dir / "omct.csv", csv.str());

  report::WriteOmctFigure(out_dir / "omct.png", std::string(config.algorithm == mca::McaAlgorithm::kMpc
                                                          ? "the model-predictive cueing (MPC)"
                                                          : "the classical washout") +
                                             " on platform " + config.platform.name,
                  points);

  progress.Finish();
  std::cout << "pwsim omct: " << mca::McaAlgorithmName(config.algorithm) << ", platform '" << config.platform.name << "', " << points.size()
            << " points (" << points.size() / 12 << " tests x 12 frequencies)\n";
  folder.Print(std::cout, "pwsim omct");
  return 0;
}

}  // namespace pwsim::app
