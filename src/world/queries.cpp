// The geometric queries (ffdaabb/queries.h): ray casts and box overlaps against the deformed
// meshes.
//
// Two levels of boxes cull the triangles: each body's box over its vertices (one pass over all
// vertices per epoch, the first time any query needs them), then a bounding-volume hierarchy
// over the body's triangles, built once per model on the rest mesh (binned surface area
// heuristic, at most 4 triangles a leaf) and refitted to the body's current vertices the first
// time a query reaches the body in an epoch. A lattice's cell boxes would be a cheaper first cut
// inside a body, but World::boxNodes come from the last substep's node update, before its
// position update and response moved the particles, so they need not hold the vertices the
// mesh update made from the final particles (after 120 frames of the alphabets, 2.1 % of the
// vertices lie outside their own cell's box, by up to 7 cm); the queries look at the vertices
// alone.
//
// Every box is padded by a few ulps of its coordinates, so that rounding in the slab and overlap
// tests never culls a triangle the exact test would find: a query gives what testing every
// triangle would (the tests compare against that).
#include "ffdaabb/queries.h"
#include "ffdaabb/error.h"
#include "world/world_data.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace ffd {

using detail::BodyQueryCache;
using detail::BodyRecord;
using detail::QueryCache;
using detail::TriangleBvh;
using detail::WorldData;

