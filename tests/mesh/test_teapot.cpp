#include "ffdaabb/error.h"
#include "ffdaabb/generators.h"
#include "ffdaabb/mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>
#include <set>
#include <tuple>
#include <utility>

using namespace ffd;

namespace {

bool isDegenerate(const std::array<uint32_t, 3>& t) {
    return t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
}

Vec3 faceNormal(const TriangleMesh& m, const std::array<uint32_t, 3>& t) {
    const Vec3 a = m.positions[t[0]], b = m.positions[t[1]], c = m.positions[t[2]];
    return cross(b - a, c - a);
}

Vec3 centroid(const TriangleMesh& m, const std::array<uint32_t, 3>& t) {
    return (m.positions[t[0]] + m.positions[t[1]] + m.positions[t[2]]) / 3.0f;
}

// Connected components over shared vertices of non-degenerate triangles: component id per
// vertex (isolated vertices get their own).
std::vector<uint32_t> vertexComponents(const TriangleMesh& m, size_t* count) {
    std::vector<uint32_t> parent(m.vertexCount());
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](uint32_t v) {
        while (parent[v] != v) v = parent[v] = parent[parent[v]];
        return v;
    };
    for (const auto& t : m.triangles) {
        if (isDegenerate(t)) continue;
        for (int e = 1; e < 3; ++e) parent[find(t[e])] = find(t[0]);
    }
    std::map<uint32_t, uint32_t> ids;
    std::vector<uint32_t> component(m.vertexCount());
    for (uint32_t v = 0; v < m.vertexCount(); ++v)
        component[v] = ids.emplace(find(v), uint32_t(ids.size())).first->second;
    *count = ids.size();
    return component;
}

// Undirected edge -> number of non-degenerate triangles using it; also reports whether any
// directed edge repeats (two neighbours wound the same way: inconsistent orientation).
std::map<std::pair<uint32_t, uint32_t>, int> edgeUse(const TriangleMesh& m, bool* consistent) {
    std::map<std::pair<uint32_t, uint32_t>, int> undirected;
    std::set<std::pair<uint32_t, uint32_t>> directed;
    *consistent = true;
    for (const auto& t : m.triangles) {
        if (isDegenerate(t)) continue;
        for (int e = 0; e < 3; ++e) {
            const uint32_t a = t[e], b = t[(e + 1) % 3];
            if (!directed.insert({a, b}).second) *consistent = false;
            ++undirected[std::minmax(a, b)];
        }
    }
    return undirected;
}

uint32_t extremeVertex(const TriangleMesh& m, Vec3 direction) {
    uint32_t best = 0;
    for (uint32_t v = 1; v < m.vertexCount(); ++v)
        if (dot(m.positions[v], direction) > dot(m.positions[best], direction)) best = v;
    return best;
}

} // namespace

TEST(Teapot, TenQuadsPerPatchGiveThePapersCounts) {
    const TriangleMesh m = teapot(10);
    std::printf("teapot(10): %zu vertices, %zu triangles (paper: %d / %d)\n", m.vertexCount(),
                m.triangleCount(), kPaperTeapot.vertices, kPaperTeapot.triangles);
    EXPECT_EQ(m.triangleCount(), size_t(kPaperTeapot.triangles));
    EXPECT_NEAR(double(m.vertexCount()), kPaperTeapot.vertices, 0.02 * kPaperTeapot.vertices);
    // Per-part welding: 32 n^2 + 4 n + 2 (see teapot.cpp), which is the paper's figure exactly.
    EXPECT_EQ(m.vertexCount(), 3242u);
    EXPECT_NO_THROW(validate(m, "teapot"));
    // The only degenerate triangles are one per quad on the two pole rows (lid knob top and
    // bottom centre): 4 patches x n quads each.
    const auto degenerate = std::count_if(m.triangles.begin(), m.triangles.end(), isDegenerate);
    EXPECT_EQ(degenerate, 2 * 4 * 10);
    size_t zeroArea = 0;
    for (const auto& t : m.triangles)
        if (!isDegenerate(t) && lengthSquared(faceNormal(m, t)) == 0.0f) ++zeroArea;
    EXPECT_EQ(zeroArea, 0u);
}

TEST(Teapot, CountsScaleWithQuadsPerPatch) {
    for (int n = 1; n <= 12; ++n) {
        const TriangleMesh m = teapot(n);
        EXPECT_EQ(m.triangleCount(), size_t(64 * n * n)) << "n = " << n;
        // body+rim+bottom: 4n rings of 4n + pole; lid: 2n rings of 4n + pole; handle and
        // spout: 2n+1 rings of 2n each.
        EXPECT_EQ(m.vertexCount(), size_t(32 * n * n + 4 * n + 2)) << "n = " << n;
    }
}

