// Running a scene for N frames and collecting what the stats, the summary and the benchmark
// tables report. Shared by `ffdaabb run`, `ffdaabb bench` and `ffdaabb soak`, and by the
// Python module's `run` (python/), which gives the same statistics.
#pragma once

#include "ffdaabb/lattice.h"
#include "ffdaabb/scene.h"
#include "interpenetration.h"

#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace ffd::cli {

/// A frame's timings, ms: every stage (ffd::stageTable's order), then every column of the
/// paper's Table 1 (ffd::tableColumns'), then the whole frame.
inline constexpr int kTimingCount = int(kStageCount + kTableColumnCount) + 1;
using Timings = std::array<double, kTimingCount>;
constexpr int timingOf(Stage stage) {
    return int(stage);
}
constexpr int timingOf(TableColumn column) {
    return int(kStageCount) + int(column);
}
inline constexpr int kTotalTiming = kTimingCount - 1;

Timings timings(const Profile& profile);

/// The `stage_ms` (every stage and the total) and `table1_ms` (every Table 1 column and the
/// total) objects of the JSON the commands write, from one summary (means or medians).
nlohmann::json stagesJson(const double (&ms)[kTimingCount]);
nlohmann::json tableColumnsJson(const double (&ms)[kTimingCount]);

/// What run/bench/soak/render/view and the Python module's World.from_scene and run may change
/// in a scene; each empty one keeps the scene's.
struct SceneOverrides {
    std::optional<int> objects;      ///< the total object count (setObjectCount), 1..100000
    std::optional<std::string> mode; ///< enhanced, previous, brute or none
    std::optional<int> threads;      ///< WorldSettings::threads
    std::optional<long long> seed;   ///< the layout's seed, 0..2147483647
};
/// How errors name each override: the command line's flags, or the Python arguments.
struct SceneOverrideNames {
    const char* objects = "--objects";
    const char* mode = "--mode";
    const char* threads = "--threads";
    const char* seed = "--seed";
};
/// The scene `name` (loadScene) with the overrides applied. Throws InputError naming the
/// override for a bad value.
Scene sceneFromOptions(const std::string& name, const SceneOverrides& overrides,
                       const SceneOverrideNames& names = {});

struct RunOptions {
    int frames = 300;
    int warmup = 0;                                    ///< frames stepped before timing starts
    std::function<void(int done, int total)> progress; ///< called after each frame
    /// Called on the built scene before the first frame (to restore a saved state, say).
    std::function<void(SceneBuild&)> atStart;
    /// Measure the meshes' interpenetration (bench/common/interpenetration.h) after every
    /// measureEvery-th frame (warm-up included) and after the last; 0: never. Untimed.
    int measureEvery = 0;
};

/// The profile's counts (Profile), summed over the timed frames by add and turned into means
/// over them by average: the one summary behind `run`'s and `bench`'s counts. Each frame
/// contributes its last substep's counts; maxContactDepth keeps the deepest instead.
struct ProfileCounts {
    double candidatePairs = 0, potentialPairs = 0, boxPairs = 0, contactBoxPairs = 0, contacts = 0,
           floorContacts = 0, sleepingBodies = 0;
    double maxContactDepth = 0; ///< the pipeline's deepest contact violation over the frames
    int frames = 0;             ///< frames added
    void add(const Profile& p);
    /// The sums divided by the frames added (left as they are when none were).
    void average();
    /// Adds the counts to `j` under the --stats and summary.json names.
    void toJson(nlohmann::json& j) const;
};

struct RunResult {
    std::string scene, mode;
    int objects = 0, frames = 0, warmup = 0, threads = 1;
    uint64_t startFrame = 0; ///< the world's frame before the first (a restored state's)
    uint32_t seed = 0;
    size_t vertices = 0, triangles = 0, cells = 0, particles = 0, nodes = 0;
    double buildMs = 0, wallSeconds = 0;
    std::vector<Timings> frameMs; ///< per timed frame
    double meanMs[kTimingCount] = {}, medianMs[kTimingCount] = {};
    /// Means over the timed frames of each frame's last substep's counts, sleeping bodies
    /// (WorldSettings::sleepSpeed) included, and the deepest contact violation.
    ProfileCounts counts;
    int sleepingAtEnd = 0; ///< after the last frame
    /// The meshes' interpenetration: the worst over the samples (keepWorst), its deepest vertex
    /// relative to the largest object's size (referenceSize), and the frame of that deepest.
    int measureEvery = 0, measureSamples = 0, deepestFrame = 0;
    double referenceSize = 1;
    bench::Interpenetration interpenetration;
    uint64_t stateHash = 0;
    bool finite = true;
    double framesPerSecond() const {
        return meanMs[kTotalTiming] > 0 ? 1000.0 / meanMs[kTotalTiming] : 0;
    }
};

/// The mean and the true median (bench/common/sample_stats.h) of each timing over the frames:
/// the one summary behind every `stage_ms`, `table1_ms` and their medians the commands write.
void summariseStages(const std::vector<Timings>& frameMs, double (&mean)[kTimingCount],
                     double (&median)[kTimingCount]);

/// Builds the scene and steps it; `build` receives the built scene (to export meshes etc.).
RunResult runScene(const Scene& scene, const RunOptions& options,
                   const std::function<void(const SceneBuild&)>& atEnd = {});

/// The `interpenetration` object of the --stats JSON: the worst of the mesh-level samples.
nlohmann::json interpenetrationJson(const RunResult& r);

/// A mesh's box standoff (measureBoxStandoff), summarised with the one median and quantile
/// (bench/common/sample_stats.h): mesh-info's and the Python module's figures.
struct StandoffSummary {
    int directions = 0;
    double median = 0, p90 = 0, max = 0; ///< over the directions; p90: the 0.9-quantile
    Vec3 worstDirection;                 ///< the direction of `max`
};
StandoffSummary summariseStandoff(const BoxStandoff& standoff);

/// Its `box_standoff` JSON object: directions, median, p90, max.
nlohmann::json standoffJson(const StandoffSummary& s);

/// The --stats JSON object (every key of DESIGN.md's contract, and more).
nlohmann::json statsJson(const RunResult& r);

/// Writes text to a file through a temporary name (nothing half-written is left behind).
void writeTextFile(const std::string& path, const std::string& text);

/// A progress bar on stderr when it is a terminal; nothing otherwise.
std::function<void(int, int)> progressBar(const std::string& label);

/// Writes every body's final deformed mesh into one OBJ, one `o body_<i>` group per body.
void exportObj(const SceneBuild& build, const std::string& path);

/// The OBJ text of exportObj, to an open file.
void writeObj(const SceneBuild& build, std::FILE* file);

} // namespace ffd::cli
