#include "ffdaabb/error.h"
#include "ffdaabb/generators.h"
#include "ffdaabb/lattice.h"
#include "lattice/geometry.h"
#include "sample_stats.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

using namespace ffd;

namespace {

// Shapes with different character: a closed sphere, a flattened ellipsoid, an open plate
// aligned with grid planes, and a bumpy closed blob.
std::vector<TriangleMesh> testMeshes() {
    std::vector<TriangleMesh> meshes;
    meshes.push_back(icosphere(3));
    TriangleMesh ellipsoid = icosphere(3);
    for (Vec3& p : ellipsoid.positions) p = mul(p, Vec3{2.0f, 0.3f, 1.0f});
    ellipsoid.name = "ellipsoid";
    meshes.push_back(ellipsoid);
    TriangleMesh plate;
    plate.name = "plate";
    const int n = 12;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) plate.positions.push_back({float(i) / n, 0.25f, float(j) / n});
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const uint32_t a = uint32_t(j * (n + 1) + i);
            plate.triangles.push_back({a, a + n + 1, a + 1});
            plate.triangles.push_back({a + 1, a + n + 1, a + n + 2});
        }
    meshes.push_back(plate);
    TriangleMesh blob = icosphere(3);
    const test::SmoothDeformation bump(7, 2.0f, 0.3f);
    for (Vec3& p : blob.positions) p = bump(p);
    blob.name = "blob";
    meshes.push_back(blob);
    return meshes;
}

float objectSize(const TriangleMesh& m) {
    return maxComponent(bounds(m).extent());
}

} // namespace

TEST(TriangleBox, KnownAnswers) {
    const Vec3 lo{0, 0, 0}, hi{1, 1, 1};
    // Inside, crossing, touching a face, just outside, and a big triangle whose corners are
    // all outside but whose interior cuts the box.
    EXPECT_TRUE(detail::triangleOverlapsBox({0.2f, 0.2f, 0.2f}, {0.8f, 0.2f, 0.2f},
                                            {0.2f, 0.8f, 0.2f}, lo, hi));
    EXPECT_TRUE(
        detail::triangleOverlapsBox({-1, 0.5f, 0.5f}, {2, 0.5f, 0.5f}, {0.5f, 2, 0.5f}, lo, hi));
    EXPECT_TRUE(detail::triangleOverlapsBox({1, 0, 0}, {1, 1, 0}, {1, 0, 1}, lo, hi));
    EXPECT_FALSE(
        detail::triangleOverlapsBox({1.001f, 0, 0}, {1.001f, 1, 0}, {1.001f, 0, 1}, lo, hi));
    EXPECT_TRUE(
        detail::triangleOverlapsBox({-5, -5, 0.5f}, {10, -5, 0.5f}, {-5, 10, 0.5f}, lo, hi));
    // Separated only by an edge-cross-axis: near the box's edge, diagonal.
    EXPECT_FALSE(detail::triangleOverlapsBox({1.5f, -0.2f, 0}, {1.5f, -0.2f, 1}, {2.2f, 0.5f, 0.5f},
                                             lo, hi));
    EXPECT_FALSE(detail::triangleOverlapsBox({1.3f, 0, 0.5f}, {2, 0, 0.5f},
                                             {1.3f, -0.3f + 1.6f, 0.5f}, lo, hi));
}

