#include "engine/vehicle/vehicle_params.h"

#include <gtest/gtest.h>

#include <fstream>
#include <regex>

#include "engine/input_error.h"

namespace pwsim::vehicle {
namespace {

const char* kFile = PWSIM_SOURCE_DIR "/assets/cars/midsize.yaml";

std::string ReadText(const char* path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

Vehicle ParseText(const std::string& text) {
  const YamlDocument doc = LoadYamlString(text, "car.yaml");
  YamlMap root(doc.root, doc.file, "");
  root.RequireFormat("pwsim-vehicle/1");
  Vehicle car = ParseVehicle(root);
  root.Finish();
  return car;
}

TEST(VehicleFile, ShippedCarIsValidAndMatchesTheBuiltIn) {
  const Vehicle file = ReadVehicleFile(kFile);
  const Vehicle built = MakeMidsizeCar();
  EXPECT_EQ(Validate(file), "");
  EXPECT_EQ(file.name, "midsize");
  EXPECT_EQ(file.gearbox.ratios, built.gearbox.ratios);
  EXPECT_EQ(file.gearbox.final_drive, built.gearbox.final_drive);
  ASSERT_EQ(file.engine.map.size(), built.engine.map.size());
  for (std::size_t i = 0; i < file.engine.map.size(); ++i) {
    EXPECT_EQ(file.engine.map[i].full_load, built.engine.map[i].full_load);
    EXPECT_EQ(file.engine.map[i].closed_throttle, built.engine.map[i].closed_throttle);
  }
  EXPECT_DOUBLE_EQ(file.steering.max_wheel_angle, 34.0 * kPi / 180.0);
}

TEST(VehicleFile, OtherRatioConventionIsConvertedOnLoad) {
  std::string text = ReadText(kFile);
  text = std::regex_replace(text, std::regex("ratio_convention: input_over_output"),
                            "ratio_convention: output_over_input");
  text = std::regex_replace(text, std::regex("ratios: \\[3.6, 2.1, 1.4, 1.05, 0.82\\]"),
                            "ratios: [0.25, 0.5, 1.0, 1.25, 2.0]");
  text = std::regex_replace(text, std::regex("reverse: -3.5"), "reverse: -0.25");
  text = std::regex_replace(text, std::regex("final_drive: 3.9"), "final_drive: 0.25");
  const Vehicle car = ParseText(text);
  EXPECT_EQ(car.gearbox.ratios, (std::vector<double>{4.0, 2.0, 1.0, 0.8, 0.5}));
  EXPECT_EQ(car.gearbox.reverse, -4.0);
  EXPECT_EQ(car.gearbox.final_drive, 4.0);
  EXPECT_EQ(car.GearRatio(-1), -4.0);
  EXPECT_EQ(car.GearRatio(0), 0.0);
}

void ExpectError(const std::string& text, const std::string& field_part, const std::string& expected_part) {
  try {
    ParseText(text);
    ADD_FAILURE() << "no error for " << field_part;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(field_part), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(expected_part), std::string::npos) << e.what();
    EXPECT_GT(e.line(), 0) << e.what();
  }
}

TEST(VehicleFile, BadInputNamesTheField) {
  const std::string text = ReadText(kFile);
  ExpectError(std::regex_replace(text, std::regex("ratios: \\[3.6, 2.1"), "ratios: [2.1, 3.6"),
              "gearbox.ratios", "falling");
  ExpectError(std::regex_replace(text, std::regex("mass_kg: 1450"), "mass_kg: heavy"), "chassis.mass_kg",
              "number");
  ExpectError(std::regex_replace(text, std::regex("closed_throttle_nm: -14"), "closed_throttle_nm: 14"),
              "engine.torque_map[2].closed_throttle_nm", "[-10000, 0]");
  ExpectError(std::regex_replace(text, std::regex("rpm: 1500,"), "rpm: 900,"), "engine.torque_map[3].rpm",
              "rising");
  ExpectError(std::regex_replace(text, std::regex("driven_axle: front"), "driven_axle: both"),
              "gearbox.driven_axle", "front");
  ExpectError(std::regex_replace(text, std::regex("  mu_x: 1.0\n"), "  mu_x: 1.0\n  mu_z: 1.0\n"), "tyre.mu_z", "");
  ExpectError(std::regex_replace(text, std::regex("idle_rpm: 800"), "idle_rpm: 300"), "engine", "stall_rpm < idle_rpm");
}

}  // namespace
}  // namespace pwsim::vehicle
