// The library's layering: the collision stages see the world only through the view it hands
// them (collision/body.h), the public headers keep the world's data private, and the renderer,
// the viewer and the command line go through the public interface.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

namespace {

std::string readAll(const fs::path& path) {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

// The files under `dir` (relative to the source tree) with `needle` in them.
std::string filesContaining(const char* dir, const std::string& needle) {
    std::string found;
    int files = 0;
    for (const auto& entry : fs::recursive_directory_iterator(fs::path(FFD_SOURCE_DIR) / dir)) {
        if (!entry.is_regular_file()) continue;
        ++files;
        if (readAll(entry.path()).find(needle) != std::string::npos)
            found += entry.path().filename().string() + " ";
    }
    EXPECT_GT(files, 3) << dir << " looks empty";
    return found;
}

} // namespace

TEST(Layering, CollisionIncludesNoWorldHeader) {
    EXPECT_EQ(filesContaining("src/collision", "#include \"world/"), "");
    EXPECT_EQ(filesContaining("src/collision", "WorldData"), "");
}

TEST(Layering, TheRendererViewerAndToolUseThePublicInterface) {
    for (const char* dir : {"src/render", "apps/ffdaabb"})
        for (const char* internal : {"#include \"world/", "#include \"collision/", "WorldData"})
            EXPECT_EQ(filesContaining(dir, internal), "") << dir << ": " << internal;
}

TEST(Layering, PublicHeadersKeepTheWorldsDataPrivate) {
    EXPECT_EQ(filesContaining("include/ffdaabb", "WorldData"), "");
    EXPECT_EQ(filesContaining("include/ffdaabb", "#include \"world/"), "");
    EXPECT_EQ(filesContaining("include/ffdaabb", "#include \"collision/"), "");
}
