// Axis recordings: YAML + CSV and YAML + MAT round trips, EMPS .mat read through libmatio, and
// every kind of bad input named with its file, variable/column and what was expected.
#include "sysid/platform/axis_recording.h"

#include <gtest/gtest.h>
#include <matio.h>

#include <cmath>
#include <fstream>
#include <limits>

#include "engine/input_error.h"
#include "tests/sysid/platform/emps_data.h"

namespace pwsim::sysid::platform {
namespace {

namespace fs = std::filesystem;

class AxisRecordingTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(PWSIM_BINARY_DIR) / "test-axis-recording" /
           ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void Write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
  }
  // A small valid CSV: t, x (position), r (reference), u (command).
  void WriteCsv(const std::string& name, int n, double dt = 0.001) {
    std::ofstream o(dir_ / name);
    o << "# a comment\nt,x,r,u\n";
    for (int i = 0; i < n; ++i)
      o << i * dt << "," << std::sin(i * 0.01) << "," << std::sin(i * 0.01 + 0.1) << ","
        << 0.5 * i << "\n";
  }
  std::string Yaml(const std::string& data, const std::string& joint_extra = "",
                   const std::string& kind = "prismatic") {
    return "format: pwsim-axis-trial/1\ndata: " + data +
           "\ntime: t\nexperiment: excitation\njoints:\n  - name: rail\n    kind: " + kind +
           "\n    position: x\n    reference: r\n    command: u\n    command_to_effort: {value: 2.0}\n" +
           joint_extra;
  }
  // Expects an InputError whose message contains every fragment.
  void ExpectError(const fs::path& file, const std::vector<std::string>& fragments) {
    try {
      ReadAxisRecording(file);
      FAIL() << "no error for " << file;
    } catch (const InputError& e) {
      for (const auto& f : fragments)
        EXPECT_NE(std::string(e.what()).find(f), std::string::npos) << e.what() << " lacks " << f;
    }
  }
  fs::path dir_;
};

TEST_F(AxisRecordingTest, CsvThroughYamlRoundTrips) {
  WriteCsv("run.csv", 200);
  Write("run.yaml", Yaml("{file: run.csv, format: csv}"));
  const AxisRecording r = ReadAxisRecording(dir_ / "run.yaml");
  ASSERT_EQ(r.size(), 200u);
  EXPECT_NEAR(r.dt, 0.001, 1e-12);
  ASSERT_EQ(r.joints.size(), 1u);
  EXPECT_EQ(r.joints[0].name, "rail");
  EXPECT_DOUBLE_EQ(r.joints[0].effort[10], 2.0 * 5.0);
  // Written back and read again: the same samples.
  WriteAxisRecordingCsv(r, dir_ / "copy.yaml");
  const AxisRecording c = ReadAxisRecording(dir_ / "copy.yaml");
  ASSERT_EQ(c.size(), r.size());
  EXPECT_EQ(c.joints[0].position, r.joints[0].position);
  EXPECT_EQ(c.joints[0].reference, r.joints[0].reference);
  EXPECT_EQ(c.joints[0].effort, r.joints[0].effort);
}

TEST_F(AxisRecordingTest, MatThroughYamlWithLibmatio) {
  // A v5 file written with libmatio itself (variables x, r, u, t, g).
  const int n = 100;
  std::vector<double> t(n), x(n), u(n);
  for (int i = 0; i < n; ++i) {
    t[static_cast<std::size_t>(i)] = i * 0.002;
    x[static_cast<std::size_t>(i)] = 0.001 * i;
    u[static_cast<std::size_t>(i)] = 1.0;
  }
  double g = 3.0;
  mat_t* mat = Mat_CreateVer((dir_ / "run.mat").c_str(), nullptr, MAT_FT_MAT5);
  ASSERT_NE(mat, nullptr);
  auto put = [&](const char* name, double* data, std::size_t rows) {
    std::size_t dims[2] = {rows, 1};
    matvar_t* v = Mat_VarCreate(name, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, data, 0);
    Mat_VarWrite(mat, v, MAT_COMPRESSION_ZLIB);
    Mat_VarFree(v);
  };
  put("t", t.data(), n);
  put("x", x.data(), n);
  put("u", u.data(), n);
  put("g", &g, 1);
  Mat_Close(mat);
  Write("run.yaml",
        "format: pwsim-axis-trial/1\ndata: {file: run.mat, format: mat}\ntime: t\njoints:\n"
        "  - {name: a, kind: revolute, position: x, command: u, command_to_effort: {variable: g}}\n");
  const AxisRecording r = ReadAxisRecording(dir_ / "run.yaml");
  ASSERT_EQ(r.size(), 100u);
  EXPECT_EQ(r.joints[0].kind, JointKind::kRevolute);
  EXPECT_TRUE(r.joints[0].reference.empty());
  EXPECT_DOUBLE_EQ(r.joints[0].effort[5], 3.0);
  // The same file with a variable that is not there.
  Write("bad.yaml",
        "format: pwsim-axis-trial/1\ndata: {file: run.mat, format: mat}\ntime: t\njoints:\n"
        "  - {name: a, kind: revolute, position: qm, command: u, command_to_effort: {value: 1}}\n");
  ExpectError(dir_ / "bad.yaml", {"run.mat", "qm", "a variable named"});
}

