// Scene files as input: every kind of bad file or field ends in an InputError that names the
// file, the field (as a path like objects[0].lattice.cells), the value and what was expected;
// nothing crashes, however deep or large the garbage.
#include "ffdaabb/error.h"
#include "ffdaabb/scene.h"
#include "support/test_support.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

using namespace ffd;
using ffd::test::ScopedEnv;
using ffd::test::TempDir;
using ffd::test::writeFile;
namespace fs = std::filesystem;

namespace {

// A small valid scene with `patch` spliced into the object (a field list that starts with a
// comma, or empty).
std::string sceneWith(const std::string& objectPatch, const std::string& topPatch = "") {
    return R"({"name": "t", "objects": [{"mesh": "sphere", "count": 2)" + objectPatch + "}]" +
           topPatch + "}";
}

// Parses `json` and expects an InputError whose message contains every one of `parts`.
void expectError(const std::string& json, const std::vector<std::string>& parts,
                 const fs::path& source = "/scenes/bad.json") {
    try {
        parseScene(json, source);
        ADD_FAILURE() << "accepted: " << json.substr(0, 200);
    } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_EQ(e.source(), source.string()) << what;
        for (const std::string& p : parts)
            EXPECT_NE(what.find(p), std::string::npos) << "missing \"" << p << "\" in: " << what;
    }
}

void expectLoadError(const fs::path& path, const std::vector<std::string>& parts) {
    try {
        loadScene(path.string());
        ADD_FAILURE() << "accepted " << path;
    } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find(path.string()), std::string::npos) << what;
        for (const std::string& p : parts)
            EXPECT_NE(what.find(p), std::string::npos) << "missing \"" << p << "\" in: " << what;
    }
}

} // namespace

TEST(SceneInput, TheShippedScenesParse) {
    for (const std::string name : {"alphabets", "spheres", "teapots", "buddhas"}) {
        const Scene s = loadScene(name);
        EXPECT_EQ(s.name, name);
        EXPECT_GT(s.objectCount(), 0);
    }
    const Scene s = parseScene(sceneWith(""), "/x/ok.json");
    EXPECT_EQ(s.objectCount(), 2);
}

// alphabets_x10: the alphabet experiment on ten times the floor, the same objects, spacing,
// lattice, world and number of layers as the paper's scene.
TEST(SceneInput, AlphabetsTimesTenIsThePaperSceneOnTenTimesTheFloor) {
    const Scene paper = loadScene("alphabets"), big = loadScene("alphabets_x10");
    EXPECT_EQ(big.objectCount(), 1650);
    EXPECT_EQ(big.objectCount(), 10 * paper.objectCount());
    EXPECT_EQ(big.layout.columns[0], 19);
    EXPECT_EQ(big.layout.columns[1], 18);
    EXPECT_EQ(big.layout.spacing, paper.layout.spacing);
    auto layers = [](const Scene& s) {
        const int perLayer = s.layout.columns[0] * s.layout.columns[1];
        return (s.objectCount() + perLayer - 1) / perLayer;
    };
    EXPECT_EQ(layers(big), layers(paper));
    ASSERT_EQ(big.objects.size(), 1u);
    EXPECT_EQ(big.objects[0].size, paper.objects[0].size);
    EXPECT_EQ(big.objects[0].body.lattice.targetCells, paper.objects[0].body.lattice.targetCells);
    EXPECT_EQ(big.world.frameStep, paper.world.frameStep);
    EXPECT_EQ(big.world.substeps, paper.world.substeps);
}

TEST(SceneInput, NotJsonEmptyAndTruncatedFilesNameTheFile) {
    expectError("", {"not valid JSON"});
    expectError("   \n", {"not valid JSON"});
    expectError("{\"objects\": [", {"not valid JSON"});
    expectError("objects: sphere", {"not valid JSON"});
    expectError("{\"objects\": []} trailing", {"not valid JSON"});
    expectError(std::string("{\"name\": \"a\0b\"}", 15), {"not valid JSON"});
    expectError("{\"name\": \"\xff\xfe\"}", {"not valid JSON"}); // not UTF-8
    // A number beyond double's range is a JSON error too, not an internal one.
    expectError(sceneWith(", \"size\": 1e999"), {"not valid JSON", "1e999"});
    // The top level must be an object with a non-empty objects array.
    expectError("[1, 2]", {"expected an object, got an array"});
    expectError("42", {"expected an object"});
    expectError("{}", {"objects", "missing"});
    expectError("{\"objects\": []}", {"objects", "non-empty array"});
    expectError("{\"objects\": {\"mesh\": \"sphere\"}}", {"objects", "non-empty array"});
}

