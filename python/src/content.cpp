// The content component from Python: the paper's objects and the colliders' shapes as arrays,
// mesh files, the shipped scenes, and the tables of stages and settings.
#include "bindings.h"

#include "ffdaabb/error.h"
#include "ffdaabb/generators.h"
#include "ffdaabb/lattice.h"
#include "ffdaabb/mesh_io.h"
#include "ffdaabb/profile.h"
#include "ffdaabb/scene.h"
#include "runner.h"

#include <cstring>
#include <string>

namespace ffd::python {

namespace {

// A Mesh (vertices float32 (V, 3), triangles uint32 (T, 3)) holding copies of the mesh's arrays.
py::object toArrays(const TriangleMesh& mesh) {
    py::array_t<float> v({ssize_t(mesh.positions.size()), ssize_t(3)});
    if (!mesh.positions.empty())
        std::memcpy(v.mutable_data(), mesh.positions.data(), mesh.positions.size() * sizeof(Vec3));
    py::array_t<uint32_t> t({ssize_t(mesh.triangles.size()), ssize_t(3)});
    if (!mesh.triangles.empty())
        std::memcpy(t.mutable_data(), mesh.triangles.data(),
                    mesh.triangles.size() * sizeof(mesh.triangles[0]));
    return support().attr("Mesh")(v, t);
}

// Runs a generator without the GIL and returns its mesh as arrays.
template <class F>
py::object generated(F&& make) {
    TriangleMesh mesh;
    {
        py::gil_scoped_release released;
        mesh = make();
    }
    return toArrays(mesh);
}

// InputError naming the Python argument when `value` is outside lo..hi: the core's bounds
// (generators.h), checked here so that the message names the argument as Python spells it.
void checkRange(const char* argument, int value, int lo, int hi) {
    if (value < lo || value > hi)
        badArgument(argument, "value " + std::to_string(value) + " is out of range (expected " +
                                  std::to_string(lo) + ".." + std::to_string(hi) + ")");
}

py::dict rangeDict(const SettingRange& r) {
    py::dict d;
    d["key"] = r.key;
    d["field"] = r.field;
    d["min"] = r.min;
    d["max"] = r.max;
    d["default"] = settingDefault(r);
    d["integer"] = r.integer;
    d["unit"] = r.unit;
    d["expected"] = r.expected;
    d["doc"] = r.doc;
    return d;
}

} // namespace

void bindContent(py::module_& m) {
    m.def(
        "sphere",
        [](int subdivisions) {
            checkRange("subdivisions", subdivisions, 0, kMaxIcosphereSubdivisions);
            return generated([&] { return icosphere(subdivisions); });
        },
        py::arg("subdivisions") = 2,
        "A unit-radius icosphere (2 subdivisions: the paper's 162 vertices, 320 triangles), as "
        "a Mesh of arrays.");
    m.def(
        "teapot",
        [](int quadsPerPatch) {
            checkRange("quads_per_patch", quadsPerPatch, 1, kMaxTeapotQuadsPerPatch);
            return generated([&] { return teapot(quadsPerPatch); });
        },
        py::arg("quads_per_patch") = 10,
        "Newell's teapot (10 quads per patch: about the paper's 3,242 vertices).");
    m.def(
        "letter",
        [](const std::string& capital, float height, float depthRatio, float refine) {
            if (capital.size() != 1)
                badArgument("capital", "expected one capital letter A-Z, got \"" + capital + "\"");
            LetterSettings s;
            s.height = height;
            s.depthRatio = depthRatio;
            s.refine = refine;
            return generated([&] { return letter(capital[0], s); });
        },
        py::arg("capital"), py::arg("height") = 1.0f, py::arg("depth_ratio") = 0.25f,
        py::arg("refine") = 1.0f,
        "An extruded capital letter (DejaVu Sans Bold), standing on y = 0.");
    m.def(
        "dragon",
        [](size_t targetTriangles, float size) {
            DragonSettings s;
            s.targetTriangles = targetTriangles;
            s.size = size;
            return generated([&] { return dragon(s); });
        },
        py::arg("target_triangles") = 67240, py::arg("size") = 1.0f,
        "The Stanford dragon simplified to about target_triangles (the paper's Buddha-class "
        "object); needs the model data the setup fetches.");
    m.def(
        "box",
        [](Vec3 halfExtents, int quadsPerEdge) {
            return generated([&] { return box(halfExtents, quadsPerEdge); });
        },
        py::arg("half_extents"), py::arg("quads_per_edge") = 4, "A box centred at the origin.");
    m.def(
        "bowl",
        [](float radius, float thickness, int segments) {
            return generated([&] { return bowl(radius, thickness, segments); });
        },
        py::arg("radius") = 1.0f, py::arg("thickness") = 0.15f, py::arg("segments") = 32,
        "A hemispherical bowl, open upwards, rim at y = 0 (a collider).");
    m.def(
        "generate",
        [](const std::string& spec) { return generated([&] { return generate(spec); }); },
        py::arg("spec"),
        "A generated object by name, as scene files name them: sphere, icosphere:N, teapot, "
        "teapot:N, letter:X, dragon, box, bowl.");
    m.def(
        "load_mesh",
        [](const py::object& file) {
            const std::string path = pathText(file);
            return generated([&] { return loadMesh(path); });
        },
        py::arg("path"),
        "Reads an .obj, .ply, .stl or .off file (optionally gzipped) as a Mesh of arrays.");
    m.def(
        "save_obj",
        [](const py::object& file, const py::object& vertices, const py::object& triangles) {
            const std::string path = pathText(file);
            const TriangleMesh mesh = meshFromArrays(vertices, triangles);
            py::gil_scoped_release released;
            saveObj(mesh, path);
        },
        py::arg("path"), py::arg("vertices"), py::arg("triangles"),
        "Writes an OBJ file (through a temporary name: a failed write leaves nothing).");
    m.def(
        "box_standoff",
        [](const py::object& vertices, const py::object& triangles, const LatticeSettings& settings,
           int directions) {
            const TriangleMesh mesh = meshFromArrays(vertices, triangles);
            checkRange("directions", directions, 1, 1000000);
            cli::StandoffSummary r;
            float h = 0;
            {
                py::gil_scoped_release released;
                const Lattice lattice = buildLattice(mesh, settings);
                r = cli::summariseStandoff(measureBoxStandoff(lattice, mesh, directions));
                h = lattice.cellSize;
            }
            py::dict d;
            d["directions"] = r.directions;
            d["median"] = r.median;
            d["p90"] = r.p90;
            d["max"] = r.max;
            d["worst_direction"] =
                py::make_tuple(r.worstDirection.x, r.worstDirection.y, r.worstDirection.z);
            d["cell_size"] = h;
            d["size"] = maxComponent(bounds(mesh).extent());
            return d;
        },
        py::arg("vertices"), py::arg("triangles"), py::arg("lattice") = LatticeSettings{},
        py::kw_only(), py::arg("directions") = 2000,
        "How far the cell boxes of the mesh's lattice (built with `lattice`) reach beyond its "
        "surface at rest, over `directions` directions spread over the sphere: along each, the "
        "farthest box node less the farthest vertex. For a convex body, the gap its boxes keep "
        "beyond its surface that way. A dict: directions, median, p90, max, worst_direction, "
        "cell_size, size (the mesh's largest extent); what `ffdaabb mesh-info` prints as the box "
        "standoff.");
    m.def("scene_names", &sceneNames, "The shipped scenes' names (World.from_scene, run).");
    m.def(
        "stages",
        [] {
            std::vector<std::string> out;
            for (const StageInfo& s : stageTable()) out.push_back(s.key);
            return out;
        },
        "The step's stages in the order they run (the keys of profile['stage_ms']).");
    m.def(
        "settings_table",
        [] {
            py::dict d;
            py::list world, material;
            for (const SettingRange& r : worldSettingRanges()) world.append(rangeDict(r));
            for (const SettingRange& r : bodySettingRanges()) material.append(rangeDict(r));
            d["world"] = world;
            d["material"] = material;
            return d;
        },
        "The numeric settings' ranges, units and defaults (as `ffdaabb settings` lists them).");
}

} // namespace ffd::python
