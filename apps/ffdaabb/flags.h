// Flag values the subcommands read as text and convert here, so that a bad value gets a message
// naming the flag, the value and what was expected (CLI11's own conversion only says "Could not
// convert"), and shared checks of the scene flags (run, soak, render, view) and output-file flags.
#pragma once

#include "ffdaabb/scene.h"

#include <CLI/CLI.hpp>

#include <string>

namespace ffd::cli {

/// The whole number in `text`, in [lo, hi]; InputError naming `flag` otherwise.
long long parseInteger(const std::string& flag, const std::string& text, long long lo,
                       long long hi);

/// The value in `text` of the integer setting named `setting` (ffd::findSettingRange: the
/// library's range and its words); InputError naming `flag` otherwise.
long long parseIntegerSetting(const std::string& flag, const std::string& text,
                              const char* setting);

/// The finite number in `text` (decimal or exponent notation), in [lo, hi]; InputError naming
/// `flag` otherwise. `expected` describes the range in the message, e.g. "metres, > 0".
double parseNumber(const std::string& flag, const std::string& text, double lo, double hi,
                   const std::string& expected);

/// Whether the user gave `option` on the command line (its value may still be empty).
inline bool given(const CLI::Option* option) {
    return option && option->count() > 0;
}

/// --scene, --objects, --mode, --threads and --seed, as run and soak take them (render and view
/// take all but --threads).
struct SceneFlags {
    std::string scene, objects, mode, threads, seed;
    CLI::Option *objectsOption = nullptr, *modeOption = nullptr, *threadsOption = nullptr,
                *seedOption = nullptr;
};

/// Adds the scene flags to `cmd` (--threads only when `threads`); `flags` must outlive the parse.
void addSceneFlags(CLI::App* cmd, SceneFlags& flags, bool threads = true);

/// Loads the scene and applies the flags that were given, each checked (InputError naming it).
Scene sceneFromFlags(const SceneFlags& flags);

/// Checks before any work that `path` (the value of `flag`; empty: not given) can be written at
/// the end: not a folder or a device, in a folder that exists. Throws InputError naming both.
void checkOutputPath(const std::string& flag, const std::string& path);

/// Throws InputError when two output flags name the same file (the second would overwrite the
/// first). Empty paths are ignored.
void checkDistinctOutputs(const std::string& flagA, const std::string& pathA,
                          const std::string& flagB, const std::string& pathB);

} // namespace ffd::cli
