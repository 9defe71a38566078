// The Enhanced FFD-AABB pipeline: narrow-phase known answers, spatial hash, bounding spheres,
// equality of the three modes, and no tunnelling or deep penetration in piles and throws.
#include "collision/narrow_phase.h"
#include "collision/pipeline.h"
#include "collision/spatial_hash.h"
#include "ffdaabb/generators.h"
#include "ffdaabb/queries.h"
#include "ffdaabb/scene.h"
#include "ffdaabb/world.h"
#include "test_support.h"
#include "world/world_data.h"

#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <random>
#include <set>

using namespace ffd;

namespace {

// The 8 nodes of an axis-aligned box [lo, hi].
void axisBox(Vec3 lo, Vec3 hi, Vec3 out[8]) {
    for (int n = 0; n < 8; ++n)
        out[n] = {(n & 1) ? hi.x : lo.x, (n & 2) ? hi.y : lo.y, (n & 4) ? hi.z : lo.z};
}

Aabb boundsOf(const Vec3 nodes[8]) {
    Aabb b;
    for (int n = 0; n < 8; ++n) b.add(nodes[n]);
    return b;
}

TriangleMesh ball(float r = 0.5f) {
    TriangleMesh m = icosphere(2);
    transform(m, r, {});
    return m;
}

BodySettings sphereSettings(Vec3 p) {
    BodySettings s;
    s.lattice.targetCells = 38;
    s.position = p;
    return s;
}

} // namespace

TEST(NarrowPhase, NodeInsideABoxByDepthD) {
    Vec3 nodes[8];
    axisBox({0, 0, 0}, {1, 1, 1}, nodes);
    const detail::BoxPlanes planes = detail::boxPlanes(nodes);
    const uint8_t allOutside = 63;
    for (float d : {0.01f, 0.1f, 0.3f}) {
        // Nearest to the +y face by d.
        const detail::NodeBoxHit hit =
            detail::testNodeInBox(planes, boundsOf(nodes), allOutside, {0.5f, 1 - d, 0.45f}, 0.02f);
        ASSERT_TRUE(hit.inside);
        EXPECT_EQ(hit.face, 3);
        EXPECT_NEAR(-hit.distance, d, 1e-5f);
        EXPECT_LE(length(planes.normal[hit.face] - Vec3{0, 1, 0}), 1e-6f);
    }
    // Only the -x and +z faces lead outside (the others touch the object's other cells): the
    // node nearest +y leaves through the nearer of those two.
    const detail::NodeBoxHit hit = detail::testNodeInBox(
        planes, boundsOf(nodes), kFaceMinX | kFaceMaxZ, {0.6f, 0.95f, 0.8f}, 0.02f);
    ASSERT_TRUE(hit.inside);
    EXPECT_EQ(hit.face, 5);
    EXPECT_NEAR(hit.distance, -0.2f, 1e-5f);
    // A box with no outside face uses all six.
    EXPECT_EQ(detail::testNodeInBox(planes, boundsOf(nodes), 0, {0.5f, 0.95f, 0.5f}, 0.02f).face,
              3);
}

TEST(NarrowPhase, NodeJustOutsideGetsNoContact) {
    Vec3 nodes[8];
    axisBox({0, 0, 0}, {1, 1, 1}, nodes);
    const detail::BoxPlanes planes = detail::boxPlanes(nodes);
    const float skin = 0.02f;
    EXPECT_FALSE(
        detail::testNodeInBox(planes, boundsOf(nodes), 63, {0.5f, 1.021f, 0.5f}, skin).inside);
    EXPECT_FALSE(
        detail::testNodeInBox(planes, boundsOf(nodes), 63, {-0.03f, 0.5f, 0.5f}, skin).inside);
    EXPECT_FALSE(
        detail::testNodeInBox(planes, boundsOf(nodes), 63, {1.1f, 1.1f, 1.1f}, skin).inside);
    // Within the skin: a (speculative) contact with positive distance.
    const detail::NodeBoxHit near =
        detail::testNodeInBox(planes, boundsOf(nodes), 63, {0.5f, 1.015f, 0.5f}, skin);
    ASSERT_TRUE(near.inside);
    EXPECT_NEAR(near.distance, 0.015f, 1e-5f);
}

namespace {

// A box pair's view of an axis-aligned box from lo to hi, all faces outside.
struct TestBox {
    Vec3 nodes[8];
    detail::BoxPlanes planes;
    detail::BoxView view;
    TestBox(Vec3 lo, Vec3 hi, uint8_t outside = 63) {
        axisBox(lo, hi, nodes);
        planes = detail::boxPlanes(nodes);
        view.nodes = nodes;
        for (int n = 0; n < 8; ++n)
            view.local[n] = {float(n & 1), float((n >> 1) & 1), float((n >> 2) & 1)};
        view.planes = &planes;
        view.outsideFaces = outside;
    }
    void transform(const Mat3& r, Vec3 t) {
        for (Vec3& n : nodes) n = r * n + t;
        planes = detail::boxPlanes(nodes);
    }
};

// The signed distance of a manifold's deepest point (0 when none overlaps).
float deepestPoint(const detail::BoxPairManifold& m) {
    float deepest = 0;
    for (int k = 0; k < m.count; ++k) deepest = std::min(deepest, m.point[k].distance);
    return deepest;
}

} // namespace

// A box resting 2 cm into a larger one: one normal for the pair and four points 2 cm deep at
// the corners of the overlap. The faces overlap equally, so the first box given holds the
// reference face: the larger one's top (the smaller box's bottom corners move up), or the
// smaller one's bottom (the larger box's top face, clipped to it, moves down).
TEST(NarrowPhase, FaceToFaceBoxesGiveFourPointsOnOneNormal) {
    const TestBox big({0, 0, 0}, {1, 1, 1});
    const TestBox small({0.25f, 0.98f, 0.25f}, {0.75f, 1.48f, 0.75f});
    for (const bool bigFirst : {true, false}) {
        SCOPED_TRACE(bigFirst ? "larger box first" : "smaller box first");
        const detail::BoxPairManifold m =
            bigFirst ? detail::boxPairManifold(big.view, small.view, 0.05f, 0.001f)
                     : detail::boxPairManifold(small.view, big.view, 0.05f, 0.001f);
        ASSERT_EQ(m.count, 4);
        EXPECT_EQ(m.reference, 0);
        const float up = bigFirst ? 1.0f : -1.0f;
        EXPECT_LE(length(m.normal - Vec3{0, up, 0}), 1e-5f);
        for (int k = 0; k < 4; ++k) {
            const ffd::detail::ManifoldPoint& p = m.point[k];
            EXPECT_NEAR(p.distance, -0.02f, 1e-5f);
            EXPECT_NEAR(p.position.y, bigFirst ? 0.98f : 1.0f, 1e-5f);
            // On the incident box's face: the smaller's bottom, the larger's top.
            EXPECT_NEAR(p.local.y, bigFirst ? 0.0f : 1.0f, 1e-5f);
            EXPECT_NEAR(std::abs(p.position.x - 0.5f), 0.25f, 1e-5f);
            EXPECT_NEAR(std::abs(p.position.z - 0.5f), 0.25f, 1e-5f);
        }
    }
    // The second box holds the reference when its face overlaps less by more than the
    // tolerance: never here (equal), so a zero tolerance keeps the first.
    EXPECT_EQ(detail::boxPairManifold(small.view, big.view, 0.05f, 0.0f).reference, 0);
    // Apart by more than the margin: nothing.
    const TestBox above({0.25f, 1.1f, 0.25f}, {0.75f, 1.6f, 0.75f});
    EXPECT_LT(detail::boxPairManifold(big.view, above.view, 0.05f, 0.001f).reference, 0);
}

