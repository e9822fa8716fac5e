#include "app/commands.h"

namespace pwsim::app {

const std::vector<Command>& AllCommands() {
  static const std::vector<Command> commands{
      {&RunSpec(), &RunCommand},
      {&SessionSpec(), &SessionCommand},
      {&ReplaySpec(), &ReplayCommand},
      {&PlatformSimSpec(), &PlatformSimCommand},
      {&HmdPeerSpec(), &HmdPeerCommand},
      {&OmctSpec(), &OmctCommand},
      {&McaValidateSpec(), &McaValidateCommand},
      {&GenerateSpec(), &GenerateCommand},
      {&IdentifySpec(), &IdentifyCommand},
      {&DiagnoseSpec(), &DiagnoseCommand},
      {&StudySpec(), &StudyCommand},
      {&SweepSpec(), &SweepCommand},
      {&PlatformSpec(), &PlatformCommand},
      {&DriveSpec(), &DriveCommand},
      {&SkillsSpec(), &SkillsCommand},
      {&CarChecksSpec(), &CarChecksCommand},
      {&ChairChecksSpec(), &ChairChecksCommand},
  };
  return commands;
}

}  // namespace pwsim::app
