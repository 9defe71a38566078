#include "commands.h"

namespace ffd::cli {

void addMeshInfoCommand(CLI::App& app, Action& action) {
    auto* cmd =
        app.add_subcommand("mesh-info", "Mesh and lattice statistics of a file or generator");
    cmd->callback([&action] { action = [] { return 0; }; });
}

} // namespace ffd::cli
