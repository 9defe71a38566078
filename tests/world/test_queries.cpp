// Queries (ffdaabb/queries.h): ray casts and box overlaps agree with testing every triangle of
// deformed bodies, and with an independent double-precision reference; rays through shared
// edges and vertices of closed meshes never slip through; contact pairs carry the weight they
// hold up; contact events begin and end once per touch, the same at any thread count.
#include "ffdaabb/error.h"
#include "ffdaabb/generators.h"
#include "ffdaabb/queries.h"
#include "ffdaabb/world.h"

#include "test_support.h"
#include "world/query_state.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <random>

using namespace ffd;
using ffd::test::ball;

namespace {

// A cube of side `size` centred on the origin, each face an n x n grid of quads.
TriangleMesh cube(float size, int n = 4) {
    TriangleMesh m;
    const float h = size * 0.5f;
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            const uint32_t base = uint32_t(m.positions.size());
            for (int j = 0; j <= n; ++j)
                for (int i = 0; i <= n; ++i) {
                    Vec3 p;
                    p[axis] = side ? h : -h;
                    p[u] = -h + size * float(i) / float(n);
                    p[v] = -h + size * float(j) / float(n);
                    m.positions.push_back(p);
                }
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i) {
                    const uint32_t a = base + uint32_t(j * (n + 1) + i), b = a + 1,
                                   c = a + uint32_t(n + 1), d = c + 1;
                    // Outward winding: (u x v) = axis on the + side.
                    if (side)
                        m.triangles.push_back({a, b, d}), m.triangles.push_back({a, d, c});
                    else
                        m.triangles.push_back({a, d, b}), m.triangles.push_back({a, c, d});
                }
        }
    cleanup(m); // welds the faces' shared edges
    return m;
}

BodySettings placed(Vec3 p, int cells = 38) {
    BodySettings s;
    s.lattice.targetCells = cells;
    s.position = p;
    return s;
}

// A few bodies of different models, piled and then bent out of shape through their particles,
// so that the meshes are deformed well beyond what their rest-pose boxes would hold.
World deformedScene() {
    World world;
    world.addBody(ball(), placed({0, 0.6f, 0}));
    world.addBody(ball(), placed({0.3f, 1.7f, 0.1f}));
    TriangleMesh pot = teapot(4);
    normalizeSize(pot, 1.0f);
    world.addBody(pot, placed({-1.1f, 0.8f, 0.2f}, 60));
    TriangleMesh a = letter('A');
    normalizeSize(a, 0.9f);
    world.addBody(a, placed({1.2f, 0.7f, -0.3f}, 34));
    world.addBody(cube(0.6f), placed({0.1f, 0.5f, 1.2f}, 27));
    for (int f = 0; f < 40; ++f) world.step();
    uint32_t seed = 7;
    for (BodyId b : world.bodies()) {
        const test::SmoothDeformation bend(seed++, 0.8f, 0.15f);
        std::vector<Vec3> x(world.particles(b).begin(), world.particles(b).end());
        for (Vec3& p : x) p = bend(p);
        world.setParticles(b, x);
    }
    return world;
}

// Moeller-Trumbore in double precision, both faces: the distance, or nothing.
std::optional<double> referenceHit(Vec3 o, Vec3 d, Vec3 a, Vec3 b, Vec3 c, double& minWeight) {
    const double e1[3] = {double(b.x) - a.x, double(b.y) - a.y, double(b.z) - a.z};
    const double e2[3] = {double(c.x) - a.x, double(c.y) - a.y, double(c.z) - a.z};
    const double dd[3] = {d.x, d.y, d.z};
    const double p[3] = {dd[1] * e2[2] - dd[2] * e2[1], dd[2] * e2[0] - dd[0] * e2[2],
                         dd[0] * e2[1] - dd[1] * e2[0]};
    const double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (std::fabs(det) < 1e-300) return std::nullopt;
    const double s[3] = {double(o.x) - a.x, double(o.y) - a.y, double(o.z) - a.z};
    const double u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) / det;
    const double q[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2],
                         s[0] * e1[1] - s[1] * e1[0]};
    const double v = (dd[0] * q[0] + dd[1] * q[1] + dd[2] * q[2]) / det;
    minWeight = std::min({u, v, 1 - u - v});
    if (minWeight < 0) return std::nullopt;
    const double t = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
    if (t < 0) return std::nullopt;
    return t;
}

struct Reference {
    bool hit = false;
    double t = 0;
    BodyId body;
    uint32_t triangle = 0;
    bool robust = true; ///< no other triangle within a whisker, not near an edge
};

