// Lattices of meshes at the edge of single precision, found by fuzzing loadMesh: a cube with
// one corner moved to 1e38 used to leave every triangle-box test undecided (overflowing
// products) and the build read outside its cell array. Now the build either refuses the mesh
// with an InputError or embeds every vertex in a real cell.
#include "ffdaabb/error.h"
#include "ffdaabb/lattice.h"

#include <gtest/gtest.h>

using namespace ffd;

namespace {

TriangleMesh cubeWithCorner(int corner, Vec3 where) {
    TriangleMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                   {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    m.positions[size_t(corner)] = where;
    m.triangles = {{0, 3, 2}, {0, 2, 1}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                   {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
    m.name = "cube";
    return m;
}

void expectRefusedOrEmbedded(const TriangleMesh& mesh) {
    for (float resolution : {1.0f, 4.0f, 64.0f}) {
        LatticeSettings s;
        s.resolution = resolution;
        try {
            const Lattice L = buildLattice(mesh, s);
            ASSERT_GT(L.cellCount(), 0u);
            ASSERT_EQ(L.vertices.size(), mesh.positions.size());
            for (const Embedding& e : L.vertices) EXPECT_LT(e.cell, L.cellCount());
        } catch (const InputError& e) {
            EXPECT_EQ(e.source(), "cube");
            EXPECT_NE(std::string(e.what()).find("single precision"), std::string::npos)
                << e.what();
        }
    }
}

} // namespace

TEST(LatticeInput, CornersNearTheEdgeOfSinglePrecision) {
    expectRefusedOrEmbedded(cubeWithCorner(4, {0, -1.70141183e38f, 1}));
    expectRefusedOrEmbedded(cubeWithCorner(2, {1, 8.50705917e37f, 0}));
    expectRefusedOrEmbedded(cubeWithCorner(6, {3e38f, 3e38f, 3e38f}));
    expectRefusedOrEmbedded(cubeWithCorner(0, {-3e38f, -3e38f, -3e38f}));
    // A denormal next to ordinary corners is an ordinary mesh.
    const Lattice L = buildLattice(cubeWithCorner(3, {5.41829427e-39f, 1, 0}));
    EXPECT_GT(L.cellCount(), 0u);
}
