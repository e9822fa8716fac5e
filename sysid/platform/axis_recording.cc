#include "sysid/platform/axis_recording.h"

#include <matio.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <sstream>

#include "engine/atomic_file.h"
#include "engine/input_error.h"
#include "engine/number_format.h"
#include "engine/yaml_reader.h"

namespace pwsim::sysid::platform {
namespace {

// --- MATLAB files through libmatio ------------------------------------------------------
struct MatCloser {
  void operator()(mat_t* m) const { Mat_Close(m); }
};
struct VarFreer {
  void operator()(matvar_t* v) const { Mat_VarFree(v); }
};

/// A MATLAB v5 file (header text, version 0x0100 and "IM"/"MI" at bytes 124..127) whose data
/// elements do not fit in it was cut short: "" when whole (or not v5), else where it ends.
/// After the 128-byte header every element is a tag (type, byte count; a small element packs
/// both and up to 4 data bytes in 8 bytes), its data, then padding to 8 bytes (none after a
/// compressed element).
std::string V5Truncation(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < 128) {
    if (bytes.rfind("MATLAB 5.0", 0) != 0) return "";
    return "cut short: " + std::to_string(bytes.size()) + " of the 128 header bytes";
  }
  const bool little = bytes[126] == 'I' && bytes[127] == 'M';
  const bool big = bytes[126] == 'M' && bytes[127] == 'I';
  if (!little && !big) return "";
  auto u16 = [&](std::size_t at) {
    const auto b0 = static_cast<unsigned char>(bytes[at]), b1 = static_cast<unsigned char>(bytes[at + 1]);
    return little ? static_cast<std::uint32_t>(b0 | (b1 << 8)) : static_cast<std::uint32_t>(b1 | (b0 << 8));
  };
  auto u32 = [&](std::size_t at) {
    std::uint32_t value = 0;
    for (int k = 0; k < 4; ++k) {
      const auto b = static_cast<unsigned char>(bytes[at + static_cast<std::size_t>(little ? 3 - k : k)]);
      value = (value << 8) | b;
    }
    return value;
  };
  if (u16(124) != 0x0100) return "";  // v7.3 (HDF5) and others: left to libmatio
  std::size_t at = 128;
  int element = 0;
  while (at < bytes.size()) {
    ++element;
    if (bytes.size() - at < 8) {
      return "cut short: element " + std::to_string(element) + " at byte " + std::to_string(at) + " has " +
             std::to_string(bytes.size() - at) + " of its 8 tag bytes (file of " + std::to_string(bytes.size()) +
             " bytes)";
    }
    const std::uint32_t type = u32(at);
    if ((type >> 16) != 0) {  // small data element
      at += 8;
      continue;
    }
    const std::uint64_t count = u32(at + 4);
    const std::uint64_t end = at + 8 + count;
    if (end > bytes.size()) {
      return "cut short: element " + std::to_string(element) + " at byte " + std::to_string(at) + " needs " +
             std::to_string(count) + " data bytes, the file ends after " + std::to_string(bytes.size() - at - 8) +
             " (file of " + std::to_string(bytes.size()) + " bytes)";
    }
    at = static_cast<std::size_t>(type == 15 ? end : std::min<std::uint64_t>((end + 7) / 8 * 8, bytes.size()));
  }
  return "";
}

class MatSource {
 public:
  explicit MatSource(std::filesystem::path file) : file_(std::move(file)) {
    RequireReadableFile(file_, "a MATLAB .mat file (v4, v5 or v7.3)");
    std::error_code error;
    if (std::filesystem::is_regular_file(file_, error) && std::filesystem::file_size(file_, error) == 0)
      throw InputError(file_.string(), 0, "(file)", "a MATLAB .mat file (v4, v5 or v7.3)", "an empty file (0 bytes)");
    if (const std::string cut = V5Truncation(file_); !cut.empty())
      throw InputError(file_.string(), 0, "(file)", "a complete MATLAB v5 .mat file", "a truncated file, " + cut);
    mat_.reset(Mat_Open(file_.c_str(), MAT_ACC_RDONLY));
    if (!mat_)
      throw InputError(file_.string(), 0, "(file)", "a readable MATLAB .mat file (v4, v5 or v7.3)",
                       std::filesystem::exists(file_) ? "unreadable" : "no such file");
  }
  bool Has(const std::string& name) {
    std::unique_ptr<matvar_t, VarFreer> v(Mat_VarReadInfo(mat_.get(), name.c_str()));
    return v != nullptr;
  }
  /// The names of the file's variables, "a, b, c" ("none" for a file without any).
  std::string Names() {
    Mat_Rewind(mat_.get());
    std::string names;
    while (true) {
      std::unique_ptr<matvar_t, VarFreer> v(Mat_VarReadNextInfo(mat_.get()));
      if (!v) break;
      names += (names.empty() ? "" : ", ") + std::string(v->name ? v->name : "?");
    }
    return names.empty() ? "none" : names;
  }
  std::vector<double> Vector(const std::string& name, const std::string& field) {
    std::unique_ptr<matvar_t, VarFreer> v(Mat_VarRead(mat_.get(), name.c_str()));
    if (!v)
      throw InputError(file_.string(), 0, field, "a variable named '" + name + "'",
                       "none (the file holds: " + Names() + ")");
    if (v->isComplex || v->data == nullptr || v->rank != 2 ||
        (v->class_type != MAT_C_DOUBLE && v->class_type != MAT_C_SINGLE))
      throw InputError(file_.string(), 0, field + " (variable '" + name + "')",
                       "a real double or single vector", "another kind of variable");
    if (v->dims[0] != 1 && v->dims[1] != 1)
      throw InputError(file_.string(), 0, field + " (variable '" + name + "')",
                       "a vector (N x 1 or 1 x N)",
                       std::to_string(v->dims[0]) + " x " + std::to_string(v->dims[1]));
    const std::size_t n = v->dims[0] * v->dims[1];
    std::vector<double> out(n);
    if (v->class_type == MAT_C_DOUBLE) {
      const auto* d = static_cast<const double*>(v->data);
      out.assign(d, d + n);
    } else {
      const auto* d = static_cast<const float*>(v->data);
      for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<double>(d[i]);
    }
    return out;
  }

