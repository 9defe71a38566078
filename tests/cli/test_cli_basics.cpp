// The ffdaabb command line: help, version, flags, exit codes, mesh-info.
#include "test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

using namespace ffd::test;

TEST(Cli, HelpAndVersionExitZero) {
    RunResult r = runCli({"--help"});
    EXPECT_EQ(r.status, 0);
    EXPECT_NE(r.out.find("mesh-info"), std::string::npos) << r.out;
    r = runCli({"--version"});
    EXPECT_EQ(r.status, 0);
    EXPECT_NE(r.out.find("ffdaabb"), std::string::npos);
    r = runCli({"mesh-info", "--help"});
    EXPECT_EQ(r.status, 0);
    EXPECT_NE(r.out.find("--generate"), std::string::npos);
}

TEST(Cli, BadFlagsAndMissingCommandExitTwo) {
    RunResult r = runCli({"mesh-info", "--no-such-flag"});
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("--no-such-flag"), std::string::npos) << r.err;
    EXPECT_EQ(runCli({}).status, 2);
    EXPECT_EQ(runCli({"no-such-command"}).status, 2);
    r = runCli({"mesh-info", "--generate", "sphere", "--cells", "abc"});
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("abc"), std::string::npos) << r.err;
    r = runCli({"mesh-info", "--generate", "cube"});
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("cube"), std::string::npos) << r.err;
}

TEST(Cli, BadMeshFileExitsTwoNamingTheFile) {
    TempDir dir;
    writeFile(dir / "broken.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n");
    RunResult r = runCli({"mesh-info", (dir / "broken.ply").string()});
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find((dir / "broken.ply").string()), std::string::npos) << r.err;
    r = runCli({"mesh-info", (dir / "absent.obj").string()});
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("absent.obj"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("does not exist"), std::string::npos) << r.err;
    writeFile(dir / "nan.obj", "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n");
    r = runCli({"mesh-info", (dir / "nan.obj").string()});
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("nan.obj"), std::string::npos) << r.err;
}

TEST(Cli, MeshInfoReproducesTableTwo) {
    struct Case {
        const char* generator;
        int vertices, triangles, cells;
    };
    for (const Case c : {Case{"sphere", 162, 320, 38}, Case{"teapot", 3242, 6400, 84},
                         Case{"alphabet", 1141, 2279, 34}, Case{"dragon", 32328, 67240, 148}}) {
        const RunResult r = runCli({"mesh-info", "--generate", c.generator, "--json"});
        ASSERT_EQ(r.status, 0) << r.err;
        const auto j = nlohmann::json::parse(r.out);
        EXPECT_NEAR(j["vertices"].get<double>(), c.vertices, 0.05 * c.vertices) << c.generator;
        EXPECT_NEAR(j["triangles"].get<double>(), c.triangles, 0.02 * c.triangles) << c.generator;
        EXPECT_NEAR(j["cells"].get<double>(), c.cells, 0.2 * c.cells) << c.generator;
        EXPECT_EQ(j["paper"]["cells"].get<int>(), c.cells);
    }
}

TEST(Cli, MeshInfoOfAFileReportsCleanupAndHonoursTheCellOptions) {
    TempDir dir;
    // A cube with a duplicated vertex (welded) and 12 triangles.
    writeFile(dir / "cube.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\n"
                                "v 0 1 1\nv 0 0 0\n"
                                "f 9 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\n"
                                "f 3 4 8\nf 3 8 7\nf 2 3 7\nf 2 7 6\nf 1 5 8\nf 1 8 4\n");
    RunResult r =
        runCli({"mesh-info", (dir / "cube.obj").string(), "--json", "--cell-size", "0.5"});
    ASSERT_EQ(r.status, 0) << r.err;
    auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["vertices"].get<int>(), 8);
    EXPECT_EQ(j["triangles"].get<int>(), 12);
    EXPECT_EQ(j["cells"].get<int>(), 8); // 2 x 2 x 2
    EXPECT_TRUE(j["closed"].get<bool>());
    // Faces on the cells' faces: the boxes stand off by their skin, half a percent of a cell
    // (sqrt 3 of it along a corner's diagonal).
    EXPECT_EQ(j["box_standoff"]["directions"].get<int>(), 2000);
    EXPECT_GT(j["box_standoff"]["median"].get<double>(), 0.0);
    EXPECT_LE(j["box_standoff"]["max"].get<double>(), std::sqrt(3.0) * 0.005 * 0.5 * 1.001);
    EXPECT_DOUBLE_EQ(j["size"].get<double>(), 1.0);
    r = runCli({"mesh-info", (dir / "cube.obj").string(), "--json", "--cells", "27"});
    ASSERT_EQ(r.status, 0) << r.err;
    j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["cells"].get<int>(), 27);
    r = runCli({"mesh-info", (dir / "cube.obj").string()});
    EXPECT_EQ(r.status, 0);
    EXPECT_NE(r.out.find("FFD cells"), std::string::npos);
}

// The settings table: every numeric setting listed with its default, range and unit, and
// docs/LIMITS.md carries exactly the --markdown output.
TEST(Cli, SettingsListsTheTableAndTheDocsCarryIt) {
    RunResult r = runCli({"settings"});
    ASSERT_EQ(r.status, 0) << r.err;
    for (const char* key : {"frame_step", "overlap_recovery_speed", "contact_rigidity", "density"})
        EXPECT_NE(r.out.find(key), std::string::npos) << key;
    EXPECT_NE(r.out.find("0.0166667 s"), std::string::npos) << r.out; // frame_step's default
    r = runCli({"settings", "--markdown"});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("| `material.density` | `density` | 1000 |"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("metres, \\|h\\| <= 1e6"), std::string::npos) << r.out; // '|' escaped
    std::ifstream in(std::string(FFD_SOURCE_DIR) + "/docs/LIMITS.md");
    std::stringstream docs;
    docs << in.rdbuf();
    const std::string begin = "<!-- generated: ffdaabb settings --markdown -->\n";
    const size_t at = docs.str().find(begin);
    ASSERT_NE(at, std::string::npos) << "docs/LIMITS.md lost its settings table";
    EXPECT_EQ(docs.str().substr(at + begin.size(), r.out.size()), r.out)
        << "docs/LIMITS.md's settings table is out of date: paste `ffdaabb settings --markdown`";
}
