// The diagnostic tools built beside the CLI (bench/causes), run on a small pile: they finish,
// write their JSON, and leave the run they measure as it would have been.
#include "test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

using namespace ffd::test;
namespace fs = std::filesystem;

namespace {

fs::path toolPath(const char* name) {
    return fs::path(FFD_BINARY_DIR) / "bin" / name;
}

} // namespace

// ffdaabb_contact_causes finds each classified frame's contacts afresh and restores the world
// afterwards: classifying frames 20 and 40 as well does not change what frame 60 shows. Its
// counts of the contacts whose constraint is off their manifold's distance stay within each
// other (docs/ALGORITHM.md §4, "Where the partner leaves the box").
TEST(CausesTool, ComparesTheContactsAndLeavesTheRunUnchanged) {
    const fs::path tool = toolPath("ffdaabb_contact_causes");
    if (!fs::exists(tool)) GTEST_SKIP() << "not built: " << tool;
    TempDir dir;
    auto run = [&](const char* every, const char* json) {
        const RunResult r =
            runProgram({tool.string(), "--scene", "alphabets", "--objects", "40", "--frames", "60",
                        "--every", every, "--json", (dir / json).string()},
                       300);
        EXPECT_EQ(r.status, 0) << r.err;
        EXPECT_NE(r.out.find("partners kept within their boxes"), std::string::npos) << r.out;
        return nlohmann::json::parse(readFile(dir / json));
    };
    const nlohmann::json often = run("20", "often.json"), once = run("60", "once.json");
    ASSERT_EQ(often["per_frame"].size(), 3u);
    ASSERT_EQ(once["per_frame"].size(), 1u);
    EXPECT_EQ(often["per_frame"][2], once["per_frame"][0]); // frame 60, the same either way
    const nlohmann::json& p = often["partners"];
    EXPECT_GT(p["contacts"].get<long long>(), 100); // the letters lie on each other by frame 60
    EXPECT_LE(p["off_1mm"].get<long long>(), p["contacts"].get<long long>());
    EXPECT_LE(p["off_1cm"].get<long long>(), p["off_1mm"].get<long long>());
    EXPECT_LE(p["off_1mm_shallower"].get<long long>(), p["off_1mm"].get<long long>());
    EXPECT_GE(p["most_off_m"].get<double>(), 0.0);
}