TEST(SceneInput, UnknownFieldsAreErrorsThatListTheKnownOnes) {
    expectError(sceneWith("", ", \"wrold\": {}"), {"wrold", "unknown field", "world"});
    expectError(sceneWith(", \"colour\": \"red\""),
                {"objects[0].colour", "unknown field", "material"});
    expectError(sceneWith(", \"lattice\": {\"cels\": 3}"),
                {"objects[0].lattice.cels", "unknown field", "cells"});
    expectError(sceneWith(", \"material\": {\"stiffnes\": 1}"),
                {"objects[0].material.stiffnes", "stiffness"});
    expectError(sceneWith("", ", \"world\": {\"gravty\": [0, 0, 0]}"), {"world.gravty", "gravity"});
    expectError(sceneWith("", ", \"layout\": {\"orgin\": [0, 0, 0]}"), {"layout.orgin", "origin"});
    expectError(sceneWith(", \"mesh\": {\"file\": \"/etc/hostname\", \"scale\": 2}"),
                {"objects[0].mesh.scale", "unknown field"});
}

TEST(SceneInput, WrongTypesNameTheFieldTheTypeAndTheValue) {
    expectError(sceneWith(", \"count\": \"many\""),
                {"objects[0].count", "expected an integer", "a string", "\"many\""});
    expectError(sceneWith(", \"count\": 2.5"), {"objects[0].count", "expected an integer", "2.5"});
    expectError(sceneWith(", \"size\": true"), {"objects[0].size", "expected a number", "true"});
    expectError(sceneWith(", \"size\": null"), {"objects[0].size", "null"});
    expectError(sceneWith("", ", \"world\": {\"floor\": 1}"),
                {"world.floor", "expected true or false", "an integer"});
    expectError(sceneWith("", ", \"world\": {\"gravity\": [0, -9.81]}"),
                {"world.gravity", "array of 3 numbers", "[0,-9.81]"});
    expectError(sceneWith("", ", \"world\": {\"gravity\": [0, \"down\", 0]}"),
                {"world.gravity", "array of 3 numbers"});
    expectError(sceneWith("", ", \"world\": {\"mode\": 3}"), {"world.mode", "expected a string"});
    expectError(sceneWith("", ", \"world\": []"), {"world", "expected an object, got an array"});
    expectError(sceneWith(", \"lattice\": 38"), {"objects[0].lattice", "expected an object"});
    expectError(sceneWith(", \"mesh\": 7"), {"objects[0].mesh", "generator name", "7"});
    expectError(sceneWith(", \"mesh\": {}"), {"objects[0].mesh.file", "missing"});
    expectError(sceneWith(", \"mesh\": {\"file\": 3}"), {"objects[0].mesh.file", "a string"});
    expectError(sceneWith("", ", \"layout\": {\"columns\": [5]}"),
                {"layout.columns", "two integers 1..10000", "[5]"});
    expectError("{\"objects\": [3]}", {"objects[0]", "expected an object, got an integer"});
    expectError("{\"name\": 5, \"objects\": [{}]}", {"name", "expected a string", "5"});
}

