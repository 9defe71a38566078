// ffdaabb bench: the paper's experiment. Each scene runs in `previous` and `enhanced` mode side
// by side (the two worlds are stepped in lockstep, alternating which goes first, so both see the
// same machine conditions frame by frame), and the results are written as the paper's Table 1,
// Table 2 and Fig. 4, beside the paper's own figures. The two pipelines find the same contacts,
// so their trajectories must be bit-identical: bench fails (exit 1, naming the scene and the two
// state hashes) when they are not. `--modes A,B` compares two other pipelines the same way, and
// `--threads A,B` one pipeline (enhanced unless --modes names two) on A and on B threads: any
// thread count must step the same trajectory.
#include "commands.h"
#include "flags.h"
#include "runner.h"

#include "ffdaabb/error.h"
#include "ffdaabb/generators.h"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace ffd::cli {

namespace {

// The paper's Table 1 (ms, previous FFD-AABB method) and its Table 2.
struct PaperRow {
    const char* scene;
    const char* label;
    int objects;
    double mesh, minmax, distance, floor, objects_ms, total;
    PaperObjectFigures figures;
};
constexpr PaperRow kPaper[] = {
    {"alphabets", "Alphabets", 165, 265.63, 0.16, 1.03, 1.42, 1061.39, 1329.64, kPaperLetter},
    {"spheres", "Spheres", 100, 115.19, 0.10, 0.47, 1.25, 216.96, 334.28, kPaperSphere},
    {"teapots", "Teapots", 80, 335.45, 0.27, 1.02, 0.40, 234.13, 571.29, kPaperTeapot},
    {"buddhas", "Buddhas", 30, 534.02, 0.10, 0.22, 1.40, 371.19, 906.94, kPaperBuddha},
};
// The paper reports "about 80-85 %" more frames per second with the enhanced method (Fig. 4).
constexpr double kPaperRatio = 1.8;

// The command line as given: numbers as text, converted and checked by run().
struct BenchFlags {
    std::string out = "bench-out";
    std::string frames = "300", warmup = "60", objects;
    CLI::Option* objectsOption = nullptr;
    std::vector<std::string> scenes{"alphabets", "spheres", "teapots", "buddhas"};
    std::vector<std::string> modes{"previous", "enhanced"};
    CLI::Option* modesOption = nullptr;
    std::vector<std::string> threads{"1", "1"};
    bool quiet = false;
};

struct BenchOptions {
    std::string out;
    int frames = 300;
    int warmup = 60;
    std::vector<std::string> scenes;
    std::array<CollisionMode, 2> modes{CollisionMode::Previous, CollisionMode::Enhanced};
    std::array<int, 2> threads{1, 1};
    int objects = 0; // 0: the paper's counts
    bool quiet = false;
};

// Checks that a two-sided flag (--modes, --threads) names two values, one per side:
// InputError naming the flag, the values and what was expected otherwise.
void requireTwo(const char* flag, const std::vector<std::string>& given, const char* noun,
                const char* example) {
    if (given.size() == 2) return;
    std::string list;
    for (const std::string& v : given) list += (list.empty() ? "" : ",") + v;
    throw InputError(flag, fmt::format("\"{}\" names {} {}{} (expected two, e.g. {})", list,
                                       given.size(), noun, given.size() == 1 ? "" : "s", example));
}

// The two pipelines of --modes, checked: InputError naming the flag and the value otherwise.
std::array<CollisionMode, 2> parseModes(const std::vector<std::string>& given) {
    requireTwo("--modes", given, "mode", "previous,enhanced");
    std::array<CollisionMode, 2> modes{};
    for (size_t i = 0; i < 2; ++i)
        if (!parseCollisionMode(given[i], modes[i]))
            throw InputError("--modes", "unknown mode \"" + given[i] +
                                            "\" (expected two of enhanced, previous, brute, none)");
    return modes;
}

// The two thread counts of --threads, checked as --modes is.
std::array<int, 2> parseThreads(const std::vector<std::string>& given) {
    requireTwo("--threads", given, "thread count", "1,2");
    return {int(parseInteger("--threads", given[0], 1, 1024)),
            int(parseInteger("--threads", given[1], 1, 1024))};
}

// A side's label: its mode, with its thread count when the sides differ in threads.
std::string sideLabel(CollisionMode mode, int threads, bool byThreads) {
    return byThreads ? fmt::format("{}_{}t", toString(mode), threads) : toString(mode);
}

struct ModeResult {
    std::string mode; ///< the side's label: its mode, "_Nt" with N threads when those differ
    int threads = 1;
    std::vector<Timings> frameMs;
    double mean[kTimingCount] = {}, median[kTimingCount] = {};
    ProfileCounts counts; ///< means over the timed frames (runner.h)
    uint64_t hash = 0;
    bool finite = true;
    double fps() const { return mean[kTotalTiming] > 0 ? 1000.0 / mean[kTotalTiming] : 0; }
    double column(TableColumn c) const { return mean[timingOf(c)]; }
};

struct SceneResult {
    std::string name;
    int objects = 0;
    double verticesPerObject = 0, trianglesPerObject = 0, cellsPerObject = 0;
    size_t vertices = 0, triangles = 0, cells = 0;
    std::array<ModeResult, 2> modes; ///< in --modes order (default previous, enhanced)
    const PaperRow* paper = nullptr;
    bool identical() const { return modes[0].hash == modes[1].hash; }
    /// Frame rate of the second mode over the first's (enhanced / previous by default).
    double fpsRatio() const { return modes[1].fps() / modes[0].fps(); }
    /// Object collision time of the first mode over the second's.
    double collisionRatio() const {
        const TableColumn column = TableColumn::ObjectsCollision;
        return modes[0].column(column) / std::max(1e-9, modes[1].column(column));
    }
};

void summarise(ModeResult& m) {
    summariseStages(m.frameMs, m.mean, m.median);
    m.counts.average();
}

void record(ModeResult& m, const World& w) {
    const Profile& p = w.profile();
    m.frameMs.push_back(timings(p));
    m.counts.add(p);
}

SceneResult benchScene(const std::string& name, const BenchOptions& o, int index, int count) {
    SceneOverrides overrides;
    if (o.objects != 0) overrides.objects = o.objects;
    overrides.threads = 1;
    Scene scene = sceneFromOptions(name, overrides);
    SceneResult r;
    r.name = scene.name;
    r.objects = scene.objectCount();
    for (const PaperRow& p : kPaper)
        if (scene.name == p.scene) r.paper = &p;
    Scene first = scene, second = scene;
    first.world.mode = o.modes[0];
    second.world.mode = o.modes[1];
    first.world.threads = o.threads[0];
    second.world.threads = o.threads[1];
    const bool byThreads = o.threads[0] != o.threads[1];
    for (int i = 0; i < 2; ++i) {
        r.modes[size_t(i)].mode = sideLabel(o.modes[size_t(i)], o.threads[size_t(i)], byThreads);
        r.modes[size_t(i)].threads = o.threads[size_t(i)];
    }
    SceneBuild a = buildScene(first), b = buildScene(second);
    r.vertices = a.vertices, r.triangles = a.triangles, r.cells = a.cells;
    r.verticesPerObject = double(a.vertices) / r.objects;
    r.trianglesPerObject = double(a.triangles) / r.objects;
    r.cellsPerObject = double(a.cells) / r.objects;
    auto progress = o.quiet ? std::function<void(int, int)>{}
                            : progressBar(fmt::format("[{}/{}] {:<10}", index + 1, count, r.name));
    const int total = o.warmup + o.frames;
    for (int f = 0; f < total; ++f) {
        // Alternate the order so that neither mode always runs on a warmer cache.
        if (f % 2 == 0)
            a.world.step(), b.world.step();
        else
            b.world.step(), a.world.step();
        if (f >= o.warmup) record(r.modes[0], a.world), record(r.modes[1], b.world);
        if (progress) progress(f + 1, total);
    }
    for (int i = 0; i < 2; ++i) {
        const SceneBuild& s = i == 0 ? a : b;
        ModeResult& m = r.modes[size_t(i)];
        summarise(m);
        m.hash = s.world.stateHash();
        for (BodyId id : s.bodies)
            for (const Vec3& p : s.world.particles(id)) m.finite &= isFinite(p);
    }
    return r;
}

std::string hashText(uint64_t hash) {
    return fmt::format("{:016x}", hash);
}

// The table's column heading for a side: "prev" and "enh" as before, the others in full, with
// the thread count when the sides differ in it.
std::string shortName(CollisionMode mode, int threads, bool byThreads) {
    const std::string name = mode == CollisionMode::Previous   ? "prev"
                             : mode == CollisionMode::Enhanced ? "enh"
                                                               : toString(mode);
    return byThreads ? fmt::format("{} {}t", name, threads) : name;
}

std::string machineDescription() {
    std::ifstream in("/proc/cpuinfo");
    std::string line, model = "unknown CPU";
    while (std::getline(in, line))
        if (line.rfind("model name", 0) == 0) {
            model = line.substr(line.find(':') + 2);
            break;
        }
    return fmt::format("{}, {} hardware threads", model, std::thread::hardware_concurrency());
}

std::string utcNow() {
    const std::time_t t = std::time(nullptr);
    char buf[64];
    std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M UTC", std::gmtime(&t));
    return buf;
}

// Fig. 4 as a bar chart, drawn by Debian's python3 with matplotlib (the script is embedded so
// the installed binary needs no other file).
constexpr const char* kPlotScript = R"PY(
import csv, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
reader = csv.DictReader(open(sys.argv[1]))
rows = list(reader)
modes = [k[len("fps_"):] for k in reader.fieldnames if k.startswith("fps_")]
labels = {"previous": "previous (FFD-AABB, 2011)", "enhanced": "enhanced (bounding spheres, 2012)"}
names = [r["scene"] for r in rows]
prev = [float(r["fps_" + modes[0]]) for r in rows]
enh = [float(r["fps_" + modes[1]]) for r in rows]
x = range(len(rows))
fig, ax = plt.subplots(figsize=(7, 4), dpi=120)
w = 0.38
b1 = ax.bar([i - w / 2 for i in x], prev, w, label=labels.get(modes[0], modes[0]), color="#7f8c99")
b2 = ax.bar([i + w / 2 for i in x], enh, w, label=labels.get(modes[1], modes[1]), color="#e07b39")
for bars in (b1, b2):
    for b in bars:
        ax.annotate(f"{b.get_height():.0f}", (b.get_x() + b.get_width() / 2, b.get_height()),
                    ha="center", va="bottom", fontsize=8)
for i, r in enumerate(rows):
    ax.annotate(f"x{float(r['ratio']):.2f}", (i, max(prev[i], enh[i]) * 1.08), ha="center", fontsize=9)
ax.set_xticks(list(x))
ax.set_xticklabels([n.capitalize() for n in names])
ax.set_ylabel("frames per second")
if modes == ["previous", "enhanced"]:
    ax.set_title("Fig. 4 reproduced: previous vs enhanced FFD-AABB")
else:
    ax.set_title(f"{modes[0]} vs {modes[1]}")
ax.set_ylim(0, max(prev + enh) * 1.25)
ax.legend(loc="upper right", fontsize=8)
fig.tight_layout()
fig.savefig(sys.argv[2] + ".tmp.png")
)PY";