 private:
  std::filesystem::path file_;
  std::unique_ptr<mat_t, MatCloser> mat_;
};

// --- CSV -----------------------------------------------------------------------------------
class CsvSource {
 public:
  explicit CsvSource(std::filesystem::path file) : file_(std::move(file)) {
    RequireReadableFile(file_, "a readable CSV file");
    std::ifstream in(file_);
    if (!in) throw InputError(file_.string(), 0, "(file)", "a readable CSV file", "no such file");
    std::string line;
    int line_no = 0;
    bool header = false;
    while (std::getline(in, line)) {
      ++line_no;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (line.empty() || line[0] == '#') continue;
      std::vector<std::string> cells;
      std::stringstream ss(line);
      std::string cell;
      while (std::getline(ss, cell, ',')) {
        const auto b = cell.find_first_not_of(" \t");
        const auto e = cell.find_last_not_of(" \t");
        cells.push_back(b == std::string::npos ? "" : cell.substr(b, e - b + 1));
      }
      if (!header) {
        names_ = cells;
        columns_.assign(names_.size(), {});
        header = true;
        continue;
      }
      if (cells.size() != names_.size())
        throw InputError(file_.string(), line_no, "(row)",
                         std::to_string(names_.size()) + " comma-separated values as in the header",
                         std::to_string(cells.size()));
      for (std::size_t c = 0; c < cells.size(); ++c) {
        double value = 0.0;
        const char* first = cells[c].data();
        const char* last = first + cells[c].size();
        auto [ptr, ec] = std::from_chars(first, last, value);
        if (ec != std::errc() || ptr != last)
          throw InputError(file_.string(), line_no, "column '" + names_[c] + "'", "a number",
                           "\"" + cells[c] + "\"");
        columns_[c].push_back(value);
      }
      lines_.push_back(line_no);
    }
    if (!header) throw InputError(file_.string(), 0, "(header)", "a header row of column names", "none");
  }
  bool Has(const std::string& name) const { return Index(name) >= 0; }
  std::vector<double> Vector(const std::string& name, const std::string& field) const {
    const int i = Index(name);
    if (i < 0) throw InputError(file_.string(), 1, field, "a column named '" + name + "'", "none");
    return columns_[static_cast<std::size_t>(i)];
  }
  /// The 1-based line of each row (sample).
  const std::vector<int>& lines() const { return lines_; }

