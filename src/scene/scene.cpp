// Scene files: parsing with field-by-field validation, and building worlds from them.
#include "ffdaabb/scene.h"

#include "ffdaabb/data.h"

#include "ffdaabb/error.h"
#include "ffdaabb/generators.h"
#include "ffdaabb/mesh_io.h"
#include "world/settings_table.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <type_traits>

namespace ffd {

namespace {

using Json = nlohmann::json;

// Scene files are at most four levels deep (objects[i].material.field); anything much deeper
// is garbage, and nlohmann's dump(), which quotes values in messages, recurses once per level.
constexpr int kMaxJsonDepth = 64;
// Scene files are a few hundred bytes; a file beyond this is not a scene.
constexpr uintmax_t kMaxSceneBytes = uintmax_t(16) << 20;
// Objects in a scene in all: the CLI's --objects limit.
constexpr long long kMaxSceneObjects = 100000;
// Mesh vertices in a scene in all (2^27, 1.5 GiB of deformed positions): every body keeps its
// own deformed copy of its mesh, and the world addresses them with 32-bit offsets. Checked
// before any body is made, so that an absurd scene fails at once rather than out of memory.
constexpr size_t kMaxSceneVertices = size_t(1) << 27;

std::string shortValue(const Json& v) {
    std::string s = v.dump();
    return s.size() > 60 ? s.substr(0, 57) + "..." : s;
}

const char* typeName(const Json& v) {
    switch (v.type()) {
    case Json::value_t::null:
        return "null";
    case Json::value_t::boolean:
        return "a boolean";
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned:
        return "an integer";
    case Json::value_t::number_float:
        return "a number";
    case Json::value_t::string:
        return "a string";
    case Json::value_t::array:
        return "an array";
    case Json::value_t::object:
        return "an object";
    default:
        return "a value";
    }
}

// A JSON object being read: knows its path for messages, checks types and ranges, and rejects
// fields nobody asked for.
class Fields {
public:
    Fields(const Json& j, std::string path, const std::filesystem::path& file)
        : j_(j), path_(std::move(path)), file_(file) {
        if (!j.is_object()) fail(path_, "expected an object, got " + std::string(typeName(j)));
    }

    [[noreturn]] void fail(const std::string& field, const std::string& problem) const {
        throw InputError(file_.string(), (field.empty() ? "" : field + ": ") + problem);
    }

    std::string at(const char* key) const { return path_.empty() ? key : path_ + "." + key; }

    const Json* find(const char* key) {
        known_.insert(key);
        const auto it = j_.find(key);
        return it == j_.end() ? nullptr : &*it;
    }

    bool number(const char* key, float& out, double lo, double hi, const char* expected) {
        const Json* v = find(key);
        if (!v) return false;
        if (!v->is_number())
            fail(at(key), "expected a number (" + std::string(expected) + "), got " + typeName(*v) +
                              " " + shortValue(*v));
        const double d = v->get<double>();
        if (!(d >= lo && d <= hi))
            fail(at(key),
                 "value " + shortValue(*v) + " is out of range (expected " + expected + ")");
        out = float(d);
        return true;
    }

    bool integer(const char* key, int& out, long lo, long hi, const char* expected) {
        const Json* v = find(key);
        if (!v) return false;
        if (!v->is_number_integer())
            fail(at(key), "expected an integer (" + std::string(expected) + "), got " +
                              typeName(*v) + " " + shortValue(*v));
        const long long i = v->get<long long>();
        if (i < lo || i > hi)
            fail(at(key),
                 "value " + shortValue(*v) + " is out of range (expected " + expected + ")");
        out = int(i);
        return true;
    }

    bool boolean(const char* key, bool& out) {
        const Json* v = find(key);
        if (!v) return false;
        if (!v->is_boolean())
            fail(at(key),
                 "expected true or false, got " + std::string(typeName(*v)) + " " + shortValue(*v));
        out = v->get<bool>();
        return true;
    }

    bool string(const char* key, std::string& out) {
        const Json* v = find(key);
        if (!v) return false;
        if (!v->is_string())
            fail(at(key),
                 "expected a string, got " + std::string(typeName(*v)) + " " + shortValue(*v));
        out = v->get<std::string>();
        return true;
    }

