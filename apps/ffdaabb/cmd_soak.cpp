// ffdaabb soak: a long run of a scene that checks, as it goes, that the simulation stays
// healthy: everything finite, energy bounded, nothing sunk into the floor, no pair of objects
// interpenetrating. Exit 0 when every check held, 1 at the first violation (with a message
// saying which check, by how much, and when), 2 for bad input.
//
//   ffdaabb soak --scene spheres --frames 20000
#include "commands.h"
#include "flags.h"
#include "runner.h"

#include "ffdaabb/error.h"
#include "interpenetration.h"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace ffd::cli {

namespace {

struct SoakOptions {
    SceneFlags scene;
    std::string frames = "20000", checkEvery = "10";
    std::string floorTolerance = "0.01", depthTolerance = "0.01", energyTolerance = "2",
                riseTolerance = "0.5", settleTime = "1", launchTolerance = "0", launchTime = "2";
    bool quiet = false;
};

struct SoakLimits {
    int frames = 0, checkEvery = 1;
    double floorTolerance = 0, depthTolerance = 0, energyTolerance = 0, riseTolerance = 0;
    double launchTolerance = 0;
    int settleFrames = 0, launchFrames = 0;
};

// Each body's centre of mass.
std::vector<Vec3> centresOfMass(const World& world, const std::vector<BodyId>& bodies) {
    std::vector<Vec3> centres;
    centres.reserve(bodies.size());
    for (BodyId id : bodies) centres.push_back(world.centreOfMass(id));
    return centres;
}

// Total mechanical energy: the particles' kinetic energy plus each body's potential energy in
// the gravity field (mass times the height of its centre of mass `centres`, zero at the origin:
// only changes matter). Joules.
double mechanicalEnergy(const World& world, const std::vector<BodyId>& bodies,
                        const std::vector<Vec3>& centres) {
    const Vec3 g = world.settings().gravity;
    double e = world.kineticEnergy();
    for (size_t b = 0; b < bodies.size(); ++b)
        e -= double(world.info(bodies[b]).mass) * double(dot(g, centres[b]));
    return e;
}

struct Violation {
    bool found = false;
    std::string what;
};

int soak(const SoakOptions& o) {
    SoakLimits lim;
    lim.frames = int(parseInteger("--frames", o.frames, 1, 10000000));
    lim.checkEvery = int(parseInteger("--check-every", o.checkEvery, 1, 10000000));
    lim.floorTolerance = parseNumber("--floor-tolerance", o.floorTolerance, 0, 1,
                                     "a fraction of the object's size, 0..1");
    lim.depthTolerance = parseNumber("--depth-tolerance", o.depthTolerance, 0, 1,
                                     "a fraction of the largest object's size, 0..1");
    lim.energyTolerance = parseNumber("--energy-tolerance", o.energyTolerance, 0, 1000,
                                      "a multiple of the energy scale, 0..1000");
    lim.riseTolerance = parseNumber("--rise-tolerance", o.riseTolerance, 0, 1000,
                                    "a multiple of the energy scale, 0..1000");
    const double settleTime =
        parseNumber("--settle-time", o.settleTime, 0, 1e6, "seconds of simulated time, >= 0");
    lim.launchTolerance =
        parseNumber("--launch-tolerance", o.launchTolerance, 0, 1e6, "metres per second, >= 0");
    const double launchTime =
        parseNumber("--launch-time", o.launchTime, 0, 1e6, "seconds of simulated time, >= 0");
    const Scene scene = sceneFromFlags(o.scene);
    auto framesIn = [&](double seconds) {
        return int(std::min(1e7, std::ceil(seconds / double(scene.world.frameStep))));
    };
    lim.settleFrames = framesIn(settleTime);
    lim.launchFrames = framesIn(launchTime);
    SceneBuild build = buildScene(scene);
    World& world = build.world;
    const std::vector<BodyId>& bodies = build.bodies;
    const WorldSettings& ws = world.settings();

    // Each body's size: its scene object's (the largest extent of its rest mesh), in the order
    // buildScene adds the bodies.
    std::vector<float> sizes;
    for (const SceneObject& object : scene.objects)
        sizes.insert(sizes.end(), size_t(object.count), object.size);
    const float largest = *std::max_element(sizes.begin(), sizes.end());
    // The energy scale: what lifting every object by its own size against gravity costs. The
    // system only loses energy (damping, friction, inelastic contacts); what contact projection
    // adds when it pushes bodies apart stays a small part of this.
    const double g = length(ws.gravity);
    double energyScale = 0;
    for (size_t b = 0; b < bodies.size(); ++b)
        energyScale += double(world.info(bodies[b]).mass) * g * double(sizes[b]);
    if (!(energyScale > 0)) energyScale = 1; // no gravity: any gain shows against 1 J
    // Each body's centre of mass at the last frame: its rise over one frame is how fast the body
    // as a whole moves up, whatever its particles do.
    std::vector<Vec3> lastCentre = centresOfMass(world, bodies);
    const double initialEnergy = mechanicalEnergy(world, bodies, lastCentre);
    double lowestEnergy = initialEnergy;

    bench::InterpenetrationSettings measure;
    measure.referenceSize = largest > 0 ? largest : 1.0f;
    measure.floorHeight = ws.floorHeight;
    measure.deepFraction = float(lim.depthTolerance);
    std::vector<bench::MeshView> views;
    for (BodyId id : bodies) views.push_back({world.vertices(id), world.triangles(id)});

    double maxEnergyGain = 0, maxLateRise = 0, deepestBelowFloor = 0, deepest = 0;
    double fastestRise = 0;
    size_t fastestObject = 0; // which object rose fastest, and at which frame
    int fastestFrame = 0;
    int measures = 0, insideSamples = 0;
    const auto progress = o.quiet ? std::function<void(int, int)>() : progressBar(scene.name);
    const auto start = std::chrono::steady_clock::now();
    auto check = [&](int frame) -> Violation {
        const double t = frame * double(ws.frameStep);
        const std::string when = fmt::format("at frame {} (t = {:.3f} s)", frame, t);
        for (size_t b = 0; b < bodies.size(); ++b) {
            for (const Vec3& p : world.particles(bodies[b]))
                if (!isFinite(p))
                    return {true, fmt::format("object {}: a particle position is not finite {}", b,
                                              when)};
            for (const Vec3& v : world.velocities(bodies[b]))
                if (!isFinite(v))
                    return {true, fmt::format("object {}: a particle velocity is not finite {}", b,
                                              when)};
        }
        std::vector<Vec3> centre = centresOfMass(world, bodies);
        const double energy = mechanicalEnergy(world, bodies, centre);
        const double gain = energy - initialEnergy, rise = energy - lowestEnergy;
        lowestEnergy = std::min(lowestEnergy, energy);
        maxEnergyGain = std::max(maxEnergyGain, gain / energyScale);
        if (gain > lim.energyTolerance * energyScale)
            return {true, fmt::format("the energy grew by {:.4g} J over the start {}, more than "
                                      "{:g} times the energy scale {:.4g} J (lifting every object "
                                      "by its size)",
                                      gain, when, lim.energyTolerance, energyScale)};
        if (frame > lim.settleFrames) {
            maxLateRise = std::max(maxLateRise, rise / energyScale);
            if (rise > lim.riseTolerance * energyScale)
                return {true, fmt::format("the energy rose by {:.4g} J over its lowest so far {}, "
                                          "more than {:g} times the energy scale {:.4g} J "
                                          "(lifting every object by its size)",
                                          rise, when, lim.riseTolerance, energyScale)};
        }
        const float gravity = length(ws.gravity);
        for (size_t b = 0; b < bodies.size() && frame > lim.launchFrames && gravity > 0; ++b) {
            const double up = double(dot(centre[b] - lastCentre[b], -ws.gravity)) /
                              (double(gravity) * double(ws.frameStep));
            if (up > fastestRise) fastestRise = up, fastestObject = b, fastestFrame = frame;
            if (lim.launchTolerance > 0 && up > lim.launchTolerance)
                return {true, fmt::format("object {} rises at {:.4g} m/s {}, faster than {:g} m/s",
                                          b, up, when, lim.launchTolerance)};
        }
        lastCentre.swap(centre);
        if (ws.floor)
            for (size_t b = 0; b < bodies.size(); ++b) {
                float lowest = INFINITY;
                for (const Vec3& v : world.vertices(bodies[b])) lowest = std::min(lowest, v.y);
                const double below = double(ws.floorHeight) - double(lowest);
                deepestBelowFloor = std::max(deepestBelowFloor, below / double(sizes[b]));
                if (below > lim.floorTolerance * double(sizes[b]))
                    return {true, fmt::format("object {} is {:.4g} m below the floor {}, more than "
                                              "{:g} of its size {:.4g} m",
                                              b, below, when, lim.floorTolerance, sizes[b])};
            }
        if (frame % lim.checkEvery == 0 || frame == lim.frames) {
            const bench::Interpenetration p = bench::measureInterpenetration(views, measure);
            ++measures;
            insideSamples += p.insideVertices > 0;
            deepest = std::max(deepest, p.maxDepthRelative);
            if (p.deepVertices > 0)
                return {true, fmt::format("{} vertices lie inside other objects {} ({} pairs), "
                                          "deepest {:.4g} m (vertex {} of object {} inside "
                                          "object {}), more than {:g} of the largest object's "
                                          "size {:.4g} m",
                                          p.deepVertices, when, p.bodyPairs, p.maxDepth,
                                          p.deepestVertex, p.deepestBody, p.deepestInside,
                                          lim.depthTolerance, measure.referenceSize)};
        }
        return {};
    };

    Violation v = check(0);
    for (int f = 1; f <= lim.frames && !v.found; ++f) {
        world.step();
        v = check(f);
        if (progress) progress(f, lim.frames);
    }
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (v.found) {
        if (progress) fmt::print(stderr, "\n");
        fmt::print(stderr, "ffdaabb soak: FAILED: {}: {}\n", scene.name, v.what);
        return 1;
    }
    if (!o.quiet) {
        fmt::print("soak {} ({} objects, {} mode): {} frames ({:.1f} s simulated) in {:.1f} s, "
                   "every check held\n",
                   scene.name, bodies.size(), toString(ws.mode), lim.frames,
                   lim.frames * double(ws.frameStep), wall);
        fmt::print("  finite                every frame\n");
        fmt::print("  energy scale          {:.4g} J (lifting every object by its size)\n",
                   energyScale);
        fmt::print("  energy over start     {:.4f} of the scale at most (limit {:g})\n",
                   maxEnergyGain, lim.energyTolerance);
        fmt::print("  energy rise           {:.4f} of the scale at most after {} frames (limit "
                   "{:g})\n",
                   maxLateRise, lim.settleFrames, lim.riseTolerance);
        fmt::print("  fastest rise          {:.3f} m/s of a centre of mass after {} frames{} "
                   "({})\n",
                   fastestRise, lim.launchFrames,
                   fastestRise > 0
                       ? fmt::format(": object {} at frame {}", fastestObject, fastestFrame)
                       : std::string(),
                   lim.launchTolerance > 0 ? fmt::format("limit {:g}", lim.launchTolerance)
                                           : std::string("not checked"));
        fmt::print("  below floor (max)     {:.4f} of the object's size (limit {:g})\n",
                   deepestBelowFloor, lim.floorTolerance);
        fmt::print("  interpenetration      deepest {:.4f} of the largest size (limit {:g}), "
                   "{} of {} samples with any vertex inside\n",
                   deepest, lim.depthTolerance, insideSamples, measures);
        fmt::print("  state hash            {:016x}\n", world.stateHash());
    }
    return 0;
}

} // namespace

