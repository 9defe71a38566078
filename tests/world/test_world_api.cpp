// The World's public API: handles, shared models, spans, forces, settings validation.
#include "ffdaabb/error.h"
#include "ffdaabb/generators.h"
#include "ffdaabb/world.h"

#include "test_support.h"
#include "world/settings_table.h"

#include <gtest/gtest.h>

#include <set>

using namespace ffd;
using ffd::test::ball;

namespace {

BodySettings at(Vec3 p) {
    BodySettings s;
    s.lattice.targetCells = 38;
    s.position = p;
    return s;
}

} // namespace

TEST(WorldApi, HandlesDetectStaleBodies) {
    World world;
    const BodyId a = world.addBody(ball(), at({0, 1, 0}));
    const BodyId b = world.addBody(ball(), at({2, 1, 0}));
    EXPECT_TRUE(world.isValid(a));
    EXPECT_TRUE(world.removeBody(a));
    EXPECT_FALSE(world.isValid(a));
    EXPECT_FALSE(world.removeBody(a));
    EXPECT_THROW(world.vertices(a), InputError);
    // The slot is reused with a new generation: the old handle stays stale.
    const BodyId c = world.addBody(ball(), at({4, 1, 0}));
    EXPECT_EQ(c.index, a.index);
    EXPECT_NE(c.generation, a.generation);
    EXPECT_FALSE(world.isValid(a));
    EXPECT_TRUE(world.isValid(b));
    EXPECT_TRUE(world.isValid(c));
    EXPECT_FALSE(world.isValid(BodyId{}));
    EXPECT_EQ(world.bodyCount(), 2u);
    const auto ids = world.bodies();
    ASSERT_EQ(ids.size(), 2u);
    EXPECT_EQ(ids[0], b);
    EXPECT_EQ(ids[1], c);
}

TEST(WorldApi, RemovingABodyKeepsTheOthersIntact) {
    World world;
    std::vector<BodyId> ids;
    for (int i = 0; i < 4; ++i) ids.push_back(world.addBody(ball(), at({2.0f * float(i), 1, 0})));
    for (int f = 0; f < 30; ++f) world.step();
    const std::vector<Vec3> before(world.particles(ids[3]).begin(), world.particles(ids[3]).end());
    const Vec3 c2 = world.centreOfMass(ids[2]);
    world.removeBody(ids[1]);
    EXPECT_EQ(std::vector<Vec3>(world.particles(ids[3]).begin(), world.particles(ids[3]).end()),
              before);
    EXPECT_EQ(world.centreOfMass(ids[2]), c2);
    for (int f = 0; f < 30; ++f) world.step(); // still steps fine
    for (const BodyId id : world.bodies())
        for (const Vec3& p : world.particles(id)) EXPECT_TRUE(isFinite(p));
}

TEST(WorldApi, TheWholeWorldsArraysHoldEveryBodysRangeInBodyOrder) {
    World world;
    std::vector<BodyId> ids;
    for (int i = 0; i < 3; ++i) ids.push_back(world.addBody(ball(), at({2.0f * float(i), 1, 0})));
    world.removeBody(ids[1]);
    ids.push_back(world.addBody(icosphere(1), at({6, 1, 0})));
    for (int f = 0; f < 10; ++f) world.step();
    uint32_t vertex = 0, particle = 0;
    for (const BodyId id : world.bodies()) {
        const World::Ranges r = world.ranges(id);
        EXPECT_EQ(r.firstVertex, vertex);
        EXPECT_EQ(r.firstParticle, particle);
        EXPECT_EQ(world.allVertices().data() + r.firstVertex, world.vertices(id).data());
        EXPECT_EQ(r.vertexCount, world.vertices(id).size());
        EXPECT_EQ(world.allParticles().data() + r.firstParticle, world.particles(id).data());
        EXPECT_EQ(world.allVelocities().data() + r.firstParticle, world.velocities(id).data());
        EXPECT_EQ(r.particleCount, world.particles(id).size());
        vertex += r.vertexCount, particle += r.particleCount;
    }
    EXPECT_EQ(world.allVertices().size(), vertex);
    EXPECT_EQ(world.allParticles().size(), particle);
    EXPECT_EQ(world.allVelocities().size(), particle);
    EXPECT_THROW(world.ranges(ids[1]), InputError);
}