 private:
  int Index(const std::string& name) const {
    for (std::size_t i = 0; i < names_.size(); ++i)
      if (names_[i] == name) return static_cast<int>(i);
    return -1;
  }
  std::filesystem::path file_;
  std::vector<std::string> names_;
  std::vector<std::vector<double>> columns_;
  std::vector<int> lines_;
};

struct Source {
  std::filesystem::path file;
  std::unique_ptr<MatSource> mat;
  std::unique_ptr<CsvSource> csv;
  std::vector<double> Vector(const std::string& name, const std::string& field) {
    return mat ? mat->Vector(name, field) : csv->Vector(name, field);
  }
  bool Has(const std::string& name) { return mat ? mat->Has(name) : csv->Has(name); }
  /// The line of each sample (CSV), or nullptr (a .mat file has no lines).
  const std::vector<int>* lines() const { return csv ? &csv->lines() : nullptr; }
};

/// The file's line of sample `i` (0-based), 0 without lines.
int LineOfSample(const std::vector<int>* lines, std::size_t i) {
  return lines != nullptr && i < lines->size() ? (*lines)[i] : 0;
}

void CheckFinite(const std::vector<double>& v, const std::filesystem::path& file,
                 const std::string& field, const std::vector<int>* lines = nullptr) {
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]))
      throw InputError(file.string(), LineOfSample(lines, i), field, "finite samples",
                       "a non-finite value at sample " + std::to_string(i + 1));
}

void CheckLength(const std::vector<double>& v, std::size_t n, const std::filesystem::path& file,
                 const std::string& field) {
  if (v.size() != n)
    throw InputError(file.string(), 0, field, std::to_string(n) + " samples (as the time vector)",
                     std::to_string(v.size()));
}

double UniformStep(const std::vector<double>& t, const std::filesystem::path& file,
                   const std::string& field, const std::vector<int>* lines = nullptr) {
  if (t.size() < 16)
    throw InputError(file.string(), 0, field, "at least 16 samples", std::to_string(t.size()));
  // Every step within 1 % of the median step (the median is not moved by the faulty step).
  std::vector<double> steps(t.size() - 1);
  for (std::size_t i = 1; i < t.size(); ++i) steps[i - 1] = t[i] - t[i - 1];
  std::vector<double> sorted = steps;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2),
                   sorted.end());
  const double median = sorted[sorted.size() / 2];
  if (!(median > 0.0))
    throw InputError(file.string(), 0, field, "increasing time", "a median step of " + FormatDouble(median) + " s");
  for (std::size_t i = 0; i < steps.size(); ++i)
    if (std::abs(steps[i] - median) > 0.01 * median)
      throw InputError(file.string(), LineOfSample(lines, i + 1), field,
                       "uniform sampling (every step within 1 % of " + FormatDouble(median) + " s)",
                       "a step of " + FormatDouble(steps[i]) + " s at sample " + std::to_string(i + 2));
  return (t.back() - t.front()) / static_cast<double>(t.size() - 1);
}

// Number or named variable: {value: X} or {variable: NAME}.
std::vector<double> GainOf(YamlMap spec, Source& source, const std::string& field, std::size_t n,
                           double* mean) {
  std::vector<double> gain;
  if (spec.Has("value") == spec.Has("variable"))
    spec.Fail("value", "exactly one of 'value' (a number) or 'variable' (a name)", "");
  if (spec.Has("value")) {
    gain.assign(1, spec.Number("value", Range::Any()));
  } else {
    gain = source.Vector(spec.String("variable"), field);
    if (gain.size() != 1) CheckLength(gain, n, source.file, field);
  }
  spec.Finish();
  CheckFinite(gain, source.file, field, gain.size() == n ? source.lines() : nullptr);
  double sum = 0.0;
  for (double g : gain) sum += g;
  *mean = sum / static_cast<double>(gain.size());
  return gain;
}

