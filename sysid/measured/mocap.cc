#include "sysid/measured/mocap.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

#include "engine/atomic_file.h"
#include "engine/input_error.h"
#include "engine/number_format.h"

namespace pwsim {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct TextLine {
  int number{0};  ///< 1-based
  std::string text;
};

/// Reads every line of `file` (CR stripped). A missing file is an InputError.
std::vector<TextLine> ReadLines(const std::filesystem::path& file, const std::string& what) {
  RequireReadableFile(file, "a readable " + what);
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), 0, "(file)", "a readable " + what, "no such file");
  std::vector<TextLine> lines;
  std::string text;
  int number = 0;
  while (std::getline(in, text)) {
    ++number;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    lines.push_back({number, std::move(text)});
  }
  return lines;
}

std::vector<std::string> Split(const std::string& text, char separator) {
  std::vector<std::string> fields;
  std::size_t begin = 0;
  while (true) {
    const std::size_t end = text.find(separator, begin);
    fields.push_back(text.substr(begin, end == std::string::npos ? std::string::npos : end - begin));
    if (end == std::string::npos) break;
    begin = end + 1;
  }
  return fields;
}

std::string Trim(const std::string& text) {
  const std::size_t begin = text.find_first_not_of(" \t");
  if (begin == std::string::npos) return "";
  const std::size_t end = text.find_last_not_of(" \t");
  return text.substr(begin, end - begin + 1);
}

bool IsBlank(const std::string& text) { return text.find_first_not_of(" \t") == std::string::npos; }

std::string Lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

/// A decimal number, or NaN/Inf spelled as such; nullopt when the text is not a number.
std::optional<double> ParseField(const std::string& raw) {
  const std::string text = Trim(raw);
  if (text.empty()) return std::nullopt;
  const std::string lower = Lower(text);
  const std::string unsigned_lower = (lower[0] == '-' || lower[0] == '+') ? lower.substr(1) : lower;
  if (unsigned_lower == "nan" || unsigned_lower == "nan(ind)") return kNaN;
  if (unsigned_lower == "inf" || unsigned_lower == "infinity") {
    return lower[0] == '-' ? -std::numeric_limits<double>::infinity()
                           : std::numeric_limits<double>::infinity();
  }
  const char* begin = text.data();
  const char* end = text.data() + text.size();
  if (*begin == '+') ++begin;
  double value = 0.0;
  auto [ptr, ec] = std::from_chars(begin, end, value);
  if (ec != std::errc() || ptr != end) return std::nullopt;
  return value;
}

std::string Quoted(const std::string& text) { return "\"" + text + "\""; }

/// `value` to 6 significant digits (a rate computed from rounded times: 99.99999 reads 100).
std::string Significant(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.6g", value);
  return text;
}

void CheckFrameCount(const MocapTrack& track, const MocapReadOptions& options,
                     const std::string& field, int line) {
  if (track.size() >= options.min_frames) return;
  throw InputError(track.file.string(), line, field,
                   "at least " + std::to_string(options.min_frames) + " frames",
                   std::to_string(track.size()) + (track.size() == 0 ? " (an empty track)" : ""));
}

}  // namespace

MocapTrack ReadMocapCsv(const std::filesystem::path& file, const MocapReadOptions& options) {
  const std::vector<TextLine> lines = ReadLines(file, "mocap csv file");
  const std::string name = file.string();
  MocapTrack track;
  track.file = file;

  std::vector<std::string> columns;
  int header_line = 0;
  std::map<std::string, std::size_t> index;
  static const std::vector<std::string> kRequired{"t_s", "x_m", "z_m", "pitch_rad"};
  static const std::vector<std::string> kKnown{"t_s",      "x_m",     "y_m",    "z_m",
                                               "pitch_rad", "roll_rad", "yaw_rad"};
  int last_line = 0;
  for (const TextLine& line : lines) {
    last_line = line.number;
    if (IsBlank(line.text) || Trim(line.text)[0] == '#') continue;
    const std::vector<std::string> fields = Split(line.text, ',');
    if (header_line == 0) {
      header_line = line.number;
      for (std::size_t c = 0; c < fields.size(); ++c) {
        const std::string column = Trim(fields[c]);
        if (index.count(column) > 0) {
          throw InputError(name, line.number, "(header)", "each column named once",
                           Quoted(column) + " twice");
        }
        index[column] = c;
        columns.push_back(column);
      }
      for (const std::string& required : kRequired) {
        if (index.count(required) == 0) {
          throw InputError(name, line.number, required,
                           "a header column named " + required +
                               " (required: t_s, x_m, z_m, pitch_rad)",
                           "header " + Quoted(line.text));
        }
      }
      continue;
    }
    if (fields.size() != columns.size()) {
      throw InputError(name, line.number, "(row)",
                       std::to_string(columns.size()) + " comma-separated values, as the header",
                       std::to_string(fields.size()) + " values");
    }
    double values[7] = {kNaN, kNaN, 0.0, kNaN, kNaN, 0.0, 0.0};
    for (std::size_t k = 0; k < kKnown.size(); ++k) {
      const auto found = index.find(kKnown[k]);
      if (found == index.end()) continue;
      const std::string& raw = fields[found->second];
      const std::optional<double> value = ParseField(raw);
      if (!value) {
        throw InputError(name, line.number, kKnown[k], "a number", Quoted(Trim(raw)));
      }
      if (!std::isfinite(*value)) {
        throw InputError(name, line.number, kKnown[k],
                         "a finite number (a csv track leaves untracked frames out)",
                         Quoted(Trim(raw)));
      }
      values[k] = *value;
    }
    if (!track.t.empty() && !(values[0] > track.t.back())) {
      throw InputError(name, line.number, "t_s", "time strictly increasing",
                       FormatDouble(values[0]) + " after " + FormatDouble(track.t.back()));
    }
    track.t.push_back(values[0]);
    track.x.push_back(values[1]);
    track.y.push_back(values[2]);
    track.z.push_back(values[3]);
    track.pitch.push_back(values[4]);
  }
  if (header_line == 0) {
    throw InputError(name, 0, "(header)", "a header row naming t_s, x_m, z_m, pitch_rad",
                     "an empty file");
  }
  CheckFrameCount(track, options, "(rows)", last_line);
  return track;
}