TEST(WorldApi, BodiesOfTheSameMeshShareOneModel) {
    World world;
    const TriangleMesh mesh = ball();
    for (int i = 0; i < 100; ++i)
        world.addBody(mesh, at({float(i % 10) * 1.2f, 1, float(i / 10) * 1.2f}));
    auto models = [&] {
        std::set<const Lattice*> lattices;
        for (const BodyId id : world.bodies()) lattices.insert(&world.lattice(id));
        return lattices.size();
    };
    EXPECT_EQ(models(), 1u);
    // A different lattice setting is a different model; so is a different mesh.
    BodySettings other = at({0, 5, 0});
    other.lattice.targetCells = 60;
    world.addBody(mesh, other);
    TriangleMesh bigger = mesh;
    transform(bigger, 2.0f, {});
    world.addBody(bigger, at({0, 9, 0}));
    EXPECT_EQ(models(), 3u);
}

TEST(WorldApi, ContactsNameTheirBodiesAndPushThemApart) {
    WorldSettings awake; // the stack stays awake, with its resting contacts, for 300 frames
    awake.sleepSpeed = 0;
    World world(awake);
    const TriangleMesh mesh = ball();
    const BodyId lower = world.addBody(mesh, at({0, 0.5f, 0}));
    const BodyId upper = world.addBody(mesh, at({0, 1.6f, 0}));
    std::vector<ContactInfo> contacts;
    world.contacts(contacts);
    EXPECT_TRUE(contacts.empty()); // nothing stepped yet
    int floor = 0, between = 0;
    for (int f = 0; f < 300; ++f) world.step();
    world.contacts(contacts);
    for (const ContactInfo& c : contacts) {
        ASSERT_TRUE(world.isValid(c.bodyA));
        EXPECT_NEAR(length(c.normal), 1.0f, 1e-4f);
        EXPECT_GE(c.depth, 0.0f);
        EXPECT_GE(c.impulse, 0.0f);
        if (c.bodyB.isNull()) {
            ++floor;
            EXPECT_EQ(c.bodyA, lower); // only the lower ball touches the floor
            EXPECT_GT(c.normal.y, 0.99f);
            EXPECT_LT(c.point.y, 0.05f);
        } else {
            ++between;
            ASSERT_TRUE(world.isValid(c.bodyB));
            EXPECT_NE(c.bodyA, c.bodyB);
            // The upper ball is pushed up off the lower one, the lower one down.
            const float up = c.bodyA == upper ? 1.0f : -1.0f;
            EXPECT_GT(c.normal.y * up, 0.5f);
        }
    }
    EXPECT_GT(floor, 0);
    EXPECT_GT(between, 0);
    // At rest, the impulses carry the upper ball's weight: over a substep, m g dt. The ball
    // rocks a little on its contacts, so one substep's lift is within about 6 % of it (one
    // standard deviation, measured over 400 frames); their mean over 60 frames within 2 %.
    double lift = 0; // upward impulse on the upper ball, N s, summed over the frames
    for (int f = 0; f < 60; ++f) {
        world.step();
        world.contacts(contacts);
        for (const ContactInfo& c : contacts)
            if (!c.bodyB.isNull())
                lift += double(c.impulse * c.normal.y) * (c.bodyA == upper ? 1 : -1);
    }
    const double weight =
        world.info(upper).mass * 9.81 * world.settings().frameStep / world.settings().substeps;
    EXPECT_NEAR(lift / 60, weight, 0.02 * weight);
    // Removing a body drops the contacts, which name its particles.
    world.removeBody(upper);
    world.contacts(contacts);
    EXPECT_TRUE(contacts.empty());
}

TEST(WorldApi, ParticleMassesSumToTheBodysMass) {
    World world;
    const BodyId id = world.addBody(ball(), at({0, 1, 0}));
    const BodyInfo info = world.info(id);
    double sum = 0;
    for (uint32_t p = 0; p < info.particles; ++p) sum += world.particleMass(id, p);
    EXPECT_NEAR(sum, info.mass, 1e-3 * info.mass);
    EXPECT_THROW(world.particleMass(id, uint32_t(info.particles)), InputError);
}

TEST(WorldApi, SpansAndInfoDescribeTheBody) {
    World world;
    const TriangleMesh mesh = ball();
    const BodyId id = world.addBody(mesh, at({1, 2, 3}));
    const BodyInfo info = world.info(id);
    EXPECT_EQ(info.vertices, 162u);
    EXPECT_EQ(info.triangles, 320u);
    EXPECT_EQ(world.vertices(id).size(), 162u);
    EXPECT_EQ(world.triangles(id).size(), 320u);
    EXPECT_EQ(world.particles(id).size(), info.particles);
    EXPECT_EQ(world.boxNodes(id).size(), info.surfaceCells * 8);
    // Initially the mesh sits at its pose, exactly.
    for (size_t v = 0; v < mesh.vertexCount(); ++v)
        EXPECT_LE(length(world.vertices(id)[v] - (mesh.positions[v] + Vec3{1, 2, 3})), 1e-5f);
    // The node bounds contain the whole mesh.
    for (const Vec3& v : world.vertices(id)) EXPECT_TRUE(world.bounds(id).contains(v, 1e-5f));
    // Density * volume: the closed icosphere's volume.
    EXPECT_NEAR(info.mass, 1000.0 * signedVolume(mesh), 1e-2);
}