// A box 2 cm into the bottom of another, its edge reaching 1 cm beyond that box's +z face: the
// clipped face gives the points on the reference normal (down), and the two nodes of the edge,
// below the reference plane but beside its +z side, become side points on that side's normal,
// 1 cm from it: were the box to move in across that side in the substep, they meet it. Beside
// a side that leads into the reference box's next cell, there are none (that cell's box meets
// the nodes).
TEST(NarrowPhase, NodesBesideAnOutsideSideOfTheReferenceFaceGiveSidePoints) {
    const TestBox upper({0, 0, 0}, {1, 1, 1});
    const TestBox lower({0.2f, -0.5f, 0.71f}, {0.8f, 0.02f, 1.01f});
    const detail::BoxPairManifold m =
        detail::boxPairManifold(upper.view, lower.view, 0.05f, 0.001f);
    ASSERT_EQ(m.reference, 0);
    EXPECT_LE(length(m.normal - Vec3{0, -1, 0}), 1e-5f);
    int onFace = 0, beside = 0;
    for (int k = 0; k < m.count; ++k) {
        const detail::ManifoldPoint& p = m.point[k];
        if (length(p.normal - m.normal) < 1e-6f) {
            ++onFace;
            EXPECT_NEAR(p.distance, -0.02f, 1e-5f);
            EXPECT_LE(p.position.z, 1.0f + 1e-5f);
        } else {
            ++beside;
            EXPECT_LE(length(p.normal - Vec3{0, 0, 1}), 1e-5f);
            EXPECT_NEAR(p.distance, 0.01f, 1e-5f);
            EXPECT_NEAR(p.position.y, 0.02f, 1e-5f);
            EXPECT_NEAR(p.position.z, 1.01f, 1e-5f);
        }
    }
    EXPECT_EQ(onFace, 4);
    EXPECT_EQ(beside, 2);
    const TestBox inner({0, 0, 0}, {1, 1, 1}, uint8_t(63 & ~kFaceMaxZ));
    const detail::BoxPairManifold handed =
        detail::boxPairManifold(inner.view, lower.view, 0.05f, 0.001f);
    ASSERT_EQ(handed.reference, 0);
    EXPECT_EQ(handed.count, 4);
}

// A long box turned 45 degrees about its length (z), its lowest edge pushed 3 cm into the top
// of another box and reaching beyond it on both sides, so that no node of either box lies
// inside the other: the crossing that a node test cannot see. The pair gets contacts pushing
// the turned box up, 3 cm deep.
TEST(NarrowPhase, CrossingEdgesWithNoNodeInsideMakeAContact) {
    const TestBox below({0, 0, 0}, {1, 1, 1});
    TestBox turned({-0.5f, -0.5f, -1.0f}, {0.5f, 0.5f, 1.0f});
    const float c = std::sqrt(0.5f);
    const Mat3 rz{{{c, -c, 0}, {c, c, 0}, {0, 0, 1}}};
    // Lowest edge along z at height -sqrt(0.5): lifted so it lies 3 cm below y = 1.
    turned.transform(rz, {0.5f, 1.0f + c - 0.03f, 0.5f});
    for (const Vec3& n : turned.nodes)
        EXPECT_FALSE(detail::testNodeInBox(below.planes, boundsOf(below.nodes), 63, n, 0).inside);
    for (const Vec3& n : below.nodes)
        EXPECT_FALSE(detail::testNodeInBox(turned.planes, boundsOf(turned.nodes), 63, n, 0).inside);
    const detail::BoxPairManifold m = detail::boxPairManifold(below.view, turned.view, 0.01f, 0);
    ASSERT_GT(m.count, 0);
    EXPECT_EQ(m.reference, 0);
    EXPECT_LE(length(m.normal - Vec3{0, 1, 0}), 1e-5f);
    EXPECT_NEAR(deepestPoint(m), -0.03f, 1e-4f);
}

// A thin rod through the middle of a thin plate, one cell each, so that neither box has a node
// within the other's node bounds grown by the pair's margin (checked): phase 2 finds the pair
// by the rod's box's centre, and the pair gets contacts. (The overlap recovery is off, so the
// pair placed overlapping is an ordinary one.) Without the centre, it got none.
TEST(ObjectContacts, ARodThroughAPlateIsFoundByItsBoxCentre) {
    WorldSettings settings;
    settings.gravity = {0, 0, 0};
    settings.floor = false;
    settings.overlapRecoverySpeed = 0;
    World world(settings);
    BodySettings plate, rod;
    plate.lattice.cellSize = 1.2f;
    plate.position = {0, 1, 0};
    rod.lattice.cellSize = 0.7f;
    rod.position = {0.1f, 1, 0.05f};
    const BodyId p = world.addBody(box({0.5f, 0.02f, 0.5f}), plate);
    const BodyId r = world.addBody(box({0.02f, 0.3f, 0.02f}), rod);
    ASSERT_EQ(world.boxNodes(p).size(), 8u);
    ASSERT_EQ(world.boxNodes(r).size(), 8u);
    auto bounds = [](std::span<const Vec3> nodes) {
        Aabb b;
        for (const Vec3& n : nodes) b.add(n);
        return b;
    };
    const float margin = settings.contactSkin * 1.2f + 0.01f;
    for (const Vec3& n : world.boxNodes(r))
        EXPECT_FALSE(bounds(world.boxNodes(p)).contains(n, margin));
    for (const Vec3& n : world.boxNodes(p))
        EXPECT_FALSE(bounds(world.boxNodes(r)).contains(n, margin));
    world.step();
    std::vector<BodyContact> partners;
    touchingBodies(world, r, partners);
    ASSERT_EQ(partners.size(), 1u);
    EXPECT_EQ(partners[0].other, p);
}

// Only faces that lead out of their objects give the pair's normal: a box pushed 10 cm into
// the side of a box whose +x face leads into its object's next cell (not an outside face)
// gets no contact from it when it lies beyond that face, and is pushed up, not sideways, when
// it lies within it.
TEST(NarrowPhase, BoxPairNormalsLeadOutOfTheObject) {
    const uint8_t topOnly = kFaceMaxY;
    const TestBox cell({0, 0, 0}, {1, 1, 1}, topOnly);
    const TestBox beyond({1.02f, 0.5f, 0.2f}, {1.5f, 1.2f, 0.8f});
    EXPECT_LT(detail::boxPairManifold(cell.view, beyond.view, 0.05f, 0.001f).reference, 0);
    const TestBox within({0.9f, 0.95f, 0.2f}, {1.5f, 1.5f, 0.8f});
    const detail::BoxPairManifold m =
        detail::boxPairManifold(cell.view, within.view, 0.05f, 0.001f);
    ASSERT_GT(m.count, 0);
    EXPECT_LE(length(m.normal - Vec3{0, 1, 0}), 1e-5f);
    // Least overlap (5 cm) along the top, an outside face: nothing bounds the depth.
    EXPECT_EQ(m.depthBound, INFINITY);
}

// Two cells whose only outside faces are their tops, the second reaching 1 cm across the
// first's +x face (which leads into the first body's next cell) and 70 cm below its top: the
// pair's normal is the first cell's top with points 70 cm deep, but its boxes overlap by only
// 1 cm across the +x face, and that is all the pair can show (depthBound). The seventy
// centimetres are the kind of claim that threw resting letters into the air.
TEST(NarrowPhase, OverlapAcrossAFaceIntoTheNextCellBoundsThePairsDepth) {
    const TestBox cell({0, 0, 0}, {1, 1, 1}, kFaceMaxY);
    const TestBox grazing({0.99f, 0.3f, 0.2f}, {1.5f, 1.2f, 0.8f}, kFaceMaxY);
    const detail::BoxPairManifold m =
        detail::boxPairManifold(cell.view, grazing.view, 0.05f, 0.001f);
    ASSERT_GT(m.count, 0);
    EXPECT_EQ(m.reference, 0);
    EXPECT_LE(length(m.normal - Vec3{0, 1, 0}), 1e-5f);
    EXPECT_NEAR(deepestPoint(m), -0.7f, 1e-4f);
    EXPECT_NEAR(m.depthBound, 0.01f, 1e-4f);
}

TEST(NarrowPhase, DeformedBoxPlanesFaceOutward) {
    Vec3 nodes[8];
    axisBox({0, 0, 0}, {1, 1, 1}, nodes);
    const test::SmoothDeformation warp(3, 1.0f, 0.2f);
    for (Vec3& n : nodes) n = warp(n);
    const detail::BoxPlanes planes = detail::boxPlanes(nodes);
    Vec3 centre{};
    for (const Vec3& n : nodes) centre += n * 0.125f;
    for (int f = 0; f < 6; ++f) {
        EXPECT_NEAR(length(planes.normal[f]), 1.0f, 1e-5f);
        EXPECT_LT(dot(planes.normal[f], centre) - planes.offset[f], 0.0f) << "face " << f;
    }
    // The centre is inside, far points are not.
    EXPECT_TRUE(detail::testNodeInBox(planes, boundsOf(nodes), 63, centre, 0.0f).inside);
    EXPECT_FALSE(
        detail::testNodeInBox(planes, boundsOf(nodes), 63, centre + Vec3{2, 0, 0}, 0.0f).inside);
}