MocapTrack ReadQtm6dTsv(const std::filesystem::path& file, const std::string& body,
                        const MocapReadOptions& options) {
  const std::vector<TextLine> lines = ReadLines(file, "QTM 6D TSV export");
  const std::string name = file.string();
  MocapTrack track;
  track.file = file;

  // Header: KEY<TAB>value lines until the column line starting "Frame".
  std::map<std::string, std::pair<std::vector<std::string>, int>> header;
  std::size_t cursor = 0;
  for (; cursor < lines.size(); ++cursor) {
    const TextLine& line = lines[cursor];
    if (IsBlank(line.text)) continue;
    std::vector<std::string> fields = Split(line.text, '\t');
    if (fields[0] == "Frame") break;
    const std::string key = fields[0];
    fields.erase(fields.begin());
    while (!fields.empty() && fields.back().empty()) fields.pop_back();
    header[key] = {fields, line.number};
  }
  if (lines.empty() || std::all_of(lines.begin(), lines.end(),
                                   [](const TextLine& l) { return IsBlank(l.text); })) {
    throw InputError(name, 0, "(file)", "a QTM 6D TSV export", "an empty file");
  }
  if (const auto found = header.find("DATA_INCLUDED"); found != header.end()) {
    const std::string got = found->second.first.empty() ? "" : found->second.first[0];
    if (got != "6D") {
      throw InputError(name, found->second.second, "DATA_INCLUDED", "6D (a 6DOF body export)",
                       Quoted(got));
    }
  }
  if (const auto found = header.find("BODY_NAMES"); found != header.end()) {
    const auto& names = found->second.first;
    if (std::find(names.begin(), names.end(), body) == names.end()) {
      std::string listed;
      for (const std::string& n : names) listed += (listed.empty() ? "" : ", ") + Quoted(n);
      throw InputError(name, found->second.second, "BODY_NAMES",
                       "a 6D body named " + Quoted(body), listed.empty() ? "no bodies" : listed);
    }
  }
  if (cursor >= lines.size()) {
    throw InputError(name, lines.back().number, "Frame",
                     "a column line starting Frame<TAB>Time<TAB><body> X ...", "no column line");
  }

  // Column line.
  const int column_line = lines[cursor].number;
  std::vector<std::string> columns = Split(lines[cursor].text, '\t');
  if (!columns.empty() && columns.back().empty()) columns.pop_back();  // the trailing tab
  if (columns.size() < 2 || columns[1] != "Time") {
    throw InputError(name, column_line, "Time", "column 2 named Time",
                     columns.size() < 2 ? "nothing" : Quoted(columns[1]));
  }
  const auto first = std::find(columns.begin(), columns.end(), body + " X");
  if (first == columns.end()) {
    throw InputError(name, column_line, body + " X",
                     "a column " + Quoted(body + " X") + " starting the body's 16 columns",
                     "no such column");
  }
  const std::size_t base = static_cast<std::size_t>(first - columns.begin());
  static const std::vector<std::string> kBodyColumns{
      "X",      "Y",      "Z",      "Roll",   "Pitch",  "Yaw",    "Residual", "Rot[0]",
      "Rot[1]", "Rot[2]", "Rot[3]", "Rot[4]", "Rot[5]", "Rot[6]", "Rot[7]",   "Rot[8]"};
  if (base + kBodyColumns.size() > columns.size()) {
    throw InputError(name, column_line, body + " X",
                     "16 columns per body (X Y Z Roll Pitch Yaw Residual Rot[0]..Rot[8])",
                     std::to_string(columns.size() - base) + " columns");
  }
  for (std::size_t k = 1; k < kBodyColumns.size(); ++k) {
    if (columns[base + k] != kBodyColumns[k]) {
      throw InputError(name, column_line, body + " " + kBodyColumns[k],
                       "column " + std::to_string(base + k + 1) + " named " +
                           Quoted(kBodyColumns[k]),
                       Quoted(columns[base + k]));
    }
  }
  const std::string body_field = body + " X";

  // Rows.
  int rows = 0;
  int last_line = column_line;
  double last_time = -std::numeric_limits<double>::infinity();
  bool have_time = false;
  int run_start_line = 0;  // first line of the current untracked run (0: none)
  double first_time = 0.0;
  for (++cursor; cursor < lines.size(); ++cursor) {
    const TextLine& line = lines[cursor];
    if (IsBlank(line.text)) continue;
    last_line = line.number;
    std::vector<std::string> fields = Split(line.text, '\t');
    if (fields.size() > 1 && fields.back().empty()) fields.pop_back();  // the trailing tab
    if (fields.size() != columns.size()) {
      throw InputError(name, line.number, "(row)",
                       std::to_string(columns.size()) +
                           " tab-separated fields, as the column line (plus a trailing tab)",
                       std::to_string(fields.size()) + " fields");
    }
    ++rows;
    auto number = [&](std::size_t column, bool allow_missing) {
      const std::optional<double> value = ParseField(fields[column]);
      if (value) return *value;
      if (allow_missing && Trim(fields[column]).empty()) return kNaN;
      throw InputError(name, line.number, columns[column],
                       allow_missing ? "a number (or NaN where untracked)" : "a number",
                       Quoted(Trim(fields[column])));
    };
    const double t = number(1, false);
    if (!std::isfinite(t)) {
      throw InputError(name, line.number, "Time", "a finite time in seconds",
                       Quoted(Trim(fields[1])));
    }
    if (have_time && !(t > last_time)) {
      throw InputError(name, line.number, "Time", "time strictly increasing",
                       FormatDouble(t) + " after " + FormatDouble(last_time));
    }
    if (!have_time) first_time = t;
    double body_values[16];
    bool tracked = true;
    for (std::size_t k = 0; k < kBodyColumns.size(); ++k) {
      body_values[k] = number(base + k, true);
      if (k != 6 && !std::isfinite(body_values[k])) tracked = false;  // residual may be anything
    }
    const double* rot = body_values + 7;  // column-major: rot[i + 3 j] = R[i][j]
    if (tracked && std::all_of(rot, rot + 9, [](double r) { return r == 0.0; })) tracked = false;
    if (!tracked) {
      ++track.untracked_frames;
      if (run_start_line == 0) run_start_line = line.number;
    } else {
      if (run_start_line != 0 && !track.t.empty() &&
          t - track.t.back() > options.max_untracked_gap) {
        throw InputError(name, run_start_line, body_field,
                         "untracked runs no longer than " +
                             FormatDouble(options.max_untracked_gap) + " s",
                         "a run of non-finite frames from t = " + FormatDouble(track.t.back()) +
                             " s to " + FormatDouble(t) + " s");
      }
      run_start_line = 0;
      track.t.push_back(t);
      track.x.push_back(body_values[0] * 1e-3);
      track.y.push_back(body_values[1] * 1e-3);
      track.z.push_back(body_values[2] * 1e-3);
      track.pitch.push_back(std::atan2(rot[2], std::hypot(rot[0], rot[1])));
    }
    last_time = t;
    have_time = true;
  }
  if (const auto found = header.find("NO_OF_FRAMES"); found != header.end()) {
    const std::string got = found->second.first.empty() ? "" : found->second.first[0];
    const std::optional<double> declared = ParseField(got);
    if (!declared || *declared != static_cast<double>(rows)) {
      throw InputError(name, found->second.second, "NO_OF_FRAMES",
                       "the number of frame rows (" + std::to_string(rows) + ")", Quoted(got));
    }
  }
  if (const auto found = header.find("FREQUENCY"); found != header.end()) {
    // Every frame has a row (untracked ones too), so the Time column gives the frame rate:
    // (rows - 1) / (last - first). QTM writes Time rounded (to 1 ms or finer): over the whole
    // record the rounding is far below the 1 % allowed here.
    const std::string got = found->second.first.empty() ? "" : found->second.first[0];
    const std::optional<double> declared = ParseField(got);
    if (!declared || !std::isfinite(*declared) || !(*declared > 0.0)) {
      throw InputError(name, found->second.second, "FREQUENCY", "the frame rate in Hz (a positive number)",
                       Quoted(got));
    }
    if (rows >= 2) {
      const double from_time = (rows - 1) / (last_time - first_time);
      if (std::abs(from_time - *declared) > 0.01 * *declared) {
        throw InputError(name, found->second.second, "FREQUENCY",
                         "the frame rate of the Time column, " + Significant(from_time) + " Hz (" +
                             std::to_string(rows) + " frames from " + FormatDouble(first_time) + " s to " +
                             FormatDouble(last_time) + " s), within 1 %",
                         Quoted(got) + " Hz");
      }
    }
  }
  if (track.size() < options.min_frames) {
    throw InputError(name, rows == 0 ? column_line : last_line, body_field,
                     "at least " + std::to_string(options.min_frames) + " tracked frames",
                     std::to_string(track.size()) + " tracked of " + std::to_string(rows) +
                         " frames");
  }
  return track;
}