void FillEffort(JointRecording& joint, const std::vector<double>& gain) {
  joint.effort.resize(joint.command.size());
  for (std::size_t i = 0; i < joint.command.size(); ++i)
    joint.effort[i] = (gain.size() == 1 ? gain[0] : gain[i]) * joint.command[i];
}

AxisRecording ReadEmpsMat(const std::filesystem::path& file) {
  Source source;
  source.file = file;
  source.mat = std::make_unique<MatSource>(file);
  AxisRecording r;
  r.file = file;
  r.t = source.Vector("t", "time");
  CheckFinite(r.t, file, "time (variable 't')");
  r.dt = UniformStep(r.t, file, "time (variable 't')");
  JointRecording j;
  j.name = "axis";
  j.kind = JointKind::kPrismatic;
  j.position = source.Vector("qm", "position");
  CheckLength(j.position, r.size(), file, "position (variable 'qm')");
  CheckFinite(j.position, file, "position (variable 'qm')");
  if (source.Has("qg")) {
    j.reference = source.Vector("qg", "reference");
    CheckLength(j.reference, r.size(), file, "reference (variable 'qg')");
    CheckFinite(j.reference, file, "reference (variable 'qg')");
  }
  j.command = source.Vector("vir", "command");
  CheckLength(j.command, r.size(), file, "command (variable 'vir')");
  CheckFinite(j.command, file, "command (variable 'vir')");
  const std::vector<double> gain = source.Vector("gtau", "command_to_effort");
  if (gain.size() != 1) CheckLength(gain, r.size(), file, "command_to_effort (variable 'gtau')");
  CheckFinite(gain, file, "command_to_effort (variable 'gtau')");
  j.command_to_effort = gain[0];
  FillEffort(j, gain);
  r.joints.push_back(std::move(j));
  if (source.Has("kp") && source.Has("kv")) {
    LoopGains g;
    g.kp = source.Vector("kp", "kp").at(0);
    g.kv = source.Vector("kv", "kv").at(0);
    r.loop = g;
  }
  return r;
}

AxisRecording ReadYaml(const std::filesystem::path& file) {
  return ReadTaggedYamlFile(file, "pwsim-axis-trial/1", [&](YamlMap& root) {
    AxisRecording r;
    r.file = file;
    YamlMap data = root.Map("data");
    const std::string data_file = data.String("file");
    const std::string format = data.Choice("format", {"mat", "csv"});
    data.Finish();
    Source source;
    source.file = ResolveRelative(file, data_file);
    if (format == "mat")
      source.mat = std::make_unique<MatSource>(source.file);
    else
      source.csv = std::make_unique<CsvSource>(source.file);
    const std::string time_name = root.String("time");
    r.t = source.Vector(time_name, "time");
    CheckFinite(r.t, source.file, "time ('" + time_name + "')", source.lines());
    r.dt = UniformStep(r.t, source.file, "time ('" + time_name + "')", source.lines());
    r.experiment = root.ChoiceOr("experiment", "excitation", {"excitation", "step", "ramp", "chirp"});
    YAML::Node joints = root.Sequence("joints");
    if (joints.size() < 1 || joints.size() > 2)
      root.Fail("joints", "one or two joints", std::to_string(joints.size()));
    for (std::size_t i = 0; i < joints.size(); ++i) {
      YamlMap js(joints[i], file, "joints[" + std::to_string(i) + "]");
      JointRecording j;
      j.name = js.String("name");
      const std::string kind = js.Choice("kind", {"prismatic", "revolute"});
      j.kind = kind == "revolute" ? JointKind::kRevolute : JointKind::kPrismatic;
      auto column = [&](const std::string& key, std::vector<double>& out) {
        const std::string name = js.String(key);
        const std::string field = js.FieldName(key) + " ('" + name + "')";
        out = source.Vector(name, field);
        CheckLength(out, r.size(), source.file, field);
        CheckFinite(out, source.file, field, source.lines());
      };
      column("position", j.position);
      if (js.Has("reference")) column("reference", j.reference);
      column("command", j.command);
      const std::vector<double> gain =
          GainOf(js.Map("command_to_effort"), source, js.FieldName("command_to_effort"), r.size(),
                 &j.command_to_effort);
      FillEffort(j, gain);
      js.Finish();
      r.joints.push_back(std::move(j));
    }
    if (root.Has("controller")) {
      YamlMap c = root.Map("controller");
      LoopGains g;
      double unused = 0.0;
      g.kp = GainOf(c.Map("kp"), source, c.FieldName("kp"), 1, &unused).at(0);
      g.kv = GainOf(c.Map("kv"), source, c.FieldName("kv"), 1, &unused).at(0);
      g.command_limit = c.NumberOr("command_limit", 10.0, Range::Positive(1e9));
      g.delay_samples = c.IntegerOr("delay_samples", 1, 0, 100);
      c.Finish();
      r.loop = g;
    }
    return r;
  });
}

}  // namespace

