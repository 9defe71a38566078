// Lattice dynamics through the World: free fall, shape recovery, conservation, resting contact,
// stability over settings, determinism.
#include "dynamics/mass_spring.h"
#include "dynamics/polar.h"
#include "dynamics/shape_matching.h"
#include "ffdaabb/generators.h"
#include "ffdaabb/world.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <random>

using namespace ffd;

namespace {

TriangleMesh ball(float radius = 0.5f) {
    TriangleMesh m = icosphere(2);
    transform(m, radius, {});
    return m;
}

// An elongated, bumpy closed body: less symmetric than the sphere.
TriangleMesh blob() {
    TriangleMesh m = icosphere(3);
    const test::SmoothDeformation bump(3, 1.0f, 0.2f);
    for (Vec3& p : m.positions) p = bump(mul(p, Vec3{0.8f, 0.4f, 0.5f}));
    return m;
}

BodySettings settingsFor(DynamicsModel model, int w = 1) {
    BodySettings s;
    s.model = model;
    s.regionHalfWidth = w;
    s.lattice.targetCells = 38;
    return s;
}

// Largest distance of the particles from the best rigid image of the rest lattice (Kabsch by
// the polar decomposition), relative to the lattice's size.
float shapeErrorUpToRigid(const Lattice& L, std::span<const Vec3> x) {
    const size_t n = x.size();
    Vec3 c{}, c0{};
    for (size_t i = 0; i < n; ++i) c += x[i], c0 += L.restParticles[i];
    c = c / float(n), c0 = c0 / float(n);
    Mat3 A;
    for (size_t i = 0; i < n; ++i) A = A + outer(x[i] - c, L.restParticles[i] - c0);
    const Mat3 R = toMat3(detail::closestRotation(A));
    float worst = 0;
    Aabb rest;
    for (size_t i = 0; i < n; ++i) {
        worst = std::max(worst, length(x[i] - (R * (L.restParticles[i] - c0) + c)));
        rest.add(L.restParticles[i]);
    }
    return worst / maxComponent(rest.extent());
}

Vec3 momentum(const World& world, BodyId id) {
    return world.linearVelocity(id) * world.info(id).mass;
}

} // namespace

class BothModels : public ::testing::TestWithParam<DynamicsModel> {};
INSTANTIATE_TEST_SUITE_P(Dynamics, BothModels,
                         ::testing::Values(DynamicsModel::ShapeMatching, DynamicsModel::MassSpring),
                         [](const auto& param) {
                             return param.param == DynamicsModel::ShapeMatching ? "ShapeMatching"
                                                                                : "MassSpring";
                         });

TEST_P(BothModels, FreeFallMatchesTheBallisticCurve) {
    World world;
    BodySettings s = settingsFor(GetParam());
    s.position = {0, 20, 0};
    const BodyId id = world.addBody(ball(), s);
    const float y0 = world.centreOfMass(id).y;
    const float g = 9.81f;
    for (int f = 1; f <= 60; ++f) {
        world.step();
        const float t = float(f) / 60.0f;
        EXPECT_NEAR(world.centreOfMass(id).y, y0 - 0.5f * g * t * t, 1e-3f) << "frame " << f;
    }
    EXPECT_EQ(world.profile().floorContacts, 0);
}

TEST_P(BothModels, ThrownBodyFollowsAParabola) {
    World world;
    BodySettings s = settingsFor(GetParam());
    s.position = {0, 10, 0};
    s.velocity = {3, 4, -1};
    const BodyId id = world.addBody(ball(), s);
    const Vec3 c0 = world.centreOfMass(id);
    for (int f = 0; f < 60; ++f) world.step();
    const Vec3 expected = c0 + Vec3{3, 4, -1} * 1.0f + Vec3{0, -0.5f * 9.81f, 0};
    EXPECT_LE(length(world.centreOfMass(id) - expected), 1e-3f);
}