MocapTrack ReadMocapFile(const std::filesystem::path& file, const std::string& format,
                         const std::string& body, const MocapReadOptions& options) {
  if (format == "csv") return ReadMocapCsv(file, options);
  if (format == "qtm-6d-tsv") return ReadQtm6dTsv(file, body, options);
  throw InputError(file.string(), 0, "mocap.format", "csv or qtm-6d-tsv", Quoted(format));
}

namespace {

std::string Fixed(double value, int precision) {
  char buffer[64];
  auto [ptr, ec] =
      std::to_chars(buffer, buffer + sizeof(buffer), value, std::chars_format::fixed, precision);
  return ec == std::errc() ? std::string(buffer, ptr) : std::string("NaN");
}

}  // namespace

void WriteMocapCsv(const std::vector<MocapFrame>& frames, const std::filesystem::path& file) {
  std::string text = "# pwsim mocap track: O_V in frame W (x along the path, z up)\n";
  text += "t_s,x_m,y_m,z_m,pitch_rad\n";
  for (const MocapFrame& f : frames) {
    if (!f.tracked) continue;
    // 10 µm and 1 µrad: far below any mocap noise.
    text += Fixed(f.t, 5) + "," + Fixed(f.x, 5) + "," + Fixed(f.y, 5) + "," + Fixed(f.z, 5) + "," +
            Fixed(f.pitch, 6) + "\n";
  }
  WriteFileAtomically(file, text);
}

