// Sleeping (WorldSettings::sleepSpeed, sleepTime; world/sleeping.h): bodies at rest fall asleep
// together with what they touch, cost nothing while asleep, and wake when anything may disturb
// them.
#include "ffdaabb/error.h"
#include "ffdaabb/queries.h"
#include "ffdaabb/scene.h"
#include "ffdaabb/world.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <vector>

using namespace ffd;
using ffd::test::ball;
using ffd::test::sphereAt;

namespace {

std::vector<Vec3> particlesOf(const World& world, BodyId b) {
    return {world.particles(b).begin(), world.particles(b).end()};
}

// Steps until every body sleeps (or `limit` frames); returns the frames stepped.
int stepUntilAsleep(World& world, int limit) {
    for (int f = 1; f <= limit; ++f) {
        world.step();
        if (world.awakeCount() == 0) return f;
    }
    return limit + 1;
}

} // namespace

TEST(Sleeping, ABodyAtRestFallsAsleepAndThenCostsNothing) {
    World world;
    const BodyId ball1 = world.addBody(ball(), sphereAt({0, 0.8f, 0}));
    EXPECT_TRUE(world.isAwake(ball1));
    const int frames = stepUntilAsleep(world, 300);
    ASSERT_LE(frames, 300) << "a ball resting on the floor never fell asleep";
    // Not before it had landed and been quiet for sleepTime (0.5 s = 30 frames).
    EXPECT_GT(frames, 30);
    EXPECT_FALSE(world.isAwake(ball1));
    EXPECT_EQ(world.profile().sleepingBodies, 1);
    EXPECT_EQ(world.linearVelocity(ball1), Vec3{});
    const std::vector<Vec3> rest = particlesOf(world, ball1);
    const uint64_t hash = world.stateHash();
    for (int f = 0; f < 120; ++f) world.step();
    EXPECT_EQ(particlesOf(world, ball1), rest);
    EXPECT_EQ(world.stateHash(), hash);
    // Asleep, it costs nothing in the stages that move bodies or find their contacts.
    const Profile& p = world.profile();
    EXPECT_EQ(p.contacts, 0);
    EXPECT_EQ(p.floorContacts, 0);
    EXPECT_EQ(p.candidatePairs, 0);
    EXPECT_GE(world.centreOfMass(ball1).y, 0.3f); // resting on the floor, not in it
}

TEST(Sleeping, ASleeperKeepsTouchingWhatItRestsOn) {
    // Falling asleep ends no contact: the pair of a sleeper and the floor goes on, with the
    // impulse of its last awake step, and no end event comes until something moves.
    World world;
    const BodyId b = world.addBody(ball(), sphereAt({0, 0.8f, 0}));
    ASSERT_LE(stepUntilAsleep(world, 300), 300);
    for (int f = 0; f < 30; ++f) {
        world.step();
        EXPECT_TRUE(contactEvents(world).end.empty()) << "frame " << f;
    }
    std::vector<BodyContact> partners;
    touchingBodies(world, b, partners);
    ASSERT_EQ(partners.size(), 1u);
    EXPECT_TRUE(partners[0].other.isNull());
    const double weight = world.info(b).mass * 9.81 * world.settings().frameStep;
    EXPECT_NEAR(partners[0].normalImpulse / weight, 1.0, 0.2);
}

TEST(Sleeping, ForcesImpulsesVelocitiesAndPosesWakeABody) {
    World world;
    const BodyId b = world.addBody(ball(), sphereAt({0, 0.8f, 0}));
    const std::vector<std::function<void()>> disturbances = {
        [&] {
            world.applyImpulse(b, {0, 1, 0});
        },
        [&] {
            world.applyForce(b, {0, 100, 0});
        },
        [&] {
            world.applyParticleForce(b, 0, {0, 10, 0});
        },
        [&] {
            world.setVelocity(b, {1, 0, 0});
        },
        [&] {
            world.translate(b, {0.5f, 0, 0});
        },
        [&] { world.setParticles(b, world.particles(b)); },
        [&] { world.setAwake(b, true); },
    };
    for (size_t k = 0; k < disturbances.size(); ++k) {
        ASSERT_LE(stepUntilAsleep(world, 600), 600) << "disturbance " << k;
        disturbances[k]();
        EXPECT_TRUE(world.isAwake(b)) << "disturbance " << k;
        world.step();
        EXPECT_TRUE(world.isAwake(b)) << "disturbance " << k << ": asleep again at once";
    }
    // An impulse moves a sleeping body as it moves an awake one.
    ASSERT_LE(stepUntilAsleep(world, 600), 600);
    const float x0 = world.centreOfMass(b).x;
    world.applyImpulse(b, Vec3{2, 0, 0} * world.info(b).mass);
    for (int f = 0; f < 30; ++f) world.step();
    EXPECT_GT(world.centreOfMass(b).x - x0, 0.3f);
}