TEST_P(BothModels, DeformedBodyReturnsToItsRestShape) {
    WorldSettings ws;
    ws.gravity = {};
    ws.floor = false;
    const TriangleMesh mesh = blob();
    const Mat3 rotation = toMat3(Quat::fromAxisAngle({1, 2, 3}, 1.1f));
    const Mat3 shear{{{1, 0.3f, 0}, {0, 1, 0.2f}, {0, 0, 1}}};
    const Mat3 squash = Mat3::diagonal({1.15f, 0.7f, 1.15f});
    for (const Mat3& deformation : {rotation, shear, squash, rotation * squash}) {
        World world(ws);
        const BodyId id = world.addBody(mesh, settingsFor(GetParam()));
        const Lattice& L = world.lattice(id);
        std::vector<Vec3> deformed(L.particleCount());
        for (size_t i = 0; i < deformed.size(); ++i) deformed[i] = deformation * L.restParticles[i];
        world.setParticles(id, deformed);
        const float before = shapeErrorUpToRigid(L, world.particles(id));
        for (int f = 0; f < 600; ++f) world.step();
        const float after = shapeErrorUpToRigid(L, world.particles(id));
        EXPECT_LT(after, 0.01f) << "before " << before;
        for (const Vec3& p : world.particles(id)) ASSERT_TRUE(isFinite(p));
    }
}

TEST_P(BothModels, NoExternalForceConservesLinearMomentum) {
    WorldSettings ws;
    ws.gravity = {};
    ws.floor = false;
    World world(ws);
    BodySettings s = settingsFor(GetParam());
    s.velocity = {1.0f, -0.5f, 0.25f};
    s.angularVelocity = {0.5f, 2.0f, -1.0f};
    s.position = {3, 4, 5};
    const BodyId id = world.addBody(blob(), s);
    // Start deformed so the internal forces are busy.
    std::vector<Vec3> deformed(world.particles(id).begin(), world.particles(id).end());
    const test::SmoothDeformation warp(9, 1.0f, 0.3f);
    for (Vec3& p : deformed) p = warp(p);
    world.setParticles(id, deformed, false);
    const Vec3 p0 = momentum(world, id);
    for (int f = 0; f < 300; ++f) world.step();
    const Vec3 p1 = momentum(world, id);
    EXPECT_LE(length(p1 - p0), 1e-5f * length(p0)) << "p0 " << p0.x << "," << p0.y << "," << p0.z;
}

TEST(ShapeMatching, DoesNotGainEnergyWithoutDamping) {
    // A body released from a deformed state with no damping oscillates; the kinetic energy of
    // late oscillations must not exceed that of the early ones (symplectic update, alpha <= 1).
    WorldSettings ws;
    ws.gravity = {};
    ws.floor = false;
    for (float alpha : {1.0f, 0.5f}) {
        World world(ws);
        BodySettings s = settingsFor(DynamicsModel::ShapeMatching);
        s.damping = 0;
        s.stiffness = alpha;
        const BodyId id = world.addBody(blob(), s);
        const Lattice& L = world.lattice(id);
        std::vector<Vec3> deformed(L.particleCount());
        for (size_t i = 0; i < deformed.size(); ++i)
            deformed[i] = Mat3::diagonal({1.2f, 0.8f, 1.1f}) * L.restParticles[i];
        world.setParticles(id, deformed);
        double early = 0, late = 0;
        for (int f = 0; f < 3000; ++f) {
            world.step();
            const double e = world.kineticEnergy();
            ASSERT_TRUE(std::isfinite(e));
            if (f < 300) early = std::max(early, e);
            if (f >= 2700) late = std::max(late, e);
        }
        EXPECT_GT(early, 0.0);
        EXPECT_LE(late, early * 1.001) << "alpha " << alpha;
    }
}

TEST(ShapeMatching, DampingRemovesDeformationEnergyButNotRigidMotion) {
    WorldSettings ws;
    ws.gravity = {};
    ws.floor = false;
    World world(ws);
    BodySettings s = settingsFor(DynamicsModel::ShapeMatching);
    s.damping = 20;
    s.velocity = {2, 0, 0};
    s.angularVelocity = {0, 3, 0};
    const BodyId id = world.addBody(ball(), s);
    const double e0 = world.kineticEnergy();
    for (int f = 0; f < 120; ++f) world.step();
    // A rigidly spinning, translating body keeps its energy under rigid-motion-preserving
    // damping (up to the small centrifugal stretch of the soft body).
    EXPECT_NEAR(world.kineticEnergy(), e0, 0.02 * e0);
    EXPECT_NEAR(world.linearVelocity(id).x, 2.0f, 1e-4f);
}