const char* JointKindName(JointKind kind) {
  return kind == JointKind::kRevolute ? "revolute" : "prismatic";
}

AxisRecording AxisRecording::Slice(std::size_t begin, std::size_t end) const {
  AxisRecording out = *this;
  auto cut = [&](std::vector<double>& v) {
    if (v.empty()) return;
    v = std::vector<double>(v.begin() + static_cast<std::ptrdiff_t>(begin),
                            v.begin() + static_cast<std::ptrdiff_t>(end));
  };
  cut(out.t);
  for (JointRecording& j : out.joints) {
    cut(j.position);
    cut(j.reference);
    cut(j.command);
    cut(j.effort);
  }
  return out;
}

AxisRecording ReadAxisRecording(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".mat") return ReadEmpsMat(file);
  if (ext == ".yaml" || ext == ".yml") return ReadYaml(file);
  throw InputError(file.string(), 0, "(file)",
                   "a pwsim-axis-trial/1 description (.yaml) or an EMPS .mat file "
                   "(a .csv needs its .yaml description)",
                   "extension '" + ext + "'");
}

void WriteAxisRecordingCsv(const AxisRecording& r, const std::filesystem::path& yaml_file) {
  std::filesystem::path csv_file = yaml_file;
  csv_file.replace_extension(".csv");
  std::ostringstream csv;
  csv << "t";
  for (const JointRecording& j : r.joints) {
    csv << "," << j.name << "_q";
    if (!j.reference.empty()) csv << "," << j.name << "_qr";
    csv << "," << j.name << "_u";
  }
  csv << "\n";
  for (std::size_t i = 0; i < r.size(); ++i) {
    csv << FormatDouble(r.t[i]);
    for (const JointRecording& j : r.joints) {
      csv << "," << FormatDouble(j.position[i]);
      if (!j.reference.empty()) csv << "," << FormatDouble(j.reference[i]);
      csv << "," << FormatDouble(j.command[i]);
    }
    csv << "\n";
  }
  std::ostringstream y;
  y << "format: pwsim-axis-trial/1\n"
    << "data: {file: " << csv_file.filename().string() << ", format: csv}\n"
    << "time: t\n"
    << "experiment: " << r.experiment << "\n"
    << "joints:\n";
  for (const JointRecording& j : r.joints) {
    y << "  - name: " << j.name << "\n    kind: " << JointKindName(j.kind) << "\n"
      << "    position: " << j.name << "_q\n";
    if (!j.reference.empty()) y << "    reference: " << j.name << "_qr\n";
    y << "    command: " << j.name << "_u\n"
      << "    command_to_effort: {value: " << FormatDouble(j.command_to_effort) << "}\n";
  }
  if (r.loop) {
    y << "controller:\n  kp: {value: " << FormatDouble(r.loop->kp) << "}\n  kv: {value: "
      << FormatDouble(r.loop->kv) << "}\n  command_limit: " << FormatDouble(r.loop->command_limit)
      << "\n  delay_samples: " << r.loop->delay_samples << "\n";
  }
  WriteFileAtomically(csv_file, csv.str());
  WriteFileAtomically(yaml_file, y.str());
}

}  // namespace pwsim::sysid::platform