TEST(Sleeping, ABodyLandingOnASleeperWakesItAndMovesAsOnAnAwakeOne) {
    // The same drop onto a ball that sleeps and onto one that never does: the sleeper wakes
    // before it is hit and both worlds go on alike (not bit for bit: waking sets its velocity
    // to 0 exactly).
    WorldSettings never;
    never.sleepSpeed = 0;
    World worlds[2] = {World{}, World{never}};
    BodyId below[2], above[2];
    for (int k = 0; k < 2; ++k) {
        below[k] = worlds[k].addBody(ball(), sphereAt({0, 0.8f, 0}));
        for (int f = 0; f < 120; ++f) worlds[k].step();
    }
    ASSERT_FALSE(worlds[0].isAwake(below[0]));
    for (int k = 0; k < 2; ++k) above[k] = worlds[k].addBody(ball(), sphereAt({0.1f, 3.0f, 0}));
    bool wokeBeforeContact = false, touched = false;
    double deepest = 0;
    for (int f = 0; f < 60; ++f) {
        for (World& w : worlds) w.step();
        std::vector<ContactInfo> contacts;
        worlds[0].contacts(contacts);
        for (const ContactInfo& c : contacts)
            if (!c.bodyB.isNull() && !touched) {
                touched = true;
                wokeBeforeContact = worlds[0].isAwake(below[0]);
            }
        deepest = std::max(deepest, ffd::test::deepestInside(worlds[0]));
    }
    ASSERT_TRUE(touched) << "the balls never met";
    EXPECT_TRUE(wokeBeforeContact) << "the ball below was still asleep when it was hit";
    EXPECT_LT(deepest, 0.01) << "metres of mesh inside the other ball";
    for (int b = 0; b < 2; ++b) {
        const BodyId id[2] = {b == 0 ? below[0] : above[0], b == 0 ? below[1] : above[1]};
        EXPECT_LT(length(worlds[0].centreOfMass(id[0]) - worlds[1].centreOfMass(id[1])), 0.02f)
            << (b == 0 ? "below" : "above");
    }
}

TEST(Sleeping, BodiesWithinReachFallAsleepInTheSameFrame) {
    // Three balls in a row, 2 cm apart (within each other's reach); the last is added 20 frames
    // after the others. A ball far away, dropped with the first two, falls asleep first: the
    // row waits for its last ball to be quiet as long, then sleeps at once.
    World world;
    std::vector<BodyId> row;
    for (int i = 0; i < 2; ++i)
        row.push_back(world.addBody(ball(), sphereAt({1.02f * float(i), 0.6f, 0})));
    const BodyId apart = world.addBody(ball(), sphereAt({6, 0.6f, 0}));
    for (int f = 0; f < 20; ++f) world.step();
    row.push_back(world.addBody(ball(), sphereAt({2.04f, 0.6f, 0})));
    int asleepAt[3] = {-1, -1, -1}, apartAt = -1;
    for (int f = 1; f <= 900 && world.awakeCount() > 0; ++f) {
        world.step();
        for (int i = 0; i < 3; ++i)
            if (asleepAt[i] < 0 && !world.isAwake(row[size_t(i)])) asleepAt[i] = f;
        if (apartAt < 0 && !world.isAwake(apart)) apartAt = f;
    }
    ASSERT_GT(asleepAt[0], 0) << "the row never fell asleep";
    EXPECT_EQ(asleepAt[1], asleepAt[0]);
    EXPECT_EQ(asleepAt[2], asleepAt[0]);
    ASSERT_GT(apartAt, 0);
    EXPECT_LT(apartAt, asleepAt[0]);
    for (int i = 0; i < 2; ++i) // still side by side
        EXPECT_LT(world.centreOfMass(row[size_t(i) + 1]).x - world.centreOfMass(row[size_t(i)]).x,
                  1.1f);
}

TEST(Sleeping, RemovingASupportWakesWhatItHeld) {
    World world;
    const BodyId below = world.addBody(ball(), sphereAt({0, 0.6f, 0}));
    const BodyId above = world.addBody(ball(), sphereAt({0, 1.65f, 0}));
    ASSERT_LE(stepUntilAsleep(world, 900), 900);
    const float high = world.centreOfMass(above).y;
    world.removeBody(below);
    EXPECT_TRUE(world.isAwake(above));
    for (int f = 0; f < 90; ++f) world.step();
    EXPECT_LT(world.centreOfMass(above).y, high - 0.5f) << "it did not fall";
}