TEST_P(BothModels, RestsOnTheFloorWithoutGapOrSinking) {
    World world;
    BodySettings s = settingsFor(GetParam());
    s.position = {0, 0.8f, 0};
    const BodyId id = world.addBody(ball(), s);
    const float h = world.info(id).cellSize;
    for (int f = 0; f < 10000; ++f) {
        world.step();
        if (f % 500 == 0) {
            for (const Vec3& p : world.particles(id)) ASSERT_TRUE(isFinite(p)) << "frame " << f;
        }
    }
    const double kePerKg = world.kineticEnergy() / world.info(id).mass;
    EXPECT_LT(kePerKg, 1e-6);
    float lowest = 1e9f;
    for (const Vec3& p : world.vertices(id)) lowest = std::min(lowest, p.y);
    EXPECT_GE(lowest, -0.01f * h);
    EXPECT_LE(lowest, 0.01f * h);
    EXPECT_LT(world.profile().maxContactDepth, 0.001f * h);
}

struct SettleCase {
    DynamicsModel model;
    int w;
    float frameStep;
};

class Settles : public ::testing::TestWithParam<SettleCase> {};

TEST_P(Settles, StaysFiniteAndComesToRest) {
    const SettleCase c = GetParam();
    WorldSettings ws;
    ws.frameStep = c.frameStep;
    World world(ws);
    BodySettings s = settingsFor(c.model, c.w);
    s.position = {0, 1.5f, 0};
    s.rotation = Quat::fromAxisAngle({1, 0, 1}, 0.7f);
    s.angularVelocity = {1, 2, 0};
    const BodyId id = world.addBody(blob(), s);
    const int frames = int(20.0f / c.frameStep); // 20 s of simulated time
    for (int f = 0; f < frames; ++f) world.step();
    for (const Vec3& p : world.particles(id)) ASSERT_TRUE(isFinite(p));
    EXPECT_LT(world.kineticEnergy() / world.info(id).mass, 1e-6);
    float lowest = 1e9f;
    for (const Vec3& p : world.vertices(id)) lowest = std::min(lowest, p.y);
    EXPECT_GT(lowest, -0.01f * world.info(id).cellSize);
    EXPECT_LT(world.profile().maxContactDepth, 0.01f * world.info(id).cellSize);
}

INSTANTIATE_TEST_SUITE_P(Dynamics, Settles,
                         ::testing::Values(SettleCase{DynamicsModel::ShapeMatching, 1, 1 / 30.0f},
                                           SettleCase{DynamicsModel::ShapeMatching, 1, 1 / 60.0f},
                                           SettleCase{DynamicsModel::ShapeMatching, 1, 1 / 120.0f},
                                           SettleCase{DynamicsModel::ShapeMatching, 2, 1 / 30.0f},
                                           SettleCase{DynamicsModel::ShapeMatching, 2, 1 / 60.0f},
                                           SettleCase{DynamicsModel::ShapeMatching, 2, 1 / 120.0f},
                                           SettleCase{DynamicsModel::ShapeMatching, 3, 1 / 30.0f},
                                           SettleCase{DynamicsModel::ShapeMatching, 3, 1 / 60.0f},
                                           SettleCase{DynamicsModel::ShapeMatching, 3, 1 / 120.0f},
                                           SettleCase{DynamicsModel::MassSpring, 1, 1 / 30.0f},
                                           SettleCase{DynamicsModel::MassSpring, 1, 1 / 60.0f},
                                           SettleCase{DynamicsModel::MassSpring, 1, 1 / 120.0f}),
                         [](const auto& param) {
                             return std::string(param.param.model == DynamicsModel::ShapeMatching
                                                    ? "LSM_w"
                                                    : "MS_w") +
                                    std::to_string(param.param.w) + "_dt" +
                                    std::to_string(int(std::lround(1.0f / param.param.frameStep)));
                         });

TEST_P(BothModels, SameSetupGivesTheSameStateHash) {
    auto run = [] {
        World world;
        for (int i = 0; i < 4; ++i) {
            BodySettings s = settingsFor(GetParam());
            s.position = {float(i) * 0.3f, 1.0f + 1.2f * float(i), 0};
            s.rotation = Quat::fromAxisAngle({0, 1, 1}, float(i));
            world.addBody(i % 2 ? ball() : blob(), s);
        }
        for (int f = 0; f < 200; ++f) world.step();
        return world.stateHash();
    };
    EXPECT_EQ(run(), run());
}

