// ffdaabb_energy_stages: which stage of a step puts kinetic energy into the bodies, and which
// takes it out.
//
// Steps a scene and, after every stage of every substep, sums over the bodies two kinetic
// energies (joules, from the particles' masses and velocities):
//
//   motion       each body's mass times its mean velocity squared, over 2: what the body
//                carries as a whole (its horizontal part, square to gravity, is printed too);
//   deformation  its particles' velocities relative to that mean: spin and deformation, what
//                shape matching makes when it restores a dent.
//
// Each stage's change of the two is summed over a window of N frames and printed per window,
// with the energies at the window's end. The stages are those of the profile (ffdaabb/profile.h);
// response_after_move is the projection after the move and the velocity pass together. Used for
// docs/ALGORITHM.md, "The 200 at one spot, before the centre's bound": in 200 spheres created at
// one spot (examples/one_spot.json) the dynamics makes deformation energy every substep and the
// response after the move hands a share of it to the bodies' motion.
#include "ffdaabb/profile.h"
#include "ffdaabb/scene.h"
#include "ffdaabb/world.h"
#include "json_output.h"
#include "util/atomic_file.h"
#include "world/world_data.h"

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <optional>
#include <span>
#include <string>
#include <vector>

using namespace ffd;

namespace {

struct Energies {
    double motion = 0, horizontal = 0, deformation = 0;
};

// Each body's particles' masses and their sum, which a step does not change.
struct BodyMasses {
    std::vector<float> particle;
    double total = 0;
};

// The bodies' energies now (`up`: unit against gravity, or zero).
Energies energiesOf(const World& world, const std::vector<BodyId>& bodies,
                    const std::vector<BodyMasses>& masses, Vec3 up) {
    Energies e;
    for (size_t k = 0; k < bodies.size(); ++k) {
        const BodyMasses& m = masses[k];
        if (!(m.total > 0)) continue;
        const Vec3 mean = world.linearVelocity(bodies[k]); // mass-weighted
        const Vec3 across = mean - up * dot(mean, up);
        e.motion += 0.5 * m.total * double(dot(mean, mean));
        e.horizontal += 0.5 * m.total * double(dot(across, across));
        const std::span<const Vec3> v = world.velocities(bodies[k]);
        for (size_t i = 0; i < v.size(); ++i) {
            const Vec3 d = v[i] - mean;
            e.deformation += 0.5 * double(m.particle[i]) * double(dot(d, d));
        }
    }
    return e;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"Which stage of a step puts kinetic energy into the bodies"};
    std::string sceneName, jsonPath;
    int frames = 120, every = 10;
    int64_t seed = -1;
    app.add_option("--scene", sceneName,
                   "Scene name or file (examples/one_spot.json: 200 at one spot)")
        ->required();
    app.add_option("--frames", frames, "Frames to step (default 120)")
        ->check(CLI::Range(1, 1000000));
    app.add_option("--every", every, "Frames per printed window (default 10)")
        ->check(CLI::Range(1, 1000000));
    app.add_option("--seed", seed, "The layout's seed (default: the scene's)")
        ->check(CLI::Range(int64_t(0), int64_t(UINT32_MAX)));
    app.add_option("--json", jsonPath, "Write the windows as JSON to this file");
    CLI11_PARSE(app, argc, argv);

    Scene scene;
    std::optional<AtomicFile> jsonFile; // opened first: a bad path fails before the run
    try {
        scene = loadScene(sceneName);
        if (seed >= 0) scene.layout.seed = uint32_t(seed);
        if (!jsonPath.empty()) jsonFile.emplace(jsonPath, "w");
    } catch (const std::exception& e) {
        fmt::print(stderr, "ffdaabb_energy_stages: {}\n", e.what());
        return 2;
    }
    SceneBuild build = buildScene(scene);
    World& world = build.world;
    const Vec3 gravity = world.settings().gravity;
    const Vec3 up = length(gravity) > 0 ? normalize(-gravity) : Vec3{};

    std::vector<BodyMasses> masses(build.bodies.size());
    for (size_t k = 0; k < build.bodies.size(); ++k) {
        const uint32_t count = uint32_t(world.velocities(build.bodies[k]).size());
        for (uint32_t i = 0; i < count; ++i) {
            masses[k].particle.push_back(world.particleMass(build.bodies[k], i));
            masses[k].total += masses[k].particle.back();
        }
    }
    // Per stage, the change of each energy over the window.
    std::array<Energies, kStageCount> change{};
    Energies last = energiesOf(world, build.bodies, masses, up);
    detail::dataOf(world).stageObserver = [&](Stage stage) {
        const Energies now = energiesOf(world, build.bodies, masses, up);
        Energies& c = change[size_t(stage)];
        c.motion += now.motion - last.motion;
        c.horizontal += now.horizontal - last.horizontal;
        c.deformation += now.deformation - last.deformation;
        last = now;
    };

    fmt::print("{}: {} bodies; per window, each stage's change of the bodies' kinetic energy "
               "(J), motion / deformation\n",
               scene.name, build.bodies.size());
    nlohmann::json windows = nlohmann::json::array();
    for (int f = 1; f <= frames; ++f) {
        world.step();
        if (f % every != 0 && f != frames) continue;
        fmt::print("frame {:>5}  motion {:.4g} (across gravity {:.4g}), deformation {:.4g}\n", f,
                   last.motion, last.horizontal, last.deformation);
        nlohmann::json stages;
        for (const StageInfo& s : stageTable()) {
            const Energies& c = change[size_t(s.stage)];
            if (c.motion == 0 && c.deformation == 0) continue;
            fmt::print("    {:<22} {:+.4g} / {:+.4g}\n", s.key, c.motion, c.deformation);
            stages[s.key] = {{"motion", c.motion},
                             {"across_gravity", c.horizontal},
                             {"deformation", c.deformation}};
        }
        windows.push_back({{"frame", f},
                           {"motion", last.motion},
                           {"across_gravity", last.horizontal},
                           {"deformation", last.deformation},
                           {"stages", stages}});
        change = {};
    }
    if (jsonFile) {
        const std::string text = nlohmann::json{{"scene", scene.name},
                                                {"bodies", build.bodies.size()},
                                                {"every", every},
                                                {"windows", windows}}
                                     .dump(2) +
                                 "\n";
        return bench::commitJson(*jsonFile, text, "ffdaabb_energy_stages");
    }
    return 0;
}
