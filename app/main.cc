// pwsim: command-line entry point. Dispatches to the subcommands of app/commands.cc.
// Exit status: 0 success, 1 bad input or failure (message on stderr), 2 usage error
// (app::UsageError). Any other exception from a library is a failure (status 1). A command
// may document more codes of its own (pwsim replay: 3 when the replay differs from the log; pwsim sweep
// run: 65 and 75). `pwsim --version` prints the version and the git commit it was built from.

#include <exception>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/commands.h"
#include "engine/input_error.h"
#include "sysid/solver_log.h"

namespace {

void PrintTopHelp() {
  std::cout << "usage: pwsim <command> [options]\n\n"
               "pwsim: visual-motion pipeline for power-wheelchair driving simulators.\n\n"
               "commands:\n";
  for (const auto& command : pwsim::app::AllCommands()) {
    std::string name = "  " + command.spec->name;
    if (name.size() < 16) name.resize(16, ' ');
    std::cout << name << command.spec->summary << "\n";
  }
  std::cout << "\nRun 'pwsim <command> --help' for its options, units and defaults;\n"
               "'pwsim --version' for the version and the commit it was built from.\n";
}

}  // namespace

int main(int argc, char** argv) {
  pwsim::QuietSolverLog();
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
    PrintTopHelp();
    return args.empty() ? 2 : 0;
  }
  if (args[0] == "--version" || args[0] == "-V" || args[0] == "version") {
    std::cout << pwsim::app::VersionText() << "\n";
    return 0;
  }
  const std::string name = args[0];
  args.erase(args.begin());
  for (const auto& command : pwsim::app::AllCommands()) {
    if (command.spec->name != name) continue;
    if (pwsim::app::WantsHelp(args)) {
      std::cout << pwsim::app::HelpText(*command.spec);
      return 0;
    }
    try {
      return command.run(pwsim::app::Parse(*command.spec, args));
    } catch (const pwsim::app::UsageError& error) {
      std::cerr << "pwsim " << name << ": " << error.what() << "\n";
      return 2;
    } catch (const pwsim::InputError& error) {
      std::cerr << "pwsim " << name << ": error: " << error.what() << "\n";
      return 1;
    } catch (const std::exception& error) {
      std::cerr << "pwsim " << name << ": error: " << error.what() << "\n";
      return 1;
    }
  }
  std::vector<std::string> names;
  for (const auto& command : pwsim::app::AllCommands()) names.push_back(command.spec->name);
  std::cerr << "pwsim: unknown " << (name.rfind("-", 0) == 0 ? "option '" : "command '") << name << "'"
            << pwsim::app::DidYouMean(name, names) << " (see pwsim --help)\n";
  return 2;
}
