// ffdaabb run --save-state / --load-state: a run split in two at a saved state ends where the
// run in one piece ends; a state file that does not fit is refused, naming the file.
#include "test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>

using namespace ffd::test;
namespace fs = std::filesystem;

namespace {

nlohmann::json stats(const fs::path& path) {
    return nlohmann::json::parse(readFile(path));
}

} // namespace

// 100 frames saved, then 50 from the saved state (on another thread count), end with the state
// hash of 150 frames in one run; the second run reports where it started.
TEST(CliSnapshot, SplitRunEndsWhereTheWholeRunEnds) {
    TempDir dir;
    const std::string state = (dir / "s.bin").string();
    const std::vector<std::string> common = {"run", "--scene", "spheres", "--measure-every", "0"};
    auto run = [&](std::vector<std::string> extra) {
        std::vector<std::string> args = common;
        args.insert(args.end(), extra.begin(), extra.end());
        return runCli(args);
    };
    RunResult r = run({"--frames", "100", "--save-state", state, "--quiet"});
    ASSERT_EQ(r.status, 0) << r.err;
    ASSERT_TRUE(fs::exists(state));
    r = run({"--frames", "50", "--threads", "2", "--load-state", state, "--stats",
             (dir / "split.json").string()});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("restored frame 100 from " + state), std::string::npos) << r.out;
    r = run({"--frames", "150", "--stats", (dir / "whole.json").string(), "--quiet"});
    ASSERT_EQ(r.status, 0) << r.err;
    const auto split = stats(dir / "split.json"), whole = stats(dir / "whole.json");
    EXPECT_EQ(split["state_hash"], whole["state_hash"]);
    EXPECT_EQ(split["start_frame"].get<int>(), 100);
    EXPECT_EQ(whole["start_frame"].get<int>(), 0);
    EXPECT_EQ(split["frames"].get<int>(), 50);
    // Going on in place: the state file read, then replaced by the later state.
    r = run({"--frames", "50", "--load-state", state, "--save-state", state, "--quiet"});
    ASSERT_EQ(r.status, 0) << r.err;
    r = run({"--frames", "1", "--load-state", state, "--stats", (dir / "next.json").string(),
             "--quiet"});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(stats(dir / "next.json")["start_frame"].get<int>(), 150);
}

// A state file that is missing, not a state, cut short, or of another scene: exit status 2 and
// one line naming the flag, the file and what is wrong; nothing written.
TEST(CliSnapshot, BadStateFilesAreRefusedNamingTheFile) {
    TempDir dir;
    const std::string state = (dir / "s.bin").string();
    ASSERT_EQ(runCli({"run", "--scene", "spheres", "--objects", "12", "--frames", "5",
                      "--save-state", state, "--quiet"})
                  .status,
              0);
    const std::string bytes = readFile(state);
    writeFile(dir / "cut.bin", bytes.substr(0, bytes.size() / 2));
    writeFile(dir / "text.bin", "not a state\n");
    struct Case {
        std::vector<std::string> flags;
        std::string expected;
    };
    const std::string missing = (dir / "missing.bin").string();
    const Case cases[] = {
        {{"--load-state", missing},
         "--load-state: cannot read \"" + missing + "\": No such file or directory"},
        {{"--load-state", dir.path().string()}, "it is a folder"},
        {{"--load-state", (dir / "text.bin").string()},
         "--load-state: cannot restore \"" + (dir / "text.bin").string() +
             "\": not an ffdaabb state"},
        {{"--load-state", (dir / "cut.bin").string()}, "\": truncated: the header announces"},
        {{"--load-state", state, "--objects", "11", "--scene", "spheres"},
         "--load-state: cannot restore \"" + state +
             "\": saved from a scene of 12 bodies, this world has 11"},
        {{"--load-state", state, "--mode", "brute"},
         "saved with the world setting mode enhanced, this world has brute"},
        {{"--save-state", (dir / "no" / "s.bin").string()}, "--save-state: cannot write"},
        {{"--save-state", (dir / "o.obj").string(), "--export-obj", (dir / "o.obj").string()},
         "is the same file as --export-obj"},
    };
    for (const Case& c : cases) {
        // The scene flags unless the case gives its own (a flag may be given once).
        std::vector<std::string> args = {"run",     "--frames", "3",
                                         "--quiet", "--stats",  (dir / "out.json").string()};
        if (std::find(c.flags.begin(), c.flags.end(), "--objects") == c.flags.end())
            args.insert(args.end(), {"--scene", "spheres", "--objects", "12"});
        args.insert(args.end(), c.flags.begin(), c.flags.end());
        const RunResult r = runCli(args);
        EXPECT_EQ(r.status, 2) << c.expected << "\n" << r.err;
        EXPECT_NE(r.err.find(c.expected), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(dir / "out.json")) << c.expected;
        EXPECT_FALSE(fs::exists(dir / "o.obj")) << c.expected;
    }
}
