// Hangs the letter J from a pin at its top corner, lets it swing and settle, then drags the pin
// sideways at 8 m/s and stops it dead: prints the pin's force (it carries the letter's weight
// once settled) and how far the pinned point lags behind the target.
#include <ffdaabb/generators.h>
#include <ffdaabb/world.h>

#include <cmath>
#include <cstdio>

int main() {
    ffd::World world; // 1/60 s frames, two substeps, gravity, a floor at y = 0

    ffd::BodySettings s;
    s.lattice.targetCells = 34;
    s.position = {0, 2, 0};
    const ffd::BodyId letter = world.addBody(ffd::letter('J'), s); // 1 m tall

    // Pin the vertex furthest up and to the left, where it is: the letter starts off balance.
    const auto v = world.vertices(letter);
    uint32_t corner = 0;
    for (uint32_t i = 0; i < v.size(); ++i)
        if (v[i].y - 0.3f * v[i].x > v[corner].y - 0.3f * v[corner].x) corner = i;
    ffd::PinSettings hard; // stiffness 0: hard; the letter follows as a whole (rigidity 1)
    const ffd::PinId pin = world.pinVertex(letter, corner, v[corner], hard);
    const float weight = world.info(letter).mass * 9.81f;

    std::printf("the letter weighs %.1f N\n", double(weight));
    std::printf("%6s %10s %10s %10s %10s\n", "time", "force N", "lag mm", "swing cm", "energy J");
    ffd::Vec3 target = world.pin(pin).target;
    for (int frame = 1; frame <= 540; ++frame) {
        if (frame > 360 && frame <= 390) target.x += 8.0f / 60.0f; // dragged at 8 m/s, 0.5 s
        world.setPinTarget(pin, target);
        world.step();
        if (frame % 30 == 0) {
            const ffd::PinInfo p = world.pin(pin);
            const ffd::Vec3 c = world.centreOfMass(letter);
            const double swing = std::hypot(c.x - p.target.x, c.z - p.target.z) * 100;
            std::printf("%5.1fs %10.1f %10.3f %10.2f %10.2f%s\n", frame / 60.0,
                        double(ffd::length(p.force)), double(p.lag) * 1000, swing,
                        world.kineticEnergy(), frame == 360 ? "   <- dragged from here" : "");
        }
    }
    const float held = world.centreOfMass(letter).y;
    world.unpin(pin); // and it falls
    for (int frame = 0; frame < 120; ++frame) world.step();
    std::printf("unpinned: the letter's centre went from %.2f m to %.2f m (on the floor)\n",
                double(held), double(world.centreOfMass(letter).y));
    return 0;
}
