#pragma once
// The immersive session, one header for all of it (see each part for the details):
//   session_config.h  configuration and its log-header form
//   session_core.h    SessionCore: the deterministic tick (inputs -> CAN, HMD, log lines)
//   session_report.h  what a session measured (JSON report)
//   session_replay.h  the log's input lines and the offline replay
//   session_text.h    text helpers of the log (round-trip numbers, hex)
// The real-time loop around the core is session_runner.h.

#include "hardware/session_config.h"
#include "hardware/session_core.h"
#include "hardware/session_replay.h"
#include "hardware/session_report.h"
#include "hardware/session_text.h"