TEST(TriangleBox, AgreesWithDenseSampling) {
    // Random triangles near a unit box: whenever a sample point of the triangle lies in the box
    // the SAT test must say overlap (the SAT test is exact, sampling is one-sided).
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-0.8f, 1.8f);
    int overlaps = 0, sampledHits = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        const Vec3 a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)}, c{u(rng), u(rng), u(rng)};
        const bool sat = detail::triangleOverlapsBox(a, b, c, {0, 0, 0}, {1, 1, 1});
        bool hit = false;
        for (int i = 0; i <= 30 && !hit; ++i)
            for (int j = 0; i + j <= 30 && !hit; ++j) {
                const float s = float(i) / 30, t = float(j) / 30;
                const Vec3 p = a + (b - a) * s + (c - a) * t;
                hit = Aabb{{0, 0, 0}, {1, 1, 1}}.contains(p);
            }
        if (hit) {
            ++sampledHits;
            EXPECT_TRUE(sat) << "trial " << trial;
        }
        overlaps += sat;
        // Clipping agrees with the overlap test: a non-empty clip only for overlapping ones.
        Aabb clip;
        if (detail::addClippedTriangle(a, b, c, {0, 0, 0}, {1, 1, 1}, clip)) {
            EXPECT_TRUE(detail::triangleOverlapsBox(a, b, c, {0, 0, 0}, {1, 1, 1}, 1e-5f));
            EXPECT_TRUE(
                Aabb({{-1e-5f, -1e-5f, -1e-5f}, {1.00001f, 1.00001f, 1.00001f}}).contains(clip.lo));
            EXPECT_TRUE(
                Aabb({{-1e-5f, -1e-5f, -1e-5f}, {1.00001f, 1.00001f, 1.00001f}}).contains(clip.hi));
        }
    }
    EXPECT_GT(sampledHits, 300);
    EXPECT_GE(overlaps, sampledHits);
}

TEST(Lattice, UndeformedLatticeReproducesEveryVertex) {
    for (const TriangleMesh& mesh : testMeshes()) {
        for (float resolution : {1.0f, 3.0f, 4.5f, 9.0f, 17.5f}) {
            LatticeSettings s;
            s.resolution = resolution;
            const Lattice L = buildLattice(mesh, s);
            std::vector<Vec3> out(mesh.vertexCount());
            deformVertices(L, L.restParticles, out);
            const float tol = 1e-6f * objectSize(mesh);
            for (size_t v = 0; v < out.size(); ++v)
                ASSERT_LE(length(out[v] - mesh.positions[v]), tol)
                    << mesh.name << " resolution " << resolution << " vertex " << v;
        }
    }
}

// Each vertex is one box's, its own cell's, at its embedding's local coordinates: the floor's
// contacts at the vertices (WorldSettings::vertexFloorContacts) read them box by box.
TEST(Lattice, EveryVertexIsListedOnceUnderItsCellsBox) {
    for (const TriangleMesh& mesh : testMeshes()) {
        for (float resolution : {1.0f, 3.0f, 4.5f, 9.0f, 17.5f}) {
            LatticeSettings s;
            s.resolution = resolution;
            const Lattice L = buildLattice(mesh, s);
            SCOPED_TRACE(mesh.name + " resolution " + std::to_string(resolution));
            ASSERT_EQ(L.boxVertexStart.size(), L.boxes.size() + 1);
            ASSERT_EQ(L.boxVertexStart.front(), 0u);
            ASSERT_EQ(L.boxVertexStart.back(), L.boxVertices.size());
            ASSERT_EQ(L.boxVertices.size(), L.vertices.size());
            std::vector<int> seen(L.vertices.size(), 0);
            for (uint32_t k = 0; k < L.boxes.size(); ++k) {
                ASSERT_LE(L.boxVertexStart[k], L.boxVertexStart[k + 1]);
                for (uint32_t i = L.boxVertexStart[k]; i < L.boxVertexStart[k + 1]; ++i) {
                    const BoxVertex& v = L.boxVertices[i];
                    ASSERT_LT(v.vertex, L.vertices.size());
                    if (i > L.boxVertexStart[k]) {
                        ASSERT_LT(L.boxVertices[i - 1].vertex, v.vertex);
                    }
                    ++seen[v.vertex];
                    EXPECT_EQ(L.cellBox[L.vertices[v.vertex].cell], k);
                    EXPECT_EQ(v.local, L.vertices[v.vertex].local);
                    const CellBox& box = L.boxes[k];
                    for (int a = 0; a < 3; ++a) {
                        EXPECT_GE(v.local[a], box.lo[a]);
                        EXPECT_LE(v.local[a], box.hi[a]);
                    }
                }
            }
            for (size_t v = 0; v < seen.size(); ++v) ASSERT_EQ(seen[v], 1) << "vertex " << v;
        }
    }
}

