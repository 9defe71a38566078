// Drops three different objects (a sphere, a teapot and the letter A) onto the floor and onto
// each other, and prints their heights as they fall and come to rest.
#include <ffdaabb/generators.h>
#include <ffdaabb/world.h>

#include <algorithm>
#include <cstdio>

namespace {

float lowestVertex(const ffd::World& world, ffd::BodyId id) {
    float y = 1e30f;
    for (const ffd::Vec3& v : world.vertices(id)) y = std::min(y, v.y);
    return y;
}

} // namespace

int main() {
    ffd::World world; // 1/60 s frames, gravity, a floor at y = 0, the Enhanced FFD-AABB pipeline

    ffd::TriangleMesh sphere = ffd::icosphere(2);
    ffd::transform(sphere, 0.4f, {}); // radius 0.4 m
    ffd::TriangleMesh teapot = ffd::teapot(10);
    ffd::normalizeSize(teapot, 1.0f);            // 1 m across
    ffd::TriangleMesh letter = ffd::letter('A'); // 1 m tall

    ffd::BodySettings s;
    s.lattice.targetCells = 84;
    s.position = {0, 0.8f, 0};
    const ffd::BodyId pot = world.addBody(teapot, s);
    s.lattice.targetCells = 38;
    s.position = {0.1f, 2.2f, 0};
    const ffd::BodyId ball = world.addBody(sphere, s);
    s.lattice.targetCells = 34;
    s.position = {-0.2f, 3.5f, 0.1f};
    s.rotation = ffd::Quat::fromAxisAngle({1, 0, 0}, 1.2f);
    const ffd::BodyId a = world.addBody(letter, s);

    std::printf("%6s %10s %10s %10s   (centre of mass height, m)\n", "t (s)", "teapot", "sphere",
                "letter A");
    for (int frame = 0; frame <= 300; ++frame) {
        if (frame % 30 == 0)
            std::printf("%6.2f %10.3f %10.3f %10.3f\n", frame / 60.0, world.centreOfMass(pot).y,
                        world.centreOfMass(ball).y, world.centreOfMass(a).y);
        world.step();
    }
    std::printf("lowest vertices: teapot %.4f, sphere %.4f, letter %.4f m\n",
                lowestVertex(world, pot), lowestVertex(world, ball), lowestVertex(world, a));
    const ffd::Profile& p = world.profile();
    std::printf("last frame: %.3f ms (dynamics %.3f, collisions %.3f), %d contacts\n", p.total,
                p.ms(ffd::TableColumn::Dynamics),
                p.ms(ffd::TableColumn::ObjectsCollision) + p.ms(ffd::TableColumn::Floor),
                p.contacts + p.floorContacts);
    return 0;
}
