// The paper's objects (Table 2) in their lattices.
#include "ffdaabb/error.h"
#include "ffdaabb/generators.h"
#include "ffdaabb/lattice.h"
#include "test_support.h"

#include <gtest/gtest.h>

using namespace ffd;

namespace {

Lattice paperLattice(const TriangleMesh& mesh, int cells) {
    LatticeSettings s;
    s.targetCells = cells;
    return buildLattice(mesh, s);
}

void expectExactEmbedding(const TriangleMesh& mesh, const Lattice& L) {
    std::vector<Vec3> out(mesh.vertexCount());
    deformVertices(L, L.restParticles, out);
    const float size = maxComponent(bounds(mesh).extent());
    for (size_t v = 0; v < out.size(); ++v)
        ASSERT_LE(length(out[v] - mesh.positions[v]), 1e-6f * size) << mesh.name << " vertex " << v;
    // A smooth deformation keeps every vertex in the hull of its cell box's nodes.
    const test::SmoothDeformation warp(17, size, 0.3f);
    std::vector<Vec3> particles(L.particleCount()), nodes(L.nodeCount());
    for (size_t p = 0; p < particles.size(); ++p) particles[p] = warp(L.restParticles[p]);
    deformVertices(L, particles, out);
    updateBoxNodes(L, particles, nodes);
    for (size_t v = 0; v < out.size(); ++v) {
        const uint32_t b = L.cellBox[L.vertices[v].cell];
        ASSERT_NE(b, UINT32_MAX);
        ASSERT_TRUE(test::insideConvexHull(&nodes[b * 8], out[v], 1e-5f * size))
            << mesh.name << " vertex " << v;
    }
}

} // namespace

TEST(PaperObjects, SphereTeapotAndDragonCellCountsMatchTableTwo) {
    for (const char* name : {"sphere", "teapot", "dragon"}) {
        const TriangleMesh mesh = generate(name);
        const PaperObjectFigures* paper = paperFigures(name);
        ASSERT_NE(paper, nullptr);
        const Lattice L = paperLattice(mesh, paper->cells);
        EXPECT_NEAR(double(L.cellCount()), double(paper->cells), 0.2 * paper->cells) << name;
        expectExactEmbedding(mesh, L);
    }
}

TEST(PaperObjects, AlphabetAverageCellCountMatchesTableTwo) {
    double cells = 0;
    for (char c = 'A'; c <= 'Z'; ++c) {
        const TriangleMesh mesh = letter(c);
        const Lattice L = paperLattice(mesh, kPaperLetter.cells);
        cells += double(L.cellCount());
        expectExactEmbedding(mesh, L);
        // Every letter keeps a lattice of its own shape, not a single block.
        EXPECT_GE(L.cellCount(), 10u) << c;
    }
    EXPECT_NEAR(cells / 26, double(kPaperLetter.cells), 0.2 * kPaperLetter.cells);
}

TEST(PaperObjects, GeneratorNamesAreResolvedAndBadOnesRejected) {
    EXPECT_EQ(generate("icosphere:1").vertexCount(), 42u);
    EXPECT_EQ(generate("teapot:2").triangleCount(), 256u);
    EXPECT_TRUE(isClosed(generate("letter:Q")));
    for (const char* bad : {"cube", "letter:a", "letter:", "icosphere:x", "teapot:-1", ""})
        EXPECT_THROW(generate(bad), InputError) << bad;
}
