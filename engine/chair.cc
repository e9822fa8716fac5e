#include "engine/chair.h"

#include <cmath>

#include "engine/check.h"
#include "engine/input_error.h"
#include "engine/number_format.h"

namespace pwsim {

double MovingMass(const Chair& chair, double load_kg) { return chair.mass + load_kg; }

double PitchInertia(const Chair& chair, double load_kg) {
  return chair.inertia + chair.cm_height * chair.cm_height * MovingMass(chair, load_kg);
}

Chair MakeTableOneChair() {
  Chair chair;
  chair.wheels = {{"front_caster", 0.38, 0.10}, {"drive", 0.0, 0.17}, {"rear_caster", -0.38, 0.10}};
  chair.gm = GeometricParams{{0.17, 0.66, 0.17}, {{0, 1, 0.5}, {0, 2, 0.0}, {1, 2, 0.6}}};
  chair.lm = LumpedParams{};
  return chair;
}

namespace {

Mode AxisMode(double stiffness, double damping, double inertia) {
  const double omega_n = std::sqrt(stiffness / inertia);
  return {omega_n, damping / (2.0 * std::sqrt(stiffness * inertia))};
}

}  // namespace

Mode HeaveMode(const Chair& chair, double load_kg) {
  PWSIM_DEMAND(chair.lm.has_value());
  return AxisMode(chair.lm->k_z, chair.lm->c_z, MovingMass(chair, load_kg));
}

Mode PitchMode(const Chair& chair, double load_kg) {
  PWSIM_DEMAND(chair.lm.has_value());
  return AxisMode(chair.lm->k_theta, chair.lm->c_theta, PitchInertia(chair, load_kg));
}

Chair ParseChair(YamlMap& map) {
  Chair chair;
  chair.name = map.String("name");
  chair.mass = map.Number("mass_kg", Range::Positive(1000.0, "kg"));
  chair.inertia = map.Number("inertia_kgm2", Range::Positive(1000.0, "kg m^2"));
  chair.cm_height = map.Number("cm_height_m", Range::Closed(0.0, 2.0, "m"));

  YAML::Node wheels = map.Sequence("wheels");
  const std::string wheels_field = map.FieldName("wheels");
  if (wheels.size() < 2 || wheels.size() > kMaxWheels) {
    throw InputError(map.file().string(), map.LineOfKey("wheels"), wheels_field,
                     "2.." + std::to_string(kMaxWheels) + " wheels, front to rear",
                     std::to_string(wheels.size()) + " wheels");
  }
  for (std::size_t i = 0; i < wheels.size(); ++i) {
    YamlMap entry(wheels[i], map.file(), wheels_field + "[" + std::to_string(i) + "]",
                  map.LineOfKey("wheels"));
    Wheel wheel;
    wheel.name = entry.String("name");
    wheel.x = entry.Number("x_m", Range::Closed(-3.0, 3.0, "m"));
    wheel.radius = entry.Number("radius_m", Range::Positive(1.0, "m"));
    entry.Finish();
    if (!chair.wheels.empty() && !(wheel.x < chair.wheels.back().x)) {
      entry.Fail("x_m", "wheels listed front to rear (x_m strictly decreasing)",
                 FormatDouble(wheel.x) + " after " + FormatDouble(chair.wheels.back().x));
    }
    chair.wheels.push_back(wheel);
  }
  const std::size_t n = chair.wheels.size();

  if (map.Has("gm")) {
    YamlMap gm = map.Map("gm");
    GeometricParams params;
    params.alpha = gm.Numbers("alpha", Range::Closed(-10.0, 10.0), n, n);
    YamlMap beta = gm.Map("beta");
    for (int i = 0; i < static_cast<int>(n); ++i) {
      for (int j = i + 1; j < static_cast<int>(n); ++j) {
        const std::string key = std::to_string(i + 1) + "-" + std::to_string(j + 1);
        if (beta.Has(key)) {
          params.beta.push_back({i, j, beta.Number(key, Range::Closed(-10.0, 10.0))});
        }
      }
    }
    beta.Finish();  // rejects keys such as "3-1" or "1-4" on a 3-wheel chair
    gm.Finish();
    chair.gm = params;
  }
  if (map.Has("lm")) {
    YamlMap lm = map.Map("lm");
    LumpedParams params;
    params.k_z = lm.Number("k_z", Range::Positive(1e8, "N/m"));
    params.c_z = lm.Number("c_z", Range::Positive(1e7, "N s/m"));
    params.k_theta = lm.Number("k_theta", Range::Positive(1e8, "N m/rad"));
    params.c_theta = lm.Number("c_theta", Range::Positive(1e7, "N m s/rad"));
    lm.Finish();
    chair.lm = params;
  }
  return chair;
}

Chair ReadChairFile(const std::filesystem::path& file) {
  return ReadTaggedYamlFile(file, "pwsim-chair/1", ParseChair);
}

std::string ChairToYaml(const Chair& chair) {
  std::string text = "format: pwsim-chair/1\n";
  text += "name: " + chair.name + "\n";
  text += "mass_kg: " + FormatDouble(chair.mass) + "\n";
  text += "inertia_kgm2: " + FormatDouble(chair.inertia) + "\n";
  text += "cm_height_m: " + FormatDouble(chair.cm_height) + "\n";
  text += "wheels:\n";
  for (const Wheel& wheel : chair.wheels) {
    text += "  - {name: " + wheel.name + ", x_m: " + FormatDouble(wheel.x) +
            ", radius_m: " + FormatDouble(wheel.radius) + "}\n";
  }
  if (chair.gm) {
    text += "gm: {alpha: [";
    for (std::size_t i = 0; i < chair.gm->alpha.size(); ++i) {
      text += (i == 0 ? "" : ", ") + FormatDouble(chair.gm->alpha[i]);
    }
    text += "], beta: {";
    for (std::size_t k = 0; k < chair.gm->beta.size(); ++k) {
      const PairWeight& pair = chair.gm->beta[k];
      text += (k == 0 ? "\"" : ", \"") + std::to_string(pair.i + 1) + "-" +
              std::to_string(pair.j + 1) + "\": " + FormatDouble(pair.weight);
    }
    text += "}}\n";
  }
  if (chair.lm) {
    text += "lm: {k_z: " + FormatDouble(chair.lm->k_z) + ", c_z: " + FormatDouble(chair.lm->c_z) +
            ", k_theta: " + FormatDouble(chair.lm->k_theta) +
            ", c_theta: " + FormatDouble(chair.lm->c_theta) + "}\n";
  }
  return text;
}

}  // namespace pwsim
