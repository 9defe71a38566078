// Overlap recovery (collision/overlap_recovery.h): which pairs are remembered, when they are
// forgotten, that the whole-body push moves no velocity into the bodies, that every mode agrees
// and that removing a body keeps the remembered pairs right. The extreme scenes
// (tests/extreme) check the outcomes on 200 bodies.
#include "ffdaabb/error.h"
#include "ffdaabb/world.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

using namespace ffd;
using ffd::test::ball;
using ffd::test::deepestInside;
using ffd::test::fastestBody;
using ffd::test::sphereAt;

// Two spheres created apart and thrown at each other (8 m/s each) meet in motion: the recovery
// never remembers them, and the run is bit-identical to one with the recovery off.
TEST(OverlapRecovery, BodiesThatMeetInMotionAreNotRemembered) {
    auto run = [](float recovery) {
        WorldSettings ws;
        ws.gravity = {};
        ws.overlapRecoverySpeed = recovery;
        World world(ws);
        world.addBody(ball(), sphereAt({-1.5f, 2, 0}, {8, 0, 0}));
        world.addBody(ball(), sphereAt({1.5f, 2, 0}, {-8, 0, 0}));
        int remembered = 0, contacts = 0;
        for (int f = 0; f < 60; ++f) {
            world.step();
            remembered = std::max(remembered, world.profile().overlapPairs);
            contacts = std::max(contacts, world.profile().contacts);
        }
        EXPECT_EQ(remembered, 0);
        EXPECT_GT(contacts, 0); // they did collide
        return world.stateHash();
    };
    EXPECT_EQ(run(2), run(0));
}

// A sphere teleported (World::translate) onto the centre of one resting on the floor is pushed
// out of it as a whole, gently, and the pair is forgotten once apart.
// Criteria: the pair is pushed apart whole in the first frame; no sphere ever faster than 4 m/s
// (measured 1.1; 14 m/s with the recovery off); after 3 s the pair is forgotten and no contact
// is violated by 5 mm or more.
TEST(OverlapRecovery, TranslatedIntoAnotherBodyIsPushedOutGently) {
    World world;
    world.addBody(ball(), sphereAt({0, 0.55f, 0}));
    const BodyId moved = world.addBody(ball(), sphereAt({3, 0.55f, 0}));
    for (int f = 0; f < 60; ++f) world.step();
    world.translate(moved, world.centreOfMass(world.bodies()[0]) - world.centreOfMass(moved) +
                               Vec3{0.01f, 0.02f, 0});
    world.step();
    EXPECT_EQ(world.profile().wholePairs, 1);
    float fastest = 0;
    for (int f = 0; f < 180; ++f) {
        world.step();
        fastest = std::max(fastest, fastestBody(world));
    }
    EXPECT_LT(fastest, 4.0f);
    EXPECT_EQ(world.profile().overlapPairs, 0);
    EXPECT_LT(deepestInside(world), 0.005); // no vertex 5 mm inside the other mesh
}

// Spheres created at one spot with the default settings: `brute`, `previous` and `enhanced`
// leave the same pairs out of the node contacts and give bit-identical states, while the pairs
// are whole and after they have become node contacts.
// Bodies placed overlapping in free space come apart and stop (docs/LIMITS.md had it as known
// problem 6): two spheres created 15 cm into each other, gravity and floor off, three
// rotations. Moved apart by their contacts' particles, the overlap became a dent that shape
// matching restored with velocity, and they drifted apart for ever (spheres twice the size,
// 30 cm in: 1.51 m/s each); now they are moved as rigid wholes. Criteria: after 1 s they are
// apart (centres at least 0.99 m) and neither moves faster than 2 cm/s, and the pair is
// forgotten.
TEST(OverlapRecovery, BodiesPlacedOverlappingComeApartAndStop) {
    for (int turn = 0; turn < 3; ++turn) {
        WorldSettings ws;
        ws.gravity = {};
        ws.floor = false;
        World world(ws);
        BodySettings a = sphereAt({0, 0, 0}), b = sphereAt({0.85f, 0, 0});
        b.rotation = normalize(Quat{0.3f * float(turn), 0.2f, -0.1f * float(turn), 1});
        const BodyId first = world.addBody(ball(), a);
        const BodyId second = world.addBody(ball(), b);
        for (int f = 0; f < 60; ++f) world.step();
        EXPECT_GT(length(world.centreOfMass(first) - world.centreOfMass(second)), 0.99f)
            << "turn " << turn;
        EXPECT_LT(fastestBody(world), 0.02f) << "turn " << turn;
        EXPECT_EQ(world.profile().overlapPairs, 0) << "turn " << turn;
    }
}