// The closest hit over every triangle, and whether the answer is clear-cut: the hit well inside
// its triangle and no other triangle's hit (or near miss) close to it.
Reference reference(const World& world, Vec3 o, Vec3 dir, double maxDistance) {
    const Vec3 d = normalize(dir);
    Reference best;
    best.t = maxDistance;
    double second = INFINITY;
    for (BodyId b : world.bodies()) {
        const auto v = world.vertices(b);
        const auto tris = world.triangles(b);
        for (uint32_t i = 0; i < tris.size(); ++i) {
            const auto& t = tris[i];
            double w = 0;
            const auto h = referenceHit(o, d, v[t[0]], v[t[1]], v[t[2]], w);
            if (!h && w > -2e-3 && w < 0) best.robust = false; // a near miss somewhere
            if (!h || *h > maxDistance) continue;
            if (w < 2e-3) best.robust = false;
            if (!best.hit || *h < best.t) {
                second = best.hit ? best.t : second;
                best = {true, *h, b, i, best.robust};
            } else {
                second = std::min(second, *h);
            }
        }
    }
    if (best.hit && second - best.t < 1e-4) best.robust = false;
    if (best.hit && std::fabs(best.t - maxDistance) < 1e-4) best.robust = false;
    return best;
}

// A random point on a random triangle of a random body, and the body.
Vec3 randomSurfacePoint(const World& world, std::mt19937& rng) {
    const auto ids = world.bodies();
    const BodyId b = ids[rng() % ids.size()];
    const auto v = world.vertices(b);
    const auto tris = world.triangles(b);
    const auto& t = tris[rng() % tris.size()];
    std::uniform_real_distribution<float> u(0, 1);
    float r1 = u(rng), r2 = u(rng);
    if (r1 + r2 > 1) r1 = 1 - r1, r2 = 1 - r2;
    return v[t[0]] + (v[t[1]] - v[t[0]]) * r1 + (v[t[2]] - v[t[0]]) * r2;
}

Vec3 randomDirection(std::mt19937& rng) {
    std::normal_distribution<float> g;
    Vec3 d{g(rng), g(rng), g(rng)};
    return lengthSquared(d) > 1e-6f ? normalize(d) : Vec3{0, 1, 0};
}

bool sameHit(const std::optional<RayHit>& a, const std::optional<RayHit>& b) {
    if (a.has_value() != b.has_value()) return false;
    if (!a) return true;
    return a->body == b->body && a->triangle == b->triangle && a->distance == b->distance &&
           a->barycentric == b->barycentric && a->point == b->point && a->normal == b->normal;
}

// The winding number of a closed mesh at p by solid angles (Van Oosterom, Strackee 1983).
double solidAngleWinding(std::span<const Vec3> v, std::span<const std::array<uint32_t, 3>> tris,
                         Vec3 p) {
    double sum = 0;
    for (const auto& t : tris) {
        double a[3], b[3], c[3];
        for (int k = 0; k < 3; ++k) {
            a[k] = double(v[t[0]][k]) - p[k];
            b[k] = double(v[t[1]][k]) - p[k];
            c[k] = double(v[t[2]][k]) - p[k];
        }
        auto len = [](const double* x) {
            return std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        };
        auto dt = [](const double* x, const double* y) {
            return x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
        };
        const double la = len(a), lb = len(b), lc = len(c);
        const double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                           a[2] * (b[0] * c[1] - b[1] * c[0]);
        const double den = la * lb * lc + dt(a, b) * lc + dt(b, c) * la + dt(c, a) * lb;
        sum += 2 * std::atan2(det, den);
    }
    return sum / (4 * M_PI);
}

// Triangle against box in double precision: the 13 separating axes.
bool referenceTriangleBox(const Aabb& box, Vec3 a, Vec3 b, Vec3 c) {
    const double ctr[3] = {0.5 * (double(box.lo.x) + box.hi.x), 0.5 * (double(box.lo.y) + box.hi.y),
                           0.5 * (double(box.lo.z) + box.hi.z)};
    const double half[3] = {0.5 * (double(box.hi.x) - box.lo.x),
                            0.5 * (double(box.hi.y) - box.lo.y),
                            0.5 * (double(box.hi.z) - box.lo.z)};
    double v[3][3];
    const Vec3 pts[3] = {a, b, c};
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) v[i][k] = double(pts[i][k]) - ctr[k];
    auto separates = [&](const double* ax) {
        double lo = INFINITY, hi = -INFINITY;
        for (int i = 0; i < 3; ++i) {
            const double p = v[i][0] * ax[0] + v[i][1] * ax[1] + v[i][2] * ax[2];
            lo = std::min(lo, p), hi = std::max(hi, p);
        }
        const double r =
            half[0] * std::fabs(ax[0]) + half[1] * std::fabs(ax[1]) + half[2] * std::fabs(ax[2]);
        return lo > r || hi < -r;
    };
    double e[3][3];
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) e[i][k] = v[(i + 1) % 3][k] - v[i][k];
    auto crossd = [](const double* x, const double* y, double* out) {
        out[0] = x[1] * y[2] - x[2] * y[1];
        out[1] = x[2] * y[0] - x[0] * y[2];
        out[2] = x[0] * y[1] - x[1] * y[0];
    };
    double ax[3];
    for (int k = 0; k < 3; ++k) {
        const double unit[3] = {double(k == 0), double(k == 1), double(k == 2)};
        if (separates(unit)) return false;
        for (int i = 0; i < 3; ++i) {
            crossd(unit, e[i], ax);
            if (separates(ax)) return false;
        }
    }
    crossd(e[0], e[1], ax);
    return !separates(ax);
}

} // namespace

