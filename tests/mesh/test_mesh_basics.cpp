#include "ffdaabb/error.h"
#include "ffdaabb/generators.h"
#include "ffdaabb/mesh.h"

#include <gtest/gtest.h>

#include <numbers>

using namespace ffd;

TEST(Icosphere, TwoSubdivisionsGiveThePapersCounts) {
    const TriangleMesh m = icosphere(2);
    EXPECT_EQ(m.vertexCount(), 162u);
    EXPECT_EQ(m.triangleCount(), 320u);
    EXPECT_TRUE(isClosed(m));
    EXPECT_GT(signedVolume(m), 0.0); // outward oriented
    for (const Vec3& p : m.positions) EXPECT_NEAR(length(p), 1.0f, 1e-6f);
}

TEST(Icosphere, CountsFollowTheSubdivisionFormula) {
    for (int n = 0; n <= 4; ++n) {
        const TriangleMesh m = icosphere(n);
        const size_t f = size_t(1) << (2 * n);
        EXPECT_EQ(m.vertexCount(), 10 * f + 2);
        EXPECT_EQ(m.triangleCount(), 20 * f);
        EXPECT_TRUE(isClosed(m));
    }
    // The volume approaches the unit ball's from below.
    EXPECT_NEAR(signedVolume(icosphere(5)), 4.0 / 3.0 * std::numbers::pi, 0.01);
}

TEST(Icosphere, RejectsAbsurdSubdivisions) {
    EXPECT_THROW(icosphere(-1), InputError);
    EXPECT_THROW(icosphere(40), InputError);
}

TEST(Cleanup, WeldsDropsAndReports) {
    TriangleMesh m;
    // Two triangles of a quad with duplicated corner vertices, a degenerate triangle, a
    // duplicate triangle (reversed) and an unreferenced vertex.
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}, {1, 1, 0}, {0, 1, 0}, {5, 5, 5}};
    m.triangles = {{0, 1, 2}, {3, 4, 5}, {0, 3, 1}, {2, 1, 0}};
    const CleanupReport r = cleanup(m);
    EXPECT_EQ(r.weldedVertices, 2u);
    EXPECT_EQ(r.degenerateTriangles, 1u);
    EXPECT_EQ(r.duplicateTriangles, 1u);
    EXPECT_EQ(r.unreferencedVertices, 1u);
    EXPECT_EQ(m.vertexCount(), 4u);
    EXPECT_EQ(m.triangleCount(), 2u);
    EXPECT_TRUE(r.changed());
    EXPECT_FALSE(cleanup(m).changed()); // idempotent
}

TEST(Cleanup, WeldToleranceMergesNearbyVertices) {
    TriangleMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1e-5f, 0, 0}, {1, 1e-5f, 0}, {1, 1, 0}};
    m.triangles = {{0, 1, 2}, {3, 5, 4}};
    CleanupSettings s;
    s.weldTolerance = 1e-4f;
    const CleanupReport r = cleanup(m, s);
    EXPECT_EQ(r.weldedVertices, 2u);
    EXPECT_EQ(m.vertexCount(), 4u);
}

TEST(Validate, NamesTheSourceAndTheProblem) {
    TriangleMesh m = icosphere(0);
    m.positions[3].y = std::numeric_limits<float>::quiet_NaN();
    try {
        validate(m, "my_mesh.obj");
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(e.source(), "my_mesh.obj");
        EXPECT_NE(std::string(e.what()).find("vertex 3"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("non-finite"), std::string::npos) << e.what();
    }
    TriangleMesh bad = icosphere(0);
    bad.triangles[0][1] = 99;
    EXPECT_THROW(validate(bad, "x"), InputError);
    EXPECT_THROW(validate(TriangleMesh{}, "x"), InputError);
}

TEST(Mesh, NormalsPointOutwardOnASphere) {
    const TriangleMesh m = icosphere(2);
    const auto normals = vertexNormals(m);
    for (size_t i = 0; i < m.vertexCount(); ++i) EXPECT_GT(dot(normals[i], m.positions[i]), 0.99f);
}

TEST(Mesh, OpenMeshIsNotClosed) {
    TriangleMesh m = icosphere(1);
    m.triangles.pop_back();
    EXPECT_FALSE(isClosed(m));
}