TEST(OverlapRecovery, ModesAgree) {
    auto run = [](CollisionMode mode) {
        WorldSettings ws;
        ws.mode = mode;
        World world(ws);
        std::mt19937 rng(5);
        std::uniform_real_distribution<float> u(-0.5f, 0.5f);
        for (int i = 0; i < 6; ++i) {
            BodySettings s = sphereAt({0.1f * float(i % 2), 0.6f, 0});
            s.rotation = normalize(Quat{u(rng), u(rng), u(rng), u(rng)});
            world.addBody(ball(), s);
        }
        int whole = 0, contacts = 0;
        for (int f = 0; f < 90; ++f) {
            world.step();
            whole = std::max(whole, world.profile().wholePairs);
            contacts = std::max(contacts, world.profile().contacts);
        }
        EXPECT_GT(whole, 0);
        EXPECT_GT(contacts, 0);
        return world.stateHash();
    };
    const uint64_t enhanced = run(CollisionMode::Enhanced);
    EXPECT_EQ(run(CollisionMode::Previous), enhanced);
    EXPECT_EQ(run(CollisionMode::Brute), enhanced);
}

// Removing a body while pairs are remembered: its pairs go, the others keep naming the right
// bodies (dense indices shift down). Three coincident spheres, the middle one removed after a
// frame: the first and last stay remembered and whole, then separate and are forgotten.
TEST(OverlapRecovery, RemovingABodyKeepsItsPartnersRemembered) {
    World world;
    std::vector<BodyId> ids;
    for (int i = 0; i < 3; ++i) ids.push_back(world.addBody(ball(), sphereAt({0, 2, 0})));
    world.step();
    EXPECT_EQ(world.profile().wholePairs, 3);
    ASSERT_TRUE(world.removeBody(ids[1]));
    world.step();
    EXPECT_EQ(world.profile().overlapPairs, 1);
    EXPECT_EQ(world.profile().wholePairs, 1);
    for (int f = 0; f < 120; ++f) world.step();
    EXPECT_EQ(world.profile().overlapPairs, 0);
    EXPECT_GT(length(world.centreOfMass(ids[0]) - world.centreOfMass(ids[2])), 0.9f);
}

// Placing a body again (here World::translate by nothing, every frame) while its pairs are
// remembered keeps their state (once overlapped, a pair stays whole until its centres are a
// cell apart): while the pairs are whole, the run is bit-identical to one without the calls.
// (Once they are apart, a body placed again touching another is a placed body like any other:
// its contacts' overlap is moved out as placed overlap, and the runs part.)
TEST(OverlapRecovery, PlacingAgainKeepsThePairsState) {
    auto run = [](bool replace) {
        World world;
        std::vector<BodyId> ids;
        for (int i = 0; i < 3; ++i)
            ids.push_back(world.addBody(ball(), sphereAt({0.05f * float(i), 0.6f, 0})));
        std::vector<uint64_t> hashes; // of the frames with whole pairs
        for (int f = 0; f < 90 && (f == 0 || world.profile().wholePairs > 0); ++f) {
            if (replace) world.translate(ids[1], {});
            world.step();
            hashes.push_back(world.stateHash());
        }
        EXPECT_GT(hashes.size(), 10u);
        return hashes;
    };
    EXPECT_EQ(run(true), run(false));
}

// Two spheres created at one spot (gravity and floor off) with a recovery of 20 m/s: the pair
// is whole, and each sphere's share of the push is 10 m/s. The centre's bound
// (WorldSettings::overlapRecoveryMaxSpeed, 4.5 m/s by default) holds each centre to it, counted
// from frame to frame. Criteria: with the bound, no centre faster than 4.5 m/s plus 10 % (what
// the response adds within a substep) and the pair apart (centres 0.99 m) and forgotten within
// 1 s; with it off (0), a centre faster than 8 m/s, so the bound is what held them (measured
// 4.50 m/s, forgotten at frame 9; off, 10.00 m/s and frame 5).
TEST(OverlapRecovery, TheCentresBoundHoldsAFastRecovery) {
    auto fastestCentre = [](float bound) {
        WorldSettings ws;
        ws.gravity = {};
        ws.floor = false;
        ws.overlapRecoverySpeed = 20;
        ws.overlapRecoveryMaxSpeed = bound;
        World world(ws);
        BodySettings b = sphereAt({0, 0, 0});
        b.rotation = normalize(Quat{0.3f, 0.2f, -0.1f, 1});
        const BodyId first = world.addBody(ball(), sphereAt({0, 0, 0}));
        const BodyId second = world.addBody(ball(), b);
        test::CentreSpeeds centres(world);
        float fastest = 0;
        for (int f = 0; f < 60; ++f) {
            world.step();
            fastest = std::max(fastest, centres.afterStep(world));
        }
        EXPECT_GT(length(world.centreOfMass(first) - world.centreOfMass(second)), 0.99f);
        EXPECT_EQ(world.profile().overlapPairs, 0);
        return fastest;
    };
    EXPECT_LT(fastestCentre(WorldSettings{}.overlapRecoveryMaxSpeed), 4.5f * 1.1f);
    EXPECT_GT(fastestCentre(0), 8.0f);
}

// The speed and the centre's bound are validated with the other world settings.
TEST(OverlapRecovery, SpeedIsValidated) {
    for (const float bad : {-1.0f, 2e4f, NAN}) {
        WorldSettings ws;
        ws.overlapRecoverySpeed = bad;
        EXPECT_THROW(World{ws}, InputError) << bad;
        ws = WorldSettings{};
        ws.overlapRecoveryMaxSpeed = bad;
        EXPECT_THROW(World{ws}, InputError) << bad;
    }
}
