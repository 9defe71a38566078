// Extreme but legal scenes: each must stay finite and recover. "Recover" is stated per test as
// exact criteria on the bodies after some seconds of simulated time: every particle finite,
// every mesh vertex above the floor within a tolerance, no pair interpenetrating (the
// engine-independent winding-number measure of bench/common), and motion died down or the
// bodies separated.
#include "ffdaabb/generators.h"
#include "ffdaabb/world.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

using namespace ffd;
using ffd::test::ball;
using ffd::test::closestCentres;
using ffd::test::deepestInside;
using ffd::test::fastestBody;
using ffd::test::sphereAt;

namespace {

bool allFinite(const World& world) {
    for (BodyId id : world.bodies()) {
        for (const Vec3& p : world.particles(id))
            if (!isFinite(p)) return false;
        for (const Vec3& v : world.velocities(id))
            if (!isFinite(v)) return false;
    }
    return true;
}

float lowestVertex(const World& world, BodyId id) {
    float lowest = INFINITY;
    for (const Vec3& v : world.vertices(id)) lowest = std::min(lowest, v.y);
    return lowest;
}

float lowestVertex(const World& world) {
    float lowest = INFINITY;
    for (BodyId id : world.bodies()) lowest = std::min(lowest, lowestVertex(world, id));
    return lowest;
}

double kineticEnergyPerKilogram(const World& world) {
    double mass = 0;
    for (BodyId id : world.bodies()) mass += world.info(id).mass;
    return world.kineticEnergy() / mass;
}

} // namespace

// Two spheres thrown down at 50 m/s, one onto a sphere resting on the floor, one onto the
// floor itself; 10 s simulated.
// Criteria: every frame finite, no vertex more than 1 cm (1 % of the size) below the floor,
// the thrown sphere never closer than 0.55 m (centre to centre; 1 m when they touch) to the one
// it hits: crushed, not passed through (closest 0.590 m, 0.614 with an even share of mass per
// lattice cell, which made the particles outside the sphere heavier); after 10 s
// no vertex inside another body deeper than 1 cm, none below the floor by more than 1 cm, and
// the kinetic energy below 2 % of the two throws' (the impact energy is gone). Measured: 0.9 %,
// one sphere rolling at 6.8 m/s after bouncing off the target at 20 m/s: the energy a crushed
// sphere stores in its deformation comes back as a rebound, with restitution 0
// (docs/LIMITS.md).
TEST(ExtremeScenes, DroppedAtFiftyMetresPerSecond) {
    World world;
    const BodyId target = world.addBody(ball(), sphereAt({0, 0.5f, 0}));
    const BodyId bullet = world.addBody(ball(), sphereAt({0.1f, 3.0f, 0}, {0, -50, 0}));
    world.addBody(ball(), sphereAt({3.0f, 3.0f, 0}, {0, -50, 0}));
    float closest = INFINITY, lowest = INFINITY;
    for (int f = 0; f < 600; ++f) {
        world.step();
        ASSERT_TRUE(allFinite(world)) << "frame " << f;
        lowest = std::min(lowest, lowestVertex(world));
        closest =
            std::min(closest, length(world.centreOfMass(bullet) - world.centreOfMass(target)));
    }
    EXPECT_GT(lowest, -0.01f);
    EXPECT_GT(closest, 0.55f);
    EXPECT_LE(deepestInside(world, 1.0f), 0.01);
    EXPECT_GT(lowestVertex(world), -0.01f);
    const float thrown = 2 * 0.5f * world.info(bullet).mass * 50 * 50;
    EXPECT_LT(world.kineticEnergy(), 0.02 * thrown);
}

// 200 spheres created overlapping: see tests/known_bugs (the collision response turns deep
// initial overlaps into velocities of tens of m/s by default) and CreatedOverlappingArePushed
// OutGently below (the push-out bound); docs/LIMITS.md.

