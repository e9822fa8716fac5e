#include "hardware/can_frame.h"

#include <gtest/gtest.h>

#include <vector>

namespace pwsim::hw {
namespace {

struct TextCase {
  const char* text;
  CodecError error;
  CanFrame frame;
};

TEST(CanFrameText, TableOfCases) {
  const std::vector<TextCase> cases = {
      {"123#DEADBEEF", CodecError::kOk, MakeFrame(0x123, {0xDE, 0xAD, 0xBE, 0xEF})},
      {"7FF#", CodecError::kOk, MakeFrame(0x7FF, {})},
      {"000#0102030405060708", CodecError::kOk, MakeFrame(0, {1, 2, 3, 4, 5, 6, 7, 8})},
      {"12345678#00", CodecError::kOk, CanFrame{0x12345678U | kCanEffFlag, 1, {}}},
      {"123#R", CodecError::kOk, CanFrame{0x123U | kCanRtrFlag, 0, {}}},
      {"123#R3", CodecError::kOk, CanFrame{0x123U | kCanRtrFlag, 3, {}}},
      {"20000040#0000000000000000", CodecError::kOk, MakeErrorFrame(kCanErrBusOff)},
      {"123#de.ad", CodecError::kOk, MakeFrame(0x123, {0xDE, 0xAD})},
      {"800#00", CodecError::kBadId, {}},
      {"1234#00", CodecError::kBadId, {}},
      {"123#0", CodecError::kBadSyntax, {}},
      {"123#GG", CodecError::kBadSyntax, {}},
      {"123#000102030405060708", CodecError::kBadLength, {}},
      {"123##1DEAD", CodecError::kBadLength, {}},
      {"123", CodecError::kBadSyntax, {}},
      {"4FFFFFFF#00", CodecError::kBadId, {}},
  };
  for (const TextCase& c : cases) {
    CanFrame f;
    EXPECT_EQ(ParseFrameText(c.text, &f), c.error) << c.text;
    if (c.error == CodecError::kOk) {
      EXPECT_EQ(f, c.frame) << c.text;
    }
  }
}

TEST(CanFrameText, FormatsLikeCanUtils) {
  EXPECT_EQ(FormatFrameText(MakeFrame(0x123, {0xDE, 0xAD})), "123#DEAD");
  EXPECT_EQ(FormatFrameText(MakeFrame(0x5, {})), "005#");
  EXPECT_EQ(FormatFrameText(CanFrame{0x1ABCDEFU | kCanEffFlag, 1, {0x42}}), "01ABCDEF#42");
  EXPECT_EQ(FormatFrameText(CanFrame{0x100U | kCanRtrFlag, 0, {}}), "100#R");
  EXPECT_EQ(FormatFrameText(MakeErrorFrame(kCanErrBusOff)), "20000040#0000000000000000");
  for (const char* text : {"123#DEADBEEF", "01ABCDEF#42", "100#R", "20000004#0020000000000000"}) {
    CanFrame f;
    ASSERT_EQ(ParseFrameText(text, &f), CodecError::kOk);
    EXPECT_EQ(FormatFrameText(f), text);
  }
}

TEST(CanFrameRaw, MatchesStructCanFrameLayout) {
  const CanFrame f = MakeFrame(0x181, {1, 2, 3, 4, 5, 6});
  std::array<std::uint8_t, kRawFrameSize> raw{};
  EncodeRawFrame(f, raw);
  EXPECT_EQ(raw[4], 6);
  EXPECT_EQ(raw[8], 1);
  EXPECT_EQ(raw[13], 6);
  CanFrame back;
  ASSERT_EQ(DecodeRawFrame(raw, &back), CodecError::kOk);
  EXPECT_EQ(back, f);
  raw[4] = 9;
  EXPECT_EQ(DecodeRawFrame(raw, &back), CodecError::kBadLength);
  EXPECT_EQ(DecodeRawFrame(std::span<const std::uint8_t>(raw.data(), 15), &back),
            CodecError::kTruncated);
}

struct CannelloniCase {
  std::vector<std::uint8_t> bytes;
  CodecError error;
  std::size_t frames;
};

TEST(Cannelloni, EncodesTheDocumentedLayout) {
  const CanFrame frames[] = {MakeFrame(0x123, {0xAA, 0xBB}),
                             CanFrame{0x1FFFFFFFU | kCanEffFlag, 1, {0x01}},
                             CanFrame{0x100U | kCanRtrFlag, 0, {}}};
  std::array<std::uint8_t, 64> out{};
  const std::size_t n = EncodeCannelloni(7, frames, out);
  const std::vector<std::uint8_t> expected = {
      2, 0, 7, 0, 3,                          // version, op DATA, seq, count (BE)
      0x00, 0x00, 0x01, 0x23, 2, 0xAA, 0xBB,  // id BE, len, data
      0x9F, 0xFF, 0xFF, 0xFF, 1, 0x01,        // EFF flag in the id
      0x40, 0x00, 0x01, 0x00, 0};             // RTR: no data bytes
  ASSERT_EQ(n, expected.size());
  EXPECT_EQ(std::vector<std::uint8_t>(out.begin(), out.begin() + static_cast<long>(n)), expected);
  std::vector<CanFrame> back;
  std::uint8_t seq = 0;
  ASSERT_EQ(DecodeCannelloni(std::span<const std::uint8_t>(out.data(), n), &seq, &back),
            CodecError::kOk);
  EXPECT_EQ(seq, 7);
  ASSERT_EQ(back.size(), 3U);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(back[i], frames[i]);
  EXPECT_EQ(EncodeCannelloni(0, frames, std::span<std::uint8_t>(out.data(), 10)), 0U);
}

TEST(Cannelloni, RejectsMalformedDatagrams) {
  const std::vector<CannelloniCase> cases = {
      {{}, CodecError::kTruncated, 0},
      {{2, 0, 1, 0}, CodecError::kTruncated, 0},
      {{1, 0, 1, 0, 0}, CodecError::kBadVersion, 0},
      {{2, 1, 1, 0, 0}, CodecError::kBadOpcode, 0},
      {{2, 0, 1, 0, 0}, CodecError::kOk, 0},
      {{2, 0, 1, 0, 1, 0, 0, 1, 0x23, 2, 0xAA}, CodecError::kTruncated, 0},
      {{2, 0, 1, 0, 1, 0, 0, 1, 0x23, 0x88, 0xAA}, CodecError::kBadLength, 0},
      {{2, 0, 1, 0, 1, 0, 0, 1, 0x23, 9}, CodecError::kBadLength, 0},
      {{2, 0, 1, 0, 1, 0, 0, 8, 0x00, 0}, CodecError::kBadId, 0},
      {{2, 0, 1, 0, 1, 0, 0, 1, 0x23, 1, 0xAA, 0xFF}, CodecError::kTrailing, 0},
      {{2, 0, 1, 0, 1, 0, 0, 1, 0x23, 1, 0xAA}, CodecError::kOk, 1},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    std::vector<CanFrame> frames;
    std::uint8_t seq = 0;
    EXPECT_EQ(DecodeCannelloni(cases[i].bytes, &seq, &frames), cases[i].error) << "case " << i;
    EXPECT_EQ(frames.size(), cases[i].frames) << "case " << i;
  }
}

}  // namespace
}  // namespace pwsim::hw