TEST(NarrowPhase, TrilinearInversionRecoversLocalCoordinates) {
    Vec3 corners[8];
    axisBox({0, 0, 0}, {1, 1, 1}, corners);
    const test::SmoothDeformation warp(5, 1.0f, 0.15f);
    for (Vec3& c : corners) c = warp(c) * 0.7f;
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> u(0, 1);
    for (int i = 0; i < 200; i += 4) { // four points a call
        Vec3 local[4], p[4], got[4];
        for (int k = 0; k < 4; ++k) {
            local[k] = {u(rng), u(rng), u(rng)};
            float w[8];
            trilinearWeights(local[k], w);
            p[k] = {};
            for (int n = 0; n < 8; ++n) p[k] += corners[n] * w[n];
            got[k] = {0.5f, 0.5f, 0.5f};
        }
        detail::invertTrilinear4(corners, p, got, 4, 6);
        for (int k = 0; k < 4; ++k) EXPECT_LE(length(got[k] - local[k]), 1e-4f);
    }
}

namespace {

// Newton's method on the trilinear map, one point in scalar arithmetic: the steps
// invertTrilinear4 takes in each lane, written plainly.
Vec3 scalarNewton(const Vec3 c[8], Vec3 p, Vec3 guess, int iterations) {
    Vec3 l = guess;
    for (int it = 0; it < iterations; ++it) {
        const float s = l.x, t = l.y, u = l.z;
        float w[8];
        trilinearWeights(l, w);
        Vec3 f = -p;
        for (int k = 0; k < 8; ++k) f += c[k] * w[k];
        // Partial derivatives of the trilinear map.
        const Vec3 ds = (c[1] - c[0]) * ((1 - t) * (1 - u)) + (c[3] - c[2]) * (t * (1 - u)) +
                        (c[5] - c[4]) * ((1 - t) * u) + (c[7] - c[6]) * (t * u);
        const Vec3 dt = (c[2] - c[0]) * ((1 - s) * (1 - u)) + (c[3] - c[1]) * (s * (1 - u)) +
                        (c[6] - c[4]) * ((1 - s) * u) + (c[7] - c[5]) * (s * u);
        const Vec3 du = (c[4] - c[0]) * ((1 - s) * (1 - t)) + (c[5] - c[1]) * (s * (1 - t)) +
                        (c[6] - c[2]) * ((1 - s) * t) + (c[7] - c[3]) * (s * t);
        Mat3 J = Mat3::fromColumns(ds, dt, du), Jinv;
        if (!inverse(J, Jinv, 1e-30f)) break;
        const Vec3 step = Jinv * f;
        l -= step;
        if (lengthSquared(step) < 1e-12f) break; // float precision of local coordinates
    }
    return l;
}

} // namespace

// The four-lane inversion gives every lane what the scalar steps give its point, bit for bit:
// points inside and far outside a strongly deformed cell, guesses near and far, a cell too flat
// to invert (the scalar steps stop at once), one to four points, three and six iterations.
TEST(NarrowPhase, TrilinearInversionInLanesIsTheScalarOneBitForBit) {
    Vec3 warped[8], flat[8];
    axisBox({0, 0, 0}, {1, 1, 1}, warped);
    const test::SmoothDeformation warp(7, 1.0f, 0.3f);
    for (Vec3& c : warped) c = warp(c) * 0.9f;
    axisBox({0, 0, 0}, {1, 1, 1}, flat);
    for (Vec3& c : flat) c.y = 0; // no volume: no Jacobian to invert
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-0.5f, 1.5f);
    auto bits = [](Vec3 v) {
        uint32_t b[3];
        std::memcpy(b, &v, sizeof b);
        return std::array<uint32_t, 3>{b[0], b[1], b[2]};
    };
    int compared = 0;
    for (const Vec3* corners : {static_cast<const Vec3*>(warped), static_cast<const Vec3*>(flat)})
        for (int iterations : {3, 6})
            for (int count = 1; count <= 4; ++count)
                for (int trial = 0; trial < 200; ++trial) {
                    Vec3 p[4], guess[4], local[4];
                    for (int k = 0; k < count; ++k) {
                        p[k] = Vec3{u(rng), u(rng), u(rng)} * (trial % 10 == 0 ? 20.0f : 1.0f);
                        guess[k] = local[k] = Vec3{u(rng), u(rng), u(rng)};
                    }
                    detail::invertTrilinear4(corners, p, local, count, iterations);
                    for (int k = 0; k < count; ++k, ++compared)
                        ASSERT_EQ(bits(local[k]),
                                  bits(scalarNewton(corners, p[k], guess[k], iterations)))
                            << "point " << k << " of " << count << ", trial " << trial;
                }
    EXPECT_EQ(compared, 2 * 2 * (1 + 2 + 3 + 4) * 200);
}

TEST(SpatialHash, FastModIsTheRemainder) {
    std::mt19937 rng(11);
    const uint32_t divisors[] = {1u, 2u, 3u, 7u, 101u, 65537u, 1000003u, 2147483647u, 4294967291u};
    for (uint32_t t : divisors) {
        const uint64_t magic = detail::fastModMagic(t);
        for (uint32_t h : {0u, 1u, t - 1, t, t + 1, 0xffffffffu, 0x80000000u})
            EXPECT_EQ(detail::fastMod(h, magic, t), h % t) << h << " mod " << t;
        for (int n = 0; n < 20000; ++n) {
            const uint32_t h = uint32_t(rng());
            ASSERT_EQ(detail::fastMod(h, magic, t), h % t) << h << " mod " << t;
        }
    }
}

TEST(SpatialHash, FindsEveryItemOfACellAndNothingOfOthers) {
    detail::SpatialHash hash;
    // A tiny table: many cells share a bucket, and the exact-cell check must keep them apart.
    hash.begin(1, 1.0f);
    ASSERT_LE(hash.tableSize(), 3u);
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> u(-5, 5);
    std::vector<Vec3> points(500);
    for (uint32_t i = 0; i < points.size(); ++i) {
        points[i] = {u(rng), u(rng), u(rng)};
        hash.add(i, i % 7, points[i]);
    }
    hash.build();
    for (int k = -5; k < 5; ++k)
        for (int j = -5; j < 5; ++j)
            for (int i = -5; i < 5; ++i) {
                std::set<uint32_t> found;
                hash.forEachInCell(i, j, k, detail::SpatialHash::kNoOwner,
                                   [&](const detail::SpatialHash::Entry& e) {
                                       EXPECT_TRUE(found.insert(e.item).second);
                                       EXPECT_EQ(e.owner, e.item % 7);
                                   });
                for (uint32_t p = 0; p < points.size(); ++p) {
                    const bool inCell = hash.cell(points[p].x) == i &&
                                        hash.cell(points[p].y) == j && hash.cell(points[p].z) == k;
                    EXPECT_EQ(found.count(p) == 1, inCell);
                }
            }
    // A new step forgets the old items without clearing the table.
    hash.begin(1, 1.0f);
    hash.build();
    int seen = 0;
    hash.forEachInCell(hash.cell(points[0].x), hash.cell(points[0].y), hash.cell(points[0].z),
                       detail::SpatialHash::kNoOwner,
                       [&](const detail::SpatialHash::Entry&) { ++seen; });
    EXPECT_EQ(seen, 0);
    // Skipping an owner hides exactly its items.
    hash.begin(4, 1.0f);
    hash.add(0, 1, {0.5f, 0.5f, 0.5f});
    hash.add(1, 2, {0.6f, 0.5f, 0.5f});
    hash.add(2, 1, {3.5f, 0.5f, 0.5f});
    hash.build();
    std::vector<uint32_t> got;
    hash.forEachInCell(0, 0, 0, 1,
                       [&](const detail::SpatialHash::Entry& e) { got.push_back(e.item); });
    EXPECT_EQ(got, std::vector<uint32_t>{1});
    got.clear();
    hash.forEachInCell(3, 0, 0, 1,
                       [&](const detail::SpatialHash::Entry& e) { got.push_back(e.item); });
    EXPECT_TRUE(got.empty());
    EXPECT_EQ(detail::nextPrime(1000), 1009u);
    EXPECT_EQ(detail::nextPrime(2), 2u);
}