// A letter 1 m tall extruded only 1 mm deep: one lying flat on the floor, a second dropped flat
// onto it from 0.5 m, a third dropped standing on its edge; 5 s simulated.
// Criteria: every frame finite; after 5 s no vertex below the floor by more than 1 mm (the
// letter's thickness), no vertex of one letter inside another deeper than 0.5 mm (half the
// thickness: the stacked plates did not pass into each other), the dropped letter's lowest
// vertex above the floor (it lies on the first one, not through it), and at rest (kinetic
// energy below 1e-4 J/kg).
TEST(ExtremeScenes, LetterOneMillimetreThick) {
    LetterSettings thin;
    thin.depthRatio = 0.001f;
    const TriangleMesh plate = letter('A', thin);
    ASSERT_NEAR(bounds(plate).extent().z, 0.001f, 1e-5f);
    World world;
    BodySettings s;
    s.lattice.targetCells = 34;
    const Quat flat = Quat::fromAxisAngle({1, 0, 0}, 1.5707963f); // depth along y
    s.rotation = flat;
    s.position = {0, 0.01f, 0};
    world.addBody(plate, s);
    s.position = {0.1f, 0.5f, 0.05f};
    const BodyId dropped = world.addBody(plate, s);
    s.rotation = Quat{};
    s.position = {2.5f, 0.3f, 0};
    world.addBody(plate, s);
    for (int f = 0; f < 300; ++f) {
        world.step();
        ASSERT_TRUE(allFinite(world)) << "frame " << f;
    }
    EXPECT_GT(lowestVertex(world), -0.001f);
    EXPECT_LE(deepestInside(world, 1.0f), 0.0005);
    EXPECT_GT(lowestVertex(world, dropped), 0.0f);
    EXPECT_LT(kineticEnergyPerKilogram(world), 1e-4);
}

// A sphere 1,000 times heavier resting on a light one, offset sideways by 0 to 10 cm; 5 s
// simulated. Criterion: the heavy sphere never more than 1 cm (1 % of the size) inside the
// light one, checked every 10th frame by the meshes (winding number). Measured: within 1 cm at
// every offset with box-pair contacts; 18 cm at the 5 cm offset with the paper's node contacts,
// when this was the known bug HeavySphereDoesNotCrushALightOne.
TEST(ExtremeScenes, HeavySphereDoesNotCrushALightOne) {
    for (const float offset : {0.0f, 0.03f, 0.05f, 0.07f, 0.1f}) {
        SCOPED_TRACE("offset " + std::to_string(offset));
        World world;
        test::addHeavyOnLight(world, offset);
        double deepest = 0;
        for (int f = 0; f < 300; ++f) {
            world.step();
            ASSERT_TRUE(allFinite(world)) << "frame " << f;
            if (f % 10 == 0) deepest = std::max(deepest, deepestInside(world));
        }
        EXPECT_LE(deepest, 0.01);
    }
}

// The same five layouts, 5 s each. Criterion: the light sphere never faster than 15 m/s (its
// fastest over the five is 7.6-9.4 m/s with the separation bound of 2 m/s; 18-30 m/s without
// it, when this was a known bug: the rigid impact phase turned the squeezed sphere's deformation
// speed into rigid motion, docs/ALGORITHM.md section 5, "Separation bound").
TEST(ExtremeScenes, LightSphereIsNotThrownFromUnderAHeavyOne) {
    for (const float offset : {0.0f, 0.03f, 0.05f, 0.07f, 0.1f}) {
        SCOPED_TRACE("offset " + std::to_string(offset));
        World world;
        const BodyId light = test::addHeavyOnLight(world, offset);
        float fastest = 0;
        for (int f = 0; f < 300; ++f) {
            world.step();
            fastest = std::max(fastest, length(world.linearVelocity(light)));
        }
        EXPECT_LT(fastest, 15.0f);
    }
}

