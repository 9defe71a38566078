// Generalized winding numbers: Jacobson, Kavan, Sorkine-Hornung, "Robust inside-outside
// segmentation using generalized winding numbers", SIGGRAPH 2013. Solid angle of a triangle:
// Van Oosterom and Strackee, "The solid angle of a plane triangle", IEEE TBME 1983. Closest
// point on a triangle: Ericson, "Real-Time Collision Detection", 5.1.5.
#include "interpenetration.h"
#include "sample_stats.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>

namespace ffd::bench {

namespace {

// Double precision throughout: a winding number sums hundreds of solid angles, and vertices
// in resting contact sit within float rounding of the other surface.
struct D3 {
    double x, y, z;
};
D3 operator-(D3 a, D3 b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
D3 operator+(D3 a, D3 b) {
    return {a.x + b.x, a.y + b.y, a.z + b.z};
}
D3 operator*(D3 a, double s) {
    return {a.x * s, a.y * s, a.z * s};
}
double dot(D3 a, D3 b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
D3 cross(D3 a, D3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
double norm(D3 a) {
    return std::sqrt(dot(a, a));
}
D3 toD3(Vec3 v) {
    return {double(v.x), double(v.y), double(v.z)};
}

// Twice the signed solid angle of triangle abc seen from the origin (a, b, c relative to the
// point), Van Oosterom and Strackee's formula.
double twiceSolidAngle(D3 a, D3 b, D3 c) {
    const double la = norm(a), lb = norm(b), lc = norm(c);
    const double numerator = dot(a, cross(b, c));
    const double denominator = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb;
    return 2.0 * std::atan2(numerator, denominator);
}

// The point of triangle abc nearest to p (Ericson, Real-Time Collision Detection, 5.1.5).
D3 closestPointOnTriangle(D3 p, D3 a, D3 b, D3 c) {
    const D3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return a;
    const D3 bp = p - b;
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
    const D3 cp = p - c;
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    const double denom = 1.0 / (va + vb + vc);
    return a + ab * (vb * denom) + ac * (vc * denom);
}

// Squared distance from p to triangle abc.
double distanceSquaredToTriangle(D3 p, D3 a, D3 b, D3 c) {
    const D3 d = p - closestPointOnTriangle(p, a, b, c);
    return dot(d, d);
}

Aabb boundsOf(std::span<const Vec3> vertices) {
    Aabb box;
    for (const Vec3& v : vertices) box.add(v);
    return box;
}

bool allFinite(std::span<const Vec3> vertices) {
    return std::all_of(vertices.begin(), vertices.end(), [](Vec3 v) { return isFinite(v); });
}

} // namespace

double windingNumber(Vec3 point, const MeshView& mesh) {
    const D3 p = toD3(point);
    double sum = 0;
    for (const auto& t : mesh.triangles) {
        sum += twiceSolidAngle(toD3(mesh.vertices[t[0]]) - p, toD3(mesh.vertices[t[1]]) - p,
                               toD3(mesh.vertices[t[2]]) - p);
    }
    return sum / (4.0 * std::numbers::pi);
}

bool insideMesh(Vec3 point, const MeshView& mesh) {
    return windingNumber(point, mesh) > 0.5;
}

namespace {

constexpr uint32_t kLeafTriangles = 8;

D3 toD3(const std::array<double, 3>& a) {
    return {a[0], a[1], a[2]};
}

// The boundary of a set of triangles given as their directed edges: each undirected edge's
// copies one way less those the other way, as that many edges the way that is left over
// (so an edge two triangles share in opposite directions drops out).
std::vector<std::array<uint32_t, 2>> boundaryOf(std::vector<std::array<uint32_t, 2>> edges) {
    auto undirected = [](const std::array<uint32_t, 2>& e) {
        return std::pair(std::min(e[0], e[1]), std::max(e[0], e[1]));
    };
    std::sort(edges.begin(), edges.end(),
              [&](const auto& a, const auto& b) { return undirected(a) < undirected(b); });
    std::vector<std::array<uint32_t, 2>> out;
    for (size_t i = 0; i < edges.size();) {
        size_t j = i;
        int net = 0; // copies from the lower vertex to the higher, less the others
        while (j < edges.size() && undirected(edges[j]) == undirected(edges[i]))
            net += edges[j][0] < edges[j][1] ? 1 : -1, ++j;
        const auto [lo, hi] = undirected(edges[i]);
        for (; net > 0; --net) out.push_back({lo, hi});
        for (; net < 0; ++net) out.push_back({hi, lo});
        i = j;
    }
    return out;
}

} // namespace

MeshTree::MeshTree(const MeshView& mesh) : mesh_(mesh) {
    v_.resize(mesh.vertices.size());
    for (size_t i = 0; i < v_.size(); ++i) {
        const Vec3 p = mesh.vertices[i];
        v_[i] = {double(p.x), double(p.y), double(p.z)};
    }
    const size_t t = mesh.triangles.size();
    order_.resize(t);
    std::vector<P3> centroid(t);
    for (size_t i = 0; i < t; ++i) {
        order_[i] = uint32_t(i);
        for (int k = 0; k < 3; ++k)
            centroid[i][size_t(k)] =
                (v_[mesh.triangles[i][0]][size_t(k)] + v_[mesh.triangles[i][1]][size_t(k)] +
                 v_[mesh.triangles[i][2]][size_t(k)]) /
                3.0;
    }
    nodes_.reserve(2 * (t / kLeafTriangles + 1));
    if (t > 0) build(0, uint32_t(t), centroid);
}

std::vector<MeshTree::Edge> MeshTree::build(uint32_t first, uint32_t count,
                                            const std::vector<P3>& centroid) {
    const uint32_t at = uint32_t(nodes_.size());
    nodes_.push_back({});
    Node node{};
    node.first = first;
    node.count = count;
    node.lo = {INFINITY, INFINITY, INFINITY};
    node.hi = {-INFINITY, -INFINITY, -INFINITY};
    std::vector<Edge> boundary;
    if (count <= kLeafTriangles) {
        for (uint32_t i = first; i < first + count; ++i) {
            const auto& tri = mesh_.triangles[order_[i]];
            for (const uint32_t corner : tri)
                for (size_t k = 0; k < 3; ++k) {
                    node.lo[k] = std::min(node.lo[k], v_[corner][k]);
                    node.hi[k] = std::max(node.hi[k], v_[corner][k]);
                }
            boundary.push_back({tri[0], tri[1]});
            boundary.push_back({tri[1], tri[2]});
            boundary.push_back({tri[2], tri[0]});
        }
    } else {
        // Halves at the median centroid along the centroids' longest extent.
        P3 clo = node.lo, chi = node.hi;
        for (uint32_t i = first; i < first + count; ++i)
            for (size_t k = 0; k < 3; ++k) {
                clo[k] = std::min(clo[k], centroid[order_[i]][k]);
                chi[k] = std::max(chi[k], centroid[order_[i]][k]);
            }
        size_t axis = 0;
        for (size_t k = 1; k < 3; ++k)
            if (chi[k] - clo[k] > chi[axis] - clo[axis]) axis = k;
        const uint32_t half = count / 2;
        std::nth_element(order_.begin() + first, order_.begin() + first + half,
                         order_.begin() + first + count, [&](uint32_t a, uint32_t b) {
                             return centroid[a][axis] < centroid[b][axis] ||
                                    (centroid[a][axis] == centroid[b][axis] && a < b);
                         });
        boundary = build(first, half, centroid);
        node.right = uint32_t(nodes_.size());
        std::vector<Edge> second = build(first + half, count - half, centroid);
        boundary.insert(boundary.end(), second.begin(), second.end());
        for (const Node& child : {nodes_[at + 1], nodes_[node.right]})
            for (size_t k = 0; k < 3; ++k) {
                node.lo[k] = std::min(node.lo[k], child.lo[k]);
                node.hi[k] = std::max(node.hi[k], child.hi[k]);
            }
    }
    for (size_t k = 0; k < 3; ++k) node.apex[k] = 0.5 * (node.lo[k] + node.hi[k]);
    boundary = boundaryOf(std::move(boundary));
    // A fan over the boundary pays when it has fewer triangles than the subtree.
    if (node.right != 0 && boundary.size() < count) {
        node.fan = true;
        node.edgeFirst = uint32_t(edges_.size());
        node.edgeCount = uint32_t(boundary.size());
        edges_.insert(edges_.end(), boundary.begin(), boundary.end());
    }
    nodes_[at] = node;
    return boundary;
}

// The trees are balanced (halves at the median), so a walk holds at most one node per level
// and its sibling: 64 is enough for 2^32 triangles.
constexpr int kStackDepth = 64;

double MeshTree::windingNumber(Vec3 point) const {
    if (nodes_.empty()) return 0;
    const D3 p = toD3(point);
    const P3 q{p.x, p.y, p.z};
    double sum = 0;
    uint32_t stack[kStackDepth];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node& n = nodes_[stack[--top]];
        const bool outside = q[0] < n.lo[0] || q[0] > n.hi[0] || q[1] < n.lo[1] || q[1] > n.hi[1] ||
                             q[2] < n.lo[2] || q[2] > n.hi[2];
        if (outside && n.fan) {
            const D3 apex = toD3(n.apex) - p;
            for (uint32_t e = n.edgeFirst; e < n.edgeFirst + n.edgeCount; ++e)
                sum +=
                    twiceSolidAngle(apex, toD3(v_[edges_[e][0]]) - p, toD3(v_[edges_[e][1]]) - p);
            continue;
        }
        if (n.right == 0) {
            for (uint32_t i = n.first; i < n.first + n.count; ++i) {
                const auto& tri = mesh_.triangles[order_[i]];
                sum += twiceSolidAngle(toD3(v_[tri[0]]) - p, toD3(v_[tri[1]]) - p,
                                       toD3(v_[tri[2]]) - p);
            }
            continue;
        }
        stack[top++] = n.right;
        stack[top++] = uint32_t(&n - nodes_.data()) + 1;
    }
    return sum / (4.0 * std::numbers::pi);
}

double MeshTree::distanceSquared(Vec3 point, double limit) const {
    if (nodes_.empty()) return limit;
    const D3 p = toD3(point);
    // Squared distance from p to node n's box: no triangle of n is nearer.
    auto boxDistance = [&](const Node& n) {
        double d = 0;
        const double c[3] = {p.x, p.y, p.z};
        for (size_t k = 0; k < 3; ++k) {
            const double below = n.lo[k] - c[k], above = c[k] - n.hi[k];
            if (below > 0) d += below * below;
            if (above > 0) d += above * above;
        }
        return d;
    };
    double best = limit;
    // Each node with its box's distance, made once when it is pushed.
    struct Pending {
        uint32_t node;
        double distance;
    };
    Pending stack[kStackDepth];
    int top = 0;
    stack[top++] = {0, boxDistance(nodes_[0])};
    while (top > 0) {
        const Pending at = stack[--top];
        if (at.distance >= best) continue;
        const Node& n = nodes_[at.node];
        if (n.right == 0) {
            for (uint32_t i = n.first; i < n.first + n.count; ++i) {
                const auto& tri = mesh_.triangles[order_[i]];
                best = std::min(best, distanceSquaredToTriangle(
                                          p, toD3(v_[tri[0]]), toD3(v_[tri[1]]), toD3(v_[tri[2]])));
            }
            continue;
        }
        // The nearer child on top.
        const Pending a{at.node + 1, boxDistance(nodes_[at.node + 1])};
        const Pending b{n.right, boxDistance(nodes_[n.right])};
        if (a.distance <= b.distance)
            stack[top++] = b, stack[top++] = a;
        else
            stack[top++] = a, stack[top++] = b;
    }
    return best;
}

double MeshTree::distanceToSurface(Vec3 point) const {
    return std::sqrt(distanceSquared(point, std::numeric_limits<double>::infinity()));
}

double distanceToSurface(Vec3 point, const MeshView& mesh) {
    const D3 p = toD3(point);
    double best = std::numeric_limits<double>::infinity();
    for (const auto& t : mesh.triangles)
        best = std::min(best, distanceSquaredToTriangle(p, toD3(mesh.vertices[t[0]]),
                                                        toD3(mesh.vertices[t[1]]),
                                                        toD3(mesh.vertices[t[2]])));
    return std::sqrt(best);
}

Vec3 closestPointOnSurface(Vec3 point, const MeshView& mesh) {
    const D3 p = toD3(point);
    double best = std::numeric_limits<double>::infinity();
    D3 nearest = p;
    for (const auto& t : mesh.triangles) {
        const D3 q = closestPointOnTriangle(p, toD3(mesh.vertices[t[0]]), toD3(mesh.vertices[t[1]]),
                                            toD3(mesh.vertices[t[2]]));
        const double d = dot(p - q, p - q);
        if (d < best) best = d, nearest = q;
    }
    return {float(nearest.x), float(nearest.y), float(nearest.z)};
}

Interpenetration measureInterpenetration(std::span<const MeshView> bodies,
                                         const InterpenetrationSettings& settings,
                                         const InsideVertexFn& onInside) {
    Interpenetration out;
    out.bodies = int(bodies.size());
    const size_t n = bodies.size();
    std::vector<Aabb> box(n);
    std::vector<bool> usable(n);
    double lowest = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < n; ++i) {
        usable[i] = allFinite(bodies[i].vertices) && !bodies[i].vertices.empty();
        if (!usable[i]) {
            out.finite = false;
            continue;
        }
        box[i] = boundsOf(bodies[i].vertices);
        for (const Vec3& v : bodies[i].vertices) {
            lowest = std::min(lowest, double(v.y));
            if (v.y < settings.floorHeight) ++out.belowFloorVertices;
        }
    }
    out.lowestY = std::isfinite(lowest) ? lowest : 0.0;
    out.belowFloor = std::max(0.0, double(settings.floorHeight) - out.lowestY);

    const double deep = double(settings.deepFraction) * double(settings.referenceSize);
    double depthSum = 0;
    // Each body's tree, made when a neighbour first needs it.
    std::vector<std::unique_ptr<MeshTree>> trees(n);
    auto tree = [&](size_t b) -> const MeshTree& {
        if (!trees[b]) trees[b] = std::make_unique<MeshTree>(bodies[b]);
        return *trees[b];
    };
    // The vertices of `a` inside `b`; returns whether there was any.
    auto probe = [&](size_t a, size_t b) {
        bool any = false;
        const MeshTree* other = nullptr; // made for the first vertex in b's bounds
        for (size_t k = 0; k < bodies[a].vertices.size(); ++k) {
            const Vec3 v = bodies[a].vertices[k];
            if (!box[b].contains(v)) continue;
            if (!other) other = &tree(b);
            if (!other->inside(v)) continue;
            const double depth = other->distanceToSurface(v);
            if (onInside) onInside(a, k, b, depth);
            any = true;
            ++out.insideVertices;
            if (depth > deep) ++out.deepVertices;
            depthSum += depth;
            if (out.deepestBody < 0 || depth > out.maxDepth) {
                out.maxDepth = depth;
                out.deepestBody = int(a), out.deepestVertex = int(k), out.deepestInside = int(b);
            }
        }
        return any;
    };
    // Smallest distance from a vertex of `a` to the surface of `b`, capped at `range`.
    const double range = double(settings.gapFraction) * double(settings.referenceSize);
    auto nearestVertex = [&](size_t a, size_t b) {
        Aabb reach = box[b];
        const Vec3 r{float(range), float(range), float(range)};
        reach.lo -= r, reach.hi += r;
        double best = range;
        const MeshTree* other = nullptr;
        for (const Vec3& v : bodies[a].vertices) {
            if (!reach.contains(v)) continue;
            if (!other) other = &tree(b);
            // Only what is nearer than the best so far matters.
            const double d = other->distanceSquared(v, best * best);
            if (d < best * best) best = std::min(best, std::sqrt(d));
        }
        return best;
    };
    std::vector<double> gap(n, range);
    // Sort-and-sweep along x keeps the pair search near-linear for piles of hundreds.
    std::vector<size_t> order;
    for (size_t i = 0; i < n; ++i)
        if (usable[i]) order.push_back(i);
    std::sort(order.begin(), order.end(),
              [&](size_t a, size_t b) { return box[a].lo.x < box[b].lo.x; });
    for (size_t k = 0; k < order.size(); ++k) {
        for (size_t m = k + 1;
             m < order.size() && double(box[order[m]].lo.x) <= double(box[order[k]].hi.x) + range;
             ++m) {
            const size_t i = order[k], j = order[m];
            Aabb grown = box[i];
            const Vec3 r{float(range), float(range), float(range)};
            grown.lo -= r, grown.hi += r;
            if (!grown.overlaps(box[j])) continue;
            bool touching = false;
            if (box[i].overlaps(box[j])) {
                const bool ij = probe(i, j);
                const bool ji = probe(j, i);
                touching = ij || ji;
            }
            if (touching) ++out.bodyPairs;
            const double g = touching ? 0.0 : std::min(nearestVertex(i, j), nearestVertex(j, i));
            gap[i] = std::min(gap[i], g);
            gap[j] = std::min(gap[j], g);
        }
        // Its pairs with the bodies before it in the sweep were met earlier, and those with the
        // bodies after it just now: its tree is not asked again (memory: the sweep's front).
        trees[order[k]].reset();
    }
    std::vector<double> near;
    for (size_t i : order)
        if (gap[i] < range) near.push_back(gap[i]);
    out.nearBodies = int(near.size());
    if (!near.empty()) {
        out.meanGap = mean(near);
        out.medianGap = median(near);
        out.minGap = *std::min_element(near.begin(), near.end());
    }
    out.meanDepth = out.insideVertices > 0 ? depthSum / out.insideVertices : 0.0;
    out.maxDepthRelative =
        settings.referenceSize > 0 ? out.maxDepth / double(settings.referenceSize) : 0.0;
    return out;
}

void keepWorst(Interpenetration& ioWorst, const Interpenetration& sample) {
    Interpenetration& w = ioWorst;
    if (w.bodies == 0) {
        w = sample;
        return;
    }
    w.bodies = std::max(w.bodies, sample.bodies);
    w.bodyPairs = std::max(w.bodyPairs, sample.bodyPairs);
    w.insideVertices = std::max(w.insideVertices, sample.insideVertices);
    w.deepVertices = std::max(w.deepVertices, sample.deepVertices);
    if (sample.deepestBody >= 0 && (w.deepestBody < 0 || sample.maxDepth > w.maxDepth)) {
        w.deepestBody = sample.deepestBody;
        w.deepestVertex = sample.deepestVertex;
        w.deepestInside = sample.deepestInside;
    }
    w.maxDepth = std::max(w.maxDepth, sample.maxDepth);
    w.meanDepth = std::max(w.meanDepth, sample.meanDepth);
    w.maxDepthRelative = std::max(w.maxDepthRelative, sample.maxDepthRelative);
    w.lowestY = std::min(w.lowestY, sample.lowestY);
    w.belowFloor = std::max(w.belowFloor, sample.belowFloor);
    w.belowFloorVertices = std::max(w.belowFloorVertices, sample.belowFloorVertices);
    w.medianGap = std::max(w.medianGap, sample.medianGap);
    w.meanGap = std::max(w.meanGap, sample.meanGap);
    // The closest approach: the smallest minGap of the samples that had near bodies.
    if (sample.nearBodies > 0 && (w.nearBodies == 0 || sample.minGap < w.minGap))
        w.minGap = sample.minGap;
    w.nearBodies = std::max(w.nearBodies, sample.nearBodies);
    w.finite = w.finite && sample.finite;
}

} // namespace ffd::bench