bool plotFig4(const std::filesystem::path& csv, const std::filesystem::path& png,
              std::string& why) {
    const char* python =
        std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
    const std::filesystem::path script = png.parent_path() / ".fig4_plot.py";
    writeTextFile(script.string(), kPlotScript);
    const pid_t pid = ::fork();
    if (pid == 0) {
        const int devnull = ::open("/dev/null", O_WRONLY);
        if (devnull >= 0) ::dup2(devnull, 1);
        ::execlp(python, python, script.c_str(), csv.c_str(), png.c_str(),
                 static_cast<char*>(nullptr));
        std::_Exit(127);
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    std::filesystem::remove(script);
    const std::filesystem::path tmp = png.string() + ".tmp.png";
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || !std::filesystem::exists(tmp)) {
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
        why = fmt::format("{} with matplotlib failed (exit {}); run scripts/setup.sh", python,
                          WIFEXITED(status) ? WEXITSTATUS(status) : -1);
        return false;
    }
    std::filesystem::rename(tmp, png);
    return true;
}

// The paper's figure in a Table 1 column (NaN where the paper has none: dynamics).
double paperColumn(const PaperRow& p, TableColumn c) {
    switch (c) {
    case TableColumn::MeshUpdating:
        return p.mesh;
    case TableColumn::MinMaxUpdating:
        return p.minmax;
    case TableColumn::DistanceCalculating:
        return p.distance;
    case TableColumn::Floor:
        return p.floor;
    case TableColumn::ObjectsCollision:
        return p.objects_ms;
    case TableColumn::Dynamics:
        break;
    }
    return std::nan("");
}