namespace {

using Triangle = std::array<uint32_t, 3>;

constexpr uint32_t kLeafSize = 4;
constexpr int kBins = 12;
constexpr size_t kMaxDepth = 96; // deeper subtrees are split at the median

// --- Building and refitting the hierarchy --------------------------------------------------

struct BuildItem {
    Aabb box;
    Vec3 centre;
    uint32_t triangle = 0;
};

float area(const Aabb& b) {
    if (b.empty()) return 0;
    const Vec3 e = b.extent();
    return e.x * e.y + e.y * e.z + e.z * e.x;
}

void buildNode(TriangleBvh& bvh, std::vector<BuildItem>& items, uint32_t first, uint32_t count,
               size_t depth) {
    const uint32_t index = uint32_t(bvh.nodes.size());
    bvh.nodes.push_back({});
    if (count <= kLeafSize) {
        bvh.nodes[index] = {first, count, 0};
        return;
    }
    Aabb centres;
    for (uint32_t i = first; i < first + count; ++i) centres.add(items[i].centre);
    const Vec3 e = centres.extent();
    const int axis = e.x >= e.y && e.x >= e.z ? 0 : (e.y >= e.z ? 1 : 2);
    uint32_t mid = first + count / 2;
    const auto byAxis = [axis](const BuildItem& a, const BuildItem& b) {
        return a.centre[axis] < b.centre[axis] ||
               (a.centre[axis] == b.centre[axis] && a.triangle < b.triangle);
    };
    bool split = false;
    if (e[axis] > 0 && depth < kMaxDepth) {
        // Binned surface area heuristic along the widest axis of the centres.
        struct Bin {
            Aabb box;
            uint32_t count = 0;
        } bins[kBins];
        const float lo = centres.lo[axis], scale = float(kBins) / e[axis];
        auto binOf = [&](const BuildItem& it) {
            return std::min(kBins - 1, int((it.centre[axis] - lo) * scale));
        };
        for (uint32_t i = first; i < first + count; ++i) {
            Bin& b = bins[binOf(items[i])];
            b.box.add(items[i].box);
            ++b.count;
        }
        float rightArea[kBins] = {};
        uint32_t rightCount[kBins] = {};
        Aabb acc;
        uint32_t n = 0;
        for (int b = kBins - 1; b > 0; --b) {
            acc.add(bins[b].box), n += bins[b].count;
            rightArea[b] = area(acc), rightCount[b] = n;
        }
        float bestCost = INFINITY;
        int bestBin = -1;
        acc = Aabb{}, n = 0;
        for (int b = 1; b < kBins; ++b) {
            acc.add(bins[b - 1].box), n += bins[b - 1].count;
            if (n == 0 || rightCount[b] == 0) continue;
            const float cost = area(acc) * float(n) + rightArea[b] * float(rightCount[b]);
            if (cost < bestCost) bestCost = cost, bestBin = b;
        }
        if (bestBin > 0) {
            const auto middle =
                std::partition(items.begin() + first, items.begin() + first + count,
                               [&](const BuildItem& it) { return binOf(it) < bestBin; });
            mid = uint32_t(middle - items.begin());
            split = mid > first && mid < first + count;
        }
    }
    if (!split) {
        mid = first + count / 2;
        std::nth_element(items.begin() + first, items.begin() + mid, items.begin() + first + count,
                         byAxis);
    }
    buildNode(bvh, items, first, mid - first, depth + 1);
    bvh.nodes[index].right = uint32_t(bvh.nodes.size());
    buildNode(bvh, items, mid, first + count - mid, depth + 1);
}

std::unique_ptr<TriangleBvh> buildBvh(const TriangleMesh& mesh) {
    auto bvh = std::make_unique<TriangleBvh>();
    std::vector<BuildItem> items(mesh.triangles.size());
    for (size_t t = 0; t < items.size(); ++t) {
        Aabb b;
        for (uint32_t v : mesh.triangles[t]) b.add(mesh.positions[v]);
        items[t] = {b, b.centre(), uint32_t(t)};
    }
    bvh->nodes.reserve(2 * items.size() / kLeafSize + 1);
    if (!items.empty()) buildNode(*bvh, items, 0, uint32_t(items.size()), 0);
    bvh->closed = isClosed(mesh);
    bvh->order.resize(items.size());
    for (size_t i = 0; i < items.size(); ++i) bvh->order[i] = items[i].triangle;
    return bvh;
}

// A box grown by a few ulps of its largest coordinate: rounding never culls what it holds.
Aabb padded(Aabb b) {
    if (b.empty()) return b;
    const float m = maxNum(maxComponent(max(-b.lo, b.hi)), maxComponent(max(b.lo, -b.hi)));
    const float pad = m * 4e-7f + 1e-30f;
    b.lo -= Vec3{pad, pad, pad};
    b.hi += Vec3{pad, pad, pad};
    return b;
}

struct BodyView {
    const TriangleBvh* bvh = nullptr;
    const std::vector<Aabb>* boxes = nullptr;
    std::span<const Vec3> vertices;
    std::span<const Triangle> triangles;
    uint32_t dense = 0;
};

// The bodies' boxes over their vertices, current for the cache's epoch.
const std::vector<Aabb>& bodyBounds(const WorldData& w) {
    QueryCache& q = w.queries;
    if (q.boundsEpoch == q.epoch && q.bounds.size() == w.bodies.size()) return q.bounds;
    q.bounds.resize(w.bodies.size());
    q.bodies.resize(w.bodies.size());
    for (size_t b = 0; b < w.bodies.size(); ++b) {
        const BodyRecord& r = w.bodies[b];
        Aabb box;
        const Vec3* v = w.vertices.data() + r.firstVertex;
        for (uint32_t i = 0; i < r.vertexCount; ++i) box.add(v[i]);
        q.bounds[b] = padded(box);
    }
    q.boundsEpoch = q.epoch;
    return q.bounds;
}

// The body's hierarchy, refitted to its vertices for the cache's epoch.
BodyView bodyView(const WorldData& w, uint32_t dense) {
    QueryCache& q = w.queries;
    const BodyRecord& r = w.bodies[dense];
    auto& model = q.models[r.model.get()];
    if (!model) model = buildBvh(r.model->mesh);
    if (q.bodies.size() < w.bodies.size()) q.bodies.resize(w.bodies.size());
    BodyQueryCache& c = q.bodies[dense];
    BodyView view{model.get(), &c.boxes,
                  std::span<const Vec3>(w.vertices.data() + r.firstVertex, r.vertexCount),
                  r.model->mesh.triangles, dense};
    if (c.epoch == q.epoch && c.boxes.size() == model->nodes.size()) return view;
    const TriangleBvh& bvh = *model;
    c.boxes.resize(bvh.nodes.size());
    for (size_t n = bvh.nodes.size(); n-- > 0;) {
        const TriangleBvh::Node& node = bvh.nodes[n];
        Aabb box;
        if (node.count > 0) {
            for (uint32_t i = node.first; i < node.first + node.count; ++i) {
                const Triangle& t = view.triangles[bvh.order[i]];
                box.add(view.vertices[t[0]]), box.add(view.vertices[t[1]]);
                box.add(view.vertices[t[2]]);
            }
            box = padded(box);
        } else {
            box = c.boxes[n + 1];
            box.add(c.boxes[node.right]);
        }
        c.boxes[n] = box;
    }
    c.epoch = q.epoch;
    return view;
}

const BodyRecord& requireBody(const WorldData& w, BodyId id) {
    const BodyRecord* r = w.find(id);
    if (!r)
        throw InputError("body", "stale or invalid body handle (index " + std::to_string(id.index) +
                                     ", generation " + std::to_string(id.generation) + ")");
    return *r;
}

// --- Rays ----------------------------------------------------------------------------------

struct Ray {
    Vec3 origin, dir, inv;
    int kx = 0, ky = 1, kz = 2; ///< the watertight test's axes: kz the direction's largest
    float sx = 0, sy = 0, sz = 0;
};

Ray makeRay(Vec3 origin, Vec3 direction, float maxDistance) {
    if (!isFinite(origin)) throw InputError("origin", "the ray's origin is not finite");
    const float largest = maxComponent(max(direction, -direction));
    if (!isFinite(direction) || !(largest > 0))
        throw InputError("direction", "the ray's direction is zero or not finite");
    if (!(maxDistance >= 0))
        throw InputError("maxDistance", "expected a distance >= 0 (metres; infinity for none)");
    Ray r;
    r.origin = origin;
    r.dir = normalize(direction / largest); // scaled first: no underflow for tiny directions
    for (int a = 0; a < 3; ++a) r.inv[a] = 1.0f / r.dir[a]; // +-inf along a zero component
    const Vec3 d = {std::fabs(r.dir.x), std::fabs(r.dir.y), std::fabs(r.dir.z)};
    r.kz = d.x >= d.y && d.x >= d.z ? 0 : (d.y >= d.z ? 1 : 2);
    r.kx = (r.kz + 1) % 3;
    r.ky = (r.kx + 1) % 3;
    if (r.dir[r.kz] < 0) std::swap(r.kx, r.ky); // keep the winding
    r.sx = r.dir[r.kx] / r.dir[r.kz];
    r.sy = r.dir[r.ky] / r.dir[r.kz];
    r.sz = 1.0f / r.dir[r.kz];
    return r;
}

// Entry distance of the ray into the box within [0, tMax], or a negative value for a miss. A
// zero direction component gives +-inf slab distances, and NaN (ignored by the min/max below)
// only for an origin exactly on that slab's plane.
float enterBox(const Ray& r, const Aabb& b, float tMax) {
    float t0 = 0, t1 = tMax;
    for (int a = 0; a < 3; ++a) {
        const float ta = (b.lo[a] - r.origin[a]) * r.inv[a];
        const float tb = (b.hi[a] - r.origin[a]) * r.inv[a];
        t0 = maxNum(t0, std::min(ta, tb));
        t1 = minNum(t1, std::max(ta, tb));
    }
    return t0 <= t1 ? t0 : -1.0f;
}

struct TriangleHit {
    float t = 0;
    float u = 0, v = 0, w = 0; ///< weights of the corners a, b, c
    bool backFacing = false;   ///< the ray leaves through the triangle (by its winding)
};

// Woop, Benthin, Wald 2013: the corners relative to the origin, sheared so that the ray runs
// along +z; the signs of the three edge functions decide, so that an edge shared by two
// triangles is never missed by both.
bool hitTriangle(const Ray& r, Vec3 a, Vec3 b, Vec3 c, float tMax, TriangleHit& out) {
    const Vec3 A = a - r.origin, B = b - r.origin, C = c - r.origin;
    const float ax = A[r.kx] - r.sx * A[r.kz], ay = A[r.ky] - r.sy * A[r.kz];
    const float bx = B[r.kx] - r.sx * B[r.kz], by = B[r.ky] - r.sy * B[r.kz];
    const float cx = C[r.kx] - r.sx * C[r.kz], cy = C[r.ky] - r.sy * C[r.kz];
    // The edge functions from exact products (floats' products fit in a double), rounded once:
    // an edge's function in its two triangles is exactly opposite, whatever the compiler
    // contracts, so no ray passes between them.
    const float u = float(double(cx) * double(by) - double(cy) * double(bx));
    const float v = float(double(ax) * double(cy) - double(ay) * double(cx));
    const float w = float(double(bx) * double(ay) - double(by) * double(ax));
    if ((u < 0 || v < 0 || w < 0) && (u > 0 || v > 0 || w > 0)) return false;
    const float det = u + v + w;
    if (det == 0) return false;
    const float az = r.sz * A[r.kz], bz = r.sz * B[r.kz], cz = r.sz * C[r.kz];
    const float t = (u * az + v * bz + w * cz) / det;
    if (!(t >= 0 && t <= tMax)) return false;
    const float inv = 1.0f / det;
    out = {t, u * inv, v * inv, w * inv, det < 0};
    return true;
}

struct Closest {
    float t = INFINITY;
    uint32_t dense = UINT32_MAX, triangle = 0;
    TriangleHit hit;
    // Whether (t, dense, triangle) comes first: the nearest, ties to the lower body and
    // triangle.
    bool beatenBy(float t2, uint32_t dense2, uint32_t triangle2) const {
        if (t2 != t) return t2 < t;
        return dense2 != dense ? dense2 < dense : triangle2 < triangle;
    }
};

template <class Visit>
void traverse(const BodyView& body, const Ray& r, const float& tMax, Visit&& visit) {
    if (body.bvh->nodes.empty()) return;
    const std::vector<Aabb>& boxes = *body.boxes;
    struct Entry {
        uint32_t node;
        float t;
    };
    Entry stack[2 * kMaxDepth + 64];
    size_t top = 0;
    const float t0 = enterBox(r, boxes[0], tMax);
    if (t0 < 0) return;
    stack[top++] = {0, t0};
    while (top > 0) {
        const Entry e = stack[--top];
        if (e.t > tMax) continue;
        const TriangleBvh::Node& node = body.bvh->nodes[e.node];
        if (node.count > 0) {
            for (uint32_t i = node.first; i < node.first + node.count; ++i) {
                const uint32_t tri = body.bvh->order[i];
                const Triangle& t = body.triangles[tri];
                TriangleHit h;
                if (hitTriangle(r, body.vertices[t[0]], body.vertices[t[1]], body.vertices[t[2]],
                                tMax, h))
                    visit(tri, h);
            }
            continue;
        }
        const uint32_t left = e.node + 1, right = node.right;
        const float tl = enterBox(r, boxes[left], tMax), tr = enterBox(r, boxes[right], tMax);
        // The nearer child is visited first.
        if (tl >= 0 && tr >= 0) {
            if (tl <= tr) {
                stack[top++] = {right, tr};
                stack[top++] = {left, tl};
            } else {
                stack[top++] = {left, tl};
                stack[top++] = {right, tr};
            }
        } else if (tl >= 0) {
            stack[top++] = {left, tl};
        } else if (tr >= 0) {
            stack[top++] = {right, tr};
        }
    }
}

RayHit makeHit(const WorldData& w, const Ray& r, uint32_t dense, uint32_t triangle,
               const TriangleHit& h) {
    const BodyRecord& rec = w.bodies[dense];
    const Triangle& t = rec.model->mesh.triangles[triangle];
    const Vec3* v = w.vertices.data() + rec.firstVertex;
    RayHit hit;
    hit.body = w.handleOf(dense);
    hit.triangle = triangle;
    hit.barycentric = {h.u, h.v, h.w};
    hit.distance = h.t;
    hit.point = r.origin + r.dir * h.t;
    hit.normal = normalize(cross(v[t[1]] - v[t[0]], v[t[2]] - v[t[0]]));
    return hit;
}

bool ignored(const WorldData& w, uint32_t dense, std::span<const BodyId> ignore) {
    return std::find(ignore.begin(), ignore.end(), w.handleOf(dense)) != ignore.end();
}

std::optional<RayHit> castClosest(const World& world, Vec3 origin, Vec3 direction,
                                  float maxDistance, std::span<const BodyId> ignore) {
    const WorldData& w = detail::dataOf(world);
    const Ray r = makeRay(origin, direction, maxDistance);
    const std::vector<Aabb>& bounds = bodyBounds(w);
    // The bodies whose boxes the ray enters, nearest entry first; stop at the first entry
    // beyond the closest hit so far.
    std::vector<std::pair<float, uint32_t>>& order = w.queries.rayOrder;
    order.clear();
    for (uint32_t b = 0; b < bounds.size(); ++b) {
        const float t = enterBox(r, bounds[b], maxDistance);
        if (t >= 0 && (ignore.empty() || !ignored(w, b, ignore))) order.push_back({t, b});
    }
    std::sort(order.begin(), order.end());
    Closest best;
    best.t = maxDistance;
    bool found = false;
    for (const std::pair<float, uint32_t>& candidate : order) {
        if (candidate.first > best.t) break;
        const uint32_t b = candidate.second; // a structured binding: not capturable in C++20
        const BodyView body = bodyView(w, b);
        traverse(body, r, best.t, [&](uint32_t tri, const TriangleHit& h) {
            if (!found || best.beatenBy(h.t, b, tri)) {
                best.t = h.t, best.dense = b, best.triangle = tri, best.hit = h;
                found = true;
            }
        });
    }
    if (!found) return std::nullopt;
    return makeHit(w, r, best.dense, best.triangle, best.hit);
}

// --- Boxes ---------------------------------------------------------------------------------

// Separating-axis test of a triangle against a box given by its centre and half extents
// (Akenine-Moeller, "Fast 3D Triangle-Box Overlap Testing", 2001): the box's three axes, the
// triangle's normal, and the nine cross products of edges and axes. Touching counts.
bool triangleMeetsBox(Vec3 centre, Vec3 half, Vec3 a, Vec3 b, Vec3 c) {
    const Vec3 v0 = a - centre, v1 = b - centre, v2 = c - centre;
    for (int k = 0; k < 3; ++k) {
        if (std::min({v0[k], v1[k], v2[k]}) > half[k]) return false;
        if (std::max({v0[k], v1[k], v2[k]}) < -half[k]) return false;
    }
    auto separates = [&](Vec3 axis) {
        const float p0 = dot(v0, axis), p1 = dot(v1, axis), p2 = dot(v2, axis);
        const float radius =
            half.x * std::fabs(axis.x) + half.y * std::fabs(axis.y) + half.z * std::fabs(axis.z);
        return std::min({p0, p1, p2}) > radius || std::max({p0, p1, p2}) < -radius;
    };
    const Vec3 edges[3] = {v1 - v0, v2 - v1, v0 - v2};
    if (separates(cross(edges[0], edges[1]))) return false;
    const Vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (const Vec3& e : edges)
        for (const Vec3& u : axes)
            if (separates(cross(u, e))) return false;
    return true;
}

// Directions with no simple relation to the axes or to generated meshes' symmetries: a ray
// along one meets an edge or a vertex exactly with probability zero.
constexpr Vec3 kWindingDirections[3] = {{0.5257311f, 0.6935787f, 0.4925049f},
                                        {-0.7071068f, 0.2588190f, 0.6580326f},
                                        {0.1736482f, -0.5735764f, -0.8003916f}};

// The mesh's winding number at p counted along a ray: +1 for each crossing that leaves the
// mesh (by the triangles' winding), -1 for each that enters. `culled`: through the hierarchy,
// else testing every triangle.
int windingAlongRay(const BodyView& body, Vec3 p, Vec3 direction, bool culled) {
    const Ray r = makeRay(p, direction, INFINITY);
    int winding = 0;
    if (culled) {
        const float tMax = INFINITY;
        traverse(body, r, tMax,
                 [&](uint32_t, const TriangleHit& h) { winding += h.backFacing ? 1 : -1; });
        return winding;
    }
    for (const Triangle& t : body.triangles) {
        TriangleHit h;
        if (hitTriangle(r, body.vertices[t[0]], body.vertices[t[1]], body.vertices[t[2]], INFINITY,
                        h))
            winding += h.backFacing ? 1 : -1;
    }
    return winding;
}

// Whether p lies inside the body's mesh: a ray's crossings decide for a closed mesh (exactly);
// for an open one, where the count depends on the ray (it may leave through a hole), two rays
// of three must say inside.
bool insideMesh(const BodyView& body, Vec3 p, bool culled = true) {
    if (body.bvh->closed) return windingAlongRay(body, p, kWindingDirections[0], culled) != 0;
    int votes = 0;
    for (const Vec3& d : kWindingDirections) votes += windingAlongRay(body, p, d, culled) != 0;
    return votes >= 2;
}

bool meshMeetsBox(const BodyView& body, const Aabb& box) {
    if (body.bvh->nodes.empty()) return false;
    const Vec3 centre = box.centre(), half = box.extent() * 0.5f;
    const std::vector<Aabb>& boxes = *body.boxes;
    uint32_t stack[2 * kMaxDepth + 64];
    size_t top = 0;
    if (boxes[0].overlaps(box)) stack[top++] = 0;
    while (top > 0) {
        const uint32_t n = stack[--top];
        const TriangleBvh::Node& node = body.bvh->nodes[n];
        if (node.count > 0) {
            for (uint32_t i = node.first; i < node.first + node.count; ++i) {
                const Triangle& t = body.triangles[body.bvh->order[i]];
                if (triangleMeetsBox(centre, half, body.vertices[t[0]], body.vertices[t[1]],
                                     body.vertices[t[2]]))
                    return true;
            }
            continue;
        }
        if (boxes[n + 1].overlaps(box)) stack[top++] = n + 1;
        if (boxes[node.right].overlaps(box)) stack[top++] = node.right;
    }
    // No triangle meets the box: it lies all inside the mesh or all outside.
    return insideMesh(body, centre);
}

void requireBox(const Aabb& box) {
    if (!isFinite(box.lo) || !isFinite(box.hi))
        throw InputError("box", "the box's corners are not finite");
    if (box.empty()) throw InputError("box", "the box is empty (lo > hi on an axis)");
}

} // namespace