TEST(Lattice, AffineMapOfParticlesMapsVerticesAndNodesAlike) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1, 1);
    for (const TriangleMesh& mesh : testMeshes()) {
        const Lattice L = buildLattice(mesh);
        std::vector<Vec3> restNodes(L.nodeCount());
        updateBoxNodes(L, L.restParticles, restNodes);
        for (int trial = 0; trial < 5; ++trial) {
            Mat3 A = Mat3::identity();
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) A.m[i][j] += 0.5f * u(rng);
            const Vec3 b{u(rng), u(rng), u(rng)};
            std::vector<Vec3> particles(L.particleCount());
            for (size_t p = 0; p < particles.size(); ++p) particles[p] = A * L.restParticles[p] + b;
            std::vector<Vec3> vertices(mesh.vertexCount()), nodes(L.nodeCount());
            deformVertices(L, particles, vertices);
            updateBoxNodes(L, particles, nodes);
            const float tol = 1e-5f * objectSize(mesh);
            for (size_t v = 0; v < vertices.size(); ++v)
                ASSERT_LE(length(vertices[v] - (A * mesh.positions[v] + b)), tol)
                    << mesh.name << " v" << v;
            for (size_t n = 0; n < nodes.size(); ++n)
                ASSERT_LE(length(nodes[n] - (A * restNodes[n] + b)), tol)
                    << mesh.name << " node " << n;
        }
    }
}

TEST(Lattice, NodesAreTheTrilinearBlendOfTheirLocalCoordinates) {
    const TriangleMesh mesh = testMeshes()[3];
    const Lattice L = buildLattice(mesh);
    std::vector<Vec3> particles(L.particleCount());
    const test::SmoothDeformation warp(5, objectSize(mesh), 0.3f);
    for (size_t p = 0; p < particles.size(); ++p) particles[p] = warp(L.restParticles[p]);
    std::vector<Vec3> nodes(L.nodeCount());
    updateBoxNodes(L, particles, nodes);
    for (size_t b = 0; b < L.boxes.size(); ++b)
        for (int n = 0; n < 8; ++n) {
            const Vec3 expected =
                evaluate(L, particles, {L.boxes[b].cell, L.boxes[b].nodeLocal(n)});
            ASSERT_LE(length(nodes[b * 8 + n] - expected), 1e-5f);
        }
}

TEST(Lattice, EveryVertexLiesInItsCellBoxAndStaysInTheDeformedHull) {
    for (const TriangleMesh& mesh : testMeshes()) {
        const Lattice L = buildLattice(mesh);
        for (size_t v = 0; v < L.vertices.size(); ++v) {
            const Embedding& e = L.vertices[v];
            ASSERT_NE(L.cellBox[e.cell], UINT32_MAX) << "vertex " << v << " in a cell with no box";
            const CellBox& box = L.boxes[L.cellBox[e.cell]];
            ASSERT_TRUE(Aabb({box.lo, box.hi}).contains(e.local)) << mesh.name << " vertex " << v;
            // In world units the rest box contains the vertex too.
            const Vec3 cmin = L.cellMin(e.cell);
            ASSERT_TRUE(Aabb({cmin + box.lo * L.cellSize, cmin + box.hi * L.cellSize})
                            .contains(mesh.positions[v], 1e-6f));
        }
        for (uint32_t seed = 1; seed <= 4; ++seed) {
            const test::SmoothDeformation warp(seed, objectSize(mesh), 0.4f);
            std::vector<Vec3> particles(L.particleCount());
            for (size_t p = 0; p < particles.size(); ++p) particles[p] = warp(L.restParticles[p]);
            std::vector<Vec3> vertices(mesh.vertexCount()), nodes(L.nodeCount());
            deformVertices(L, particles, vertices);
            updateBoxNodes(L, particles, nodes);
            const float tol = 1e-5f * objectSize(mesh);
            for (size_t v = 0; v < vertices.size(); ++v) {
                const uint32_t b = L.cellBox[L.vertices[v].cell];
                ASSERT_TRUE(test::insideConvexHull(&nodes[b * 8], vertices[v], tol))
                    << mesh.name << " seed " << seed << " vertex " << v;
            }
        }
    }
}

