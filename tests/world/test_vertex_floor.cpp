// Contacts with the floor and the plane colliders at the meshes' vertices
// (WorldSettings::vertexFloorContacts): off by default; with it a body rests on its mesh, not on
// its cell boxes' corners, a ball rolls down a slope instead of sliding, a pile of letters lands
// without a vertex sinking into the floor, and the result is the same at any thread count.
#include "ffdaabb/generators.h"
#include "ffdaabb/world.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <span>
#include <string>
#include <vector>

using namespace ffd;
using ffd::test::ball;
using ffd::test::lowestVertex;
using ffd::test::sphereAt;

namespace {

WorldSettings atVertices(bool on = true) {
    WorldSettings s;
    s.vertexFloorContacts = on ? 1 : 0;
    s.sleepSpeed = 0; // watched awake
    return s;
}

} // namespace

TEST(VertexFloorContacts, IsOffByDefault) {
    EXPECT_EQ(WorldSettings{}.vertexFloorContacts, 0);
}

// A ball 1 m across (38 cells) turned eight ways at random, dropped 10 cm, after 2 s: its mesh
// touches the floor, its lowest vertex within a fifth of the contact skin below it (the slop a
// vertex off the four a box keeps may sink within a substep) and 2 mm above it.
TEST(VertexFloorContacts, ATurnedBallRestsOnItsMesh) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-0.5f, 0.5f);
    for (int k = 0; k < 8; ++k) {
        SCOPED_TRACE("rotation " + std::to_string(k));
        BodySettings s = sphereAt({0, 0.6f, 0});
        s.rotation = normalize(Quat{u(rng), u(rng), u(rng), u(rng)});
        World world(atVertices());
        const BodyId b = world.addBody(ball(), s);
        for (int f = 0; f < 120; ++f) world.step();
        const float cell = world.info(b).cellSize;
        EXPECT_GT(lowestVertex(world, b), -0.2f * WorldSettings{}.contactSkin * cell);
        EXPECT_LT(lowestVertex(world, b), 0.002f);
    }
}

// The ball of KnownBugs.ABallOnATiltedFloorRollsRatherThanSlides (at rest on the floor, then
// gravity tilted by 17 degrees; it slides on its boxes' corners, its spin times its radius a
// tenth of its speed after 1 s): on its vertices it rolls, the spin times the radius at least
// 0.6 of the speed after 1 s, and the speed above 1 m/s (a rigid ball: 2.1 m/s, rolling).
// The same on a plane collider tilted as much, with gravity straight down.
TEST(VertexFloorContacts, ABallRollsDownASlope) {
    for (const bool collider : {false, true}) {
        SCOPED_TRACE(collider ? "plane collider" : "floor");
        WorldSettings ws = atVertices();
        ws.floor = !collider;
        World world(ws);
        BodyId b;
        if (collider) { // a slope down towards +x from the start
            const Vec3 n = normalize(Vec3{3, 9.81f, 0});
            world.addPlane(n, 0);
            b = world.addBody(ball(), sphereAt(n * 0.5f));
        } else { // at rest first, then gravity tilted towards -x
            b = world.addBody(ball(), sphereAt({0, 0.6f, 0}));
            for (int f = 0; f < 120; ++f) world.step();
            WorldSettings tilted = world.settings();
            tilted.gravity = {-3, -9.81f, 0};
            world.setSettings(tilted);
        }
        for (int f = 0; f < 60; ++f) world.step();
        const Vec3 velocity = world.linearVelocity(b), spin = test::spinOf(world, b);
        const float speed = length(velocity), rolling = length(spin) * 0.5f;
        EXPECT_GT(speed, 1.0f);
        EXPECT_GT(rolling, 0.6f * speed) << "speed " << speed << " m/s";
        EXPECT_GT(collider ? velocity.x : -velocity.x, 0.9f * speed); // down the slope
    }
}

// Bodies landing on the floor and on a plane collider, on one thread and on three: the same
// particles, bit for bit.
TEST(VertexFloorContacts, TheSameAtAnyThreadCount) {
    std::vector<std::vector<Vec3>> results;
    for (const int threads : {1, 3}) {
        WorldSettings ws = atVertices();
        ws.threads = threads;
        World world(ws);
        world.addPlane(normalize(Vec3{0.3f, 1, 0}), -0.5f);
        std::mt19937 rng(5);
        std::uniform_real_distribution<float> u(-0.5f, 0.5f);
        for (int k = 0; k < 12; ++k) {
            BodySettings s = sphereAt({float(k % 4) * 1.2f - 2, 0.8f + float(k / 4) * 1.2f, 0});
            s.rotation = normalize(Quat{u(rng), u(rng), u(rng), u(rng)});
            world.addBody(k % 2 ? ball() : box({0.4f, 0.3f, 0.35f}), s);
        }
        for (int f = 0; f < 90; ++f) world.step();
        std::vector<Vec3> all;
        for (const BodyId id : world.bodies())
            for (const Vec3& x : world.particles(id)) all.push_back(x);
        results.push_back(all);
    }
    ASSERT_EQ(results[0].size(), results[1].size());
    for (size_t i = 0; i < results[0].size(); ++i) ASSERT_EQ(results[0][i], results[1][i]) << i;
}