TEST(Sleeping, ABodyThatMayNotSleepStaysAwakeAndKeepsItsNeighboursAwake) {
    World world;
    BodySettings restless = sphereAt({0, 0.6f, 0});
    restless.allowSleep = false;
    const BodyId a = world.addBody(ball(), restless);
    const BodyId b = world.addBody(ball(), sphereAt({0, 1.65f, 0}));
    const BodyId far = world.addBody(ball(), sphereAt({6, 0.6f, 0}));
    for (int f = 0; f < 600; ++f) world.step();
    EXPECT_TRUE(world.isAwake(a));
    EXPECT_TRUE(world.isAwake(b)); // it rests on a: one island
    EXPECT_FALSE(world.isAwake(far));
    world.setAwake(a, false);
    EXPECT_TRUE(world.isAwake(a));
}

TEST(Sleeping, OffNeverSleepsAndTurningItOffWakesEverybody) {
    WorldSettings off;
    off.sleepSpeed = 0;
    World never(off);
    const BodyId n = never.addBody(ball(), sphereAt({0, 0.8f, 0}));
    for (int f = 0; f < 300; ++f) never.step();
    EXPECT_TRUE(never.isAwake(n));

    World world;
    const BodyId b = world.addBody(ball(), sphereAt({0, 0.8f, 0}));
    ASSERT_LE(stepUntilAsleep(world, 300), 300);
    world.setSettings(off);
    EXPECT_TRUE(world.isAwake(b));
    // A changed gravity wakes sleeping bodies too.
    World tilted;
    const BodyId t = tilted.addBody(ball(), sphereAt({0, 0.8f, 0}));
    ASSERT_LE(stepUntilAsleep(tilted, 300), 300);
    WorldSettings s = tilted.settings();
    s.gravity = {-3, -9.81f, 0};
    tilted.setSettings(s);
    EXPECT_TRUE(tilted.isAwake(t));
    const float x0 = tilted.centreOfMass(t).x;
    for (int f = 0; f < 60; ++f) tilted.step();
    // It goes the new way: it slides more than it rolls (docs/LIMITS.md, known problem 8).
    EXPECT_LT(tilted.centreOfMass(t).x, x0 - 0.1f);
}

TEST(Sleeping, SleepingIsTheSameAtAnyThreadCount) {
    Scene scene = loadScene("spheres");
    setObjectCount(scene, 30);
    uint64_t hash[2] = {};
    int asleep[2] = {};
    for (int t = 0; t < 2; ++t) {
        scene.world.threads = t + 1;
        SceneBuild build = buildScene(scene);
        for (int f = 0; f < 600; ++f) build.world.step();
        hash[t] = build.world.stateHash();
        asleep[t] = build.world.profile().sleepingBodies;
    }
    EXPECT_EQ(hash[0], hash[1]);
    EXPECT_EQ(asleep[0], asleep[1]);
    EXPECT_GT(asleep[0], 15) << "of 30 spheres after 10 s";
}

TEST(Sleeping, SettingsAreValidatedAndReadFromScenes) {
    WorldSettings s;
    s.sleepSpeed = -1;
    EXPECT_THROW(validate(s), InputError);
    s.sleepSpeed = 0.05f;
    s.sleepTime = -0.5f;
    try {
        validate(s);
        FAIL() << "a negative sleep time was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("sleepTime"), std::string::npos) << e.what();
    }
    const Scene scene = parseScene(R"({"world": {"sleep_speed": 0.1, "sleep_time": 2},
        "objects": [{"mesh": "sphere", "count": 1, "material": {"allow_sleep": false}}]})",
                                   "inline.json");
    EXPECT_FLOAT_EQ(scene.world.sleepSpeed, 0.1f);
    EXPECT_FLOAT_EQ(scene.world.sleepTime, 2.0f);
    EXPECT_FALSE(scene.objects[0].body.allowSleep);
    try {
        parseScene(R"({"world": {"sleep_speed": -2}, "objects": []})", "bad.json");
        FAIL() << "a negative sleep speed was accepted";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("world.sleep_speed"), std::string::npos) << e.what();
    }
    try {
        parseScene(R"({"objects": [{"mesh": "sphere", "material": {"allow_sleep": 3}}]})",
                   "bad.json");
        FAIL() << "a number was accepted for allow_sleep";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("allow_sleep"), std::string::npos) << e.what();
    }
}
