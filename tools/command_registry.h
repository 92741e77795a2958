// Registry of `frameless` subcommands: each tools/*.cpp registers itself; main builds the CLI.
#pragma once
#include <functional>
#include <string>

#include <CLI/CLI.hpp>

namespace frameless::cli {

// Adds options to `app` (the subcommand) and returns the function to run when it is chosen.
// The runner returns the process exit code.
using CommandSetup = std::function<std::function<int()>(CLI::App& app)>;

// parent: "" for a top-level command, or the name of a top-level command (e.g. "bench").
// Returns true so it can initialise a static: `static bool reg = register_command(...);`
bool register_command(const std::string& parent, const std::string& name,
                      const std::string& description, CommandSetup setup);

}  // namespace frameless::cli