void WriteQtm6dTsv(const std::vector<MocapFrame>& frames, const std::string& body, double rate_hz,
                   const std::filesystem::path& file) {
  std::string text;
  text += "NO_OF_FRAMES\t" + std::to_string(frames.size()) + "\n";
  text += "NO_OF_CAMERAS\t12\n";
  text += "NO_OF_BODIES\t1\n";
  text += "FREQUENCY\t" + FormatDouble(rate_hz) + "\n";
  text += "NO_OF_ANALOG\t0\n";
  text += "ANALOG_FREQUENCY\t0\n";
  text += "DESCRIPTION\t--\n";
  text += "TIME_STAMP\t2026-01-01, 00:00:00\t0.00000000\n";
  text += "DATA_INCLUDED\t6D\n";
  text += "BODY_NAMES\t" + body + "\n";
  text += "Frame\tTime\t" + body + " X\tY\tZ\tRoll\tPitch\tYaw\tResidual";
  for (int k = 0; k < 9; ++k) text += "\tRot[" + std::to_string(k) + "]";
  text += "\t\n";
  constexpr double kRadToDeg = 57.29577951308232;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const MocapFrame& f = frames[k];
    text += std::to_string(k + 1) + "\t" + Fixed(f.t, 5);
    if (!f.tracked) {
      for (int c = 0; c < 16; ++c) text += "\tNaN";
      text += "\t\n";
      continue;
    }
    // Pure pitch θ (nose-up): forward axis (cos θ, 0, sin θ). QTM's Euler pitch is about +Y,
    // which lifts the nose for negative angles, hence the sign.
    const double c = std::cos(f.pitch);
    const double s = std::sin(f.pitch);
    const double rot[9] = {c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c};  // column-major
    text += "\t" + Fixed(f.x * 1e3, 3) + "\t" + Fixed(f.y * 1e3, 3) + "\t" + Fixed(f.z * 1e3, 3);
    text += "\t0.000000\t" + Fixed(-f.pitch * kRadToDeg, 6) + "\t0.000000\t0.800";
    for (double r : rot) text += "\t" + Fixed(r, 8);
    text += "\t\n";
  }
  WriteFileAtomically(file, text);
}

}  // namespace pwsim
