#include "hardware/canopen.h"

#include <gtest/gtest.h>

#include <vector>

namespace pwsim::hw::canopen {
namespace {

TEST(CanopenCodecs, TableOfEncodings) {
  struct Case {
    CanFrame frame;
    const char* text;
  };
  const std::vector<Case> cases = {
      {EncodeNmt(NmtCommand::kStart, 0), "000#0100"},
      {EncodeNmt(NmtCommand::kResetComm, 2), "000#8202"},
      {EncodeSync(1), "080#01"},
      {EncodeSync(0), "080#"},
      {EncodeHeartbeat(1, NmtState::kBootUp), "701#00"},
      {EncodeHeartbeat(2, NmtState::kOperational), "702#05"},
      {EncodeEmcy(1, {0x8611, 0x01, {}}), "081#1186010000000000"},
      {EncodeCspCommand(2, {0x000F, 100000}), "202#0F00A0860100"},
      {EncodeCspCommand(1, {0x0006, -1}), "201#0600FFFFFFFF"},
      {EncodeCspStatus(1, {0x0237, 123456}), "181#370240E20100"},
      {EncodeCspFeedback(2, {-2, -1000}), "282#FEFFFFFF18FC"},
  };
  for (const Case& c : cases) EXPECT_EQ(FormatFrameText(c.frame), c.text);
}

TEST(CanopenCodecs, DecodeRoundTripsAndRejects) {
  NmtCommand cmd{};
  std::uint8_t node = 0;
  ASSERT_TRUE(DecodeNmt(EncodeNmt(NmtCommand::kStop, 5), &cmd, &node));
  EXPECT_EQ(cmd, NmtCommand::kStop);
  EXPECT_EQ(node, 5);
  EXPECT_FALSE(DecodeNmt(MakeFrame(0, {0x03, 0}), &cmd, &node));
  EXPECT_FALSE(DecodeNmt(MakeFrame(0, {0x01}), &cmd, &node));
  std::uint8_t counter = 0;
  EXPECT_TRUE(DecodeSync(EncodeSync(240), &counter));
  EXPECT_FALSE(DecodeSync(MakeFrame(0x80, {241}), &counter));
  NmtState st{};
  ASSERT_TRUE(DecodeHeartbeat(MakeFrame(0x77F, {0x85}), &node, &st));  // toggle bit ignored
  EXPECT_EQ(node, 0x7F);
  EXPECT_EQ(st, NmtState::kOperational);
  EXPECT_FALSE(DecodeHeartbeat(MakeFrame(0x701, {0x06}), &node, &st));
  Emcy e;
  ASSERT_TRUE(DecodeEmcy(EncodeEmcy(3, {0x2310, 0x03, {1, 2, 3, 4, 5}}), &node, &e));
  EXPECT_EQ(e, (Emcy{0x2310, 0x03, {1, 2, 3, 4, 5}}));
  CspCommand c;
  ASSERT_TRUE(DecodeCspCommand(EncodeCspCommand(2, {0x0F, -123456}), &node, &c));
  EXPECT_EQ(c, (CspCommand{0x0F, -123456}));
  EXPECT_FALSE(DecodeCspCommand(MakeFrame(0x202, {0x0F, 0, 0, 0, 0}), &node, &c));
  CspStatus s;
  ASSERT_TRUE(DecodeCspStatus(EncodeCspStatus(1, {0x0627, 42}), &node, &s));
  EXPECT_EQ(s, (CspStatus{0x0627, 42}));
  EXPECT_EQ(Classify(MakeFrame(0x181, {}), &node), FrameKind::kTpdo1);
  EXPECT_EQ(node, 1);
  EXPECT_EQ(Classify(MakeFrame(0x080, {}), &node), FrameKind::kSync);
  EXPECT_EQ(Classify(MakeFrame(0x0FF, {}), &node), FrameKind::kEmcy);
  EXPECT_EQ(Classify(MakeFrame(0x600, {}), &node), FrameKind::kOther);
  EXPECT_EQ(Classify(CanFrame{0x181U | kCanEffFlag, 0, {}}, &node), FrameKind::kOther);
}

TEST(Cia402, StatuswordTable) {
  struct Case {
    std::uint16_t sw;
    DriveState state;
  };
  for (const Case& c : std::vector<Case>{{0x0000, DriveState::kNotReadyToSwitchOn},
                                         {0x0040, DriveState::kSwitchOnDisabled},
                                         {0x0031, DriveState::kReadyToSwitchOn},
                                         {0x0233, DriveState::kSwitchedOn},
                                         {0x0637, DriveState::kOperationEnabled},
                                         {0x0017, DriveState::kQuickStopActive},
                                         {0x001F, DriveState::kFaultReactionActive},
                                         {0x0008, DriveState::kFault},
                                         {0x0218, DriveState::kFault}}) {
    EXPECT_EQ(DecodeStatusword(c.sw), c.state) << std::hex << c.sw;
  }
  for (DriveState s : {DriveState::kSwitchOnDisabled, DriveState::kReadyToSwitchOn,
                       DriveState::kSwitchedOn, DriveState::kOperationEnabled,
                       DriveState::kQuickStopActive, DriveState::kFault}) {
    EXPECT_EQ(DecodeStatusword(StatuswordFor(s)), s) << DriveStateName(s);
  }
}

TEST(Cia402, MasterControlwordsWalkTheDriveToOperationEnabled) {
  DriveState s = DriveState::kSwitchOnDisabled;
  std::uint16_t prev = 0;
  for (int i = 0; i < 5 && s != DriveState::kOperationEnabled; ++i) {
    const std::uint16_t cw = ControlwordTowardEnabled(s);
    s = NextDriveState(s, cw, prev);
    prev = cw;
  }
  EXPECT_EQ(s, DriveState::kOperationEnabled);
  // Enable straight from switch-on-disabled is ignored by a conforming drive.
  EXPECT_EQ(NextDriveState(DriveState::kSwitchOnDisabled, 0x0F, 0), DriveState::kSwitchOnDisabled);
  EXPECT_EQ(NextDriveState(DriveState::kOperationEnabled, 0x02, 0x0F), DriveState::kQuickStopActive);
  EXPECT_EQ(NextDriveState(DriveState::kQuickStopActive, 0x00, 0x02), DriveState::kSwitchOnDisabled);
  // Fault reset needs a rising edge of bit 7.
  EXPECT_EQ(NextDriveState(DriveState::kFault, 0x80, 0x80), DriveState::kFault);
  EXPECT_EQ(NextDriveState(DriveState::kFault, 0x80, 0x00), DriveState::kSwitchOnDisabled);
}

}  // namespace
}  // namespace pwsim::hw::canopen