// Items with a reach (per owner) stand for cubes: a range query reports, exactly once, every
// item whose cube meets its bounds and nothing else, with and without an allowance, however
// many cells the cubes and the bounds cover (allowances up to a whole cell, as phase 2 uses).
TEST(SpatialHash, ReachCubesAreFoundExactlyOnce) {
    std::mt19937 rng(21);
    std::uniform_real_distribution<float> u(-3, 3), r(0, 1);
    const std::vector<float> reach = {0.0f, 0.05f, 0.3f, 0.9f, 2.5f};
    for (float allowance : {0.0f, 0.1f, 0.25f, 0.5f}) {
        detail::SpatialHash hash;
        hash.begin(400, 0.5f, reach, allowance);
        std::vector<Vec3> points(400);
        for (uint32_t i = 0; i < points.size(); ++i) {
            points[i] = {u(rng), u(rng), u(rng)};
            hash.add(i, i % 5, points[i]);
        }
        hash.reserveTable(hash.stagedCount());
        hash.build();
        // Slow owners' items in one cell, faster ones' in several, the fastest's kept apart.
        EXPECT_GT(hash.entryCount() + hash.wideCount(), points.size());
        EXPECT_GT(hash.wideCount(), 0u);
        size_t found = 0;
        for (int q = 0; q < 300; ++q) {
            const Vec3 c{u(rng), u(rng), u(rng)};
            const Vec3 h{r(rng), r(rng), r(rng)};
            const Aabb within{c - h, c + h};
            std::vector<int> seen(points.size(), 0);
            hash.forEachNear(within, 3,
                             [&](const detail::SpatialHash::Entry& e) { ++seen[e.item]; });
            for (uint32_t i = 0; i < points.size(); ++i) {
                const bool meets =
                    i % 5 != 3 && detail::SpatialHash::cubeMeets(points[i], reach[i % 5], within);
                ASSERT_EQ(seen[i], meets ? 1 : 0)
                    << "item " << i << " allowance " << allowance << " query " << q;
                found += seen[i];
            }
        }
        EXPECT_GT(found, 5000u);
    }
}

// Queries made together (forEachNearAll, as a body's boxes query the table) report exactly the
// (query, item) pairs that the same queries made one at a time do: items of every reach (one
// cell, several, kept apart), several owners to skip, queries close together (one block of
// cells, shared) and far apart (a block past kMaxGroupCells: one at a time).
TEST(SpatialHash, QueriesMadeTogetherFindWhatEachFindsAlone) {
    std::mt19937 rng(57);
    std::uniform_real_distribution<float> u(-3, 3), r(0, 0.6f), spread(-0.8f, 0.8f);
    const std::vector<float> reach = {0.0f, 0.05f, 0.3f, 0.9f, 2.5f};
    for (float allowance : {0.0f, 0.1f, 0.25f}) {
        detail::SpatialHash hash;
        hash.begin(600, 0.25f, reach, allowance);
        std::vector<Vec3> points(600);
        for (uint32_t i = 0; i < points.size(); ++i) {
            points[i] = {u(rng), u(rng), u(rng)};
            hash.add(i, (i / 7) % 5, points[i]); // owners in runs, as bodies add their nodes
        }
        hash.reserveTable(hash.stagedCount());
        hash.build();
        ASSERT_GT(hash.wideCount(), 0u);
        detail::SpatialHash::GroupScratch scratch;
        size_t found = 0;
        for (int group = 0; group < 80; ++group) {
            const bool far = group % 4 == 3;
            const Vec3 centre{u(rng), u(rng), u(rng)};
            std::vector<Aabb> within(1 + group % 9);
            for (Aabb& a : within) {
                const Vec3 c = far ? Vec3{u(rng), u(rng), u(rng)} * 40.0f
                                   : centre + Vec3{spread(rng), spread(rng), spread(rng)};
                const Vec3 h{r(rng), r(rng), r(rng)};
                a = {c - h, c + h};
            }
            const uint32_t skip = uint32_t(group % 6); // 5: no owner skipped
            const uint32_t skipOwner = skip == 5 ? detail::SpatialHash::kNoOwner : skip;
            std::multiset<std::pair<uint32_t, uint32_t>> alone, together;
            for (uint32_t q = 0; q < within.size(); ++q)
                hash.forEachNear(within[q], skipOwner, [&](const detail::SpatialHash::Entry& e) {
                    alone.insert({q, e.item});
                });
            hash.forEachNearAll(within, skipOwner, scratch,
                                [&](uint32_t q, const detail::SpatialHash::Entry& e) {
                                    together.insert({q, e.item});
                                });
            ASSERT_EQ(together, alone) << "group " << group << " allowance " << allowance;
            found += alone.size();
        }
        EXPECT_GT(found, 1000u);
    }
}

// Queries made together and told the largest reach of the owners wanted (less than the
// allowance) visit fewer cells but find every item of those owners that the plain queries find.
TEST(SpatialHash, QueriesToldTheirOwnersReachFindTheirItems) {
    std::mt19937 rng(58);
    std::uniform_real_distribution<float> u(-2, 2), r(0, 0.6f), spread(-0.8f, 0.8f);
    const std::vector<float> reach = {0.0f, 0.01f, 0.04f, 0.2f, 0.9f};
    detail::SpatialHash hash;
    hash.begin(3000, 0.25f, reach, 0.25f * 0.25f); // the allowance: a quarter of a cell
    std::vector<Vec3> points(3000);
    for (uint32_t i = 0; i < points.size(); ++i) {
        points[i] = {u(rng), u(rng), u(rng)};
        hash.add(i, (i / 7) % 5, points[i]);
    }
    hash.reserveTable(hash.stagedCount());
    hash.build();
    detail::SpatialHash::GroupScratch scratch;
    size_t found = 0;
    for (int group = 0; group < 120; ++group) {
        const Vec3 centre{u(rng), u(rng), u(rng)};
        std::vector<Aabb> within(1 + group % 9);
        for (Aabb& a : within) {
            const Vec3 c = centre + Vec3{spread(rng), spread(rng), spread(rng)};
            const Vec3 h{r(rng), r(rng), r(rng)};
            a = {c - h, c + h};
        }
        // The owners wanted: those of reach at most reach[top].
        const uint32_t top = uint32_t(group % 3);
        std::multiset<std::pair<uint32_t, uint32_t>> plain, told;
        hash.forEachNearAll(within, detail::SpatialHash::kNoOwner, scratch,
                            [&](uint32_t q, const detail::SpatialHash::Entry& e) {
                                if (e.owner <= top) plain.insert({q, e.item});
                            });
        hash.forEachNearAll(
            within, detail::SpatialHash::kNoOwner, scratch,
            [&](uint32_t q, const detail::SpatialHash::Entry& e) {
                if (e.owner <= top) told.insert({q, e.item});
            },
            reach[top]);
        ASSERT_EQ(told, plain) << "group " << group;
        found += plain.size();
    }
    EXPECT_GT(found, 1500u);
}

// The box pairs' keys sorted by radix come out as std::sort puts them, for few keys and many,
// for box counts that need a few bits and many (halves packed into up to 64 bits).
TEST(BoxPairKeys, SortLikeStdSort) {
    std::mt19937_64 rng(8);
    std::vector<uint64_t> scratch;
    for (uint32_t boxes : {2u, 300u, 5664u, 70000u, 0x80000000u})
        for (size_t n : {size_t(0), size_t(10), size_t(255), size_t(256), size_t(20000)}) {
            std::vector<uint64_t> keys(n);
            for (uint64_t& k : keys) {
                const uint64_t a = rng() % boxes, b = rng() % boxes;
                k = std::min(a, b) << 32 | std::max(a, b);
            }
            if (n > 100) // repeats, as the queries find them
                for (size_t i = 0; i < n / 2; ++i) keys[rng() % n] = keys[rng() % n];
            std::vector<uint64_t> expected = keys;
            std::sort(expected.begin(), expected.end());
            detail::sortBoxPairKeys(keys, scratch, boxes);
            ASSERT_EQ(keys, expected) << boxes << " boxes, " << n << " keys";
        }
}

// The cells of a pile around the origin spread over the buckets as random keys would: a block of
// 20 x 20 x 20 cells straddling the origin in a table of twice as many buckets fills 78.7 % as
// many buckets as cells at random. The paper's hash (i 73856093 ^ j 19349663 ^ k 83492791)
// fills 54.9 % there: the xor of small products of mixed signs lands neighbours together. The
// same holds of the keys the table takes its buckets from (the blocks of 4 x 4 x 4 cells at
// random), and of a flat pile and a tall one.
TEST(SpatialHash, CellsAroundTheOriginSpreadOverTheBuckets) {
    auto fill = [](int lo, int ni, int nj, int nk, auto&& key) {
        const uint32_t cells = uint32_t(ni * nj * nk), table = detail::nextPrime(2 * cells + 1);
        std::set<uint32_t> buckets;
        for (int k = lo; k < lo + nk; ++k)
            for (int j = lo; j < lo + nj; ++j)
                for (int i = lo; i < lo + ni; ++i) buckets.insert(key(i, j, k) % table);
        return double(buckets.size()) / cells;
    };
    for (const int lo : {-10, 0, -30, 7}) {
        EXPECT_GE(fill(lo, 20, 20, 20, detail::SpatialHash::cellHash), 0.75) << "from " << lo;
        EXPECT_GE(fill(lo, 20, 20, 20, detail::SpatialHash::cellKey), 0.75) << "from " << lo;
    }
    EXPECT_GE(fill(-37, 200, 10, 200, detail::SpatialHash::cellKey), 0.75);
    EXPECT_GE(fill(3, 61, 29, 59, detail::SpatialHash::cellKey), 0.75);
}

