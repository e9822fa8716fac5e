#include "hardware/candump_log.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include "engine/input_error.h"
#include "hardware/rnet_joystick.h"

namespace pwsim::hw {
namespace {

/// A fresh folder of this test under the build tree.
std::filesystem::path CandumpScratch() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path dir = std::filesystem::path(PWSIM_BINARY_DIR) / "test_out" / "candump" / info->name();
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// The InputError ReadCandumpFile throws for `file` (fails the test when none).
InputError CandumpFileError(const std::filesystem::path& file) {
  try {
    ReadCandumpFile(file);
  } catch (const InputError& error) {
    return error;
  }
  ADD_FAILURE() << "no InputError for " << file;
  return InputError("", 0, "", "", "");
}

// Tests the three R-Net logs that used to "drive" 4.5 s and exit 0: an empty one, one whose
// time goes back (named at the line that goes back, with the time before it), a directory.
TEST(CandumpFile, RefusesEmptyBackwardsAndDirectoryLogs) {
  const std::filesystem::path dir = CandumpScratch();
  std::ofstream(dir / "empty.log").close();
  const InputError empty = CandumpFileError(dir / "empty.log");
  EXPECT_EQ(empty.field(), "frame");
  EXPECT_EQ(empty.got(), "an empty file");
  std::ofstream(dir / "blank.log") << "\n\n";
  EXPECT_EQ(CandumpFileError(dir / "blank.log").got(), "only blank lines");

  std::ofstream(dir / "back.log") << "(1700000000.000000) can0 02000000#0000\n"
                                     "(1700000000.010000) can0 02000000#0064\n"
                                     "(1700000000.010000) can0 02000000#0064\n"
                                     "(1699999999.990000) can0 02000000#0000\n";
  const InputError back = CandumpFileError(dir / "back.log");
  EXPECT_EQ(back.line(), 4);
  EXPECT_EQ(back.field(), "timestamp");
  EXPECT_EQ(back.got(), "(1699999999.990000)");
  EXPECT_NE(back.expected().find("line 3 is at (1700000000.010000)"), std::string::npos) << back.what();

  const InputError folder = CandumpFileError(dir);
  EXPECT_EQ(folder.line(), 0);
  EXPECT_EQ(folder.got(), "a path that is a directory");
  // equal timestamps (frames of one microsecond) are fine
  std::ofstream(dir / "ok.log") << "(1.000000) can0 02000000#0000\n(1.000000) can0 02000000#0001\n";
  EXPECT_EQ(ReadCandumpFile(dir / "ok.log").size(), 2U);
}

TEST(CandumpLog, LinesRoundTrip) {
  const std::vector<CandumpRecord> records = {
      {1700000000123456, "can0", MakeFrame(0x123, {0xDE, 0xAD})},
      {5, "vcan1", CanFrame{0x1234567U | kCanEffFlag, 0, {}}},
      {999999, "can0", CanFrame{0x80U | kCanRtrFlag, 0, {}}},
      {1000000, "can0", MakeErrorFrame(kCanErrBusOff)},
  };
  std::stringstream s;
  CandumpWriter w0(s, "can0");
  for (const auto& r : records) s << FormatCandumpLine(r) << "\n";
  EXPECT_EQ(FormatCandumpLine(records[0]), "(1700000000.123456) can0 123#DEAD");
  EXPECT_EQ(FormatCandumpLine(records[1]), "(0.000005) vcan1 01234567#");
  int bad = 0;
  CodecError e{};
  const auto back = ReadCandumpLog(s, &bad, &e);
  EXPECT_EQ(bad, 0);
  EXPECT_EQ(back, records);
}

TEST(CandumpLog, RejectsMalformedLines) {
  CandumpRecord r;
  for (const char* line : {"", "1.000000 can0 123#00", "(1.00) can0 123#00", "(1.000000)can0 123#00",
                           "(1.000000) can0", "(x.000000) can0 123#00", "(1.000000) can0 123#0"}) {
    EXPECT_NE(ParseCandumpLine(line, &r), CodecError::kOk) << line;
  }
  EXPECT_EQ(ParseCandumpLine("(1.000000) can0 123#00 R", &r), CodecError::kOk);
  std::stringstream s("(1.000000) can0 123#00\n\n(2.000000) can0 12#00\n");
  int bad = 0;
  CodecError e{};
  EXPECT_EQ(ReadCandumpLog(s, &bad, &e).size(), 1U);
  EXPECT_EQ(bad, 3);
}

std::string RunTool(const std::string& command) {
  std::string out;
  FILE* p = ::popen(command.c_str(), "r");
  if (p == nullptr) return out;
  char buf[512];
  while (std::fgets(buf, sizeof(buf), p) != nullptr) out += buf;
  ::pclose(p);
  return out;
}

TEST(CandumpLog, CanUtilsLog2longAndLog2ascReadOurLogs) {
  if (std::system("command -v log2long >/dev/null 2>&1 && command -v log2asc >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "can-utils (log2long, log2asc) not installed";
  const auto file = std::filesystem::temp_directory_path() /
                    ("pwsim_candump_" + std::to_string(::getpid()) + ".log");
  {
    std::ofstream out(file);
    CandumpWriter w(out, "can0");
    w.Write(1000000, MakeFrame(0x000, {0x01, 0x00}));
    w.Write(1004000, MakeFrame(0x201, {0x0F, 0x00, 0x40, 0x42, 0x0F, 0x00}));
    w.Write(1004100, MakeFrame(0x080, {0x01}));
    w.Write(1005000, CanFrame{0x1ABCDEFU | kCanEffFlag, 2, {0x12, 0x34}});
    w.Write(1006000, CanFrame{0x123U | kCanRtrFlag, 0, {}});
    w.Write(1007000, MakeErrorFrame(kCanErrBusOff));
  }
  const std::string longform = RunTool("log2long < " + file.string());
  EXPECT_NE(longform.find("201"), std::string::npos) << longform;
  EXPECT_NE(longform.find("0F 00 40 42 0F 00"), std::string::npos) << longform;
  EXPECT_NE(longform.find("01ABCDEF"), std::string::npos) << longform;
  EXPECT_NE(longform.find("remote request"), std::string::npos) << longform;
  EXPECT_NE(longform.find("ERRORFRAME"), std::string::npos) << longform;
  int lines = 0;
  for (char c : longform) lines += c == '\n';
  EXPECT_EQ(lines, 6) << longform;
  const std::string asc = RunTool("log2asc -I " + file.string() + " can0 2>&1");
  EXPECT_NE(asc.find("201"), std::string::npos) << asc;
  EXPECT_NE(asc.find("1ABCDEFx"), std::string::npos) << asc;
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace pwsim::hw