TEST(SceneInput, OutOfRangeValuesNameTheRange) {
    struct Case {
        std::string object, top;
        std::vector<std::string> parts;
    };
    const std::vector<Case> cases = {
        {", \"count\": 0", "", {"objects[0].count", "value 0", "1..1000000"}},
        {", \"count\": -3", "", {"objects[0].count", "-3"}},
        {", \"size\": 0", "", {"objects[0].size", "1e-4..1e4"}},
        {", \"size\": 1e5", "", {"objects[0].size", "100000"}},
        {", \"lattice\": {\"cells\": 0}", "", {"objects[0].lattice.cells", "1..1000000"}},
        {", \"lattice\": {\"cell_size\": -1}", "", {"objects[0].lattice.cell_size", "> 0"}},
        {", \"lattice\": {\"cells\": 5, \"cell_size\": 0.1}",
         "",
         {"objects[0].lattice.cell_size", "only one of"}},
        {", \"lattice\": {\"box_skin\": 0.5}", "", {"objects[0].lattice.box_skin", "0..0.25"}},
        {", \"material\": {\"stiffness\": 0}", "", {"objects[0].material.stiffness", "0 <"}},
        {", \"material\": {\"region_half_width\": 9}",
         "",
         {"objects[0].material.region_half_width", "1..4"}},
        {", \"material\": {\"restitution\": 1.5}", "", {"material.restitution", "0..1"}},
        {", \"material\": {\"density\": -5}", "", {"material.density", "-5"}},
        {", \"material\": {\"model\": \"rigid\"}", "", {"material.model", "rigid", "mass-spring"}},
        {"", ", \"world\": {\"frame_step\": 0}", {"world.frame_step", "0 < frame_step <= 1"}},
        {"", ", \"world\": {\"frame_step\": 2}", {"world.frame_step"}},
        {"", ", \"world\": {\"substeps\": 0}", {"world.substeps", "1..1000"}},
        {"", ", \"world\": {\"threads\": -1}", {"world.threads", "1024"}},
        {"", ", \"world\": {\"gravity\": [0, -1e5, 0]}", {"world.gravity", "at most 10000"}},
        {"", ", \"world\": {\"mode\": \"fast\"}", {"world.mode", "fast", "enhanced"}},
        {"", ", \"world\": {\"contact_skin\": 2}", {"world.contact_skin", "0..1"}},
        {"",
         ", \"world\": {\"max_separation_speed\": -1}",
         {"world.max_separation_speed", "-1", "0 (no bound)..1e4 m/s"}},
        {"",
         ", \"world\": {\"push_out_speed\": 2e4}",
         {"world.push_out_speed", "20000", "0 (no bound)..1e4 m/s"}},
        {"",
         ", \"world\": {\"overlap_recovery_speed\": -0.5}",
         {"world.overlap_recovery_speed", "-0.5", "0 (at once)..1e4 m/s"}},
        {"",
         ", \"world\": {\"overlap_recovery_max_speed\": -2}",
         {"world.overlap_recovery_max_speed", "-2", "0 (no bound)..1e4 m/s"}},
        {"", ", \"layout\": {\"spacing\": 0}", {"layout.spacing", "1e-4..1e4"}},
        {"", ", \"layout\": {\"jitter\": 0.9}", {"layout.jitter", "0..0.5"}},
        {"", ", \"layout\": {\"seed\": -1}", {"layout.seed", "0..2147483647"}},
        {"", ", \"layout\": {\"seed\": 99999999999}", {"layout.seed", "99999999999"}},
        {"", ", \"layout\": {\"columns\": [0, 5]}", {"layout.columns"}},
        {"", ", \"layout\": {\"origin\": [0, 1e7, 0]}", {"layout.origin"}},
    };
    for (const Case& c : cases) expectError(sceneWith(c.object, c.top), c.parts);
}

