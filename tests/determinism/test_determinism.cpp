// Determinism: golden state hashes of the paper's four scenes (tests/data/golden_hashes.json,
// written by scripts/update_golden.sh), and the same hash from repeated runs and from any
// thread count, through the library and through `ffdaabb run`.
#include "ffdaabb/scene.h"
#include "test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <string>

using namespace ffd;
using ffd::test::readFile;
using ffd::test::runCli;
using ffd::test::TempDir;

namespace {

const std::filesystem::path kGoldenFile =
    std::filesystem::path(FFD_SOURCE_DIR) / "tests" / "data" / "golden_hashes.json";

std::string hex(uint64_t h) {
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
    return buf;
}

// The state hash after `frames` frames of a shipped scene with `objects` objects, as
// `ffdaabb run --scene NAME --objects N --frames F --threads T` computes it.
std::string hashAfter(const std::string& name, int objects, int frames, int threads) {
    Scene scene = loadScene(name);
    setObjectCount(scene, objects);
    scene.world.threads = threads;
    SceneBuild build = buildScene(scene);
    for (int f = 0; f < frames; ++f) build.world.step();
    return hex(build.world.stateHash());
}

std::string cliHash(const std::vector<std::string>& args) {
    TempDir dir;
    std::vector<std::string> all = args;
    all.insert(all.end(), {"--quiet", "--stats", (dir / "stats.json").string()});
    const auto r = runCli(all);
    EXPECT_EQ(r.status, 0) << r.err;
    if (r.status != 0) return "(failed)";
    return nlohmann::json::parse(readFile(dir / "stats.json"))["state_hash"].get<std::string>();
}

} // namespace

TEST(Determinism, PaperScenesMatchTheGoldenHashes) {
    const nlohmann::json golden = nlohmann::json::parse(readFile(kGoldenFile));
    const int frames = golden["frames"].get<int>();
    std::vector<std::string> names;
    for (const auto& entry : golden["scenes"]) {
        const std::string name = entry["scene"].get<std::string>();
        const int objects = entry["objects"].get<int>();
        const std::string expected = entry["state_hash"].get<std::string>();
        const std::string got = hashAfter(name, objects, frames, 1);
        EXPECT_EQ(got, expected)
            << "The state of scene " << name << " (" << objects << " objects) after " << frames
            << " frames drifted from " << kGoldenFile.string() << ": expected " << expected
            << ", got " << got
            << ".\nThe simulation's results changed. If the change is deliberate (physics, "
               "collision response, scene layout), regenerate the hashes with\n"
               "    scripts/update_golden.sh\nand commit tests/data/golden_hashes.json with "
               "the change. If it is not, this change altered the simulation's results.";
        names.push_back(name);
    }
    // The file covers the paper's four scenes.
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"alphabets", "buddhas", "spheres", "teapots"}));
}

TEST(Determinism, RepeatedRunsGiveTheSameHash) {
    // Two layers of teapots: they land on each other.
    const std::string first = hashAfter("teapots", 24, 120, 1);
    EXPECT_EQ(hashAfter("teapots", 24, 120, 1), first);
}

TEST(Determinism, ThreadCountsGiveTheSameHashThroughTheCli) {
    // `--threads 1/2/4` and a repeated run agree with each other and with the library.
    const std::vector<std::string> run = {"run", "--scene",  "spheres", "--objects",
                                          "30",  "--frames", "150"};
    auto with = [&](const std::string& threads) {
        std::vector<std::string> args = run;
        args.insert(args.end(), {"--threads", threads});
        return cliHash(args);
    };
    const std::string one = with("1");
    EXPECT_EQ(with("2"), one);
    EXPECT_EQ(with("4"), one);
    EXPECT_EQ(with("1"), one);
    EXPECT_EQ(hashAfter("spheres", 30, 150, 3), one);
}
