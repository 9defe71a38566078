// ffdaabb: the command-line tool. Subcommands live in their own files (cmd_*.cpp) and register
// themselves here.
#include "commands.h"

#include "ffdaabb/error.h"

#include <CLI/CLI.hpp>
#include <fmt/core.h>

int main(int argc, char** argv) {
    CLI::App app{"ffdaabb: real-time deformable objects with the Enhanced FFD-AABB collision "
                 "pipeline"};
    app.require_subcommand(1);
    app.set_version_flag("--version", std::string("ffdaabb ") + ffd::cli::kVersion);
    ffd::cli::registerCommands(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // CLI11 prints help/version with exit 0 and errors with a message; bad flags exit 2.
        const int code = app.exit(e);
        return code == 0 ? 0 : 2;
    }
    try {
        return ffd::cli::runSelected(app);
    } catch (const ffd::InputError& e) {
        fmt::print(stderr, "ffdaabb: error: {}\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        fmt::print(stderr, "ffdaabb: internal error: {}\n", e.what());
        return 1;
    }
}