// Touching spheres with a mass ratio of 1:1000, both ways round: a heavy sphere resting on a
// light one and a light one on a heavy one, the upper sphere offset sideways by 0 to 10 cm
// (what happens on the way depends on the offset: one offset alone passed or failed by chance);
// 10 s simulated each.
// Criteria, every offset: every frame finite and no vertex more than 1 cm below the floor (the
// light sphere is not pressed through the floor); after 10 s no vertex inside another body
// deeper than 1 cm, both heavy spheres at rest (slower than 0.1 m/s) and the total mechanical
// energy below the start's (nothing gained).
TEST(ExtremeScenes, MassRatioOneToAThousand) {
    for (const float offset : {0.0f, 0.03f, 0.05f, 0.07f, 0.1f}) {
        SCOPED_TRACE("offset " + std::to_string(offset));
        World world;
        auto add = [&](Vec3 p, float density) {
            BodySettings s = sphereAt(p);
            s.density = density;
            return world.addBody(ball(), s);
        };
        const BodyId light = add({0, 0.5f, 0}, 10);
        const BodyId heavyAbove = add({offset, 1.52f, 0}, 10000);
        const BodyId heavyBelow = add({3, 0.5f, 0}, 10000);
        add({3 + offset, 1.52f, 0}, 10);
        ASSERT_NEAR(world.info(heavyAbove).mass / world.info(light).mass, 1000, 1);
        auto energy = [&] {
            double e = world.kineticEnergy();
            for (BodyId id : world.bodies())
                e += double(world.info(id).mass) * 9.81 * double(world.centreOfMass(id).y);
            return e;
        };
        const double startEnergy = energy();
        for (int f = 0; f < 600; ++f) {
            world.step();
            ASSERT_TRUE(allFinite(world)) << "frame " << f;
            ASSERT_GT(lowestVertex(world), -0.01f) << "frame " << f;
        }
        EXPECT_LE(deepestInside(world, 1.0f), 0.01);
        EXPECT_LT(length(world.linearVelocity(heavyAbove)), 0.1f);
        EXPECT_LT(length(world.linearVelocity(heavyBelow)), 0.1f);
        EXPECT_LT(energy(), startEnergy);
    }
}

// A column of 20 spheres falling onto each other with frames of 1/15 s (two substeps of
// 1/30 s); 20 s simulated; the column nearly aligned (each sphere offset by up to dx, dz) for
// four choices of (dx, dz).
// Criteria, each column: every frame finite and no two centres closer than 0.6 m (radius 0.5:
// at 1/15 s a sphere meeting another at 10 m/s sinks in by up to a third of a frame's travel
// before the contacts push it out, and the column collapses sideways, so the closest pair
// depends on the path: over twelve columns offset by 0-2 cm the closest is 0.675-0.810 m with
// the separation bound of 2 m/s and 0.706-0.814 m without it, the exact column the least with
// the bound; a pass through would bring the centres near 0); after 20 s no vertex below the
// floor by more than 1 cm, none inside another body deeper than 1 cm, and at rest (kinetic
// energy below 1e-6 J/kg).
TEST(ExtremeScenes, FrameStepOneFifteenth) {
    for (const auto& [dx, dz] :
         {std::pair{0.1f, 0.1f}, {0.12f, 0.1f}, {0.05f, 0.05f}, {0.0f, 0.0f}}) {
        SCOPED_TRACE("dx " + std::to_string(dx) + " dz " + std::to_string(dz));
        WorldSettings ws;
        ws.frameStep = 1.0f / 15.0f;
        World world(ws);
        std::vector<BodyId> ids;
        for (int i = 0; i < 20; ++i)
            ids.push_back(world.addBody(
                ball(), sphereAt({dx * float(i % 3), 0.6f + 1.1f * float(i), dz * float(i % 2)})));
        float closest = INFINITY;
        for (int f = 0; f < 300; ++f) {
            world.step();
            ASSERT_TRUE(allFinite(world)) << "frame " << f;
            closest = std::min(closest, closestCentres(world));
        }
        EXPECT_GT(closest, 0.6f);
        EXPECT_GT(lowestVertex(world), -0.01f);
        EXPECT_LE(deepestInside(world, 1.0f), 0.01);
        EXPECT_LT(kineticEnergyPerKilogram(world), 1e-6);
    }
}

