// The peer benchmarks' interpenetration measure against known answers: overlapping spheres,
// separate spheres, a sphere inside another, the floor figures and non-finite input.
#include "interpenetration.h"

#include "ffdaabb/generators.h"
#include "ffdaabb/mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <tuple>
#include <vector>

using namespace ffd;
using namespace ffd::bench;

namespace {

// An icosphere of 162 vertices / 320 triangles (the scene's sphere), radius `radius`, at `at`.
TriangleMesh sphere(float radius, Vec3 at) {
    TriangleMesh m = icosphere(2);
    transform(m, radius, at);
    return m;
}

MeshView view(const TriangleMesh& m) {
    return {m.positions, m.triangles};
}

Interpenetration measure(const std::vector<TriangleMesh>& meshes,
                         const InterpenetrationSettings& settings = {}) {
    std::vector<MeshView> views;
    for (const TriangleMesh& m : meshes) views.push_back(view(m));
    return measureInterpenetration(views, settings);
}

} // namespace

TEST(Interpenetration, WindingNumberIsOneInsideAndZeroOutside) {
    const TriangleMesh m = sphere(1.0f, {0.3f, -0.2f, 0.1f});
    EXPECT_NEAR(windingNumber({0.3f, -0.2f, 0.1f}, view(m)), 1.0, 1e-9);
    EXPECT_NEAR(windingNumber({0.9f, 0.2f, 0.3f}, view(m)), 1.0, 1e-9);
    EXPECT_NEAR(windingNumber({5.0f, 0.0f, 0.0f}, view(m)), 0.0, 1e-9);
    EXPECT_NEAR(windingNumber({0.3f, 1.5f, 0.1f}, view(m)), 0.0, 1e-9);
    EXPECT_TRUE(insideMesh({0.3f, -0.2f, 0.1f}, view(m)));
    EXPECT_FALSE(insideMesh({2.0f, 0.0f, 0.0f}, view(m)));
}

TEST(Interpenetration, DistanceToSurfaceOfAUnitSphere) {
    const TriangleMesh m = sphere(1.0f, {});
    // From the centre: the faces' distance, a little under the radius for 320 triangles.
    const double inradius = distanceToSurface({}, view(m));
    EXPECT_GT(inradius, 0.97);
    EXPECT_LE(inradius, 1.0);
    // On a vertex: zero; outside along a vertex direction: the distance to that vertex.
    const Vec3 v = m.positions[7];
    EXPECT_NEAR(distanceToSurface(v, view(m)), 0.0, 1e-6);
    EXPECT_NEAR(distanceToSurface(v * 3.0f, view(m)), 2.0, 1e-5);
}

// The nearest surface point lies at the distance distanceToSurface gives, on the surface, and
// for a point inside a sphere roughly along the radius through it.
TEST(Interpenetration, ClosestPointOnTheSurfaceOfAUnitSphere) {
    const TriangleMesh m = sphere(1.0f, {1, 2, 3});
    for (const Vec3 p : {Vec3{1.2f, 2.1f, 3.3f}, Vec3{0.5f, 2.0f, 3.0f}, Vec3{1, 5, 3}}) {
        const Vec3 q = closestPointOnSurface(p, view(m));
        EXPECT_NEAR(length(q - p), distanceToSurface(p, view(m)), 1e-5);
        EXPECT_NEAR(distanceToSurface(q, view(m)), 0.0, 1e-5);
        const Vec3 radial = normalize(p - Vec3{1, 2, 3});
        EXPECT_GT(dot(normalize(q - Vec3{1, 2, 3}), radial), 0.99f);
    }
}

