// The data folders (ffdaabb/data.h): where scenes and models are found at run time, with no
// source or build path compiled into the library.
#include "ffdaabb/data.h"
#include "ffdaabb/error.h"
#include "ffdaabb/scene.h"
#include "support/test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

using namespace ffd;
namespace fs = std::filesystem;

namespace {

long indexOf(const std::vector<fs::path>& folders, const fs::path& folder) {
    const auto it = std::find(folders.begin(), folders.end(), folder);
    return it == folders.end() ? -1 : long(it - folders.begin());
}

TEST(DataFolders, AddedThenEnvironmentThenBesideTheProgramThenTheInstall) {
    const test::ScopedEnv env("FFDAABB_DATA", "/first/data::/second/data");
    addDataFolder("/added/data");
    const std::vector<fs::path> folders = dataFolders();
    const fs::path build = fs::path(FFD_BINARY_DIR) / "share" / "ffdaabb"; // tests run from bin/
    ASSERT_GE(folders.size(), 5u);
    EXPECT_LT(indexOf(folders, "/added/data"), indexOf(folders, "/first/data"));
    EXPECT_EQ(indexOf(folders, "/first/data") + 1, indexOf(folders, "/second/data")); // "" skipped
    EXPECT_EQ(indexOf(folders, "/second/data") + 1, indexOf(folders, build));
    EXPECT_EQ(indexOf(folders, build) + 2, long(folders.size())); // the install's is last
    EXPECT_EQ(folders.back().filename(), "ffdaabb");
}

TEST(DataFolders, TheBuildTreeIsLaidOutAsAnInstall) {
    const test::ScopedEnv env("FFDAABB_DATA", nullptr);
    const fs::path found = findData("scenes/spheres.json");
    ASSERT_FALSE(found.empty());
    EXPECT_TRUE(fs::equivalent(found, fs::path(FFD_SOURCE_DIR) / "scenes" / "spheres.json"));
    EXPECT_TRUE(findData("scenes/no_such_scene.json").empty());
}

TEST(DataFolders, AFolderInTheEnvironmentComesBeforeTheBuildsScenes) {
    test::TempDir dir;
    fs::create_directories(dir / "scenes");
    // A scene of the same name as a shipped one, and one of a new name.
    fs::copy_file(fs::path(FFD_SOURCE_DIR) / "scenes" / "spheres.json",
                  dir / "scenes/spheres.json");
    std::ifstream in(fs::path(FFD_SOURCE_DIR) / "scenes" / "teapots.json");
    std::ofstream(dir / "scenes/mine.json") << in.rdbuf();
    const test::ScopedEnv env("FFDAABB_DATA", dir.path().c_str());
    EXPECT_TRUE(fs::equivalent(findData("scenes/spheres.json"), dir / "scenes/spheres.json"));
    EXPECT_TRUE(fs::equivalent(loadScene("mine").source, dir / "scenes/mine.json"));
    const std::vector<std::string> names = sceneNames();
    EXPECT_NE(std::find(names.begin(), names.end(), "mine"), names.end());
    EXPECT_NE(std::find(names.begin(), names.end(), "alphabets"), names.end());
}

} // namespace