TEST(SceneInput, GeneratorNamesAreCheckedWhenParsed) {
    expectError(sceneWith(", \"mesh\": \"cube\""),
                {"objects[0].mesh", "unknown generator", "cube"});
    // "alphabet" is mesh-info's name for the 26 letters; scenes say "letters".
    expectError(sceneWith(", \"mesh\": \"alphabet\""), {"objects[0].mesh", "alphabet", "letters"});
    expectError(sceneWith(", \"mesh\": \"icosphere:9\""),
                {"objects[0].mesh", "icosphere:9", "icosphere:0..icosphere:8"});
    expectError(sceneWith(", \"mesh\": \"icosphere:\""), {"objects[0].mesh", "icosphere:0"});
    expectError(sceneWith(", \"mesh\": \"icosphere:2x\""), {"objects[0].mesh"});
    expectError(sceneWith(", \"mesh\": \"teapot:0\""), {"teapot:1..teapot:256"});
    expectError(sceneWith(", \"mesh\": \"teapot:-4\""), {"teapot:1..teapot:256"});
    expectError(sceneWith(", \"mesh\": \"letter:a\""), {"letter:A..letter:Z"});
    expectError(sceneWith(", \"mesh\": \"letter:AB\""), {"letter:A..letter:Z"});
    expectError(sceneWith(", \"mesh\": \"sphere\", \"letters\": \"AB\""),
                {"objects[0].letters", "only for"});
    expectError(sceneWith(", \"mesh\": \"letters\", \"letters\": \"Ab\""),
                {"objects[0].letters", "outside A-Z"});
    expectError(sceneWith(", \"mesh\": \"letters\", \"letters\": \"\""),
                {"objects[0].letters", "at least one"});
    for (const std::string ok : {"sphere", "teapot", "dragon", "icosphere:0", "icosphere:8",
                                 "teapot:1", "teapot:256", "letter:Q", "letters"})
        EXPECT_NO_THROW(parseScene(sceneWith(", \"mesh\": \"" + ok + "\""), "/x/s.json")) << ok;
}

TEST(SceneInput, MeshFilesMustExistAndBeFiles) {
    TempDir dir;
    fs::create_directories(dir / "models" / "sub.obj");
    writeFile(dir / "models" / "ok.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                         "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    const fs::path scene = dir / "scene.json";
    // Relative paths are resolved against the scene file's folder.
    const Scene s = parseScene(sceneWith(", \"mesh\": {\"file\": \"models/ok.obj\"}"), scene);
    EXPECT_EQ(s.objects[0].meshFile, dir / "models" / "ok.obj");
    expectError(sceneWith(", \"mesh\": {\"file\": \"models/absent.obj\"}"),
                {"objects[0].mesh.file", "models/absent.obj", "does not exist",
                 (dir / "models" / "absent.obj").string()},
                scene);
    expectError(sceneWith(", \"mesh\": {\"file\": \"models/sub.obj\"}"),
                {"objects[0].mesh.file", "is a folder"}, scene);
    expectError(sceneWith(", \"mesh\": {\"file\": \"\"}"), {"objects[0].mesh.file", "empty"},
                scene);
}

TEST(SceneInput, ModelsAreLookedUpInTheModelsFolder) {
    // {"model": name} follows $FFDAABB_MODELS, wherever the scene file is.
    TempDir dir;
    fs::create_directories(dir / "models" / "sub.obj");
    writeFile(dir / "models" / "ok.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                         "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    const ScopedEnv env("FFDAABB_MODELS", (dir / "models").c_str());
    const fs::path scene = "/elsewhere/scene.json";
    const Scene s = parseScene(sceneWith(", \"mesh\": {\"model\": \"ok.obj\"}"), scene);
    EXPECT_EQ(s.objects[0].meshFile, dir / "models" / "ok.obj");
    expectError(sceneWith(", \"mesh\": {\"model\": \"absent.ply.gz\"}"),
                {"objects[0].mesh.model", "absent.ply.gz", "does not exist",
                 (dir / "models" / "absent.ply.gz").string(), "FFDAABB_MODELS"},
                scene);
    expectError(sceneWith(", \"mesh\": {\"model\": \"sub.obj\"}"),
                {"objects[0].mesh.model", "is a folder"}, scene);
    expectError(sceneWith(", \"mesh\": {\"model\": \"\"}"), {"objects[0].mesh.model", "empty"},
                scene);
    for (const std::string outside : {"../ok.obj", "/etc/hostname", "sub.obj/../../ok.obj"})
        expectError(sceneWith(", \"mesh\": {\"model\": \"" + outside + "\"}"),
                    {"objects[0].mesh.model", outside, "not inside the models folder"}, scene);
    expectError(sceneWith(", \"mesh\": {\"model\": \"ok.obj\", \"file\": \"ok.obj\"}"),
                {"objects[0].mesh.model", "not both"}, scene);
    expectError(sceneWith(", \"mesh\": {\"model\": 3}"), {"objects[0].mesh.model", "a string"},
                scene);
}

TEST(SceneInput, ErrorsWhileBuildingNameTheObject) {
    TempDir dir;
    // A mesh file that exists but is malformed fails when the scene is built: the message
    // names the scene, the object and the mesh file.
    writeFile(dir / "broken.obj", "v 0 0 0\nv 1 0 0\nf 1 2 7\n");
    writeFile(dir / "scene.json", sceneWith(", \"mesh\": {\"file\": \"broken.obj\"}"));
    const Scene s = loadScene((dir / "scene.json").string());
    try {
        buildScene(s);
        ADD_FAILURE() << "built a scene with a broken mesh";
    } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_EQ(e.source(), (dir / "scene.json").string());
        EXPECT_NE(what.find("objects[0]"), std::string::npos) << what;
        EXPECT_NE(what.find((dir / "broken.obj").string()), std::string::npos) << what;
    }
    // A cell size far too small for the object: the lattice refuses it, named by object.
    writeFile(dir / "tiny.json", sceneWith(", \"lattice\": {\"cell_size\": 1e-6}"));
    try {
        buildScene(loadScene((dir / "tiny.json").string()));
        ADD_FAILURE() << "built a lattice of 1e-6 m cells";
    } catch (const InputError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("objects[0]"), std::string::npos) << what;
        EXPECT_NE(what.find("cellSize"), std::string::npos) << what;
    }
}

