// Tests of sweep/: the sweep file reader (every refusal names file, line and field), the planner
// (order, ids, overrides on copies read back by the scene loader), the task runner's outcome
// classes and exit codes, the task index from the job-array environment, the collector and the
// local engine's retry logic (with a stand-in executable, so the logic is tested apart from pwsim).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "engine/input_error.h"
#include "engine/scene.h"
#include "sweep/collect.h"
#include "sweep/engines.h"
#include "sweep/plan.h"
#include "sweep/sweep_file.h"
#include "sweep/task_runner.h"

namespace pwsim::sweep {
namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kCommands{"run", "omct", "identify", "sweep", "platform"};

/// A fresh folder for one test, removed when the test program ends.
fs::path Scratch(const std::string& name) {
  static const fs::path root = [] {
    const fs::path r = fs::temp_directory_path() / ("pwsim_sweep_test_" + std::to_string(::getpid()));
    std::atexit([] { std::error_code e; fs::remove_all(fs::temp_directory_path() /
                                                      ("pwsim_sweep_test_" + std::to_string(::getpid())), e); });
    return r;
  }();
  const fs::path dir = root / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void Write(const fs::path& file, const std::string& text) {
  fs::create_directories(file.parent_path());
  std::ofstream(file) << text;
}

std::string Read(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string Scene() { return std::string(PWSIM_SOURCE_DIR) + "/scenes/speed_cushion.yaml"; }

/// A valid sweep over the repository's speed-cushion scene, with `extra` appended.
std::string SweepText(const std::string& body) {
  return "format: pwsim-sweep/1\nname: t\ncommand: [run]\ninputs: {scene: " + Scene() + "}\n" + body;
}

const std::string kGather = "gather:\n  heave: {file: summary.json, path: peak_heave.excursion_m}\n";

TEST(Fnv1a64, MatchesThePublishedTestVectors) {
  // FNV reference test vectors (Fowler, Noll, Vo): "", "a", "foobar"
  EXPECT_EQ(Fnv1a64(""), 0xcbf29ce484222325ULL);
  EXPECT_EQ(Fnv1a64("a"), 0xaf63dc4c8601ec8cULL);
  EXPECT_EQ(Fnv1a64("foobar"), 0x85944171f73967e8ULL);
}

TEST(ArrayList, CompactsRunsOfIndices) {
  EXPECT_EQ(ArrayList({0, 1, 2, 3}), "0-3");
  EXPECT_EQ(ArrayList({7, 0, 1, 3, 9, 10}), "0-1,3,7,9-10");
  EXPECT_EQ(ArrayList({5}), "5");
}

TEST(Substitute, ReplacesPlaceholdersAndKeepsEscapedBraces) {
  EXPECT_EQ(Substitute("--seed={seed}/{out}", {{"seed", "7"}, {"out", "o"}}), "--seed=7/o");
  EXPECT_EQ(Substitute("{{literal}}", {}), "{literal}");
  EXPECT_THROW(Substitute("{nope}", {}), std::out_of_range);
  EXPECT_THROW(PlaceholdersIn("{open"), std::invalid_argument);
  EXPECT_EQ(PlaceholdersIn("a{x}b{y}"), (std::vector<std::string>{"x", "y"}));
}

struct Broken {
  std::string body;   // after format/name/command/inputs
  std::string field;  // the field the error must name
  int line;           // the line it must name
};

TEST(ReadSweepFile, RefusesEachMistakeNamingFileLineAndField) {
  const fs::path dir = Scratch("broken");
  const std::string args = "arguments: [\"{scene}\", --out, \"{out}\"]\n";
  const std::vector<Broken> cases{
      // line 5 is the first line after the header
      {args + "grid:\n  scene.drvie.speed_mps: [1]\n" + kGather, "grid.scene.drvie.speed_mps", 7},
      {args + "grid:\n  scne.drive.speed_mps: [1]\n" + kGather, "grid.scne.drive.speed_mps", 7},
      {args + "grid:\n  scene.drive.speed_mps: []\n" + kGather, "grid.scene.drive.speed_mps", 7},
      {args + "grid:\n  seed: [1, 2]\n" + kGather, "seed", 7},  // used by nothing
      {"arguments: [\"{scene}\", \"--seed={sede}\"]\ngrid:\n  seed: [1]\n" + kGather, "arguments[1]", 5},
      {args + "grid:\n  scene.occupant.head_offset_m.3: [1]\n" + kGather, "grid.scene.occupant.head_offset_m.3", 7},
      {args + "gird:\n  scene.drive.speed_mps: [1]\n" + kGather, "gird", 6},
      {args + "grid:\n  scene.drive.speed_mps: [1]\n", "gather", 0},
      {args + "grid:\n  scene.drive.speed_mps: [1]\ngather:\n  h: {file: summary.json}\n", "gather.h.path", 9},
      {args + "list:\n  - {scene.drive.speed_mps: 1}\n  - {scene.load_kg: 80}\n" + kGather, "list[1]", 8},
      {args + "grid:\n  seed: {from: 1, to: 0}\n" + kGather, "grid.seed.to", 7},
      {args + "retries: -1\ngrid:\n  scene.drive.speed_mps: [1]\n" + kGather, "retries", 6},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const fs::path file = dir / ("case" + std::to_string(i) + ".yaml");
    Write(file, SweepText(cases[i].body));
    try {
      ReadSweepFile(file, kCommands);
      ADD_FAILURE() << "case " << i << " was accepted:\n" << cases[i].body;
    } catch (const InputError& error) {
      EXPECT_EQ(error.file(), file.string()) << "case " << i;
      EXPECT_EQ(error.field(), cases[i].field) << "case " << i << ": " << error.what();
      if (cases[i].line > 0) {
        EXPECT_EQ(error.line(), cases[i].line) << "case " << i << ": " << error.what();
      }
    }
  }
}

TEST(ReadSweepFile, ChecksTheCommandAgainstTheCliAndRefusesSweepItself) {
  const fs::path dir = Scratch("command");
  for (const std::string& command : {std::string("[runn]"), std::string("[sweep, run]"), std::string("[]")}) {
    Write(dir / "s.yaml", "format: pwsim-sweep/1\nname: t\ncommand: " + command +
                              "\narguments: [--out, \"{out}\", \"{seed}\"]\ngrid: {seed: [1]}\n" + kGather);
    try {
      ReadSweepFile(dir / "s.yaml", kCommands);
      ADD_FAILURE() << command << " was accepted";
    } catch (const InputError& error) {
      EXPECT_EQ(error.field(), "command") << error.what();
      EXPECT_NE(std::string(error.what()).find("one of: run, omct"), std::string::npos) << error.what();
    }
  }
  // a command of two words whose first is known is accepted (e.g. `platform identify`)
  Write(dir / "s.yaml", "format: pwsim-sweep/1\nname: t\ncommand: platform identify\n"
                        "arguments: [--out, \"{out}\", \"--seed={seed}\"]\ngrid: {seed: {from: 1, to: 5, step: 2}}\n" +
                            kGather);
  const SweepSpec spec = ReadSweepFile(dir / "s.yaml", kCommands);
  EXPECT_EQ(spec.command, (std::vector<std::string>{"platform", "identify"}));
  ASSERT_EQ(spec.grid_values.size(), 1U);
  ASSERT_EQ(spec.grid_values[0].size(), 3U);
  EXPECT_EQ(spec.grid_values[0][2].text, "5");
}

TEST(Plan, OneTaskPerCombinationLastGridKeyFastestWithStableIds) {
  const fs::path dir = Scratch("plan");
  Write(dir / "s.yaml",
        SweepText("arguments: [\"{scene}\", --no-video, --out, \"{out}\", \"--tag={tag}\"]\n"
                  "set: {scene.drive.accel_mps2: 1.5}\n"
                  "list:\n  - {tag: a}\n  - {tag: b}\n"
                  "grid:\n  scene.drive.speed_mps: [0.5, 1.0, 1.5]\n  scene.load_kg: [80, 120]\n" +
                  std::string(kGather)));
  const SweepSpec spec = ReadSweepFile(dir / "s.yaml", kCommands);
  ASSERT_EQ(spec.TaskCount(), 12U);
  const Manifest manifest = Plan(spec, dir / "plan", false);
  ASSERT_EQ(manifest.tasks.size(), 12U);
  EXPECT_EQ(manifest.variables, (std::vector<std::string>{"tag", "scene.drive.speed_mps", "scene.load_kg"}));
  // task 5: list entry a (0), speed index 2, load index 1
  EXPECT_EQ(manifest.tasks[5].values, (std::vector<std::string>{"a", "1.5", "120"}));
  EXPECT_EQ(manifest.tasks[6].values, (std::vector<std::string>{"b", "0.5", "80"}));
  EXPECT_EQ(manifest.tasks[6].argv,
            (std::vector<std::string>{"run", "inputs/scene.yaml", "--no-video", "--out", "out", "--tag=b"}));
  std::set<std::string> ids;
  for (const Task& task : manifest.tasks) ids.insert(task.id);
  EXPECT_EQ(ids.size(), 12U);

  // the copy is a valid scene with the overrides, read back by the scene loader itself
  const pwsim::Scene scene = LoadScene(TaskDir(manifest.dir, 5) / "inputs" / "scene.yaml");
  EXPECT_DOUBLE_EQ(scene.drive.speed, 1.5);
  EXPECT_DOUBLE_EQ(scene.load_kg, 120.0);
  EXPECT_DOUBLE_EQ(scene.drive.accel, 1.5);
  const pwsim::Scene original = LoadScene(Scene());
  EXPECT_EQ(scene.terrain.x, original.terrain.x);  // the terrain path was made absolute and still loads

  // the same sweep planned again: the same manifest, ids included
  const Manifest again = Plan(ReadSweepFile(dir / "s.yaml", kCommands), dir / "plan2", false);
  for (std::size_t i = 0; i < manifest.tasks.size(); ++i) EXPECT_EQ(again.tasks[i].id, manifest.tasks[i].id);
  // read back from disk: the same tasks
  const Manifest read = ReadManifest(dir / "plan");
  ASSERT_EQ(read.tasks.size(), 12U);
  EXPECT_EQ(read.tasks[11].argv, manifest.tasks[11].argv);
  EXPECT_EQ(read.gather[0].path, (std::vector<std::string>{"peak_heave", "excursion_m"}));

  // an existing plan is not overwritten without --force
  EXPECT_THROW(Plan(spec, dir / "plan", false), InputError);
  EXPECT_NO_THROW(Plan(spec, dir / "plan", true));
}

TEST(Plan, RefusesARepeatedCombinationAndLeavesNoTaskFolders) {
  const fs::path dir = Scratch("repeat");
  Write(dir / "s.yaml", SweepText("arguments: [\"{scene}\", --out, \"{out}\"]\n"
                                  "list:\n  - {scene.load_kg: 80}\n  - {scene.load_kg: 90}\n  - {scene.load_kg: 80}\n" +
                                  std::string(kGather)));
  try {
    Plan(ReadSweepFile(dir / "s.yaml", kCommands), dir / "plan", false);
    ADD_FAILURE() << "a repeated combination was planned";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("task 2 repeats task 0"), std::string::npos) << error.what();
  }
  EXPECT_FALSE(fs::exists(dir / "plan" / "manifest.json"));
  EXPECT_FALSE(fs::exists(dir / "plan" / "tasks"));
}

/// The scene reader as the input check (pwsim sweep plan passes the CLI's, which adds mca:).
void ReadAsScene(const fs::path& file) { ParseScene(LoadYamlFile(file)); }

/// The InputError planning `body` with the scene check throws (fails the test when none), and
/// that nothing of the plan is left.
InputError PlanError(const std::string& name, const std::string& body) {
  const fs::path dir = Scratch(name);
  Write(dir / "s.yaml", SweepText("arguments: [\"{scene}\", --out, \"{out}\"]\n" + body + kGather));
  try {
    Plan(ReadSweepFile(dir / "s.yaml", kCommands), dir / "plan", false, ReadAsScene);
  } catch (const InputError& error) {
    EXPECT_FALSE(fs::exists(dir / "plan"));  // the refused plan made it and removed it
    return error;
  }
  ADD_FAILURE() << "planned:\n" << body;
  return InputError("", 0, "", "", "");
}

// Tests that every task's copy of the scene is read by the scene reader at plan time: a grid
// value "fast" for a speed and a misspelt override key (grid:, set:, list:) are refused before
// any submission, at the sweep file's line and field, with the task's copy and field named.
TEST(Plan, ChecksEveryTasksInputsWithTheReaderBeforeSubmission) {
  const InputError fast = PlanError("fast", "grid:\n  scene.drive.speed_mps: [0.5, fast, 1.5]\n");
  EXPECT_EQ(fast.line(), 7);
  EXPECT_EQ(fast.field(), "grid.scene.drive.speed_mps");
  EXPECT_EQ(fast.got(), "\"fast\"");
  EXPECT_NE(fast.expected().find("a number in (0, "), std::string::npos) << fast.what();
  EXPECT_NE(fast.expected().find("task 1's scene, "), std::string::npos) << fast.what();
  EXPECT_NE(fast.expected().find("/tasks/1/inputs/scene.yaml:"), std::string::npos) << fast.what();
  EXPECT_NE(fast.expected().find("field 'drive.speed_mps', as pwsim run reads it"), std::string::npos) << fast.what();

  const InputError key = PlanError("key", "grid:\n  scene.drive.sped_mps: [0.5, 1.0]\n");
  EXPECT_EQ(key.line(), 7);
  EXPECT_EQ(key.field(), "grid.scene.drive.sped_mps");
  EXPECT_EQ(key.got(), "unknown key \"sped_mps\"");

  const InputError set = PlanError("set", "set: {scene.drive.acel_mps2: 1.5}\ngrid:\n  scene.load_kg: [80, 90]\n");
  EXPECT_EQ(set.line(), 6);
  EXPECT_EQ(set.field(), "set.scene.drive.acel_mps2");

  const InputError list = PlanError("list", "list:\n  - {scene.load_kg: 80}\n  - {scene.load_kg: heavy}\n");
  EXPECT_EQ(list.line(), 8);
  EXPECT_EQ(list.field(), "list[1].scene.load_kg");
  EXPECT_EQ(list.got(), "\"heavy\"");
}

/// A hand-made plan whose "pwsim" is /bin/sh: each task's words are `-c SCRIPT`.
Manifest ShellPlan(const fs::path& dir, const std::vector<std::string>& scripts, double timeout_s = 0.0) {
  Manifest m;
  m.dir = dir;
  m.name = "shell";
  m.command = {"-c"};
  m.variables = {"n"};
  GatherField field;
  field.name = "b1";
  field.file = "r.json";
  field.path = {"a", "b", "1"};
  m.gather = {field};
  m.timeout_s = timeout_s;
  for (std::size_t i = 0; i < scripts.size(); ++i) {
    Task task;
    task.index = i;
    task.id = "id" + std::to_string(i);
    task.values = {std::to_string(i) + ",x"};
    task.argv = {"-c", scripts[i]};
    m.tasks.push_back(task);
  }
  return m;
}

const char* kWritesResult = "mkdir -p out && printf '{\"a\":{\"b\":[1,2.5]}}' > out/r.json";

TEST(RunTask, ClassifiesOutcomesAndWritesTheResult) {
  const fs::path dir = Scratch("run");
  const Manifest m = ShellPlan(dir, {kWritesResult, "exit 1", "kill -9 $$", "exit 3", "exit 0", "exec sleep 60"},
                               /*timeout_s=*/0.3);
  const TaskOutcome ok = RunTask(m, 0, "/bin/sh");
  EXPECT_EQ(ok.status, TaskStatus::kOk) << ok.reason;
  EXPECT_EQ(ok.fields["b1"].get<double>(), 2.5);
  EXPECT_EQ(ReadResult(dir, 0)->at("status"), "ok");

  const TaskOutcome bad = RunTask(m, 1, "/bin/sh");
  EXPECT_EQ(bad.status, TaskStatus::kBadInput);
  EXPECT_EQ(ExitCodeFor(bad.status), 65);

  const TaskOutcome killed = RunTask(m, 2, "/bin/sh");
  EXPECT_EQ(killed.status, TaskStatus::kRetryable);
  EXPECT_EQ(killed.signal, 9);
  EXPECT_EQ(ExitCodeFor(killed.status), 75);

  EXPECT_EQ(RunTask(m, 3, "/bin/sh").status, TaskStatus::kRetryable);

  const TaskOutcome no_field = RunTask(m, 4, "/bin/sh");  // succeeded, wrote nothing to gather
  EXPECT_EQ(no_field.status, TaskStatus::kBadInput);
  EXPECT_NE(no_field.reason.find("out/r.json is missing"), std::string::npos) << no_field.reason;

  const TaskOutcome slow = RunTask(m, 5, "/bin/sh");
  EXPECT_EQ(slow.status, TaskStatus::kRetryable);
  EXPECT_NE(slow.reason.find("timeout"), std::string::npos) << slow.reason;

  const TaskOutcome missing_exe = RunTask(m, 0, dir / "no-such-pwsim");
  EXPECT_EQ(missing_exe.status, TaskStatus::kRetryable);
  EXPECT_NE(missing_exe.reason.find("could not start"), std::string::npos) << missing_exe.reason;
  EXPECT_EQ(missing_exe.attempt, 2);  // the second attempt of task 0
  EXPECT_FALSE(fs::exists(TaskDir(dir, 0) / "out"));  // the first attempt's outputs were removed
  EXPECT_THROW(RunTask(m, 6, "/bin/sh"), InputError);
}

TEST(RunTask, DoesNotGatherAnEarlierAttemptsOutput) {
  const fs::path dir = Scratch("stale");
  Manifest m = ShellPlan(dir, {kWritesResult});
  ASSERT_EQ(RunTask(m, 0, "/bin/sh").status, TaskStatus::kOk);
  m.tasks[0].argv = {"-c", "exit 0"};
  EXPECT_EQ(RunTask(m, 0, "/bin/sh").status, TaskStatus::kBadInput);
}

TEST(TaskIndex, FromFlagSlurmOrOarWithOffset) {
  EXPECT_EQ(TaskIndex(4, {{"SLURM_ARRAY_TASK_ID", "9"}}), 4U);
  EXPECT_EQ(TaskIndex(std::nullopt, {{"SLURM_ARRAY_TASK_ID", "9"}, {"OAR_ARRAY_INDEX", "2"}}), 9U);
  EXPECT_EQ(TaskIndex(std::nullopt, {{"OAR_ARRAY_INDEX", "1"}}), 0U);  // OAR counts from 1
  EXPECT_EQ(TaskIndex(std::nullopt, {{"SLURM_ARRAY_TASK_ID", "3"}, {"PWSIM_SWEEP_INDEX_OFFSET", "1000"}}), 1003U);
  EXPECT_THROW(TaskIndex(std::nullopt, {}), std::invalid_argument);
  EXPECT_THROW(TaskIndex(std::nullopt, {{"SLURM_ARRAY_TASK_ID", "x"}}), std::invalid_argument);
  EXPECT_THROW(TaskIndex(std::nullopt, {{"OAR_ARRAY_INDEX", "0"}}), std::invalid_argument);
}

TEST(JsonAt, FollowsKeysAndArrayIndices) {
  const auto json = nlohmann::json::parse(R"({"a":{"b":[10,{"c":"x"}]}})");
  EXPECT_EQ(*JsonAt(json, {"a", "b", "0"}), 10);
  EXPECT_EQ(*JsonAt(json, {"a", "b", "1", "c"}), "x");
  EXPECT_FALSE(JsonAt(json, {"a", "b", "2"}));
  EXPECT_FALSE(JsonAt(json, {"a", "z"}));
  EXPECT_FALSE(JsonAt(json, {"a", "b", "0", "c"}));
}

TEST(CsvAt, FindsTheColumnOfTheFirstMatchingRowNumbersByValue) {
  const auto csv = ParseCsv("test,frequency,gain\r\nfz,0.5,1\nfz,1.0,2\n\"a,b\",1,\"say \"\"hi\"\"\"\n");
  ASSERT_EQ(csv.size(), 4U);
  EXPECT_EQ(csv[3], (std::vector<std::string>{"a,b", "1", "say \"hi\""}));
  GatherField field;
  field.file = "omct.csv";
  field.column = "gain";
  field.row = {{"test", "fz"}, {"frequency", "1"}};
  std::string why;
  EXPECT_EQ(CsvAt(csv, field, why).value_or("none"), "2");  // "1" matches "1.0"
  field.row = {{"test", "a,b"}};
  EXPECT_EQ(CsvAt(csv, field, why).value_or("none"), "say \"hi\"");
  field.row = {{"test", "fz"}, {"frequency", "3"}};
  EXPECT_FALSE(CsvAt(csv, field, why));
  EXPECT_EQ(why, "omct.csv has no row where test = fz frequency = 3");
  field.column = "phase";
  EXPECT_FALSE(CsvAt(csv, field, why));
  EXPECT_EQ(why, "omct.csv has no column 'phase'");
}

TEST(Collect, OneRowPerTaskWithMissingAndFailedListed) {
  const fs::path dir = Scratch("collect");
  const Manifest m = ShellPlan(dir, {kWritesResult, "exit 1", kWritesResult});
  RunTask(m, 0, "/bin/sh");
  RunTask(m, 1, "/bin/sh");  // task 2 never runs
  const Collection c = Collect(m);
  ASSERT_EQ(c.rows.size(), 3U);
  EXPECT_EQ(c.missing, (std::vector<std::size_t>{2}));
  EXPECT_EQ(c.failed, (std::vector<std::size_t>{1}));
  EXPECT_FALSE(c.complete());
  EXPECT_DOUBLE_EQ(c.rows[0].numbers[0], 2.5);
  EXPECT_TRUE(std::isnan(c.rows[1].numbers[0]));
  const std::string csv = ResultsCsv(c);
  EXPECT_EQ(csv,
            "index,id,status,attempts,n,b1\n"
            "0,id0,ok,1,\"0,x\",2.5\n"
            "1,id1,bad_input,1,\"1,x\",\n"
            "2,id2,missing,0,\"2,x\",\n");
  EXPECT_NE(MissingReport(c).find("task 2 (id2): missing: never run"), std::string::npos);
}

TEST(SubmitLocal, RetriesRetryableFailuresOnlyAndBoundsTheRetries) {
  const fs::path dir = Scratch("local");
  const Manifest m = ShellPlan(dir, {"", "", ""});
  // a stand-in for `pwsim sweep run DIR --index N`: task 0 ok; task 1 killed on its first run;
  // task 2 bad input. Each run is counted in runs-N.
  const fs::path fake = dir / "fake-pwsim";
  Write(fake,
        "#!/bin/sh\n"
        "d=$3; n=$5; echo run >> \"$d/runs-$n\"; runs=$(wc -l < \"$d/runs-$n\")\n"
        "ok() { mkdir -p \"$d/tasks/$n\"; echo '{\"status\":\"ok\"}' > \"$d/tasks/$n/result.json\"; exit 0; }\n"
        "case $n in 0) ok;; 1) [ \"$runs\" -ge 2 ] && ok; kill -9 $$;; 2) exit 65;; esac\n");
  fs::permissions(fake, fs::perms::owner_all);
  EngineOptions options;
  options.pwsim_exe = fake;
  options.max_parallel = 2;
  options.retries = 2;
  const SubmitReport report = SubmitLocal(m, options);
  EXPECT_EQ(report.ok, (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(report.bad_input, (std::vector<std::size_t>{2}));
  EXPECT_TRUE(report.failed.empty());
  EXPECT_EQ(Read(dir / "runs-1"), "run\nrun\n");
  EXPECT_EQ(Read(dir / "runs-2"), "run\n");  // bad input is not retried

  // a second submit runs nothing that is already ok
  const SubmitReport again = SubmitLocal(m, options);
  EXPECT_EQ(Read(dir / "runs-0"), "run\n");
  EXPECT_EQ(again.ok.size(), 2U);

  // with no retries, a killed task is reported failed
  const Manifest m2 = ShellPlan(dir / "b", {"", ""});
  options.retries = 0;
  const SubmitReport none = SubmitLocal(m2, options);
  EXPECT_EQ(none.failed, (std::vector<std::size_t>{1}));
}

TEST(SlurmBatchScript, CarriesTheSettingsAndRunsTheTaskOfTheArrayIndex) {
  Manifest m = ShellPlan("/data/sweeps/s1", {"true"});
  m.slurm.partition = "short";
  m.slurm.account = "lab";
  m.slurm.time = "00:20:00";
  m.slurm.extra = {"--qos=normal"};
  const std::string script = SlurmBatchScript(m, "/opt/pwsim/bin/pwsim");
  EXPECT_NE(script.find("#SBATCH --partition=short\n"), std::string::npos);
  EXPECT_NE(script.find("#SBATCH --account=lab\n"), std::string::npos);
  EXPECT_NE(script.find("#SBATCH --time=00:20:00\n"), std::string::npos);
  EXPECT_NE(script.find("#SBATCH --qos=normal\n"), std::string::npos);
  EXPECT_NE(script.find("#SBATCH --output=/data/sweeps/s1/slurm/logs/%A_%a.out\n"), std::string::npos);
  EXPECT_NE(script.find("exec '/opt/pwsim/bin/pwsim' sweep run '/data/sweeps/s1'\n"), std::string::npos);
}

}  // namespace
}  // namespace pwsim::sweep
