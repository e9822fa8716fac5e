#pragma once
// Motion-capture tracks of the chair's rigid body (measured-trials.md, "mocap"): readers for
// the `csv` format and the Qualisys QTM 6D TSV export (`qtm-6d-tsv`), and writers for both.
// Everything is converted to SI at this boundary: metres, seconds, radians, frame W.
//
//   MocapTrack track = ReadMocapCsv("trial/mocap.csv");
//   MocapTrack track = ReadQtm6dTsv("trial/mocap.tsv", "wheelchair");
//
// Every malformed file throws InputError naming file, line, field and what was expected.

#include <filesystem>
#include <string>
#include <vector>

namespace pwsim {

/// The chair body's track in W, one entry per kept frame, time strictly increasing.
struct MocapTrack {
  std::vector<double> t;      ///< [s]
  std::vector<double> x;      ///< [m] along the path (O_V)
  std::vector<double> y;      ///< [m] lateral (0 when the file has none)
  std::vector<double> z;      ///< [m] altitude of O_V
  std::vector<double> pitch;  ///< θ [rad], positive nose-up
  int untracked_frames{0};    ///< frames left out because the body was not tracked
  std::filesystem::path file;

  std::size_t size() const { return t.size(); }
};

struct MocapReadOptions {
  /// Longest run of untracked (non-finite) frames accepted [s]; a longer run is an error
  /// (nothing sensible can be interpolated across it, e.g. through an impact).
  double max_untracked_gap{0.5};
  /// Fewest frames a usable track has.
  std::size_t min_frames{2};
};

/// Reads a `csv` mocap file: header row with t_s, x_m, z_m, pitch_rad (any order; optional
/// y_m, roll_rad, yaw_rad), `#` comment lines, time strictly increasing, every value finite.
MocapTrack ReadMocapCsv(const std::filesystem::path& file, const MocapReadOptions& options = {});

/// Reads a QTM 6D TSV export and returns the track of `body`. Positions mm -> m; pitch from
/// the column-major rotation matrix: θ = atan2(R20, hypot(R00, R10)). Frames whose fields for
/// the body are not finite numbers are left out and counted in `untracked_frames`. A FREQUENCY
/// header, when present, must match the Time column's frame rate (rows − 1)/(t_last − t_first)
/// within 1 %; NO_OF_FRAMES, when present, the number of frame rows.
MocapTrack ReadQtm6dTsv(const std::filesystem::path& file, const std::string& body,
                        const MocapReadOptions& options = {});

/// Reads `file` in `format` ("csv" or "qtm-6d-tsv"); `body` is used by qtm-6d-tsv only.
MocapTrack ReadMocapFile(const std::filesystem::path& file, const std::string& format,
                         const std::string& body, const MocapReadOptions& options = {});

/// One frame to write; non-finite fields mark an untracked frame (QTM writes NaN).
struct MocapFrame {
  double t{0.0};      ///< [s]
  double x{0.0};      ///< [m]
  double y{0.0};      ///< [m]
  double z{0.0};      ///< [m]
  double pitch{0.0};  ///< [rad]
  bool tracked{true};
};

/// `csv` text (untracked frames are simply absent). Atomic write.
void WriteMocapCsv(const std::vector<MocapFrame>& frames, const std::filesystem::path& file);
/// QTM 6D TSV text for one body, `rate_hz` in the FREQUENCY header. Atomic write.
void WriteQtm6dTsv(const std::vector<MocapFrame>& frames, const std::string& body, double rate_hz,
                   const std::filesystem::path& file);

}  // namespace pwsim
