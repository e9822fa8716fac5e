#include "sysid/measured/mocap.h"

#include <gtest/gtest.h>

#include <cmath>

#include "engine/input_error.h"
#include "tests/sysid/measured/test_files.h"

namespace pwsim {
namespace {

using testing::ScratchDir;
using testing::WriteText;

/// Runs `read` and returns the InputError it throws (fails the test if none).
template <typename Read>
InputError ExpectInputError(Read read) {
  try {
    read();
  } catch (const InputError& error) {
    return error;
  }
  ADD_FAILURE() << "no InputError thrown";
  return InputError("", 0, "", "", "");
}

// A hand-written file in the exact QTM 6D TSV layout: KEY<TAB>value header lines, the column
// line, rows ending with a trailing tab. Frame 3 is untracked (NaN). The Euler "Pitch" column
// deliberately disagrees with Rot[]: pitch must come from the rotation matrix.
// Rows: θ = 0, θ = 0.1 rad (Rot: cos .1 = 0.995004165, sin .1 = 0.0998334166), NaN, θ = -0.05.
const char* kQtmFile =
    "NO_OF_FRAMES\t4\n"
    "NO_OF_CAMERAS\t12\n"
    "NO_OF_BODIES\t2\n"
    "FREQUENCY\t100\n"
    "NO_OF_ANALOG\t0\n"
    "ANALOG_FREQUENCY\t0\n"
    "DESCRIPTION\t--\n"
    "TIME_STAMP\t2023-03-01, 10:12:33\t1234.56789\n"
    "DATA_INCLUDED\t6D\n"
    "BODY_NAMES\thead\twheelchair\n"
    "Frame\tTime\thead X\tY\tZ\tRoll\tPitch\tYaw\tResidual\tRot[0]\tRot[1]\tRot[2]\tRot[3]\tRot[4]"
    "\tRot[5]\tRot[6]\tRot[7]\tRot[8]\twheelchair X\tY\tZ\tRoll\tPitch\tYaw\tResidual\tRot[0]"
    "\tRot[1]\tRot[2]\tRot[3]\tRot[4]\tRot[5]\tRot[6]\tRot[7]\tRot[8]\t\n"
    "1\t0.00000\t1.0\t2.0\t1200.0\t0\t0\t0\t0.5\t1\t0\t0\t0\t1\t0\t0\t0\t1"
    "\t-1500.00000\t12.50000\t310.00000\t0.00000\t33.00000\t0.00000\t0.81\t1.00000\t0.00000"
    "\t0.00000\t0.00000\t1.00000\t0.00000\t0.00000\t0.00000\t1.00000\t\n"
    "2\t0.01000\t1.0\t2.0\t1200.0\t0\t0\t0\t0.5\t1\t0\t0\t0\t1\t0\t0\t0\t1"
    "\t-1488.00000\t12.40000\t311.00000\t0.00000\t33.00000\t0.00000\t0.79\t0.995004165\t0.00000"
    "\t0.0998334166\t0.00000\t1.00000\t0.00000\t-0.0998334166\t0.00000\t0.995004165\t\n"
    "3\t0.02000\t1.0\t2.0\t1200.0\t0\t0\t0\t0.5\t1\t0\t0\t0\t1\t0\t0\t0\t1"
    "\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\tNaN\t\n"
    "4\t0.03000\t1.0\t2.0\t1200.0\t0\t0\t0\t0.5\t1\t0\t0\t0\t1\t0\t0\t0\t1"
    "\t-1464.00000\t12.20000\t309.50000\t0.00000\t33.00000\t0.00000\t0.80\t0.998750260\t0.00000"
    "\t-0.0499791693\t0.00000\t1.00000\t0.00000\t0.0499791693\t0.00000\t0.998750260\t\n";

TEST(ReadQtm6dTsvTest, HandWrittenExportInTheExactLayout) {
  const auto file = WriteText(ScratchDir() / "trial_6D.tsv", kQtmFile);
  const MocapTrack track = ReadQtm6dTsv(file, "wheelchair");
  ASSERT_EQ(track.size(), 3u);
  EXPECT_EQ(track.untracked_frames, 1);
  EXPECT_DOUBLE_EQ(track.t[0], 0.0);
  EXPECT_DOUBLE_EQ(track.t[1], 0.01);
  EXPECT_DOUBLE_EQ(track.t[2], 0.03);
  EXPECT_NEAR(track.x[0], -1.5, 1e-12);  // mm -> m
  EXPECT_NEAR(track.x[2], -1.464, 1e-12);
  EXPECT_NEAR(track.y[1], 0.0124, 1e-12);
  EXPECT_NEAR(track.z[1], 0.311, 1e-12);
  EXPECT_NEAR(track.pitch[0], 0.0, 1e-12);
  EXPECT_NEAR(track.pitch[1], 0.1, 1e-8);   // from Rot, not from the Euler column (33°)
  EXPECT_NEAR(track.pitch[2], -0.05, 1e-8);
}

TEST(ReadQtm6dTsvTest, OtherBodyOfTheSameFile) {
  const auto file = WriteText(ScratchDir() / "trial_6D.tsv", kQtmFile);
  const MocapTrack head = ReadQtm6dTsv(file, "head");
  EXPECT_EQ(head.size(), 4u);
  EXPECT_NEAR(head.z[0], 1.2, 1e-12);
}

TEST(ReadQtm6dTsvTest, WriterRoundTrip) {
  std::vector<MocapFrame> frames;
  for (int k = 0; k < 50; ++k) {
    frames.push_back({k * 0.005, 0.3 + 0.01 * k, 0.001, 0.02 * std::sin(k * 0.2),
                      0.03 * std::cos(k * 0.3), k != 7});
  }
  const auto dir = ScratchDir();
  WriteQtm6dTsv(frames, "wheelchair", 200.0, dir / "m.tsv");
  WriteMocapCsv(frames, dir / "m.csv");
  const MocapTrack tsv = ReadQtm6dTsv(dir / "m.tsv", "wheelchair");
  const MocapTrack csv = ReadMocapCsv(dir / "m.csv");
  ASSERT_EQ(tsv.size(), 49u);
  ASSERT_EQ(csv.size(), 49u);
  EXPECT_EQ(tsv.untracked_frames, 1);
  for (std::size_t k = 0; k < tsv.size(); ++k) {
    EXPECT_NEAR(tsv.x[k], csv.x[k], 6e-6);
    EXPECT_NEAR(tsv.z[k], csv.z[k], 6e-6);
    EXPECT_NEAR(tsv.pitch[k], csv.pitch[k], 6e-7);
  }
}

TEST(ReadMocapCsvTest, ColumnsInAnyOrderWithComments) {
  const auto file = WriteText(ScratchDir() / "m.csv",
                              "# lab export\n"
                              "pitch_rad, z_m ,t_s,x_m,yaw_rad\n"
                              "0.01,0.30,0.0,1.0,0\n"
                              "\n"
                              "# a comment between rows\n"
                              "0.02,0.31,0.01,1.01,0\r\n");
  const MocapTrack track = ReadMocapCsv(file);
  ASSERT_EQ(track.size(), 2u);
  EXPECT_DOUBLE_EQ(track.pitch[1], 0.02);
  EXPECT_DOUBLE_EQ(track.z[0], 0.30);
  EXPECT_DOUBLE_EQ(track.x[1], 1.01);
  EXPECT_DOUBLE_EQ(track.y[1], 0.0);
}

// ---- malformed input: one test each; the error names file, line, field and expectation ----

TEST(MalformedMocapTest, MissingFile) {
  const auto file = ScratchDir() / "absent.csv";
  const InputError error = ExpectInputError([&] { ReadMocapCsv(file); });
  EXPECT_EQ(error.file(), file.string());
  EXPECT_EQ(error.field(), "(file)");
  EXPECT_NE(std::string(error.what()).find("no such file"), std::string::npos);
  EXPECT_THROW(ReadQtm6dTsv(ScratchDir() / "absent.tsv", "wheelchair"), InputError);
}

TEST(MalformedMocapTest, EmptyCsvFile) {
  const auto file = WriteText(ScratchDir() / "m.csv", "");
  const InputError error = ExpectInputError([&] { ReadMocapCsv(file); });
  EXPECT_EQ(error.field(), "(header)");
  EXPECT_NE(std::string(error.what()).find("an empty file"), std::string::npos);
}

TEST(MalformedMocapTest, EmptyQtmFile) {
  const auto file = WriteText(ScratchDir() / "m.tsv", "\n\n");
  const InputError error = ExpectInputError([&] { ReadQtm6dTsv(file, "wheelchair"); });
  EXPECT_NE(std::string(error.what()).find("an empty file"), std::string::npos);
}

TEST(MalformedMocapTest, HeaderOnlyCsvHasNoFrames) {
  const auto file = WriteText(ScratchDir() / "m.csv", "t_s,x_m,z_m,pitch_rad\n");
  const InputError error = ExpectInputError([&] { ReadMocapCsv(file); });
  EXPECT_NE(error.expected().find("at least 2 frames"), std::string::npos);
}

TEST(MalformedMocapTest, CsvMissingRequiredColumn) {
  const auto file = WriteText(ScratchDir() / "m.csv", "t_s,x_m,pitch_rad\n0,0,0\n");
  const InputError error = ExpectInputError([&] { ReadMocapCsv(file); });
  EXPECT_EQ(error.line(), 1);
  EXPECT_EQ(error.field(), "z_m");
}

TEST(MalformedMocapTest, CsvBadNumber) {
  const auto file = WriteText(ScratchDir() / "m.csv",
                              "t_s,x_m,z_m,pitch_rad\n0,0,0,0\n0.01,0.1,0.3x,0\n");
  const InputError error = ExpectInputError([&] { ReadMocapCsv(file); });
  EXPECT_EQ(error.line(), 3);
  EXPECT_EQ(error.field(), "z_m");
  EXPECT_EQ(error.expected(), "a number");
  EXPECT_NE(std::string(error.what()).find("\"0.3x\""), std::string::npos);
}

TEST(MalformedMocapTest, QtmBadNumber) {
  std::string text = kQtmFile;
  text.replace(text.find("-1488.00000"), 11, "-14x8.00000");
  const auto file = WriteText(ScratchDir() / "m.tsv", text);
  const InputError error = ExpectInputError([&] { ReadQtm6dTsv(file, "wheelchair"); });
  EXPECT_EQ(error.line(), 13);
  EXPECT_EQ(error.field(), "wheelchair X");
}

TEST(MalformedMocapTest, CsvNonIncreasingTime) {
  const auto file = WriteText(ScratchDir() / "m.csv",
                              "t_s,x_m,z_m,pitch_rad\n0,0,0,0\n0.01,0,0,0\n0.01,0,0,0\n");
  const InputError error = ExpectInputError([&] { ReadMocapCsv(file); });
  EXPECT_EQ(error.line(), 4);
  EXPECT_EQ(error.field(), "t_s");
  EXPECT_EQ(error.expected(), "time strictly increasing");
}

TEST(MalformedMocapTest, QtmNonIncreasingTime) {
  std::string text = kQtmFile;
  text.replace(text.find("4\t0.03000"), 9, "4\t0.01000");
  const auto file = WriteText(ScratchDir() / "m.tsv", text);
  const InputError error = ExpectInputError([&] { ReadQtm6dTsv(file, "wheelchair"); });
  EXPECT_EQ(error.line(), 15);
  EXPECT_EQ(error.field(), "Time");
}

TEST(MalformedMocapTest, QtmMissingBody) {
  const auto file = WriteText(ScratchDir() / "m.tsv", kQtmFile);
  const InputError error = ExpectInputError([&] { ReadQtm6dTsv(file, "chair"); });
  EXPECT_EQ(error.line(), 10);
  EXPECT_EQ(error.field(), "BODY_NAMES");
  EXPECT_NE(std::string(error.what()).find("\"head\", \"wheelchair\""), std::string::npos);
}

TEST(MalformedMocapTest, QtmWrongDataIncluded) {
  std::string text = kQtmFile;
  text.replace(text.find("DATA_INCLUDED\t6D"), 16, "DATA_INCLUDED\t3D");
  const auto file = WriteText(ScratchDir() / "m.tsv", text);
  const InputError error = ExpectInputError([&] { ReadQtm6dTsv(file, "wheelchair"); });
  EXPECT_EQ(error.line(), 9);
  EXPECT_EQ(error.field(), "DATA_INCLUDED");
}

TEST(MalformedMocapTest, CsvWrongColumnCount) {
  const auto file = WriteText(ScratchDir() / "m.csv",
                              "t_s,x_m,z_m,pitch_rad\n0,0,0,0\n0.01,0,0\n");
  const InputError error = ExpectInputError([&] { ReadMocapCsv(file); });
  EXPECT_EQ(error.line(), 3);
  EXPECT_EQ(error.field(), "(row)");
  EXPECT_NE(error.expected().find("4 comma-separated values"), std::string::npos);
}

TEST(MalformedMocapTest, QtmWrongColumnCount) {
  std::string text = kQtmFile;
  text.replace(text.find("\t0.998750260\t\n"), 14, "\t\n");  // row 4 loses its last column
  const auto file = WriteText(ScratchDir() / "m.tsv", text);
  const InputError error = ExpectInputError([&] { ReadQtm6dTsv(file, "wheelchair"); });
  EXPECT_EQ(error.line(), 15);
  EXPECT_EQ(error.field(), "(row)");
  EXPECT_NE(error.expected().find("34 tab-separated fields"), std::string::npos);
}

TEST(MalformedMocapTest, QtmNaNRunLongerThanAllowed) {
  const auto file = WriteText(ScratchDir() / "m.tsv", kQtmFile);
  MocapReadOptions options;
  options.max_untracked_gap = 0.015;  // frame 3 alone leaves a 0.02 s hole
  const InputError error = ExpectInputError([&] { ReadQtm6dTsv(file, "wheelchair", options); });
  EXPECT_EQ(error.line(), 14);
  EXPECT_EQ(error.field(), "wheelchair X");
  EXPECT_NE(error.expected().find("untracked runs no longer than"), std::string::npos);
}

TEST(MalformedMocapTest, CsvNaNValue) {
  const auto file = WriteText(ScratchDir() / "m.csv",
                              "t_s,x_m,z_m,pitch_rad\n0,0,0,0\n0.01,0,nan,0\n0.02,0,0,0\n");
  const InputError error = ExpectInputError([&] { ReadMocapCsv(file); });
  EXPECT_EQ(error.line(), 3);
  EXPECT_EQ(error.field(), "z_m");
  EXPECT_NE(error.expected().find("finite"), std::string::npos);
}

TEST(MalformedMocapTest, QtmAllFramesUntracked) {
  std::string text = "DATA_INCLUDED\t6D\nBODY_NAMES\twheelchair\nFrame\tTime\twheelchair X\tY\tZ"
                     "\tRoll\tPitch\tYaw\tResidual\tRot[0]\tRot[1]\tRot[2]\tRot[3]\tRot[4]\tRot[5]"
                     "\tRot[6]\tRot[7]\tRot[8]\t\n";
  for (int k = 0; k < 3; ++k) {
    text += std::to_string(k + 1) + "\t0.0" + std::to_string(k);
    for (int c = 0; c < 16; ++c) text += "\tNaN";
    text += "\t\n";
  }
  const auto file = WriteText(ScratchDir() / "m.tsv", text);
  const InputError error = ExpectInputError([&] { ReadQtm6dTsv(file, "wheelchair"); });
  EXPECT_NE(std::string(error.what()).find("0 tracked of 3 frames"), std::string::npos);
}

TEST(MalformedMocapTest, QtmFrameCountDisagreesWithHeader) {
  std::string text = kQtmFile;
  text.replace(text.find("NO_OF_FRAMES\t4"), 14, "NO_OF_FRAMES\t5");
  const auto file = WriteText(ScratchDir() / "m.tsv", text);
  const InputError error = ExpectInputError([&] { ReadQtm6dTsv(file, "wheelchair"); });
  EXPECT_EQ(error.line(), 1);
  EXPECT_EQ(error.field(), "NO_OF_FRAMES");
}

TEST(MalformedMocapTest, QtmRenamedBodyColumn) {
  std::string text = kQtmFile;
  text.replace(text.rfind("\tResidual\t"), 10, "\tResid\t");
  const auto file = WriteText(ScratchDir() / "m.tsv", text);
  const InputError error = ExpectInputError([&] { ReadQtm6dTsv(file, "wheelchair"); });
  EXPECT_EQ(error.line(), 11);
  EXPECT_EQ(error.field(), "wheelchair Residual");
}

// Tests that a FREQUENCY header contradicting the Time column (4 frames 10 ms apart: 100 Hz)
// is refused at its line, naming the rate the Time column gives; 100.5 Hz (within 1 %) passes.
TEST(MalformedMocapTest, QtmFrequencyContradictsTheTimeColumn) {
  std::string text = kQtmFile;
  text.replace(text.find("FREQUENCY\t100\n"), 14, "FREQUENCY\t50\n");
  const auto file = WriteText(ScratchDir() / "m.tsv", text);
  const InputError error = ExpectInputError([&] { ReadQtm6dTsv(file, "wheelchair"); });
  EXPECT_EQ(error.line(), 4);
  EXPECT_EQ(error.field(), "FREQUENCY");
  EXPECT_EQ(error.got(), "\"50\" Hz");
  EXPECT_NE(error.expected().find("the frame rate of the Time column, 100 Hz (4 frames from 0 s to 0.03 s)"),
            std::string::npos)
      << error.what();
  text.replace(text.find("FREQUENCY\t50\n"), 13, "FREQUENCY\t100.5\n");
  EXPECT_NO_THROW(ReadQtm6dTsv(WriteText(ScratchDir() / "m2.tsv", text), "wheelchair"));
  text.replace(text.find("FREQUENCY\t100.5\n"), 16, "FREQUENCY\tfast\n");
  const InputError word = ExpectInputError([&] { ReadQtm6dTsv(WriteText(ScratchDir() / "m3.tsv", text), "wheelchair"); });
  EXPECT_EQ(word.field(), "FREQUENCY");
  EXPECT_EQ(word.got(), "\"fast\"");
}

// Tests that a directory named as a mocap file says it is a directory.
TEST(MalformedMocapTest, DirectoryInsteadOfAFile) {
  const InputError error = ExpectInputError([&] { ReadQtm6dTsv(ScratchDir(), "wheelchair"); });
  EXPECT_EQ(error.got(), "a path that is a directory");
  const InputError csv = ExpectInputError([&] { ReadMocapCsv(ScratchDir()); });
  EXPECT_EQ(csv.got(), "a path that is a directory");
}

}  // namespace
}  // namespace pwsim