TEST(Polar, ExtractsTheClosestRotationEvenForDegenerateMatrices) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(-1, 1);
    for (int trial = 0; trial < 200; ++trial) {
        const Quat truth = normalize(Quat{u(rng), u(rng), u(rng), u(rng)});
        const Mat3 R = toMat3(truth);
        // Symmetric positive stretch, possibly flat (rank 2) or a line (rank 1).
        Vec3 d{0.5f + std::fabs(u(rng)), 0.5f + std::fabs(u(rng)), 0.5f + std::fabs(u(rng))};
        if (trial % 4 == 1) d.z = 0;
        if (trial % 4 == 2) d.y = d.z = 0;
        const Quat sq = normalize(Quat{u(rng), u(rng), u(rng), u(rng)});
        const Mat3 Q = toMat3(sq);
        const Mat3 A = R * Q * Mat3::diagonal(d) * transpose(Q);
        const Mat3 got = toMat3(detail::closestRotation(A));
        // The warm-started iteration from a nearby start lands on the same rotation wherever
        // it is unique (rank >= 2; a line leaves the spin about itself free).
        if (trial % 4 != 2) {
            Quat warm =
                normalize(detail::closestRotation(A) * Quat::fromAxisAngle({1, 0, 0}, 0.2f));
            detail::extractRotation(A, warm, 3);
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j)
                    EXPECT_NEAR(toMat3(warm).m[i][j], got.m[i][j], 1e-4f) << trial;
        }
        EXPECT_NEAR(determinant(got), 1.0f, 1e-4f);
        if (trial % 4 == 0) {
            // Full rank: the rotation is unique.
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) EXPECT_NEAR(got.m[i][j], R.m[i][j], 2e-3f) << trial;
        } else if (trial % 4 == 1) {
            // Flat: the two stretched directions must be mapped exactly like R does.
            for (int k = 0; k < 2; ++k) {
                const Vec3 axis = Q.column(k);
                EXPECT_LE(length(got * axis - R * axis), 2e-3f) << trial;
            }
        }
    }
    // A reflection gives a proper rotation, not the reflection.
    const Mat3 mirror = Mat3::diagonal({1, 1, -1});
    const Mat3 fromMirror = toMat3(detail::closestRotation(mirror));
    EXPECT_NEAR(determinant(fromMirror), 1.0f, 1e-5f);
    // ...the best one: tr(R^T A) = 1 (a half turn about an in-plane axis), not 3.
    EXPECT_NEAR(fromMirror.m[0][0] * 1 + fromMirror.m[1][1] - fromMirror.m[2][2], 1.0f, 1e-4f);
    // All zero (a collapsed region) keeps the warm start.
    Quat warm = Quat::fromAxisAngle({0, 0, 1}, 0.3f);
    const Quat before = warm;
    detail::refineRotation(Mat3{}, warm, 10);
    EXPECT_EQ(warm, before);
    // Newton converges in a couple of steps from a nearby warm start.
    const Mat3 S = Mat3::diagonal({3, 1, 0.2f});
    const Mat3 target = toMat3(Quat::fromAxisAngle({1, 2, 3}, 0.7f));
    Quat near = Quat::fromAxisAngle({1, 2, 3.1f}, 0.65f);
    EXPECT_LT(detail::refineRotation(target * S, near, 3), 1e-4f);
}