TEST(Teapot, WeldingHoldsAtFineTessellations) {
    // Seams still weld and pole-adjacent samples (the closest distinct ones) still do not.
    const int n = 64;
    const TriangleMesh m = teapot(n);
    EXPECT_EQ(m.triangleCount(), size_t(64 * n * n));
    EXPECT_EQ(m.vertexCount(), size_t(32 * n * n + 4 * n + 2));
}

TEST(Teapot, IsDeterministic) {
    const TriangleMesh a = teapot(7), b = teapot(7);
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_EQ(a.triangles, b.triangles);
}

// The classic teapot is four separate surfaces: body (rim, body and bottom welded into one,
// open only along the rim's inner circle), lid (knob and lid, open along its lower circle),
// handle and spout (tubes open at both ends). Handle and spout pierce the body without sharing
// vertices with it; each open boundary is a loop of 4n edges (2n per tube end).
TEST(Teapot, PartsAreWeldedIntoFourComponentsWithTheClassicOpenings) {
    const int n = 10;
    const TriangleMesh m = teapot(n);
    size_t count = 0;
    const std::vector<uint32_t> component = vertexComponents(m, &count);
    EXPECT_EQ(count, 4u);

    const uint32_t body = component[extremeVertex(m, {0, -1, 0})];
    const uint32_t lid = component[extremeVertex(m, {0, 1, 0})];
    const uint32_t handle = component[extremeVertex(m, {-1, 0, 0})];
    const uint32_t spout = component[extremeVertex(m, {1, 0, 0})];
    EXPECT_EQ(std::set<uint32_t>({body, lid, handle, spout}).size(), 4u);

    bool consistent = false;
    const auto edges = edgeUse(m, &consistent);
    EXPECT_TRUE(consistent) << "neighbouring triangles wound the same way";
    std::map<uint32_t, int> boundary;
    for (const auto& [edge, uses] : edges) {
        EXPECT_LE(uses, 2) << "non-manifold edge " << edge.first << "-" << edge.second;
        if (uses == 1) ++boundary[component[edge.first]];
    }
    EXPECT_EQ(boundary[body], 4 * n);
    EXPECT_EQ(boundary[lid], 4 * n);
    EXPECT_EQ(boundary[handle], 2 * 2 * n);
    EXPECT_EQ(boundary[spout], 2 * 2 * n);

    // The handle's lower end touches the body at one point, a shared control point; that point
    // is deliberately left as two vertices (welding it would pin the handle by a non-manifold
    // vertex).
    int atContact = 0;
    for (uint32_t v = 0; v < m.vertexCount(); ++v)
        if (lengthSquared(m.positions[v] - Vec3{-2.0f, 0.9f, 0.0f}) < 1e-10f) {
            EXPECT_TRUE(component[v] == body || component[v] == handle);
            ++atContact;
        }
    EXPECT_EQ(atContact, 2);

    // The body's open circle is the rim's inner edge (radius 1.4 at y = 2.4), the lid's its
    // lower edge (radius 1.3 at y = 2.4).
    for (const auto& [edge, uses] : edges) {
        if (uses != 1) continue;
        const Vec3 p = m.positions[edge.first];
        const float r = std::hypot(p.x, p.z);
        if (component[edge.first] == body) {
            EXPECT_NEAR(p.y, 2.4f, 1e-5f);
            EXPECT_NEAR(r, 1.4f, 0.01f); // the Bezier quarter circle is not exactly round
        } else if (component[edge.first] == lid) {
            EXPECT_NEAR(p.y, 2.4f, 1e-5f);
            EXPECT_NEAR(r, 1.3f, 0.01f);
        }
    }
}

TEST(Teapot, BodyNormalsPointOutward) {
    const TriangleMesh m = teapot(10);
    size_t count = 0;
    const std::vector<uint32_t> component = vertexComponents(m, &count);
    const uint32_t body = component[extremeVertex(m, {0, -1, 0})];
    int side = 0, sideOut = 0, bottom = 0, bottomOut = 0;
    for (const auto& t : m.triangles) {
        if (isDegenerate(t) || component[t[0]] != body) continue;
        const Vec3 c = centroid(m, t), normal = faceNormal(m, t);
        if (c.y > 0.2f && c.y < 2.35f) { // the body wall, below the rim's lip
            ++side;
            if (dot(normal, Vec3{c.x, 0, c.z}) > 0) ++sideOut;
        } else if (c.y < 0.1f && std::hypot(c.x, c.z) < 1.4f) { // the bottom
            ++bottom;
            if (normal.y < 0) ++bottomOut;
        }
    }
    EXPECT_GT(side, 1400);
    EXPECT_GT(bottom, 400);
    EXPECT_EQ(sideOut, side);
    EXPECT_EQ(bottomOut, bottom);
}