// Every vertex the measure counts inside is reported once to the callback, with its depth.
TEST(Interpenetration, TheCallbackSeesEveryInsideVertex) {
    const std::vector<TriangleMesh> meshes = {sphere(1.0f, {}), sphere(1.0f, {1.5f, 0, 0})};
    std::vector<MeshView> views;
    for (const TriangleMesh& mesh : meshes) views.push_back(view(mesh));
    int seen = 0;
    double deepest = 0;
    const Interpenetration r =
        measureInterpenetration(views, {}, [&](size_t a, size_t vertex, size_t b, double depth) {
            ++seen;
            EXPECT_NE(a, b);
            EXPECT_TRUE(insideMesh(views[a].vertices[vertex], views[b]));
            deepest = std::max(deepest, depth);
        });
    EXPECT_GT(seen, 0);
    EXPECT_EQ(seen, r.insideVertices);
    EXPECT_EQ(deepest, r.maxDepth);
}

// The deepest vertex is named: it lies inside the body named, as deep as maxDepth, and no
// vertex of any body lies deeper inside another. A third body far away shifts the indices.
TEST(Interpenetration, TheDeepestVertexIsNamed) {
    const std::vector<TriangleMesh> meshes = {sphere(1.0f, {10, 0, 0}), sphere(1.0f, {}),
                                              sphere(0.6f, {1.2f, 0.1f, 0})};
    std::vector<MeshView> views;
    for (const TriangleMesh& mesh : meshes) views.push_back(view(mesh));
    const Interpenetration r = measureInterpenetration(views);
    ASSERT_GE(r.deepestBody, 1);
    ASSERT_GE(r.deepestInside, 1);
    EXPECT_NE(r.deepestBody, r.deepestInside);
    const MeshView& body = views[size_t(r.deepestBody)];
    ASSERT_LT(size_t(r.deepestVertex), body.vertices.size());
    const Vec3 v = body.vertices[size_t(r.deepestVertex)];
    const MeshView& other = views[size_t(r.deepestInside)];
    EXPECT_TRUE(insideMesh(v, other));
    EXPECT_EQ(distanceToSurface(v, other), r.maxDepth);
    double deepest = 0;
    for (size_t a = 0; a < views.size(); ++a)
        for (size_t b = 0; b < views.size(); ++b)
            for (const Vec3& u : views[a].vertices)
                if (a != b && insideMesh(u, views[b]))
                    deepest = std::max(deepest, distanceToSurface(u, views[b]));
    EXPECT_EQ(deepest, r.maxDepth);
    EXPECT_GT(r.maxDepth, 0.3);
}

// Radius-1 spheres whose centres are 1.5 apart overlap by 0.5: the vertex of A on the line of
// centres lies 0.5 from B's centre, so 0.5 inside B's sphere (a little less from B's faces).
TEST(Interpenetration, UnitRadiusSpheresAtOnePointFive) {
    const TriangleMesh probe = icosphere(2);
    const Vec3 direction = probe.positions[11]; // a vertex, so one lies on the line of centres
    const std::vector<TriangleMesh> meshes{sphere(1.0f, {}), sphere(1.0f, direction * 1.5f)};
    const Interpenetration r = measure(meshes);
    EXPECT_EQ(r.bodies, 2);
    EXPECT_EQ(r.bodyPairs, 1);
    EXPECT_GT(r.insideVertices, 2);
    EXPECT_NEAR(r.maxDepth, 0.5, 0.03);
    EXPECT_GT(r.meanDepth, 0.0);
    EXPECT_LT(r.meanDepth, r.maxDepth);
    EXPECT_NEAR(r.maxDepthRelative, r.maxDepth, 1e-12); // reference size 1
    EXPECT_TRUE(r.finite);
}

// The scene's spheres have diameter 1 (size 1.0): 0.75 apart they overlap by 0.25.
TEST(Interpenetration, UnitDiameterSpheresAtThreeQuarters) {
    TriangleMesh a = icosphere(2), b = icosphere(2);
    normalizeSize(a, 1.0f);
    normalizeSize(b, 1.0f);
    const Vec3 direction = normalize(a.positions[20]);
    transform(b, 1.0f, direction * 0.75f);
    InterpenetrationSettings s;
    s.referenceSize = 1.0f;
    const Interpenetration r = measure({a, b}, s);
    EXPECT_EQ(r.bodyPairs, 1);
    EXPECT_NEAR(r.maxDepth, 0.25, 0.02);
    EXPECT_NEAR(r.maxDepthRelative, r.maxDepth, 1e-12);
    // The overlap is symmetric: as many of A's vertices in B as of B's in A.
    EXPECT_EQ(r.insideVertices % 2, 0);
}

