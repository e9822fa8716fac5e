// pwsim --version: the project version and the git state the binary was built from
// (app/version.cmake writes version_info.h into the build tree at every build).

#include "app/cli.h"
#include "version_info.h"

namespace pwsim::app {

std::string VersionText() {
  return std::string("pwsim ") + PWSIM_VERSION + " (git " + PWSIM_GIT_DESCRIBE + ", commit " + PWSIM_GIT_COMMIT + ")";
}

}  // namespace pwsim::app
