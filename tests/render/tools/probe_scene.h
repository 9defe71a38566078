// The scene of ffdaabb_viewer_probe, shared with the tests that check its state hash.
#pragma once

#include "ffdaabb/generators.h"
#include "ffdaabb/world.h"

namespace ffd::test {

inline BodySettings probeBall(Vec3 position) {
    BodySettings s;
    s.lattice.targetCells = 38;
    s.position = position;
    return s;
}

/// Four unit spheres dropped from staggered heights onto the floor.
inline World probeScene() {
    World world;
    const TriangleMesh ball = icosphere(2);
    for (int i = 0; i < 4; ++i)
        world.addBody(ball, probeBall({float(i % 2) * 2.2f - 1.1f, 1.2f + float(i) * 1.1f,
                                       float(i / 2) * 2.2f - 1.1f}));
    return world;
}

/// The "drop more objects" action: one more sphere from above.
inline void probeDrop(World& world) {
    world.addBody(icosphere(2), probeBall({0, 6, 0}));
}

} // namespace ffd::test