    bool vec3(const char* key, Vec3& out, double limit) {
        const Json* v = find(key);
        if (!v) return false;
        if (!v->is_array() || v->size() != 3 || !(*v)[0].is_number() || !(*v)[1].is_number() ||
            !(*v)[2].is_number())
            fail(at(key), "expected an array of 3 numbers, got " + shortValue(*v));
        for (int i = 0; i < 3; ++i) {
            const double d = (*v)[size_t(i)].get<double>();
            if (!(std::fabs(d) <= limit))
                fail(at(key),
                     "value " + shortValue(*v) +
                         " is out of range (expected finite numbers of magnitude at most " +
                         std::to_string(int(limit)) + ")");
            out[i] = float(d);
        }
        return true;
    }

    /// Call last: any field not asked for is an error that lists the known ones.
    void finish() const {
        for (auto it = j_.begin(); it != j_.end(); ++it)
            if (!known_.count(it.key())) {
                std::string list;
                for (const std::string& k : known_) list += (list.empty() ? "" : ", ") + k;
                // The name is the file's: shown cut short and without control characters.
                std::string name = it.key().substr(0, 40);
                for (char& c : name)
                    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
                if (it.key().size() > 40) name += "...";
                fail(at(name.c_str()), "unknown field (expected one of: " + list + ")");
            }
    }

    const std::string& path() const { return path_; }

private:
    const Json& j_;
    std::string path_;
    const std::filesystem::path& file_;
    std::set<std::string> known_;
};

// Every numeric setting of the table (ffdaabb/world.h: SettingRange) the object gives.
template <class Settings>
void readRanges(Fields& f, Settings& s, std::span<const SettingRange> ranges,
                std::span<const detail::SettingMember<Settings>> members) {
    for (size_t i = 0; i < ranges.size(); ++i) {
        const SettingRange& r = ranges[i];
        std::visit(
            [&](auto member) {
                if constexpr (std::is_same_v<decltype(member), int Settings::*>)
                    f.integer(r.key, s.*member, long(r.min), long(r.max), r.expected);
                else
                    f.number(r.key, s.*member, r.min, r.max, r.expected);
            },
            members[i]);
    }
}

void readWorld(Fields f, WorldSettings& w) {
    readRanges(f, w, worldSettingRanges(), detail::worldSettingMembers());
    f.vec3("gravity", w.gravity, 1e4);
    f.boolean("floor", w.floor);
    std::string mode;
    if (f.string("mode", mode) && !parseCollisionMode(mode, w.mode))
        f.fail(f.at("mode"),
               "unknown mode \"" + mode + "\" (expected enhanced, previous, brute or none)");
    f.finish();
}

void readLattice(Fields f, LatticeSettings& l) {
    bool any = false;
    int cells = 0;
    if (f.integer("cells", cells, 1, 1000000, "1..1000000")) l.targetCells = cells, any = true;
    float size = 0;
    if (f.number("cell_size", size, 1e-6, 1e6, "metres, > 0")) {
        if (any) f.fail(f.at("cell_size"), "give only one of cells, cell_size, resolution");
        l.cellSize = size, any = true;
    }
    float resolution = 0;
    if (f.number("resolution", resolution, 1e-3, 4096, "cells along the longest extent, 0..4096")) {
        if (any) f.fail(f.at("resolution"), "give only one of cells, cell_size, resolution");
        l.resolution = resolution;
    }
    f.boolean("fill_interior", l.fillInterior);
    f.number("box_skin", l.boxSkin, 0.0, 0.25, "0..0.25 of a cell");
    f.finish();
}

void readMaterial(Fields f, BodySettings& b) {
    std::string model;
    if (f.string("model", model) && !parseDynamicsModel(model, b.model))
        f.fail(f.at("model"),
               "unknown model \"" + model + "\" (expected shape-matching or mass-spring)");
    readRanges(f, b, bodySettingRanges(), detail::bodySettingMembers());
    f.boolean("region_damping", b.regionDamping);
    f.boolean("allow_sleep", b.allowSleep);
    f.finish();
}

// Why `spec` is not a generator a scene can use ("" when it is). Checked here, where the field
// is known, rather than when the scene is built; the ranges are those of icosphere() and
// teapot(), which check them again.
std::string generatorProblem(const std::string& spec) {
    const auto suffix = [&](std::string_view prefix, int lo, int hi) -> std::string {
        const std::string_view digits = std::string_view(spec).substr(prefix.size());
        int n = 0;
        const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), n);
        if (digits.empty() || ec != std::errc() || end != digits.data() + digits.size() || n < lo ||
            n > hi)
            return "\"" + spec + "\" is out of range (expected " + std::string(prefix) +
                   std::to_string(lo) + ".." + std::string(prefix) + std::to_string(hi) + ")";
        return "";
    };
    if (spec == "sphere" || spec == "teapot" || spec == "dragon" || spec == "box" || spec == "bowl")
        return "";
    if (spec.rfind("icosphere:", 0) == 0) return suffix("icosphere:", 0, kMaxIcosphereSubdivisions);
    if (spec.rfind("teapot:", 0) == 0) return suffix("teapot:", 1, kMaxTeapotQuadsPerPatch);
    if (spec.rfind("letter:", 0) == 0) {
        if (spec.size() == 8 && spec[7] >= 'A' && spec[7] <= 'Z') return "";
        return "\"" + spec + "\" is not a letter generator (expected letter:A..letter:Z)";
    }
    return "unknown generator \"" + spec + "\" (expected letters, " + generatorNames() +
           ", {\"file\": \"path\"} or {\"model\": \"name\"})";
}