TEST(ShapeMatching, FastSummationEqualsNaiveSummation) {
    const TriangleMesh mesh = blob();
    for (int w = 1; w <= 3; ++w) {
        LatticeSettings ls;
        ls.targetCells = 60;
        const Lattice L = buildLattice(mesh, ls);
        const detail::ShapeMatchingModel model = detail::buildShapeMatching(L, w);
        std::vector<Vec3> x(L.particleCount());
        const test::SmoothDeformation warp(4, 1.0f, 0.4f);
        for (size_t i = 0; i < x.size(); ++i) x[i] = warp(L.restParticles[i]) + Vec3{5, 6, 7};
        std::vector<Quat> qa(x.size()), qb(x.size());
        std::vector<Vec3> ga(x.size()), gb(x.size());
        detail::ShapeMatchingScratch sa, sb;
        detail::shapeMatchingGoals(model, x, qa, 20, sa, ga, false);
        detail::shapeMatchingGoals(model, x, qb, 20, sb, gb, true);
        for (size_t i = 0; i < x.size(); ++i) ASSERT_LE(length(ga[i] - gb[i]), 1e-4f) << "w " << w;
        // Region membership is the cube of half-width w around each particle.
        for (size_t r = 0; r < x.size(); ++r)
            for (uint32_t k = model.memberStart[r]; k < model.memberStart[r + 1]; ++k) {
                const GridCoord a = L.particleCoords[r], b = L.particleCoords[model.members[k]];
                for (int axis = 0; axis < 3; ++axis) ASSERT_LE(std::abs(a[axis] - b[axis]), w);
            }
    }
}

TEST(ShapeMatching, RigidMotionIsAFixedPoint) {
    const TriangleMesh mesh = blob();
    const Lattice L = buildLattice(mesh);
    const detail::ShapeMatchingModel model = detail::buildShapeMatching(L, 2);
    const Mat3 R = toMat3(Quat::fromAxisAngle({1, 1, 0}, 2.0f));
    std::vector<Vec3> x(L.particleCount()), g(L.particleCount());
    for (size_t i = 0; i < x.size(); ++i) x[i] = R * L.restParticles[i] + Vec3{1, 2, 3};
    std::vector<Quat> q(x.size());
    detail::ShapeMatchingScratch s;
    detail::shapeMatchingGoals(model, x, q, 30, s, g);
    for (size_t i = 0; i < x.size(); ++i) EXPECT_LE(length(g[i] - x[i]), 1e-5f);
}

TEST(Polar, FourLanesAgreeWithOneAtATime) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1, 1);
    for (int trial = 0; trial < 300; ++trial) {
        detail::F4 A[9];
        detail::Q4 q;
        Mat3 m[4];
        Quat warm[4];
        for (int l = 0; l < 4; ++l) {
            // Rotations near, far from (a poor warm start) and exactly at the warm start, of
            // stretched, flat and zero matrices.
            const Quat truth = normalize(Quat{u(rng), u(rng), u(rng), u(rng)});
            const float off = (trial + l) % 3 == 0 ? 0.0f : ((trial + l) % 3 == 1 ? 0.05f : 1.5f);
            warm[l] = normalize(truth * Quat::fromAxisAngle({u(rng), u(rng), 1}, off));
            Vec3 d{1 + std::fabs(u(rng)), 1 + std::fabs(u(rng)), 1 + std::fabs(u(rng))};
            if (l == 2) d.z = 0;
            m[l] = (trial % 7 == 0 && l == 3) ? Mat3{} : toMat3(truth) * Mat3::diagonal(d);
            for (int e = 0; e < 9; ++e) A[e][l] = m[l].m[e / 3][e % 3];
            q.w[l] = warm[l].w, q.x[l] = warm[l].x, q.y[l] = warm[l].y, q.z[l] = warm[l].z;
        }
        detail::extractRotations4(A, q, 2);
        for (int l = 0; l < 4; ++l) {
            Quat one = warm[l];
            detail::extractRotation(m[l], one, 2);
            const Mat3 a = toMat3(one), b = toMat3(Quat{q.w[l], q.x[l], q.y[l], q.z[l]});
            for (int e = 0; e < 9; ++e)
                ASSERT_NEAR(a.m[e / 3][e % 3], b.m[e / 3][e % 3], 2e-4f) << trial << " lane " << l;
            EXPECT_NEAR(q.w[l] * q.w[l] + q.x[l] * q.x[l] + q.y[l] * q.y[l] + q.z[l] * q.z[l], 1.0f,
                        1e-5f);
        }
    }
}

