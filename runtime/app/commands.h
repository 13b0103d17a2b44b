#pragma once
// Every annex-runtime subcommand; main.cpp lists them in one table.

#include "cli.h"

namespace annex::cli {

extern const Command kCheckCommand;
extern const Command kMatchCommand;
extern const Command kScanCommand;
extern const Command kSynthCommand;
extern const Command kRenderCommand;
extern const Command kRunCommand;

}  // namespace annex::cli