// At a part's extreme point in direction d the surface is tangent to a plane with normal d and
// the part lies behind it, so an outward surface has its normal along +d there (roughly, at the
// sampled extreme of a coarse tessellation; inward would give about -1). Checked for every part
// and 26 directions, skipping extremes that lie on an open boundary.
TEST(Teapot, EveryPartIsOutwardAtItsExtremePoints) {
    const TriangleMesh m = teapot(12);
    size_t count = 0;
    const std::vector<uint32_t> component = vertexComponents(m, &count);
    bool consistent = false;
    const auto edges = edgeUse(m, &consistent);
    std::vector<bool> onBoundary(m.vertexCount(), false);
    for (const auto& [edge, uses] : edges)
        if (uses == 1) onBoundary[edge.first] = onBoundary[edge.second] = true;

    // The 26 directions to the neighbours of a cube cell: axes, face and space diagonals.
    std::vector<Vec3> directions;
    for (int i = -1; i <= 1; ++i)
        for (int j = -1; j <= 1; ++j)
            for (int k = -1; k <= 1; ++k)
                if (i != 0 || j != 0 || k != 0)
                    directions.push_back(normalize(Vec3{float(i), float(j), float(k)}));
    std::vector<int> checked(count, 0);
    for (uint32_t part = 0; part < count; ++part)
        for (const Vec3 d : directions) {
            uint32_t best = UINT32_MAX;
            for (uint32_t v = 0; v < m.vertexCount(); ++v)
                if (component[v] == part &&
                    (best == UINT32_MAX || dot(m.positions[v], d) > dot(m.positions[best], d)))
                    best = v;
            if (onBoundary[best]) continue;
            Vec3 normal{};
            for (const auto& t : m.triangles)
                if (!isDegenerate(t) && (t[0] == best || t[1] == best || t[2] == best))
                    normal += faceNormal(m, t);
            EXPECT_GT(dot(normalize(normal), d), 0.5f)
                << "part " << part << ", direction (" << d.x << ", " << d.y << ", " << d.z << ")";
            ++checked[part];
        }
    // Many extremes of the tubes and the lid lie on their open ends; at least 8 per part do not.
    for (uint32_t part = 0; part < count; ++part) EXPECT_GE(checked[part], 8) << "part " << part;
}

TEST(Teapot, StandsOnTheGroundYUpSymmetricInZ) {
    const TriangleMesh m = teapot(10);
    const Aabb box = bounds(m);
    EXPECT_EQ(box.lo.y, 0.0f);           // the bottom's centre
    EXPECT_NEAR(box.hi.y, 3.15f, 1e-5f); // the lid knob's top
    EXPECT_NEAR(box.lo.x, -3.0f, 1e-5f); // the handle's outer bend
    EXPECT_GT(box.hi.x, 3.3f);           // the spout's tip
    EXPECT_LT(box.hi.x, 3.525f);         // inside its control polygon
    EXPECT_NEAR(box.hi.z, 2.0f, 1e-5f);  // the body's widest circle
    EXPECT_NEAR(box.lo.z, -2.0f, 1e-5f);
    // Every vertex has a mirror image across the xy-plane.
    std::vector<Vec3> mirrored;
    for (const Vec3& p : m.positions) mirrored.push_back({p.x, p.y, -p.z});
    auto less = [](const Vec3& a, const Vec3& b) {
        return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
    };
    std::vector<Vec3> original = m.positions;
    std::sort(original.begin(), original.end(), less);
    size_t unmatched = 0;
    for (const Vec3& q : mirrored) {
        // Neighbours in x order within the tolerance; a linear scan of that window suffices.
        auto it = std::lower_bound(original.begin(), original.end(),
                                   Vec3{q.x - 1e-5f, -1e9f, -1e9f}, less);
        bool found = false;
        for (; it != original.end() && it->x <= q.x + 1e-5f && !found; ++it)
            found = lengthSquared(*it - q) < 1e-10f;
        if (!found) ++unmatched;
    }
    EXPECT_EQ(unmatched, 0u);
}

TEST(Teapot, RejectsBadQuadsPerPatch) {
    EXPECT_THROW(teapot(0), InputError);
    EXPECT_THROW(teapot(-3), InputError);
    EXPECT_THROW(teapot(257), InputError);
    try {
        teapot(0);
    } catch (const InputError& e) {
        EXPECT_EQ(e.source(), "teapot");
        EXPECT_NE(std::string(e.what()).find("quadsPerPatch"), std::string::npos) << e.what();
    }
}