TEST(Queries, RaycastFindsWhatTestingEveryTriangleFinds) {
    World world = deformedScene();
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-3, 3);
    int hits = 0, misses = 0, fromInside = 0;
    for (int i = 0; i < 3000; ++i) {
        Vec3 origin, dir;
        switch (i % 4) {
        case 0: // at a random surface point from outside the pile
            origin = {u(rng), 3.0f + u(rng), u(rng)};
            dir = randomSurfacePoint(world, rng) - origin;
            break;
        case 1: // at a mesh vertex: through shared edges and corners
        {
            const auto ids = world.bodies();
            const auto v = world.vertices(ids[rng() % ids.size()]);
            origin = {u(rng), 3.0f + u(rng), u(rng)};
            dir = v[rng() % v.size()] - origin;
            break;
        }
        case 2: // anywhere: mostly misses
            origin = {u(rng), u(rng) + 1, u(rng)};
            dir = randomDirection(rng);
            break;
        default: // from inside a body (near its centre of mass)
        {
            const auto ids = world.bodies();
            origin = world.centreOfMass(ids[rng() % ids.size()]);
            dir = randomDirection(rng);
            break;
        }
        }
        const float maxDistance = i % 5 == 0 ? 2.5f : INFINITY;
        const auto fast = raycast(world, origin, dir, maxDistance);
        const auto every = detail::raycastEveryTriangle(world, origin, dir, maxDistance);
        ASSERT_TRUE(sameHit(fast, every)) << "ray " << i;
        const Reference ref = reference(world, origin, dir, maxDistance);
        if (fast) {
            ++hits;
            if (i % 4 == 3) ++fromInside;
            EXPECT_NEAR(fast->barycentric.x + fast->barycentric.y + fast->barycentric.z, 1.0f,
                        1e-5f);
            const auto tri = world.triangles(fast->body)[fast->triangle];
            const auto v = world.vertices(fast->body);
            const Vec3 p = v[tri[0]] * fast->barycentric.x + v[tri[1]] * fast->barycentric.y +
                           v[tri[2]] * fast->barycentric.z;
            EXPECT_LT(length(p - fast->point), 1e-4f) << "ray " << i;
            EXPECT_NEAR(length(fast->normal), 1.0f, 1e-5f);
            EXPECT_LE(fast->distance, maxDistance);
        } else {
            ++misses;
        }
        if (!ref.robust) continue;
        ASSERT_EQ(fast.has_value(), ref.hit) << "ray " << i;
        if (!ref.hit) continue;
        EXPECT_EQ(fast->body, ref.body) << "ray " << i;
        EXPECT_EQ(fast->triangle, ref.triangle) << "ray " << i;
        EXPECT_NEAR(fast->distance, ref.t, 1e-4 * std::max(1.0, ref.t)) << "ray " << i;
    }
    EXPECT_GT(hits, 1500);
    EXPECT_GT(misses, 300);
    EXPECT_GT(fromInside, 500);
}