SceneObject readObject(Fields f, const std::filesystem::path& file) {
    SceneObject o;
    const Json* mesh = f.find("mesh");
    if (!mesh)
        f.fail(f.at("mesh"),
               "missing (expected a generator name, {\"file\": ...} or {\"model\": ...})");
    if (mesh->is_string()) {
        o.mesh = mesh->get<std::string>();
        if (o.mesh != "letters") {
            const std::string problem = generatorProblem(o.mesh);
            if (!problem.empty()) f.fail(f.at("mesh"), problem);
        }
    } else if (mesh->is_object()) {
        // {"file": path}: relative to the scene file's folder; {"model": name}: a file in the
        // models folder (modelCacheDir: $FFDAABB_MODELS, else the data folders' `models`).
        Fields m(*mesh, f.at("mesh"), file);
        std::string path, model;
        const bool hasFile = m.string("file", path);
        const bool hasModel = m.string("model", model);
        m.finish();
        if (hasFile && hasModel)
            m.fail(m.at("model"), "give either \"file\" or \"model\", not both");
        if (!hasFile && !hasModel)
            m.fail(m.at("file"), "missing (expected a mesh file path, or \"model\": a file name "
                                 "in the models folder)");
        const char* key = hasModel ? "model" : "file";
        const std::string& name = hasModel ? model : path;
        if (name.empty())
            m.fail(m.at(key), hasModel ? "empty (expected a file name in the models folder)"
                                       : "empty (expected a mesh file path)");
        std::filesystem::path p(name);
        if (hasModel) {
            const std::filesystem::path rel = p.lexically_normal();
            if (p.is_absolute() || rel.empty() || *rel.begin() == "..")
                m.fail(m.at(key), "\"" + name +
                                      "\" is not inside the models folder (expected a file name "
                                      "such as \"dragon_vrip_res3.ply.gz\")");
            p = modelCacheDir() / rel;
        } else if (p.is_relative() && !file.empty()) {
            p = file.parent_path() / p;
        }
        if (!std::filesystem::exists(p))
            m.fail(m.at(key), "\"" + name + "\" does not exist (looked for " + p.string() +
                                  (hasModel ? "; scripts/setup.sh fetches the models, or set "
                                              "FFDAABB_MODELS to their folder)"
                                            : ")"));
        if (std::filesystem::is_directory(p))
            m.fail(m.at(key), "\"" + name + "\" is a folder (expected a mesh file)");
        o.mesh.clear();
        o.meshFile = p;
    } else {
        f.fail(f.at("mesh"),
               "expected a generator name, {\"file\": ...} or {\"model\": ...}, got " +
                   shortValue(*mesh));
    }
    if (f.string("letters", o.letters)) {
        if (o.mesh != "letters") f.fail(f.at("letters"), "only for \"mesh\": \"letters\"");
        if (o.letters.empty()) f.fail(f.at("letters"), "expected at least one capital letter A-Z");
        for (char c : o.letters)
            if (c < 'A' || c > 'Z')
                f.fail(f.at("letters"), "\"" + o.letters + "\" has a character outside A-Z");
    }
    f.integer("count", o.count, 1, 1000000, "1..1000000");
    f.number("size", o.size, 1e-4, 1e4, "metres, 1e-4..1e4");
    o.body.lattice.targetCells = 64;
    if (const Json* l = f.find("lattice"))
        readLattice(Fields(*l, f.at("lattice"), file), o.body.lattice);
    if (const Json* m = f.find("material"))
        readMaterial(Fields(*m, f.at("material"), file), o.body);
    std::string motion;
    if (f.string("motion", motion) && !parseBodyMotion(motion, o.body.motion))
        f.fail(f.at("motion"),
               "unknown motion \"" + motion + "\" (expected dynamic, static or kinematic)");
    o.placed = f.vec3("position", o.position, 1e6);
    if (o.placed && o.count != 1)
        f.fail(f.at("count"), "value " + std::to_string(o.count) +
                                  " with a position (expected 1: a placed object is one object)");
    if (f.vec3("scale", o.scale, 1e4) && !(o.scale.x > 0 && o.scale.y > 0 && o.scale.z > 0))
        f.fail(f.at("scale"), "expected positive numbers (a scale per axis)");
    f.finish();
    return o;
}

