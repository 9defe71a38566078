// Colliders: balls dropped on static stairs and on a kinematic platform that carries them back
// and forth, beside a tilted plane. Static and kinematic bodies collide through the same pipeline
// as any body, as bodies of infinite mass; the program moves the platform with setKinematicTarget.
#include <ffdaabb/generators.h>
#include <ffdaabb/world.h>

#include <cmath>
#include <cstdio>
#include <vector>

int main() {
    ffd::World world;

    // Stairs: three static boxes 0.5 m deep, 0.25 m per step, falling towards +x.
    ffd::BodySettings wall;
    wall.motion = ffd::BodyMotion::Static;
    std::vector<ffd::BodyId> steps;
    for (int k = 0; k < 3; ++k) {
        const float height = 0.25f * float(3 - k);
        wall.position = {-2.0f + 0.5f * float(k), 0.5f * height, 0};
        steps.push_back(world.addBody(ffd::box({0.25f, 0.5f * height, 1.0f}), wall));
    }

    // A platform at the foot of the stairs, moved back and forth by the program.
    ffd::BodySettings ride;
    ride.motion = ffd::BodyMotion::Kinematic;
    const ffd::Vec3 home{0.2f, 0.15f, 0};
    ride.position = home;
    const ffd::BodyId platform = world.addBody(ffd::box({0.6f, 0.1f, 1.0f}), ride);

    // A plane tilted 15 degrees, rising beyond the platform's reach: a ramp.
    const float tilt = 0.26f;
    world.addPlane({-std::sin(tilt), std::cos(tilt), 0}, -std::sin(tilt) * 2.5f);

    // Balls dropped on each step, and two boxes on the platform.
    ffd::TriangleMesh ball = ffd::icosphere(2);
    ffd::transform(ball, 0.2f, {}); // radius 0.2 m
    ffd::BodySettings s;
    s.lattice.targetCells = 38;
    s.friction = 0.8f;
    std::vector<ffd::BodyId> balls;
    for (int k = 0; k < 3; ++k) {
        s.position = {-2.0f + 0.5f * float(k), 1.5f, 0.3f * float(k - 1)};
        balls.push_back(world.addBody(ball, s));
    }
    s.lattice.targetCells = 27;
    std::vector<ffd::BodyId> crates;
    for (int i = 0; i < 2; ++i) {
        s.position = home + ffd::Vec3{-0.3f + 0.6f * float(i), 0.45f, 0};
        crates.push_back(world.addBody(ffd::box({0.15f, 0.15f, 0.15f}), s));
    }

    const float T = world.settings().frameStep;
    std::printf("%6s %10s %16s   %s\n", "t (s)", "platform x", "crates x", "balls y (m)");
    for (int frame = 1; frame <= 480; ++frame) {
        // Back and forth along x, 0.6 m each way, a 4 s period.
        const float t = float(frame) * T;
        world.setKinematicTarget(platform, home + ffd::Vec3{0.6f * std::sin(1.5708f * t), 0, 0});
        world.step();
        if (frame % 60 == 0) {
            std::printf("%6.2f %10.3f %8.3f %7.3f  ", t, world.centreOfMass(platform).x,
                        world.centreOfMass(crates[0]).x, world.centreOfMass(crates[1]).x);
            for (const ffd::BodyId b : balls) std::printf(" %6.3f", world.centreOfMass(b).y);
            std::printf("\n");
        }
    }
    // The stairs never moved, and no ball went below the floor.
    float lowest = 1e30f;
    for (const ffd::BodyId b : balls)
        for (const ffd::Vec3& v : world.vertices(b)) lowest = std::fmin(lowest, v.y);
    // The crates rode the platform: still on top of it (its top is at y = 0.25).
    for (const ffd::BodyId c : crates)
        if (world.centreOfMass(c).y < 0.3f) return 1;
    for (const ffd::BodyId st : steps)
        for (const ffd::Vec3& v : world.velocities(st))
            if (v.x != 0 || v.y != 0 || v.z != 0) return 1;
    std::printf("lowest ball vertex %.4f m; %zu bodies, %zu planes\n", lowest, world.bodyCount(),
                world.planes().size());
    return lowest > -0.01f ? 0 : 1;
}