// What each Table 1 column sums, from the stage table: "`a` + `b`".
std::string columnStages(TableColumn c) {
    std::string keys;
    for (const StageInfo& s : stageTable())
        if (s.column == c) keys += fmt::format("{}`{}`", keys.empty() ? "" : " + ", s.key);
    return keys;
}

std::string table1(const std::vector<SceneResult>& rs, const BenchOptions& o) {
    std::ostringstream md;
    md << "# Table 1: time per frame by stage (ms)\n\n";
    md << fmt::format("Mean over {} frames after {} warm-up; `{}` on {} thread{} and `{}` on {} "
                      "thread{} stepped side by side. The paper's figures (Core i5 3.3 GHz, "
                      "previous method, one thread) are beside ours.\n\n",
                      o.frames, o.warmup, toString(o.modes[0]), o.threads[0],
                      o.threads[0] == 1 ? "" : "s", toString(o.modes[1]), o.threads[1],
                      o.threads[1] == 1 ? "" : "s");
    md << "| scene | objects | source |";
    for (const TableColumnInfo& c : tableColumns()) md << " " << c.heading << " |";
    md << " total | fps |\n|---|---|---|";
    for (size_t c = 0; c < kTableColumnCount; ++c) md << "---|";
    md << "---|---|\n";
    for (const SceneResult& r : rs) {
        if (r.paper) {
            md << fmt::format("| {} | {} | paper (previous) |", r.paper->label, r.paper->objects);
            for (const TableColumnInfo& c : tableColumns()) {
                const double ms = paperColumn(*r.paper, c.column);
                md << (std::isnan(ms) ? std::string(" – |") : fmt::format(" {:.2f} |", ms));
            }
            md << fmt::format(" {:.2f} | {:.2f} |\n", r.paper->total, 1000.0 / r.paper->total);
        }
        for (const ModeResult& m : r.modes) {
            md << fmt::format("| {} | {} | ours, {} |", r.name, r.objects, m.mode);
            for (const TableColumnInfo& c : tableColumns())
                md << fmt::format(" {:.3f} |", m.column(c.column));
            md << fmt::format(" {:.3f} | {:.1f} |\n", m.mean[kTotalTiming], m.fps());
        }
    }
    md << "\nColumns, each the sum of the step's stages (ffdaabb/profile.h):";
    for (const TableColumnInfo& c : tableColumns())
        md << fmt::format(" {} = {}{};", c.heading, columnStages(c.column),
                          c.column == TableColumn::DistanceCalculating
                              ? " (0 in `previous`, which has no phase 1)"
                          : c.column == TableColumn::Dynamics ? " (not in the paper's table)"
                                                              : "");
    md.seekp(-1, std::ios_base::cur);
    md << ".\n";
    return md.str();
}

