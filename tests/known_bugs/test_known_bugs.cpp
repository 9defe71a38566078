// Bugs found by the robustness work (issue 7) that are not fixed yet, as tests of the behaviour
// we want. CTest runs them with WILL_FAIL: each must fail today. When one passes, its bug is
// fixed: move the test to its area folder (tests/extreme, tests/collision) and delete the
// entry in docs/LIMITS.md. They run every time, so a fix is noticed at once.
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

// A ball 0.5 m across dropped into a square of four static pegs (as in tests/world
// Colliders.BallsPouredOnAFieldOfPegs...: 0.16 m thick, 0.6 m tall, 0.6 m apart), at seven
// points 1 cm apart. Wanted: every ball asleep after 10 s. Today some wedge between the pegs
// above the floor, where the mesh would pass (the pipeline collides cell boxes, which reach
// beyond the meshes; not yet traced further), and never stop: the centre keeps moving at
// 0.01-0.3 m/s, with or without the separation bound (switching it off at 5 s leaves the jitter
// as it is), so nothing puts them to sleep (docs/LIMITS.md, known problem 2).
TEST(KnownBugs, ABallWedgedAmongPegsComesToRest) {
    for (int k = 0; k <= 6; ++k) {
        SCOPED_TRACE("offset " + std::to_string(k) + " cm");
        World world;
        for (int i = 0; i < 2; ++i)
            for (int j = 0; j < 2; ++j)
                world.addBody(
                    box({0.08f, 0.3f, 0.08f}),
                    test::collider(BodyMotion::Static, {-0.6f * float(i), 0.3f, -0.6f * float(j)}));
        const BodyId dropped = world.addBody(
            test::smallBall(), test::sphereAt({-0.3f, 0.9f, -0.3f - 0.01f * float(k)}));
        for (int f = 0; f < 600; ++f) world.step();
        EXPECT_FALSE(world.isAwake(dropped)) << "centre at " << world.centreOfMass(dropped).y;
    }
}

// A ball 1 m across (the spheres scene's, restitution 0) dropped 1.2 m onto the floor, turned
// eight ways at random, lands at 4.3-4.5 m/s (its centre's fall over a frame). Wanted: it
// rebounds at about a tenth of that at most, 0.5 m/s (its centre's rise over a frame, after the
// landing). Today it leaves the floor at 0.55-1.26 m/s (0.56-2.0 with the separation bound at
// 1 m/s, before 2026-11-29). Traced on one rotation (1.9 m/s, bound 1 m/s): over the landing's
// 13 substeps the rigid impact phase gives it 7.3 m/s upward where 4.7 stop it, because shape
// matching pulls the dented bottom back down at about 3 m/s while the body already rises, and
// the phase reads that as an approach; the same phase turns the ball (up to 7 rad/s) by
// stopping its lattice's lowest box corners, and without that turn it leaves at the separation
// bound exactly (docs/LIMITS.md, known problem 3). The first failure ends it.
TEST(KnownBugs, ABallDroppedWithRestitutionZeroDoesNotBounce) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(-0.5f, 0.5f);
    for (int k = 0; k < 8; ++k) {
        SCOPED_TRACE("rotation " + std::to_string(k));
        World world;
        BodySettings s = test::sphereAt({0, 0.55f + 1.2f, 0});
        s.rotation = normalize(Quat{u(rng), u(rng), u(rng), u(rng)});
        const BodyId b = world.addBody(test::ball(), s);
        float previous = world.centreOfMass(b).y, fastestFall = 0, fastestRise = 0;
        for (int f = 0; f < 150; ++f) {
            world.step();
            const float y = world.centreOfMass(b).y, speed = (y - previous) * 60.0f;
            previous = y;
            fastestFall = std::min(fastestFall, speed);
            if (fastestFall < -3.0f) fastestRise = std::max(fastestRise, speed);
        }
        ASSERT_LT(fastestFall, -4.0f); // it landed as meant
        ASSERT_LT(fastestRise, 0.5f);
    }
}

// Four balls poured into a static bowl, as in tests/world
// Colliders.BallsPouredIntoAStaticBowlNoneInsideNoneThrough, in forty piles (each ball i moved
// 1.3 * k * i mm for pile k). Wanted: after 5 s every ball rests in the bowl (its centre over
// the bowl's inside, above its inner bottom and below its rim, and slower than 0.1 m/s). Today
// (2026-11-28) in 9 of the 40 piles a ball still rolls at 0.10-0.27 m/s after 5 s; none is
// thrown out (docs/LIMITS.md, known problem 2). The first failure ends it.
TEST(KnownBugs, BallsPouredIntoABowlComeToRestInIt) {
    for (int k = 0; k < 40; ++k) {
        SCOPED_TRACE("pile " + std::to_string(k));
        World world;
        const std::vector<BodyId> balls = test::pourBallsIntoABowl(world, 0.0013f * float(k));
        for (int f = 0; f < 300; ++f) world.step();
        for (const BodyId b : balls) {
            const Vec3 c = world.centreOfMass(b);
            ASSERT_LT(std::hypot(c.x, c.z), 1.0f); // in the bowl
            ASSERT_GT(c.y, 0.05f + 0.25f - 0.02f); // above its inner bottom
            ASSERT_LT(c.y, 1.25f);                 // below its rim
            ASSERT_LT(length(world.linearVelocity(b)), 0.1f);
        }
    }
}

