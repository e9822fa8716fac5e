#pragma once
// --link-key FILE, shared by session, drive, platform-sim and hmd-peer: the pre-shared key of
// the links' authenticated mode (hardware/link_auth.h). Absent: plain links (cannelloni, the
// HMD protocol as is). Wiring only.

#include <iostream>
#include <optional>
#include <string>

#include "app/cli.h"
#include "hardware/link_auth.h"

namespace pwsim::app {

inline OptionSpec LinkKeyOptionSpec() {
  return {"link-key", "FILE", "-", "",
          "authenticated links: every datagram carries a tag (HMAC-SHA-512-256) under this pre-shared key "
          "(64 hex digits; the same file at both ends) and replays are refused; not cannelloni on the wire "
          "(docs/hardware.md, Links: plain and authenticated)"};
}

/// The key, or nothing when --link-key is absent. Warns on stderr when the file is readable by
/// others. @throws InputError on a bad key file.
inline std::optional<hw::LinkKey> LinkKeyOption(const ParsedArgs& args, const std::string& who) {
  const std::string path = args.Get("link-key");
  if (path.empty()) return std::nullopt;
  std::string warning;
  const hw::LinkKey key = hw::ReadLinkKeyFile(path, &warning);
  if (!warning.empty()) std::cerr << "pwsim " << who << ": warning: " << warning << "\n";
  return key;
}

}  // namespace pwsim::app