TEST(Lattice, ParticlesAreSharedCellCornersAtTheirGridPoints) {
    const Lattice L = buildLattice(icosphere(3));
    // Each particle is the corner of at least one cell, at origin + h * coord.
    std::vector<int> uses(L.particleCount(), 0);
    for (size_t c = 0; c < L.cellCount(); ++c)
        for (int corner = 0; corner < 8; ++corner) {
            const uint32_t p = L.cellParticles[c][corner];
            ASSERT_LT(p, L.particleCount());
            ++uses[p];
            const GridCoord expected{L.cells[c][0] + (corner & 1),
                                     L.cells[c][1] + ((corner >> 1) & 1),
                                     L.cells[c][2] + ((corner >> 2) & 1)};
            EXPECT_EQ(L.particleCoords[p], expected);
        }
    for (int u : uses) EXPECT_GE(u, 1);
    // Sharing: far fewer particles than 8 per cell.
    EXPECT_LT(L.particleCount(), 4 * L.cellCount());
    for (size_t p = 0; p < L.particleCount(); ++p) {
        const GridCoord& g = L.particleCoords[p];
        EXPECT_LE(length(L.restParticles[p] -
                         (L.origin + Vec3{float(g[0]), float(g[1]), float(g[2])} * L.cellSize)),
                  1e-6f);
    }
}

TEST(Lattice, InteriorFillOnlyAddsEnclosedCells) {
    TriangleMesh sphere = icosphere(4);
    LatticeSettings filled, hollow;
    filled.resolution = hollow.resolution = 8;
    hollow.fillInterior = false;
    LatticeStats fs, hs;
    const Lattice a = buildLattice(sphere, filled, &fs), b = buildLattice(sphere, hollow, &hs);
    EXPECT_EQ(fs.surfaceCells, hs.surfaceCells);
    EXPECT_EQ(hs.interiorCells, 0);
    EXPECT_GT(fs.interiorCells, 0);
    EXPECT_EQ(a.cellCount(), b.cellCount() + size_t(fs.interiorCells));
    // Interior cells are enclosed: their centres are inside the unit sphere.
    for (size_t c = 0; c < a.cellCount(); ++c)
        if (!a.cellIsSurface[c]) {
            EXPECT_LT(length(a.cellMin(uint32_t(c)) + Vec3{0.5f, 0.5f, 0.5f} * a.cellSize), 1.0f);
        }
    // An open plate encloses nothing.
    LatticeStats ps;
    buildLattice(testMeshes()[2], filled, &ps);
    EXPECT_EQ(ps.interiorCells, 0);
}

TEST(Lattice, SurfaceCellsAreExactlyTheCellsTrianglesTouch) {
    // Brute force: a cell is a surface cell iff some triangle overlaps it.
    const TriangleMesh mesh = testMeshes()[1];
    LatticeSettings s;
    s.resolution = 6;
    s.fillInterior = false;
    const Lattice L = buildLattice(mesh, s);
    for (int k = 0; k < L.dims[2]; ++k)
        for (int j = 0; j < L.dims[1]; ++j)
            for (int i = 0; i < L.dims[0]; ++i) {
                const Vec3 lo = L.origin + Vec3{float(i), float(j), float(k)} * L.cellSize;
                const Vec3 hi = lo + Vec3{1, 1, 1} * L.cellSize;
                bool touched = false;
                for (const auto& t : mesh.triangles)
                    touched = touched || detail::triangleOverlapsBox(mesh.positions[t[0]],
                                                                     mesh.positions[t[1]],
                                                                     mesh.positions[t[2]], lo, hi);
                EXPECT_EQ(L.findCell({i, j, k}) != UINT32_MAX, touched)
                    << i << "," << j << "," << k;
            }
}