TEST(Queries, RaysThroughSharedEdgesAndVerticesNeverSlipThrough) {
    World world = deformedScene();
    // Rays at every vertex and every edge midpoint of the closed meshes, each from outside
    // along the point's normal (the mean of its triangles' normals, all of which must face
    // the ray): the point lies inside the surface as the ray sees it, on the triangles'
    // shared edges, and a watertight test hits no further than the point.
    int rays = 0;
    for (BodyId b : world.bodies()) {
        TriangleMesh mesh;
        mesh.positions.assign(world.vertices(b).begin(), world.vertices(b).end());
        mesh.triangles.assign(world.triangles(b).begin(), world.triangles(b).end());
        if (!isClosed(mesh)) continue;
        const auto& v = mesh.positions;
        std::vector<Vec3> faceNormal;
        std::vector<std::vector<uint32_t>> around(v.size());
        std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> edges;
        for (uint32_t i = 0; i < mesh.triangles.size(); ++i) {
            const auto& t = mesh.triangles[i];
            faceNormal.push_back(normalize(cross(v[t[1]] - v[t[0]], v[t[2]] - v[t[0]])));
            for (int k = 0; k < 3; ++k) {
                around[t[k]].push_back(i);
                const uint32_t p = t[k], q = t[(k + 1) % 3];
                edges[{std::min(p, q), std::max(p, q)}].push_back(i);
            }
        }
        auto shoot = [&](Vec3 target, const std::vector<uint32_t>& faces) {
            Vec3 n{};
            for (uint32_t f : faces) n += faceNormal[f];
            n = normalize(n);
            for (uint32_t f : faces)
                if (dot(faceNormal[f], n) < 0.2f) return; // a sharp corner: not all facing
            const Vec3 origin = target + n * 3.0f;
            const auto hit = raycast(world, origin, target - origin);
            ASSERT_TRUE(hit.has_value()) << "body " << b.index << " ray " << rays;
            EXPECT_LE(hit->distance, 3.0f * (1 + 1e-5f)) << "body " << b.index << " ray " << rays;
            ++rays;
        };
        for (uint32_t i = 0; i < v.size(); ++i) shoot(v[i], around[i]);
        for (const auto& [edge, faces] : edges)
            shoot((v[edge.first] + v[edge.second]) * 0.5f, faces);
    }
    EXPECT_GT(rays, 3000);
}

TEST(Queries, RayFromInsideABallLeavesThroughItsSurface) {
    World world;
    const BodyId b = world.addBody(ball(), placed({0, 2, 0}));
    std::mt19937 rng(3);
    Vec3 centre{};
    for (Vec3 p : world.vertices(b)) centre += p / float(world.vertices(b).size());
    for (int i = 0; i < 200; ++i) {
        const Vec3 dir = randomDirection(rng);
        const auto hit = raycast(world, centre, dir);
        ASSERT_TRUE(hit.has_value());
        EXPECT_EQ(hit->body, b);
        EXPECT_NEAR(hit->distance, 0.5f, 0.02f); // the icosphere's faces lie within 2 % of it
        EXPECT_GT(dot(hit->normal, dir), 0.9f);  // leaving through the outward face
    }
    // From outside, the same face is met from its front.
    const auto in = raycast(world, {0, 5, 0}, {0, -1, 0});
    ASSERT_TRUE(in.has_value());
    EXPECT_LT(dot(in->normal, Vec3{0, -1, 0}), -0.9f);
    EXPECT_NEAR(in->distance, 2.5f, 0.02f);
}

TEST(Queries, IgnoringBodiesAndListingEveryCrossing) {
    World world;
    std::vector<BodyId> row;
    for (int i = 0; i < 3; ++i)
        row.push_back(world.addBody(ball(), placed({2.0f * float(i), 2, 0})));
    const Vec3 origin{-3, 2.01f, 0.02f}, dir{1, 0, 0};
    const auto first = raycast(world, origin, dir);
    ASSERT_TRUE(first.has_value());
    EXPECT_EQ(first->body, row[0]);
    const BodyId skip[] = {row[0], BodyId{77, 5}}; // a handle of no body is allowed
    const auto second = raycast(world, origin, dir, INFINITY, skip);
    ASSERT_TRUE(second.has_value());
    EXPECT_EQ(second->body, row[1]);
    EXPECT_FALSE(raycast(world, origin, dir, 2.4f).has_value()); // the first ball is 2.5 away
    std::vector<RayHit> all;
    raycastAll(world, origin, dir, INFINITY, all);
    ASSERT_EQ(all.size(), 6u); // in and out of each ball
    for (size_t i = 0; i < all.size(); ++i) {
        EXPECT_EQ(all[i].body, row[i / 2]);
        if (i > 0) {
            EXPECT_LE(all[i - 1].distance, all[i].distance);
        }
        EXPECT_EQ(dot(all[i].normal, dir) > 0, i % 2 == 1); // entering, then leaving
    }
    raycastAll(world, origin, dir, 5.0f, all);
    EXPECT_EQ(all.size(), 3u);
    // Bad input is refused.
    EXPECT_THROW(raycast(world, origin, {0, 0, 0}), InputError);
    EXPECT_THROW(raycast(world, {NAN, 0, 0}, dir), InputError);
    EXPECT_THROW(raycast(world, origin, dir, -1.0f), InputError);
    // A tiny direction is still a direction.
    const auto tiny = raycast(world, origin, Vec3{1e-30f, 0, 0});
    ASSERT_TRUE(tiny.has_value());
    EXPECT_EQ(tiny->body, row[0]);
}