// Lattices of a single cell (8 particles, one FFD-AABB box): one dropped tumbling onto the
// floor, and one dropped onto another from 0.7 m above it, offset by (0.2, 0.15) m; 8 s (the
// upper one slides off and tumbles along the floor for up to about 5 s).
// Criteria: every frame finite; the stacked pair's centres never closer than 0.9 m (they
// did not pass through each other); after 8 s no vertex below the floor by more than 1 cm,
// none inside another body deeper than 1 cm, and at rest (below 1e-6 J/kg).
TEST(ExtremeScenes, LatticeOfASingleCell) {
    World world;
    auto single = [](Vec3 p) {
        BodySettings s = sphereAt(p);
        s.lattice.targetCells = 1;
        return s;
    };
    BodySettings tumbling = single({4, 1.5f, 0});
    tumbling.rotation = Quat::fromAxisAngle({1, 0, 1}, 0.7f);
    tumbling.angularVelocity = {1, 2, 0};
    world.addBody(ball(), tumbling);
    const BodyId below = world.addBody(ball(), single({0, 0.5f, 0}));
    const BodyId above = world.addBody(ball(), single({0.2f, 1.7f, 0.15f}));
    ASSERT_EQ(world.info(below).cells, 1u);
    ASSERT_EQ(world.info(below).particles, 8u);
    float closest = INFINITY;
    for (int f = 0; f < 480; ++f) {
        world.step();
        ASSERT_TRUE(allFinite(world)) << "frame " << f;
        closest = std::min(closest, length(world.centreOfMass(above) - world.centreOfMass(below)));
    }
    EXPECT_GT(closest, 0.9f);
    EXPECT_GT(lowestVertex(world), -0.01f);
    EXPECT_LE(deepestInside(world, 1.0f), 0.01);
    EXPECT_LT(kineticEnergyPerKilogram(world), 1e-6);
}

// Two single-cell spheres stacked exactly (same x and z, unrotated), the upper one dropped
// from 0.2 m above the lower one: the upper box's corners lie on the lower box's side planes
// (and the other way round), so the nearest way out of the box for a corner that sinks in is a
// side face. The node-vs-box test settles such near ties by the side the node's own box lies
// on (object_contacts.cpp); before that the upper sphere sank straight through the lower one.
// Criteria: every frame finite; the centres never closer than 0.9 m; after 4 s no vertex
// inside the other body deeper than 1 cm and at rest (below 1e-6 J/kg).
TEST(ExtremeScenes, AlignedSingleCellBoxesStack) {
    World world;
    BodySettings s;
    s.lattice.targetCells = 1;
    s.position = {0, 0.5f, 0};
    const BodyId below = world.addBody(ball(), s);
    s.position = {0, 1.7f, 0};
    const BodyId above = world.addBody(ball(), s);
    float closest = INFINITY;
    for (int f = 0; f < 240; ++f) {
        world.step();
        ASSERT_TRUE(allFinite(world)) << "frame " << f;
        closest = std::min(closest, length(world.centreOfMass(above) - world.centreOfMass(below)));
    }
    EXPECT_GT(closest, 0.9f);
    EXPECT_LE(deepestInside(world, 1.0f), 0.01);
    EXPECT_LT(kineticEnergyPerKilogram(world), 1e-6);
}

// An object of more than a million vertices (Newell's teapot at 180 x 180 quads per patch,
// 1.04 million vertices, in an 84-cell lattice) dropped from 0.5 m; 2 s simulated.
// Criteria: every vertex finite every 10th frame; after 2 s every vertex above the floor
// within 1 % of the size (1.2 cm) and the body at rest (below 1e-3 J/kg). The lattice, not
// the mesh, sets the cost of a step: the frames must stay cheap (the mesh update is linear).
TEST(ExtremeScenes, AMillionVertices) {
    TriangleMesh pot = teapot(180);
    ASSERT_GE(pot.vertexCount(), 1000000u);
    normalizeSize(pot, 1.2f);
    World world;
    BodySettings s;
    s.lattice.targetCells = 84;
    s.position = {0, 1.0f, 0};
    const BodyId id = world.addBody(pot, s);
    EXPECT_EQ(world.info(id).vertices, pot.vertexCount());
    for (int f = 0; f < 120; ++f) {
        world.step();
        if (f % 10 == 0) {
            for (const Vec3& v : world.vertices(id)) ASSERT_TRUE(isFinite(v)) << "frame " << f;
        }
    }
    ASSERT_TRUE(allFinite(world));
    EXPECT_GT(lowestVertex(world), -0.012f);
    EXPECT_LT(kineticEnergyPerKilogram(world), 1e-3);
}

