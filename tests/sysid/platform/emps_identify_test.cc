// IDIM-LS on the real EMPS recording against the published reference results (Janot, Gautier,
// Brunot 2019; shared/data/emps/README.md). Skips when the shared data are absent.
#include <gtest/gtest.h>

#include <cmath>

#include "sysid/platform/axis_recording.h"
#include "sysid/platform/idim.h"
#include "tests/sysid/platform/emps_data.h"

namespace pwsim::sysid::platform {
namespace {

// Rounds to the published number of decimals and compares exactly.
void ExpectPrinted(double value, double published, int decimals) {
  const double scale = std::pow(10.0, decimals);
  EXPECT_EQ(std::round(value * scale), std::round(published * scale))
      << value << " vs published " << published;
}

TEST(EmpsIdentify, ReproducesPublishedIdimLs) {
  PWSIM_REQUIRE_EMPS();
  const AxisRecording r = ReadAxisRecording(test::EmpsDir() / "DATA_EMPS.mat");
  ASSERT_EQ(r.size(), 24841u);
  ASSERT_EQ(r.joints.size(), 1u);
  ASSERT_TRUE(r.loop.has_value());
  const PlatformFit fit = IdentifyPlatform({r}, {}, "");
  EXPECT_EQ(fit.model.name, "axis-base");
  EXPECT_EQ(fit.ls.rows, 2480);
  ExpectPrinted(fit.ls.theta(0), 95.1089, 4);
  ExpectPrinted(fit.ls.theta(1), 203.5034, 4);
  ExpectPrinted(fit.ls.theta(2), 20.3935, 4);
  ExpectPrinted(fit.ls.theta(3), -3.1648, 4);
  ExpectPrinted(fit.ls.sigma(0), 0.1085, 4);
  ExpectPrinted(fit.ls.sigma(1), 1.1460, 4);
  ExpectPrinted(fit.ls.sigma(2), 0.1012, 4);
  ExpectPrinted(fit.ls.sigma(3), 0.0444, 4);
  ExpectPrinted(fit.ls.relative_error_pct, 4.0834, 4);
  ExpectPrinted(fit.ls.condition_number, 25.9883, 4);
  ExpectPrinted(fit.ls.error_norm, 108.7569, 4);
}

TEST(EmpsIdentify, ReproducesPublishedAsymmetricFriction) {
  PWSIM_REQUIRE_EMPS();
  const AxisRecording r = ReadAxisRecording(test::EmpsDir() / "DATA_EMPS.mat");
  const PlatformFit fit = IdentifyPlatform({r}, {}, "axis-asymmetric");
  ExpectPrinted(fit.ls.theta(0), 95.1540, 4);
  ExpectPrinted(fit.ls.theta(1), 166.7061, 4);
  ExpectPrinted(fit.ls.theta(2), 20.1440, 4);
  ExpectPrinted(fit.ls.theta(3), 240.4236, 4);
  ExpectPrinted(fit.ls.theta(4), 20.6277, 4);
  ExpectPrinted(fit.ls.relative_error_pct, 3.1117, 4);
}

}  // namespace
}  // namespace pwsim::sysid::platform