TEST(Queries, RaycastFollowsTheMeshesAfterStepsAndMoves) {
    World world;
    const BodyId b = world.addBody(ball(), placed({0, 2, 0}));
    const Vec3 origin{0, 10, 0}, down{0, -1, 0};
    EXPECT_NEAR(raycast(world, origin, down)->distance, 7.5f, 0.02f);
    for (int f = 0; f < 20; ++f) world.step();
    Vec3 centre{};
    for (Vec3 p : world.vertices(b)) centre += p / float(world.vertices(b).size());
    const float top = centre.y + 0.5f;
    EXPECT_NEAR(raycast(world, origin, down)->distance, 10 - top, 0.02f);
    world.translate(b, {5, 0, 0});
    EXPECT_FALSE(raycast(world, origin, down).has_value());
    world.removeBody(b);
    EXPECT_FALSE(raycast(world, {5, 10, 0}, down).has_value());
    const BodyId c = world.addBody(ball(), placed({5, 1, 0}));
    ASSERT_TRUE(raycast(world, {5, 10, 0}, down).has_value());
    EXPECT_EQ(raycast(world, {5, 10, 0}, down)->body, c);
}

TEST(Queries, BodiesOverlappingABoxMatchTestingEveryTriangle) {
    World world = deformedScene();
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-2, 2), size(0.005f, 1.2f);
    int overlapping = 0, inside = 0, total = 0;
    std::vector<BodyId> found;
    for (int i = 0; i < 400; ++i) {
        Vec3 centre;
        if (i % 3 == 0) {
            const auto ids = world.bodies();
            centre = world.centreOfMass(ids[rng() % ids.size()]); // a box inside a body
        } else {
            centre = {u(rng), u(rng) + 1.5f, u(rng)};
        }
        const float s = i % 3 == 0 ? 0.05f * size(rng) : size(rng);
        const Vec3 half{s, s * (0.3f + size(rng)), s * (0.5f + 0.5f * size(rng))};
        const Aabb box{centre - half, centre + half};
        bodiesOverlapping(world, box, found);
        for (BodyId b : world.bodies()) {
            const bool fast = std::find(found.begin(), found.end(), b) != found.end();
            EXPECT_EQ(fast, bodyOverlaps(world, b, box));
            ASSERT_EQ(fast, detail::bodyOverlapsEveryTriangle(world, b, box)) << "box " << i;
            // The independent reference: a triangle meets the box, or the box's centre is
            // inside the mesh by its solid-angle winding number.
            const auto v = world.vertices(b);
            const auto tris = world.triangles(b);
            bool meets = false;
            for (const auto& t : tris)
                if (referenceTriangleBox(box, v[t[0]], v[t[1]], v[t[2]])) meets = true;
            const bool within = !meets && std::fabs(solidAngleWinding(v, tris, centre)) > 0.5;
            EXPECT_EQ(fast, meets || within) << "box " << i << " body " << b.index;
            overlapping += fast, inside += within, ++total;
        }
        // In body order.
        const auto ids = world.bodies();
        for (size_t k = 1; k < found.size(); ++k)
            EXPECT_LT(std::find(ids.begin(), ids.end(), found[k - 1]) - ids.begin(),
                      std::find(ids.begin(), ids.end(), found[k]) - ids.begin());
    }
    EXPECT_GT(overlapping, 150);
    EXPECT_GT(inside, 50);
    EXPECT_LT(overlapping, total / 2);
    EXPECT_THROW(bodiesOverlapping(world, Aabb{}, found), InputError); // empty box
    EXPECT_THROW(bodyOverlaps(world, BodyId{}, Aabb{{0, 0, 0}, {1, 1, 1}}), InputError);
}

namespace {

// Per step, the body's partners and the impulses over `frames` steps.
struct Resting {
    double meanImpulse = 0, worstError = 0;
    Vec3 meanVector;
};

// Settings under which bodies never sleep: the impulses are measured step by step (a sleeping
// pair keeps the impulse of its last awake step).
WorldSettings awake() {
    WorldSettings s;
    s.sleepSpeed = 0;
    return s;
}

Resting restingImpulse(World& world, BodyId body, BodyId other, double expected, int frames) {
    Resting r;
    std::vector<BodyContact> partners;
    for (int f = 0; f < frames; ++f) {
        world.step();
        touchingBodies(world, body, partners);
        const auto it = std::find_if(partners.begin(), partners.end(),
                                     [&](const BodyContact& c) { return c.other == other; });
        EXPECT_NE(it, partners.end()) << "frame " << f;
        if (it == partners.end()) continue;
        r.meanImpulse += it->normalImpulse / frames;
        r.meanVector += it->impulse / float(frames);
        r.worstError = std::max(r.worstError, std::fabs(it->normalImpulse / expected - 1));
    }
    return r;
}

} // namespace

