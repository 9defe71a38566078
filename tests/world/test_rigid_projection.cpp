// Contacts projected on the bodies' rigid modes (WorldSettings::rigidProjection): what it is
// for (a stacked body rests, a carried body keeps up), that it is off by default, that the
// impulses it applies are reported, and that it gives the same result at any thread count.
#include "ffdaabb/generators.h"
#include "ffdaabb/queries.h"
#include "ffdaabb/world.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <span>
#include <vector>

using namespace ffd;
using ffd::test::ball;
using ffd::test::deepestInside;

namespace {

WorldSettings withProjection(float share) {
    WorldSettings s;
    s.rigidProjection = share;
    s.sleepSpeed = 0; // watched awake
    return s;
}

// The test stack (test_support.h) with the projection's share.
double stackBuzz(float share) {
    return ffd::test::stackBuzz(withProjection(share));
}

} // namespace

TEST(RigidProjection, IsOffByDefault) {
    EXPECT_EQ(WorldSettings{}.rigidProjection, 0.0f);
}

// The load of a body resting on a dynamic body reaches the lower body's whole lattice in the
// substep it arrives: the upper box rests. With the particles alone it buzzed at 0.11 m/s
// while the separation bound was 1 m/s (the rigid phase turning the dents the load makes into
// rigid separation; docs/LIMITS.md, known problem 5); with the bound at 0.25 m/s, the default
// since 2026-11-29, it rests nearly as well without the projection. Measured: 0.006 m/s with
// the projection, 0.012 without, at the default 4 solver iterations. At other counts from 2 to 8
// it rests as well with the projection (0.001-0.010 m/s) but buzzes without it at 0.05-0.10 m/s
// (KnownBugs.AStackedBoxRestsAtEverySolverIterationCount).
TEST(RigidProjection, ABoxOnADynamicBoxRests) {
    EXPECT_LT(stackBuzz(1.0f), 0.02);
    EXPECT_LT(stackBuzz(0.0f), 0.03);
}

// A crate on a kinematic platform that sets off at 0.5 m/s: static friction at the rigid level
// carries the crate as a rigid one would be (it slips for about v / (mu g) = 64 ms, 1.6 cm).
// Measured: carried 0.980 of the platform's 1 m with the projection, 0.933 without.
TEST(RigidProjection, AKinematicPlatformCarriesACrateAsARigidOne) {
    World world(withProjection(1.0f));
    BodySettings p;
    p.motion = BodyMotion::Kinematic;
    p.position = {0, 0.5f, 0};
    p.lattice.targetCells = 64;
    const BodyId platform = world.addBody(box({1.5f, 0.1f, 1.0f}), p);
    BodySettings s;
    s.position = {0, 0.85f, 0};
    s.friction = 0.8f;
    const BodyId crate = world.addBody(box({0.25f, 0.25f, 0.25f}), s);
    for (int f = 0; f < 60; ++f) world.step();
    const Vec3 rested = world.centreOfMass(crate);
    const float T = world.settings().frameStep;
    for (int f = 1; f <= 120; ++f) {
        world.setKinematicTarget(platform, p.position + Vec3{0.5f * T * float(f), 0, 0});
        world.step();
    }
    const Vec3 carried = world.centreOfMass(crate) - rested;
    EXPECT_NEAR(carried.x, 1.0f, 0.04f);
    EXPECT_NEAR(carried.y, 0.0f, 0.02f);
    EXPECT_LT(deepestInside(world), 0.01);
}

// The impulses the projection applies are part of what the contacts report: a box resting on
// the floor is held up by its weight times the frame step.
TEST(RigidProjection, TheFloorStillReportsTheWeight) {
    World world(withProjection(1.0f));
    BodySettings s;
    s.position = {0, 0.25f, 0};
    s.lattice.targetCells = 27;
    const BodyId body = world.addBody(box({0.25f, 0.25f, 0.25f}), s);
    for (int f = 0; f < 120; ++f) world.step();
    const WorldSettings& w = world.settings();
    const double weight = world.info(body).mass * -w.gravity.y * w.frameStep;
    double sum = 0;
    for (int f = 0; f < 60; ++f) {
        world.step();
        std::vector<BodyContact> partners;
        touchingBodies(world, body, partners);
        ASSERT_EQ(partners.size(), 1u);
        sum += partners[0].impulse.y;
    }
    EXPECT_NEAR(sum / 60 / weight, 1.0, 0.01);
}

// Balls poured in a heap: the same state at one and at three threads.
TEST(RigidProjection, TheSameAtAnyThreadCount) {
    auto run = [](int threads) {
        WorldSettings s = withProjection(1.0f);
        s.threads = threads;
        World world(s);
        for (int i = 0; i < 40; ++i) {
            BodySettings b;
            b.lattice.targetCells = 38;
            b.position = {0.45f * float(i % 4), 0.6f + 0.9f * float(i / 4), 0.4f * float(i % 3)};
            world.addBody(ball(), b);
        }
        for (int f = 0; f < 120; ++f) world.step();
        return world.stateHash();
    };
    EXPECT_EQ(run(1), run(3));
}
