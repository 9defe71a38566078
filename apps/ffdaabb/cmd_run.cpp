// ffdaabb run: one scene for N frames, with stats, mesh export, a progress bar and a summary.
#include "commands.h"
#include "flags.h"
#include "runner.h"

#include "ffdaabb/error.h"
#include "util/atomic_file.h"

#include <fmt/core.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>
#include <vector>

namespace ffd::cli {

namespace {

struct RunCommandOptions {
    SceneFlags scene;
    std::string frames = "300", warmup = "0", measureEvery = "10";
    std::string stats, exportObj, saveState, loadState;
    bool quiet = false;
};

// The bytes of the --load-state file.
std::vector<uint8_t> readStateFile(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        throw InputError("--load-state", "cannot read \"" + path + "\": it is a folder");
    std::FILE* file = std::fopen(path.c_str(), "rb");
    if (!file)
        throw InputError("--load-state",
                         "cannot read \"" + path + "\": " + std::string(std::strerror(errno)));
    std::vector<uint8_t> bytes;
    uint8_t buffer[1 << 16];
    size_t n;
    while ((n = std::fread(buffer, 1, sizeof buffer, file)) > 0)
        bytes.insert(bytes.end(), buffer, buffer + n);
    const bool failed = std::ferror(file) != 0;
    std::fclose(file);
    if (failed) throw InputError("--load-state", "cannot read \"" + path + "\": read error");
    return bytes;
}

int run(const RunCommandOptions& o) {
    const int frames = int(parseInteger("--frames", o.frames, 1, 10000000));
    const int warmup = int(parseInteger("--warmup", o.warmup, 0, 10000000));
    const int measureEvery = int(parseInteger("--measure-every", o.measureEvery, 0, 10000000));
    checkOutputPath("--stats", o.stats);
    checkOutputPath("--export-obj", o.exportObj);
    checkOutputPath("--save-state", o.saveState);
    checkDistinctOutputs("--stats", o.stats, "--export-obj", o.exportObj);
    checkDistinctOutputs("--stats", o.stats, "--save-state", o.saveState);
    checkDistinctOutputs("--export-obj", o.exportObj, "--save-state", o.saveState);
    const Scene scene = sceneFromFlags(o.scene);
    const std::vector<uint8_t> loaded =
        o.loadState.empty() ? std::vector<uint8_t>{} : readStateFile(o.loadState);

    RunOptions ro;
    ro.frames = frames;
    ro.warmup = warmup;
    ro.measureEvery = measureEvery;
    if (!o.quiet) ro.progress = progressBar(scene.name);
    if (!o.loadState.empty())
        ro.atStart = [&](SceneBuild& build) {
            try {
                build.world.restoreState(loaded);
            } catch (const InputError& e) {
                throw InputError("--load-state",
                                 "cannot restore \"" + o.loadState + "\": " + e.problem());
            }
        };
    // The outputs go to temporary files that are renamed into place together at the end: a
    // run that fails, or an output that cannot be written, leaves none of them behind.
    std::optional<AtomicFile> objFile, statsFile, stateFile;
    const RunResult r = runScene(scene, ro, [&](const SceneBuild& build) {
        if (!o.exportObj.empty()) {
            objFile.emplace(o.exportObj);
            writeObj(build, objFile->handle());
        }
        if (!o.saveState.empty()) {
            stateFile.emplace(o.saveState);
            const std::vector<uint8_t> bytes = build.world.saveState();
            std::fwrite(bytes.data(), 1, bytes.size(), stateFile->handle());
        }
    });
    if (!o.stats.empty()) {
        statsFile.emplace(o.stats);
        const std::string text = statsJson(r).dump(2) + "\n";
        std::fwrite(text.data(), 1, text.size(), statsFile->handle());
    }
    std::vector<const std::filesystem::path*> committed;
    for (std::optional<AtomicFile>* file : {&objFile, &statsFile, &stateFile}) {
        if (!*file) continue;
        try {
            (*file)->commit();
        } catch (const InputError&) {
            std::error_code ec;
            for (const std::filesystem::path* path : committed) std::filesystem::remove(*path, ec);
            throw;
        }
        committed.push_back(&(*file)->path());
    }
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
    if (!o.loadState.empty())
        fmt::print("  state       restored frame {} from {}\n", r.startFrame, o.loadState);
    fmt::print("  {:<22} {:>10} {:>10}\n", "stage (ms/frame)", "mean", "median");
    for (const StageInfo& s : stageTable())
        fmt::print("  {:<22} {:>10.3f} {:>10.3f}\n", s.key, r.meanMs[timingOf(s.stage)],
                   r.medianMs[timingOf(s.stage)]);
    fmt::print("  {:<22} {:>10.3f} {:>10.3f}\n", "total", r.meanMs[kTotalTiming],
               r.medianMs[kTotalTiming]);
    fmt::print("  frames per second  {:.1f}\n", r.framesPerSecond());
    fmt::print("  a substep (mean)   {:.1f} candidate object pairs, {:.0f} node/box pairs tested, "
               "{:.0f} box pairs tested ({:.0f} with contacts), {:.1f} object contacts, {:.1f} "
               "floor contacts (each frame's last substep)\n",
               r.counts.candidatePairs, r.counts.potentialPairs, r.counts.boxPairs,
               r.counts.contactBoxPairs, r.counts.contacts, r.counts.floorContacts);
    fmt::print("  sleeping           {:.1f} bodies asleep per frame (mean), {} of {} at the end\n",
               r.counts.sleepingBodies, r.sleepingAtEnd, r.objects);
    if (r.measureSamples > 0) {
        const bench::Interpenetration& p = r.interpenetration;
        const std::string which =
            p.deepestBody < 0 ? std::string()
                              : fmt::format(" (vertex {} of object {} inside object {})",
                                            p.deepestVertex, p.deepestBody, p.deepestInside);
        fmt::print(
            "  interpenetration   deepest vertex {:.4f} m inside another object ({:.2f} % of "
            "the largest size) at frame {}{}; at most {} vertices inside, {} deeper than "
            "1 % ({} samples, every {} frames)\n",
            p.maxDepth, 100 * p.maxDepthRelative, r.deepestFrame, which, p.insideVertices,
            p.deepVertices, r.measureSamples, r.measureEvery);
    }
    fmt::print("  deepest contact    {:.4f} m (the pipeline's node in a box, after the response)\n",
               r.counts.maxContactDepth);
    fmt::print("  state hash         {:016x}   finite: {}\n", r.stateHash, r.finite ? "yes" : "NO");
    if (!o.stats.empty()) fmt::print("  stats written to   {}\n", o.stats);
    if (!o.exportObj.empty()) fmt::print("  meshes written to  {}\n", o.exportObj);
    if (!o.saveState.empty())
        fmt::print("  state written to   {} (frame {})\n", o.saveState,
                   r.startFrame + uint64_t(r.warmup + r.frames));
    return r.finite ? 0 : 1;
}

} // namespace

void addRunCommand(CLI::App& app, Action& action) {
    auto o = std::make_shared<RunCommandOptions>();
    CLI::App* cmd =
        app.add_subcommand("run", "Run a scene for N frames and report timings and stats");
    addSceneFlags(cmd, o->scene);
    cmd->add_option("--frames", o->frames,
                    "Frames to simulate and time, 1..10000000 (default 300)");
    cmd->add_option("--warmup", o->warmup,
                    "Frames to simulate before timing starts, 0..10000000 (default 0)");
    cmd->add_option("--measure-every", o->measureEvery,
                    "Measure the meshes' interpenetration (vertices inside other objects, by "
                    "winding number) every N frames and after the last, 0..10000000 (default "
                    "10; 0: never)");
    cmd->add_option("--stats", o->stats, "Write the run's statistics as JSON to this file");
    cmd->add_option("--export-obj", o->exportObj,
                    "Write the final deformed meshes to this OBJ file");
    cmd->add_option("--save-state", o->saveState,
                    "Write the world's whole state after the last frame to this file (restored "
                    "by --load-state with the same scene flags, on this build)");
    cmd->add_option("--load-state", o->loadState,
                    "Restore the state in this file (from --save-state, same scene flags, "
                    "--threads aside) before the first frame: the run goes on from its frame");
    cmd->add_flag("--quiet", o->quiet, "No progress bar and no summary");
    cmd->callback([o, &action] { action = [o] { return run(*o); }; });
}

} // namespace ffd::cli
