// The smallest ffdaabb program: one soft ball falls onto the floor.
#include <ffdaabb/generators.h>
#include <ffdaabb/world.h>

#include <cstdio>

int main() {
    ffd::World world;
    ffd::BodySettings ball;
    ball.position = {0, 2, 0};
    const ffd::BodyId id = world.addBody(ffd::icosphere(2), ball);
    for (int frame = 0; frame <= 120; ++frame) {
        if (frame % 20 == 0)
            std::printf("t = %.2f s  lowest point y = %.3f m\n", frame / 60.0,
                        world.bounds(id).lo.y);
        world.step();
    }
}