void readLayout(Fields f, SceneLayout& l) {
    f.vec3("origin", l.origin, 1e6);
    if (const Json* c = f.find("columns")) {
        if (!c->is_array() || c->size() != 2 || !(*c)[0].is_number_integer() ||
            !(*c)[1].is_number_integer() || (*c)[0].get<long long>() < 1 ||
            (*c)[1].get<long long>() < 1 || (*c)[0].get<long long>() > 10000 ||
            (*c)[1].get<long long>() > 10000)
            f.fail(f.at("columns"), "expected two integers 1..10000, got " + shortValue(*c));
        l.columns[0] = int((*c)[0].get<long long>());
        l.columns[1] = int((*c)[1].get<long long>());
    }
    f.number("spacing", l.spacing, 1e-4, 1e4, "metres, 1e-4..1e4");
    f.number("jitter", l.jitter, 0.0, 0.5, "0..0.5 of the spacing");
    f.boolean("random_rotation", l.randomRotation);
    f.vec3("velocity", l.velocity, 1e4);
    f.number("velocity_jitter", l.velocityJitter, 0.0, 1e4, "m/s, >= 0");
    int seed = int(l.seed);
    if (f.integer("seed", seed, 0, 2147483647, "0..2147483647")) l.seed = uint32_t(seed);
    f.finish();
}

