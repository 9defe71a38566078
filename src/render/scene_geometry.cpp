#include "render/scene_geometry.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace ffd::render::detail {

void smoothNormals(std::span<const Vec3> positions,
                   std::span<const std::array<uint32_t, 3>> triangles,
                   std::vector<Vec3>& outNormals) {
    outNormals.assign(positions.size(), Vec3{});
    // The unnormalised cross product weights each face by its area.
    for (const auto& t : triangles) {
        const Vec3 a = positions[t[0]], b = positions[t[1]], c = positions[t[2]];
        const Vec3 n = cross(b - a, c - a);
        outNormals[t[0]] += n;
        outNormals[t[1]] += n;
        outNormals[t[2]] += n;
    }
    for (Vec3& n : outNormals) n = normalize(n);
}

void overlaySphere(const World& world, BodyId body, Vec3& outCentre, float& outRadius) {
    if (world.settings().mode == CollisionMode::Enhanced && world.frame() > 0) {
        world.boundingSphere(body, outCentre, outRadius);
        if (outRadius > 0) return;
    }
    const std::span<const Vec3> nodes = world.boxNodes(body);
    Aabb all;
    for (const Vec3& p : nodes) all.add(p);
    const Vec3 c = all.centre();
    float r2 = 0;
    for (size_t b = 0; b + 8 <= nodes.size(); b += 8) {
        Aabb box;
        for (size_t n = 0; n < 8; ++n) box.add(nodes[b + n]);
        r2 = std::max(r2, lengthSquared(max(box.hi - c, c - box.lo)));
    }
    outCentre = c;
    outRadius = std::sqrt(r2);
}

namespace {

void addLine(Vec3 a, Vec3 b, Vec3 colour, std::vector<LineVertex>& out) {
    out.push_back({a, colour});
    out.push_back({b, colour});
}

void appendContacts(const World& world, std::vector<LineVertex>& out) {
    std::vector<ContactInfo> contacts;
    world.contacts(contacts);
    for (const ContactInfo& c : contacts) {
        const float h = world.lattice(c.bodyA).cellSize;
        const Vec3 colour = c.bodyB.isNull() ? kFloorContactColour : kObjectContactColour;
        const Vec3 p = c.point;
        const float s = 0.12f * h;
        addLine(p - Vec3{s, 0, 0}, p + Vec3{s, 0, 0}, colour, out);
        addLine(p - Vec3{0, s, 0}, p + Vec3{0, s, 0}, colour, out);
        addLine(p - Vec3{0, 0, s}, p + Vec3{0, 0, s}, colour, out);
        addLine(p, p + c.normal * (0.6f * h), colour, out);
    }
}

} // namespace

void appendSphereWire(Vec3 centre, float radius, Vec3 colour, std::vector<LineVertex>& out,
                      int meridians, int parallels, int segments) {
    const float pi = std::numbers::pi_v<float>;
    auto circlePoint = [&](int i, auto&& at) { return at(2 * pi * float(i) / float(segments)); };
    for (int m = 0; m < meridians; ++m) {
        const float phi = pi * float(m) / float(meridians);
        const Vec3 axis{std::cos(phi), 0, std::sin(phi)};
        auto at = [&](float t) {
            return centre + (axis * std::cos(t) + Vec3{0, std::sin(t), 0}) * radius;
        };
        for (int i = 0; i < segments; ++i)
            addLine(circlePoint(i, at), circlePoint(i + 1, at), colour, out);
    }
    for (int p = 1; p <= parallels; ++p) {
        const float lat = pi * (float(p) / float(parallels + 1) - 0.5f);
        const float y = std::sin(lat) * radius, rr = std::cos(lat) * radius;
        auto at = [&](float t) { return centre + Vec3{rr * std::cos(t), y, rr * std::sin(t)}; };
        for (int i = 0; i < segments; ++i)
            addLine(circlePoint(i, at), circlePoint(i + 1, at), colour, out);
    }
}

void appendHexahedronWire(const Vec3* corners, Vec3 colour, std::vector<LineVertex>& out) {
    for (int n = 0; n < 8; ++n)
        for (int bit = 1; bit < 8; bit <<= 1)
            if (!(n & bit)) addLine(corners[n], corners[n | bit], colour, out);
}

void latticeEdges(const Lattice& lattice, std::vector<std::array<uint32_t, 2>>& outEdges) {
    outEdges.clear();
    outEdges.reserve(lattice.cellParticles.size() * 12);
    for (const auto& corner : lattice.cellParticles)
        for (int n = 0; n < 8; ++n)
            for (int bit = 1; bit < 8; bit <<= 1)
                if (!(n & bit)) {
                    const uint32_t a = corner[n], b = corner[n | bit];
                    outEdges.push_back({std::min(a, b), std::max(a, b)});
                }
    std::sort(outEdges.begin(), outEdges.end());
    outEdges.erase(std::unique(outEdges.begin(), outEdges.end()), outEdges.end());
}

void appendOverlayLines(const World& world, const DrawOptions& options,
                        std::vector<LineVertex>& out) {
    const std::vector<BodyId> bodies = world.bodies();
    if (options.overlays.spheres)
        for (BodyId b : bodies) {
            Vec3 c;
            float r = 0;
            overlaySphere(world, b, c, r);
            if (r > 0) appendSphereWire(c, r, kSphereColour, out);
        }
    if (options.overlays.boxes)
        for (BodyId b : bodies) {
            const std::span<const Vec3> nodes = world.boxNodes(b);
            for (size_t i = 0; i + 8 <= nodes.size(); i += 8)
                appendHexahedronWire(nodes.data() + i, kBoxColour, out);
        }
    if (options.overlays.lattice) {
        // Bodies made from the same model share one lattice: its edges are found once per draw.
        std::vector<std::pair<const Lattice*, std::vector<std::array<uint32_t, 2>>>> cache;
        for (BodyId b : bodies) {
            const Lattice& lattice = world.lattice(b);
            auto it = std::find_if(cache.begin(), cache.end(),
                                   [&](const auto& c) { return c.first == &lattice; });
            if (it == cache.end()) {
                cache.emplace_back(&lattice, std::vector<std::array<uint32_t, 2>>{});
                latticeEdges(lattice, cache.back().second);
                it = cache.end() - 1;
            }
            const std::span<const Vec3> x = world.particles(b);
            for (const auto& e : it->second) addLine(x[e[0]], x[e[1]], kLatticeColour, out);
        }
    }
    if (options.overlays.contacts) appendContacts(world, out);
    for (const Line& l : options.lines) addLine(l.a, l.b, l.colour, out);
}

} // namespace ffd::render::detail
