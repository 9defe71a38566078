// Colliders (BodyMotion, World::setKinematicTarget, World::addPlane): static and kinematic
// bodies collide through the same pipeline as bodies of infinite mass, never move under
// contacts, and hold what rests on them without sinking; planes of any orientation hold like the
// floor.
#include "ffdaabb/error.h"
#include "ffdaabb/generators.h"
#include "ffdaabb/world.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

using namespace ffd;
using ffd::test::ball;
using ffd::test::collider;
using ffd::test::deepestInside;
using ffd::test::lowestVertex;
using ffd::test::smallBall;
using ffd::test::sphereAt;

namespace {

std::vector<Vec3> particlesOf(const World& world, BodyId b) {
    return {world.particles(b).begin(), world.particles(b).end()};
}

} // namespace

TEST(Colliders, AStaticBoxHoldsABallAndNeverMoves) {
    World world;
    const BodyId slab =
        world.addBody(box({1.0f, 0.25f, 1.0f}), collider(BodyMotion::Static, {0, 0.5f, 0}));
    const std::vector<Vec3> before = particlesOf(world, slab);
    const BodyId b = world.addBody(ball(), sphereAt({0.1f, 2.0f, 0}));
    double deepest = 0;
    for (int f = 0; f < 180; ++f) {
        world.step();
        deepest = std::max(deepest, deepestInside(world));
    }
    EXPECT_EQ(particlesOf(world, slab), before); // bit-identical: contacts never move it
    // At rest on the slab's top (y = 0.75): the ball's bottom there, not sunk in.
    EXPECT_NEAR(lowestVertex(world, b), 0.75f, 0.03f);
    EXPECT_LT(deepest, 0.01); // 1 % of the ball's size, over the whole fall
    EXPECT_LT(length(world.linearVelocity(b)), 0.05f);
    for (const Vec3& v : world.velocities(slab)) EXPECT_EQ(v, Vec3{});
}

TEST(Colliders, ABallOnAStaticBoxFallsAsleepAndTheBoxNeitherSleepsNorWakesIt) {
    World world;
    world.addBody(box({1.0f, 0.25f, 1.0f}), collider(BodyMotion::Static, {0, 0.5f, 0}));
    const BodyId b = world.addBody(ball(), sphereAt({0, 1.3f, 0}));
    int frames = 0;
    while (world.awakeCount() > 0 && frames < 300) world.step(), ++frames;
    EXPECT_LT(frames, 300);
    EXPECT_FALSE(world.isAwake(b));
    const uint64_t hash = world.stateHash();
    for (int f = 0; f < 30; ++f) world.step();
    EXPECT_FALSE(world.isAwake(b));
    EXPECT_EQ(world.stateHash(), hash);
}

TEST(Colliders, AKinematicPlatformCarriesABoxByFriction) {
    World world;
    const Vec3 start{0, 0.5f, 0};
    const BodyId platform =
        world.addBody(box({1.5f, 0.1f, 1.0f}), collider(BodyMotion::Kinematic, start));
    BodySettings s;
    s.position = {0, 0.85f, 0};
    s.friction = 0.8f;
    const BodyId crate = world.addBody(box({0.25f, 0.25f, 0.25f}), s);
    for (int f = 0; f < 60; ++f) world.step(); // settles on the platform
    const Vec3 rested = world.centreOfMass(crate);
    const float from = world.centreOfMass(platform).x;
    const float speed = 0.5f; // m/s along x, for 2 s
    const float T = world.settings().frameStep;
    for (int f = 1; f <= 120; ++f) {
        world.setKinematicTarget(platform, start + Vec3{speed * T * float(f), 0, 0});
        world.step();
    }
    const float travelled = world.centreOfMass(platform).x - from;
    EXPECT_NEAR(travelled, 1.0f, 1e-3f); // the platform went where it was sent
    const Vec3 carried = world.centreOfMass(crate) - rested;
    EXPECT_NEAR(carried.x, travelled, 0.1f * travelled); // carried along, within 10 %
    EXPECT_NEAR(carried.y, 0.0f, 0.02f);                 // still on top
    EXPECT_LT(deepestInside(world), 0.01);
    // After the last step the platform rests: its velocities are 0 again.
    for (const Vec3& v : world.velocities(platform)) EXPECT_EQ(v, Vec3{});
}