TEST(WorldApi, ExplicitMassAndRotationAreHonoured) {
    World world;
    BodySettings s = at({0, 3, 0});
    s.mass = 2.5f;
    s.rotation = Quat::fromAxisAngle({0, 0, 1}, 1.5707963f);
    TriangleMesh rod;
    rod.positions = {{-1, -0.1f, -0.1f}, {1, -0.1f, -0.1f}, {0, 0.1f, -0.1f}, {0, 0, 0.1f}};
    rod.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
    const BodyId id = world.addBody(rod, s);
    EXPECT_FLOAT_EQ(world.info(id).mass, 2.5f);
    // Rotated a quarter turn about z: the long axis now points along y.
    const Aabb b = world.bounds(id);
    EXPECT_GT(b.extent().y, 1.8f);
    EXPECT_LT(b.extent().x, 0.5f);
}

TEST(WorldApi, ForcesAndImpulsesMoveTheCentreOfMass) {
    WorldSettings ws;
    ws.gravity = {};
    ws.floor = false;
    World world(ws);
    const BodyId id = world.addBody(ball(), at({0, 0, 0}));
    const float m = world.info(id).mass;
    world.applyImpulse(id, Vec3{m * 2.0f, 0, 0}); // +2 m/s
    EXPECT_NEAR(world.linearVelocity(id).x, 2.0f, 1e-5f);
    world.applyForce(id, Vec3{0, m * 6.0f, 0}); // 6 m/s^2 for one frame
    world.step();
    EXPECT_NEAR(world.linearVelocity(id).y, 6.0f / 60.0f, 1e-4f);
    world.step(); // the force was for one step only
    EXPECT_NEAR(world.linearVelocity(id).y, 6.0f / 60.0f, 1e-4f);
    // A force on one particle pushes the body (and spins or deforms it).
    const Vec3 before = world.linearVelocity(id);
    world.applyParticleForce(id, 0, Vec3{0, 0, m * 60.0f});
    world.step();
    EXPECT_NEAR(world.linearVelocity(id).z - before.z, 1.0f, 1e-3f);
    EXPECT_THROW(world.applyParticleForce(id, 100000, {1, 0, 0}), InputError);
    EXPECT_THROW(world.applyForce(id, {std::nanf(""), 0, 0}), InputError);
}

TEST(WorldApi, SettingsAreValidatedWithTheFieldName) {
    auto field = [](auto&& f) -> std::string {
        try {
            f();
        } catch (const InputError& e) {
            return e.source();
        }
        return "(no error)";
    };
    WorldSettings ws;
    ws.frameStep = 0;
    EXPECT_EQ(field([&] { World w(ws); }), "world.frameStep");
    ws = {};
    ws.substeps = 0;
    EXPECT_EQ(field([&] { World w(ws); }), "world.substeps");
    ws = {};
    ws.gravity.y = INFINITY;
    EXPECT_EQ(field([&] { World w(ws); }), "world.gravity");
    World world;
    BodySettings s;
    s.regionHalfWidth = 7;
    EXPECT_EQ(field([&] { world.addBody(ball(), s); }), "body.regionHalfWidth");
    s = {};
    s.stiffness = 1.5f;
    EXPECT_EQ(field([&] { world.addBody(ball(), s); }), "body.stiffness");
    s = {};
    s.friction = -1;
    EXPECT_EQ(field([&] { world.addBody(ball(), s); }), "body.friction");
    s = {};
    s.position.x = NAN;
    EXPECT_EQ(field([&] { world.addBody(ball(), s); }), "body.position");
    s = {};
    s.lattice.cellSize = -1;
    EXPECT_EQ(field([&] { world.addBody(ball(), s); }), "lattice.cellSize");
    TriangleMesh bad = ball();
    bad.positions[5].z = NAN;
    bad.name = "bad-ball";
    EXPECT_EQ(field([&] { world.addBody(bad, {}); }), "bad-ball");
    EXPECT_EQ(world.bodyCount(), 0u); // nothing half-added
}

