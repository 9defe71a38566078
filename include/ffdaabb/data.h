// Where the content component finds its data at run time: scenes (`scenes/NAME.json`) and model
// files (`models/`, filled by the setup script). Nothing is compiled in from the source or build
// tree; a build tree holds a `share/ffdaabb` folder laid out as an install's.
#pragma once

#include <filesystem>
#include <vector>

namespace ffd {

/// The data folders, searched in this order:
///   1. those added with addDataFolder(), in the order added;
///   2. the folders listed in the environment variable FFDAABB_DATA (separated by ':');
///   3. `share/ffdaabb` beside the running program's folder (`<prefix>/bin/app` finds
///      `<prefix>/share/ffdaabb`: an install, or a build tree, whose `bin/` programs find the
///      build's `share/ffdaabb`);
///   4. the data folder of the install prefix the library was configured with.
/// Folders that do not exist are listed too (they are where a file would be looked for).
std::vector<std::filesystem::path> dataFolders();

/// Searches `folder` first from now on (after folders added earlier). Thread-safe.
void addDataFolder(const std::filesystem::path& folder);

/// `relative` (e.g. "scenes/spheres.json") in the first data folder that holds it; empty when
/// none does.
std::filesystem::path findData(const std::filesystem::path& relative);

} // namespace ffd
