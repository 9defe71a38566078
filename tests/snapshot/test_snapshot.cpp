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

// The documented checksum: FNV-1a over the payload's 64-bit little-endian words, then its last
// bytes one by one.
uint64_t checksum(const uint8_t* p, size_t n) {
    uint64_t h = 14695981039346656037ull;
    size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        uint64_t w = 0;
        for (int k = 0; k < 8; ++k) w |= uint64_t(p[i + size_t(k)]) << (8 * k);
        h = (h ^ w) * 1099511628211ull;
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
    const Bytes saved = uninterrupted.world.saveState();
    std::vector<uint64_t> hashes;
    for (int f = 0; f < frames; ++f) {
        uninterrupted.world.step();
        hashes.push_back(uninterrupted.world.stateHash());
    }

    SceneBuild restored = build(name, 2);
    ASSERT_NE(restored.world.stateHash(), uninterrupted.world.stateHash());
    restored.world.restoreState(saved);
    EXPECT_EQ(restored.world.frame(), 100u);
    EXPECT_EQ(restored.world.saveState(), saved); // restored is exactly what was saved
    for (int f = 0; f < frames; ++f) {
        restored.world.step();
        ASSERT_EQ(restored.world.stateHash(), hashes[size_t(f)])
            << name << ": differs " << f + 1 << " frames after the restore";
    }
    EXPECT_EQ(restored.world.frame(), uninterrupted.world.frame());
    EXPECT_EQ(restored.world.saveState(), uninterrupted.world.saveState());
    std::printf("%s: %zu bytes of state, 100 + %d frames, restored and compared in %.1f s\n", name,
                saved.size(), frames, secondsSince(t0));
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
    World saved;
    std::vector<BodyId> ids = addBalls(saved, 8);
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
    addBalls(restored, 7, 5.0f); // the same bodies, elsewhere, no history
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
        for (int f = 0; f < (spot ? 10 : 100); ++f) saved.world.step();
        const Bytes state = saved.world.saveState();
        saved.world.step();
        const uint64_t next = saved.world.stateHash();
        SceneBuild fresh = buildScene(scene);
        const detail::WorldData& freshData = detail::dataOf(fresh.world);
        const std::vector<Quat> rotations = freshData.rotations, steps = freshData.rotationSteps;
        for (const Case& c : cases) {
            if (c.oneSpot != spot) continue;
            World restored = std::move(buildScene(scene).world);
            restored.restoreState(state);
            detail::WorldData& w = detail::dataOf(restored);
            detail::WorldData reference;
            reference.rotations = rotations;
            reference.rotationSteps = steps;
            c.reset(w, reference);
            restored.step();
            EXPECT_NE(restored.stateHash(), next) << c.what;
        }
    }
}