// A block of 4 x 4 x 4 cells (coordinates from a multiple of 4) has 64 consecutive keys, one per
// cell, so the cells a box's query visits share cache lines of the table; blocks straddling the
// origin and far from it alike.
TEST(SpatialHash, ABlocksCellsHaveConsecutiveKeys) {
    for (const int32_t lo : {-8, -4, 0, 4, 1 << 20, -(1 << 24)}) {
        std::set<uint32_t> keys;
        for (int32_t k = lo; k < lo + 4; ++k)
            for (int32_t j = lo; j < lo + 4; ++j)
                for (int32_t i = lo; i < lo + 4; ++i)
                    keys.insert(detail::SpatialHash::cellKey(i, j, k));
        ASSERT_EQ(keys.size(), 64u) << "block from " << lo;
        EXPECT_EQ(*keys.rbegin() - *keys.begin(), 63u) << "block from " << lo;
        EXPECT_EQ(*keys.begin() % 64, 0u) << "block from " << lo;
    }
    // Neighbouring blocks do not share keys.
    EXPECT_NE(detail::SpatialHash::cellKey(0, 0, 0) / 64,
              detail::SpatialHash::cellKey(4, 0, 0) / 64);
}

// Items added owner after owner, as the pipeline adds each body's nodes: a bucket's entries come
// in runs of one owner, and a query skips the querying owner's run at either end unread. In a
// tiny table (every bucket holds many cells and owners) and a roomy one, with each owner skipped
// in turn, a query still reports exactly the other owners' items.
TEST(SpatialHash, SkippingTheQueryingOwnersRunsHidesExactlyItsItems) {
    std::mt19937 rng(33);
    std::uniform_real_distribution<float> u(-2, 2), r(0, 0.8f);
    constexpr uint32_t kOwners = 6, kPerOwner = 60;
    std::vector<Vec3> points(kOwners * kPerOwner);
    for (Vec3& p : points) p = {u(rng), u(rng), u(rng)};
    // Owner 2's items all in one cell: a bucket of a single run.
    for (uint32_t i = 2 * kPerOwner; i < 3 * kPerOwner; ++i)
        points[i] = {0.1f + 0.001f * float(i % 7), 0.2f, 0.3f};
    for (size_t expected : {size_t(1), points.size()}) {
        detail::SpatialHash hash;
        hash.begin(expected, 0.5f);
        for (uint32_t i = 0; i < points.size(); ++i) hash.add(i, i / kPerOwner, points[i]);
        hash.build();
        for (uint32_t skip = 0; skip <= kOwners; ++skip) {
            const uint32_t skipOwner = skip == kOwners ? detail::SpatialHash::kNoOwner : skip;
            for (int q = 0; q < 60; ++q) {
                const Vec3 c{u(rng), u(rng), u(rng)};
                const Vec3 h{r(rng), r(rng), r(rng)};
                const Aabb within{c - h, c + h};
                std::vector<int> seen(points.size(), 0);
                hash.forEachNear(within, skipOwner,
                                 [&](const detail::SpatialHash::Entry& e) { ++seen[e.item]; });
                for (uint32_t i = 0; i < points.size(); ++i)
                    ASSERT_EQ(seen[i], i / kPerOwner != skip && within.contains(points[i], 0))
                        << "item " << i << " skipping " << skip << " table " << hash.tableSize();
            }
            std::vector<int> seen(points.size(), 0);
            for (int k = -4; k < 4; ++k)
                for (int j = -4; j < 4; ++j)
                    for (int i = -4; i < 4; ++i)
                        hash.forEachInCell(
                            i, j, k, skipOwner,
                            [&](const detail::SpatialHash::Entry& e) { ++seen[e.item]; });
            for (uint32_t i = 0; i < points.size(); ++i)
                ASSERT_EQ(seen[i], i / kPerOwner != skip ? 1 : 0) << "item " << i;
        }
    }
}

namespace {

// The paper's objects (letters, spheres, teapots, a dragon), placed, rotated and deformed at
// random, n at a time. The world's model cache makes re-adding them cheap.
class Pool {
public:
    Pool() {
        TriangleMesh sphere = ball(0.45f);
        TriangleMesh pot = teapot(10);
        normalizeSize(pot, 1.0f);
        TriangleMesh dragonMesh = dragon();
        normalizeSize(dragonMesh, 1.1f);
        kinds.push_back({sphere, 38});
        kinds.push_back({pot, 84});
        kinds.push_back({dragonMesh, 148});
        for (char c : {'A', 'B', 'G', 'K', 'O', 'S', 'W', 'X'}) kinds.push_back({letter(c), 34});
    }

    // n bodies in a cube of side about 1.4 roomScale cbrt(n) m.
    void configure(std::mt19937& rng, int n, float roomScale = 0.7f) {
        for (BodyId id : world.bodies()) world.removeBody(id);
        std::uniform_real_distribution<float> u(-1, 1);
        std::uniform_int_distribution<size_t> pick(0, kinds.size() - 1);
        const float room = roomScale * std::cbrt(float(n));
        bool dragonUsed = false;
        for (int i = 0; i < n; ++i) {
            size_t k = pick(rng);
            if (k == 2 && dragonUsed) k = 0; // one dragon at most: it has 8 times the nodes
            dragonUsed = dragonUsed || k == 2;
            BodySettings s;
            s.lattice.targetCells = kinds[k].cells;
            const BodyId id = world.addBody(kinds[k].mesh, s);
            const Lattice& L = world.lattice(id);
            Vec3 centre{};
            for (const Vec3& p : L.restParticles) centre += p / float(L.particleCount());
            const Mat3 R = toMat3(normalize(Quat{u(rng), u(rng), u(rng), u(rng)}));
            const Vec3 where{room * u(rng), room * u(rng) + 3.0f, room * u(rng)};
            const test::SmoothDeformation warp(uint32_t(rng()), 1.0f, 0.25f * std::fabs(u(rng)));
            std::vector<Vec3> x(L.particleCount());
            for (size_t p = 0; p < x.size(); ++p)
                x[p] = warp(R * (L.restParticles[p] - centre)) + where;
            world.setParticles(id, x);
            // Velocities widen the speculative margins: give some bodies some.
            world.setVelocity(id, Vec3{u(rng), u(rng), u(rng)} * (i % 3 == 0 ? 4.0f : 0.0f));
        }
    }

    // Uneven particle velocities: each body at rest, slow, or fast (10-50 m/s), and in some
    // bodies a share of the particles moving the other way or spinning, so that a body's spread
    // (largest deviation from its mean velocity) is up to twice its speed.
    void unevenVelocities(std::mt19937& rng) {
        detail::WorldData& w = detail::dataOf(world);
        std::uniform_real_distribution<float> u(-1, 1);
        for (const detail::BodyRecord& r : w.bodies) {
            const int kind = int(rng() % 5);
            const Vec3 dir = normalize(Vec3{u(rng), u(rng), u(rng)} + Vec3{0, 1e-3f, 0});
            const float speed = kind == 0 ? 0.0f : kind == 1 ? 1.0f : 30.0f + 20.0f * u(rng);
            const uint32_t reversed = kind == 3 ? 1 + uint32_t(rng() % r.particleCount) : 0;
            for (uint32_t i = 0; i < r.particleCount; ++i) {
                Vec3 v = dir * speed;
                if (i < reversed) v = -v; // moving backwards
                if (kind == 4) v += Vec3{u(rng), u(rng), u(rng)} * (0.5f * speed); // spinning
                w.v[r.firstParticle + i] = v;
            }
        }
    }

    struct Kind {
        TriangleMesh mesh;
        int cells;
    };
    std::vector<Kind> kinds;
    World world;
};

// The contacts `mode` finds on the world's current state, each with its solver zone's key (the
// order they come in: zone by zone, canonical within a zone); `testedPairs`: how many node/box
// pairs it tested.
std::vector<std::tuple<uint32_t, uint64_t, Vec3, float>>
contactSet(detail::WorldData& w, CollisionMode mode, int* testedPairs = nullptr) {
    detail::CollisionWorld view = detail::collisionView(w);
    detail::updateNodes(view, 0, w.bodies.size());
    w.collision.pairs.clear();
    if (mode == CollisionMode::Enhanced) detail::sphereTest(view);
    detail::ContactList contacts;
    detail::ObjectContactCounts counts;
    detail::findObjectContacts(view, mode, contacts, counts);
    if (testedPairs) *testedPairs = counts.nodeBoxPairs;
    std::vector<detail::ZoneCell> cells;
    detail::zoneCells(view, cells);
    int32_t i0, k0;
    detail::lowestZoneCell(cells, i0, k0);
    std::vector<std::tuple<uint32_t, uint64_t, Vec3, float>> out;
    for (const detail::Contact& c : contacts)
        out.emplace_back(detail::zoneKey(cells[c.bodyA], cells[c.bodyB], i0, k0),
                         detail::contactKey(c), c.normal, c.depth());
    return out;
}

} // namespace

