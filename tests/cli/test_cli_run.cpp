// ffdaabb run / bench / render: contract keys, exports, bad scenes and flags.
#include "ffdaabb/profile.h"
#include "test_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <regex>

using namespace ffd::test;
using ffd::StageInfo;
using ffd::stageTable;
using ffd::TableColumnInfo;
using ffd::tableColumns;
namespace fs = std::filesystem;

TEST(CliRun, StatsHaveEveryContractKeyAndObjExportHasOneGroupPerBody) {
    TempDir dir;
    const RunResult r =
        runCli({"run", "--scene", "spheres", "--objects", "12", "--frames", "20", "--stats",
                (dir / "s.json").string(), "--export-obj", (dir / "m.obj").string()});
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(readFile(dir / "s.json"));
    for (const char* key : {"scene", "mode", "objects", "vertices", "triangles", "cells", "frames",
                            "stage_ms", "frames_per_second", "candidate_pairs", "contacts",
                            "max_contact_depth", "interpenetration", "state_hash", "finite"})
        EXPECT_TRUE(j.contains(key)) << key;
    // Every stage of the library's table, and every Table 1 column as the sum of its stages.
    ASSERT_TRUE(j["stage_ms"].contains("total"));
    double stages = 0;
    for (const StageInfo& s : stageTable()) {
        ASSERT_TRUE(j["stage_ms"].contains(s.key)) << s.key;
        stages += j["stage_ms"][s.key].get<double>();
    }
    EXPECT_LE(stages, j["stage_ms"]["total"].get<double>() * 1.0001);
    for (const TableColumnInfo& c : tableColumns()) {
        ASSERT_TRUE(j["table1_ms"].contains(c.key)) << c.key;
        double sum = 0;
        for (const StageInfo& s : stageTable())
            if (s.column == c.column) sum += j["stage_ms"][s.key].get<double>();
        EXPECT_NEAR(j["table1_ms"][c.key].get<double>(), sum, 1e-9 + 1e-9 * sum) << c.key;
    }
    EXPECT_EQ(j["objects"].get<int>(), 12);
    EXPECT_EQ(j["vertices"].get<int>(), 12 * 162);
    EXPECT_EQ(j["frames"].get<int>(), 20);
    EXPECT_TRUE(j["finite"].get<bool>());
    EXPECT_EQ(j["state_hash"].get<std::string>().size(), 16u);
    // One group per body, each with the sphere's 162 vertices and 320 faces.
    std::ifstream obj(dir / "m.obj");
    std::string line;
    int groups = 0, vertices = 0, faces = 0, maxIndex = 0;
    std::vector<int> perGroup;
    while (std::getline(obj, line)) {
        if (line.rfind("o body_", 0) == 0) {
            EXPECT_EQ(line, "o body_" + std::to_string(groups));
            ++groups;
            perGroup.push_back(0);
        } else if (line.rfind("v ", 0) == 0) {
            ++vertices, ++perGroup.back();
        } else if (line.rfind("f ", 0) == 0) {
            ++faces;
            int a, b, c;
            ASSERT_EQ(std::sscanf(line.c_str(), "f %d %d %d", &a, &b, &c), 3);
            maxIndex = std::max({maxIndex, a, b, c});
        }
    }
    EXPECT_EQ(groups, 12);
    EXPECT_EQ(vertices, 12 * 162);
    EXPECT_EQ(faces, 12 * 320);
    EXPECT_EQ(maxIndex, vertices);
    for (int n : perGroup) EXPECT_EQ(n, 162);
}