TEST(Colliders, AKinematicPaddlePushesABallAndIsNotPushedBack) {
    WorldSettings ws;
    ws.sleepSpeed = 0;
    World world(ws);
    const Vec3 start{-1.0f, 0.45f, 0};
    const BodyId paddle =
        world.addBody(box({0.1f, 0.4f, 0.6f}), collider(BodyMotion::Kinematic, start, 48));
    const BodyId b = world.addBody(ball(), sphereAt({0, 0.5f, 0}));
    const float speed = 1.0f, T = world.settings().frameStep;
    std::vector<Vec3> targets;
    for (int f = 1; f <= 90; ++f) {
        const Vec3 at = start + Vec3{speed * T * float(f), 0, 0};
        world.setKinematicTarget(paddle, at);
        world.step();
        // The paddle is where it was sent, contacts or not (within rounding of the substeps).
        EXPECT_NEAR(world.centreOfMass(paddle).x, at.x, 1e-4f) << "frame " << f;
    }
    // The paddle's front (x = 0.6 after 1.5 s) pushed the ball ahead of it at about its speed:
    // the ball's centre a radius ahead of the front, less 5 cm. (The bound had 0.1 more; it held
    // while each body's centre of mass lay off its centre towards +x, at its lattice's centre.)
    EXPECT_GT(world.centreOfMass(b).x, 0.6f + 0.45f);
    EXPECT_GT(world.linearVelocity(b).x, 0.8f * speed);
    EXPECT_LT(deepestInside(world), 0.01);
}

TEST(Colliders, ATiltedPlaneLetsABallRollDownAndNothingPassesThrough) {
    WorldSettings ws;
    ws.floor = false;
    World world(ws);
    const float angle = 0.35f; // about 20 degrees, falling towards +x
    const Vec3 n{std::sin(angle), std::cos(angle), 0};
    const PlaneId plane = world.addPlane(n * 2.0f, 0.0f); // normalised by addPlane
    ASSERT_TRUE(world.isValid(plane));
    ASSERT_EQ(world.planes().size(), 1u);
    EXPECT_NEAR(length(world.planes()[0].normal), 1.0f, 1e-6f);
    const BodyId b = world.addBody(ball(), sphereAt(n * 0.7f));
    float deepest = 0;
    for (int f = 0; f < 120; ++f) {
        world.step();
        for (const Vec3& v : world.vertices(b)) deepest = std::max(deepest, -dot(n, v));
    }
    EXPECT_LT(deepest, 0.01f);                      // nothing through the plane (1 % of 1 m)
    EXPECT_GT(world.centreOfMass(b).x, 1.0f);       // went down the slope (towards +x): it
                                                    // slides more than it rolls (LIMITS, 8)
    EXPECT_LT(world.centreOfMass(b).y, -0.3f);      // and down
    EXPECT_LT(dot(n, world.centreOfMass(b)), 1.0f); // along the plane, not thrown off it
    EXPECT_TRUE(world.removePlane(plane));
    EXPECT_FALSE(world.isValid(plane));
    EXPECT_FALSE(world.removePlane(plane));
    for (int f = 0; f < 30; ++f) world.step();
    EXPECT_LT(world.centreOfMass(b).y, -1.0f); // without it the ball falls
}

// Four balls poured into a static bowl, in eight piles (each ball i moved 1.3 * k * i mm for
// pile k): the bowl never moves, no ball's mesh is inside another's or the bowl's, no ball
// passes through the bowl (a ball over its inside is above its inner bottom), and after 5 s
// every ball is in the bowl (none thrown out over the rim: none in 40 such piles with the
// separation bound at 1 m/s; at 2 m/s, before side points, 9 of the 40 threw a ball out). That
// every ball comes to rest in the bowl is
// KnownBugs.BallsPouredIntoABowlComeToRestInIt.
TEST(Colliders, BallsPouredIntoAStaticBowlNoneInsideNoneThrough) {
    for (int k = 0; k < 8; ++k) {
        SCOPED_TRACE("pile " + std::to_string(k));
        World world;
        const std::vector<BodyId> balls = test::pourBallsIntoABowl(world, 0.0013f * float(k));
        const BodyId bowlBody = world.bodies().front();
        const std::vector<Vec3> before = particlesOf(world, bowlBody);
        double deepest = 0;
        for (int f = 0; f < 300; ++f) {
            world.step();
            if (f % 10 == 9) deepest = std::max(deepest, deepestInside(world, 0.5f));
            for (const BodyId b : balls) {
                const Vec3 c = world.centreOfMass(b);
                if (std::hypot(c.x, c.z) < 1.0f) {
                    ASSERT_GT(c.y, 0.05f + 0.25f - 0.02f) << "frame " << f; // not through it
                }
            }
        }
        EXPECT_EQ(particlesOf(world, bowlBody), before);
        EXPECT_LT(deepest, 0.01 * 0.5); // below 1 % of a ball's size
        for (const BodyId b : balls) {
            const Vec3 c = world.centreOfMass(b);
            EXPECT_LT(std::hypot(c.x, c.z), 1.0f); // in the bowl
            EXPECT_LT(c.y, 1.25f);                 // below its rim
        }
    }
}