TEST(Lattice, OutsideFaceMasksOfATwoCellLattice) {
    // A flat quad inside a 2x1x1 block of cells: cell 0 (x in [0,1]) and cell 1 (x in [1,2]).
    TriangleMesh bar;
    bar.positions = {{0.1f, 0.5f, 0.1f}, {1.9f, 0.5f, 0.1f}, {1.9f, 0.5f, 0.9f},
                     {0.1f, 0.5f, 0.9f}, {0.1f, 0.1f, 0.5f}, {1.9f, 0.9f, 0.5f}};
    bar.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 0}};
    LatticeSettings s;
    s.cellSize = 1.0f;
    const Lattice L = buildLattice(bar, s);
    ASSERT_EQ(L.dims, (GridCoord{2, 1, 1}));
    ASSERT_EQ(L.cellCount(), 2u);
    ASSERT_EQ(L.boxes.size(), 2u);
    EXPECT_EQ(L.particleCount(), 12u);
    const uint8_t all = kFaceMinX | kFaceMaxX | kFaceMinY | kFaceMaxY | kFaceMinZ | kFaceMaxZ;
    EXPECT_EQ(L.boxes[0].outsideFaces, all & ~kFaceMaxX); // +x neighbour is cell 1
    EXPECT_EQ(L.boxes[1].outsideFaces, all & ~kFaceMinX);
}

namespace {

// The cell at grid coordinates g and its box.
const CellBox& boxAtCell(const Lattice& L, GridCoord g) {
    const uint32_t cell = L.findCell(g);
    EXPECT_NE(cell, UINT32_MAX);
    EXPECT_NE(L.cellBox[cell], UINT32_MAX);
    return L.boxes[L.cellBox[cell]];
}

TriangleMesh boxMesh(Vec3 lo, Vec3 hi) {
    TriangleMesh m = box((hi - lo) * 0.5f, 1);
    for (Vec3& p : m.positions) p += (lo + hi) * 0.5f;
    return m;
}

} // namespace

TEST(Lattice, AFaceTowardsANotchInItsNeighbourCellLeadsOut) {
    // Two cubes in one mesh, in neighbouring cells with a gap of 0.7 between them: the cells
    // share a face, but the space between the two parts is outside the mesh, so each box's face
    // towards the other leads out of the body.
    TriangleMesh two = boxMesh({0, 0, 0}, {0.6f, 0.6f, 0.6f});
    const TriangleMesh second = boxMesh({1.3f, 0, 0}, {1.9f, 0.6f, 0.6f});
    const uint32_t base = uint32_t(two.positions.size());
    two.positions.insert(two.positions.end(), second.positions.begin(), second.positions.end());
    for (auto t : second.triangles)
        two.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    LatticeSettings s;
    s.cellSize = 1.0f;
    const Lattice L = buildLattice(two, s);
    ASSERT_EQ(L.dims, (GridCoord{2, 1, 1}));
    EXPECT_EQ(boxAtCell(L, {0, 0, 0}).outsideFaces, 63);
    EXPECT_EQ(boxAtCell(L, {1, 0, 0}).outsideFaces, 63);
    // One bar through both cells: its surface runs on across the shared face, which leads into
    // the body.
    const Lattice bar = buildLattice(boxMesh({0, 0, 0}, {1.9f, 0.6f, 0.6f}), s);
    EXPECT_EQ(boxAtCell(bar, {0, 0, 0}).outsideFaces, 63 & ~kFaceMaxX);
    EXPECT_EQ(boxAtCell(bar, {1, 0, 0}).outsideFaces, 63 & ~kFaceMinX);
}

