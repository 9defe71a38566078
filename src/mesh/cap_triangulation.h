// The planar geometry of the letters' caps (letters.cpp): points, orientation, and the cap's
// triangulation, made a constrained Delaunay triangulation by Lawson's edge flips (C. L. Lawson,
// "Software for C1 surface interpolation", Mathematical Software III, 1977, pp. 161-194) and
// refined by incremental insertion of points with the same flips.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

namespace ffd::detail {

struct P2 {
    double x = 0, y = 0;
};

inline P2 operator-(P2 a, P2 b) {
    return {a.x - b.x, a.y - b.y};
}
inline double cross(P2 a, P2 b) {
    return a.x * b.y - a.y * b.x;
}
inline double dot(P2 a, P2 b) {
    return a.x * b.x + a.y * b.y;
}
inline double dist(P2 a, P2 b) {
    return std::hypot(a.x - b.x, a.y - b.y);
}
// Twice the signed area of (a, b, c): positive when counter-clockwise.
inline double orient(P2 a, P2 b, P2 c) {
    return cross(b - a, c - a);
}
inline double segmentDistanceSquared(P2 p, P2 a, P2 b) {
    const P2 ab = b - a;
    const double len2 = dot(ab, ab);
    const double t = len2 > 0 ? std::clamp(dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    const P2 d{p.x - a.x - t * ab.x, p.y - a.y - t * ab.y};
    return dot(d, d);
}

// Triangles counter-clockwise; neighbour[t][i] is the triangle across edge (v[i], v[i+1]), -1
// on the outline. Only the outline is constrained: every interior edge may be flipped.
class CapTriangulation {
public:
    std::vector<P2> points;
    std::vector<std::array<uint32_t, 3>> tris;
    std::vector<std::array<int32_t, 3>> neighbours;

    // Returns false when the triangles are not an edge-manifold, consistently oriented set.
    bool build() {
        std::unordered_map<uint64_t, std::pair<int32_t, int>> edges;
        edges.reserve(tris.size() * 3);
        neighbours.assign(tris.size(), {-1, -1, -1});
        for (size_t t = 0; t < tris.size(); ++t)
            for (int i = 0; i < 3; ++i) {
                const uint32_t a = tris[t][size_t(i)], b = tris[t][size_t((i + 1) % 3)];
                if (!edges.emplace(key(a, b), std::pair{int32_t(t), i}).second) return false;
            }
        for (size_t t = 0; t < tris.size(); ++t)
            for (int i = 0; i < 3; ++i) {
                const uint32_t a = tris[t][size_t(i)], b = tris[t][size_t((i + 1) % 3)];
                if (auto it = edges.find(key(b, a)); it != edges.end())
                    neighbours[t][size_t(i)] = it->second.first;
            }
        return true;
    }

    // Flips interior edges until every one is locally Delaunay (the sum of the two opposite
    // angles is at most pi). Zero-area triangles from collinear outline samples have an angle
    // of pi and are flipped away too.
    void makeDelaunay() {
        for (size_t t = 0; t < tris.size(); ++t)
            for (int i = 0; i < 3; ++i) stack_.push_back({int32_t(t), i});
        legalize();
    }

    // Inserts p when it lies strictly inside the triangulation; returns whether it did.
    bool insert(P2 p, double minDistance) {
        const int32_t t = locate(p);
        if (t < 0) return false;
        const auto [a, b, c] = tris[size_t(t)];
        const std::array<std::pair<uint32_t, uint32_t>, 3> edges{{{a, b}, {b, c}, {c, a}}};
        for (const auto& [u, v] : edges)
            if (orient(points[u], points[v], p) <= minDistance * dist(points[u], points[v]))
                return false; // on or too near an edge: leave it out rather than make a sliver
        const uint32_t pIndex = uint32_t(points.size());
        points.push_back(p);
        const auto n = neighbours[size_t(t)];
        const int32_t t1 = int32_t(tris.size()), t2 = t1 + 1;
        tris[size_t(t)] = {a, b, pIndex};
        tris.push_back({b, c, pIndex});
        tris.push_back({c, a, pIndex});
        neighbours[size_t(t)] = {n[0], t1, t2};
        neighbours.push_back({n[1], t2, t});
        neighbours.push_back({n[2], t, t1});
        relink(n[1], t, t1);
        relink(n[2], t, t2);
        stack_.push_back({t, 0});
        stack_.push_back({t1, 0});
        stack_.push_back({t2, 0});
        legalize();
        last_ = t;
        return true;
    }

    // Moves each interior vertex towards the centroid of its neighbours, refusing any move that
    // would fold a triangle, then restores the Delaunay property.
    void smooth(int passes, const std::vector<bool>& onOutline) {
        for (int pass = 0; pass < passes; ++pass) {
            std::vector<std::vector<uint32_t>> incident(points.size());
            for (size_t t = 0; t < tris.size(); ++t)
                for (uint32_t v : tris[t]) incident[v].push_back(uint32_t(t));
            for (size_t v = 0; v < points.size(); ++v) {
                if (onOutline[v] || incident[v].empty()) continue;
                P2 sum;
                double weight = 0;
                for (uint32_t t : incident[v])
                    for (uint32_t w : tris[t])
                        if (w != v) sum.x += points[w].x, sum.y += points[w].y, weight += 1;
                const P2 target{sum.x / weight, sum.y / weight};
                bool folds = false;
                for (uint32_t t : incident[v]) {
                    std::array<P2, 3> q;
                    for (int i = 0; i < 3; ++i)
                        q[size_t(i)] =
                            tris[t][size_t(i)] == v ? target : points[tris[t][size_t(i)]];
                    // Keep a margin: a triangle squashed to a needle is as bad as a folded one.
                    const double e =
                        std::max({dist(q[0], q[1]), dist(q[1], q[2]), dist(q[2], q[0])});
                    if (orient(q[0], q[1], q[2]) <= 0.05 * e * e) folds = true;
                }
                if (!folds) points[v] = target;
            }
            makeDelaunay();
        }
    }

    double minOrientation() const {
        double m = INFINITY;
        for (const auto& t : tris)
            m = std::min(m, orient(points[t[0]], points[t[1]], points[t[2]]));
        return m;
    }

private:
    struct EdgeRef {
        int32_t tri;
        int edge;
    };
    std::vector<EdgeRef> stack_;
    int32_t last_ = 0;

    static uint64_t key(uint32_t a, uint32_t b) { return (uint64_t(a) << 32) | b; }

    // In `tri`, the neighbour pointer that was `from` becomes `to`.
    void relink(int32_t tri, int32_t from, int32_t to) {
        if (tri < 0) return;
        for (int32_t& n : neighbours[size_t(tri)])
            if (n == from) {
                n = to;
                return;
            }
    }

    void legalize() {
        // Lawson's flips terminate in exact arithmetic; the cap is a guard against rounding
        // making two nearly cocircular configurations flip back and forth forever.
        size_t budget = 64 * tris.size() + 1024;
        while (!stack_.empty()) {
            const EdgeRef e = stack_.back();
            stack_.pop_back();
            if (budget == 0) continue;
            if (flipIfIllegal(e.tri, e.edge)) --budget;
        }
    }

    bool flipIfIllegal(int32_t t, int i) {
        const int32_t u = neighbours[size_t(t)][size_t(i)];
        if (u < 0) return false;
        const uint32_t a = tris[size_t(t)][size_t(i)], b = tris[size_t(t)][size_t((i + 1) % 3)],
                       c = tris[size_t(t)][size_t((i + 2) % 3)];
        int j = 0;
        while (j < 3 &&
               !(tris[size_t(u)][size_t(j)] == b && tris[size_t(u)][size_t((j + 1) % 3)] == a))
            ++j;
        if (j == 3) return false;
        const uint32_t d = tris[size_t(u)][size_t((j + 2) % 3)];
        const P2 pa = points[a], pb = points[b], pc = points[c], pd = points[d];
        // The quad a-d-b-c must be strictly convex for the other diagonal to be inside it.
        if (orient(pc, pa, pd) <= 0 || orient(pd, pb, pc) <= 0) return false;
        // Delaunay test "the angles at c and d sum to more than pi", as sin(C + D) < 0 from cross
        // and dot products: no trigonometry, and a zero-area triangle with c inside segment ab
        // (angle pi) is flipped as it should be.
        const P2 ca = pa - pc, cb = pb - pc, db = pb - pd, da = pa - pd;
        const double sinSum = cross(ca, cb) * dot(db, da) + dot(ca, cb) * cross(db, da);
        const double scale = std::sqrt(dot(ca, ca) * dot(cb, cb) * dot(db, db) * dot(da, da));
        if (sinSum >= -1e-9 * scale) return false;
        const int32_t tca = neighbours[size_t(t)][size_t((i + 2) % 3)],
                      tbc = neighbours[size_t(t)][size_t((i + 1) % 3)],
                      uad = neighbours[size_t(u)][size_t((j + 1) % 3)],
                      udb = neighbours[size_t(u)][size_t((j + 2) % 3)];
        tris[size_t(t)] = {c, a, d};
        neighbours[size_t(t)] = {tca, uad, u};
        tris[size_t(u)] = {d, b, c};
        neighbours[size_t(u)] = {udb, tbc, t};
        relink(uad, u, t);
        relink(tbc, t, u);
        stack_.push_back({t, 0});
        stack_.push_back({t, 1});
        stack_.push_back({u, 0});
        stack_.push_back({u, 1});
        return true;
    }

    // Walks from the last insertion towards p (consecutive lattice points are close); falls
    // back to a linear search when the walk leaves the domain through the outline or a hole.
    int32_t locate(P2 p) const {
        int32_t t = std::min(last_, int32_t(tris.size()) - 1);
        for (size_t steps = 0; steps < tris.size(); ++steps) {
            int32_t next = -2;
            for (int i = 0; i < 3 && next == -2; ++i)
                if (orient(points[tris[size_t(t)][size_t(i)]],
                           points[tris[size_t(t)][size_t((i + 1) % 3)]], p) < 0)
                    next = neighbours[size_t(t)][size_t(i)];
            if (next == -2) return t;
            if (next == -1) break;
            t = next;
        }
        for (size_t s = 0; s < tris.size(); ++s) {
            const auto& v = tris[s];
            if (orient(points[v[0]], points[v[1]], p) >= 0 &&
                orient(points[v[1]], points[v[2]], p) >= 0 &&
                orient(points[v[2]], points[v[0]], p) >= 0)
                return int32_t(s);
        }
        return -1;
    }
};

// Winding number of p with respect to the outline edges (directed with the domain on the left):
// 1 inside the cap, 0 outside and in holes.
inline int winding(P2 p, const std::vector<std::pair<P2, P2>>& outline) {
    int w = 0;
    for (const auto& [a, b] : outline) {
        if (a.y <= p.y) {
            if (b.y > p.y && orient(a, b, p) > 0) ++w;
        } else if (b.y <= p.y && orient(a, b, p) < 0) {
            --w;
        }
    }
    return w;
}

} // namespace ffd::detail