std::string table1Csv(const std::vector<SceneResult>& rs) {
    std::ostringstream csv;
    csv << "scene,objects,mode";
    for (const TableColumnInfo& c : tableColumns()) csv << "," << c.key;
    csv << ",total,total_median,fps\n";
    for (const SceneResult& r : rs) {
        if (r.paper) {
            csv << fmt::format("{},{},paper_previous", r.name, r.paper->objects);
            for (const TableColumnInfo& c : tableColumns()) {
                const double ms = paperColumn(*r.paper, c.column);
                csv << (std::isnan(ms) ? std::string(",") : fmt::format(",{}", ms));
            }
            csv << fmt::format(",{},,{:.3f}\n", r.paper->total, 1000.0 / r.paper->total);
        }
        for (const ModeResult& m : r.modes) {
            csv << fmt::format("{},{},{}", r.name, r.objects, m.mode);
            for (const TableColumnInfo& c : tableColumns())
                csv << fmt::format(",{:.4f}", m.column(c.column));
            csv << fmt::format(",{:.4f},{:.4f},{:.2f}\n", m.mean[kTotalTiming],
                               m.median[kTotalTiming], m.fps());
        }
    }
    return csv.str();
}

std::string table2(const std::vector<SceneResult>& rs) {
    std::ostringstream md;
    md << "# Table 2: the objects\n\n";
    md << "| object | vertices (paper) | vertices (ours) | triangles (paper) | triangles (ours) | "
          "FFD cells (paper) | FFD cells (ours) |\n|---|---|---|---|---|---|---|\n";
    for (const SceneResult& r : rs) {
        if (!r.paper) continue;
        const PaperObjectFigures& p = r.paper->figures;
        md << fmt::format("| {} | {} | {:.0f} | {} | {:.0f} | {} | {:.1f} |\n", p.name, p.vertices,
                          r.verticesPerObject, p.triangles, r.trianglesPerObject, p.cells,
                          r.cellsPerObject);
    }
    md << "\nLetters: averages over the scene's letters (A-Z cycled). Buddha: the Stanford dragon "
          "simplified to the Buddha's triangle count (the Buddha is not obtainable here).\n";
    return md.str();
}

