// Entry point of the `frameless` command line: builds the subcommand tree from the registry.
#include <cstdio>
#include <map>
#include <vector>

#include "core/scene/scene_finalize.h"
#include "frameless/thread_executor.h"
#include "tools/command_registry.h"

namespace frameless::cli {
namespace {

struct Entry {
  std::string parent, name, description;
  CommandSetup setup;
};

std::vector<Entry>& registry() {
  static std::vector<Entry> entries;
  return entries;
}

}  // namespace

bool register_command(const std::string& parent, const std::string& name,
                      const std::string& description, CommandSetup setup) {
  registry().push_back({parent, name, description, std::move(setup)});
  return true;
}

}  // namespace frameless::cli

int main(int argc, char** argv) {
  using namespace frameless::cli;
  // Scenes load (and their BVHs build) on every core: the same tree as one thread builds.
  frameless::set_default_build_executor(frameless::thread_executor(0));
  CLI::App app{"frameless: an interactive ray tracer with a frameless (asynchronous) display"};
  app.set_version_flag("--version", FRAMELESS_VERSION);
  app.require_subcommand(1);
  std::map<std::string, CLI::App*> parents;
  std::map<CLI::App*, std::function<int()>> runners;
  // Top-level commands first, so bench sub-benchmarks find their parent.
  for (int pass = 0; pass < 2; ++pass) {
    for (Entry& e : registry()) {
      if ((pass == 0) != e.parent.empty()) continue;
      CLI::App* parent = &app;
      if (!e.parent.empty()) {
        auto it = parents.find(e.parent);
        if (it == parents.end()) {
          it = parents.emplace(e.parent, app.add_subcommand(e.parent, e.parent + " commands")).first;
          it->second->require_subcommand(1);
        }
        parent = it->second;
      }
      CLI::App* sub = parent->add_subcommand(e.name, e.description);
      if (e.parent.empty()) parents[e.name] = sub;
      if (e.setup) runners[sub] = e.setup(*sub);
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    // Bad flags: one line, like every other error.
    std::fprintf(stderr, "frameless: %s (see --help)\n", e.what());
    return 2;
  }
  for (auto& [sub, run] : runners)
    if (sub->parsed() && run && sub->get_subcommands().empty()) return run();
  std::fprintf(stderr, "frameless: no command chosen (see --help)\n");
  return 2;
}