TEST(Queries, ABodyRestingOnTheFloorCarriesItsWeight) {
    // A cube and a ball set down on the floor: once settled, the floor holds each up with its
    // weight times the frame step, every step.
    for (int kind = 0; kind < 2; ++kind) {
        World world(awake());
        const BodyId body = kind == 0 ? world.addBody(cube(0.5f), placed({0, 0.25f, 0}, 27))
                                      : world.addBody(ball(), placed({0, 0.5f, 0}));
        for (int f = 0; f < 120; ++f) world.step();
        const WorldSettings& s = world.settings();
        const double weight = world.info(body).mass * -s.gravity.y * s.frameStep; // N s
        const Resting r = restingImpulse(world, body, BodyId{}, weight, 60);
        EXPECT_NEAR(r.meanImpulse / weight, 1.0, 0.01) << "kind " << kind;
        EXPECT_LT(r.worstError, 0.03) << "kind " << kind;
        EXPECT_NEAR(r.meanVector.y / weight, 1.0, 0.01); // pushed up
        EXPECT_LT(std::fabs(r.meanVector.x) + std::fabs(r.meanVector.z), 0.01 * weight);
        std::vector<BodyContact> partners;
        touchingBodies(world, body, partners);
        ASSERT_EQ(partners.size(), 1u);
        EXPECT_TRUE(partners[0].other.isNull());
        EXPECT_GT(partners[0].contactCount, 0u);
    }
}

TEST(Queries, AStackedBodyWeighsOnTheOneBelow) {
    // A ball set on a cube on the floor: the cube holds the ball's weight, the floor both.
    World world(awake());
    const BodyId bottom = world.addBody(cube(0.5f), placed({0, 0.25f, 0}, 27));
    TriangleMesh small = icosphere(2);
    transform(small, 0.3f, {});
    const BodyId top = world.addBody(small, placed({0.03f, 0.8f, 0}));
    for (int f = 0; f < 120; ++f) world.step();
    const WorldSettings& s = world.settings();
    const double g = -s.gravity.y * s.frameStep;
    const double topWeight = world.info(top).mass * g;
    const double bothWeight = (world.info(top).mass + world.info(bottom).mass) * g;
    const Resting onBottom = restingImpulse(world, top, bottom, topWeight, 60);
    EXPECT_NEAR(onBottom.meanImpulse / topWeight, 1.0, 0.01);
    EXPECT_LT(onBottom.worstError, 0.03);
    EXPECT_NEAR(onBottom.meanVector.y / topWeight, 1.0, 0.01);
    const Resting onFloor = restingImpulse(world, bottom, BodyId{}, bothWeight, 60);
    EXPECT_NEAR(onFloor.meanImpulse / bothWeight, 1.0, 0.01);
    EXPECT_LT(onFloor.worstError, 0.03);
    // The pair seen from the cube: the same impulse, pushing it down; the floor last.
    std::vector<BodyContact> partners;
    touchingBodies(world, bottom, partners);
    ASSERT_EQ(partners.size(), 2u);
    EXPECT_EQ(partners[0].other, top);
    EXPECT_NEAR(partners[0].impulse.y / topWeight, -1.0, 0.03);
    EXPECT_TRUE(partners[1].other.isNull());

    // A cube on a cube: the lower one carries the upper one's weight in every step. With an
    // even share of mass per lattice cell the pair rocked in a cycle of a few steps (the impulse
    // of a step swung by tens of per cent) and never slept; with the mesh's volume it rests,
    // and falls asleep when allowed (so awake() here: a sleeping pair reports its last step).
    World cubes(awake());
    const BodyId base = cubes.addBody(cube(0.5f), placed({0, 0.25f, 0}, 27));
    const BodyId upper = cubes.addBody(cube(0.4f), placed({0.03f, 0.7f, 0}, 27));
    for (int f = 0; f < 120; ++f) cubes.step();
    const double upperWeight = cubes.info(upper).mass * g;
    const Resting stacked = restingImpulse(cubes, upper, base, upperWeight, 60);
    EXPECT_NEAR(stacked.meanImpulse / upperWeight, 1.0, 0.01);
    EXPECT_LT(stacked.worstError, 0.03);
}

