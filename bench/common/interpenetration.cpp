// Generalized winding numbers: Jacobson, Kavan, Sorkine-Hornung, "Robust inside-outside
// segmentation using generalized winding numbers", SIGGRAPH 2013. Solid angle of a triangle:
// Van Oosterom and Strackee, "The solid angle of a plane triangle", IEEE TBME 1983. Closest
// point on a triangle: Ericson, "Real-Time Collision Detection", 5.1.5.
#include "interpenetration.h"
#include "sample_stats.h"

#include <algorithm>
#include <cmath>
#include <limits>
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

// Squared distance from p to triangle abc (Ericson's region tests).
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
        const D3 a = toD3(mesh.vertices[t[0]]) - p;
        const D3 b = toD3(mesh.vertices[t[1]]) - p;
        const D3 c = toD3(mesh.vertices[t[2]]) - p;
        const double la = norm(a), lb = norm(b), lc = norm(c);
        const double numerator = dot(a, cross(b, c));
        const double denominator = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb;
        sum += 2.0 * std::atan2(numerator, denominator);
    }
    return sum / (4.0 * std::numbers::pi);
}

bool insideMesh(Vec3 point, const MeshView& mesh) {
    return windingNumber(point, mesh) > 0.5;
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
    // The vertices of `a` inside `b`; returns whether there was any.
    auto probe = [&](size_t a, size_t b) {
        bool any = false;
        for (size_t k = 0; k < bodies[a].vertices.size(); ++k) {
            const Vec3 v = bodies[a].vertices[k];
            if (!box[b].contains(v) || !insideMesh(v, bodies[b])) continue;
            const double depth = distanceToSurface(v, bodies[b]);
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
        for (const Vec3& v : bodies[a].vertices)
            if (reach.contains(v)) best = std::min(best, distanceToSurface(v, bodies[b]));
        return best;
    };
    std::vector<double> gap(n, range);
    // Sort-and-sweep along x keeps the pair search near-linear for piles of hundreds.
    std::vector<size_t> order;
    for (size_t i = 0; i < n; ++i)
        if (usable[i]) order.push_back(i);
    std::sort(order.begin(), order.end(),
              [&](size_t a, size_t b) { return box[a].lo.x < box[b].lo.x; });
    for (size_t k = 0; k < order.size(); ++k)
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