// `run` judges contacts by the meshes (vertices inside other objects' closed meshes, by winding
// number), not by the pipeline's node/box depths: two spheres created half a metre into each
// other with nothing pushing them apart (no gravity, collisions off) report vertices deep inside
// in every sample; two created apart report none.
TEST(CliRun, StatsReportTheMeshesInterpenetration) {
    TempDir dir;
    auto measure = [&](double spacing) {
        writeFile(dir / "pair.json",
                  R"({"name": "pair", "world": {"gravity": [0, 0, 0], "mode": "none",
                       "floor": false},
                      "objects": [{"mesh": "sphere", "count": 2, "size": 1.0}],
                      "layout": {"origin": [0, 2, 0], "columns": [2, 1], "spacing": )" +
                      std::to_string(spacing) + "}}");
        const RunResult r = runCli({"run", "--scene", (dir / "pair.json").string(), "--frames", "6",
                                    "--measure-every", "2", "--stats", (dir / "s.json").string()});
        EXPECT_EQ(r.status, 0) << r.err;
        EXPECT_NE(r.out.find("interpenetration"), std::string::npos) << r.out;
        return nlohmann::json::parse(readFile(dir / "s.json"))["interpenetration"];
    };
    const auto inside = measure(0.5);
    EXPECT_EQ(inside["samples"].get<int>(), 3);
    EXPECT_EQ(inside["sample_every"].get<int>(), 2);
    EXPECT_GT(inside["max_inside_vertices"].get<int>(), 20);
    EXPECT_GT(inside["max_depth_m"].get<double>(), 0.1);
    EXPECT_NEAR(inside["max_depth_relative"].get<double>(), inside["max_depth_m"].get<double>(),
                1e-9); // size 1 m
    // The deepest vertex: of one sphere, inside the other.
    const auto& deepest = inside["deepest_vertex"];
    ASSERT_TRUE(deepest.is_object()) << inside;
    EXPECT_EQ(deepest["object"].get<int>() + deepest["inside"].get<int>(), 1) << deepest;
    EXPECT_GE(deepest["vertex"].get<int>(), 0);
    const auto apart = measure(1.5);
    EXPECT_EQ(apart["max_inside_vertices"].get<int>(), 0);
    EXPECT_EQ(apart["max_depth_m"].get<double>(), 0.0);
    EXPECT_TRUE(apart["deepest_vertex"].is_null()) << apart;
}

TEST(CliRun, SameRunTwiceGivesTheSameHash) {
    TempDir dir;
    auto hash = [&] {
        const RunResult r = runCli({"run", "--scene", "teapots", "--objects", "6", "--frames", "30",
                                    "--quiet", "--stats", (dir / "s.json").string()});
        EXPECT_EQ(r.status, 0) << r.err;
        return nlohmann::json::parse(readFile(dir / "s.json"))["state_hash"].get<std::string>();
    };
    EXPECT_EQ(hash(), hash());
}

TEST(CliRun, BadScenesExitTwoNamingTheField) {
    TempDir dir;
    struct Case {
        const char* json;
        const char* field;
    };
    const Case cases[] = {
        {R"({"objects": [{"mesh": "sphere"}], "wrold": {}})", "wrold"},
        {R"({"objects": [{"mesh": "sphere", "count": "ten"}]})", "objects[0].count"},
        {R"({"objects": [{"mesh": "sphere", "lattice": {"cells": 0}}]})",
         "objects[0].lattice.cells"},
        {R"({"world": {"substeps": 0}, "objects": [{"mesh": "sphere"}]})", "world.substeps"},
        {R"({"objects": [{"mesh": {"file": "no_such_mesh.obj"}}]})", "objects[0].mesh.file"},
        {R"({"objects": [{"mesh": "cube"}]})", "objects[0].mesh"},
        {R"({"objects": []})", "objects"},
        {R"({"objects": [{"mesh": "sphere", "material": {"friction": -1}}]})",
         "objects[0].material.friction"},
        {R"({"objects": [{"mesh": "sphere"}], "world": {"mode": "fast"}})", "world.mode"},
        {R"({"objects": [{"mesh": "sphere"}], "layout": {"columns": [0, 3]}})", "layout.columns"},
        {R"({"objects": [{"mesh": "sphere"}], "world": {"gravity": [0, "down", 0]}})",
         "world.gravity"},
    };
    int n = 0;
    for (const Case& c : cases) {
        const fs::path file = dir / ("bad" + std::to_string(n++) + ".json");
        writeFile(file, c.json);
        const RunResult r = runCli({"run", "--scene", file.string(), "--frames", "1", "--stats",
                                    (dir / "never.json").string()});
        EXPECT_EQ(r.status, 2) << c.json;
        EXPECT_NE(r.err.find(file.string()), std::string::npos) << r.err;
        EXPECT_NE(r.err.find(c.field), std::string::npos) << c.field << ": " << r.err;
        EXPECT_FALSE(fs::exists(dir / "never.json"));
    }
    writeFile(dir / "garbage.json", "{not json");
    const RunResult r = runCli({"run", "--scene", (dir / "garbage.json").string()});
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("JSON"), std::string::npos) << r.err;
}

TEST(CliRun, BadFlagsExitTwo) {
    for (const std::vector<std::string>& args :
         {std::vector<std::string>{"run", "--scene", "spheres", "--frames", "0"},
          std::vector<std::string>{"run", "--scene", "spheres", "--objects", "-3"},
          std::vector<std::string>{"run", "--scene", "spheres", "--mode", "sideways"},
          std::vector<std::string>{"run", "--scene", "spheres", "--threads", "x"},
          std::vector<std::string>{"run"},
          std::vector<std::string>{"run", "--scene", "nosuchscene"},
          std::vector<std::string>{"bench", "--frames", "-1"},
          std::vector<std::string>{"render", "--scene", "spheres", "--out", "/tmp/x.mp4",
                                   "--overlay", "rainbows"},
          std::vector<std::string>{"render", "--scene", "spheres", "--out", "/tmp/x.mp4",
                                   "--camera", "1,2:3"},
          std::vector<std::string>{"render", "--scene", "spheres", "--out", "/tmp/x.mp4", "--width",
                                   "5"}}) {
        const RunResult r = runCli(args);
        EXPECT_EQ(r.status, 2) << args.back() << ": " << r.err;
        EXPECT_FALSE(r.err.empty());
    }
}