// Spheres created all at one spot (same centre, random rotations), with the overlap recovery
// off so that their box contacts are all found: every box of each sphere overlaps boxes of
// every other. A pair of boxes gives at most four contacts (collision/narrow_phase.h), and only
// a pair whose node bounds come within the pair's margin of each other is tested.
// Criteria: every particle finite for 10 frames (they fly apart: nothing bounds their speed
// with the recovery off); in the first frame at least as many contacts as boxes (they do
// overlap deeply) and at most four per pair of boxes of different spheres whose node bounds
// overlap (grown by 5 cm, more than the margins at rest); the `brute` and `enhanced` modes give
// bit-identical states.
TEST(ExtremeScenes, CoincidentBodiesKeepBoundedContacts) {
    auto run = [](CollisionMode mode) {
        WorldSettings ws;
        ws.mode = mode;
        ws.overlapRecoverySpeed = 0;
        World world(ws);
        test::addBallsAtOneSpot(world, 8, {0, 2, 0}, 3);
        for (int f = 0; f < 10; ++f) {
            world.step();
            EXPECT_TRUE(allFinite(world)) << "frame " << f;
            if (f > 0) continue;
            // In the first frame, at rest (margins of the skin, 1.6 cm): each box's node bounds
            // grown by 5 cm, by body.
            std::vector<std::vector<Aabb>> boxes;
            for (BodyId id : world.bodies()) {
                const auto nodes = world.boxNodes(id);
                auto& list = boxes.emplace_back();
                for (size_t k = 0; k < nodes.size(); k += 8) {
                    Aabb b;
                    for (size_t n = 0; n < 8; ++n) b.add(nodes[k + n]);
                    const Vec3 grow{0.05f, 0.05f, 0.05f};
                    list.push_back({b.lo - grow, b.hi + grow});
                }
            }
            size_t near = 0, count = 0;
            for (size_t a = 0; a < boxes.size(); ++a) {
                count += boxes[a].size();
                for (size_t b = a + 1; b < boxes.size(); ++b)
                    for (const Aabb& x : boxes[a])
                        for (const Aabb& y : boxes[b]) near += x.overlaps(y);
            }
            EXPECT_GT(world.profile().contacts, int(count));
            EXPECT_LE(world.profile().contacts, int(4 * near));
        }
        return world.stateHash();
    };
    EXPECT_EQ(run(CollisionMode::Brute), run(CollisionMode::Enhanced));
}

// Spheres created overlapping at random points of a 10 m cube (as OverlappingSpheresRecover)
// with gravity off, the overlap recovery off and WorldSettings::maxSeparationSpeed = 2 m/s (the
// default, set here so that the test keeps its meaning if the default moves):
// the rigid impact phase does not turn the crushed bodies' deformation speed into rigid motion.
// Criteria: every particle finite; after 1 s every sphere slower than 12 m/s (measured: 10.9 m/s
// with box-pair contacts, 8.7 with node contacts; 53 m/s without a bound).
TEST(ExtremeScenes, OverlappingSpheresSeparateGentlyWithASeparationBound) {
    WorldSettings ws;
    ws.gravity = {};
    ws.overlapRecoverySpeed = 0;
    ws.maxSeparationSpeed = 2;
    World world(ws);
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(-0.5f, 0.5f);
    for (int i = 0; i < 60; ++i) {
        BodySettings s = sphereAt({5 * u(rng), 5 + 5 * u(rng), 5 * u(rng)});
        s.rotation = normalize(Quat{u(rng), u(rng), u(rng), u(rng)});
        world.addBody(ball(), s);
    }
    for (int f = 0; f < 60; ++f) {
        world.step();
        ASSERT_TRUE(allFinite(world)) << "frame " << f;
    }
    float fastest = 0;
    for (BodyId id : world.bodies()) fastest = std::max(fastest, length(world.linearVelocity(id)));
    EXPECT_LT(fastest, 12.0f);
}