TEST(CollisionModes, BrutePreviousAndEnhancedFindIdenticalContacts) {
    Pool pool;
    detail::WorldData& w = detail::dataOf(pool.world);
    w.substep = 1.0f / 120.0f;
    std::mt19937 rng(12345);
    std::uniform_int_distribution<int> count(2, 20);
    size_t withContacts = 0, total = 0, prunedPairs = 0;
    for (int config = 0; config < 1000; ++config) {
        const int n = count(rng);
        pool.configure(rng, n);
        int tested[3] = {};
        const auto brute = contactSet(w, CollisionMode::Brute, &tested[0]);
        const auto previous = contactSet(w, CollisionMode::Previous, &tested[1]);
        const auto enhanced = contactSet(w, CollisionMode::Enhanced, &tested[2]);
        // `previous` tests the node/box pairs brute force tests within reach; `enhanced` those
        // of the pairs phase 1 keeps, no more.
        ASSERT_EQ(tested[1], tested[0]) << "configuration " << config;
        ASSERT_LE(tested[2], tested[1]) << "configuration " << config;
        ASSERT_EQ(previous, brute) << "configuration " << config << " with " << n << " objects";
        for (size_t k = 1; k < brute.size(); ++k) // zone by zone, canonical within each
            ASSERT_LT(std::make_pair(std::get<0>(brute[k - 1]), std::get<1>(brute[k - 1])),
                      std::make_pair(std::get<0>(brute[k]), std::get<1>(brute[k])))
                << "not in the zones' canonical order";
        ASSERT_EQ(enhanced, brute) << "configuration " << config << " with " << n << " objects";
        withContacts += !brute.empty();
        total += brute.size();
        prunedPairs += size_t(n) * size_t(n - 1) / 2 - w.collision.pairs.size();
    }
    // The configurations collide for real, and the spheres prune real pairs.
    EXPECT_GT(withContacts, 800u);
    EXPECT_GT(total, 50000u);
    EXPECT_GT(prunedPairs, 10000u);
    RecordProperty("contacts", int(total));
}

// Above settings.sweepThreshold bodies phase 1 sorts and sweeps: with more than 64 bodies of
// uneven particle velocities (fast, slow, some particles reversed, spinning) its window must
// still cover every margin the narrow phase uses, so the three modes find identical contacts.
TEST(CollisionModes, SweepPathWithUnevenVelocitiesFindsIdenticalContacts) {
    Pool pool;
    detail::WorldData& w = detail::dataOf(pool.world);
    w.substep = 1.0f / 120.0f;
    ASSERT_EQ(w.settings.sweepThreshold, 64);
    std::mt19937 rng(2024);
    size_t total = 0, prunedPairs = 0;
    std::vector<int> sizes;
    for (int config = 0; config < 6; ++config) {
        const int n = 65 + int(rng() % 30);
        pool.configure(rng, n, 1.6f);
        pool.unevenVelocities(rng);
        int tested[3] = {};
        const auto brute = contactSet(w, CollisionMode::Brute, &tested[0]);
        const auto previous = contactSet(w, CollisionMode::Previous, &tested[1]);
        const auto enhanced = contactSet(w, CollisionMode::Enhanced, &tested[2]);
        ASSERT_EQ(previous, brute) << "configuration " << config << " with " << n << " objects";
        ASSERT_EQ(enhanced, brute) << "configuration " << config << " with " << n << " objects";
        // The node/box pairs within reach depend on the two bodies only: `previous` tests those
        // brute force tests, `enhanced` those of the pairs phase 1 keeps, no more.
        EXPECT_EQ(tested[1], tested[0]) << "configuration " << config;
        EXPECT_LE(tested[2], tested[1]) << "configuration " << config;
        total += brute.size();
        prunedPairs += size_t(n) * size_t(n - 1) / 2 - w.collision.pairs.size();
    }
    EXPECT_GT(total, 5000u);       // they collide for real
    EXPECT_GT(prunedPairs, 5000u); // and the sweep rejects real pairs
}

// The case that a sweep window sized from the fastest particle missed: two spheres 3.4 m apart
// closing fast, one particle of each moving the other way (a spread twice the speed), among 64
// others (so phase 1 sweeps). Within one substep their nodes and boxes can meet; every mode
// must find the same contacts. (At 50 m/s each the margin's bound found contacts, but their
// points cannot close the 2.4 m between them in a substep, and the speculative reach leaves
// none; at 100 m/s each they can.)
TEST(CollisionModes, SweepFindsFastBodiesWithReversedParticles) {
    World world;
    for (int i = 0; i < 64; ++i)
        world.addBody(test::ball(),
                      test::sphereAt({4.0f * float(i % 8), 3.0f, 20.0f + 4.0f * float(i / 8)}));
    const BodyId a = world.addBody(test::ball(), test::sphereAt({0, 3, 0}, {100, 0, 0}));
    const BodyId b = world.addBody(test::ball(), test::sphereAt({3.4f, 3, 0}, {-100, 0, 0}));
    detail::WorldData& w = detail::dataOf(world);
    w.substep = 1.0f / 120.0f;
    for (BodyId id : {a, b}) {
        const detail::BodyRecord& r = *w.find(id);
        w.v[r.firstParticle] = -w.v[r.firstParticle];
    }
    const auto brute = contactSet(w, CollisionMode::Brute);
    EXPECT_GT(brute.size(), 100u);
    EXPECT_EQ(contactSet(w, CollisionMode::Previous), brute);
    EXPECT_EQ(contactSet(w, CollisionMode::Enhanced), brute);
}

// Phase 2's allowance follows the fastest hashed body's reach, up to a whole hash cell: while no
// body's reach exceeds a cell, every node and box centre is stored in its own cell only (none in
// several, none kept apart), however fast the bodies, and the contacts are those brute force
// finds. Balls thrown at each other in pairs, faster pair after pair.
TEST(ObjectContacts, NodesAreStoredInTheirOwnCellWhileNoReachExceedsACell) {
    World world;
    for (int i = 0; i < 6; ++i) {
        const float speed = 2.0f + 3.0f * float(i), z = 3.0f * float(i);
        world.addBody(test::ball(), test::sphereAt({-0.6f, 1.5f, z}, {speed, 0, 0}));
        world.addBody(test::ball(), test::sphereAt({0.6f, 1.5f, z}, {-speed, 0, 0}));
    }
    detail::WorldData& w = detail::dataOf(world);
    const float cell = w.collision.bodies.empty() ? 0.0f : w.collision.bodies[0].cellSize;
    int checked = 0, beyondAQuarter = 0;
    for (int f = 0; f < 30; ++f) {
        world.step();
        if (world.profile().potentialPairs == 0) continue; // no query in the last substep
        float reach = 0;
        size_t samples = 0;
        for (size_t b = 0; b < w.collision.reach.size(); ++b)
            if (w.collision.hashedSamples[b] > 0) {
                reach = std::max(reach, w.collision.reach[b]);
                samples += w.collision.hashedSamples[b];
            }
        ASSERT_GT(cell, 0.0f);
        if (reach > cell) continue;
        ++checked;
        beyondAQuarter += reach > 0.25f * cell;
        EXPECT_EQ(w.collision.hash.entryCount(), samples) << "frame " << f << " reach " << reach;
        EXPECT_EQ(w.collision.hash.wideCount(), 0u) << "frame " << f;
        EXPECT_EQ(contactSet(w, CollisionMode::Enhanced), contactSet(w, CollisionMode::Brute))
            << "frame " << f;
    }
    EXPECT_GE(checked, 3);
    EXPECT_GE(beyondAQuarter, 2); // where a quarter of a cell stored fast nodes in several cells
}

TEST(CollisionModes, SweepAndAllPairsAgree) {
    Pool pool;
    detail::WorldData& w = detail::dataOf(pool.world);
    w.substep = 1.0f / 120.0f;
    std::mt19937 rng(9);
    for (int config = 0; config < 100; ++config) {
        pool.configure(rng, 20, config % 2 ? 1.6f : 0.7f);
        if (config % 4 >= 2) pool.unevenVelocities(rng);
        w.settings.sweepThreshold = 1000;
        detail::CollisionWorld view = detail::collisionView(w);
        detail::updateNodes(view, 0, w.bodies.size());
        detail::sphereTest(view);
        std::vector<detail::CandidatePair> all, sweep;
        detail::sphereTestAllPairs(view, all);
        detail::sphereTestSweep(view, sweep);
        ASSERT_EQ(all, sweep) << config;
    }
}