TEST(Colliders, BallsOnStaticStairsRestOnTheStepsNoneInside) {
    World world;
    std::vector<BodyId> steps;
    for (int k = 0; k < 3; ++k) {
        const float h = 0.25f * float(k + 1); // step k: top at h, its run 0.6 m along x
        steps.push_back(
            world.addBody(box({0.3f, 0.5f * h, 1.0f}),
                          collider(BodyMotion::Static, {0.6f * float(k), 0.5f * h, 0})));
    }
    std::vector<BodyId> balls;
    for (int i = 0; i < 3; ++i)
        balls.push_back(world.addBody(smallBall(), sphereAt({0.6f * float(i), 1.5f, 0.3f})));
    double deepest = 0;
    for (int f = 0; f < 240; ++f) {
        world.step();
        if (f % 10 == 9) deepest = std::max(deepest, deepestInside(world, 0.5f));
    }
    EXPECT_LT(deepest, 0.01 * 0.5);
    for (const BodyId s : steps)
        for (const Vec3& v : world.velocities(s)) EXPECT_EQ(v, Vec3{});
    // Each ball rests on the top of a step (0.25, 0.5 or 0.75) or on the floor, its bottom there.
    for (const BodyId b : balls) {
        const float bottom = lowestVertex(world, b);
        float nearest = std::abs(bottom);
        for (int k = 0; k < 3; ++k)
            nearest = std::min(nearest, std::abs(bottom - 0.25f * float(k + 1)));
        EXPECT_LT(nearest, 0.02f) << "bottom at " << bottom;
        EXPECT_LT(length(world.linearVelocity(b)), 0.1f);
    }
}

TEST(Colliders, AMovingPlatformWakesWhatSleepsOnIt) {
    World world;
    const Vec3 start{0, 0.5f, 0};
    const BodyId platform =
        world.addBody(box({1.5f, 0.1f, 1.0f}), collider(BodyMotion::Kinematic, start));
    const BodyId b = world.addBody(ball(), sphereAt({0, 1.12f, 0}));
    int frames = 0;
    while (world.isAwake(b) && frames < 300) world.step(), ++frames;
    ASSERT_LT(frames, 300); // a still kinematic body lets it sleep
    world.setKinematicTarget(platform, start + Vec3{0, 0.01f, 0});
    world.step();
    EXPECT_TRUE(world.isAwake(b));
}

TEST(Colliders, StepsAlikeAtOneAndTwoThreads) {
    uint64_t hashes[2];
    for (int threads : {1, 2}) {
        WorldSettings ws;
        ws.threads = threads;
        World world(ws);
        for (int k = 0; k < 2; ++k)
            world.addBody(
                box({0.3f, 0.125f * float(k + 1), 1.0f}),
                collider(BodyMotion::Static, {0.6f * float(k), 0.125f * float(k + 1), 0}));
        const BodyId platform = world.addBody(box({0.5f, 0.1f, 0.5f}),
                                              collider(BodyMotion::Kinematic, {-1.5f, 0.3f, 0}));
        world.addPlane({0.2f, 1.0f, 0}, -0.1f);
        for (int i = 0; i < 4; ++i)
            world.addBody(smallBall(),
                          sphereAt({-1.5f + 0.6f * float(i), 1.0f + 0.3f * float(i), 0}));
        for (int f = 1; f <= 90; ++f) {
            world.setKinematicTarget(platform, {-1.5f + 0.01f * float(f), 0.3f, 0},
                                     Quat{} /* no turn */);
            world.step();
        }
        hashes[threads - 1] = world.stateHash();
    }
    EXPECT_EQ(hashes[0], hashes[1]);
}