TEST(Interpenetration, FarApartSpheresDoNotInterpenetrate) {
    const Interpenetration r = measure({sphere(1.0f, {}), sphere(1.0f, {5, 0.5f, 0})});
    EXPECT_EQ(r.bodyPairs, 0);
    EXPECT_EQ(r.insideVertices, 0);
    EXPECT_EQ(r.deepVertices, 0);
    EXPECT_EQ(r.maxDepth, 0.0);
    EXPECT_EQ(r.meanDepth, 0.0);
    EXPECT_EQ(r.deepestBody, -1);
    EXPECT_EQ(r.deepestVertex, -1);
}

// Touching at one point (centres 2 apart, radius 1): bounds overlap, nothing is inside.
TEST(Interpenetration, SpheresBarelyApartHaveNoDeepVertices) {
    const Interpenetration r = measure({sphere(1.0f, {}), sphere(1.0f, {2.001f, 0, 0})});
    EXPECT_EQ(r.deepVertices, 0);
    EXPECT_LT(r.maxDepth, 1e-3);
}

TEST(Interpenetration, TinySphereInsideABigOne) {
    const std::vector<TriangleMesh> meshes{sphere(1.0f, {}), sphere(0.1f, {0.05f, 0, 0})};
    const Interpenetration r = measure(meshes);
    EXPECT_EQ(r.bodyPairs, 1);
    EXPECT_EQ(r.insideVertices, 162); // all of the tiny one's, none of the big one's
    EXPECT_EQ(r.deepVertices, 162);
    EXPECT_GT(r.maxDepth, 0.8);
    EXPECT_LT(r.maxDepth, 1.0);
    EXPECT_GT(r.meanDepth, 0.8);
    EXPECT_EQ(r.deepestBody, 1);
    EXPECT_EQ(r.deepestInside, 0);
}

TEST(Interpenetration, FloorFigures) {
    const TriangleMesh m = sphere(1.0f, {0, 0.6f, 0});
    const float lowest = bounds(m).lo.y;
    int below = 0;
    for (const Vec3& v : m.positions) below += v.y < 0 ? 1 : 0;
    InterpenetrationSettings s;
    s.referenceSize = 2.0f;
    const Interpenetration r = measure({m}, s);
    EXPECT_FLOAT_EQ(float(r.lowestY), lowest);
    EXPECT_NEAR(r.belowFloor, -double(lowest), 1e-6);
    EXPECT_EQ(r.belowFloorVertices, below);
    EXPECT_EQ(r.bodyPairs, 0);

    s.floorHeight = -2.0f;
    const Interpenetration above = measure({m}, s);
    EXPECT_EQ(above.belowFloor, 0.0);
    EXPECT_EQ(above.belowFloorVertices, 0);
}

TEST(Interpenetration, ReferenceSizeScalesTheRelativeDepth) {
    InterpenetrationSettings s;
    s.referenceSize = 2.0f; // the diameter of a radius-1 sphere
    const Interpenetration r = measure({sphere(1.0f, {}), sphere(1.0f, {1.5f, 0, 0})}, s);
    EXPECT_NEAR(r.maxDepthRelative, r.maxDepth / 2.0, 1e-12);
}

TEST(Interpenetration, NonFiniteBodiesAreReportedAndSkipped) {
    std::vector<TriangleMesh> meshes{sphere(1.0f, {}), sphere(1.0f, {0.5f, 0, 0})};
    meshes[1].positions[3].x = std::numeric_limits<float>::quiet_NaN();
    const Interpenetration r = measure(meshes);
    EXPECT_FALSE(r.finite);
    EXPECT_EQ(r.bodyPairs, 0);
    EXPECT_TRUE(std::isfinite(r.lowestY));
}