TEST(CollisionModes, PreviousAndEnhancedGiveIdenticalTrajectories) {
    auto run = [](CollisionMode mode) {
        WorldSettings ws;
        ws.mode = mode;
        World world(ws);
        std::mt19937 rng(1);
        std::uniform_real_distribution<float> u(-1, 1);
        for (int i = 0; i < 20; ++i) {
            BodySettings s = sphereSettings({0.3f * u(rng), 0.8f + 1.1f * float(i), 0.3f * u(rng)});
            s.rotation = normalize(Quat{u(rng), u(rng), u(rng), u(rng)});
            world.addBody(ball(), s);
        }
        int contacts = 0;
        for (int f = 0; f < 600; ++f) {
            world.step();
            contacts += world.profile().contacts;
        }
        return std::make_pair(world.stateHash(), contacts);
    };
    const auto enhanced = run(CollisionMode::Enhanced);
    const auto previous = run(CollisionMode::Previous);
    EXPECT_EQ(enhanced.first, previous.first);
    EXPECT_EQ(enhanced.second, previous.second);
    EXPECT_GT(enhanced.second, 300); // they did pile and collide
}

TEST(CollisionResponse, FiftySpheresInAColumnSettleWithoutPassingThrough) {
    World world;
    const int n = 50;
    std::vector<BodyId> ids;
    for (int i = 0; i < n; ++i) {
        BodySettings s =
            sphereSettings({0.05f * float(i % 3), 0.6f + 1.05f * float(i), 0.05f * float(i % 2)});
        ids.push_back(world.addBody(ball(), s));
    }
    const float h = world.info(ids[0]).cellSize;
    float closest = 1e9f;
    for (int f = 0; f < 900; ++f) {
        world.step();
        // No pair ever overlaps deeply: the centres of two radius-0.5 spheres stay well apart.
        closest = std::min(closest, test::closestCentres(world));
        if (f % 100 == 0) {
            for (BodyId id : ids) ASSERT_TRUE(isFinite(world.centreOfMass(id))) << "frame " << f;
        }
    }
    EXPECT_GT(closest, 0.75f);
    // No mesh vertex deeper than 10 % of the lattice spacing inside another object's boxes.
    const detail::WorldData& w = detail::dataOf(world);
    float deepest = 0;
    for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
            if (a == b) continue;
            const auto& B = w.bodies[size_t(b)];
            const auto nodes = world.boxNodes(ids[b]);
            for (uint32_t k = 0; k < B.boxCount; ++k) {
                const detail::BoxPlanes planes = detail::boxPlanes(&nodes[k * 8]);
                const Aabb bb = boundsOf(&nodes[k * 8]);
                for (const Vec3& v : world.vertices(ids[a])) {
                    const detail::NodeBoxHit hit = detail::testNodeInBox(
                        planes, bb, B.model->lattice.boxes[k].outsideFaces, v, 0.0f);
                    if (hit.inside) deepest = std::max(deepest, -hit.distance);
                }
            }
        }
    EXPECT_LE(deepest, 0.1f * h);
    // Everything is on or above the floor.
    for (BodyId id : ids)
        for (const Vec3& v : world.vertices(id)) EXPECT_GT(v.y, -0.01f * h);
}

// The alphabets scene with layout seed 8, while its layers land: at frame 60 a vertex of letter
// 147 lay 2.22 cm inside letter 111 (an H), whose box beside the notch between its legs led into
// the next cell's, so a box pair apart along it by 9.5 mm made no contact, and the next cell's
// box, across the notch, met nothing. The faces towards the notch now lead out of the body
// (Lattice.AFaceTowardsANotchInItsNeighbourCellLeadsOut): by the mesh measure, no vertex deeper
// than 1 % of a letter's size inside another letter, sampled every 10 frames up to frame 80.
TEST(CollisionResponse, AlphabetsSeedEightLandsWithoutSinking) {
    Scene scene = loadScene("alphabets");
    scene.layout.seed = 8;
    SceneBuild build = buildScene(scene);
    for (int f = 1; f <= 80; ++f) {
        build.world.step();
        if (f % 10 == 0) {
            ASSERT_LT(test::deepestInside(build.world), 0.01) << "frame " << f;
        }
    }
}

TEST(CollisionResponse, ASphereThrownAt20MetresPerSecondDoesNotTunnel) {
    for (CollisionMode mode : {CollisionMode::Enhanced, CollisionMode::Previous}) {
        WorldSettings ws;
        ws.mode = mode;
        World world(ws);
        const BodyId target = world.addBody(ball(), sphereSettings({0, 0.5f, 0}));
        for (int f = 0; f < 120; ++f) world.step(); // at rest on the floor
        BodySettings s = sphereSettings({-3.0f, 0.55f, 0});
        s.velocity = {20, 0, 0};
        const BodyId bullet = world.addBody(ball(), s);
        float minGap = 1e9f;
        for (int f = 0; f < 60; ++f) {
            world.step();
            const float gap = world.centreOfMass(target).x - world.centreOfMass(bullet).x;
            minGap = std::min(minGap, gap);
        }
        EXPECT_GT(minGap, 0.6f) << toString(mode); // never through, never deep inside
        EXPECT_GT(world.centreOfMass(target).x, 0.5f) << "the target was hit and pushed";
    }
}

// The paper's four scenes at full size (165 letters, 100 spheres, 80 teapots, 30 dragons),
// stepped in `previous` and `enhanced` side by side while their layers land: every frame the
// two find the same contacts, `enhanced` tests no node/box pair `previous` does not (and
// `previous` few more: no scene-wide margin inflates its queries), and they end in the same
// state.
TEST(CollisionModes, PaperScenesAtFullSizeAgree) {
    const std::pair<const char*, int> scenes[] = {
        {"alphabets", 70}, {"spheres", 70}, {"teapots", 70}, {"buddhas", 60}};
    for (const auto& [name, frames] : scenes) {
        SCOPED_TRACE(name);
        Scene scene = loadScene(name);
        scene.world.mode = CollisionMode::Previous;
        SceneBuild previous = buildScene(scene);
        scene.world.mode = CollisionMode::Enhanced;
        SceneBuild enhanced = buildScene(scene);
        int framesWithContacts = 0;
        double testedPrevious = 0, testedEnhanced = 0;
        for (int f = 0; f < frames; ++f) {
            previous.world.step();
            enhanced.world.step();
            const Profile& p = previous.world.profile();
            const Profile& e = enhanced.world.profile();
            ASSERT_EQ(p.contacts, e.contacts) << name << " frame " << f;
            // Phase 1 only removes pairs that cannot touch: the node/box pairs tested are
            // those of the pairs it keeps, which `previous` tests too.
            ASSERT_LE(e.potentialPairs, p.potentialPairs) << name << " frame " << f;
            EXPECT_LT(e.candidatePairs, p.candidatePairs) << name << " frame " << f;
            testedPrevious += p.potentialPairs, testedEnhanced += e.potentialPairs;
            framesWithContacts += e.contacts > 0;
        }
        EXPECT_GE(testedEnhanced, 0.9 * double(testedPrevious)) << name;
        EXPECT_EQ(previous.world.stateHash(), enhanced.world.stateHash()) << name;
        EXPECT_GT(framesWithContacts, 10) << name << ": the objects must collide";
    }
}

