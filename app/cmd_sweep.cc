// pwsim sweep plan|run|submit|collect: sweeps and batches of pwsim commands on this machine or
// on a Slurm cluster (sweep/). Wiring only: the sweep file, plan, task runner, engines and
// collector are in sweep/; the plots of each swept parameter against each field are drawn here
// with plot/.

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <set>
#include <stdexcept>

#include "app/commands.h"
#include "app/progress.h"
#include "engine/atomic_file.h"
#include "engine/chair.h"
#include "engine/input_error.h"
#include "engine/scene.h"
#include "engine/vehicle/car_scene.h"
#include "engine/yaml_reader.h"
#include "mca/config.h"
#include "mca/platform.h"
#include "render/render_config.h"
#include "report/sweep_report.h"
#include "sweep/collect.h"
#include "sweep/engines.h"
#include "sweep/plan.h"
#include "sweep/sweep_file.h"
#include "sweep/task_runner.h"

namespace pwsim::app {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> KnownCommands() {
  std::vector<std::string> names;
  for (const Command& command : AllCommands()) names.push_back(command.spec->name);
  return names;
}

fs::path SelfExecutable() {
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  if (error) throw std::runtime_error("cannot find the pwsim executable (/proc/self/exe): " + error.message());
  return self;
}

void RequireOnly(const ParsedArgs& args, const std::string& sub, const std::set<std::string>& allowed) {
  for (const char* name : {"out", "force", "index", "engine", "max-parallel", "retries", "poll-s", "sbatch"}) {
    if (args.Has(name) && allowed.count(name) == 0) {
      throw UsageError("option --" + std::string(name) + " does not apply to 'sweep " + sub + "'");
    }
  }
}

/// A task's copy of an input read as the pwsim commands read it (sweep::InputCheck): a scene
/// with its engine, mca:, platform: and render: sections, a platform file, a chair file. Other
/// formats are left to the task.
void CheckTaskInput(const fs::path& file) {
  const YamlDocument document = LoadYamlFile(file);
  const YAML::Node format = document.root.IsMap() ? document.root["format"] : YAML::Node();
  if (!format || !format.IsScalar()) return;
  if (format.Scalar() == "pwsim-scene/1") {
    if (vehicle::SceneKind(document) == "car") {
      mca::LoadCarMcaConfig(vehicle::ParseCarScene(document));
      return;
    }
    const Scene scene = ParseScene(document);
    mca::LoadMcaConfig(scene);
    render::ParseRenderConfig(scene);
  } else if (format.Scalar() == "pwsim-platform/1") {
    mca::ReadPlatformFile(file);
  } else if (format.Scalar() == "pwsim-chair/1") {
    ReadChairFile(file);
  }
}

/// The swept command's options in the sweep file's arguments:, checked at plan time against the
/// command's own table (app/commands.h): an unknown option (with the suggestion pwsim would give)
/// or an option without its value is refused at its line and field, arguments[i].
/// @throws InputError.
void CheckArguments(const sweep::SweepSpec& spec) {
  const CommandSpec* command = nullptr;
  for (const Command& c : AllCommands())
    if (!spec.command.empty() && c.spec->name == spec.command.front()) command = c.spec;
  if (command == nullptr) return;  // ReadSweepFile has refused an unknown command already
  std::vector<std::string> names{"help"};
  for (const OptionSpec& option : command->options) names.push_back(option.name);
  const std::string pwsim = "pwsim " + command->name;
  for (std::size_t i = 0; i < spec.arguments.size(); ++i) {
    const std::string& word = spec.arguments[i];
    if (word.rfind("--", 0) != 0 || word == "--" || word.find('{') != std::string::npos) continue;
    const std::string name = word.substr(2, word.find('=') == std::string::npos ? std::string::npos : word.find('=') - 2);
    const int line = i < spec.argument_lines.size() ? spec.argument_lines[i] : 0;
    const std::string field = "arguments[" + std::to_string(i) + "]";
    const auto option = std::find_if(command->options.begin(), command->options.end(),
                                     [&](const OptionSpec& o) { return o.name == name; });
    if (option == command->options.end()) {
      throw InputError(spec.file.string(), line, field, "an option of " + pwsim + " (see " + pwsim + " --help)",
                       "\"" + word + "\"" + DidYouMean(name, names, "--"));
    }
    if (option->value_name.empty()) continue;
    const bool inline_value = word.find('=') != std::string::npos;
    if (!inline_value && i + 1 >= spec.arguments.size()) {
      throw InputError(spec.file.string(), line, field, "option --" + name + " followed by its value " + option->value_name,
                       "the end of the arguments");
    }
    // A literal value of a counted or timed option (value names N; S, MS, HZ) must be a number,
    // as the command will read it; a {placeholder} is the task's (its inputs are checked per task).
    const std::string value = inline_value ? word.substr(word.find('=') + 1) : spec.arguments[i + 1];
    const std::string value_field = inline_value ? field : "arguments[" + std::to_string(i + 1) + "]";
    const int value_line = inline_value || i + 1 >= spec.argument_lines.size() ? line : spec.argument_lines[i + 1];
    const std::string& kind = option->value_name;
    if (value.find('{') != std::string::npos || (kind != "N" && kind != "S" && kind != "MS" && kind != "HZ")) continue;
    double number = 0.0;
    const char* end = value.data() + value.size();
    const auto [ptr, ec] = std::from_chars(value.data(), end, number);
    if (ec != std::errc() || ptr != end || !std::isfinite(number) || (kind == "N" && number != std::floor(number))) {
      throw InputError(spec.file.string(), value_line, value_field,
                       std::string(kind == "N" ? "an integer" : "a number") + " for option --" + name + " of " + pwsim,
                       "\"" + value + "\"");
    }
  }
}

fs::path OneDir(const ParsedArgs& args, const std::string& sub) {
  if (args.positional().size() != 2) throw UsageError("usage: pwsim sweep " + sub + " DIR");
  return args.positional()[1];
}

int Plan(const ParsedArgs& args) {
  RequireOnly(args, "plan", {"out", "force"});
  if (args.positional().size() != 2) throw UsageError("usage: pwsim sweep plan SWEEP.yaml [--out DIR]");
  Progress progress("pwsim sweep plan", args.Flag("quiet"));  // stages on stderr (app/progress.h)
  progress.Stage("read the sweep file");
  const sweep::SweepSpec spec = sweep::ReadSweepFile(args.positional()[1], KnownCommands());
  CheckArguments(spec);
  progress.Stage("plan and check the tasks' inputs");
  int checked = 0;
  const sweep::Manifest manifest = sweep::Plan(spec, OutDir(args), args.Flag("force"), [&](const fs::path& input) {
    CheckTaskInput(input);
    progress.Report("plan and check the tasks' inputs", ++checked, 0);
  });
  progress.Finish();
  std::cout << "pwsim sweep plan: '" << manifest.name << "': " << manifest.tasks.size() << " tasks of 'pwsim";
  for (const auto& word : manifest.command) std::cout << " " << word;
  std::cout << "'\n  " << (manifest.dir / "manifest.json").string() << "\n  "
            << (manifest.dir / "tasks").string() << "/0.." << manifest.tasks.size() - 1 << "\n";
  return 0;
}

int Run(const ParsedArgs& args) {
  RequireOnly(args, "run", {"index"});
  const fs::path dir = OneDir(args, "run");
  std::optional<long long> flag;
  if (args.Has("index")) flag = args.GetInt("index");
  const std::size_t index = sweep::TaskIndex(flag, sweep::IndexEnvironment());
  sweep::Manifest manifest;
  try {
    manifest = sweep::ReadManifest(dir);
  } catch (const InputError& error) {
    std::cerr << "pwsim sweep run: error: " << error.what() << "\n";
    return sweep::kExitBadInput;
  }
  if (index >= manifest.tasks.size()) {
    std::cerr << "pwsim sweep run: error: task " << index << " is not in the plan (" << manifest.tasks.size()
              << " tasks)\n";
    return sweep::kExitBadInput;
  }
  Progress progress("pwsim sweep run", args.Flag("quiet"));  // stages on stderr (app/progress.h)
  progress.Stage("task " + std::to_string(index) + " (" + manifest.tasks[index].id + "): pwsim " +
                 (manifest.command.empty() ? std::string() : manifest.command.front()));
  const sweep::TaskOutcome outcome = sweep::RunTask(manifest, index, SelfExecutable());
  progress.Finish();
  std::cout << "pwsim sweep run: task " << index << " (" << manifest.tasks[index].id << "), attempt "
            << outcome.attempt << ": " << sweep::StatusName(outcome.status)
            << (outcome.reason.empty() ? "" : ": " + outcome.reason) << "\n";
  return sweep::ExitCodeFor(outcome.status);
}

int Submit(const ParsedArgs& args) {
  RequireOnly(args, "submit", {"engine", "max-parallel", "retries", "poll-s", "sbatch"});
  const fs::path dir = OneDir(args, "submit");
  const std::string engine = args.Get("engine");
  if (engine != "local" && engine != "slurm") {
    throw UsageError("option --engine: expected local or slurm, got \"" + engine + "\"");
  }
  const sweep::Manifest manifest = sweep::ReadManifest(dir);
  sweep::EngineOptions options;
  options.pwsim_exe = SelfExecutable();
  options.max_parallel = static_cast<int>(args.GetInt("max-parallel"));
  if (options.max_parallel < 0) throw UsageError("option --max-parallel: expected an integer >= 0");
  if (args.Has("retries")) {
    options.retries = static_cast<int>(args.GetInt("retries"));
    if (options.retries < 0 || options.retries > 100) {
      throw UsageError("option --retries: expected an integer in [0, 100]");
    }
  }
  options.poll_s = args.GetDouble("poll-s");
  if (!(options.poll_s >= 0.01 && options.poll_s <= 3600.0)) {
    throw UsageError("option --poll-s: expected a number in [0.01, 3600] s");
  }
  if (args.Has("sbatch")) {
    std::string word;
    for (char c : args.Get("sbatch") + " ") {
      if (c == ' ') {
        if (!word.empty()) options.sbatch_options.push_back(word);
        word.clear();
      } else {
        word += c;
      }
    }
  }
  Progress progress("pwsim sweep submit", args.Flag("quiet"));  // stages on stderr (app/progress.h)
  ProgressLog log(progress, std::cout);  // the engine's lines on stdout, never on the progress line
  options.log = &log;
  options.progress = progress.callback();
  const sweep::SubmitReport report =
      engine == "slurm" ? sweep::SubmitSlurm(manifest, options) : sweep::SubmitLocal(manifest, options);
  progress.Finish();
  std::cout << "pwsim sweep submit: " << report.ok.size() << " of " << manifest.tasks.size() << " tasks ok";
  if (!report.bad_input.empty()) std::cout << ", bad input: " << sweep::ArrayList(report.bad_input);
  if (!report.failed.empty()) std::cout << ", failed after retries: " << sweep::ArrayList(report.failed);
  std::cout << " (results in " << (manifest.dir / "tasks").string() << "/N/result.json)\n";
  return report.complete() ? 0 : 1;
}


int Collect(const ParsedArgs& args) {
  RequireOnly(args, "collect", {});
  const sweep::Manifest manifest = sweep::ReadManifest(OneDir(args, "collect"));
  // outputs of an earlier collection go first
  fs::remove(manifest.dir / "results.csv");
  fs::remove(manifest.dir / "missing.txt");
  fs::remove_all(manifest.dir / "plots");
  const sweep::Collection collection = sweep::Collect(manifest);
  WriteFileAtomically(manifest.dir / "results.csv", sweep::ResultsCsv(collection));
  std::cout << "pwsim sweep collect: '" << manifest.name << "': "
            << collection.rows.size() - collection.missing.size() - collection.failed.size() << " of "
            << collection.rows.size() << " tasks ok\n  " << (manifest.dir / "results.csv").string() << "\n";
  for (const fs::path& png : report::WriteSweepPlots(manifest, collection)) std::cout << "  " << png.string() << "\n";
  if (collection.complete()) return 0;
  WriteFileAtomically(manifest.dir / "missing.txt", sweep::MissingReport(collection));
  std::cout << "  " << (manifest.dir / "missing.txt").string() << "\n";
  if (!collection.missing.empty()) std::cout << "missing tasks: " << sweep::ArrayList(collection.missing) << "\n";
  if (!collection.failed.empty()) std::cout << "failed tasks: " << sweep::ArrayList(collection.failed) << "\n";
  std::cout << sweep::MissingReport(collection);
  return 1;
}

}  // namespace