int run(const BenchFlags& flags) {
    BenchOptions o;
    o.frames = int(parseInteger("--frames", flags.frames, 1, 1000000));
    o.warmup = int(parseInteger("--warmup", flags.warmup, 0, 10000000));
    o.objects =
        given(flags.objectsOption) ? int(parseInteger("--objects", flags.objects, 1, 100000)) : 0;
    o.modes = parseModes(flags.modes);
    o.threads = parseThreads(flags.threads);
    const bool byThreads = o.threads[0] != o.threads[1];
    if (byThreads && !given(flags.modesOption))
        o.modes = {CollisionMode::Enhanced, CollisionMode::Enhanced};
    if (o.modes[0] == o.modes[1] && !byThreads) {
        const std::string list = toString(o.modes[0]) + std::string(",") + toString(o.modes[1]);
        throw InputError("--modes", "\"" + list +
                                        "\" names the same mode twice (expected two different "
                                        "modes, or two thread counts with --threads)");
    }
    o.out = flags.out;
    o.scenes = flags.scenes;
    o.quiet = flags.quiet;
    namespace fs = std::filesystem;
    const fs::path out(o.out);
    if (fs::exists(out) && !fs::is_directory(out))
        throw InputError("--out", "\"" + o.out + "\" exists and is not a folder");
    if (out.has_parent_path() && !fs::is_directory(out.parent_path()))
        throw InputError("--out", "the folder " + out.parent_path().string() + " does not exist");
    for (const std::string& s : o.scenes) loadScene(s); // fail early on a bad name
    fs::create_directories(out);

    std::vector<SceneResult> results;
    const auto start = std::chrono::steady_clock::now();
    for (size_t i = 0; i < o.scenes.size(); ++i)
        results.push_back(benchScene(o.scenes[i], o, int(i), int(o.scenes.size())));
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    writeTextFile((out / "table1.md").string(), table1(results, o));
    writeTextFile((out / "table1.csv").string(), table1Csv(results));
    writeTextFile((out / "table2.md").string(), table2(results));
    std::ostringstream fig4;
    fig4 << fmt::format("scene,fps_{},fps_{},ratio,paper_ratio\n",
                        results.empty() ? "" : results[0].modes[0].mode,
                        results.empty() ? "" : results[0].modes[1].mode);
    for (const SceneResult& r : results)
        fig4 << fmt::format("{},{:.2f},{:.2f},{:.3f},{}\n", r.name, r.modes[0].fps(),
                            r.modes[1].fps(), r.fpsRatio(),
                            r.paper && !byThreads ? fmt::format("{}", kPaperRatio)
                                                  : ""); // none: not the paper's comparison
    writeTextFile((out / "fig4.csv").string(), fig4.str());
    std::string why;
    const bool plotted = plotFig4(out / "fig4.csv", out / "fig4.png", why);

    nlohmann::json summary;
    summary["machine"] = machineDescription();
    summary["date"] = utcNow();
    summary["frames"] = o.frames;
    summary["warmup"] = o.warmup;
    summary["threads"] = {o.threads[0], o.threads[1]};
    summary["modes"] = {toString(o.modes[0]), toString(o.modes[1])};
    summary["seconds"] = seconds;
    summary["fig4_png"] = plotted;
    for (const SceneResult& r : results) {
        nlohmann::json j;
        j["objects"] = r.objects;
        j["vertices_per_object"] = r.verticesPerObject;
        j["triangles_per_object"] = r.trianglesPerObject;
        j["cells_per_object"] = r.cellsPerObject;
        for (const ModeResult& m : r.modes) {
            nlohmann::json mj;
            mj["stage_ms"] = stagesJson(m.mean);
            mj["stage_ms_median"] = stagesJson(m.median);
            mj["table1_ms"] = tableColumnsJson(m.mean);
            mj["table1_ms_median"] = tableColumnsJson(m.median);
            mj["frames_per_second"] = m.fps();
            mj["threads"] = m.threads;
            m.counts.toJson(mj);
            mj["state_hash"] = hashText(m.hash);
            mj["finite"] = m.finite;
            j[m.mode] = mj;
        }
        j["fps_ratio"] = r.fpsRatio();
        j["object_collision_ratio"] = r.collisionRatio();
        j["identical_trajectories"] = r.identical();
        summary["scenes"][r.name] = j;
    }
    writeTextFile((out / "summary.json").string(), summary.dump(2) + "\n");

    if (!o.quiet) {
        fmt::print("\n{:<10} {:>8} {:>12} {:>12} {:>8} {:>14} {:>10}\n", "scene", "objects",
                   "fps " + shortName(o.modes[0], o.threads[0], byThreads),
                   "fps " + shortName(o.modes[1], o.threads[1], byThreads), "ratio", "coll. ratio",
                   "same hash");
        for (const SceneResult& r : results)
            fmt::print("{:<10} {:>8} {:>12.1f} {:>12.1f} {:>8.2f} {:>14.2f} {:>10}\n", r.name,
                       r.objects, r.modes[0].fps(), r.modes[1].fps(), r.fpsRatio(),
                       r.collisionRatio(), r.identical() ? "yes" : "NO");
        fmt::print(
            "\nwritten to {}/: table1.md table1.csv table2.md fig4.csv {}summary.json ({:.0f} s)\n",
            out.string(), plotted ? "fig4.png " : "", seconds);
        if (!plotted) fmt::print(stderr, "ffdaabb: fig4.png not drawn: {}\n", why);
    }
    // The verdict, printed even with --quiet: both modes must stay finite and step the same
    // trajectory (the same contacts, in the same order, give bit-identical states).
    bool ok = true;
    for (const SceneResult& r : results) {
        for (const ModeResult& m : r.modes)
            if (!m.finite) {
                fmt::print(stderr,
                           "ffdaabb: bench: scene {}: a particle of the {} run is not "
                           "finite\n",
                           r.name, m.mode);
                ok = false;
            }
        if (!r.identical()) {
            fmt::print(stderr,
                       "ffdaabb: bench: scene {}: the trajectories differ: {} ends with state "
                       "hash {}, {} with {} after {} frames (expected identical)\n",
                       r.name, r.modes[0].mode, hashText(r.modes[0].hash), r.modes[1].mode,
                       hashText(r.modes[1].hash), o.warmup + o.frames);
            ok = false;
        }
    }
    return ok ? 0 : 1;
}

} // namespace

