// The frame of a settled paper scene with sleeping on (the default) and off: each scene is
// stepped for 20 s of simulated time once per process (untimed, both ways from the same start),
// then each benchmark times one more frame per iteration. A counter gives the bodies asleep.
#include "ffdaabb/scene.h"
#include "ffdaabb/world.h"

#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <string>
#include <utility>

using namespace ffd;

namespace {

const char* const kScenes[] = {"spheres", "teapots", "buddhas", "alphabets"};
constexpr int kSettleFrames = 1200;

// The scene settled with sleeping on or off, built and stepped on first use.
World& settled(int scene, bool sleeping) {
    static std::map<std::pair<int, bool>, std::unique_ptr<SceneBuild>> cache;
    std::unique_ptr<SceneBuild>& slot = cache[{scene, sleeping}];
    if (!slot) {
        Scene s = loadScene(kScenes[scene]);
        if (!sleeping) s.world.sleepSpeed = 0;
        slot = std::make_unique<SceneBuild>(buildScene(s));
        for (int f = 0; f < kSettleFrames; ++f) slot->world.step();
    }
    return slot->world;
}

void BM_SettledFrame(benchmark::State& state) {
    const int scene = int(state.range(0));
    const bool sleeping = state.range(1) != 0;
    World& world = settled(scene, sleeping);
    for (auto _ : state) world.step();
    state.SetLabel(std::string(kScenes[scene]) + (sleeping ? " sleeping on" : " sleeping off"));
    state.counters["asleep"] = double(world.bodyCount() - world.awakeCount());
    state.counters["bodies"] = double(world.bodyCount());
}

} // namespace

BENCHMARK(BM_SettledFrame)
    ->ArgsProduct({{0, 1, 2, 3}, {0, 1}})
    ->ArgNames({"scene", "sleep"})
    ->Unit(benchmark::kMillisecond);