// Bodies created overlapping: a sphere created 30 cm deep in the floor, one half buried; two
// spheres (gravity off) created with their centres 0.7 m apart (30 cm into each other), three
// rotations. Run with the default settings (overlap recovery at 2 m/s: the pair is pushed
// apart as whole bodies, the buried spheres' floor contacts push out at 2 m/s) and with the
// recovery off and WorldSettings::pushOutSpeed = 1 m/s (every deep contact pushed out by at
// most the skin plus 1 m/s x substep per substep) (docs/ALGORITHM.md, "Overlap recovery").
// Criteria: every particle finite; the buried spheres never faster than `buried` m/s, out of
// the floor and at rest after 8 s; the pair never faster than `pair` m/s and, after 1 s, out
// of each other (no contact violated by 5 mm or more, the pair no longer remembered). Measured
// (default; push-out): buried 3.3 and 2.4 m/s; 7.1 and 4.4; the pair 0-2.8 m/s; 5.6-10.6 (3.8-5.3
// with node contacts: the box pairs' one normal per pair pushes a deep pair apart along fewer,
// deeper contacts). With neither, the buried spheres are launched at 18 and 25 m/s (one 30 m up)
// and the pair parts at 11.6-14.5 m/s.
TEST(ExtremeScenes, CreatedOverlappingArePushedOutGently) {
    struct Case {
        const char* name;
        float recovery, pushOut, buried, pair;
    };
    for (const Case& c : {Case{"default", 2, 0, 5, 4}, Case{"push-out 1 m/s", 0, 1, 10, 12}}) {
        SCOPED_TRACE(c.name);
        for (const float y : {0.2f, 0.0f}) {
            SCOPED_TRACE("centre at y = " + std::to_string(y));
            WorldSettings ws;
            ws.overlapRecoverySpeed = c.recovery;
            ws.pushOutSpeed = c.pushOut;
            World world(ws);
            world.addBody(ball(), sphereAt({0, y, 0}));
            float fastest = 0;
            for (int f = 0; f < 480; ++f) {
                world.step();
                ASSERT_TRUE(allFinite(world)) << "frame " << f;
                fastest = std::max(fastest, fastestBody(world));
            }
            EXPECT_LT(fastest, c.buried);
            EXPECT_GT(lowestVertex(world), -0.01f);
            EXPECT_LT(kineticEnergyPerKilogram(world), 1e-4);
        }
        for (const int seed : {1, 2, 3}) {
            SCOPED_TRACE("seed " + std::to_string(seed));
            WorldSettings ws;
            ws.gravity = {};
            ws.overlapRecoverySpeed = c.recovery;
            ws.pushOutSpeed = c.pushOut;
            World world(ws);
            std::mt19937 rng{uint32_t(seed)};
            std::uniform_real_distribution<float> u(-0.5f, 0.5f);
            for (int i = 0; i < 2; ++i) {
                BodySettings s = sphereAt({0.7f * float(i), 3, 0});
                s.rotation = normalize(Quat{u(rng), u(rng), u(rng), u(rng)});
                world.addBody(ball(), s);
            }
            float fastest = 0;
            for (int f = 0; f < 60; ++f) {
                world.step();
                ASSERT_TRUE(allFinite(world)) << "frame " << f;
                fastest = std::max(fastest, fastestBody(world));
            }
            EXPECT_LT(fastest, c.pair);
            EXPECT_EQ(world.profile().overlapPairs, 0);
            EXPECT_LT(deepestInside(world), 0.005); // no vertex 5 mm inside the other mesh
        }
    }
}

// The "200 objects created all overlapping in one spot": 200 spheres (1 m) created with
// the same centre, just above the floor, random rotations, default settings. Every pair is
// pushed apart as whole bodies at 2.45 m/s (the heap spreading as a whole) until neither centre is
// within a cell of the other's lattice, then along the way out of its contacts' overlap, by
// positions only, no body's centre faster than 4.5 m/s with its velocity counted
// (docs/ALGORITHM.md, "Overlap recovery"). Criteria: every particle finite every frame; no
// sphere's velocity ever above 5 m/s and no sphere's centre moving faster than 5 m/s from one
// frame to the next (what a viewer sees), as the dense-pile issue asks (measured 3.64 and 4.87 on
// this layout; over the rotations of seeds 1-12 see TwoHundredAtOneSpotApartInThreeSeconds below.
// Before the centre's bound, 2026-12-06, the recovery's moves came on top of the velocity and
// centres moved at up to 5.96-6.55 m/s over those layouts: docs/ALGORITHM.md, "Overlap
// recovery"); after 4.5 s every pair forgotten by the recovery but two at most, no two centres
// closer than 0.9 m, no vertex inside another sphere deeper than 1 cm (the mesh measure) and none
// more than 1 cm below the floor; after 6 s every pair forgotten. (Until 2026-11-27 this test
// checked centres 0.9 m apart after 3 s, which held while a pair was still 5 cm inside each other
// by the meshes.) Without the recovery, 50 spheres at one spot take 2-3 s per frame and never
// separate.
TEST(ExtremeScenes, TwoHundredAtOneSpotSeparate) {
    World world;
    test::addBallsAtOneSpot(world, 200, {0, 0.6f, 0}, 1);
    test::CentreSpeeds centres(world);
    float fastest = 0, fastestCentre = 0;
    int whole = 0;
    for (int f = 0; f < 270; ++f) {
        world.step();
        ASSERT_TRUE(allFinite(world)) << "frame " << f;
        fastest = std::max(fastest, fastestBody(world));
        whole = std::max(whole, world.profile().wholePairs);
        fastestCentre = std::max(fastestCentre, centres.afterStep(world));
    }
    EXPECT_EQ(whole, 200 * 199 / 2); // all at once, at first
    EXPECT_LT(fastest, 5.0f);
    EXPECT_LT(fastestCentre, 5.0f);
    EXPECT_GT(closestCentres(world), 0.9f);
    EXPECT_LE(deepestInside(world), 0.01);
    EXPECT_LE(world.profile().overlapPairs, 2);
    EXPECT_GT(lowestVertex(world), -0.01f);
    for (int f = 270; f < 360; ++f) world.step();
    EXPECT_EQ(world.profile().overlapPairs, 0);
}