void addBenchCommand(CLI::App& app, Action& action) {
    auto o = std::make_shared<BenchFlags>();
    CLI::App* cmd = app.add_subcommand(
        "bench",
        "Reproduce the paper's Tables 1-2 and Fig. 4 (previous vs enhanced, side by side)");
    cmd->add_option("--out", o->out,
                    "Folder for table1.md/.csv, table2.md, fig4.csv/.png, summary.json");
    cmd->add_option("--frames", o->frames,
                    "Timed frames per scene and mode, 1..1000000 (default 300)");
    cmd->add_option("--warmup", o->warmup, "Untimed frames first, 0..10000000 (default 60)");
    cmd->add_option("--scenes", o->scenes,
                    "Scenes to run (default: alphabets spheres teapots buddhas)")
        ->delimiter(',');
    o->modesOption =
        cmd->add_option("--modes", o->modes,
                        "The two collision modes stepped side by side, from enhanced, previous, "
                        "brute, none (default: previous,enhanced); exit 1 when their trajectories "
                        "differ")
            ->delimiter(',');
    cmd->add_option("--threads", o->threads,
                    "The two sides' worker threads, 1..1024 each (default 1,1); with two "
                    "different counts the sides step one pipeline (enhanced, or --modes), and "
                    "exit 1 when their trajectories differ")
        ->delimiter(',');
    o->objectsOption = cmd->add_option(
        "--objects", o->objects, "Objects per scene, 1..100000 (default: the paper's counts)");
    cmd->add_flag("--quiet", o->quiet, "No progress and no summary");
    cmd->callback([o, &action] { action = [o] { return run(*o); }; });
}

} // namespace ffd::cli
