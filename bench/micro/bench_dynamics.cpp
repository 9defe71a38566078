// Lattice dynamics cost per particle per substep: shape matching (fast summation and the naive
// reference, per-body and per-region damping, w = 1..3) and mass-spring.
#include "dynamics/mass_spring.h"
#include "dynamics/shape_matching.h"
#include "ffdaabb/generators.h"
#include "ffdaabb/lattice.h"

#include <benchmark/benchmark.h>

#include <cmath>

using namespace ffd;

namespace {

// A lattice of about `cells` cells around a sphere, deformed by a wave, moving.
struct Setup {
    Lattice lattice;
    std::vector<Vec3> x, v;
    explicit Setup(int cells) {
        TriangleMesh m = icosphere(3);
        LatticeSettings s;
        s.targetCells = cells;
        lattice = buildLattice(m, s);
        x = lattice.restParticles;
        v.assign(x.size(), Vec3{0.1f, 0.0f, 0.0f});
        for (Vec3& p : x) p += Vec3{0.05f * std::sin(3 * p.y), 0.0f, 0.05f * std::cos(2 * p.x)};
    }
};

void BM_ShapeMatching(benchmark::State& state) {
    const int w = int(state.range(0));
    const bool naive = state.range(1) & 1;
    const bool regionDamping = state.range(1) & 2;
    Setup setup(int(state.range(2)));
    const detail::ShapeMatchingModel model = detail::buildShapeMatching(setup.lattice, w);
    std::vector<Quat> q(setup.x.size());
    detail::ShapeMatchingScratch scratch;
    detail::ShapeMatchingStep step;
    step.damping = 0.1f;
    step.regionDamping = regionDamping;
    step.acceleration = {0, -9.81f, 0};
    std::vector<Vec3> x = setup.x, v = setup.v;
    for (auto _ : state) {
        // Re-deform every step so the work stays representative (no convergence to rest).
        x = setup.x;
        detail::stepShapeMatching(model, step, x, v, q, scratch, naive);
        benchmark::DoNotOptimize(x.data());
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(x.size()));
    state.SetLabel(std::string(naive ? "naive" : "fast") +
                   (regionDamping ? " region-damping" : " body-damping") +
                   " P=" + std::to_string(x.size()) + " mean region " +
                   std::to_string(model.members.size() / x.size()));
}

// Four bodies of one model per call, one per vector lane (what the World does), with the
// rotation-step warm start; each body deformed differently.
void BM_ShapeMatching4(benchmark::State& state) {
    const int w = int(state.range(0));
    Setup setup(int(state.range(1)));
    const detail::ShapeMatchingModel model = detail::buildShapeMatching(setup.lattice, w);
    const size_t P = setup.x.size();
    std::vector<Vec3> rest[4], x[4], v[4];
    std::vector<Quat> q[4], steps[4];
    detail::ShapeMatchingLane lanes[4];
    for (int l = 0; l < 4; ++l) {
        rest[l] = setup.x;
        for (Vec3& p : rest[l]) p += Vec3{0.01f * float(l) * p.y, 0.0f, 0.0f};
        x[l] = rest[l];
        v[l] = setup.v;
        q[l].assign(P, Quat{});
        steps[l].assign(P, Quat{});
        lanes[l].x = x[l];
        lanes[l].v = v[l];
        lanes[l].rotations = q[l];
        lanes[l].rotationSteps = steps[l];
        lanes[l].damping = 0.1f;
        lanes[l].acceleration = {0, -9.81f, 0};
    }
    detail::ShapeMatchingScratch scratch;
    for (auto _ : state) {
        detail::stepShapeMatching4(model, 1.0f / 120.0f, 2, lanes, 4, scratch);
        benchmark::DoNotOptimize(v[0].data());
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(4 * P));
    state.SetLabel("4 bodies, P=" + std::to_string(P) + " each");
}

void BM_MassSpring(benchmark::State& state) {
    Setup setup(int(state.range(0)));
    const detail::MassSpringModel model = detail::buildMassSpring(setup.lattice);
    std::vector<float> invMass(setup.x.size(), 1.0f);
    detail::MassSpringScratch scratch;
    detail::MassSpringStep step;
    step.damping = 0.1f;
    step.acceleration = {0, -9.81f, 0};
    step.youngsModulus = 2e5f;
    std::vector<Vec3> x = setup.x, v = setup.v;
    int iterations = 0;
    for (auto _ : state) {
        x = setup.x;
        iterations = detail::stepMassSpring(model, step, invMass, x, v, scratch);
        benchmark::DoNotOptimize(x.data());
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(x.size()));
    state.SetLabel("P=" + std::to_string(x.size()) +
                   " springs=" + std::to_string(model.springs.size()) +
                   " CG iterations=" + std::to_string(iterations));
}

} // namespace

// Arguments: w, mode (bit 0 naive, bit 1 region damping), target cells.
BENCHMARK(BM_ShapeMatching)
    ->ArgsProduct({{1, 2, 3}, {0, 1, 2, 3}, {38, 148}})
    ->Unit(benchmark::kMicrosecond);
// Arguments: w, target cells.
BENCHMARK(BM_ShapeMatching4)->ArgsProduct({{1, 2, 3}, {38, 148}})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MassSpring)->Arg(38)->Arg(148)->Unit(benchmark::kMicrosecond);