namespace {

struct EventLog {
    std::vector<std::pair<uint64_t, ContactEvent>> begin, end; // frame, event
    std::vector<ContactPair> lastPairs;
    uint64_t hash = 14695981039346656037ull;
};

void record(const World& world, EventLog& log) {
    const ContactEvents e = contactEvents(world);
    for (const ContactEvent& ev : e.begin) log.begin.push_back({world.frame(), ev});
    for (const ContactEvent& ev : e.end) log.end.push_back({world.frame(), ev});
    const auto pairs = contactPairs(world);
    log.lastPairs.assign(pairs.begin(), pairs.end());
    for (const ContactPair& p : pairs) {
        const unsigned char* bytes = reinterpret_cast<const unsigned char*>(&p);
        for (size_t i = 0; i < sizeof p; ++i) log.hash = (log.hash ^ bytes[i]) * 1099511628211ull;
    }
}

size_t countEvents(const std::vector<std::pair<uint64_t, ContactEvent>>& events, BodyId a,
                   BodyId b) {
    return size_t(std::count_if(events.begin(), events.end(), [&](const auto& e) {
        return (e.second.bodyA == a && e.second.bodyB == b) ||
               (e.second.bodyA == b && e.second.bodyB == a);
    }));
}

} // namespace

TEST(Queries, DroppingABallOnABodyBeginsOnceAndLiftingItEndsOnce) {
    World world;
    const BodyId bottom = world.addBody(cube(0.5f), placed({0, 0.25f, 0}, 27));
    EXPECT_TRUE(contactEvents(world).begin.empty());
    EXPECT_TRUE(contactPairs(world).empty());
    EventLog log;
    for (int f = 0; f < 30; ++f) {
        world.step();
        record(world, log);
    }
    // Dropped from 2 cm above the cube, the ball lands without bouncing off (from 10 cm it
    // bounces once: begin, end, begin).
    const BodyId ballId = world.addBody(ball(), placed({0.02f, 1.02f, 0.01f}));
    const uint64_t dropped = world.frame();
    for (int f = 0; f < 120; ++f) {
        world.step();
        record(world, log);
    }
    EXPECT_EQ(countEvents(log.begin, bottom, ballId), 1u);
    EXPECT_EQ(countEvents(log.end, bottom, ballId), 0u);
    EXPECT_EQ(countEvents(log.begin, bottom, BodyId{}), 1u);
    EXPECT_EQ(countEvents(log.begin, ballId, BodyId{}), 0u); // it never reached the floor
    // The begin names the pair in canonical order: the body added first as A.
    const auto begun = std::find_if(log.begin.begin(), log.begin.end(),
                                    [&](const auto& e) { return e.second.bodyB == ballId; });
    ASSERT_NE(begun, log.begin.end());
    EXPECT_EQ(begun->second.bodyA, bottom);
    // It falls 2 cm in about 0.064 s (4 frames); the contacts within the skin and the
    // speculative margin may begin a frame or two early.
    EXPECT_GE(begun->first, dropped + 1);
    EXPECT_LE(begun->first, dropped + 5);

    // Lifted away: one end, and nothing begins while it is in the air.
    world.translate(ballId, {0, 2, 0});
    world.setVelocity(ballId, {0, 0, 0});
    const uint64_t lifted = world.frame();
    log = EventLog{};
    for (int f = 0; f < 10; ++f) {
        world.step();
        record(world, log);
    }
    EXPECT_EQ(countEvents(log.end, bottom, ballId), 1u);
    EXPECT_EQ(log.end.size(), 1u);
    EXPECT_EQ(log.end[0].first, lifted + 1); // at the first step after the lift
    EXPECT_TRUE(log.begin.empty());
    std::vector<BodyContact> partners;
    touchingBodies(world, ballId, partners);
    EXPECT_TRUE(partners.empty());
}

TEST(Queries, ASphereDroppedOnASphereBeginsOnceAndEndsOnceLifted) {
    // Two balls, the upper one dropped 2 cm onto the lower one, which rests on the floor; the
    // pile is unstable, so it is lifted off after half a second, before it could roll down.
    for (int threads : {1, 2}) {
        WorldSettings s;
        s.threads = threads;
        World world(s);
        const BodyId lower = world.addBody(ball(), placed({0, 0.5f, 0}));
        for (int f = 0; f < 20; ++f) world.step();
        const BodyId upper = world.addBody(ball(), placed({0.01f, 1.52f, 0}));
        EventLog log;
        for (int f = 0; f < 30; ++f) {
            world.step();
            record(world, log);
        }
        EXPECT_EQ(countEvents(log.begin, lower, upper), 1u) << threads << " threads";
        EXPECT_EQ(countEvents(log.end, lower, upper), 0u) << threads << " threads";
        world.translate(upper, {0, 2, 0});
        for (int f = 0; f < 10; ++f) {
            world.step();
            record(world, log);
        }
        EXPECT_EQ(countEvents(log.begin, lower, upper), 1u) << threads << " threads";
        EXPECT_EQ(countEvents(log.end, lower, upper), 1u) << threads << " threads";
    }
}