TEST(Lattice, AFaceTowardsTheBodysInsideAcrossAGapLeadsIn) {
    // A block 1.8 x 2.9 x 2.9 on unit cells: the middle row along x, cells (0,1,1) and (1,1,1),
    // holds only the two end faces (x = 0 and x = 1.8), with the block's inside between them.
    LatticeSettings s;
    s.cellSize = 1.0f;
    const Lattice L = buildLattice(boxMesh({0, 0, 0}, {1.8f, 2.9f, 2.9f}), s);
    ASSERT_EQ(L.dims, (GridCoord{2, 3, 3}));
    const CellBox& left = boxAtCell(L, {0, 1, 1});
    EXPECT_LT(left.hi.x, 0.1f); // the end face only: a gap of most of the cell towards +x
    EXPECT_EQ(left.outsideFaces, kFaceMinX);
    EXPECT_EQ(boxAtCell(L, {1, 1, 1}).outsideFaces, kFaceMaxX);
}

TEST(Lattice, CellBoxesBoundTheClippedSurface) {
    // A single triangle spanning several cells: each box must cover the triangle's part in its
    // cell (checked by dense sampling) and stay inside the cell grown by the skin.
    TriangleMesh tri;
    tri.positions = {{0.05f, 0.1f, 0.2f}, {2.9f, 0.4f, 0.3f}, {0.3f, 2.7f, 0.9f}};
    tri.triangles = {{0, 1, 2}};
    LatticeSettings s;
    s.cellSize = 1.0f;
    const Lattice L = buildLattice(tri, s);
    for (int i = 0; i <= 60; ++i)
        for (int j = 0; i + j <= 60; ++j) {
            const Vec3 p = tri.positions[0] +
                           (tri.positions[1] - tri.positions[0]) * (float(i) / 60) +
                           (tri.positions[2] - tri.positions[0]) * (float(j) / 60);
            const Embedding e = embedPoint(L, p);
            const uint32_t b = L.cellBox[e.cell];
            ASSERT_NE(b, UINT32_MAX);
            EXPECT_TRUE(Aabb({L.boxes[b].lo, L.boxes[b].hi}).contains(e.local, 1e-5f));
        }
    for (const CellBox& box : L.boxes) {
        const float skin = s.boxSkin + 1e-6f;
        EXPECT_TRUE(Aabb({{-skin, -skin, -skin}, {1 + skin, 1 + skin, 1 + skin}}).contains(box.lo));
        EXPECT_TRUE(Aabb({{-skin, -skin, -skin}, {1 + skin, 1 + skin, 1 + skin}}).contains(box.hi));
    }
}

TEST(Lattice, TargetCellCountIsFound) {
    const TriangleMesh sphere = icosphere(2);
    for (int target : {8, 38, 100, 400}) {
        LatticeSettings s;
        s.targetCells = target;
        const Lattice L = buildLattice(sphere, s);
        EXPECT_NEAR(double(L.cellCount()), double(target), 0.2 * target) << "target " << target;
        EXPECT_EQ(countCells(sphere, L.cellSize, true), int(L.cellCount()));
    }
}

TEST(Lattice, IsDeterministic) {
    const TriangleMesh mesh = testMeshes()[3];
    const Lattice a = buildLattice(mesh), b = buildLattice(mesh);
    ASSERT_EQ(a.cellCount(), b.cellCount());
    EXPECT_EQ(a.cells, b.cells);
    EXPECT_EQ(a.restParticles.size(), b.restParticles.size());
    for (size_t i = 0; i < a.boxes.size(); ++i) {
        EXPECT_EQ(a.boxes[i].lo, b.boxes[i].lo);
        EXPECT_EQ(a.boxes[i].hi, b.boxes[i].hi);
    }
}

