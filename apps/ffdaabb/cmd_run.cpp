// ffdaabb run: one scene for N frames, with stats, mesh export, a progress bar and a summary.
#include "commands.h"
#include "runner.h"

#include "ffdaabb/error.h"

#include <fmt/core.h>

#include <filesystem>

namespace ffd::cli {

namespace {

struct RunCommandOptions {
    std::string scene;
    int objects = 0;
    int frames = 300;
    int warmup = 0;
    std::string mode;
    int threads = -1;
    long long seed = -1;
    std::string stats, exportObj;
    bool quiet = false;
};

// Fails before any work when an output file could not be written at the end.
void checkOutputPath(const std::string& flag, const std::string& path) {
    if (path.empty()) return;
    const std::filesystem::path p(path);
    if (std::filesystem::is_directory(p))
        throw InputError(flag, "\"" + path + "\" is a folder (expected a file name)");
    const std::filesystem::path parent = p.has_parent_path() ? p.parent_path() : ".";
    if (!std::filesystem::is_directory(parent))
        throw InputError(flag, "cannot write \"" + path + "\": the folder " + parent.string() +
                                   " does not exist");
}

} // namespace

Scene sceneFromOptions(const std::string& name, int objects, const std::string& mode, int threads,
                       long long seed) {
    Scene scene = loadScene(name);
    if (objects != 0) {
        if (objects < 1 || objects > 100000)
            throw InputError("--objects", "value " + std::to_string(objects) +
                                              " is out of range (expected 1..100000)");
        setObjectCount(scene, objects);
    }
    if (!mode.empty() && !parseCollisionMode(mode, scene.world.mode))
        throw InputError("--mode", "unknown mode \"" + mode +
                                       "\" (expected enhanced, previous, brute or none)");
    if (threads >= 0) {
        if (threads > 1024)
            throw InputError("--threads", "value " + std::to_string(threads) +
                                              " is out of range (expected 0 (all cores)..1024)");
        scene.world.threads = threads;
    }
    if (seed >= 0) {
        if (seed > 2147483647)
            throw InputError("--seed", "value " + std::to_string(seed) +
                                           " is out of range (expected 0..2147483647)");
        scene.layout.seed = uint32_t(seed);
    }
    return scene;
}

namespace {

int run(const RunCommandOptions& o) {
    if (o.frames < 1 || o.frames > 10000000)
        throw InputError("--frames", "value " + std::to_string(o.frames) +
                                         " is out of range (expected 1..10000000)");
    if (o.warmup < 0) throw InputError("--warmup", "must be >= 0, got " + std::to_string(o.warmup));
    checkOutputPath("--stats", o.stats);
    checkOutputPath("--export-obj", o.exportObj);
    const Scene scene = sceneFromOptions(o.scene, o.objects, o.mode, o.threads, o.seed);

    RunOptions ro;
    ro.frames = o.frames;
    ro.warmup = o.warmup;
    if (!o.quiet) ro.progress = progressBar(scene.name);
    const RunResult r = runScene(scene, ro, [&](const SceneBuild& build) {
        if (!o.exportObj.empty()) exportObj(build, o.exportObj);
    });
    if (!o.stats.empty()) writeTextFile(o.stats, statsJson(r).dump(2) + "\n");
    if (o.quiet) return r.finite ? 0 : 1;

    fmt::print("scene {} ({} objects, {} mode, {} thread{}, seed {})\n", r.scene, r.objects, r.mode,
               r.threads, r.threads == 1 ? "" : "s", r.seed);
    fmt::print("  mesh        {} vertices, {} triangles in all ({:.0f} and {:.0f} per object)\n",
               r.vertices, r.triangles, double(r.vertices) / r.objects,
               double(r.triangles) / r.objects);
    fmt::print("  lattice     {} cells ({:.1f} per object), {} particles, {} box nodes, built in "
               "{:.0f} ms\n",
               r.cells, double(r.cells) / r.objects, r.particles, r.nodes, r.buildMs);
    fmt::print("  run         {} frames ({:.2f} s simulated) after {} warm-up, {:.2f} s wall\n",
               r.frames, r.frames * scene.world.frameStep, r.warmup, r.wallSeconds);
    fmt::print("  {:<18} {:>10} {:>10}\n", "stage (ms/frame)", "mean", "median");
    for (int s = 0; s < kStageCount; ++s)
        fmt::print("  {:<18} {:>10.3f} {:>10.3f}\n", kStageNames[s], r.meanMs[s], r.medianMs[s]);
    fmt::print("  frames per second  {:.1f}\n", r.framesPerSecond());
    fmt::print("  per frame (mean)   {:.1f} candidate object pairs, {:.0f} node/box pairs tested, "
               "{:.1f} object contacts, {:.1f} floor contacts\n",
               r.candidatePairs, r.potentialPairs, r.contacts, r.floorContacts);
    fmt::print("  max penetration    {:.4f} m (after the response)\n", r.maxPenetration);
    fmt::print("  state hash         {:016x}   finite: {}\n", r.stateHash, r.finite ? "yes" : "NO");
    if (!o.stats.empty()) fmt::print("  stats written to   {}\n", o.stats);
    if (!o.exportObj.empty()) fmt::print("  meshes written to  {}\n", o.exportObj);
    return r.finite ? 0 : 1;
}

} // namespace

void addRunCommand(CLI::App& app, Action& action) {
    auto o = std::make_shared<RunCommandOptions>();
    CLI::App* cmd =
        app.add_subcommand("run", "Run a scene for N frames and report timings and stats");
    cmd->add_option("--scene", o->scene,
                    "Scene name (alphabets, spheres, teapots, buddhas) or a .json file")
        ->required();
    cmd->add_option("--objects", o->objects, "Total number of objects (default: the scene's)");
    cmd->add_option("--frames", o->frames, "Frames to simulate and time (default 300)");
    cmd->add_option("--warmup", o->warmup, "Frames to simulate before timing starts (default 0)");
    cmd->add_option("--mode", o->mode, "Collision mode: enhanced, previous, brute or none");
    cmd->add_option("--threads", o->threads,
                    "Worker threads (0 = all cores; default: the scene's)");
    cmd->add_option("--seed", o->seed, "Layout seed (default: the scene's)");
    cmd->add_option("--stats", o->stats, "Write the run's statistics as JSON to this file");
    cmd->add_option("--export-obj", o->exportObj,
                    "Write the final deformed meshes to this OBJ file");
    cmd->add_flag("--quiet", o->quiet, "No progress bar and no summary");
    cmd->callback([o, &action] { action = [o] { return run(*o); }; });
}

} // namespace ffd::cli
