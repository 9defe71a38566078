// Queries on a running world (ffdaabb/queries.h): drops a sphere and a teapot onto a block,
// prints the contact begin and end events of each step as they come, then casts rays at the
// pile, asks which bodies a box overlaps and what each body rests on.
#include <ffdaabb/generators.h>
#include <ffdaabb/queries.h>
#include <ffdaabb/world.h>

#include <cstdio>
#include <string>
#include <vector>

namespace {

// A box of the given half sizes centred on the origin (12 triangles, outward).
ffd::TriangleMesh block(ffd::Vec3 h) {
    ffd::TriangleMesh m;
    for (int i = 0; i < 8; ++i)
        m.positions.push_back({i & 1 ? h.x : -h.x, i & 2 ? h.y : -h.y, i & 4 ? h.z : -h.z});
    m.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                   {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
    return m;
}

std::string nameOf(ffd::BodyId id, const std::vector<std::pair<ffd::BodyId, const char*>>& names) {
    if (id.isNull()) return "floor";
    for (const auto& [body, name] : names)
        if (body == id) return name;
    return "body " + std::to_string(id.index);
}

} // namespace

int main() {
    ffd::World world;

    ffd::BodySettings s;
    s.lattice.targetCells = 48;
    s.position = {0, 0.25f, 0}; // resting on the floor
    const ffd::BodyId table = world.addBody(block({0.8f, 0.25f, 0.6f}), s);

    ffd::TriangleMesh sphere = ffd::icosphere(2);
    ffd::transform(sphere, 0.3f, {}); // radius 0.3 m
    s.lattice.targetCells = 38;
    s.position = {-0.35f, 1.2f, 0};
    const ffd::BodyId ball = world.addBody(sphere, s);

    ffd::TriangleMesh pot = ffd::teapot(6);
    ffd::normalizeSize(pot, 0.6f);
    s.lattice.targetCells = 64;
    s.position = {0.4f, 1.6f, 0.05f};
    const ffd::BodyId teapot = world.addBody(pot, s);

    const std::vector<std::pair<ffd::BodyId, const char*>> names = {
        {table, "block"}, {ball, "sphere"}, {teapot, "teapot"}};

    // Three seconds of falling and settling; each step's events as Box2D would report them.
    for (int frame = 1; frame <= 180; ++frame) {
        world.step();
        const ffd::ContactEvents events = ffd::contactEvents(world);
        for (const ffd::ContactEvent& e : events.begin)
            std::printf("frame %3d: %s begins touching %s\n", frame, nameOf(e.bodyA, names).c_str(),
                        nameOf(e.bodyB, names).c_str());
        for (const ffd::ContactEvent& e : events.end)
            std::printf("frame %3d: %s stops touching %s\n", frame, nameOf(e.bodyA, names).c_str(),
                        nameOf(e.bodyB, names).c_str());
    }

    // What each body rests on, with the force it gets from there (normal impulse of the step
    // over the step), beside its weight.
    std::vector<ffd::BodyContact> touching;
    for (const auto& [body, name] : names) {
        ffd::touchingBodies(world, body, touching);
        std::printf("%s (weight %.0f N) touches:", name, double(world.info(body).mass) * 9.81);
        for (const ffd::BodyContact& c : touching)
            std::printf("  %s %.0f N", nameOf(c.other, names).c_str(),
                        double(c.normalImpulse / world.settings().frameStep));
        std::printf("\n");
    }

    // Rays straight down onto the pile, every 20 cm.
    for (int i = -4; i <= 4; ++i) {
        const float x = 0.2f * float(i);
        const std::optional<ffd::RayHit> hit = ffd::raycast(world, {x, 3, 0}, {0, -1, 0});
        if (hit)
            std::printf("ray at x = %+.1f hits %s, triangle %u, at height %.3f m\n", double(x),
                        nameOf(hit->body, names).c_str(), hit->triangle, double(hit->point.y));
        else
            std::printf("ray at x = %+.1f hits nothing\n", double(x));
    }
    // A ray that ignores the sphere, and all crossings of one through the whole pile.
    const ffd::BodyId skip[] = {ball};
    if (auto hit = ffd::raycast(world, {-0.35f, 3, 0}, {0, -1, 0}, 10.0f, skip))
        std::printf("ignoring the sphere, the ray at x = -0.35 hits %s at %.3f m\n",
                    nameOf(hit->body, names).c_str(), double(hit->point.y));
    std::vector<ffd::RayHit> all;
    ffd::raycastAll(world, {-2, 0.3f, 0.01f}, {1, 0, 0}, 4.0f, all);
    std::printf("a level ray at 0.3 m crosses %zu surfaces\n", all.size());

    // Which bodies a 30 cm box just above the block overlaps.
    std::vector<ffd::BodyId> inBox;
    ffd::bodiesOverlapping(world, ffd::Aabb{{-0.5f, 0.5f, -0.15f}, {-0.2f, 0.8f, 0.15f}}, inBox);
    std::printf("the box over the block's left half overlaps:");
    for (ffd::BodyId b : inBox) std::printf(" %s", nameOf(b, names).c_str());
    std::printf("\n");

    // Lift the sphere away: its contact ends at the next step.
    world.translate(ball, {0, 3, 0});
    world.step();
    for (const ffd::ContactEvent& e : ffd::contactEvents(world).end)
        std::printf("after the lift: %s stops touching %s\n", nameOf(e.bodyA, names).c_str(),
                    nameOf(e.bodyB, names).c_str());
    return 0;
}