TEST(Queries, ContactPairsAndEventsAreTheSameAtAnyThreadCount) {
    auto run = [](int threads) {
        WorldSettings s;
        s.threads = threads;
        World world(s);
        for (int i = 0; i < 14; ++i)
            world.addBody(
                i % 2 ? ball() : cube(0.5f),
                placed({0.3f * float(i % 3) - 0.3f, 0.5f + 0.7f * float(i), 0.25f * float(i % 2)},
                       i % 2 ? 38 : 27));
        EventLog log;
        for (int f = 0; f < 160; ++f) {
            world.step();
            record(world, log);
        }
        // Removing a body that touches others ends its pairs at the next step, by its stale
        // handle.
        const ContactPair touching = contactPairs(world)[0];
        const BodyId gone = touching.bodyA;
        size_t pairsOfGone = 0;
        for (const ContactPair& p : contactPairs(world))
            pairsOfGone += p.bodyA == gone || p.bodyB == gone;
        world.removeBody(gone);
        world.step();
        record(world, log);
        size_t endedWithGone = 0;
        for (const ContactEvent& e : contactEvents(world).end)
            endedWithGone += e.bodyA == gone || e.bodyB == gone;
        EXPECT_EQ(endedWithGone, pairsOfGone);
        for (const ContactPair& p : contactPairs(world)) {
            EXPECT_NE(p.bodyA, gone);
            EXPECT_NE(p.bodyB, gone);
        }
        return log;
    };
    const EventLog one = run(1), two = run(2);
    EXPECT_GT(one.begin.size(), 14u);
    EXPECT_GT(one.end.size(), 0u);
    EXPECT_EQ(one.begin, two.begin);
    EXPECT_EQ(one.end, two.end);
    EXPECT_EQ(one.hash, two.hash); // pairs and impulses, bit for bit, every step
}

TEST(Queries, ContactPairsComeInCanonicalOrderAndMatchTheLastSubstepsContacts) {
    World world;
    for (int i = 0; i < 8; ++i)
        world.addBody(ball(),
                      placed({0.35f * float(i % 3), 0.5f + 0.8f * float(i), 0.2f * float(i % 2)}));
    for (int f = 0; f < 45; ++f) world.step();
    const auto ids = world.bodies();
    auto place = [&](BodyId b) {
        return b.isNull() ? ids.size() : size_t(std::find(ids.begin(), ids.end(), b) - ids.begin());
    };
    const auto pairs = contactPairs(world);
    ASSERT_FALSE(pairs.empty());
    for (size_t i = 0; i < pairs.size(); ++i) {
        EXPECT_LT(place(pairs[i].bodyA), place(pairs[i].bodyB));
        EXPECT_GE(pairs[i].normalImpulse, 0);
        EXPECT_GT(pairs[i].contactCount, 0u);
        if (i == 0) continue;
        EXPECT_LT(std::make_pair(place(pairs[i - 1].bodyA), place(pairs[i - 1].bodyB)),
                  std::make_pair(place(pairs[i].bodyA), place(pairs[i].bodyB)));
    }
    // Every pair of the last substep's contacts (World::contacts) is among them, and every
    // pair listed had contacts in one of the substeps.
    std::vector<ContactInfo> contacts;
    world.contacts(contacts);
    for (const ContactInfo& c : contacts) {
        const bool listed = std::any_of(pairs.begin(), pairs.end(), [&](const ContactPair& p) {
            return (p.bodyA == c.bodyA && p.bodyB == c.bodyB) ||
                   (p.bodyA == c.bodyB && p.bodyB == c.bodyA);
        });
        EXPECT_TRUE(listed);
    }
    // Only gravity and the floor act on the pile from outside: over 60 steps the floor pairs'
    // impulses make up the pile's change of momentum less its weight's impulse.
    auto momentum = [&] {
        double p = 0;
        for (BodyId b : ids) p += double(world.info(b).mass) * world.linearVelocity(b).y;
        return p;
    };
    double mass = 0;
    for (BodyId b : ids) mass += world.info(b).mass;
    const double before = momentum();
    double floor = 0;
    for (int f = 0; f < 60; ++f) {
        world.step();
        for (const ContactPair& p : contactPairs(world))
            if (p.bodyB.isNull()) floor += p.impulse.y;
    }
    const double gravity = mass * world.settings().gravity.y * world.settings().frameStep * 60;
    const double after = momentum();
    EXPECT_NEAR((floor + gravity) / -gravity, (after - before) / -gravity, 0.002);
    EXPECT_GT(std::fabs(after - before), 0.01 * -gravity); // the pile still moves
}
