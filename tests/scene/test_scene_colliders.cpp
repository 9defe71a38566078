// Colliders in scene files: "motion", "position" and "scale" per object, "planes" at the top;
// bad values end in InputErrors that name the field.
#include "ffdaabb/error.h"
#include "ffdaabb/scene.h"
#include "support/test_support.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace ffd;

namespace {

const char* kStairsScene = R"({"objects": [
    {"mesh": "box", "motion": "static", "position": [0, 0.25, 0], "scale": [1, 0.5, 1]},
    {"mesh": "box", "motion": "kinematic", "position": [2, 0.1, 0], "scale": [1, 0.2, 1]},
    {"mesh": "sphere", "size": 0.5, "count": 3, "lattice": {"cells": 38}}],
  "layout": {"origin": [1, 1.5, 0], "columns": [3, 1], "spacing": 1},
  "planes": [{"normal": [0, 0, 2], "offset": -1.5}]})";

void expectError(const std::string& json, const std::vector<std::string>& parts) {
    try {
        parseScene(json, "/scenes/bad.json");
        ADD_FAILURE() << "accepted: " << json.substr(0, 200);
    } catch (const InputError& e) {
        const std::string what = e.what();
        for (const std::string& p : parts)
            EXPECT_NE(what.find(p), std::string::npos) << "missing \"" << p << "\" in: " << what;
    }
}

std::string object(const std::string& fields) {
    return R"({"objects": [{"mesh": "box")" + fields + "}]}";
}

} // namespace

TEST(SceneColliders, MotionPositionScaleAndPlanesAreRead) {
    const Scene s = parseScene(kStairsScene, "/x/stairs.json");
    ASSERT_EQ(s.objects.size(), 3u);
    EXPECT_EQ(s.objects[0].body.motion, BodyMotion::Static);
    EXPECT_EQ(s.objects[1].body.motion, BodyMotion::Kinematic);
    EXPECT_EQ(s.objects[2].body.motion, BodyMotion::Dynamic);
    EXPECT_TRUE(s.objects[0].placed);
    EXPECT_FALSE(s.objects[2].placed);
    EXPECT_EQ(s.objects[0].scale, (Vec3{1, 0.5f, 1}));
    ASSERT_EQ(s.planes.size(), 1u);
    EXPECT_EQ(s.planes[0].normal, (Vec3{0, 0, 1})); // normalised
    EXPECT_EQ(s.planes[0].offset, -1.5f);
}

TEST(SceneColliders, PlacedObjectsGoWhereTheySayAndTheLayoutPlacesTheRest) {
    SceneBuild b = buildScene(parseScene(kStairsScene, "/x/stairs.json"));
    ASSERT_EQ(b.bodies.size(), 5u);
    const Aabb step = b.world.bounds(b.bodies[0]);
    EXPECT_NEAR(step.hi.y, 0.5f, 0.05f); // a 1 x 0.5 x 1 box standing on the floor
    EXPECT_NEAR(step.lo.y, 0.0f, 0.05f);
    EXPECT_EQ(b.world.settings(b.bodies[0]).motion, BodyMotion::Static);
    EXPECT_EQ(b.world.planes().size(), 1u);
    // The layout's first cell is its first dynamic object's: x = origin - spacing.
    EXPECT_NEAR(b.world.centreOfMass(b.bodies[2]).x, 0.0f, 0.15f);
    const std::vector<Vec3> before(b.world.particles(b.bodies[0]).begin(),
                                   b.world.particles(b.bodies[0]).end());
    for (int f = 0; f < 90; ++f) b.world.step();
    EXPECT_EQ(std::vector<Vec3>(b.world.particles(b.bodies[0]).begin(),
                                b.world.particles(b.bodies[0]).end()),
              before);
    EXPECT_LT(ffd::test::deepestInside(b.world, 0.5f), 0.005);
}

TEST(SceneColliders, SetObjectCountKeepsThePlacedObjects) {
    Scene s = parseScene(kStairsScene, "/x/stairs.json");
    setObjectCount(s, 10);
    EXPECT_EQ(s.objects[0].count, 1);
    EXPECT_EQ(s.objects[1].count, 1);
    EXPECT_EQ(s.objectCount(), 10);
}

TEST(SceneColliders, TheShippedCollidersSceneParsesAndBuilds) {
    const Scene s = loadScene("colliders");
    EXPECT_EQ(s.name, "colliders");
    EXPECT_EQ(s.planes.size(), 1u);
    SceneBuild b = buildScene(s);
    EXPECT_EQ(b.bodies.size(), 16u);
}

TEST(SceneColliders, BadFieldsAreNamed) {
    expectError(object(R"(, "motion": "frozen")"),
                {"/scenes/bad.json", "objects[0].motion", "unknown motion \"frozen\"",
                 "dynamic, static or kinematic"});
    expectError(object(R"(, "motion": 3)"), {"objects[0].motion", "expected a string"});
    expectError(object(R"(, "position": [0, 1])"), {"objects[0].position", "3 numbers"});
    expectError(object(R"(, "count": 2, "position": [0, 1, 0])"),
                {"objects[0].count", "with a position", "expected 1"});
    expectError(object(R"(, "scale": [1, 0, 1])"), {"objects[0].scale", "positive"});
    expectError(R"({"objects": [{"mesh": "box"}], "planes": 3})", {"planes", "array of planes"});
    expectError(R"({"objects": [{"mesh": "box"}], "planes": [{"offset": 1}]})",
                {"planes[0].normal", "missing"});
    expectError(R"({"objects": [{"mesh": "box"}], "planes": [{"normal": [0, 0, 0]}]})",
                {"planes[0].normal", "zero"});
    expectError(R"({"objects": [{"mesh": "box"}], "planes": [{"normal": [0, 1, 0], "tilt": 1}]})",
                {"planes[0].tilt", "unknown field"});
    expectError(
        R"({"objects": [{"mesh": "box"}], "planes": [{"normal": [0, 1, 0], "offset": "a"}]})",
        {"planes[0].offset", "expected a number"});
}

TEST(SceneColliders, AColliderCannotBePinned) {
    const std::string json = R"({"objects": [{"mesh": "box", "motion": "static",
        "position": [0, 0.5, 0]}], "pins": [{"object": 0, "particle": 0}]})";
    try {
        buildScene(parseScene(json, "/x/pin.json"));
        ADD_FAILURE() << "pinned a static object";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("pins[0].object"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("static"), std::string::npos) << e.what();
    }
}