ScenePin readPin(Fields f, long long objects) {
    ScenePin pin;
    if (!f.find("object")) f.fail(f.at("object"), "missing (expected the index of a body)");
    f.integer("object", pin.object, 0, long(std::max<long long>(objects - 1, 0)),
              objects > 1
                  ? ("0.." + std::to_string(objects - 1) + ", the scene's objects in order").c_str()
                  : "0, the scene's only object");
    int given = 0, index = 0;
    if (f.integer("particle", index, 0, 2147483647, "a particle index, >= 0"))
        pin.at = ScenePin::At::Particle, pin.index = uint32_t(index), ++given;
    if (f.integer("vertex", index, 0, 2147483647, "a vertex index, >= 0"))
        pin.at = ScenePin::At::Vertex, pin.index = uint32_t(index), ++given;
    if (f.vec3("point", pin.point, 1e6)) pin.at = ScenePin::At::Point, ++given;
    if (given != 1)
        f.fail(f.path(), given == 0 ? "no point to pin (expected one of particle, vertex, point)"
                                    : "give only one of particle, vertex, point");
    pin.hasTarget = f.vec3("target", pin.target, 1e6);
    if (const Json* k = f.find("stiffness")) {
        if (k->is_string() && k->get<std::string>() == "hard")
            pin.settings.stiffness = 0;
        else if (!k->is_number() || !(k->get<double>() > 0 && k->get<double>() <= 1e12))
            f.fail(f.at("stiffness"), "value " + shortValue(*k) +
                                          " is out of range (expected \"hard\" or N/m, "
                                          "0 < stiffness <= 1e12)");
        else
            pin.settings.stiffness = float(k->get<double>());
    }
    f.number("rigidity", pin.settings.rigidity, 0.0, 1.0, "0..1");
    f.number("swing_damping", pin.settings.swingDamping, 0.0, 1000.0, "1/s, 0..1000");
    f.number("max_speed", pin.settings.maxSpeed, 0.0, 1e6, "m/s, 0 (any) or 0 < v <= 1e6");
    f.finish();
    return pin;
}