// The same 200 spheres at one spot, with the rotations of seeds 1-6: the dense-pile issue asks
// them apart within 3 s. Criterion: after 180 frames no vertex inside another sphere deeper than
// 1 cm (the mesh measure). Measured 2026-12-06 with the recovery at 2.45 m/s and centres bounded
// to 4.5 m/s (docs/ALGORITHM.md, "Overlap recovery"): apart, sampled every 10 frames, in
// 3.00, 2.83, 3.00, 3.00, 3.00 and 3.00 s, 2.83-3.00 s over seeds 1-12, no sphere faster than
// 3.01-4.05 m/s, no centre faster than 4.65-4.87 m/s between frames. At 2.25 m/s without the
// centre's bound 2.67-3.00 s, velocities 2.74-4.00, centres 5.96-6.55; pushed by their pairs
// alone 3.0-3.5 s (a known bug until then). The first failure ends it.
TEST(ExtremeScenes, TwoHundredAtOneSpotApartInThreeSeconds) {
    for (const unsigned seed : {1u, 3u, 5u, 6u, 4u, 2u}) {
        SCOPED_TRACE("seed " + std::to_string(seed));
        World world;
        test::addBallsAtOneSpot(world, 200, {0, 0.6f, 0}, seed);
        for (int f = 0; f < 180; ++f) world.step();
        ASSERT_LE(deepestInside(world), 0.01);
    }
}

// 200 spheres (1 m) created overlapping at random points of a 10 m cube with random rotations
// (about a tenth of the cube's volume is sphere, so most overlap a neighbour), gravity off,
// default settings.
// Criteria: every sphere finite, never faster than 8 m/s and within 10 m of where it started
// after 1 s (measured 6.0 m/s; 44 m/s with the recovery off: the rigid impact phase turned the
// crushed spheres' deformation speed into rigid motion).
TEST(ExtremeScenes, OverlappingSpheresRecover) {
    WorldSettings ws;
    ws.gravity = {};
    World world(ws);
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(-0.5f, 0.5f);
    std::vector<Vec3> start;
    for (int i = 0; i < 200; ++i) {
        BodySettings s = sphereAt({10 * u(rng), 5.5f + 10 * u(rng), 10 * u(rng)});
        s.rotation = normalize(Quat{u(rng), u(rng), u(rng), u(rng)});
        world.addBody(ball(), s);
        start.push_back(s.position);
    }
    float fastest = 0;
    for (int f = 0; f < 60; ++f) {
        world.step();
        ASSERT_TRUE(allFinite(world)) << "frame " << f;
        fastest = std::max(fastest, fastestBody(world));
    }
    EXPECT_LT(fastest, 8.0f);
    const std::vector<BodyId> ids = world.bodies();
    for (size_t i = 0; i < ids.size(); ++i)
        EXPECT_LT(length(world.centreOfMass(ids[i]) - start[i]), 10.0f) << "sphere " << i;
}