TEST(Interpenetration, KeepWorstTakesFieldwiseExtremes) {
    Interpenetration worst;
    Interpenetration a;
    a.bodies = 2, a.bodyPairs = 1, a.insideVertices = 5, a.maxDepth = 0.2, a.meanDepth = 0.1;
    a.lowestY = -0.01;
    keepWorst(worst, a);
    EXPECT_EQ(worst.insideVertices, 5);
    EXPECT_EQ(worst.lowestY, -0.01);
    Interpenetration b;
    b.bodies = 2, b.bodyPairs = 3, b.insideVertices = 2, b.maxDepth = 0.1, b.meanDepth = 0.05;
    b.lowestY = 0.2, b.finite = false;
    keepWorst(worst, b);
    EXPECT_EQ(worst.bodyPairs, 3);
    EXPECT_EQ(worst.insideVertices, 5);
    EXPECT_EQ(worst.maxDepth, 0.2);
    EXPECT_EQ(worst.meanDepth, 0.1);
    EXPECT_EQ(worst.lowestY, -0.01);
    EXPECT_FALSE(worst.finite);
}

// The deepest vertex goes with maxDepth: a shallower sample leaves it, a deeper one replaces it.
TEST(Interpenetration, KeepWorstCarriesTheDeepestVertexWithTheDepth) {
    auto sample = [](double depth, int body, int vertex, int inside) {
        Interpenetration s;
        s.bodies = 3, s.insideVertices = 1, s.maxDepth = depth;
        s.deepestBody = body, s.deepestVertex = vertex, s.deepestInside = inside;
        return s;
    };
    Interpenetration worst;
    keepWorst(worst, sample(0.2, 0, 7, 1));
    keepWorst(worst, sample(0.1, 1, 3, 0));
    EXPECT_EQ(worst.deepestBody, 0);
    EXPECT_EQ(worst.deepestVertex, 7);
    EXPECT_EQ(worst.deepestInside, 1);
    Interpenetration none;
    none.bodies = 3;
    keepWorst(worst, none);
    EXPECT_EQ(worst.deepestVertex, 7);
    keepWorst(worst, sample(0.3, 2, 4, 0));
    EXPECT_EQ(worst.maxDepth, 0.3);
    EXPECT_EQ(worst.deepestBody, 2);
    EXPECT_EQ(worst.deepestVertex, 4);
    EXPECT_EQ(worst.deepestInside, 0);
}

// Two radius-1 spheres facing each other vertex to vertex (the icosphere is centrally
// symmetric), 0.05 apart: each one's gap is 0.05.
TEST(Interpenetration, GapBetweenSeparateNeighbours) {
    const Vec3 direction = icosphere(2).positions[5];
    const std::vector<TriangleMesh> meshes{sphere(1.0f, {}), sphere(1.0f, direction * 2.05f)};
    InterpenetrationSettings s;
    s.referenceSize = 2.0f; // gap range 0.2
    const Interpenetration r = measure(meshes, s);
    EXPECT_EQ(r.bodyPairs, 0);
    EXPECT_EQ(r.nearBodies, 2);
    EXPECT_NEAR(r.medianGap, 0.05, 1e-4);
    EXPECT_NEAR(r.meanGap, 0.05, 1e-4);
    EXPECT_NEAR(r.minGap, 0.05, 1e-4);

    // Beyond the range they are not neighbours; overlapping, their gap is 0.
    const Interpenetration far = measure({sphere(1.0f, {}), sphere(1.0f, direction * 2.5f)}, s);
    EXPECT_EQ(far.nearBodies, 0);
    EXPECT_EQ(far.medianGap, 0.0);
    const Interpenetration overlap = measure({sphere(1.0f, {}), sphere(1.0f, direction * 1.9f)}, s);
    EXPECT_EQ(overlap.nearBodies, 2);
    EXPECT_EQ(overlap.medianGap, 0.0);
}

