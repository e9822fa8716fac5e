// engine/yaml_reader.h: a key written twice in one mapping (which yaml-cpp keeps, the second
// unread) and a directory named where a YAML file belongs are refused with file, line, field
// and expectation; a scene file with either is refused through the scene reader as well.

#include "engine/yaml_reader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "engine/input_error.h"

namespace pwsim {
namespace {

namespace fs = std::filesystem;

fs::path Scratch(const std::string& name) {
  const fs::path dir = fs::path(PWSIM_BINARY_DIR) / "test_out" / "yaml_reader" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// The InputError `load` throws (fails the test when it throws none).
template <typename Load>
InputError ErrorOf(Load load) {
  try {
    load();
  } catch (const InputError& error) {
    return error;
  }
  ADD_FAILURE() << "no InputError";
  return InputError("", 0, "", "", "");
}

// Tests that a top-level key written twice names the second line, the key and the first line.
TEST(YamlReader, RefusesAKeyWrittenTwice) {
  const InputError error = ErrorOf([] { LoadYamlString("a: 1\nb: 2\na: 3\n", "x.yaml"); });
  EXPECT_EQ(error.file(), "x.yaml");
  EXPECT_EQ(error.line(), 3);
  EXPECT_EQ(error.field(), "a");
  EXPECT_EQ(error.expected(), "each key once in a mapping");
  EXPECT_EQ(error.got(), "\"a\" again (first on line 1)");
}

// Tests the same inside nested mappings and mappings inside lists, with the dotted path.
TEST(YamlReader, RefusesADuplicateAtAnyDepthNamingItsPath) {
  const InputError nested =
      ErrorOf([] { LoadYamlString("drive:\n  speed_mps: 1\n  accel_mps2: 1\n  speed_mps: 2\n", "s.yaml"); });
  EXPECT_EQ(nested.line(), 4);
  EXPECT_EQ(nested.field(), "drive.speed_mps");
  const InputError listed =
      ErrorOf([] { LoadYamlString("wheels:\n  - {name: a, x_m: 1}\n  - {name: b, x_m: 2, name: c}\n", "w.yaml"); });
  EXPECT_EQ(listed.line(), 3);
  EXPECT_EQ(listed.field(), "wheels[1].name");
  EXPECT_EQ(listed.got(), "\"name\" again (first on line 3)");
  // the same key in two different mappings is fine
  EXPECT_NO_THROW(LoadYamlString("a: {x: 1}\nb: {x: 2}\n", "ok.yaml"));
}

// Tests that a directory named as a YAML file says so (not "an empty document").
TEST(YamlReader, RefusesADirectoryAsSuch) {
  const fs::path dir = Scratch("directory");
  const InputError error = ErrorOf([&] { LoadYamlFile(dir); });
  EXPECT_EQ(error.file(), dir.string());
  EXPECT_EQ(error.field(), "(file)");
  EXPECT_EQ(error.got(), "a path that is a directory");
  const InputError missing = ErrorOf([&] { LoadYamlFile(dir / "none.yaml"); });
  EXPECT_EQ(missing.got(), "no such file");
}

// Tests the scene reader end to end: the speed written twice in a scene file is refused at
// the second line rather than run at the first speed.
TEST(YamlReader, SceneWithTheSpeedTwiceIsRefused) {
  const fs::path dir = Scratch("scene");
  std::ifstream in(fs::path(PWSIM_SOURCE_DIR) / "scenes" / "speed_cushion.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t at = text.find("  speed_mps:");
  ASSERT_NE(at, std::string::npos);
  text.insert(at, "  speed_mps: 0.3\n");
  const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(at), '\n'));
  std::ofstream(dir / "twice.yaml") << text;
  const InputError error = ErrorOf([&] { LoadYamlFile(dir / "twice.yaml"); });
  EXPECT_EQ(error.line(), line + 1) << error.what();
  EXPECT_EQ(error.field(), "drive.speed_mps") << error.what();
  EXPECT_NE(std::string(error.what()).find("twice.yaml:" + std::to_string(line + 1) +
                                           ": field 'drive.speed_mps': expected each key once in a mapping"),
            std::string::npos)
      << error.what();
}

}  // namespace
}  // namespace pwsim