TEST(SceneInput, FilesThatAreNotScenes) {
    TempDir dir;
    expectLoadError(dir / "absent.json", {"does not exist"});
    fs::create_directories(dir / "folder.json");
    expectLoadError(dir / "folder.json", {"is a folder"});
    ASSERT_EQ(::mkfifo((dir / "pipe.json").c_str(), 0600), 0);
    expectLoadError(dir / "pipe.json", {"not a regular file"});
    writeFile(dir / "empty.json", "");
    expectLoadError(dir / "empty.json", {"is empty"});
    // A file far larger than any scene is refused before it is read.
    {
        std::FILE* f = std::fopen((dir / "huge.json").c_str(), "wb");
        ASSERT_NE(f, nullptr);
        ASSERT_EQ(::ftruncate(::fileno(f), off_t(64) << 20), 0);
        std::fclose(f);
    }
    expectLoadError(dir / "huge.json", {"16 MiB"});
    writeFile(dir / "binary.json", std::string("\x89PNG\r\n\x1a\n\0\0\0", 11));
    expectLoadError(dir / "binary.json", {"not valid JSON"});
    // A name that is neither a file nor a shipped scene lists the shipped ones.
    try {
        loadScene("no-such-scene");
        ADD_FAILURE();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("spheres"), std::string::npos) << e.what();
    }
}

TEST(SceneInput, DeeplyNestedGarbageIsRefusedWithoutRecursing) {
    // nlohmann's parser is iterative, but quoting a value in a message (dump) recurses: a
    // deep value in any field used to overflow the stack. 200,000 levels is 400 KB of text.
    const int depth = 200000;
    const std::string deepArray = std::string(depth, '[') + std::string(depth, ']');
    expectError("{\"name\": " + deepArray + ", \"objects\": [{}]}", {"nested", "64"});
    expectError(sceneWith(", \"size\": " + deepArray), {"nested"});
    std::string deepObject;
    for (int i = 0; i < depth; ++i) deepObject += "{\"a\":";
    deepObject += "1" + std::string(depth, '}');
    expectError(deepObject, {"nested"});
    // Unbalanced deep garbage is refused as well (by the depth limit or as bad JSON).
    expectError(std::string(depth, '['), {"bad.json"});
    // Moderate nesting inside an unknown field is an ordinary unknown-field error.
    expectError(sceneWith(", \"extra\": [[[[[[[[1]]]]]]]]"), {"objects[0].extra", "unknown"});
}

TEST(SceneInput, ObjectCountsAreBounded) {
    expectError(sceneWith(", \"count\": 1000001"), {"objects[0].count", "1..1000000"});
    // In all, a scene holds at most 100,000 objects (the CLI's --objects limit).
    const std::string many = R"({"objects": [{"mesh": "sphere", "count": 60000},
                                             {"mesh": "sphere", "count": 60000}]})";
    expectError(many, {"objects[1].count", "120000", "100000"});
    Scene s = parseScene(R"({"objects": [{"mesh": "sphere", "count": 100000}]})", "/x/s.json");
    EXPECT_EQ(s.objectCount(), 100000);
}

