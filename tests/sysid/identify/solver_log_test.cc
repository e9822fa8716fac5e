// QuietSolverLog (sysid/solver_log.h): Ceres' glog messages below FATAL stop reaching stderr.
#include "sysid/solver_log.h"

#include <gtest/gtest.h>

#include <glog/logging.h>

#include <cstdlib>
#include <string>

namespace pwsim {
namespace {

TEST(SolverLogTest, ErrorsOfTheSolverNoLongerReachStderr) {
  ::unsetenv("PWSIM_SOLVER_LOG");  // the debugging switch would keep the messages
  FLAGS_minloglevel = google::GLOG_INFO;
  testing::internal::CaptureStderr();
  LOG(ERROR) << "pwsim-solver-log-probe";
  const std::string before = testing::internal::GetCapturedStderr();
  EXPECT_NE(before.find("pwsim-solver-log-probe"), std::string::npos);

  QuietSolverLog();
  testing::internal::CaptureStderr();
  LOG(ERROR) << "pwsim-solver-log-probe";
  LOG(WARNING) << "pwsim-solver-log-probe";
  const std::string after = testing::internal::GetCapturedStderr();
  EXPECT_EQ(after.find("pwsim-solver-log-probe"), std::string::npos) << after;
}

}  // namespace
}  // namespace pwsim