TEST_F(AxisRecordingTest, EmpsMatReadDirectly) {
  PWSIM_REQUIRE_EMPS();
  const AxisRecording r = ReadAxisRecording(test::EmpsDir() / "DATA_EMPS.mat");
  ASSERT_EQ(r.size(), 24841u);
  EXPECT_NEAR(r.dt, 0.001, 1e-6);
  EXPECT_NEAR(r.joints[0].command_to_effort, 35.150652, 1e-5);
  ASSERT_TRUE(r.loop.has_value());
  EXPECT_NEAR(r.loop->kp, 160.18, 1e-9);
  EXPECT_NEAR(r.loop->kv, 243.45, 1e-9);
}

TEST_F(AxisRecordingTest, NonUniformTimeIsNamed) {
  std::ofstream o(dir_ / "run.csv");
  o << "t,x,r,u\n";
  for (int i = 0; i < 50; ++i) o << (i < 30 ? i * 0.001 : i * 0.001 + 0.0005) << ",0,0,0\n";
  o.close();
  Write("run.yaml", Yaml("{file: run.csv, format: csv}"));
  ExpectError(dir_ / "run.yaml", {"run.csv:32:", "time ('t')", "uniform sampling", "sample 31"});
}

TEST_F(AxisRecordingTest, NanIsNamed) {
  std::ofstream o(dir_ / "run.csv");
  o << "t,x,r,u\n";
  for (int i = 0; i < 50; ++i) o << i * 0.001 << "," << (i == 7 ? "nan" : "0") << ",0,0\n";
  o.close();
  Write("run.yaml", Yaml("{file: run.csv, format: csv}"));
  ExpectError(dir_ / "run.yaml", {"run.csv:9:", "position", "'x'", "finite", "sample 8"});
}

TEST_F(AxisRecordingTest, MissingColumnAndRaggedRowAreNamed) {
  WriteCsv("run.csv", 50);
  Write("run.yaml",
        "format: pwsim-axis-trial/1\ndata: {file: run.csv, format: csv}\ntime: t\njoints:\n"
        "  - {name: a, kind: prismatic, position: pos, command: u, command_to_effort: {value: 1}}\n");
  ExpectError(dir_ / "run.yaml", {"run.csv", "'pos'", "a column named"});
  std::ofstream(dir_ / "ragged.csv") << "t,x,r,u\n0,1,2,3\n0.001,1,2\n";
  Write("ragged.yaml", Yaml("{file: ragged.csv, format: csv}"));
  ExpectError(dir_ / "ragged.yaml", {"ragged.csv:3", "4 comma-separated values"});
}

TEST_F(AxisRecordingTest, MismatchedLengthsAreNamed) {
  const int n = 60;
  std::vector<double> t(n), x(n - 5), u(n);
  for (int i = 0; i < n; ++i) t[static_cast<std::size_t>(i)] = i * 0.001;
  mat_t* mat = Mat_CreateVer((dir_ / "short.mat").c_str(), nullptr, MAT_FT_MAT5);
  ASSERT_NE(mat, nullptr);
  for (auto [name, v] : {std::pair{"t", &t}, std::pair{"x", &x}, std::pair{"u", &u}}) {
    std::size_t dims[2] = {v->size(), 1};
    matvar_t* m = Mat_VarCreate(name, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, v->data(), 0);
    Mat_VarWrite(mat, m, MAT_COMPRESSION_NONE);
    Mat_VarFree(m);
  }
  Mat_Close(mat);
  Write("run.yaml",
        "format: pwsim-axis-trial/1\ndata: {file: short.mat, format: mat}\ntime: t\njoints:\n"
        "  - {name: a, kind: prismatic, position: x, command: u, command_to_effort: {value: 1}}\n");
  ExpectError(dir_ / "run.yaml", {"short.mat", "'x'", "60 samples", "55"});
}