void addSoakCommand(CLI::App& app, Action& action) {
    auto o = std::make_shared<SoakOptions>();
    CLI::App* cmd = app.add_subcommand(
        "soak", "Run a scene for many frames, checking every frame that it stays healthy");
    addSceneFlags(cmd, o->scene);
    cmd->add_option("--frames", o->frames, "Frames to simulate, 1..10000000 (default 20000)");
    cmd->add_option("--check-every", o->checkEvery,
                    "Measure interpenetration every N frames (default 10; the other checks run "
                    "every frame)");
    cmd->add_option("--floor-tolerance", o->floorTolerance,
                    "Deepest a vertex may sink below the floor, as a fraction of its object's "
                    "size (default 0.01)");
    cmd->add_option("--depth-tolerance", o->depthTolerance,
                    "Deepest a vertex may lie inside another object, as a fraction of the "
                    "largest object's size (default 0.01)");
    cmd->add_option("--energy-tolerance", o->energyTolerance,
                    "Largest gain of kinetic plus potential energy over the start, in units of "
                    "the energy scale (lifting every object by its own size; default 2)");
    cmd->add_option("--rise-tolerance", o->riseTolerance,
                    "After the settle time, largest rise of the energy over its lowest value so "
                    "far, in units of the energy scale (default 0.5)");
    cmd->add_option("--settle-time", o->settleTime,
                    "Seconds of simulated time before the rise check starts: objects placed "
                    "close together are pushed apart at first (default 1)");
    cmd->add_option("--launch-tolerance", o->launchTolerance,
                    "After the launch time, fastest any object's centre of mass may rise, m/s "
                    "(default 0: reported, not checked)");
    cmd->add_option("--launch-time", o->launchTime,
                    "Seconds of simulated time before the launch check starts (default 2)");
    cmd->add_flag("--quiet", o->quiet, "No progress bar and no summary (failures still print)");
    cmd->footer("Exit status: 0 when every check held, 1 at the first violation (the message "
                "says which check, by how much and at which frame), 2 for bad input.");
    cmd->callback([o, &action] { action = [o] { return soak(*o); }; });
}

} // namespace ffd::cli
