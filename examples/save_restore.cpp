// Snapshots: saves a pile of teapots and spheres mid-fall to a file, restores it into a world
// built afresh (as a later run of a program would) and into the same world (a rewind), and
// shows that both step on to exactly the state the world that never stopped reaches. Then a
// world of other bodies refuses the file, saying what differs.
#include <ffdaabb/error.h>
#include <ffdaabb/generators.h>
#include <ffdaabb/world.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

namespace {

// The scene: both a saving and a restoring program build it the same way (the same bodies, in
// the same order, with the same settings).
ffd::World buildWorld(int spheres) {
    ffd::World world;
    ffd::TriangleMesh teapot = ffd::teapot(6);
    ffd::normalizeSize(teapot, 0.8f);
    ffd::TriangleMesh sphere = ffd::icosphere(2);
    ffd::transform(sphere, 0.3f, {});
    ffd::BodySettings s;
    s.lattice.targetCells = 84;
    for (int i = 0; i < 3; ++i) {
        s.position = {0.9f * float(i - 1), 0.6f + 0.3f * float(i), 0};
        world.addBody(teapot, s);
    }
    s.lattice.targetCells = 38;
    for (int i = 0; i < spheres; ++i) {
        s.position = {0.5f * float(i % 3 - 1), 1.8f + 0.7f * float(i / 3), 0.1f * float(i % 2)};
        world.addBody(sphere, s);
    }
    return world;
}

uint64_t hashAfter(ffd::World& world, int frames) {
    for (int f = 0; f < frames; ++f) world.step();
    return world.stateHash();
}

} // namespace

int main() {
    const std::filesystem::path file =
        std::filesystem::temp_directory_path() / "ffdaabb_save_restore.state";

    // One program: 90 frames, then the state to a file, then on.
    ffd::World world = buildWorld(9);
    for (int f = 0; f < 90; ++f) world.step();
    const std::vector<uint8_t> saved = world.saveState();
    std::ofstream(file, std::ios::binary)
        .write(reinterpret_cast<const char*>(saved.data()), std::streamsize(saved.size()));
    const uint64_t uninterrupted = hashAfter(world, 120);
    std::printf("saved frame 90 (%zu bytes) to %s\n", saved.size(), file.string().c_str());
    std::printf("never stopped:      frame %llu, state hash %016llx\n",
                static_cast<unsigned long long>(world.frame()),
                static_cast<unsigned long long>(uninterrupted));

    // A later program: the same scene built afresh, the state read back, then on.
    std::ifstream in(file, std::ios::binary);
    const std::vector<uint8_t> bytes{std::istreambuf_iterator<char>(in), {}};
    ffd::World later = buildWorld(9);
    later.restoreState(bytes);
    const uint64_t restored = hashAfter(later, 120);
    std::printf("restored afresh:    frame %llu, state hash %016llx\n",
                static_cast<unsigned long long>(later.frame()),
                static_cast<unsigned long long>(restored));

    // A rewind: the first world back to frame 90, then on again.
    world.restoreState(saved);
    const uint64_t rewound = hashAfter(world, 120);
    std::printf("rewound:            frame %llu, state hash %016llx\n",
                static_cast<unsigned long long>(world.frame()),
                static_cast<unsigned long long>(rewound));

    // A world of other bodies refuses the state, and is left as it was.
    ffd::World other = buildWorld(8);
    try {
        other.restoreState(bytes);
        std::printf("a world of other bodies took the state\n");
        return 1;
    } catch (const ffd::InputError& e) {
        std::printf("a world of other bodies refuses it: %s\n", e.what());
    }
    std::filesystem::remove(file);

    const bool same = restored == uninterrupted && rewound == uninterrupted;
    std::printf("%s\n", same ? "bit for bit the same" : "DIFFERENT");
    return same ? 0 : 1;
}
