#include "plot/plot.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace pwsim::plot {
namespace {

namespace fs = std::filesystem;

Series MakeSeries(std::string label, std::vector<double> x, std::vector<double> y,
                  Style style = Style::kLines) {
  Series s;
  s.label = std::move(label);
  s.x = std::move(x);
  s.y = std::move(y);
  s.style = style;
  return s;
}

Panel MakePanel(std::string title, std::string y_label, std::vector<Series> series) {
  Panel p;
  p.title = std::move(title);
  p.y_label = std::move(y_label);
  p.series = std::move(series);
  return p;
}

fs::path TempDir(const std::string& name) {
  fs::path dir = fs::path(PWSIM_BINARY_DIR) / "test_out" / "plot" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::vector<std::string> Lines(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string Slurp(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

class PlotTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // scripts/install-deps.sh installs gnuplot-nox, so its absence is a failure, not a skip.
    ASSERT_TRUE(GnuplotAvailable()) << "gnuplot not on PATH (Debian package gnuplot-nox)";
  }
};

TEST_F(PlotTest, WritesPngSvgCsvAndScriptWithThePlottedData) {
  const fs::path dir = TempDir("two_panels");
  std::vector<double> t, a, b;
  for (int i = 0; i <= 50; ++i) {
    t.push_back(0.1 * i);
    a.push_back(std::sin(0.1 * i));
    b.push_back(i == 25 ? NAN : 0.5 * std::cos(0.1 * i));
  }
  Figure fig;
  fig.title = "test figure";
  fig.x_label = "t [s]";
  fig.panels.push_back(MakePanel("heave", "a_z [m/s^2]",
                                 {MakeSeries("vehicle, raw", t, a),
                                  MakeSeries("platform", t, b, Style::kPoints)}));
  fig.panels.push_back(MakePanel("pitch", "theta [deg]", {MakeSeries("it's quoted", t, a)}));
  WriteFigure(dir / "fig.png", fig);

  const FigureFiles files = FigureFilesFor(dir / "fig");
  ASSERT_TRUE(fs::exists(files.png));
  ASSERT_TRUE(fs::exists(files.svg));
  ASSERT_TRUE(fs::exists(files.gp));
  const std::string png = Slurp(files.png);
  ASSERT_GT(png.size(), 1000u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  EXPECT_NE(Slurp(files.svg).find("<svg"), std::string::npos);
  EXPECT_NE(Slurp(files.svg).find("theta [deg]"), std::string::npos);

  const auto csv = Lines(files.csv);
  ASSERT_EQ(csv.size(), 1u + 3u * 51u);
  EXPECT_EQ(csv[0], "panel,series,x,y");
  EXPECT_EQ(csv[1], "heave,\"vehicle, raw\",0,0");
  // Row for i = 10 of the first series: x = 1, y = sin(1), shortest round-trip text.
  const std::string row = csv[11];
  const auto last_comma = row.rfind(',');
  EXPECT_DOUBLE_EQ(std::stod(row.substr(last_comma + 1)), std::sin(0.1 * 10));
  EXPECT_EQ(csv[1 + 51 + 25], "heave,platform,2.5,nan");
  // No temporary file is left behind.
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().string().find(".partial"), std::string::npos) << entry.path();
}

// Tests a map panel: equal_axes makes gnuplot keep one metre as long on x as on y, for that
// panel only (the next panel is free again), and the PNG is drawn.
TEST_F(PlotTest, EqualAxesPanelKeepsTheAspectRatio) {
  const fs::path dir = TempDir("map");
  Figure fig;
  fig.x_label = "x [m]";
  Panel map = MakePanel("top view", "y [m]", {});
  map.series.push_back({"path", {0.0, 4.0, 8.0}, {0.0, 1.0, 0.0}});
  map.equal_axes = true;
  fig.panels.push_back(map);
  Panel free = MakePanel("other", "v [m/s]", {});
  free.series.push_back({"v", {0.0, 1.0}, {0.0, 1.0}});
  fig.panels.push_back(free);
  WriteFigure(dir / "map", fig);
  const std::string gp = Slurp(dir / "map.gp");
  const auto ratio = gp.find("set size ratio -1");
  ASSERT_NE(ratio, std::string::npos);
  const auto reset = gp.find("set size noratio", ratio);
  ASSERT_NE(reset, std::string::npos);
  EXPECT_LT(reset, gp.find("other", ratio));  // before the next panel's title
  EXPECT_TRUE(fs::exists(dir / "map.png"));
}

TEST_F(PlotTest, BoxPlotCsvHoldsEveryValuePerGroup) {
  const fs::path dir = TempDir("box");
  Figure fig;
  fig.x_label = "condition";
  Panel panel = MakePanel("ratings", "rating [1-6]", {});
  panel.boxes = {{"T_r", {1, 2, 2, 3, 6}}, {"T_m", {2, 3, 3, 4}}};
  fig.panels.push_back(panel);
  WriteFigure(dir / "box", fig);
  const auto csv = Lines(dir / "box.plot.csv");
  ASSERT_EQ(csv.size(), 10u);
  EXPECT_EQ(csv[1], "ratings,T_r,,1");
  EXPECT_EQ(csv[9], "ratings,T_m,,4");
  EXPECT_TRUE(fs::exists(dir / "box.png"));
  // Tukey whiskers by default: gnuplot's 1.5 IQR range with outliers.
  EXPECT_NE(Slurp(dir / "box.gp").find("boxplot range 1.5 outliers"), std::string::npos);
}

TEST_F(PlotTest, BoxPlotWithExtremeWhiskersShowsEveryValue) {
  const fs::path dir = TempDir("box_extremes");
  Figure fig;
  Panel panel = MakePanel("ratings", "rating [1-6]", {});
  panel.boxes = {{"T_r", {1, 2, 2, 2, 2, 6}}, {"T_m", {2, 3, 3, 4}}};
  panel.box_whiskers_to_extremes = true;
  panel.box_show_points = true;
  fig.panels.push_back(panel);
  WriteFigure(dir / "box", fig);
  const std::string gp = Slurp(dir / "box.gp");
  EXPECT_NE(gp.find("boxplot fraction 1.0 nooutliers"), std::string::npos) << gp;
  EXPECT_NE(gp.find("using (1):2 with points"), std::string::npos) << gp;
  EXPECT_NE(gp.find("using (2):2 with points"), std::string::npos) << gp;
  EXPECT_NE(gp.find("set jitter"), std::string::npos) << gp;
  EXPECT_TRUE(fs::exists(dir / "box.png"));
}

TEST_F(PlotTest, ReplacesAnOldFigureAndLeavesNothingWhenGnuplotFails) {
  const fs::path dir = TempDir("fail");
  Figure ok;
  ok.x_label = "x [m]";
  ok.panels.push_back(MakePanel("p", "y [m]", {MakeSeries("s", {1, 2, 3}, {1, 4, 9})}));
  WriteFigure(dir / "f", ok);
  ASSERT_TRUE(fs::exists(dir / "f.png"));
  // A gnuplot that fails (a stand-in on PATH: a real gnuplot failure cannot be provoked
  // reliably from valid input) must leave neither the old nor a partial figure behind.
  const fs::path fake = dir / "fakebin";
  fs::create_directories(fake);
  {
    std::ofstream script(fake / "gnuplot");
    script << "#!/bin/sh\necho 'simulated gnuplot failure' >&2\nexit 3\n";
  }
  fs::permissions(fake / "gnuplot", fs::perms::owner_all);
  const std::string old_path = std::getenv("PATH");
  setenv("PATH", (fake.string() + ":" + old_path).c_str(), 1);
  try {
    WriteFigure(dir / "f", ok);
    ADD_FAILURE() << "expected a failure";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("status 3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("simulated gnuplot failure"), std::string::npos);
  }
  setenv("PATH", old_path.c_str(), 1);
  EXPECT_FALSE(fs::exists(dir / "f.png"));
  EXPECT_FALSE(fs::exists(dir / "f.plot.csv"));
}

TEST(PlotValidation, MismatchedLengthsAreRejected) {
  Figure fig;
  fig.panels.push_back(MakePanel("p", "", {MakeSeries("s", {1, 2}, {1})}));
  EXPECT_THROW(WriteFigure("unused", fig), std::invalid_argument);
  EXPECT_THROW(WriteFigure("unused", Figure{}), std::invalid_argument);
}

}  // namespace
}  // namespace pwsim::plot