// What each box pair claimed in the last substep is kept by box-pair key (object_contacts.cpp,
// emitBoxPairs). Removing a body renumbers the boxes after its own: the claims of the other
// pairs follow their boxes, with the same depths, and none is left naming a removed box.
TEST(BoxPairClaims, FollowTheirBoxesWhenABodyIsRemoved) {
    World world;
    const BodyId first = world.addBody(ball(), sphereSettings({-3, 0.5f, 0}));
    const BodyId lower = world.addBody(ball(), sphereSettings({0, 0.5f, 0}));
    const BodyId upper = world.addBody(ball(), sphereSettings({0.1f, 1.45f, 0}));
    const BodyId beside = world.addBody(ball(), sphereSettings({-3, 1.45f, 0}));
    for (int f = 0; f < 30; ++f) world.step();
    const detail::WorldData& w = detail::dataOf(world);
    // Each claim as (body slot, box within the body) twice, and its depths.
    using Claim = std::tuple<uint32_t, uint32_t, uint32_t, uint32_t, float, float>;
    auto claims = [&] {
        std::set<Claim> out;
        for (const detail::BoxPairClaim& c : w.collision.claims) {
            uint32_t at[4];
            for (int j = 0; j < 2; ++j) {
                const uint32_t box = j == 0 ? uint32_t(c.key >> 32) : uint32_t(c.key);
                const detail::BodyRecord& r = w.bodies[w.collision.boxBody[box]];
                at[2 * j] = r.slot;
                at[2 * j + 1] = box - r.firstBox;
            }
            out.insert({at[0], at[1], at[2], at[3], c.claimed, c.deepest});
        }
        return out;
    };
    const std::set<Claim> before = claims();
    std::set<Claim> expected;
    for (const Claim& c : before)
        if (std::get<0>(c) != first.index && std::get<2>(c) != first.index) expected.insert(c);
    ASSERT_FALSE(expected.empty());            // the stacked pairs touch
    ASSERT_LT(expected.size(), before.size()); // and so do the first two on their own
    ASSERT_TRUE(world.removeBody(first));
    EXPECT_EQ(claims(), expected);
    EXPECT_TRUE(std::is_sorted(w.collision.claims.begin(), w.collision.claims.end(),
                               [](const detail::BoxPairClaim& a, const detail::BoxPairClaim& b) {
                                   return a.key < b.key;
                               }));
    for (int f = 0; f < 30; ++f) world.step();
    EXPECT_TRUE(world.isValid(lower) && world.isValid(upper) && world.isValid(beside));
}

// A contact point is its box and local coordinates; its particles come from the box table
// (rebuilt when bodies come and go) and its weights are made where it is read. Checked against
// the lattices themselves and a trilinear blend written out here, after a body is removed from
// the middle of a pile (every later box renumbered) and another added.
TEST(ContactPoints, TheBoxTableAndTheBlendsFollowTheLattices) {
    Scene scene = loadScene("spheres");
    scene.objects[0].count = 30;
    SceneBuild build = buildScene(scene);
    for (int f = 0; f < 40; ++f) build.world.step();
    ASSERT_TRUE(build.world.removeBody(build.bodies[4]));
    BodySettings above;
    above.position = {0, 6, 0};
    build.world.addBody(icosphere(2), above);
    for (int f = 0; f < 40; ++f) build.world.step();
    const detail::WorldData& w = detail::dataOf(build.world);
    const detail::CollisionState& s = w.collision;
    size_t boxes = 0;
    for (const detail::CollisionBody& b : s.bodies) {
        for (uint32_t k = 0; k < b.boxCount; ++k) {
            const auto& corners = b.lattice->cellParticles[b.lattice->boxes[k].cell];
            for (int n = 0; n < 8; ++n)
                ASSERT_EQ(s.boxParticles[b.firstBox + k][n], b.firstParticle + corners[n]);
        }
        boxes += b.boxCount;
    }
    EXPECT_EQ(s.boxParticles.size(), boxes);
    ASSERT_GT(s.objectCount, 10u); // the spheres lie on each other
    auto blended = [&](const detail::ContactPoint& p) {
        const Vec3 l = p.local;
        Vec3 sum{};
        for (int n = 0; n < 8; ++n) {
            const float ws = (n & 1) ? l.x : 1 - l.x, wt = (n & 2) ? l.y : 1 - l.y;
            const float wu = (n & 4) ? l.z : 1 - l.z;
            sum += w.x[s.boxParticles[p.box][n]] * (ws * wt * wu);
        }
        return sum;
    };
    for (const detail::Contact& c : s.all) {
        const Vec3 a = detail::blend(c.a, s.boxParticles, w.x);
        EXPECT_LT(length(a - blended(c.a)), 1e-5f);
        if (!c.hasB) continue;
        const Vec3 b = detail::blend(c.b, s.boxParticles, w.x);
        EXPECT_LT(length(b - blended(c.b)), 1e-5f);
        EXPECT_FLOAT_EQ(detail::separation(c, s.boxParticles, w.x),
                        dot(a - b, c.normal) - c.offset);
    }
}

// The invariants FFD_CHECKS asserts after every schedule build: met by a real pile's contacts
// and schedule, and each broken one found.
TEST(SolverSchedule, APilesScheduleMeetsItsInvariantsAndBrokenOnesAreFound) {
    Scene scene = loadScene("spheres");
    scene.objects[0].count = 30;
    SceneBuild build = buildScene(scene);
    for (int f = 0; f < 40; ++f) build.world.step();
    const detail::WorldData& w = detail::dataOf(build.world);
    const detail::CollisionState& s = w.collision;
    ASSERT_GT(s.all.size(), 100u); // the spheres lie on each other and the floor
    const detail::SolverSchedule& real = s.solver.schedule;
    ASSERT_GT(real.colourStart.size(), 2u); // more than one colour
    EXPECT_EQ(detail::scheduleProblem(s.all, real, w.bodies.size()), "");
    EXPECT_EQ(detail::contactProblem(s.all, s.boxParticles, w.bodies.size(), s.bodyFirstParticle,
                                     s.bodyParticleCount),
              "");

    detail::SolverSchedule twice = real;
    twice.order[1] = twice.order[0];
    EXPECT_NE(detail::scheduleProblem(s.all, twice, w.bodies.size()).find("twice"),
              std::string::npos);

    // Two floor contacts of one body in two zones of one colour (and a tail colour after it).
    std::vector<detail::Contact> floor(3);
    for (detail::Contact& c : floor) c.bodyA = 0;
    floor[2].bodyA = 1;
    detail::SolverSchedule shared;
    shared.order = {0, 1, 2};
    shared.zoneStart = {0, 1, 2, 3};
    shared.colourStart = {0, 2, 3};
    shared.bySize = {0, 1, 2};
    EXPECT_NE(detail::scheduleProblem(floor, shared, 2).find("two zones of one colour"),
              std::string::npos);
    shared.colourStart = {0, 1, 2, 3}; // each zone its own colour: nothing shared
    EXPECT_EQ(detail::scheduleProblem(floor, shared, 2), "");

    // The same contacts in blocks of at least 64: bands of zone rows, each block's zones of a
    // colour a run of that colour's, the blocks' rows in order, the tail in the last block.
    detail::SolverSchedule banded;
    detail::Workers workers;
    detail::buildSolverSchedule(s.all, s.solver.cells, banded, workers, 64);
    ASSERT_GT(banded.blockCount(), 2u);
    EXPECT_EQ(detail::scheduleProblem(s.all, banded, w.bodies.size()), "");
    EXPECT_EQ(banded.order, real.order); // the zones and their contacts as without blocks
    EXPECT_EQ(banded.zoneStart, real.zoneStart);
    const size_t colours = banded.colourCount();
    uint32_t lastRow = 0;
    for (size_t b = 0; b < banded.blockCount(); ++b) {
        uint32_t contacts = 0, lowest = UINT32_MAX, highest = 0;
        for (size_t c = 0; c < colours; ++c)
            for (uint32_t z = banded.blockZone(b, c); z < banded.blockZone(b + 1, c); ++z) {
                contacts += banded.zoneStart[z + 1] - banded.zoneStart[z];
                if (banded.zones[z] == detail::kTailZone) {
                    EXPECT_EQ(b + 1, banded.blockCount()) << "the tail before the last block";
                    continue;
                }
                const uint32_t row =
                    banded.zones[z] >> detail::kZoneIndexBits & detail::kZoneIndexMask;
                lowest = std::min(lowest, row), highest = std::max(highest, row);
            }
        if (b + 1 < banded.blockCount()) {
            EXPECT_GE(contacts, 64u) << "block " << b;
        }
        if (b > 0) {
            EXPECT_GT(lowest, lastRow) << "block " << b << " shares a row";
        }
        lastRow = highest;
    }
    detail::SolverSchedule crossed = banded;
    crossed.blockStart[colours] = crossed.colourStart[1] + 1; // past its colour's end
    EXPECT_NE(detail::scheduleProblem(s.all, crossed, w.bodies.size()).find("block"),
              std::string::npos);

    std::vector<detail::Contact> stray(s.all.begin(), s.all.begin() + 2);
    auto problem = [&] {
        return detail::contactProblem(stray, s.boxParticles, w.bodies.size(), s.bodyFirstParticle,
                                      s.bodyParticleCount);
    };
    stray[1].a.box = uint32_t(s.boxParticles.size()); // beyond every body's boxes
    EXPECT_NE(problem().find("box out of range"), std::string::npos);
    // A box of another body than the contact's A.
    const detail::CollisionBody& other = s.bodies[stray[1].bodyA == 0 ? 1 : 0];
    stray[1].a.box = other.firstBox;
    EXPECT_NE(problem().find("another body's particle"), std::string::npos);
    stray[1].a = s.all[1].a;
    stray[1].a.local.y = NAN;
    EXPECT_NE(problem().find("not finite"), std::string::npos);
}
