// Queries (ffdaabb/queries.h) on the paper's scenes after two seconds of falling and piling up:
// rays per second with the caches warm, what the first query after a step pays, box queries.
#include "ffdaabb/queries.h"
#include "ffdaabb/scene.h"
#include "world/world_data.h"

#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <random>

using namespace ffd;

namespace {

const char* kScenes[] = {"alphabets", "buddhas"};

struct Piled {
    SceneBuild build;
    std::vector<std::pair<Vec3, Vec3>> rays; // origin, direction
    std::vector<Aabb> boxes;
    size_t triangles = 0;
};

// The scene after 120 frames, and rays from above the pile at random points of its meshes
// (hits, through the pile's top) and in random directions from random points above the floor
// (mostly misses), half and half.
Piled& piled(int index) {
    static std::map<int, std::unique_ptr<Piled>> cache;
    auto& slot = cache[index];
    if (slot) return *slot;
    slot = std::make_unique<Piled>();
    Piled& p = *slot;
    p.build = buildScene(loadScene(kScenes[index]));
    World& world = p.build.world;
    for (int f = 0; f < 120; ++f) world.step();
    Aabb all;
    for (BodyId b : world.bodies())
        all.add(world.bounds(b)), p.triangles += world.triangles(b).size();
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(0, 1);
    const auto ids = world.bodies();
    for (int i = 0; i < 4096; ++i) {
        const Vec3 e = all.extent();
        const Vec3 origin{all.lo.x + u(rng) * e.x, all.hi.y + 1 + u(rng) * e.y,
                          all.lo.z + u(rng) * e.z};
        if (i % 2 == 0) {
            const BodyId b = ids[rng() % ids.size()];
            const auto v = world.vertices(b);
            p.rays.push_back({origin, v[rng() % v.size()] - origin});
        } else {
            const Vec3 from{all.lo.x + u(rng) * e.x, all.lo.y + u(rng) * e.y,
                            all.lo.z + u(rng) * e.z};
            p.rays.push_back({from, Vec3{u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f}});
        }
        const Vec3 c{all.lo.x + u(rng) * e.x, all.lo.y + u(rng) * e.y, all.lo.z + u(rng) * e.z};
        const float h = 0.05f + 0.2f * u(rng);
        p.boxes.push_back({c - Vec3{h, h, h}, c + Vec3{h, h, h}});
    }
    return p;
}

// Rays with the caches warm (every body refitted once): the steady cost of a query.
void BM_RaycastWarm(benchmark::State& state) {
    Piled& p = piled(int(state.range(0)));
    const World& world = p.build.world;
    std::vector<BodyId> found;
    bodiesOverlapping(world, Aabb{{-1e6f, -1e6f, -1e6f}, {1e6f, 1e6f, 1e6f}}, found); // refit all
    size_t i = 0, hits = 0;
    for (auto _ : state) {
        const auto& [o, d] = p.rays[i++ % p.rays.size()];
        const auto hit = raycast(world, o, d);
        hits += hit.has_value();
        benchmark::DoNotOptimize(hit);
    }
    state.SetItemsProcessed(int64_t(state.iterations()));
    state.SetLabel(kScenes[state.range(0)]);
    state.counters["hit_share"] = double(hits) / double(std::max<size_t>(i, 1));
    state.counters["triangles"] = double(p.triangles);
}

// The first ray after a step: the bodies' boxes over all vertices, and a refit of each body the
// ray reaches.
void BM_RaycastFirstAfterStep(benchmark::State& state) {
    Piled& p = piled(int(state.range(0)));
    const World& world = p.build.world;
    size_t i = 0;
    for (auto _ : state) {
        detail::meshesChanged(detail::dataOf(world).queries);         // as a step does
        const auto& [o, d] = p.rays[2 * (i++ % (p.rays.size() / 2))]; // rays that hit
        benchmark::DoNotOptimize(raycast(world, o, d));
    }
    state.SetLabel(kScenes[state.range(0)]);
}

// Refitting every body after a step (a query reaching every body: a box over the whole scene).
void BM_RefitAll(benchmark::State& state) {
    Piled& p = piled(int(state.range(0)));
    const World& world = p.build.world;
    std::vector<BodyId> found;
    for (auto _ : state) {
        detail::meshesChanged(detail::dataOf(world).queries);
        bodiesOverlapping(world, Aabb{{-1e6f, -1e6f, -1e6f}, {1e6f, 1e6f, 1e6f}}, found);
    }
    state.SetLabel(kScenes[state.range(0)]);
    state.counters["triangles"] = double(p.triangles);
}

// Boxes of 10 to 50 cm inside the pile's bounds, caches warm.
void BM_BodiesOverlapping(benchmark::State& state) {
    Piled& p = piled(int(state.range(0)));
    const World& world = p.build.world;
    std::vector<BodyId> found;
    bodiesOverlapping(world, Aabb{{-1e6f, -1e6f, -1e6f}, {1e6f, 1e6f, 1e6f}}, found);
    size_t i = 0, bodies = 0;
    for (auto _ : state) {
        bodiesOverlapping(world, p.boxes[i++ % p.boxes.size()], found);
        bodies += found.size();
    }
    state.SetItemsProcessed(int64_t(state.iterations()));
    state.SetLabel(kScenes[state.range(0)]);
    state.counters["bodies_per_box"] = double(bodies) / double(std::max<size_t>(i, 1));
}

// What a step pays for the contact queries: its substeps' contacts summed per pair (here the
// last substep's contacts, as many times as there are substeps) and the pairs and events made.
void BM_ContactTally(benchmark::State& state) {
    Piled& p = piled(int(state.range(0)));
    detail::WorldData& w = detail::dataOf(p.build.world);
    for (auto _ : state) {
        for (int s = 0; s < w.settings.substeps; ++s) detail::tallyContacts(w);
        detail::finishContactTally(w);
    }
    state.SetLabel(kScenes[state.range(0)]);
    state.counters["contacts"] = double(w.collision.all.size());
    state.counters["pairs"] = double(w.contactTally.pairs.size());
}

} // namespace

BENCHMARK(BM_ContactTally)->DenseRange(0, 1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RaycastWarm)->DenseRange(0, 1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RaycastFirstAfterStep)->DenseRange(0, 1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RefitAll)->DenseRange(0, 1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BodiesOverlapping)->DenseRange(0, 1)->Unit(benchmark::kMicrosecond);