// Deterministic on every platform (std distributions are not): splitmix64.
struct Random {
    uint64_t state;
    uint64_t next() {
        uint64_t z = (state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    float uniform(float lo, float hi) {
        return lo + (hi - lo) * float(next() >> 40) / float(1 << 24);
    }
    Quat rotation() {
        // Uniform on SO(3) (Shoemake's method).
        const float u1 = uniform(0, 1), u2 = uniform(0, 6.2831853f), u3 = uniform(0, 6.2831853f);
        const float a = std::sqrt(1 - u1), b = std::sqrt(u1);
        return normalize(
            Quat{b * std::cos(u3), a * std::sin(u2), a * std::cos(u2), b * std::sin(u3)});
    }
};

// $FFDAABB_SCENES, then the `scenes` folder of every data folder (ffdaabb/data.h).
std::vector<std::filesystem::path> sceneFolders() {
    std::vector<std::filesystem::path> folders;
    if (const char* env = std::getenv("FFDAABB_SCENES"); env && *env) folders.emplace_back(env);
    for (const std::filesystem::path& data : dataFolders()) folders.push_back(data / "scenes");
    return folders;
}

} // namespace

int Scene::objectCount() const {
    int n = 0;
    for (const SceneObject& o : objects) n += o.count;
    return n;
}

Scene parseScene(const std::string& text, const std::filesystem::path& file) {
    Json j;
    try {
        j = Json::parse(text, [&](int depth, Json::parse_event_t, Json&) {
            if (depth > kMaxJsonDepth)
                throw InputError(file.string(), "not a scene: values nested more than " +
                                                    std::to_string(kMaxJsonDepth) +
                                                    " levels deep (a scene file has at most 4)");
            return true;
        });
    } catch (const Json::exception& e) {
        // parse_error, and out_of_range for numbers beyond double's range (1e999).
        throw InputError(file.string(), std::string("not valid JSON: ") + e.what());
    }
    Scene scene;
    scene.source = file;
    Fields f(j, "", file);
    f.string("name", scene.name);
    f.string("description", scene.description);
    if (scene.name.empty()) scene.name = file.stem().string();
    if (const Json* w = f.find("world")) readWorld(Fields(*w, "world", file), scene.world);
    const Json* objects = f.find("objects");
    if (!objects) f.fail("objects", "missing (expected an array of objects)");
    if (!objects->is_array() || objects->empty())
        f.fail("objects", "expected a non-empty array of objects, got " + shortValue(*objects));
    long long total = 0;
    for (size_t i = 0; i < objects->size(); ++i) {
        scene.objects.push_back(
            readObject(Fields((*objects)[i], "objects[" + std::to_string(i) + "]", file), file));
        total += scene.objects.back().count;
        if (total > kMaxSceneObjects)
            f.fail("objects[" + std::to_string(i) + "].count",
                   "the scene would hold " + std::to_string(total) + " objects (expected at most " +
                       std::to_string(kMaxSceneObjects) + " in all)");
    }
    if (const Json* l = f.find("layout")) readLayout(Fields(*l, "layout", file), scene.layout);
    if (const Json* pins = f.find("pins")) {
        if (!pins->is_array())
            f.fail("pins", "expected an array of pins, got " + shortValue(*pins));
        for (size_t i = 0; i < pins->size(); ++i)
            scene.pins.push_back(
                readPin(Fields((*pins)[i], "pins[" + std::to_string(i) + "]", file), total));
    }
    if (const Json* planes = f.find("planes")) {
        if (!planes->is_array())
            f.fail("planes", "expected an array of planes, got " + shortValue(*planes));
        for (size_t i = 0; i < planes->size(); ++i) {
            Fields p((*planes)[i], "planes[" + std::to_string(i) + "]", file);
            Plane plane;
            if (!p.vec3("normal", plane.normal, 1e6))
                p.fail(p.at("normal"), "missing (expected an array of 3 numbers)");
            const float len = length(plane.normal);
            if (!(len > 1e-6f)) p.fail(p.at("normal"), "zero (expected a non-zero direction)");
            plane.normal = plane.normal / len;
            p.number("offset", plane.offset, -1e6, 1e6, "metres, -1e6..1e6");
            p.finish();
            scene.planes.push_back(plane);
        }
    }
    f.finish();
    validate(scene.world);
    for (const SceneObject& o : scene.objects) validate(o.body);
    return scene;
}

Scene loadScene(const std::string& nameOrPath) {
    std::filesystem::path path(nameOrPath);
    const bool isFile = nameOrPath.find('/') != std::string::npos || path.extension() == ".json";
    if (!isFile) {
        bool found = false;
        for (const auto& folder : sceneFolders())
            if (std::filesystem::exists(folder / (nameOrPath + ".json"))) {
                path = folder / (nameOrPath + ".json");
                found = true;
                break;
            }
        if (!found) {
            std::string names;
            for (const std::string& n : sceneNames()) names += (names.empty() ? "" : ", ") + n;
            if (names.empty()) { // no scene folder at all: say where they were looked for
                std::string folders;
                for (const auto& folder : sceneFolders())
                    folders += (folders.empty() ? "" : ", ") + folder.string();
                throw InputError(nameOrPath, "no such scene, and no scene folder found (looked "
                                             "in " +
                                                 folders +
                                                 "; set FFDAABB_DATA to the folder that holds "
                                                 "scenes/, or give a .json file)");
            }
            throw InputError(nameOrPath,
                             "no such scene (expected a .json file or one of: " + names + ")");
        }
    }
    if (!std::filesystem::exists(path))
        throw InputError(path.string(), "does not exist (expected a scene .json file)");
    if (std::filesystem::is_directory(path))
        throw InputError(path.string(), "is a folder (expected a scene .json file)");
    if (!std::filesystem::is_regular_file(path))
        throw InputError(path.string(), "is not a regular file (expected a scene .json file)");
    std::error_code ec;
    const uintmax_t bytes = std::filesystem::file_size(path, ec);
    if (ec) throw InputError(path.string(), "cannot be read: " + ec.message());
    if (bytes == 0) throw InputError(path.string(), "is empty (expected a scene .json file)");
    if (bytes > kMaxSceneBytes)
        throw InputError(path.string(), "is " + std::to_string(bytes) +
                                            " bytes, more than the limit of 16 MiB for a scene "
                                            "file (expected a scene .json file)");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path.string(), "cannot be read");
    std::stringstream ss;
    ss << in.rdbuf();
    return parseScene(ss.str(), path);
}

std::vector<std::string> sceneNames() {
    std::set<std::string> names;
    for (const auto& folder : sceneFolders()) {
        std::error_code ec;
        if (!std::filesystem::is_directory(folder, ec)) continue;
        for (const auto& e : std::filesystem::directory_iterator(folder, ec))
            if (e.path().extension() == ".json") names.insert(e.path().stem().string());
    }
    return {names.begin(), names.end()};
}

