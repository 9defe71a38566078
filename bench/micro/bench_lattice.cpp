// Lattice building, FFD-AABB node update and trilinear mesh update on the paper's objects.
#include "ffdaabb/generators.h"
#include "ffdaabb/lattice.h"

#include <benchmark/benchmark.h>

#include <map>
#include <memory>

using namespace ffd;

namespace {

// The paper's objects with Table 2's cell counts (built once per process).
struct PaperObject {
    TriangleMesh mesh;
    int cells;
};

const PaperObject& paperObject(int index) {
    static std::map<int, std::unique_ptr<PaperObject>> cache;
    auto& slot = cache[index];
    if (!slot) {
        slot = std::make_unique<PaperObject>();
        switch (index) {
        case 0:
            slot->mesh = letter('A'), slot->cells = 34;
            break;
        case 1:
            slot->mesh = icosphere(2), slot->cells = 38;
            break;
        case 2:
            slot->mesh = teapot(10), slot->cells = 84;
            break;
        default:
            slot->mesh = dragon(), slot->cells = 148;
            break;
        }
    }
    return *slot;
}

const char* kNames[] = {"letter_A", "sphere", "teapot", "dragon"};

void BM_BuildLattice(benchmark::State& state) {
    const PaperObject& o = paperObject(int(state.range(0)));
    LatticeSettings s;
    s.targetCells = o.cells;
    const float h = chooseCellSize(o.mesh, s);
    LatticeSettings fixed;
    fixed.cellSize = h;
    for (auto _ : state) benchmark::DoNotOptimize(buildLattice(o.mesh, fixed));
    state.SetLabel(kNames[state.range(0)]);
    state.counters["triangles"] = double(o.mesh.triangleCount());
}

void BM_ChooseCellSize(benchmark::State& state) {
    const PaperObject& o = paperObject(int(state.range(0)));
    LatticeSettings s;
    s.targetCells = o.cells;
    for (auto _ : state) benchmark::DoNotOptimize(chooseCellSize(o.mesh, s));
    state.SetLabel(kNames[state.range(0)]);
}

void BM_NodeUpdate(benchmark::State& state) {
    const PaperObject& o = paperObject(int(state.range(0)));
    LatticeSettings s;
    s.targetCells = o.cells;
    const Lattice L = buildLattice(o.mesh, s);
    std::vector<Vec3> particles = L.restParticles, nodes(L.nodeCount());
    for (size_t i = 0; i < particles.size(); ++i)
        particles[i] += Vec3{0.01f, 0.0f, -0.01f} * float(i % 7);
    for (auto _ : state) {
        updateBoxNodes(L, particles, nodes);
        benchmark::DoNotOptimize(nodes.data());
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(L.nodeCount()));
    state.SetLabel(std::string(kNames[state.range(0)]) + " nodes/s");
}

void BM_MeshUpdate(benchmark::State& state) {
    const PaperObject& o = paperObject(int(state.range(0)));
    LatticeSettings s;
    s.targetCells = o.cells;
    const Lattice L = buildLattice(o.mesh, s);
    std::vector<Vec3> particles = L.restParticles, vertices(o.mesh.vertexCount());
    for (size_t i = 0; i < particles.size(); ++i)
        particles[i] += Vec3{0.01f, 0.0f, -0.01f} * float(i % 7);
    for (auto _ : state) {
        deformVertices(L, particles, vertices);
        benchmark::DoNotOptimize(vertices.data());
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(vertices.size()));
    state.SetLabel(std::string(kNames[state.range(0)]) + " vertices/s");
}

} // namespace

BENCHMARK(BM_BuildLattice)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ChooseCellSize)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NodeUpdate)->DenseRange(0, 3)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MeshUpdate)->DenseRange(0, 3)->Unit(benchmark::kMicrosecond);
