// annex-runtime: the companion runtime's command line (docs/cli.md).
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "commands.h"

namespace {

using annex::cli::Command;

const Command* const kCommands[] = {
    &annex::cli::kCheckCommand,
    &annex::cli::kMatchCommand,
    &annex::cli::kScanCommand,
    &annex::cli::kSynthCommand,
    &annex::cli::kRenderCommand,
    &annex::cli::kRunCommand,
};

void print_usage(std::ostream& out) {
  out << "usage: annex-runtime <command> [args] [--help]\n\ncommands:\n";
  for (const Command* c : kCommands)
    out << "  " << c->name << std::string(10 - std::min<size_t>(9, c->name.size()), ' ')
        << c->summary << "\n";
  out << "\nRun 'annex-runtime <command> --help' for a command's options, "
         "'annex-runtime --version' for the version.\n";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    print_usage(std::cerr);
    return annex::cli::kExitBadInput;
  }
  const std::string name = argv[1];
  if (name == "--help" || name == "-h" || name == "help") {
    print_usage(std::cout);
    return annex::cli::kExitOk;
  }
  if (name == "--version" || name == "version") {
    std::cout << "annex-runtime " << ANNEX_VERSION << "\n";
    return annex::cli::kExitOk;
  }
  const std::vector<std::string> args(argv + 2, argv + argc);
  for (const Command* c : kCommands) {
    if (c->name != name) continue;
    if (annex::cli::wants_help(args)) {
      std::cout << c->usage;
      return annex::cli::kExitOk;
    }
    try {
      return c->run(args);
    } catch (const std::exception& e) {
      // Only programmer errors throw; still end with one clear line, not an abort.
      std::cerr << "annex-runtime " << name << ": internal error: " << e.what() << "\n";
      return annex::cli::kExitFailure;
    }
  }
  std::vector<std::string> names;
  for (const Command* c : kCommands) names.emplace_back(c->name);
  names.emplace_back("--help");
  names.emplace_back("--version");
  std::cerr << "annex-runtime: error: unknown command '" << name << "'"
            << annex::cli::did_you_mean(name, names) << "\n";
  print_usage(std::cerr);
  return annex::cli::kExitBadInput;
}