void setObjectCount(Scene& scene, int count) {
    if (count < 1)
        throw InputError("--objects", "must be at least 1, got " + std::to_string(count));
    // The placed entries keep their one object; the others share the rest.
    std::vector<SceneObject*> free;
    int placed = 0;
    for (SceneObject& o : scene.objects) {
        if (o.placed)
            ++placed;
        else
            free.push_back(&o);
    }
    if (free.empty()) return;
    if (placed > 0) count = std::max(count - placed, 1);
    int total = 0;
    for (const SceneObject* o : free) total += o->count;
    const int entries = int(free.size());
    int assigned = 0;
    for (int i = 0; i < entries; ++i) {
        SceneObject& o = *free[size_t(i)];
        const int share =
            i + 1 == entries ? count - assigned : int(std::lround(double(o.count) * count / total));
        // Every entry keeps at least one object, and rounding up must not take the ones the
        // later entries need: the total is `count` (or the number of entries, if larger).
        const int mostLeft = count - assigned - (entries - i - 1);
        o.count = std::clamp(share, 1, std::max(1, mostLeft));
        assigned += o.count;
    }
}

TriangleMesh sceneObjectMesh(const SceneObject& o, int index) {
    TriangleMesh m;
    if (!o.meshFile.empty()) {
        m = loadMesh(o.meshFile);
        cleanup(m);
        m.name = o.meshFile.string();
    } else if (o.mesh == "letters") {
        m = generate(std::string("letter:") + o.letters[size_t(index) % o.letters.size()]);
    } else {
        m = generate(o.mesh);
    }
    normalizeSize(m, o.size);
    if (o.scale != Vec3{1, 1, 1})
        for (Vec3& p : m.positions) p = {p.x * o.scale.x, p.y * o.scale.y, p.z * o.scale.z};
    return m;
}