TEST(Lattice, BadSettingsAreRejectedWithTheFieldName) {
    const TriangleMesh sphere = icosphere(1);
    auto expectField = [&](LatticeSettings s, const std::string& field) {
        try {
            buildLattice(sphere, s);
            FAIL() << "expected an error for " << field;
        } catch (const InputError& e) {
            EXPECT_EQ(e.source(), field) << e.what();
        }
    };
    LatticeSettings s;
    s.cellSize = -1;
    expectField(s, "lattice.cellSize");
    s = {};
    s.cellSize = std::numeric_limits<float>::quiet_NaN();
    expectField(s, "lattice.cellSize");
    s = {};
    s.cellSize = 1e-6f; // a grid of 2e6^3 cells
    expectField(s, "lattice.cellSize");
    s = {};
    s.resolution = -1;
    expectField(s, "lattice.resolution");
    s = {};
    s.boxSkin = 2;
    expectField(s, "lattice.boxSkin");
    s = {};
    s.targetCells = -5;
    expectField(s, "lattice.targetCells");
}

TEST(Lattice, ASingleCellLattice) {
    LatticeSettings s;
    s.cellSize = 10.0f;
    const Lattice L = buildLattice(icosphere(2), s);
    EXPECT_EQ(L.cellCount(), 1u);
    EXPECT_EQ(L.particleCount(), 8u);
    EXPECT_EQ(L.boxes.size(), 1u);
    EXPECT_EQ(L.boxes[0].outsideFaces, 63);
}

namespace {

// The particles' centre of mass at rest: their mass fractions times their rest positions.
Vec3 restMassCentre(const Lattice& L) {
    Vec3 c{};
    for (size_t p = 0; p < L.particleCount(); ++p) c += L.restParticles[p] * L.massFraction[p];
    return c;
}

void expectValidMassFractions(const Lattice& L) {
    ASSERT_EQ(L.massFraction.size(), L.particleCount());
    double sum = 0;
    for (const float m : L.massFraction) {
        EXPECT_GT(m, 0.0f);
        sum += double(m);
    }
    EXPECT_NEAR(sum, 1.0, 1e-5);
}

} // namespace

// A sphere's grid is anchored at its minimum corner, so its lattice overhangs it on the far
// sides; with an even share per cell the particles' centre of mass lay 11 cm off the centre of a
// unit sphere on each axis. Spread by the volume it is the sphere's centre.
TEST(LatticeMass, ASpheresCentreOfMassIsItsCentre) {
    LatticeSettings s;
    s.targetCells = 38;
    const Lattice L = buildLattice(icosphere(2), s);
    expectValidMassFractions(L);
    const Vec3 c = restMassCentre(L);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(c[a], 0.0f, 0.02f) << "axis " << a;
}

// A slab a hair deeper than one cell gets a second layer of cells that its back face only
// grazes: an even share per cell put half the mass in that empty layer, and the centre of mass
// on the slab's back face (the letters' case, docs/ALGORITHM.md §1, "Mass").
TEST(LatticeMass, AnEmptyLayerOfCellsCarriesAlmostNoMass) {
    const TriangleMesh slab = box({0.49f, 0.49f, 0.125f});
    LatticeSettings s;
    s.cellSize = 0.2499f;
    const Lattice L = buildLattice(slab, s);
    ASSERT_EQ(L.dims[2], 2);
    expectValidMassFractions(L);
    const Vec3 c = restMassCentre(L);
    EXPECT_NEAR(c.z, 0.0f, 0.025f); // a tenth of the depth; the even share gave 0.125
    EXPECT_NEAR(c.x, 0.0f, 0.01f);
    EXPECT_NEAR(c.y, 0.0f, 0.01f);
    // The particles of the far plane keep only their least share.
    double far = 0;
    for (size_t p = 0; p < L.particleCount(); ++p)
        if (L.particleCoords[p][2] == 2) far += double(L.massFraction[p]);
    EXPECT_LT(far, 0.05);
}

