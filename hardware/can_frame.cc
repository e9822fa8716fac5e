#include "hardware/can_frame.h"

#include <cstring>

#include "engine/check.h"

namespace pwsim::hw {
namespace {

constexpr char kHex[] = "0123456789ABCDEF";

int HexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

void PutU32Be(std::uint8_t* p, std::uint32_t v) {
  p[0] = static_cast<std::uint8_t>(v >> 24);
  p[1] = static_cast<std::uint8_t>(v >> 16);
  p[2] = static_cast<std::uint8_t>(v >> 8);
  p[3] = static_cast<std::uint8_t>(v);
}

std::uint32_t GetU32Be(const std::uint8_t* p) {
  return (static_cast<std::uint32_t>(p[0]) << 24) | (static_cast<std::uint32_t>(p[1]) << 16) |
         (static_cast<std::uint32_t>(p[2]) << 8) | static_cast<std::uint32_t>(p[3]);
}

}  // namespace

CanFrame MakeFrame(std::uint32_t id, std::initializer_list<std::uint8_t> bytes) {
  PWSIM_DEMAND(bytes.size() <= 8);
  CanFrame frame;
  frame.id = id;
  frame.len = static_cast<std::uint8_t>(bytes.size());
  std::size_t i = 0;
  for (std::uint8_t b : bytes) frame.data[i++] = b;
  return frame;
}

CanFrame MakeErrorFrame(std::uint32_t error_class, std::uint8_t ctrl_state) {
  CanFrame frame;
  frame.id = kCanErrFlag | (error_class & kCanEffMask);
  frame.len = 8;
  frame.data[1] = ctrl_state;
  return frame;
}

bool IsValidFrame(const CanFrame& frame) {
  if (frame.len > 8) return false;
  if (frame.error()) return (frame.id & kCanEffFlag) == 0 && (frame.id & kCanRtrFlag) == 0;
  if (frame.extended()) return (frame.id & ~(kCanEffFlag | kCanRtrFlag | kCanEffMask)) == 0;
  return (frame.id & ~(kCanRtrFlag | kCanSffMask)) == 0;
}

const char* CodecErrorName(CodecError error) {
  switch (error) {
    case CodecError::kOk: return "ok";
    case CodecError::kTruncated: return "truncated";
    case CodecError::kBadLength: return "bad length";
    case CodecError::kBadVersion: return "bad version";
    case CodecError::kBadOpcode: return "bad op code";
    case CodecError::kBadSyntax: return "bad syntax";
    case CodecError::kBadId: return "bad identifier";
    case CodecError::kTrailing: return "trailing bytes";
    case CodecError::kNoSpace: return "no space";
  }
  return "?";
}

void EncodeRawFrame(const CanFrame& frame, std::span<std::uint8_t, kRawFrameSize> out) {
  std::memset(out.data(), 0, kRawFrameSize);
  std::memcpy(out.data(), &frame.id, 4);  // host byte order, as struct can_frame
  out[4] = frame.len;
  std::memcpy(out.data() + 8, frame.data.data(), 8);
}

CodecError DecodeRawFrame(std::span<const std::uint8_t> in, CanFrame* frame) {
  if (in.size() < kRawFrameSize) return CodecError::kTruncated;
  if (in.size() > kRawFrameSize) return CodecError::kTrailing;
  CanFrame f;
  std::memcpy(&f.id, in.data(), 4);
  f.len = in[4];
  if (f.len > 8) return CodecError::kBadLength;
  std::memcpy(f.data.data(), in.data() + 8, 8);
  if (!IsValidFrame(f)) return CodecError::kBadId;
  *frame = f;
  return CodecError::kOk;
}

std::size_t FormatFrameText(const CanFrame& frame, std::span<char, kFrameTextMax> out) {
  std::size_t n = 0;
  auto put_hex = [&](std::uint32_t value, int digits) {
    for (int d = digits - 1; d >= 0; --d) out[n++] = kHex[(value >> (4 * d)) & 0xFU];
  };
  if (frame.error()) {
    put_hex(frame.id & (kCanErrFlag | kCanEffMask), 8);
  } else if (frame.extended()) {
    put_hex(frame.id & kCanEffMask, 8);
  } else {
    put_hex(frame.id & kCanSffMask, 3);
  }
  out[n++] = '#';
  if (frame.remote() && !frame.error()) {
    out[n++] = 'R';
    if (frame.len > 0 && frame.len <= 8) out[n++] = kHex[frame.len];  // can-utils: "R<dlc>"
    return n;
  }
  for (std::size_t i = 0; i < frame.len && i < 8; ++i) put_hex(frame.data[i], 2);
  return n;
}

std::string FormatFrameText(const CanFrame& frame) {
  std::array<char, kFrameTextMax> text{};
  return std::string(text.data(), FormatFrameText(frame, text));
}

CodecError ParseFrameText(std::string_view text, CanFrame* frame) {
  const std::size_t hash = text.find('#');
  if (hash == std::string_view::npos) return CodecError::kBadSyntax;
  if (hash != 3 && hash != 8) return CodecError::kBadId;
  std::uint32_t id = 0;
  for (std::size_t i = 0; i < hash; ++i) {
    const int v = HexValue(text[i]);
    if (v < 0) return CodecError::kBadSyntax;
    id = (id << 4) | static_cast<std::uint32_t>(v);
  }
  CanFrame f;
  if (hash == 3) {
    if (id > kCanSffMask) return CodecError::kBadId;
    f.id = id;
  } else if ((id & kCanErrFlag) != 0) {
    if ((id & ~(kCanErrFlag | kCanEffMask)) != 0) return CodecError::kBadId;
    f.id = id;
  } else {
    if (id > kCanEffMask) return CodecError::kBadId;
    f.id = id | kCanEffFlag;
  }
  std::string_view rest = text.substr(hash + 1);
  if (!rest.empty() && rest[0] == '#') return CodecError::kBadLength;  // CAN FD: not carried
  if (!rest.empty() && (rest[0] == 'R' || rest[0] == 'r')) {
    if (f.error()) return CodecError::kBadSyntax;
    f.id |= kCanRtrFlag;
    if (rest.size() == 2 && rest[1] >= '0' && rest[1] <= '8') {
      f.len = static_cast<std::uint8_t>(rest[1] - '0');
    } else if (rest.size() != 1) {
      return CodecError::kBadSyntax;
    }
    *frame = f;
    return CodecError::kOk;
  }
  std::size_t n = 0;
  std::size_t i = 0;
  while (i < rest.size()) {
    if (rest[i] == '.') {  // can-utils allows '.' between bytes
      ++i;
      continue;
    }
    if (i + 1 >= rest.size()) return CodecError::kBadSyntax;
    const int hi = HexValue(rest[i]);
    const int lo = HexValue(rest[i + 1]);
    if (hi < 0 || lo < 0) return CodecError::kBadSyntax;
    if (n >= 8) return CodecError::kBadLength;
    f.data[n++] = static_cast<std::uint8_t>(hi * 16 + lo);
    i += 2;
  }
  f.len = static_cast<std::uint8_t>(n);
  *frame = f;
  return CodecError::kOk;
}

std::size_t CannelloniFrameSize(const CanFrame& frame) {
  return 5 + ((frame.remote() && !frame.error()) ? 0 : frame.len);
}

std::size_t EncodeCannelloni(std::uint8_t seq, std::span<const CanFrame> frames,
                             std::span<std::uint8_t> out) {
  std::size_t need = kCannelloniHeaderSize;
  for (const CanFrame& f : frames) need += CannelloniFrameSize(f);
  if (need > out.size() || frames.size() > 0xFFFF) return 0;
  std::uint8_t* p = out.data();
  p[0] = kCannelloniVersion;
  p[1] = kCannelloniOpData;
  p[2] = seq;
  p[3] = static_cast<std::uint8_t>(frames.size() >> 8);
  p[4] = static_cast<std::uint8_t>(frames.size());
  p += kCannelloniHeaderSize;
  for (const CanFrame& f : frames) {
    PutU32Be(p, f.id);
    const std::uint8_t len = f.len > 8 ? std::uint8_t{8} : f.len;
    p[4] = len;
    p += 5;
    if (!(f.remote() && !f.error())) {
      std::memcpy(p, f.data.data(), len);
      p += len;
    }
  }
  return need;
}

CodecError DecodeCannelloni(std::span<const std::uint8_t> in, std::uint8_t* seq,
                            std::vector<CanFrame>* frames) {
  if (in.size() < kCannelloniHeaderSize) return CodecError::kTruncated;
  if (in[0] != kCannelloniVersion) return CodecError::kBadVersion;
  if (in[1] != kCannelloniOpData) return CodecError::kBadOpcode;
  const std::size_t count = (static_cast<std::size_t>(in[3]) << 8) | in[4];
  std::size_t pos = kCannelloniHeaderSize;
  const std::size_t first = frames->size();
  for (std::size_t k = 0; k < count; ++k) {
    if (pos + 5 > in.size()) {
      frames->resize(first);
      return CodecError::kTruncated;
    }
    CanFrame f;
    f.id = GetU32Be(in.data() + pos);
    const std::uint8_t len = in[pos + 4];
    if ((len & 0x80U) != 0 || len > 8) {  // MSB set = CAN FD, not carried here
      frames->resize(first);
      return CodecError::kBadLength;
    }
    f.len = len;
    pos += 5;
    if (!(f.remote() && !f.error())) {
      if (pos + len > in.size()) {
        frames->resize(first);
        return CodecError::kTruncated;
      }
      std::memcpy(f.data.data(), in.data() + pos, len);
      pos += len;
    }
    if (!IsValidFrame(f)) {
      frames->resize(first);
      return CodecError::kBadId;
    }
    frames->push_back(f);
  }
  if (pos != in.size()) {
    frames->resize(first);
    return CodecError::kTrailing;
  }
  *seq = in[2];
  return CodecError::kOk;
}

}  // namespace pwsim::hw
