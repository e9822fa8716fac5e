#include "sysid/solver_log.h"

#include <cstdlib>
#include <cstring>

#include <glog/logging.h>

namespace pwsim {

void QuietSolverLog() {
  const char* keep = std::getenv("PWSIM_SOLVER_LOG");
  if (keep != nullptr && std::strcmp(keep, "1") == 0) return;
  FLAGS_minloglevel = google::GLOG_FATAL;
}

}  // namespace pwsim
