// Snapshots (World::saveState / restoreState): a state restored into a world built from the same
// scene, or into the same world, steps on bit for bit as the world that never stopped; bytes
// that are not such a state are refused, naming what differs, and leave the world unchanged.
#include "ffdaabb/error.h"
#include "ffdaabb/generators.h"
#include "ffdaabb/scene.h"
#include "ffdaabb/world.h"

#include "test_support.h"
#include "world/world_data.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <random>
#include <string>
#include <vector>

using namespace ffd;
using ffd::test::ball;
using ffd::test::sphereAt;
using Bytes = std::vector<uint8_t>;

namespace {

// The layout the format documents (src/world/snapshot.cpp): a 32-byte header (magic, version,
// reserved, payload bytes, payload checksum), then tagged, length-prefixed sections.
constexpr size_t kHeader = 32;

uint64_t readU64(const Bytes& b, size_t at) {
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v |= uint64_t(b[at + size_t(i)]) << (8 * i);
    return v;
}
uint32_t readU32(const Bytes& b, size_t at) {
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= uint32_t(b[at + size_t(i)]) << (8 * i);
    return v;
}
void writeU64(Bytes& b, size_t at, uint64_t v) {
    for (int i = 0; i < 8; ++i) b[at + size_t(i)] = uint8_t(v >> (8 * i));
}
void writeU32(Bytes& b, size_t at, uint32_t v) {
    for (int i = 0; i < 4; ++i) b[at + size_t(i)] = uint8_t(v >> (8 * i));
}

// The documented checksum: FNV-1a over the payload's 64-bit little-endian words, each step's
// high half folded into its low half, then its last bytes one by one.
uint64_t checksum(const uint8_t* p, size_t n) {
    uint64_t h = 14695981039346656037ull;
    size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        uint64_t w = 0;
        for (int k = 0; k < 8; ++k) w |= uint64_t(p[i + size_t(k)]) << (8 * k);
        h = (h ^ w) * 1099511628211ull;
        h ^= h >> 32;
    }
    for (; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
    return h;
}

// After an edit of the payload: its size and checksum in the header made right again, so that
// what is refused is the edit itself.
void reseal(Bytes& b) {
    writeU64(b, 16, b.size() - kHeader);
    writeU64(b, 24, checksum(b.data() + kHeader, b.size() - kHeader));
}

uint32_t tag(const char (&name)[5]) {
    return uint32_t(uint8_t(name[0])) | uint32_t(uint8_t(name[1])) << 8 |
           uint32_t(uint8_t(name[2])) << 16 | uint32_t(uint8_t(name[3])) << 24;
}

// Where the section `name`'s bytes start, and their length.
std::pair<size_t, size_t> findSection(const Bytes& b, const char (&name)[5]) {
    for (size_t at = kHeader; at + 16 <= b.size();) {
        const size_t length = size_t(readU64(b, at + 8));
        if (readU32(b, at) == tag(name)) return {at + 16, length};
        at += 16 + length;
    }
    ADD_FAILURE() << "no section " << name;
    return {0, 0};
}

// Replaces the section `name`'s bytes.
void replaceSection(Bytes& b, const char (&name)[5], const Bytes& content) {
    const auto [at, length] = findSection(b, name);
    b.erase(b.begin() + ptrdiff_t(at), b.begin() + ptrdiff_t(at + length));
    b.insert(b.begin() + ptrdiff_t(at), content.begin(), content.end());
    writeU64(b, at - 8, content.size());
    reseal(b);
}

// The InputError message restoreState throws, or "" when it accepts the bytes.
std::string refusal(World& world, const Bytes& bytes) {
    try {
        world.restoreState(bytes);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

SceneBuild build(const std::string& name, int threads = 1) {
    Scene scene = loadScene(name);
    scene.world.threads = threads;
    return buildScene(scene);
}

double secondsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Balls stacked in a column over the floor (poses a little apart, so that they pile).
std::vector<BodyId> addBalls(World& world, int count, float y = 0.6f) {
    std::vector<BodyId> ids;
    for (int i = 0; i < count; ++i)
        ids.push_back(world.addBody(
            ball(), sphereAt({0.3f * float(i % 3), y + 1.1f * float(i), 0.2f * float(i % 2)})));
    return ids;
}

// The state hashes of the next `frames` frames.
std::vector<uint64_t> hashesOfNext(World& world, int frames) {
    std::vector<uint64_t> hashes;
    for (int f = 0; f < frames; ++f) {
        world.step();
        hashes.push_back(world.stateHash());
    }
    return hashes;
}

// A smaller one_spot (examples/one_spot.json): `count` spheres created at one spot, which the
// overlap recovery pushes apart.
Scene oneSpot(int count) {
    Scene scene = loadScene(FFD_SOURCE_DIR "/examples/one_spot.json");
    setObjectCount(scene, count);
    return scene;
}

} // namespace

// The property, on every paper scene at full size: saved at frame 100 and restored into
// a world built afresh from the same scene (on another thread count), the world steps on with
// the same state hash every frame as the world that never stopped, and ends in the same state
// (its saved bytes equal).
class PaperScene : public ::testing::TestWithParam<std::pair<const char*, int>> {};

TEST_P(PaperScene, SavedAtFrame100AndRestoredStepsOnBitForBit) {
    const auto [name, frames] = GetParam();
    const auto t0 = std::chrono::steady_clock::now();
    SceneBuild uninterrupted = build(name, 1);
    for (int f = 0; f < 100; ++f) uninterrupted.world.step();
    const auto t1 = std::chrono::steady_clock::now();
    const Bytes saved = uninterrupted.world.saveState();
    const double saveSeconds = secondsSince(t1);
    std::vector<uint64_t> hashes;
    for (int f = 0; f < frames; ++f) {
        uninterrupted.world.step();
        hashes.push_back(uninterrupted.world.stateHash());
    }

    SceneBuild restored = build(name, 2);
    ASSERT_NE(restored.world.stateHash(), uninterrupted.world.stateHash());
    const auto t2 = std::chrono::steady_clock::now();
    restored.world.restoreState(saved);
    const double restoreSeconds = secondsSince(t2);
    EXPECT_EQ(restored.world.frame(), 100u);
    EXPECT_EQ(restored.world.saveState(), saved); // restored is exactly what was saved
    for (int f = 0; f < frames; ++f) {
        restored.world.step();
        ASSERT_EQ(restored.world.stateHash(), hashes[size_t(f)])
            << name << ": differs " << f + 1 << " frames after the restore";
    }
    EXPECT_EQ(restored.world.frame(), uninterrupted.world.frame());
    EXPECT_EQ(restored.world.saveState(), uninterrupted.world.saveState());
    std::printf("%s: %zu bytes of state (saved in %.1f ms, restored in %.1f ms), 100 + %d "
                "frames, restored and compared in %.1f s\n",
                name, saved.size(), 1e3 * saveSeconds, 1e3 * restoreSeconds, frames,
                secondsSince(t0));
}

INSTANTIATE_TEST_SUITE_P(Snapshot, PaperScene,
                         ::testing::Values(std::pair{"alphabets", 60}, std::pair{"spheres", 60},
                                           std::pair{"teapots", 60}, std::pair{"buddhas", 60}),
                         [](const auto& param) { return std::string(param.param.first); });

// Bodies removed and added (free slots, bumped generations), a ball teleported into another
// (placed: the overlap recovery will remember the pair), forces pending: restored into a world
// of the same bodies built without that history, the handles are the saved world's and the
// world steps on bit for bit.
TEST(Snapshot, RemovedAndAddedBodiesKeepTheirHandles) {
    // The other dynamics too: a mass-spring ball and one damped per region, dropped on the pile.
    BodySettings springs = sphereAt({0.2f, 10, 0}), regions = sphereAt({-0.2f, 11.5f, 0});
    springs.model = DynamicsModel::MassSpring;
    regions.regionDamping = true;
    World saved;
    std::vector<BodyId> ids = addBalls(saved, 8);
    saved.addBody(ball(), springs);
    saved.addBody(ball(), regions);
    for (int f = 0; f < 40; ++f) saved.step();
    ASSERT_TRUE(saved.removeBody(ids[2]));
    ASSERT_TRUE(saved.removeBody(ids[5]));
    const BodyId added = saved.addBody(ball(), sphereAt({-2, 0.6f, 0}));
    EXPECT_EQ(added.index, ids[5].index); // the last freed slot, a new generation
    for (int f = 0; f < 20; ++f) saved.step();
    saved.translate(ids[0],
                    saved.centreOfMass(ids[1]) - saved.centreOfMass(ids[0]) + Vec3{0.1f, 0, 0});
    saved.applyForce(ids[3], {40, 0, 0});
    saved.applyParticleForce(ids[4], 0, {0, 30, 0});
    const auto& sd = detail::dataOf(saved);
    ASSERT_FALSE(sd.collision.claims.empty()); // the pile's box pairs have claims
    ASSERT_FALSE(sd.freeSlots.empty());
    ASSERT_TRUE(sd.collision.bodies[sd.slots[ids[0].index].dense].placed);
    const Bytes state = saved.saveState();
    const std::vector<BodyId> handles = saved.bodies();
    const std::vector<uint64_t> hashes = hashesOfNext(saved, 60);

    World restored;
    addBalls(restored, 6, 5.0f); // the same bodies, in the same order, elsewhere, no history
    restored.addBody(ball(), springs);
    restored.addBody(ball(), regions);
    addBalls(restored, 1, 20.0f);
    EXPECT_NE(restored.bodies(), handles);
    restored.restoreState(state);
    EXPECT_EQ(restored.bodies(), handles);
    EXPECT_FALSE(restored.isValid(ids[2]));
    EXPECT_FALSE(restored.isValid(ids[5]));
    EXPECT_TRUE(restored.isValid(added));
    EXPECT_EQ(restored.settings(ids[7]).position.y, saved.settings(ids[7]).position.y);
    EXPECT_EQ(hashesOfNext(restored, 60), hashes);
    // And both hand out the same handle next.
    EXPECT_EQ(restored.addBody(ball(), sphereAt({3, 1, 0})),
              saved.addBody(ball(), sphereAt({3, 1, 0})));
    EXPECT_EQ(restored.saveState(), saved.saveState());
}

// Rewinding: a world restored to a state it saved earlier steps through the same states again.
TEST(Snapshot, RewindsTheSameWorld) {
    SceneBuild scene = build("spheres");
    for (int f = 0; f < 100; ++f) scene.world.step();
    const Bytes state = scene.world.saveState();
    const std::vector<uint64_t> hashes = hashesOfNext(scene.world, 30);
    std::vector<ContactInfo> contacts;
    scene.world.contacts(contacts);
    EXPECT_FALSE(contacts.empty());
    scene.world.restoreState(state);
    EXPECT_EQ(scene.world.frame(), 100u);
    scene.world.contacts(contacts);
    EXPECT_TRUE(contacts.empty()); // the last step's contacts are not part of the state
    EXPECT_EQ(scene.world.saveState(), state);
    EXPECT_EQ(hashesOfNext(scene.world, 30), hashes);
}

// The overlap recovery's pairs (bodies created at one spot, pushed apart over many frames)
// survive a restore into a fresh world.
TEST(Snapshot, OverlapRecoveryRoundTrips) {
    const Scene scene = oneSpot(40);
    SceneBuild saved = buildScene(scene);
    for (int f = 0; f < 10; ++f) saved.world.step();
    ASSERT_FALSE(detail::dataOf(saved.world).collision.overlaps.empty());
    const Bytes state = saved.world.saveState();
    const std::vector<uint64_t> hashes = hashesOfNext(saved.world, 40);
    SceneBuild restored = buildScene(scene);
    restored.world.restoreState(state);
    EXPECT_EQ(hashesOfNext(restored.world, 40), hashes);
    // Saved right after the bodies were placed (frame 0, every body placed) and restored into a
    // world of the same scene that has stepped: the recovery starts over from the same place.
    SceneBuild atStart = buildScene(scene);
    const Bytes first = atStart.world.saveState();
    const std::vector<uint64_t> firstHashes = hashesOfNext(atStart.world, 10);
    restored.world.restoreState(first);
    EXPECT_EQ(restored.world.frame(), 0u);
    EXPECT_EQ(hashesOfNext(restored.world, 10), firstHashes);
}

TEST(Snapshot, SleepingBodiesRoundTripAndWakeAlike) {
    // Spheres, some asleep and some still settling: saved, restored into a fresh world, they
    // sleep and wake frame for frame as in the world that never stopped, also when a sleeper is
    // woken by hand after the restore.
    Scene scene = loadScene("spheres");
    setObjectCount(scene, 30);
    SceneBuild saved = buildScene(scene);
    int f = 0;
    for (; f < 900 && (saved.world.profile().sleepingBodies == 0 || saved.world.awakeCount() == 0);
         ++f)
        saved.world.step();
    ASSERT_GT(saved.world.profile().sleepingBodies, 0) << "nothing slept in " << f << " frames";
    const Bytes state = saved.world.saveState();
    SceneBuild restored = buildScene(scene);
    restored.world.restoreState(state);
    EXPECT_EQ(restored.world.awakeCount(), saved.world.awakeCount());
    const std::vector<BodyId> ids = saved.world.bodies();
    for (World* w : {&saved.world, &restored.world}) {
        for (const BodyId id : ids) EXPECT_EQ(w->isAwake(id), saved.world.isAwake(id));
    }
    EXPECT_EQ(hashesOfNext(restored.world, 60), hashesOfNext(saved.world, 60));
    for (World* w : {&saved.world, &restored.world})
        for (const BodyId id : ids)
            if (!w->isAwake(id)) {
                w->applyImpulse(id, {0, 50, 0});
                break;
            }
    EXPECT_EQ(hashesOfNext(restored.world, 30), hashesOfNext(saved.world, 30));
    EXPECT_EQ(restored.world.awakeCount(), saved.world.awakeCount());
}

TEST(Snapshot, PinsRoundTripWithTheirHandles) {
    // A ball swinging from a pin whose target moves every frame, saved mid-swing and restored
    // into a world of the same ball that was never pinned: the restored pin has the same
    // handle and the two worlds step on alike.
    auto target = [](int frame) { return Vec3{0.02f * float(frame), 2.5f, 0}; };
    World saved;
    const BodyId b = saved.addBody(ball(), sphereAt({0.4f, 2.0f, 0}));
    const PinId pin = saved.pinParticle(b, 0, target(0));
    int f = 0;
    for (; f < 40; ++f) {
        saved.setPinTarget(pin, target(f));
        saved.step();
    }
    const Bytes state = saved.saveState();
    World restored;
    restored.addBody(ball(), sphereAt({0.4f, 2.0f, 0}));
    restored.restoreState(state);
    ASSERT_TRUE(restored.isValid(pin));
    EXPECT_EQ(restored.pins(), saved.pins());
    for (int k = 0; k < 40; ++k, ++f) {
        for (World* w : {&saved, &restored}) {
            w->setPinTarget(pin, target(f));
            w->step();
        }
        ASSERT_EQ(restored.stateHash(), saved.stateHash()) << "frame " << f;
    }
    EXPECT_EQ(restored.pin(pin).force, saved.pin(pin).force);
}

TEST(Snapshot, RefusesAWorldWithOtherPlanes) {
    auto make = [](int planes, float offset) {
        World w;
        w.addBody(ball(), sphereAt({0, 1, 0}));
        for (int k = 0; k < planes; ++k) w.addPlane(normalize(Vec3{1, 1, 0}), offset);
        return w;
    };
    World saved = make(1, -2.0f);
    for (int f = 0; f < 10; ++f) saved.step();
    const Bytes state = saved.saveState();
    World none = make(0, -2.0f);
    EXPECT_NE(refusal(none, state).find("planes 1, this world has 0"), std::string::npos)
        << refusal(none, state);
    World elsewhere = make(1, -1.0f);
    EXPECT_NE(refusal(elsewhere, state).find("planes.layout"), std::string::npos)
        << refusal(elsewhere, state);
    World same = make(1, -2.0f);
    EXPECT_EQ(refusal(same, state), "");
}

// The comparisons above would catch a snapshot that left out any of these: each, reset to what
// a freshly built world holds after a restore, changes the very next frame.
TEST(Snapshot, EveryPieceOfTheStateChangesTheNextFrame) {
    struct Case {
        const char* what;
        bool oneSpot;
        void (*reset)(detail::WorldData&, const detail::WorldData& fresh);
    };
    const Case cases[] = {
        {"placed", false,
         [](detail::WorldData& w, const detail::WorldData&) {
             for (detail::CollisionBody& c : w.collision.bodies) c.placed = true;
         }},
        {"halfKick", false,
         [](detail::WorldData& w, const detail::WorldData&) {
             for (detail::BodyRecord& r : w.bodies) r.halfKick = true;
         }},
        {"claims", false,
         [](detail::WorldData& w, const detail::WorldData&) { w.collision.claims.clear(); }},
        {"rotations", false,
         [](detail::WorldData& w, const detail::WorldData& fresh) {
             w.rotations = fresh.rotations;
         }},
        {"rotationSteps", false,
         [](detail::WorldData& w, const detail::WorldData& fresh) {
             w.rotationSteps = fresh.rotationSteps;
         }},
        {"overlaps", true,
         [](detail::WorldData& w, const detail::WorldData&) { w.collision.overlaps.clear(); }},
    };
    for (const bool spot : {false, true}) {
        const Scene scene = spot ? oneSpot(40) : loadScene("spheres");
        SceneBuild saved = buildScene(scene);
        SceneBuild fresh = buildScene(scene);
        detail::WorldData reference; // what a freshly built world holds
        reference.rotations = detail::dataOf(fresh.world).rotations;
        reference.rotationSteps = detail::dataOf(fresh.world).rotationSteps;
        World& restored = fresh.world;
        for (int f = 0; f < (spot ? 10 : 1); ++f) saved.world.step();
        Bytes state = saved.world.saveState();
        saved.world.step();
        uint64_t next = saved.world.stateHash();
        // Whether resetting each piece changes the next frame.
        auto everyPieceCounts = [&] {
            for (const Case& c : cases) {
                if (c.oneSpot != spot) continue;
                restored.restoreState(state);
                c.reset(detail::dataOf(restored), reference);
                restored.step();
                if (restored.stateHash() == next) return false;
            }
            return true;
        };
        // The spheres from frame 1 on, to the first frame whose next one depends on every
        // piece: at many frames of this pile, for example, no box pair has a claim bounding its
        // depth, and clearing the claims changes nothing there.
        for (int f = 1; !spot && !everyPieceCounts(); ++f) {
            ASSERT_LT(f, 400) << "no frame of the spheres depends on every piece";
            state = saved.world.saveState();
            saved.world.step();
            next = saved.world.stateHash();
        }
        restored.restoreState(state);
        restored.step();
        EXPECT_EQ(restored.stateHash(), next); // the whole state: the same next frame
        for (const Case& c : cases) {
            if (c.oneSpot != spot) continue;
            restored.restoreState(state); // a rewind restores every piece
            c.reset(detail::dataOf(restored), reference);
            restored.step();
            EXPECT_NE(restored.stateHash(), next) << c.what;
        }
    }
}

// A state names the scene it belongs to: restored into a world of other bodies or settings it
// is refused with what differs, and the world is left as it was. The thread count may differ.
TEST(Snapshot, RefusesAnotherSceneNamingWhatDiffers) {
    auto world = [](auto&& edit) {
        WorldSettings ws;
        BodySettings bs = sphereAt({0, 0.6f, 0});
        TriangleMesh mesh = ball();
        edit(ws, bs, mesh);
        World w(ws);
        w.addBody(ball(), sphereAt({1.5f, 0.6f, 0}));
        w.addBody(mesh, bs);
        w.addBody(ball(), sphereAt({-1.5f, 0.6f, 0}));
        for (int f = 0; f < 5; ++f) w.step();
        return w;
    };
    auto same = [](WorldSettings&, BodySettings&, TriangleMesh&) {};
    const Bytes state = world(same).saveState();
    struct Case {
        const char* expected;
        void (*edit)(WorldSettings&, BodySettings&, TriangleMesh&);
    };
    const Case cases[] = {
        {"saved with the world setting substeps 2, this world has 3",
         [](WorldSettings& w, BodySettings&, TriangleMesh&) { w.substeps = 3; }},
        {"saved with the world setting mode enhanced, this world has previous",
         [](WorldSettings& w, BodySettings&, TriangleMesh&) { w.mode = CollisionMode::Previous; }},
        {"saved with the world setting gravity.y -9.81, this world has -5",
         [](WorldSettings& w, BodySettings&, TriangleMesh&) { w.gravity.y = -5; }},
        {"saved with body 1 (of 3, in the order added) of friction 0.5, this world has 0.8",
         [](WorldSettings&, BodySettings& b, TriangleMesh&) { b.friction = 0.8f; }},
        {"saved with body 1 (of 3, in the order added) of lattice.targetCells 38, this world has "
         "64",
         [](WorldSettings&, BodySettings& b, TriangleMesh&) { b.lattice.targetCells = 64; }},
        {"saved with body 1 (of 3, in the order added) of model shape-matching, this world has "
         "mass-spring",
         [](WorldSettings&, BodySettings& b, TriangleMesh&) {
             b.model = DynamicsModel::MassSpring;
         }},
        {"saved with body 1 (of 3, in the order added) made from another mesh",
         [](WorldSettings&, BodySettings&, TriangleMesh& m) { m.positions[0].x *= 1.01f; }},
    };
    for (const Case& c : cases) {
        World other = world(c.edit);
        const Bytes before = other.saveState();
        const std::string message = refusal(other, state);
        EXPECT_NE(message.find(c.expected), std::string::npos) << message;
        EXPECT_EQ(message.rfind("state: ", 0), 0u) << message;
        EXPECT_EQ(other.saveState(), before) << c.expected; // unchanged
    }
    World two;
    addBalls(two, 2);
    EXPECT_EQ(refusal(two, state), "state: saved from a scene of 3 bodies, this world has 2");
    // Another thread count, and another pose of the bodies, are the same scene.
    World threads = world([](WorldSettings& w, BodySettings& b, TriangleMesh&) {
        w.threads = 2;
        b.position = {0, 3, 0};
    });
    EXPECT_EQ(refusal(threads, state), "");
    EXPECT_EQ(threads.saveState().size(), state.size());
}

// Bytes that are not a complete state of this format and build are refused with what is wrong
// with them; the world is left unchanged.
TEST(Snapshot, RefusesBytesThatAreNotAState) {
    World world;
    addBalls(world, 3);
    for (int f = 0; f < 30; ++f) world.step();
    const Bytes state = world.saveState();
    for (int f = 0; f < 5; ++f) world.step();
    const Bytes before = world.saveState();
    auto expectRefused = [&](const Bytes& bytes, const std::string& expected) {
        const std::string message = refusal(world, bytes);
        EXPECT_NE(message.find(expected), std::string::npos)
            << "expected \"" << expected << "\", got \"" << message << "\"";
        EXPECT_EQ(world.saveState(), before) << expected;
    };
    expectRefused({}, "state: not an ffdaabb state");
    expectRefused(Bytes{'h', 'e', 'l', 'l', 'o'}, "state: not an ffdaabb state");
    expectRefused(Bytes(state.begin(), state.begin() + 20), "state: truncated: 20 bytes, shorter");
    Bytes b = state;
    writeU32(b, 8, 1); // the format before the checksum's fold
    expectRefused(b, "state: format version 1, this build reads version 2");
    b = state;
    b.pop_back();
    expectRefused(b, "state: truncated: the header announces");
    b = state;
    b.push_back(0);
    expectRefused(b, "state: malformed: 1 bytes after the state's end (expected none)");
    b = state;
    b[b.size() / 2] ^= 0x10;
    expectRefused(b, "state: corrupted: its checksum does not match");
    // The top bit of two consecutive words: without the fold a product carries a change only
    // upwards, so the first flip changed only the sum's top bit and the second undid it.
    b = state;
    b[kHeader + 7] ^= 0x80;
    b[kHeader + 15] ^= 0x80;
    expectRefused(b, "state: corrupted: its checksum does not match");
    b = state;
    b[12] = 1;
    expectRefused(b, "state: malformed: the header's reserved field is not 0");
    // Another build: the same bytes but for the build they name (checksum made right).
    b = state;
    const std::string build = "ffdaabb 9.9.9, state format 1, GCC 99, Release, x86-64";
    Bytes named(4, 0);
    writeU32(named, 0, uint32_t(build.size()));
    named.insert(named.end(), build.begin(), build.end());
    replaceSection(b, "BILD", named);
    expectRefused(b, "state: saved by another build (ffdaabb 9.9.9, state format 1, GCC 99, "
                     "Release, x86-64); this is ffdaabb ");
    // A section this build does not know (state it could not restore), and one missing.
    b = state;
    const Bytes extra = {'X', 'T', 'R', 'A', 1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 7};
    b.insert(b.end(), extra.begin(), extra.end());
    reseal(b);
    expectRefused(b, "state: holds a section this build does not know (XTRA)");
    b = state;
    {
        const auto [at, length] = findSection(b, "VERT");
        b.erase(b.begin() + ptrdiff_t(at - 16), b.begin() + ptrdiff_t(at + length));
        reseal(b);
    }
    expectRefused(b, "state: malformed: section VERT is missing");
    // Sealed but inconsistent: a slot that names a body that does not exist.
    b = state;
    writeU32(b, findSection(b, "SLOT").first + 8, 7);
    reseal(b);
    expectRefused(b, "state: malformed: section SLOT gives slot 0 body 7");
    // A non-finite position.
    b = state;
    writeU32(b, findSection(b, "PART").first + 8, 0x7FC00000u);
    reseal(b);
    expectRefused(b, "state: malformed: section PART holds a non-finite position (0)");
    EXPECT_EQ(refusal(world, state), ""); // and the state itself is fine
}

// Random damage never crashes a restore: flipped bytes and truncations are refused (the
// checksum and the header catch them all), and damage sealed with a right checksum is either
// refused, leaving the world unchanged, or a state the world takes.
TEST(Snapshot, RandomDamageIsRefusedAndNeverCrashes) {
    World world;
    addBalls(world, 4);
    for (int f = 0; f < 40; ++f) world.step();
    const Bytes state = world.saveState();
    const Bytes before = world.saveState();
    std::mt19937 random(18);
    int refused = 0, sealedRefused = 0, sealedTaken = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        Bytes b = state;
        const int kind = trial % 3;
        if (kind == 0) {
            b.resize(std::uniform_int_distribution<size_t>(0, b.size() - 1)(random));
        } else {
            const int flips = 1 + int(random() % 8);
            for (int k = 0; k < flips; ++k) {
                // Half of the flips in the header and the section framing's first bytes.
                const size_t limit = random() % 2 ? 200 : b.size();
                b[random() % limit] ^= uint8_t(1u << (random() % 8));
            }
            if (b == state) continue;
            if (kind == 2 && b.size() > kHeader) reseal(b); // past the checksum
        }
        const std::string message = refusal(world, b);
        if (kind == 2) {
            if (message.empty()) {
                ++sealedTaken;
                world.restoreState(state);
            } else {
                ++sealedRefused;
                ASSERT_EQ(world.saveState(), before) << message;
            }
            continue;
        }
        ASSERT_FALSE(message.empty()) << "trial " << trial << " was taken";
        ASSERT_EQ(message.rfind("state: ", 0), 0u) << message;
        ++refused;
        if (trial % 10 == 0) {
            ASSERT_EQ(world.saveState(), before);
        }
    }
    EXPECT_GT(refused, 1900);
    EXPECT_GT(sealedRefused, 0);
    std::printf("%d damaged states refused; of the resealed ones %d refused, %d taken\n", refused,
                sealedRefused, sealedTaken);
}

// The bytes depend on the state alone: saved twice, or from two worlds built alike, they are
// the same; they start with the format's magic.
TEST(Snapshot, BytesDependOnTheStateAlone) {
    World a, b(WorldSettings{.threads = 2});
    addBalls(a, 3);
    addBalls(b, 3);
    for (int f = 0; f < 20; ++f) a.step(), b.step();
    const Bytes state = a.saveState();
    EXPECT_EQ(a.saveState(), state);
    EXPECT_EQ(b.saveState(), state); // threads are not part of the state
    ASSERT_GT(state.size(), kHeader);
    EXPECT_EQ(std::string(state.begin(), state.begin() + 8), "FFDSTATE");
    EXPECT_EQ(readU64(state, 16), state.size() - kHeader);
}