std::optional<RayHit> raycast(const World& world, Vec3 origin, Vec3 direction, float maxDistance) {
    return castClosest(world, origin, direction, maxDistance, {});
}

std::optional<RayHit> raycast(const World& world, Vec3 origin, Vec3 direction, float maxDistance,
                              std::span<const BodyId> ignore) {
    return castClosest(world, origin, direction, maxDistance, ignore);
}

void raycastAll(const World& world, Vec3 origin, Vec3 direction, float maxDistance,
                std::vector<RayHit>& out) {
    out.clear();
    const WorldData& w = detail::dataOf(world);
    const Ray r = makeRay(origin, direction, maxDistance);
    const std::vector<Aabb>& bounds = bodyBounds(w);
    struct Found {
        float t;
        uint32_t dense, triangle;
        TriangleHit hit;
    };
    std::vector<Found> found;
    for (uint32_t b = 0; b < bounds.size(); ++b) {
        if (enterBox(r, bounds[b], maxDistance) < 0) continue;
        const BodyView body = bodyView(w, b);
        traverse(body, r, maxDistance, [&](uint32_t tri, const TriangleHit& h) {
            found.push_back({h.t, b, tri, h});
        });
    }
    std::sort(found.begin(), found.end(), [](const Found& a, const Found& b) {
        if (a.t != b.t) return a.t < b.t;
        return a.dense != b.dense ? a.dense < b.dense : a.triangle < b.triangle;
    });
    out.reserve(found.size());
    for (const Found& f : found) out.push_back(makeHit(w, r, f.dense, f.triangle, f.hit));
}

