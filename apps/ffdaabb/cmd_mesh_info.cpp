// ffdaabb mesh-info: mesh and lattice statistics of a file or a generated object, with the
// paper's Table 2 beside ours for the paper's objects.
#include "commands.h"
#include "flags.h"
#include "runner.h"

#include "ffdaabb/error.h"
#include "ffdaabb/generators.h"
#include "ffdaabb/lattice.h"
#include "ffdaabb/mesh_io.h"

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <functional>

namespace ffd::cli {

namespace {

struct MeshInfoOptions {
    std::string file;
    std::string generate;
    std::string cellsText, cellSizeText;
    CLI::Option *cellsOption = nullptr, *cellSizeOption = nullptr;
    int cells = 0;      ///< from cellsText when given
    float cellSize = 0; ///< from cellSizeText when given
    bool json = false;
};

// A lattice setting the user gave that the lattice refuses for this mesh (a cell size too small
// for its extent) is reported against the flag, not the library's field.
Lattice buildLatticeFor(const TriangleMesh& mesh, const LatticeSettings& settings,
                        const MeshInfoOptions& o, LatticeStats* stats) {
    try {
        return buildLattice(mesh, settings, stats);
    } catch (const InputError& e) {
        if (e.source().rfind("lattice.", 0) != 0) throw;
        const std::string flag = given(o.cellSizeOption) ? "--cell-size"
                                 : given(o.cellsOption)  ? "--cells"
                                                         : e.source();
        throw InputError(flag, e.problem() + " (for " + mesh.name + ")");
    }
}

struct ObjectStats {
    std::string name;
    size_t vertices = 0, triangles = 0;
    bool closed = false;
    size_t cells = 0, surfaceCells = 0, interiorCells = 0, particles = 0, nodes = 0;
    float cellSize = 0;
    float size = 0; ///< the mesh's largest extent
    cli::StandoffSummary standoff;
    double buildMs = 0, generateMs = 0;
    CleanupReport cleanup;
};

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

ObjectStats analyse(TriangleMesh mesh, const MeshInfoOptions& o, int defaultCells,
                    double generateMs, bool clean) {
    ObjectStats s;
    s.name = mesh.name;
    s.generateMs = generateMs;
    if (clean) s.cleanup = ffd::cleanup(mesh);
    s.vertices = mesh.vertexCount();
    s.triangles = mesh.triangleCount();
    s.closed = isClosed(mesh);
    LatticeSettings ls;
    if (o.cellSize > 0)
        ls.cellSize = o.cellSize;
    else
        ls.targetCells = o.cells > 0 ? o.cells : defaultCells;
    LatticeStats stats;
    const auto t = Clock::now();
    const Lattice L = buildLatticeFor(mesh, ls, o, &stats);
    s.buildMs = msSince(t);
    s.cells = L.cellCount();
    s.surfaceCells = L.surfaceCellCount();
    s.interiorCells = size_t(stats.interiorCells);
    s.particles = L.particleCount();
    s.nodes = L.nodeCount();
    s.cellSize = L.cellSize;
    s.size = maxComponent(bounds(mesh).extent());
    s.standoff = cli::summariseStandoff(measureBoxStandoff(L, mesh));
    return s;
}

nlohmann::json toJson(const ObjectStats& s) {
    return {{"name", s.name},
            {"vertices", s.vertices},
            {"triangles", s.triangles},
            {"closed", s.closed},
            {"cells", s.cells},
            {"surface_cells", s.surfaceCells},
            {"interior_cells", s.interiorCells},
            {"particles", s.particles},
            {"nodes", s.nodes},
            {"cell_size", s.cellSize},
            {"size", s.size},
            {"box_standoff", cli::standoffJson(s.standoff)},
            {"lattice_build_ms", s.buildMs},
            {"generate_ms", s.generateMs}};
}

// The generated mesh; a bad name or parameter is reported against --generate.
TriangleMesh generateFor(const std::string& spec) {
    try {
        return generate(spec);
    } catch (const InputError& e) {
        // A missing model or font file is about the file, not the flag: keep its message.
        if (e.source().find('/') != std::string::npos) throw;
        // An unknown name (the error is about the spec itself) also gets mesh-info's alphabet.
        throw InputError("--generate", "\"" + spec + "\": " + e.problem() +
                                           (e.source() == spec ? " (or alphabet)" : ""));
    }
}

int run(MeshInfoOptions o) {
    const bool hasFile = !o.file.empty(), hasGenerator = !o.generate.empty();
    if (hasFile == hasGenerator)
        throw InputError("mesh-info", hasFile
                                          ? "give either a mesh FILE or --generate NAME, not both"
                                          : "give a mesh FILE or --generate NAME");
    if (given(o.cellsOption) && given(o.cellSizeOption))
        throw InputError("--cell-size", "give either --cells or --cell-size, not both (--cells " +
                                            o.cellsText + ", --cell-size " + o.cellSizeText + ")");
    if (given(o.cellsOption)) o.cells = int(parseInteger("--cells", o.cellsText, 1, 1000000));
    if (given(o.cellSizeOption))
        o.cellSize = float(parseNumber("--cell-size", o.cellSizeText, 1e-30, 1e30,
                                       "a cell size in mesh units, 1e-30..1e30"));

    std::vector<ObjectStats> objects;
    const PaperObjectFigures* paper = nullptr;
    if (hasFile) {
        const auto t = Clock::now();
        TriangleMesh mesh = loadMesh(o.file);
        mesh.name = o.file;
        objects.push_back(analyse(std::move(mesh), o, 64, msSince(t), true));
    } else if (o.generate == "alphabet") {
        paper = &kPaperLetter;
        for (char c = 'A'; c <= 'Z'; ++c) {
            const auto t = Clock::now();
            TriangleMesh mesh = generateFor(std::string("letter:") + c);
            objects.push_back(analyse(std::move(mesh), o, paper->cells, msSince(t), false));
        }
    } else {
        paper = paperFigures(o.generate);
        const auto t = Clock::now();
        TriangleMesh mesh = generateFor(o.generate);
        objects.push_back(
            analyse(std::move(mesh), o, paper ? paper->cells : 64, msSince(t), false));
    }

    // The alphabet reports the averages over A-Z, as the paper's Table 2 does.
    ObjectStats summary = objects.front();
    if (objects.size() > 1) {
        auto mean = [&](auto field) {
            double sum = 0;
            for (const ObjectStats& s : objects) sum += double(std::invoke(field, s));
            return sum / double(objects.size());
        };
        summary.name = "alphabet (A-Z average)";
        summary.vertices = size_t(std::lround(mean(&ObjectStats::vertices)));
        summary.triangles = size_t(std::lround(mean(&ObjectStats::triangles)));
        summary.cells = size_t(std::lround(mean(&ObjectStats::cells)));
        summary.surfaceCells = size_t(std::lround(mean(&ObjectStats::surfaceCells)));
        summary.interiorCells = size_t(std::lround(mean(&ObjectStats::interiorCells)));
        summary.particles = size_t(std::lround(mean(&ObjectStats::particles)));
        summary.nodes = size_t(std::lround(mean(&ObjectStats::nodes)));
        summary.size = float(mean(&ObjectStats::size));
        summary.standoff.median = mean([](const ObjectStats& s) { return s.standoff.median; });
        summary.standoff.p90 = mean([](const ObjectStats& s) { return s.standoff.p90; });
        summary.standoff.max = mean([](const ObjectStats& s) { return s.standoff.max; });
        summary.buildMs = mean(&ObjectStats::buildMs);
        summary.generateMs = mean(&ObjectStats::generateMs);
        summary.closed = true;
        for (const ObjectStats& s : objects) summary.closed = summary.closed && s.closed;
    }

    if (o.json) {
        nlohmann::json j = toJson(summary);
        if (objects.size() > 1) {
            j["letters"] = nlohmann::json::array();
            for (const ObjectStats& s : objects) j["letters"].push_back(toJson(s));
        }
        if (paper)
            j["paper"] = {{"object", paper->name},
                          {"vertices", paper->vertices},
                          {"triangles", paper->triangles},
                          {"cells", paper->cells}};
        if (hasFile)
            j["cleanup"] = {{"welded_vertices", summary.cleanup.weldedVertices},
                            {"degenerate_triangles", summary.cleanup.degenerateTriangles},
                            {"duplicate_triangles", summary.cleanup.duplicateTriangles},
                            {"unreferenced_vertices", summary.cleanup.unreferencedVertices}};
        fmt::print("{}\n", j.dump(2));
        return 0;
    }

    if (objects.size() > 1) {
        fmt::print("{:<8} {:>9} {:>9} {:>6} {:>8} {:>9}\n", "letter", "vertices", "triangles",
                   "cells", "surface", "particles");
        for (const ObjectStats& s : objects)
            fmt::print("{:<8} {:>9} {:>9} {:>6} {:>8} {:>9}\n", s.name, s.vertices, s.triangles,
                       s.cells, s.surfaceCells, s.particles);
        fmt::print("\n");
    }
    fmt::print("{}\n", summary.name);
    if (hasFile && summary.cleanup.changed())
        fmt::print("  cleanup        welded {} vertices, dropped {} degenerate and {} duplicate "
                   "triangles and {} unreferenced vertices\n",
                   summary.cleanup.weldedVertices, summary.cleanup.degenerateTriangles,
                   summary.cleanup.duplicateTriangles, summary.cleanup.unreferencedVertices);
    const auto row = [&](const char* what, auto ours, int theirs) {
        if (paper)
            fmt::print("  {:<14} {:>10} {:>12}\n", what, ours, theirs);
        else
            fmt::print("  {:<14} {:>10}\n", what, ours);
    };
    if (paper) fmt::print("  {:<14} {:>10} {:>12}\n", "", "ours", "paper (T2)");
    row("vertices", summary.vertices, paper ? paper->vertices : 0);
    row("triangles", summary.triangles, paper ? paper->triangles : 0);
    row("FFD cells", summary.cells, paper ? paper->cells : 0);
    fmt::print("  {:<14} {:>10}\n", "closed", summary.closed ? "yes" : "no");
    fmt::print("  {:<14} {:>10}\n", "surface cells", summary.surfaceCells);
    fmt::print("  {:<14} {:>10}\n", "interior cells", summary.interiorCells);
    fmt::print("  {:<14} {:>10}\n", "particles", summary.particles);
    fmt::print("  {:<14} {:>10}\n", "box nodes", summary.nodes);
    if (objects.size() == 1) fmt::print("  {:<14} {:>10.4g}\n", "cell size", summary.cellSize);
    // How far the boxes reach beyond the surface, direction by direction (measureBoxStandoff).
    const auto share = [&](double v) { return summary.size > 0 ? 100.0 * v / summary.size : 0.0; };
    fmt::print("  {:<14} {:>10.4g} median, {:.4g} at 90 %, {:.4g} at most ({:.1f} %, {:.1f} %, "
               "{:.1f} % of the size){}\n",
               "box standoff", summary.standoff.median, summary.standoff.p90, summary.standoff.max,
               share(summary.standoff.median), share(summary.standoff.p90),
               share(summary.standoff.max), objects.size() > 1 ? ", means over A-Z" : "");
    fmt::print("  {:<14} {:>10.2f} ms\n", "lattice build", summary.buildMs);
    fmt::print("  {:<14} {:>10.2f} ms\n", hasFile ? "load" : "generate", summary.generateMs);
    return 0;
}

} // namespace

void addMeshInfoCommand(CLI::App& app, Action& action) {
    auto options = std::make_shared<MeshInfoOptions>();
    CLI::App* cmd = app.add_subcommand(
        "mesh-info", "Mesh and lattice statistics of a mesh file or a generated object");
    cmd->add_option("file", options->file, "Mesh file (.obj, .ply, .ply.gz, .stl, .off)");
    cmd->add_option("--generate", options->generate,
                    std::string("Generated object: ") + generatorNames() + ", alphabet");
    options->cellsOption = cmd->add_option(
        "--cells", options->cellsText,
        "Target lattice cell count, 1..1000000 (default: the paper's for its objects, else 64)");
    options->cellSizeOption = cmd->add_option("--cell-size", options->cellSizeText,
                                              "Lattice cell size in mesh units (not with --cells)");
    cmd->add_flag("--json", options->json, "Print one JSON object");
    cmd->footer("For the paper's objects (sphere, teapot, letter:X, alphabet, dragon) the "
                "paper's Table 2 figures are printed beside ours.");
    cmd->callback([options, &action] { action = [options] { return run(*options); }; });
}

} // namespace ffd::cli