// Three in a row: the middle one's nearest neighbour is the closer one.
TEST(Interpenetration, GapIsToTheNearestNeighbour) {
    const Vec3 d = icosphere(2).positions[5];
    const std::vector<TriangleMesh> meshes{sphere(1.0f, {}), sphere(1.0f, d * 2.02f),
                                           sphere(1.0f, d * 4.1f)};
    InterpenetrationSettings s;
    s.referenceSize = 2.0f;
    const Interpenetration r = measure(meshes, s);
    EXPECT_EQ(r.nearBodies, 3);
    EXPECT_NEAR(r.medianGap, 0.02, 1e-4); // gaps 0.02, 0.02, 0.08
    EXPECT_NEAR(r.meanGap, (0.02 + 0.02 + 0.08) / 3, 1e-4);
    EXPECT_NEAR(r.minGap, 0.02, 1e-4);
}

TEST(Interpenetration, KeepWorstKeepsTheClosestApproach) {
    Interpenetration worst;
    Interpenetration a;
    a.bodies = 2, a.nearBodies = 2, a.minGap = 0.04, a.medianGap = 0.04;
    keepWorst(worst, a);
    Interpenetration apart; // nobody near: its zero gaps say nothing
    apart.bodies = 2;
    keepWorst(worst, apart);
    EXPECT_EQ(worst.minGap, 0.04);
    Interpenetration closer;
    closer.bodies = 2, closer.nearBodies = 2, closer.minGap = 0.01, closer.medianGap = 0.01;
    keepWorst(worst, closer);
    EXPECT_EQ(worst.minGap, 0.01);
    EXPECT_EQ(worst.medianGap, 0.04);
    EXPECT_EQ(worst.nearBodies, 2);
}

namespace {

// Points in and around a mesh: uniform in its bounds grown by a fifth, and beside its vertices
// (within a thousandth of its size, where winding numbers change fastest).
std::vector<Vec3> probePoints(const TriangleMesh& m, uint32_t seed, int count) {
    const Aabb box = bounds(m);
    const Vec3 size = box.extent();
    uint32_t state = seed;
    auto unit = [&] { // xorshift, in [0, 1)
        state ^= state << 13, state ^= state >> 17, state ^= state << 5;
        return float(state >> 8) / float(1u << 24);
    };
    std::vector<Vec3> points;
    for (int i = 0; i < count; ++i) {
        points.push_back(
            box.lo - size * 0.1f +
            Vec3{size.x * 1.2f * unit(), size.y * 1.2f * unit(), size.z * 1.2f * unit()});
        const Vec3 v = m.positions[size_t(unit() * float(m.positions.size()))];
        points.push_back(v + (Vec3{unit(), unit(), unit()} - Vec3{0.5f, 0.5f, 0.5f}) *
                                 (0.002f * length(size)));
    }
    return points;
}

// A mesh turned about y by `angle` and moved to `at`.
TriangleMesh placed(TriangleMesh m, float angle, Vec3 at) {
    const float c = std::cos(angle), s = std::sin(angle);
    for (Vec3& p : m.positions) p = Vec3{c * p.x + s * p.z, p.y, -s * p.x + c * p.z} + at;
    return m;
}

} // namespace