TEST_F(AxisRecordingTest, UnknownJointKindIsNamed) {
  WriteCsv("run.csv", 50);
  Write("run.yaml", Yaml("{file: run.csv, format: csv}", "", "spherical"));
  ExpectError(dir_ / "run.yaml", {"run.yaml", "joints[0].kind", "spherical"});
}

TEST_F(AxisRecordingTest, CsvWithoutDescriptionIsRefused) {
  WriteCsv("run.csv", 50);
  ExpectError(dir_ / "run.csv", {"run.csv", ".yaml"});
}

// Tests an empty .mat and .mat files cut short (uncompressed and compressed v5, and the real
// EMPS file when present): each named as such, never as "no variable 't'".
TEST_F(AxisRecordingTest, EmptyAndTruncatedMatAreNamed) {
  std::ofstream(dir_ / "empty.mat").close();
  ExpectError(dir_ / "empty.mat", {"empty.mat", "an empty file (0 bytes)"});
  const int n = 400;
  std::vector<double> t(n), x(n), u(n);
  for (int i = 0; i < n; ++i) {
    t[static_cast<std::size_t>(i)] = i * 0.001;
    x[static_cast<std::size_t>(i)] = std::sin(0.37 * i);
    u[static_cast<std::size_t>(i)] = std::cos(0.11 * i);
  }
  for (const auto compression : {MAT_COMPRESSION_NONE, MAT_COMPRESSION_ZLIB}) {
    const fs::path whole = dir_ / "whole.mat";
    mat_t* mat = Mat_CreateVer(whole.c_str(), nullptr, MAT_FT_MAT5);
    ASSERT_NE(mat, nullptr);
    for (auto [name, v] : {std::pair{"t", &t}, std::pair{"qm", &x}, std::pair{"vir", &u}}) {
      std::size_t dims[2] = {v->size(), 1};
      matvar_t* m = Mat_VarCreate(name, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, v->data(), 0);
      Mat_VarWrite(mat, m, compression);
      Mat_VarFree(m);
    }
    Mat_Close(mat);
    const auto size = fs::file_size(whole);
    for (const double share : {0.2, 0.5, 0.9}) {
      const fs::path cut = dir_ / "cut.mat";
      fs::copy_file(whole, cut, fs::copy_options::overwrite_existing);
      fs::resize_file(cut, static_cast<std::uintmax_t>(share * static_cast<double>(size)));
      ExpectError(cut, {"cut.mat", "a complete MATLAB v5 .mat file", "a truncated file", "cut short"});
    }
  }
  if (fs::exists(test::EmpsDir() / "DATA_EMPS.mat")) {
    fs::copy_file(test::EmpsDir() / "DATA_EMPS.mat", dir_ / "emps_cut.mat");
    fs::permissions(dir_ / "emps_cut.mat", fs::perms::owner_write, fs::perm_options::add);
    fs::resize_file(dir_ / "emps_cut.mat", fs::file_size(dir_ / "emps_cut.mat") / 2);
    ExpectError(dir_ / "emps_cut.mat", {"emps_cut.mat", "a truncated file"});
  }
}

// Tests that a directory named as the recording or its data file says it is a directory.
TEST_F(AxisRecordingTest, DirectoryWhereAFileBelongsIsNamed) {
  fs::create_directories(dir_ / "data.mat");
  ExpectError(dir_ / "data.mat", {"data.mat", "a path that is a directory"});
  fs::create_directories(dir_ / "run.csv");
  Write("run.yaml", Yaml("{file: run.csv, format: csv}"));
  ExpectError(dir_ / "run.yaml", {"run.csv", "a path that is a directory"});
}

}  // namespace
}  // namespace pwsim::sysid::platform