// A ball 1 m across (38 cells, friction 0.5) resting on the floor, then gravity tilted by 17
// degrees. Wanted: after 1 s it rolls, as a ball with that friction does (it needs 0.09): the
// slip of its lowest point, its centre's velocity plus its spin times its radius (the spin by
// least squares over its particles), at most a fifth of its centre's speed, and that speed
// above 0.5 m/s (a rigid ball rolls at 2 m/s by then). Today it slides without turning: 0.62
// m/s at 1 s, its spin times its radius 0.05 m/s (2026-11-29). Its contacts stand on the corners of
// its lowest cell's box, a flat patch that a turn presses into the floor, and it creeps down like
// the box below (docs/LIMITS.md, known problem 8; docs/ALGORITHM.md section 5, "One friction
// point per body pair").
TEST(KnownBugs, ABallOnATiltedFloorRollsRatherThanSlides) {
    WorldSettings ws;
    ws.sleepSpeed = 0;
    World world(ws);
    const BodyId b = world.addBody(test::ball(), test::sphereAt({0, 0.8f, 0}));
    for (int f = 0; f < 120; ++f) world.step(); // at rest on the floor
    WorldSettings tilted = world.settings();
    tilted.gravity = {-3, -9.81f, 0};
    world.setSettings(tilted);
    for (int f = 0; f < 60; ++f) world.step();
    // The particles' mean velocity and their spin about their centre (least squares).
    const Vec3 p = world.linearVelocity(b), spin = test::spinOf(world, b);
    const float radius = 0.5f;
    const float slip = std::fabs(p.x + spin.z * radius); // the lowest point's velocity along x
    EXPECT_GT(-p.x, 0.5f);
    EXPECT_LT(slip, 0.2f * std::fabs(p.x))
        << "speed " << p.x << " m/s, spin times radius " << spin.z * radius << " m/s";
}

// A 0.3 m box (27 cells, friction 0.8) resting on the floor with gravity tilted by 10 and by 20
// degrees, far below its friction angle (atan 0.8 = 38.7 degrees), sleeping off. Wanted: it
// stays where it settled, its centre moving less than 4 mm over 2-6 s (1 mm/s). Today it creeps
// down at a steady 0.069 and 0.14 m/s: friction acts only at the contact particles, after the
// move, and shape matching spreads the slip back over the body (docs/LIMITS.md, known problem
// 8). The first failure ends it.
TEST(KnownBugs, ABoxOnASlopeBelowItsFrictionAngleStays) {
    for (const float degrees : {10.0f, 20.0f}) {
        SCOPED_TRACE(std::to_string(degrees) + " degrees");
        const float angle = degrees * 3.14159265f / 180.0f;
        WorldSettings ws;
        ws.gravity = {9.81f * std::sin(angle), -9.81f * std::cos(angle), 0};
        ws.sleepSpeed = 0;
        World world(ws);
        BodySettings s;
        s.friction = 0.8f;
        s.lattice.targetCells = 27;
        s.position = {0, 0.16f, 0};
        const BodyId crate = world.addBody(box({0.15f, 0.15f, 0.15f}), s);
        for (int f = 0; f < 120; ++f) world.step();
        const float start = world.centreOfMass(crate).x;
        for (int f = 0; f < 240; ++f) world.step();
        ASSERT_LT(std::fabs(world.centreOfMass(crate).x - start), 0.004f);
    }
}

// A ball 1 m across (38 cells) dropped onto four static balls that stand touching in a square
// on the floor. Wanted: after 5 s it rests on their meshes, its centre still (slower than 5 cm/s)
// and at most 3 cm further from each of theirs than the 1 m at which the meshes touch (the
// meshes' flat faces lie at most 0.9 cm inside the 0.5 m radius). Today it rests 18-19 cm above
// them, its centre 1.457 m high where touching is 1.207 m: the contacts hold the cell boxes
// apart, and the boxes of a curved surface stand off it by up to 28.5 cm along the lattice's
// diagonals, the directions the four contacts here lie along (docs/LIMITS.md, known problem 9).
TEST(KnownBugs, ABallOnFourBallsRestsOnTheirMeshes) {
    World world;
    std::vector<BodyId> below;
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j)
            below.push_back(world.addBody(
                test::ball(),
                test::collider(BodyMotion::Static, {float(i) - 0.5f, 0.5f, float(j) - 0.5f}, 38)));
    const BodyId top = world.addBody(test::ball(), test::sphereAt({0, 1.5f, 0}));
    for (int f = 0; f < 300; ++f) world.step();
    EXPECT_LT(length(world.linearVelocity(top)), 0.05f);
    for (const BodyId b : below)
        EXPECT_LT(length(world.centreOfMass(top) - world.centreOfMass(b)) - 1.0f, 0.03f)
            << "top centre at " << world.centreOfMass(top).y << " m";
}

// The stacked box of RigidProjection.ABoxOnADynamicBoxRests, without the projection (the
// default), at solver iteration counts around the default 4. Wanted: at rest at every count, as
// at 4 (0.012 m/s). Today it buzzes at 0.05-0.10 m/s at 2, 3, 5, 6 and 8 (2026-12-07): the
// resting contacts' projection and shape matching fight (docs/LIMITS.md, known problem 5), and
// the default count passes by where that fight happens to settle. With the opt-in projection on
// the rigid modes (world.rigid_projection 1) the stack rests at every one of these counts.
TEST(KnownBugs, AStackedBoxRestsAtEverySolverIterationCount) {
    for (const int iterations : {2, 3, 4, 5, 6, 8}) {
        WorldSettings settings;
        settings.solverIterations = iterations;
        EXPECT_LT(ffd::test::stackBuzz(settings), 0.03) << iterations << " iterations";
    }
}
