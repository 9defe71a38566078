// One substep's contacts found (phases 2 and 3, the object_contacts stage) and their response
// (collision/contact.h: pre-stabilisation, the rigid impact phase, the move, the projection and
// the velocity pass) on a paper scene while its pile lands: the same state every iteration, so
// each times its stage alone, without the rest of the frame that the whole-frame benchmarks mix
// in.
#include "collision/overlap_recovery.h"
#include "collision/pipeline.h"
#include "ffdaabb/scene.h"
#include "world/stages.h"
#include "world/world_data.h"

#include <benchmark/benchmark.h>

#include <map>
#include <memory>

using namespace ffd;

namespace {

// alphabets_x10 (1,650 letters) shows what a pile ten times the paper's costs per contact once
// its contacts and particles no longer fit the caches; it takes about half a minute to set up.
const char* kScenes[] = {"alphabets", "spheres", "alphabets_x10"};

struct Landing {
    SceneBuild build;
    std::vector<Vec3> x, v;
    detail::ContactList contacts;
    std::vector<detail::BoxPairClaim> claims; ///< the last substep's, as phase 3 reads them
};

// The scene after 90 frames, one more substep's contacts found (as World::step finds them), and
// the state they were found on.
Landing& landing(int index) {
    static std::map<int, std::unique_ptr<Landing>> cache;
    auto& slot = cache[index];
    if (slot) return *slot;
    slot = std::make_unique<Landing>();
    Landing& l = *slot;
    l.build = buildScene(loadScene(kScenes[index]));
    World& world = l.build.world;
    for (int f = 0; f < 90; ++f) world.step();
    detail::WorldData& w = detail::dataOf(world);
    const float dt = w.settings.frameStep / float(w.settings.substeps);
    detail::CollisionWorld view = detail::collisionView(w);
    detail::latticeDynamicsStage(w, dt);
    detail::nodeUpdateStage(w, view);
    w.collision.pairs.clear();
    detail::trackOverlaps(view);
    detail::pushPairsApart(view, dt);
    detail::sphereTest(view);
    l.claims = w.collision.claims;
    detail::findAllObjectContacts(view);
    detail::findFloorContacts(view);
    detail::settleOverlaps(view);
    l.x = w.x;
    l.v = w.v;
    l.contacts = w.collision.all;
    return l;
}

void BM_ContactResponse(benchmark::State& state) {
    Landing& l = landing(int(state.range(0)));
    detail::WorldData& w = detail::dataOf(l.build.world);
    const float dt = w.settings.frameStep / float(w.settings.substeps);
    detail::CollisionWorld view = detail::collisionView(w);
    for (auto _ : state) {
        state.PauseTiming();
        w.x = l.x;
        w.v = l.v;
        w.collision.all = l.contacts;
        state.ResumeTiming();
        detail::respondBeforeMove(view, dt);
        detail::positionUpdateStage(w, dt);
        benchmark::DoNotOptimize(detail::respondAfterMove(view, dt));
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(l.contacts.size()));
    state.SetLabel(kScenes[state.range(0)]);
    state.counters["contacts"] = double(l.contacts.size());
}

void BM_ObjectContacts(benchmark::State& state) {
    Landing& l = landing(int(state.range(0)));
    detail::WorldData& w = detail::dataOf(l.build.world);
    detail::CollisionWorld view = detail::collisionView(w);
    w.x = l.x;
    w.v = l.v;
    for (auto _ : state) {
        state.PauseTiming();
        w.collision.claims = l.claims;
        state.ResumeTiming();
        detail::findAllObjectContacts(view);
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(w.collision.objectCount));
    state.SetLabel(kScenes[state.range(0)]);
    state.counters["contacts"] = double(w.collision.objectCount);
    state.counters["node_box_pairs"] = double(w.profile.potentialPairs);
    state.counters["box_pairs"] = double(w.profile.boxPairs);
}

} // namespace

BENCHMARK(BM_ObjectContacts)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ContactResponse)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);