TEST(CliBench, WritesTablesAndFigureWithIdenticalModes) {
    TempDir dir;
    const RunResult r =
        runCli({"bench", "--frames", "10", "--warmup", "2", "--objects", "8", "--scenes",
                "spheres,teapots", "--out", (dir / "b").string(), "--quiet"});
    ASSERT_EQ(r.status, 0) << r.err;
    for (const char* f :
         {"table1.md", "table1.csv", "table2.md", "fig4.csv", "fig4.png", "summary.json"})
        EXPECT_TRUE(fs::exists(dir / "b" / f)) << f;
    const auto j = nlohmann::json::parse(readFile(dir / "b" / "summary.json"));
    for (const char* scene : {"spheres", "teapots"}) {
        EXPECT_TRUE(j["scenes"][scene]["identical_trajectories"].get<bool>()) << scene;
        EXPECT_GT(j["scenes"][scene]["enhanced"]["frames_per_second"].get<double>(), 0);
        // The profile's counts, under --stats's names. The two modes find identical contacts;
        // only their candidate pairs differ (previous has no bounding-sphere test).
        EXPECT_GE(j["scenes"][scene]["previous"]["candidate_pairs"].get<double>(),
                  j["scenes"][scene]["enhanced"]["candidate_pairs"].get<double>());
        for (const char* key : {"potential_pairs", "box_pairs", "contact_box_pairs", "contacts",
                                "floor_contacts", "sleeping_bodies", "max_contact_depth"}) {
            const auto& previous = j["scenes"][scene]["previous"][key];
            ASSERT_TRUE(previous.is_number()) << scene << " " << key;
            EXPECT_EQ(previous, j["scenes"][scene]["enhanced"][key]) << scene << " " << key;
        }
    }
    const std::string table1 = readFile(dir / "b" / "table1.md");
    EXPECT_NE(table1.find("334.28"), std::string::npos); // the paper's spheres total beside ours
    EXPECT_NE(readFile(dir / "b" / "table2.md").find("6400"), std::string::npos);
}

TEST(CliBench, DifferentTrajectoriesExitOneNamingTheSceneAndHashes) {
    // `none` lets the spheres pass through each other where `enhanced` makes them collide: a real
    // mismatch of the two trajectories, which bench must report and fail on.
    TempDir dir;
    const RunResult r =
        runCli({"bench", "--frames", "10", "--warmup", "2", "--objects", "8", "--scenes", "spheres",
                "--modes", "enhanced,none", "--out", (dir / "b").string(), "--quiet"});
    EXPECT_EQ(r.status, 1) << r.err;
    // The results are still written, with the verdict in them.
    const auto j = nlohmann::json::parse(readFile(dir / "b" / "summary.json"));
    EXPECT_EQ(j["modes"], (nlohmann::json{"enhanced", "none"}));
    const auto& s = j["scenes"]["spheres"];
    EXPECT_GT(s["enhanced"]["contacts"].get<double>(), 0); // the bodies did touch
    EXPECT_EQ(s["none"]["contacts"].get<double>(), 0);
    EXPECT_FALSE(s["identical_trajectories"].get<bool>());
    const std::string a = s["enhanced"]["state_hash"], b = s["none"]["state_hash"];
    ASSERT_NE(a, b);
    // One message, printed even with --quiet, naming the scene and both hashes.
    EXPECT_EQ(r.out, "");
    EXPECT_NE(r.err.find("scene spheres"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("trajectories differ"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("enhanced ends with state hash " + a), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("none with " + b), std::string::npos) << r.err;
    EXPECT_NE(readFile(dir / "b" / "fig4.csv").find("scene,fps_enhanced,fps_none,"),
              std::string::npos);
    EXPECT_NE(readFile(dir / "b" / "table1.md").find("ours, none"), std::string::npos);

    // Two modes that find the same contacts (brute is the oracle) agree: exit 0.
    const RunResult same =
        runCli({"bench", "--frames", "10", "--warmup", "2", "--objects", "8", "--scenes", "spheres",
                "--modes", "brute,enhanced", "--out", (dir / "c").string(), "--quiet"});
    EXPECT_EQ(same.status, 0) << same.err;
    EXPECT_EQ(same.err, "");
}
