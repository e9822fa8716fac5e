// The links' authenticated mode (hardware/link_auth.h) without sockets: the tag is
// HMAC-SHA-512-256 over the documented bytes (checked against Python's hmac, an independent
// implementation), every altered byte, another key, a replay, an older epoch, a reflected
// datagram and a datagram of the other link are dropped and counted, reordering inside the
// window passes, a restarted peer (a newer epoch) is taken once it echoes our epoch and
// datagrams recorded before this end started are not, and the key file is checked.
#include "hardware/link_auth.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "engine/input_error.h"

namespace pwsim::hw {
namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<std::uint8_t>;

LinkKey KeyOf(std::uint8_t seed) {
  LinkKey k;
  for (std::size_t i = 0; i < k.bytes.size(); ++i) k.bytes[i] = static_cast<std::uint8_t>(seed * 31 + i * 7 + 1);
  return k;
}

Bytes Seal(LinkAuth& a, const Bytes& payload) {
  Bytes out(kLinkAuthOverhead + payload.size());
  out.resize(a.Seal(payload, out));
  return out;
}
Bytes Hello(LinkAuth& a) {
  Bytes out(kLinkAuthOverhead);
  out.resize(a.SealHello(out));
  return out;
}

struct Opened {
  LinkAuth::Verdict verdict;
  Bytes payload;
  bool answer;
};
Opened Open(LinkAuth& a, const Bytes& datagram, std::int64_t now_ns = 0) {
  std::span<const std::uint8_t> payload;
  bool answer = false;
  const LinkAuth::Verdict v = a.Open(datagram, now_ns, &payload, &answer);
  return {v, Bytes(payload.begin(), payload.end()), answer};
}

/// A session end and a peer end that have heard each other's epoch (a HELLO each way).
struct Pair {
  LinkAuth session{KeyOf(1), LinkKind::kCan, LinkRole::kSession, 1000};
  LinkAuth peer{KeyOf(1), LinkKind::kCan, LinkRole::kPeer, 2000};
  Pair() {
    EXPECT_EQ(Open(peer, Hello(session)).verdict, LinkAuth::Verdict::kHello);
    EXPECT_EQ(Open(session, Hello(peer)).verdict, LinkAuth::Verdict::kHello);
  }
};

std::string Hex(const Bytes& b) {
  static const char* kDigits = "0123456789abcdef";
  std::string s;
  for (std::uint8_t v : b) {
    s += kDigits[v >> 4];
    s += kDigits[v & 15];
  }
  return s;
}

TEST(LinkAuth, TagIsHmacSha512TruncatedOverTheDocumentedHeaderAndPayload) {
  if (std::system("python3 -c 'import hmac, hashlib' >/dev/null 2>&1") != 0) GTEST_SKIP() << "python3 not available";
  LinkAuth a(KeyOf(3), LinkKind::kHmd, LinkRole::kPeer, 0x1122334455667788ULL);
  const Bytes payload = {'P', 'W', 'H', 'M', 1, 2, 3};
  const Bytes d = Seal(a, payload);
  ASSERT_EQ(d.size(), 32U + payload.size() + 32U);
  // The header, field by field (little endian).
  EXPECT_EQ(Bytes(d.begin(), d.begin() + 4), (Bytes{'P', 'W', 'L', 'A'}));
  EXPECT_EQ(d[4], 1);  // version
  EXPECT_EQ(d[5], 2);  // HMD
  EXPECT_EQ(d[6], 2);  // peer role
  EXPECT_EQ(d[7], 1);  // DATA
  EXPECT_EQ(Bytes(d.begin() + 8, d.begin() + 16), (Bytes{0x88, 0x77, 0x66, 0x55, 0x44, 0x33, 0x22, 0x11}));
  EXPECT_EQ(Bytes(d.begin() + 16, d.begin() + 24), Bytes(8, 0));  // no peer epoch heard yet
  EXPECT_EQ(Bytes(d.begin() + 24, d.begin() + 32), (Bytes{1, 0, 0, 0, 0, 0, 0, 0}));  // counter 1
  EXPECT_EQ(Bytes(d.begin() + 32, d.begin() + 39), payload);
  // The tag from an independent HMAC implementation.
  const LinkKey k = KeyOf(3);
  const std::string cmd = "python3 -c \"import hmac, hashlib; print(hmac.new(bytes.fromhex('" +
                          Hex(Bytes(k.bytes.begin(), k.bytes.end())) + "'), bytes.fromhex('" +
                          Hex(Bytes(d.begin(), d.end() - 32)) + "'), hashlib.sha512).hexdigest()[:64])\"";
  FILE* p = ::popen(cmd.c_str(), "r");
  ASSERT_NE(p, nullptr);
  char line[256] = {};
  ASSERT_NE(std::fgets(line, sizeof(line), p), nullptr);
  ::pclose(p);
  EXPECT_EQ(std::string(line).substr(0, 64), Hex(Bytes(d.end() - 32, d.end())));
}

TEST(LinkAuth, GoodDatagramsPassAndEveryAlteredByteIsDroppedAndCounted) {
  Pair p;
  const Bytes payload = {0x02, 0x00, 0x00, 0x00, 0x80, 0x00, 0x01, 0x07};
  const Bytes d = Seal(p.session, payload);
  std::uint64_t expected_bad = 0;
  for (std::size_t i = 0; i < d.size(); ++i) {
    Bytes t = d;
    t[i] ^= 0x01;
    const Opened o = Open(p.peer, t);
    EXPECT_EQ(o.verdict, LinkAuth::Verdict::kDropped) << "byte " << i;
    // Bytes 0-7 make it no datagram of this link (malformed, before the tag); the rest fail the tag.
    if (i >= 8) ++expected_bad;
  }
  EXPECT_EQ(p.peer.counters().bad_tag, expected_bad);
  EXPECT_EQ(p.peer.counters().accepted, 0U);
  // Truncated and extended copies.
  EXPECT_EQ(Open(p.peer, Bytes(d.begin(), d.end() - 1)).verdict, LinkAuth::Verdict::kDropped);
  Bytes longer = d;
  longer.push_back(0);
  EXPECT_EQ(Open(p.peer, longer).verdict, LinkAuth::Verdict::kDropped);
  // The untouched datagram still passes (nothing above consumed its counter).
  const Opened o = Open(p.peer, d);
  ASSERT_EQ(o.verdict, LinkAuth::Verdict::kData);
  EXPECT_EQ(o.payload, payload);
  EXPECT_EQ(p.peer.counters().accepted, 1U);
}

TEST(LinkAuth, AnotherKeyIsRefused) {
  LinkAuth session(KeyOf(1), LinkKind::kCan, LinkRole::kSession, 1000);
  LinkAuth peer(KeyOf(1), LinkKind::kCan, LinkRole::kPeer, 2000);
  LinkAuth stranger(KeyOf(2), LinkKind::kCan, LinkRole::kSession, 3000);
  Open(peer, Hello(session));
  Open(session, Hello(peer));
  EXPECT_EQ(Open(peer, Seal(stranger, {1, 2, 3})).verdict, LinkAuth::Verdict::kDropped);
  EXPECT_EQ(Open(peer, Hello(stranger)).verdict, LinkAuth::Verdict::kDropped);
  EXPECT_EQ(peer.counters().bad_tag, 2U);
  EXPECT_EQ(peer.peer_epoch(), 1000U);  // a forged HELLO teaches nothing
  EXPECT_EQ(Open(peer, Seal(session, {4})).verdict, LinkAuth::Verdict::kData);
}

TEST(LinkAuth, ReplaysAreDroppedReorderingInsideTheWindowPasses) {
  Pair p;
  std::vector<Bytes> sent;
  for (int i = 0; i < 100; ++i) sent.push_back(Seal(p.session, {static_cast<std::uint8_t>(i)}));
  // Out of order inside the window: 5, 3, 4, 0, 1, 2 all pass once.
  for (int i : {5, 3, 4, 0, 1, 2}) EXPECT_EQ(Open(p.peer, sent[static_cast<std::size_t>(i)]).verdict, LinkAuth::Verdict::kData) << i;
  for (int i : {5, 0, 2}) EXPECT_EQ(Open(p.peer, sent[static_cast<std::size_t>(i)]).verdict, LinkAuth::Verdict::kDropped) << i;
  EXPECT_EQ(p.peer.counters().replayed, 3U);
  // Jump ahead: 99 taken; 99 - 63 = 36 still inside the window, 35 behind it.
  EXPECT_EQ(Open(p.peer, sent[99]).verdict, LinkAuth::Verdict::kData);
  EXPECT_EQ(Open(p.peer, sent[36]).verdict, LinkAuth::Verdict::kData);
  EXPECT_EQ(Open(p.peer, sent[35]).verdict, LinkAuth::Verdict::kDropped);
  EXPECT_EQ(Open(p.peer, sent[99]).verdict, LinkAuth::Verdict::kDropped);
  EXPECT_EQ(p.peer.counters().replayed, 5U);
  EXPECT_EQ(p.peer.counters().accepted, 8U);
}

TEST(LinkAuth, ReflectedAndOtherLinkDatagramsAreRefused) {
  Pair p;
  const Bytes own = Seal(p.session, {1});
  EXPECT_EQ(Open(p.session, own).verdict, LinkAuth::Verdict::kDropped);  // its own datagram, sent back
  LinkAuth hmd_session(KeyOf(1), LinkKind::kHmd, LinkRole::kSession, 1000);
  EXPECT_EQ(Open(p.peer, Seal(hmd_session, {1})).verdict, LinkAuth::Verdict::kDropped);  // same key, HMD link
  EXPECT_EQ(p.session.counters().malformed, 1U);
  EXPECT_EQ(p.peer.counters().malformed, 1U);
}

TEST(LinkAuth, UnconfirmedUntilTheSenderEchoesOurEpochThenAHelloAnswerConverges) {
  LinkAuth session(KeyOf(1), LinkKind::kCan, LinkRole::kSession, 1000);
  LinkAuth peer(KeyOf(1), LinkKind::kCan, LinkRole::kPeer, 2000);
  // The session has not heard the peer: its datagram echoes 0 and is not taken, but answered.
  const Opened first = Open(peer, Seal(session, {7}), 0);
  EXPECT_EQ(first.verdict, LinkAuth::Verdict::kDropped);
  EXPECT_TRUE(first.answer);
  EXPECT_EQ(peer.counters().unconfirmed, 1U);
  EXPECT_EQ(peer.peer_epoch(), 1000U);  // learnt from the authentic datagram
  // Answers are paced: not again within kHelloIntervalNs.
  EXPECT_FALSE(Open(peer, Seal(session, {8}), kHelloIntervalNs / 2).answer);
  EXPECT_TRUE(Open(peer, Seal(session, {9}), kHelloIntervalNs).answer);
  // The answer (a HELLO echoing the session's epoch) teaches the session the peer's epoch.
  const Opened h = Open(session, Hello(peer), 0);
  EXPECT_EQ(h.verdict, LinkAuth::Verdict::kHello);
  EXPECT_FALSE(h.answer);  // it already echoes the session's epoch
  EXPECT_EQ(session.peer_epoch(), 2000U);
  const Opened now = Open(peer, Seal(session, {10}));
  ASSERT_EQ(now.verdict, LinkAuth::Verdict::kData);
  EXPECT_EQ(now.payload, Bytes{10});
}

TEST(LinkAuth, ARestartedPeerIsTakenAndItsEarlierLifeIsNot) {
  Pair p;
  std::vector<Bytes> old_life;
  for (int i = 0; i < 3; ++i) old_life.push_back(Seal(p.peer, {static_cast<std::uint8_t>(i)}));
  EXPECT_EQ(Open(p.session, old_life[0]).verdict, LinkAuth::Verdict::kData);
  // The peer restarts: a newer epoch, counters from 1 again.
  LinkAuth reborn(KeyOf(1), LinkKind::kCan, LinkRole::kPeer, 3000);
  EXPECT_EQ(Open(reborn, Seal(p.session, {0})).verdict, LinkAuth::Verdict::kDropped);  // learns the session's epoch
  Open(p.session, Hello(reborn));
  const Opened o = Open(p.session, Seal(reborn, {42}));
  ASSERT_EQ(o.verdict, LinkAuth::Verdict::kData);
  EXPECT_EQ(o.payload, Bytes{42});
  EXPECT_EQ(p.session.counters().peer_restarts, 1U);
  // The earlier life's datagrams (recorded, echoing the session's epoch) are refused now.
  EXPECT_EQ(Open(p.session, old_life[1]).verdict, LinkAuth::Verdict::kDropped);
  EXPECT_EQ(Open(p.session, old_life[2]).verdict, LinkAuth::Verdict::kDropped);
  EXPECT_EQ(p.session.counters().replayed, 2U);
  EXPECT_EQ(Open(p.session, Seal(reborn, {43})).verdict, LinkAuth::Verdict::kData);
}

TEST(LinkAuth, DatagramsRecordedBeforeThisEndStartedAreNotTaken) {
  Pair p;
  const Bytes recorded = Seal(p.peer, {1});  // echoes the session's first epoch
  ASSERT_EQ(Open(p.session, recorded).verdict, LinkAuth::Verdict::kData);
  // The session restarts (new epoch): the recording, replayed to it, is not fresh.
  LinkAuth session2(KeyOf(1), LinkKind::kCan, LinkRole::kSession, 1500);
  EXPECT_EQ(Open(session2, recorded).verdict, LinkAuth::Verdict::kDropped);
  EXPECT_EQ(session2.counters().unconfirmed, 1U);
  EXPECT_EQ(session2.counters().accepted, 0U);
}

TEST(LinkAuth, GarbageIsCountedNeverTaken) {
  LinkAuth a(KeyOf(1), LinkKind::kCan, LinkRole::kPeer, 5);
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> byte(0, 255), length(0, 200);
  for (int i = 0; i < 2000; ++i) {
    Bytes b(static_cast<std::size_t>(length(rng)));
    for (auto& v : b) v = static_cast<std::uint8_t>(byte(rng));
    if (i % 2 == 0 && b.size() >= 8) {  // a valid-looking header half of the time
      b[0] = 'P'; b[1] = 'W'; b[2] = 'L'; b[3] = 'A'; b[4] = 1; b[5] = 1; b[6] = 1; b[7] = 1;
    }
    EXPECT_NE(Open(a, b).verdict, LinkAuth::Verdict::kData);
  }
  const LinkAuthCounters& c = a.counters();
  EXPECT_EQ(c.accepted, 0U);
  EXPECT_EQ(c.malformed + c.bad_tag, 2000U);
  EXPECT_GT(c.bad_tag, 0U);
}

class KeyFile : public ::testing::Test {
 protected:
  fs::path dir_ = fs::temp_directory_path() / ("pwsim_link_key_" + std::to_string(::getpid()));
  void SetUp() override { fs::create_directories(dir_); }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path Write(const std::string& name, const std::string& text, mode_t mode = 0600) {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << text;
    ::chmod(p.c_str(), mode);
    return p;
  }
  static std::string Error(const fs::path& p) {
    try {
      ReadLinkKeyFile(p.string(), nullptr);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
};

const std::string kHex64 = "000102030405060708090a0b0c0d0e0f101112131415161718191a1b1c1d1e1F";

TEST_F(KeyFile, ReadsSixtyFourHexDigitsWithOrWithoutANewline) {
  std::string warning = "x";
  const LinkKey k = ReadLinkKeyFile(Write("a.key", kHex64 + "\n").string(), &warning);
  EXPECT_EQ(warning, "");
  for (std::size_t i = 0; i < 32; ++i) EXPECT_EQ(k.bytes[i], i == 31 ? 0x1F : i);
  EXPECT_EQ(ReadLinkKeyFile(Write("b.key", kHex64).string(), nullptr).bytes, k.bytes);
  EXPECT_EQ(ReadLinkKeyFile(Write("c.key", kHex64 + "\r\n").string(), nullptr).bytes, k.bytes);
}

TEST_F(KeyFile, BadFilesAreRefusedWithTheFileLineAndWhatWasWrong) {
  const auto missing = Error(dir_ / "none.key");
  EXPECT_NE(missing.find("none.key"), std::string::npos) << missing;
  EXPECT_NE(missing.find("no such file"), std::string::npos) << missing;
  const auto short_key = Error(Write("short.key", kHex64.substr(0, 62) + "\n"));
  EXPECT_NE(short_key.find("short.key:1: field 'link key': expected 64 hexadecimal digits"), std::string::npos) << short_key;
  EXPECT_NE(short_key.find("got 62 hexadecimal digits"), std::string::npos) << short_key;
  const auto long_key = Error(Write("long.key", kHex64 + "00"));
  EXPECT_NE(long_key.find("got 66 hexadecimal digits"), std::string::npos) << long_key;
  const auto not_hex = Error(Write("g.key", "0g" + kHex64.substr(2)));
  EXPECT_NE(not_hex.find("'g' at column 2"), std::string::npos) << not_hex;
  const auto two_lines = Error(Write("two.key", kHex64 + "\n\n"));
  EXPECT_NE(two_lines.find("two.key:2"), std::string::npos) << two_lines;
  const auto binary = Error(Write("bin.key", std::string(32, '\x01')));
  EXPECT_NE(binary.find("byte 0x01 at column 1"), std::string::npos) << binary;
  const auto zeros = Error(Write("zero.key", std::string(64, '0')));
  EXPECT_NE(zeros.find("all zeros"), std::string::npos) << zeros;
  const auto huge = Error(Write("huge.key", std::string(10000, 'a')));
  EXPECT_NE(huge.find("10000 bytes"), std::string::npos) << huge;
  EXPECT_NE(Error(dir_).find("a regular file"), std::string::npos);
}

TEST_F(KeyFile, AKeyOthersCanReadIsTakenWithAWarning) {
  std::string warning;
  ReadLinkKeyFile(Write("world.key", kHex64, 0644).string(), &warning);
  EXPECT_NE(warning.find("readable by every user (mode 0644)"), std::string::npos) << warning;
  EXPECT_NE(warning.find("chmod 600"), std::string::npos) << warning;
  ReadLinkKeyFile(Write("group.key", kHex64, 0640).string(), &warning);
  EXPECT_NE(warning.find("readable by its group"), std::string::npos) << warning;
  ReadLinkKeyFile(Write("own.key", kHex64, 0400).string(), &warning);
  EXPECT_EQ(warning, "");
}

TEST(LinkEpoch, StrictlyIncreasesWithinAProcess) {
  std::uint64_t last = NewLinkEpoch();
  EXPECT_GT(last, 1'600'000'000ULL * 1'000'000'000ULL);  // realtime ns, after 2020
  for (int i = 0; i < 1000; ++i) {
    const std::uint64_t e = NewLinkEpoch();
    EXPECT_GT(e, last);
    last = e;
  }
}

}  // namespace
}  // namespace pwsim::hw