SceneBuild buildScene(const Scene& scene) {
    const auto start = std::chrono::steady_clock::now();
    SceneBuild out{World(scene.world), {}, 0, 0, 0, 0, 0, 0, {}};
    // Each distinct mesh is made once; the World shares lattices between identical ones.
    std::map<std::string, TriangleMesh> meshes;
    auto meshFor = [&](const SceneObject& o, int index) -> const TriangleMesh& {
        std::string key = !o.meshFile.empty() ? "file:" + o.meshFile.string()
                          : o.mesh == "letters"
                              ? std::string(1, o.letters[size_t(index) % o.letters.size()])
                              : o.mesh;
        key += '@';
        key += std::to_string(o.size);
        if (o.scale != Vec3{1, 1, 1})
            key += '*' + std::to_string(o.scale.x) + ',' + std::to_string(o.scale.y) + ',' +
                   std::to_string(o.scale.z);
        auto it = meshes.find(key);
        if (it == meshes.end()) it = meshes.emplace(key, sceneObjectMesh(o, index)).first;
        return it->second;
    };

    // Errors from a mesh file, a generator or the lattice name the object they come from.
    const auto objectError = [&](size_t object, const std::string& problem) {
        return InputError(scene.source.string(),
                          "objects[" + std::to_string(object) + "]: " + problem);
    };
    // Every mesh first (each distinct one is made once), to bound the total before building.
    size_t totalVertices = 0;
    for (size_t oi = 0; oi < scene.objects.size(); ++oi) {
        const SceneObject& o = scene.objects[oi];
        for (int i = 0; i < o.count; ++i) {
            try {
                totalVertices += meshFor(o, i).vertexCount();
            } catch (const InputError& e) {
                throw objectError(oi, e.what());
            }
            if (totalVertices > kMaxSceneVertices)
                throw objectError(oi, "the scene would hold more than " +
                                          std::to_string(kMaxSceneVertices) +
                                          " mesh vertices in all (expected fewer or smaller "
                                          "objects)");
        }
    }

    const SceneLayout& L = scene.layout;
    Random rng{uint64_t(L.seed) * 0x2545F4914F6CDD1Dull + 1};
    const int perLayer = L.columns[0] * L.columns[1];
    int slot = 0;
    for (size_t oi = 0; oi < scene.objects.size(); ++oi) {
        const SceneObject& o = scene.objects[oi];
        for (int i = 0; i < o.count; ++i, slot += !o.placed) {
            const TriangleMesh& mesh = meshFor(o, i); // made above: cannot fail now
            if (o.placed) { // where it is given, at rest: no cell of the layout, no randomness
                BodySettings s = o.body;
                s.position = o.position;
                try {
                    out.bodies.push_back(out.world.addBody(mesh, s));
                } catch (const InputError& e) {
                    throw objectError(oi, e.what());
                }
                const BodyInfo info = out.world.info(out.bodies.back());
                out.vertices += info.vertices;
                out.triangles += info.triangles;
                out.cells += info.cells;
                out.particles += info.particles;
                out.nodes += info.surfaceCells * 8;
                continue;
            }
            const int layer = slot / perLayer, r = slot % perLayer;
            const int ix = r % L.columns[0], iz = r / L.columns[0];
            BodySettings s = o.body;
            const float j = L.jitter * L.spacing;
            s.position = L.origin +
                         Vec3{(float(ix) - 0.5f * float(L.columns[0] - 1)) * L.spacing,
                              float(layer) * L.spacing,
                              (float(iz) - 0.5f * float(L.columns[1] - 1)) * L.spacing} +
                         Vec3{rng.uniform(-j, j), rng.uniform(-j, j), rng.uniform(-j, j)};
            s.rotation = L.randomRotation ? rng.rotation() : Quat{};
            s.velocity =
                L.velocity +
                Vec3{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)} * L.velocityJitter;
            BodyId id;
            try {
                id = out.world.addBody(mesh, s);
            } catch (const InputError& e) {
                throw objectError(oi, e.what());
            }
            out.bodies.push_back(id);
            const BodyInfo info = out.world.info(id);
            out.vertices += info.vertices;
            out.triangles += info.triangles;
            out.cells += info.cells;
            out.particles += info.particles;
            out.nodes += info.surfaceCells * 8;
        }
    }
    for (const Plane& plane : scene.planes) out.world.addPlane(plane.normal, plane.offset);
    for (size_t n = 0; n < scene.pins.size(); ++n) {
        const ScenePin& pin = scene.pins[n];
        const auto pinError = [&](const char* field, const std::string& problem) {
            return InputError(scene.source.string(),
                              "pins[" + std::to_string(n) + "]." + field + ": " + problem);
        };
        if (pin.object < 0 || size_t(pin.object) >= out.bodies.size())
            throw pinError("object", "value " + std::to_string(pin.object) +
                                         " is out of range (the scene holds " +
                                         std::to_string(out.bodies.size()) + " objects)");
        const BodyId body = out.bodies[size_t(pin.object)];
        const BodyInfo info = out.world.info(body);
        if (out.world.settings(body).motion != BodyMotion::Dynamic)
            throw pinError("object", "object " + std::to_string(pin.object) + " is " +
                                         toString(out.world.settings(body).motion) +
                                         " (expected a dynamic object: colliders are not pinned)");
        PinId id;
        if (pin.at == ScenePin::At::Particle) {
            if (pin.index >= info.particles)
                throw pinError("particle", "value " + std::to_string(pin.index) +
                                               " is out of range (object " +
                                               std::to_string(pin.object) + " has " +
                                               std::to_string(info.particles) + " particles)");
            const Vec3 at = out.world.particles(body)[pin.index];
            id = out.world.pinParticle(body, pin.index, pin.hasTarget ? pin.target : at,
                                       pin.settings);
        } else if (pin.at == ScenePin::At::Vertex) {
            if (pin.index >= info.vertices)
                throw pinError("vertex", "value " + std::to_string(pin.index) +
                                             " is out of range (object " +
                                             std::to_string(pin.object) + " has " +
                                             std::to_string(info.vertices) + " vertices)");
            const Vec3 at = out.world.vertices(body)[pin.index];
            id =
                out.world.pinVertex(body, pin.index, pin.hasTarget ? pin.target : at, pin.settings);
        } else {
            id = out.world.pinPoint(body, pin.point, pin.settings);
            if (pin.hasTarget) out.world.setPinTarget(id, pin.target);
        }
        out.pins.push_back(id);
    }
    out.buildMilliseconds =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return out;
}

} // namespace ffd