TEST(ShapeMatching, FourBodiesAtOnceMatchOneAtATimeAndNeverMix) {
    const TriangleMesh mesh = blob();
    LatticeSettings ls;
    ls.targetCells = 60;
    const Lattice L = buildLattice(mesh, ls);
    const detail::ShapeMatchingModel model = detail::buildShapeMatching(L, 1);
    const size_t P = L.particleCount();
    const float dt = 1.0f / 120.0f;
    // Four differently deformed, moving bodies with different materials.
    std::vector<Vec3> x[4], v[4];
    std::vector<Quat> q[4];
    detail::ShapeMatchingLane lanes[4];
    for (int l = 0; l < 4; ++l) {
        const test::SmoothDeformation warp(4, 1.0f, 0.1f * float(l + 1));
        for (size_t i = 0; i < P; ++i) {
            x[l].push_back(warp(L.restParticles[i]) + Vec3{float(l), 2, 0});
            v[l].push_back(Vec3{0.3f * float(l), 0, 0} + cross({0, 1, 0}, L.restParticles[i]));
        }
        q[l].assign(P, Quat{});
        lanes[l].x = x[l];
        lanes[l].rotations = q[l];
        lanes[l].stiffness = 0.4f + 0.2f * float(l);
        lanes[l].damping = 0.05f * float(l);
        lanes[l].acceleration = {0, -9.81f, float(l)};
    }
    // All four at once.
    std::vector<Vec3> together[4];
    std::vector<Quat> qTogether[4];
    detail::ShapeMatchingScratch scratch;
    for (int l = 0; l < 4; ++l) {
        together[l] = v[l], qTogether[l] = q[l];
        lanes[l].v = together[l], lanes[l].rotations = qTogether[l];
    }
    detail::stepShapeMatching4(model, dt, 2, lanes, 4, scratch);
    for (int l = 0; l < 4; ++l) {
        // The same body alone (in lane 0) gives bit-identical velocities and rotations: lanes
        // never mix, so grouping bodies cannot change a simulation.
        std::vector<Vec3> alone = v[l];
        std::vector<Quat> qAlone = q[l];
        detail::ShapeMatchingLane one = lanes[l];
        one.v = alone, one.rotations = qAlone;
        detail::stepShapeMatching4(model, dt, 2, &one, 1, scratch);
        ASSERT_EQ(alone, together[l]) << "lane " << l;
        ASSERT_EQ(qAlone, qTogether[l]) << "lane " << l;
        // And the one-body path agrees to rounding.
        std::vector<Vec3> xs = x[l], vs = v[l];
        std::vector<Quat> qs = q[l];
        detail::ShapeMatchingStep step;
        step.dt = dt;
        step.stiffness = lanes[l].stiffness;
        step.damping = lanes[l].damping;
        step.acceleration = lanes[l].acceleration;
        step.integratePositions = false;
        detail::stepShapeMatching(model, step, xs, vs, qs, scratch);
        for (size_t i = 0; i < P; ++i)
            ASSERT_LE(length(vs[i] - together[l][i]), 1e-4f * (1 + length(vs[i])))
                << "lane " << l << " particle " << i;
    }
}

TEST(MassSpring, SpringsFollowTheLatticeEdgesAndDiagonals) {
    LatticeSettings ls;
    ls.cellSize = 1.0f;
    TriangleMesh bar;
    bar.positions = {
        {0.1f, 0.5f, 0.1f}, {2.9f, 0.5f, 0.1f}, {2.9f, 0.5f, 0.9f}, {0.1f, 0.5f, 0.9f}};
    bar.triangles = {{0, 1, 2}, {0, 2, 3}};
    const Lattice L = buildLattice(bar, ls); // 3 x 1 x 1 cells, 16 particles
    ASSERT_EQ(L.cellCount(), 3u);
    const detail::MassSpringModel m = detail::buildMassSpring(L);
    int counts[4] = {};
    for (const auto& s : m.springs) ++counts[int(s.kind)];
    // Edges: 4 lines of 3 along x, 8 along y, 8 along z. Faces: 16 distinct (4 across x, 6 + 6
    // along), 2 diagonals each. Body diagonals: 4 per cell. Bending: 4 lines of 4 points along
    // x give 2 pairs each (none across, only 2 points there).
    EXPECT_EQ(counts[int(detail::SpringKind::Structural)], 28);
    EXPECT_EQ(counts[int(detail::SpringKind::Shear)], 32);
    EXPECT_EQ(counts[int(detail::SpringKind::Diagonal)], 12);
    EXPECT_EQ(counts[int(detail::SpringKind::Bending)], 8);
}