TEST(Colliders, NamedErrorsAndCollidersIgnoreForces) {
    World world;
    const BodyId dynamic = world.addBody(ball(), sphereAt({3, 1, 0}));
    const BodyId wall =
        world.addBody(box({0.5f, 0.5f, 0.5f}), collider(BodyMotion::Static, {0, 0.5f, 0}));
    EXPECT_THROW(world.setKinematicTarget(dynamic, {0, 1, 0}), InputError);
    EXPECT_THROW(world.setKinematicTarget(wall, {0, 1, 0}), InputError);
    EXPECT_THROW(world.addPlane({0, 0, 0}, 0), InputError);
    EXPECT_THROW(world.addPlane({0, 1, 0}, NAN), InputError);
    BodyMotion m;
    EXPECT_TRUE(parseBodyMotion("kinematic", m));
    EXPECT_EQ(m, BodyMotion::Kinematic);
    EXPECT_FALSE(parseBodyMotion("frozen", m));
    const std::vector<Vec3> before = particlesOf(world, wall);
    world.applyImpulse(wall, {100, 0, 0});
    world.applyForce(wall, {100, 0, 0});
    world.setVelocity(wall, {1, 0, 0});
    for (int f = 0; f < 10; ++f) world.step();
    EXPECT_EQ(particlesOf(world, wall), before);
    EXPECT_TRUE(world.isAwake(wall)); // colliders never sleep
}

TEST(Colliders, BallsPouredOnAFieldOfPegsSettleNoneInsideNoneThrough) {
    World world;
    std::vector<BodyId> pegs;
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
            pegs.push_back(world.addBody(
                box({0.08f, 0.3f, 0.08f}),
                collider(BodyMotion::Static, {0.6f * float(i - 1), 0.3f, 0.6f * float(k - 1)})));
    std::vector<std::vector<Vec3>> before;
    for (const BodyId p : pegs) before.push_back(particlesOf(world, p));
    std::vector<BodyId> balls;
    for (int i = 0; i < 6; ++i)
        balls.push_back(world.addBody(smallBall(),
                                      sphereAt({0.25f * float(i % 3) - 0.3f, 1.2f + 0.4f * float(i),
                                                0.2f * float(i % 2) - 0.1f})));
    double deepest = 0;
    for (int f = 0; f < 300; ++f) {
        world.step();
        if (f % 10 == 9) deepest = std::max(deepest, deepestInside(world, 0.5f));
    }
    EXPECT_LT(deepest, 0.01 * 0.5);
    for (size_t p = 0; p < pegs.size(); ++p) EXPECT_EQ(particlesOf(world, pegs[p]), before[p]);
    // Each is down among the pegs or on them, none thrown or still falling (one may still roll
    // on the floor between them, and one wedged between pegs above the floor may jitter at up to
    // 0.3 m/s: tests/known_bugs ABallWedgedAmongPegsComesToRest).
    for (const BodyId b : balls) {
        EXPECT_GT(lowestVertex(world, b), -0.005f);
        EXPECT_LT(length(world.linearVelocity(b)), 0.5f);
        EXPECT_LT(world.centreOfMass(b).y, 0.6f + 0.3f);
    }
}

TEST(Colliders, ASnapshotWithCollidersRestoresAndStepsAlike) {
    World world;
    world.addBody(box({1.0f, 0.25f, 1.0f}), collider(BodyMotion::Static, {-1.5f, 0.25f, 0}));
    const BodyId platform =
        world.addBody(box({0.6f, 0.1f, 0.6f}), collider(BodyMotion::Kinematic, {1.0f, 0.2f, 0}));
    world.addBody(ball(), sphereAt({-1.5f, 1.5f, 0}));
    world.addBody(ball(), sphereAt({1.0f, 1.2f, 0}));
    auto drive = [&](int frame) {
        world.setKinematicTarget(platform, {1.0f + 0.5f * std::sin(0.05f * float(frame)), 0.2f, 0},
                                 Quat::fromAxisAngle({0, 1, 0}, 0.01f * float(frame)));
        world.step();
    };
    for (int f = 1; f <= 40; ++f) drive(f);
    const std::vector<uint8_t> saved = world.saveState();
    for (int f = 41; f <= 80; ++f) drive(f);
    const uint64_t hash = world.stateHash();
    world.restoreState(saved);
    for (int f = 41; f <= 80; ++f) drive(f);
    EXPECT_EQ(world.stateHash(), hash);
}
