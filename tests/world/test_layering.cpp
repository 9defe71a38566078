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
    EXPECT_GT(files, 0) << dir << " looks empty";
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

// The core (lattice, dynamics, collision, world, meshes in memory) includes nothing of the
// content component's (files, generators, scenes, data folders) nor any of its libraries, and
// the library knows no source or build path: its data is found at run time (ffdaabb/data.h).
TEST(Layering, TheCoreIncludesNoContent) {
    for (const char* dir :
         {"src/geometry", "src/lattice", "src/dynamics", "src/collision", "src/world", "src/util"})
        for (const char* content :
             {"ffdaabb/scene.h", "ffdaabb/generators.h", "ffdaabb/mesh_io.h", "ffdaabb/data.h",
              "#include \"mesh/", "#include \"scene/", "assimp/", "meshoptimizer", "ft2build",
              "GL/glu", "nlohmann", "zlib.h"})
            EXPECT_EQ(filesContaining(dir, content), "") << dir << ": " << content;
    for (const char* core :
         {"include/ffdaabb/world.h", "include/ffdaabb/lattice.h", "include/ffdaabb/mesh.h",
          "include/ffdaabb/math.h", "include/ffdaabb/profile.h", "include/ffdaabb/tasks.h",
          "include/ffdaabb/error.h"}) {
        const std::string text = readAll(fs::path(FFD_SOURCE_DIR) / core);
        for (const char* content : {"#include \"ffdaabb/scene.h", "#include \"ffdaabb/generators.h",
                                    "#include \"ffdaabb/mesh_io.h", "#include \"ffdaabb/data.h"})
            EXPECT_EQ(text.find(content), std::string::npos) << core << " includes " << content;
    }
}

TEST(Layering, NoSourceOrBuildPathIsCompiledIn) {
    for (const char* dir : {"src", "include/ffdaabb", "apps/ffdaabb"})
        for (const char* path : {"FFD_SOURCE_DIR", "FFD_BINARY_DIR", "CMAKE_SOURCE_DIR"})
            EXPECT_EQ(filesContaining(dir, path), "") << dir << ": " << path;
}
