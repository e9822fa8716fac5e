#pragma once
// The pwsim subcommands. Each lives in its own app/cmd_<name>.cc and is listed once in
// app/commands.cc; a command only parses arguments and wires libraries together.

#include <string>
#include <vector>

#include "app/cli.h"

namespace pwsim::app {

struct Command {
  const CommandSpec* spec;
  int (*run)(const ParsedArgs& args);
};

/// Every subcommand, in the order `pwsim --help` lists them.
const std::vector<Command>& AllCommands();

// Declarations, one pair per app/cmd_<name>.cc.
const CommandSpec& RunSpec();
int RunCommand(const ParsedArgs& args);
const CommandSpec& PlatformSimSpec();
int PlatformSimCommand(const ParsedArgs& args);
const CommandSpec& HmdPeerSpec();
int HmdPeerCommand(const ParsedArgs& args);
const CommandSpec& SessionSpec();
int SessionCommand(const ParsedArgs& args);
const CommandSpec& ReplaySpec();
int ReplayCommand(const ParsedArgs& args);
const CommandSpec& OmctSpec();
int OmctCommand(const ParsedArgs& args);
const CommandSpec& McaValidateSpec();
int McaValidateCommand(const ParsedArgs& args);
const CommandSpec& GenerateSpec();
int GenerateCommand(const ParsedArgs& args);
const CommandSpec& IdentifySpec();
int IdentifyCommand(const ParsedArgs& args);
const CommandSpec& DiagnoseSpec();
int DiagnoseCommand(const ParsedArgs& args);
const CommandSpec& StudySpec();
int StudyCommand(const ParsedArgs& args);
const CommandSpec& SweepSpec();
int SweepCommand(const ParsedArgs& args);
const CommandSpec& PlatformSpec();
int PlatformCommand(const ParsedArgs& args);
const CommandSpec& CarChecksSpec();
int CarChecksCommand(const ParsedArgs& args);
const CommandSpec& ChairChecksSpec();
int ChairChecksCommand(const ParsedArgs& args);
const CommandSpec& DriveSpec();
int DriveCommand(const ParsedArgs& args);
const CommandSpec& SkillsSpec();
int SkillsCommand(const ParsedArgs& args);

}  // namespace pwsim::app