TEST(WorldApi, ModesCanBeSwitchedLiveAndNoneLetsObjectsPass) {
    WorldSettings ws;
    ws.gravity = {};
    ws.floor = false;
    ws.mode = CollisionMode::None;
    World world(ws);
    BodySettings s = at({-1.5f, 0, 0});
    s.velocity = {3, 0, 0};
    const BodyId a = world.addBody(ball(), s);
    s = at({1.5f, 0, 0});
    s.velocity = {-3, 0, 0};
    const BodyId b = world.addBody(ball(), s);
    for (int f = 0; f < 60; ++f) world.step();
    EXPECT_GT(world.centreOfMass(a).x, world.centreOfMass(b).x); // passed through
    world.setMode(CollisionMode::Enhanced);
    EXPECT_EQ(world.settings().mode, CollisionMode::Enhanced);
    world.setVelocity(a, {-3, 0, 0});
    world.setVelocity(b, {3, 0, 0});
    for (int f = 0; f < 60; ++f) world.step();
    EXPECT_GT(world.centreOfMass(a).x, world.centreOfMass(b).x); // bounced back, did not pass
    CollisionMode m;
    EXPECT_TRUE(parseCollisionMode("previous", m));
    EXPECT_EQ(m, CollisionMode::Previous);
    EXPECT_FALSE(parseCollisionMode("fast", m));
}

TEST(WorldApi, ThreadCountDoesNotChangeTheResult) {
    auto run = [](int threads) {
        WorldSettings ws;
        ws.threads = threads;
        World world(ws);
        for (int i = 0; i < 12; ++i) {
            BodySettings s = at({0.2f * float(i % 3), 0.6f + 1.1f * float(i), 0.1f * float(i % 2)});
            s.rotation = Quat::fromAxisAngle({1, 1, 0}, float(i));
            world.addBody(i % 3 ? ball() : letter('R'), s);
        }
        for (int f = 0; f < 150; ++f) world.step();
        return world.stateHash();
    };
    const uint64_t one = run(1);
    EXPECT_EQ(run(2), one);
    EXPECT_EQ(run(4), one);
    EXPECT_EQ(run(0), one);
}

// One table of setting ranges serves validate(), the scene reader and the command line: its
// entries describe their members, the defaults lie in range, and each bound is where validate
// starts to refuse.
TEST(WorldApi, TheSettingRangesDescribeTheirMembersAndValidateByThem) {
    auto check = [](auto defaults, std::span<const SettingRange> ranges, const auto& members,
                    const char* prefix) {
        using Settings = decltype(defaults);
        ASSERT_EQ(ranges.size(), members.size());
        for (size_t i = 0; i < ranges.size(); ++i) {
            const SettingRange& r = ranges[i];
            EXPECT_EQ(std::holds_alternative<int Settings::*>(members[i]), r.integer) << r.field;
            EXPECT_EQ(findSettingRange(r.field), &r);
            EXPECT_EQ(findSettingRange(r.key), &r);
            const double value = detail::settingValue(defaults, members[i]);
            EXPECT_TRUE(value >= r.min && value <= r.max) << r.field << " default " << value;
            EXPECT_EQ(settingDefault(r), value) << r.field;
            SettingRange copy = r; // found by name when not the table's own entry
            EXPECT_EQ(settingDefault(copy), value) << r.field;
            EXPECT_NE(r.doc, nullptr);
            EXPECT_GT(std::string(r.doc).size(), 10u) << r.field << " has no doc line";
            EXPECT_NE(r.unit, nullptr);
            // Just outside each bound, validate names the field; on the bound it accepts.
            for (const double bound : {r.min, r.max}) {
                Settings s = defaults;
                std::visit([&](auto m) { s.*m = std::remove_reference_t<decltype(s.*m)>(bound); },
                           members[i]);
                EXPECT_NO_THROW(validate(s)) << r.field << " = " << bound;
                const double out = bound == r.min
                                       ? r.min - (r.integer ? 1.0 : 1e-3 * (1 + std::abs(r.min)))
                                       : r.max + (r.integer ? 1.0 : 1e-3 * (1 + std::abs(r.max)));
                std::visit([&](auto m) { s.*m = std::remove_reference_t<decltype(s.*m)>(out); },
                           members[i]);
                try {
                    validate(s);
                    ADD_FAILURE() << r.field << " = " << out << " accepted";
                } catch (const InputError& e) {
                    EXPECT_EQ(e.source(), std::string(prefix) + "." + r.field);
                    EXPECT_NE(std::string(e.what()).find(r.expected), std::string::npos);
                }
            }
        }
    };
    check(WorldSettings{}, worldSettingRanges(), detail::worldSettingMembers(), "world");
    check(BodySettings{}, bodySettingRanges(), detail::bodySettingMembers(), "body");
    EXPECT_EQ(findSettingRange("no_such_setting"), nullptr);
}
