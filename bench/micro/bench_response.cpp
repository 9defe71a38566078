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

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <string>

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

// Times the response (before the move, the move, after it) to `contacts` on the landing's
// state, `objects` of them object contacts (CollisionState::objectCount), each iteration from
// that same state.
void timeResponse(benchmark::State& state, Landing& l, const detail::ContactList& contacts,
                  size_t objects) {
    detail::WorldData& w = detail::dataOf(l.build.world);
    const float dt = w.settings.frameStep / float(w.settings.substeps);
    detail::CollisionWorld view = detail::collisionView(w);
    const size_t landingObjects = w.collision.objectCount;
    for (auto _ : state) {
        state.PauseTiming();
        w.x = l.x;
        w.v = l.v;
        w.collision.all = contacts;
        w.collision.objectCount = objects;
        state.ResumeTiming();
        detail::respondBeforeMove(view, dt);
        detail::positionUpdateStage(w, dt);
        benchmark::DoNotOptimize(detail::respondAfterMove(view, dt));
    }
    w.collision.objectCount = landingObjects;
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(contacts.size()));
    state.counters["contacts"] = double(contacts.size());
}

void BM_ContactResponse(benchmark::State& state) {
    Landing& l = landing(int(state.range(0)));
    timeResponse(state, l, l.contacts, detail::dataOf(l.build.world).collision.objectCount);
    state.SetLabel(kScenes[state.range(0)]);
}

// BM_ContactResponse on alphabets_x10's contacts between letters that lie in the first
// 1/parts of the floor along x: the same pile and the same contacts' neighbourhoods, fewer of
// them. The cost per contact against the strip's size shows what the cache holds (docs/
// BENCHMARKS.md, "The large pile's sweeps in blocks").
void BM_ContactResponseStrip(benchmark::State& state) {
    Landing& l = landing(2);
    const detail::WorldData& w = detail::dataOf(l.build.world);
    const std::span<const detail::CollisionBody> bodies = w.collision.bodies;
    float lo = INFINITY, hi = -INFINITY;
    for (const detail::CollisionBody& b : bodies)
        lo = std::min(lo, b.bounds.lo.x), hi = std::max(hi, b.bounds.hi.x);
    const float cut = lo + (hi - lo) / float(state.range(0));
    auto inStrip = [&](uint32_t b) { return bodies[b].bounds.hi.x < cut; };
    detail::ContactList strip;
    size_t objects = 0; // the object contacts come first (CollisionState::objectCount)
    for (size_t n = 0; n < l.contacts.size(); ++n) {
        const detail::Contact& c = l.contacts[n];
        const bool object = n < w.collision.objectCount;
        if (inStrip(c.bodyA) && (!object || inStrip(c.bodyB))) {
            strip.push_back(c);
            objects += object;
        }
    }
    timeResponse(state, l, strip, objects);
    state.SetLabel("alphabets_x10, 1/" + std::to_string(state.range(0)) + " of the floor");
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
BENCHMARK(BM_ContactResponseStrip)->Arg(1)->Arg(2)->Arg(4)->Arg(10)->Unit(benchmark::kMillisecond);
