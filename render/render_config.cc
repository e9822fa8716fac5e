#include "render/render_config.h"

#include <string>

#include "engine/input_error.h"
#include "engine/yaml_reader.h"

namespace pwsim::render {
namespace {

void ReadSize(YamlMap& map, const std::string& key, int* width, int* height) {
  if (!map.Has(key)) return;
  const std::vector<double> size = map.Numbers(key, Range::Closed(16, 8192, "px"), 2, 2);
  if (size[0] != static_cast<int>(size[0]) || size[1] != static_cast<int>(size[1]) ||
      static_cast<int>(size[0]) % 2 != 0 || static_cast<int>(size[1]) % 2 != 0) {
    map.Fail(key, "two even whole numbers [width, height] in px", "a fraction or odd size");
  }
  *width = static_cast<int>(size[0]);
  *height = static_cast<int>(size[1]);
}

}  // namespace

std::string RenderConfig::Validate(const Clock& clock) const {
  if (width < 16 || height < 16 || width % 2 != 0 || height % 2 != 0) {
    return "size: expected even width and height >= 16 px, got " + std::to_string(width) + "x" +
           std::to_string(height);
  }
  if (fps < 1 || clock.rate_hz % fps != 0) {
    return "fps: expected a divisor of the clock rate " + std::to_string(clock.rate_hz) +
           " Hz (frame k is tick k*N exactly, e.g. 25, 40, 50, 100), got " + std::to_string(fps);
  }
  if (!(fov_y_deg > 1.0 && fov_y_deg < 170.0)) return "fov_y_deg: expected (1, 170) deg";
  if (!(near > 0.0 && far > near)) return "near_m/far_m: expected 0 < near < far";
  if (hmd.eye_width < 16 || hmd.eye_height < 16 || hmd.eye_width % 2 != 0 ||
      hmd.eye_height % 2 != 0) {
    return "stereo.eye_size: expected even sizes >= 16 px";
  }
  return "";
}

RenderConfig ParseRenderConfig(const Scene& scene) {
  RenderConfig config;
  const SceneSection* section = scene.section("render");
  if (section == nullptr) return config;
  YamlMap map(section->node, section->file, "render", section->line);
  ReadSize(map, "size", &config.width, &config.height);
  config.fps = map.IntegerOr("fps", config.fps, 1, 1000);
  config.fov_y_deg = map.NumberOr("fov_y_deg", config.fov_y_deg, Range::Closed(1, 170, "deg"));
  config.near = map.NumberOr("near_m", config.near, Range::Positive(10.0, "m"));
  config.far = map.NumberOr("far_m", config.far, Range::Positive(1e5, "m"));
  config.warmup_frames = map.IntegerOr("warmup_frames", config.warmup_frames, 0, 100);
  config.stereo = map.BoolOr("stereo", config.stereo);
  config.remove_tilt = map.BoolOr("remove_tilt", config.remove_tilt);
  config.texture_seed = static_cast<std::uint32_t>(
      map.IntegerOr("texture_seed", static_cast<int>(config.texture_seed), 0, 2147483647));
  config.cushion_width =
      map.NumberOr("cushion_width_m", config.cushion_width, Range::Positive(20.0, "m"));
  config.crf = map.IntegerOr("crf", config.crf, 0, 51);
  config.anisotropy = map.IntegerOr("anisotropy", config.anisotropy, 1, 16);
  if (map.Has("hmd")) {
    YamlMap hmd = map.Map("hmd");
    ReadSize(hmd, "eye_size", &config.hmd.eye_width, &config.hmd.eye_height);
    config.hmd.ipd = hmd.NumberOr("ipd_m", config.hmd.ipd, Range::Closed(0.0, 0.1, "m"));
    const Range half_angle = Range::Closed(1, 85, "deg");
    config.hmd.fov.outer_deg = hmd.NumberOr("outer_deg", config.hmd.fov.outer_deg, half_angle);
    config.hmd.fov.inner_deg = hmd.NumberOr("inner_deg", config.hmd.fov.inner_deg, half_angle);
    config.hmd.fov.up_deg = hmd.NumberOr("up_deg", config.hmd.fov.up_deg, half_angle);
    config.hmd.fov.down_deg = hmd.NumberOr("down_deg", config.hmd.fov.down_deg, half_angle);
    hmd.Finish();
  }
  map.Finish();
  if (const std::string error = config.Validate(scene.clock); !error.empty()) {
    throw InputError(section->file.string(), section->line, "render", error, "an invalid value");
  }
  return config;
}

}  // namespace pwsim::render