// An open sheet has no volume: without an interior its surface cells weigh alike.
TEST(LatticeMass, AnOpenSheetIsSpreadOverItsCells) {
    const TriangleMesh plate = testMeshes()[2];
    const Lattice L = buildLattice(plate);
    expectValidMassFractions(L);
    const Vec3 c = restMassCentre(L);
    EXPECT_NEAR(c.x, 0.5f, 0.05f);
    EXPECT_NEAR(c.z, 0.5f, 0.05f);
}

namespace {

// A mesh turned by q about the origin.
TriangleMesh turned(TriangleMesh mesh, Quat q) {
    for (Vec3& p : mesh.positions) p = rotate(q, p);
    return mesh;
}

} // namespace

TEST(Lattice, BoxStandoffIsTheSkinWhereFacesLieAlongTheCells) {
    // A cube whose faces lie on cell faces: each box is its part's bounds, flush with the
    // faces, so its nodes stand off only by the skin (sqrt 3 of it along a corner's diagonal).
    const TriangleMesh cube = box({1, 1, 1}, 4);
    LatticeSettings s;
    s.cellSize = 0.5f;
    const Lattice L = buildLattice(cube, s);
    const BoxStandoff aligned = measureBoxStandoff(L, cube);
    const float skin = s.boxSkin * s.cellSize;
    ASSERT_EQ(aligned.standoff.size(), 2000u);
    const std::vector<double> sample(aligned.standoff.begin(), aligned.standoff.end());
    EXPECT_GE(bench::median(sample), 0.99f * skin);
    EXPECT_LE(aligned.max, std::sqrt(3.0f) * skin * 1.001f);
    EXPECT_EQ(aligned.max, *std::max_element(aligned.standoff.begin(), aligned.standoff.end()));
}

TEST(Lattice, BoxStandoffSeesFacesThatCrossTheCells) {
    // The same cube turned: its faces cross the cells, and a box's corner stands off its part
    // of a face (docs/LIMITS.md, known problem 9). Never more than a cell's diagonal with the
    // skin, since every box lies in its cell and holds some of the surface.
    const TriangleMesh cube = turned(box({1, 1, 1}, 4), normalize(Quat{0.3f, 0.2f, 0.1f, 1}));
    const TriangleMesh ball = icosphere(2);
    LatticeSettings s;
    s.cellSize = 0.5f;
    for (const TriangleMesh* mesh : {&cube, &ball}) {
        const Lattice L = buildLattice(*mesh, s);
        const BoxStandoff r = measureBoxStandoff(L, *mesh, 500);
        const std::vector<double> sample(r.standoff.begin(), r.standoff.end());
        EXPECT_GT(bench::median(sample), 10 * s.boxSkin * s.cellSize) << mesh->name;
        EXPECT_LE(r.max, std::sqrt(3.0f) * s.cellSize * (1 + 2 * s.boxSkin)) << mesh->name;
        // The worst direction gives the largest figure.
        float boxes = -INFINITY, surface = -INFINITY;
        std::vector<Vec3> nodes(L.nodeCount());
        updateBoxNodes(L, L.restParticles, nodes);
        for (const Vec3& n : nodes) boxes = std::max(boxes, dot(r.worstDirection, n));
        for (const Vec3& v : mesh->positions) surface = std::max(surface, dot(r.worstDirection, v));
        EXPECT_NEAR(boxes - surface, r.max, 1e-5f) << mesh->name;
    }
}

TEST(Lattice, BoxStandoffRefusesAnotherMeshAndABadDirectionCount) {
    const TriangleMesh ball = icosphere(1);
    const Lattice L = buildLattice(ball);
    EXPECT_THROW(measureBoxStandoff(L, ball, 0), InputError);
    EXPECT_THROW(measureBoxStandoff(L, ball, 1000001), InputError);
    EXPECT_THROW(measureBoxStandoff(L, icosphere(2)), InputError);
    EXPECT_EQ(measureBoxStandoff(L, ball, 1).standoff.size(), 1u);
}