// The tree's winding numbers and distances are those of every triangle: a letter, the teapot,
// a box, and an open surface (a sphere with a cap of triangles taken off), at points in and
// around them and beside their vertices.
TEST(Interpenetration, TheMeshTreeAnswersAsEveryTriangleDoes) {
    TriangleMesh open = icosphere(3);
    open.triangles.resize(open.triangles.size() - 40);
    const std::vector<TriangleMesh> meshes = {letter('R'), teapot(6), box({0.4f, 0.2f, 0.3f}),
                                              open};
    for (size_t k = 0; k < meshes.size(); ++k) {
        const MeshView mesh = view(meshes[k]);
        const MeshTree tree(mesh);
        EXPECT_GT(tree.nodeCount(), 8u);
        EXPECT_GT(tree.fanCount(), tree.nodeCount() / 8); // subtrees read through their fans
        int inside = 0;
        for (const Vec3 p : probePoints(meshes[k], uint32_t(17 + k), 300)) {
            const double every = windingNumber(p, mesh), fast = tree.windingNumber(p);
            EXPECT_NEAR(fast, every, 1e-9)
                << "mesh " << k << " at " << p.x << ", " << p.y << ", " << p.z;
            if (std::abs(every - 0.5) > 1e-6) {
                EXPECT_EQ(tree.inside(p), insideMesh(p, mesh));
            }
            inside += insideMesh(p, mesh) ? 1 : 0;
            const double distance = distanceToSurface(p, mesh);
            EXPECT_EQ(tree.distanceToSurface(p), distance);
            // A limit below the distance comes back as it is.
            EXPECT_EQ(tree.distanceSquared(p, 0.25 * distance * distance),
                      0.25 * distance * distance);
        }
        EXPECT_GT(inside, 30) << "mesh " << k; // the points test the inside too
    }
}

// The measure of a heap of letters placed into each other equals one that asks every triangle
// (the measure as it was before the trees), figure by figure.
TEST(Interpenetration, TheMeasureIsTheSameAsAskingEveryTriangle) {
    std::vector<TriangleMesh> meshes;
    const char* capitals = "ABRSOW";
    for (int i = 0; i < 6; ++i)
        meshes.push_back(placed(letter(capitals[i]), 0.7f * float(i),
                                {0.35f * float(i % 3), 0.2f * float(i / 3), 0.05f * float(i)}));
    std::vector<MeshView> views;
    for (const TriangleMesh& m : meshes) views.push_back(view(m));
    InterpenetrationSettings s;
    s.referenceSize = 1.0f;
    const Interpenetration r = measureInterpenetration(views, s);

    // Every triangle: the inside vertices and their depths, and each near body's gap.
    const double range = double(s.gapFraction);
    int inside = 0, deepCount = 0, pairs = 0;
    double deepest = 0, sum = 0;
    std::vector<double> gap(views.size(), range);
    for (size_t a = 0; a < views.size(); ++a)
        for (size_t b = a + 1; b < views.size(); ++b) {
            const Aabb ba = bounds(meshes[a]), bb = bounds(meshes[b]);
            bool touching = false;
            for (const auto& [p, q, qb] : {std::tuple{a, b, bb}, std::tuple{b, a, ba}})
                for (const Vec3& v : views[p].vertices)
                    if (qb.contains(v) && insideMesh(v, views[q])) {
                        const double depth = distanceToSurface(v, views[q]);
                        ++inside, touching = true, sum += depth;
                        deepCount += depth > 0.01 ? 1 : 0;
                        deepest = std::max(deepest, depth);
                    }
            pairs += touching ? 1 : 0;
            double g = touching ? 0.0 : range;
            for (const auto& [p, q, qb] : {std::tuple{a, b, bb}, std::tuple{b, a, ba}}) {
                const Vec3 r3{float(range), float(range), float(range)};
                const Aabb reach{qb.lo - r3, qb.hi + r3};
                for (const Vec3& v : views[p].vertices)
                    if (!touching && reach.contains(v))
                        g = std::min(g, distanceToSurface(v, views[q]));
            }
            gap[a] = std::min(gap[a], g), gap[b] = std::min(gap[b], g);
        }
    ASSERT_GT(inside, 100); // the heap does interpenetrate
    EXPECT_EQ(r.insideVertices, inside);
    EXPECT_EQ(r.deepVertices, deepCount);
    EXPECT_EQ(r.bodyPairs, pairs);
    EXPECT_EQ(r.maxDepth, deepest);
    EXPECT_NEAR(r.meanDepth, sum / inside, 1e-12);
    int near = 0;
    double closest = range;
    for (const double g : gap)
        if (g < range) ++near, closest = std::min(closest, g);
    EXPECT_EQ(r.nearBodies, near);
    EXPECT_EQ(r.minGap, closest);
}