TEST(SceneInput, RandomMutationsNeverCrash) {
    // Byte-level mutations of a full scene: each parse either succeeds or throws InputError
    // (any other exception fails the test). The fuzz target does this at scale.
    const std::string base = R"({"name": "m", "world": {"frame_step": 0.01, "substeps": 2,
        "gravity": [0, -9.81, 0], "mode": "previous"}, "objects": [{"mesh": "letters",
        "letters": "AB", "count": 3, "size": 0.5, "lattice": {"resolution": 4},
        "material": {"model": "mass-spring", "damping": 5}}], "layout": {"origin": [0, 1, 0],
        "columns": [2, 2], "spacing": 1.1, "seed": 7}})";
    std::mt19937 rng(7);
    const std::string alphabet = "{}[]\",:.-+e0123456789tfnul \\x";
    int accepted = 0;
    for (int i = 0; i < 5000; ++i) {
        std::string s = base;
        const int edits = 1 + int(rng() % 4);
        for (int k = 0; k < edits; ++k) {
            const size_t at = rng() % s.size();
            switch (rng() % 3) {
            case 0:
                s[at] = alphabet[rng() % alphabet.size()];
                break;
            case 1:
                s.erase(at, 1 + rng() % 8);
                break;
            default:
                s.insert(at, 1, alphabet[rng() % alphabet.size()]);
                break;
            }
        }
        try {
            parseScene(s, "/x/m.json");
            ++accepted;
        } catch (const InputError&) {
        }
    }
    EXPECT_GT(accepted, 50); // some mutations keep the scene valid (digits, spaces)
}

TEST(SceneInput, SetObjectCountHitsTheTotal) {
    Scene s = parseScene(R"({"objects": [{"mesh": "sphere"}, {"mesh": "teapot"},
                                          {"mesh": "sphere"}, {"mesh": "dragon"}]})",
                         "/x/s.json");
    // Rounding each entry's share up used to overshoot: 4 entries of 1, asked for 6, gave 7.
    for (int count : {1, 3, 4, 6, 7, 100, 99999}) {
        setObjectCount(s, count);
        EXPECT_EQ(s.objectCount(), std::max(count, 4)) << count;
        for (const SceneObject& o : s.objects) EXPECT_GE(o.count, 1);
    }
    Scene one = loadScene("spheres");
    setObjectCount(one, 7);
    EXPECT_EQ(one.objectCount(), 7);
    EXPECT_THROW(setObjectCount(one, 0), InputError);
}

TEST(SceneInput, UnknownFieldNamesAreShownSafely) {
    // A field name with a terminal escape and a newline, and a very long one.
    expectError("{\"objects\": [{\"mesh\": \"sphere\"}], \"a\\u001b[2Jb\\nc\": 1}",
                {"a?[2Jb?c", "unknown field"});
    try {
        parseScene("{\"objects\": [{\"mesh\": \"sphere\"}], \"" + std::string(5000, 'k') + "\": 1}",
                   "/x/s.json");
        ADD_FAILURE();
    } catch (const InputError& e) {
        EXPECT_LT(std::string(e.what()).size(), 300u) << e.what();
    }
}

TEST(SceneInput, TheTotalVertexCountIsBoundedBeforeBuilding) {
    // 300 icospheres of 655,362 vertices (197 million): refused at once, not after gigabytes.
    const Scene s = parseScene(R"({"objects": [{"mesh": "sphere", "count": 10},
                                  {"mesh": "icosphere:8", "count": 300}]})",
                               "/x/big.json");
    const auto start = std::chrono::steady_clock::now();
    try {
        buildScene(s);
        ADD_FAILURE() << "built 197 million vertices";
    } catch (const InputError& e) {
        EXPECT_NE(
            std::string(e.what()).find("objects[1]: the scene would hold more than 134217728"),
            std::string::npos)
            << e.what();
    }
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(60));
}