const CommandSpec& SweepSpec() {
  static const CommandSpec spec{
      "sweep",
      "pwsim sweep plan SWEEP.yaml [--out DIR] | run DIR [--index N] | submit DIR [--engine E] | collect DIR",
      "Sweeps and batches: plan a sweep file into tasks, run them locally or as a Slurm job array, collect.",
      {
          OutOption("sweep", "plan: the sweep folder (manifest.json, tasks/N/), new or empty"),
          {"force", "", "-", "", "plan: replace the plan and results already in DIR"},
          {"index", "N", "-", "", "run: the task (default: SLURM_ARRAY_TASK_ID, else OAR_ARRAY_INDEX - 1)"},
          {"engine", "E", "-", "local", "submit: local (this machine's cores) or slurm (sbatch --array)"},
          {"max-parallel", "K", "tasks", "0", "submit: tasks at a time (0: local = cores, slurm = no limit)"},
          {"retries", "R", "-", "", "submit: resubmissions of a failed task (default: the sweep file's)"},
          {"poll-s", "S", "s", "10", "submit --engine slurm: time between squeue queries"},
          {"sbatch", "\"OPTS\"", "-", "", "submit --engine slurm: more sbatch options (space separated)"},
          QuietOption(),
      },
      "plan SWEEP.yaml  validate a pwsim-sweep/1 file and write DIR/manifest.json, DIR/tasks/N/\n"
      "run DIR          run one task; exit 0 ok, 65 bad input, 75 retryable failure\n"
      "submit DIR       run every task not yet ok; resubmit retryable failures\n"
      "collect DIR      DIR/results.csv, DIR/plots/, DIR/missing.txt; exit 1 while any task is not ok"};
  return spec;
}

int SweepCommand(const ParsedArgs& args) {
  if (args.positional().empty()) throw UsageError("expected plan, run, submit or collect");
  const std::string& sub = args.positional()[0];
  if (sub == "plan") return Plan(args);
  if (sub == "run") return Run(args);
  if (sub == "submit") return Submit(args);
  if (sub == "collect") return Collect(args);
  throw UsageError("unknown sweep command '" + sub + "'" + DidYouMean(sub, {"plan", "run", "submit", "collect"}) +
                   " (expected plan, run, submit or collect)");
}

}  // namespace pwsim::app