bool bodyOverlaps(const World& world, BodyId body, const Aabb& box) {
    const WorldData& w = detail::dataOf(world);
    requireBody(w, body);
    requireBox(box);
    const uint32_t dense = w.slots[body.index].dense;
    if (!bodyBounds(w)[dense].overlaps(box)) return false;
    return meshMeetsBox(bodyView(w, dense), box);
}

void bodiesOverlapping(const World& world, const Aabb& box, std::vector<BodyId>& out) {
    out.clear();
    requireBox(box);
    const WorldData& w = detail::dataOf(world);
    const std::vector<Aabb>& bounds = bodyBounds(w);
    for (uint32_t b = 0; b < bounds.size(); ++b) {
        if (!bounds[b].overlaps(box) || !meshMeetsBox(bodyView(w, b), box)) continue;
        out.push_back(w.handleOf(b));
    }
}

namespace detail {

std::optional<RayHit> raycastEveryTriangle(const World& world, Vec3 origin, Vec3 direction,
                                           float maxDistance) {
    const WorldData& w = dataOf(world);
    const Ray r = makeRay(origin, direction, maxDistance);
    Closest best;
    best.t = maxDistance;
    bool found = false;
    for (uint32_t b = 0; b < w.bodies.size(); ++b) {
        const BodyRecord& rec = w.bodies[b];
        const Vec3* v = w.vertices.data() + rec.firstVertex;
        const auto& triangles = rec.model->mesh.triangles;
        for (uint32_t tri = 0; tri < triangles.size(); ++tri) {
            const Triangle& t = triangles[tri];
            TriangleHit h;
            if (hitTriangle(r, v[t[0]], v[t[1]], v[t[2]], best.t, h) &&
                (!found || best.beatenBy(h.t, b, tri))) {
                best.t = h.t, best.dense = b, best.triangle = tri, best.hit = h;
                found = true;
            }
        }
    }
    if (!found) return std::nullopt;
    return makeHit(w, r, best.dense, best.triangle, best.hit);
}

bool bodyOverlapsEveryTriangle(const World& world, BodyId body, const Aabb& box) {
    const WorldData& w = dataOf(world);
    const BodyRecord& rec = requireBody(w, body);
    requireBox(box);
    const Vec3* v = w.vertices.data() + rec.firstVertex;
    const Vec3 centre = box.centre(), half = box.extent() * 0.5f;
    for (const Triangle& t : rec.model->mesh.triangles)
        if (triangleMeetsBox(centre, half, v[t[0]], v[t[1]], v[t[2]])) return true;
    return insideMesh(bodyView(w, w.slots[body.index].dense), centre, false);
}

} // namespace detail

} // namespace ffd
