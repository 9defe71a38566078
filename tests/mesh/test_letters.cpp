#include "ffdaabb/error.h"
#include "ffdaabb/generators.h"
#include "ffdaabb/mesh.h"

#include "support/test_support.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <thread>

using namespace ffd;

namespace {

// Euler characteristic V - E + F of a closed triangle mesh (each edge in two triangles).
long eulerCharacteristic(const TriangleMesh& m) {
    return long(m.vertexCount()) - long(m.triangleCount()) * 3 / 2 + long(m.triangleCount());
}

double minAngleDegrees(const TriangleMesh& m) {
    double smallest = 180;
    for (const auto& t : m.triangles)
        for (size_t i = 0; i < 3; ++i) {
            const Vec3 a = m.positions[t[i]], b = m.positions[t[(i + 1) % 3]],
                       c = m.positions[t[(i + 2) % 3]];
            const Vec3 u = b - a, v = c - a;
            smallest =
                std::min(smallest, std::atan2(double(length(cross(u, v))), double(dot(u, v))) *
                                       180 / std::numbers::pi);
        }
    return smallest;
}

// The message of the InputError that f throws, or a marker when it throws none.
std::string inputErrorMessage(const std::function<void()>& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "(no InputError thrown)";
}

bool identical(const TriangleMesh& a, const TriangleMesh& b) {
    return a.positions == b.positions && a.triangles == b.triangles;
}

} // namespace

TEST(Letters, EveryCapitalIsAClosedOutwardSolidWithExactBounds) {
    LetterSettings s;
    s.height = 2.0f;
    s.depthRatio = 0.3f;
    for (char c = 'A'; c <= 'Z'; ++c) {
        SCOPED_TRACE(std::string("letter ") + c);
        const TriangleMesh m = letter(c, s);
        EXPECT_NO_THROW(validate(m, m.name)); // finite, indices in range
        EXPECT_TRUE(isClosed(m));
        EXPECT_GT(signedVolume(m), 0.0);
        const Aabb box = bounds(m);
        EXPECT_EQ(box.lo.y, 0.0f);
        EXPECT_NEAR(box.hi.y, 2.0f, 1e-5f);
        EXPECT_NEAR(box.lo.z, -0.3f, 1e-6f);
        EXPECT_NEAR(box.hi.z, 0.3f, 1e-6f);
        EXPECT_NEAR(box.lo.x + box.hi.x, 0.0f, 1e-5f);
        EXPECT_GT(box.hi.x - box.lo.x, 0.2f); // a glyph, not a sliver
        // Welded, no zero-area or repeated triangles, nothing unused.
        TriangleMesh copy = m;
        const CleanupReport r = cleanup(copy);
        EXPECT_EQ(r.weldedVertices, 0u);
        EXPECT_EQ(r.degenerateTriangles, 0u);
        EXPECT_EQ(r.duplicateTriangles, 0u);
        EXPECT_EQ(r.unreferencedVertices, 0u);
        // Delaunay caps with lattice points and near-square wall quads: no needles.
        EXPECT_GT(minAngleDegrees(m), 15.0);
    }
}

TEST(Letters, GenusCountsTheHolesOfDejaVuSansBold) {
    // One connected solid each, so V - E + F = 2 - 2 * genus.
    const std::string oneHole = "ADOPQR";
    for (char c = 'A'; c <= 'Z'; ++c) {
        const long genus = c == 'B' ? 2 : (oneHole.find(c) != std::string::npos ? 1 : 0);
        EXPECT_EQ(eulerCharacteristic(letter(c)), 2 - 2 * genus) << "letter " << c;
    }
}

TEST(Letters, AlphabetAverageIsNearThePapersCounts) {
    std::vector<TriangleMesh> meshes;
    const auto start = std::chrono::steady_clock::now();
    for (char c = 'A'; c <= 'Z'; ++c) meshes.push_back(letter(c));
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    double vertices = 0, triangles = 0;
    std::printf("mesh       vertices  triangles\n");
    for (const TriangleMesh& m : meshes) {
        std::printf("%-9s  %8zu  %9zu\n", m.name.c_str(), m.vertexCount(), m.triangleCount());
        vertices += double(m.vertexCount()) / double(meshes.size());
        triangles += double(m.triangleCount()) / double(meshes.size());
    }
    std::printf("average    %8.1f  %9.1f   (paper %d / %d); A-Z generated in %.3f s\n", vertices,
                triangles, kPaperLetter.vertices, kPaperLetter.triangles, seconds);
    RecordProperty("average_vertices", std::to_string(vertices));
    RecordProperty("average_triangles", std::to_string(triangles));
    RecordProperty("alphabet_seconds", std::to_string(seconds));
    EXPECT_NEAR(vertices, kPaperLetter.vertices, 0.25 * kPaperLetter.vertices);
    EXPECT_NEAR(triangles, kPaperLetter.triangles, 0.25 * kPaperLetter.triangles);
}

TEST(Letters, RefineScalesTheResolution) {
    for (char c : std::string("ASW")) {
        SCOPED_TRACE(std::string("letter ") + c);
        LetterSettings fine, coarse;
        fine.refine = 2.0f;
        coarse.refine = 0.5f;
        const TriangleMesh base = letter(c), more = letter(c, fine), fewer = letter(c, coarse);
        // Resolution is per unit length, so the count grows about with refine squared.
        EXPECT_GT(more.vertexCount(), 3 * base.vertexCount());
        EXPECT_LT(fewer.vertexCount(), base.vertexCount() / 2);
        for (const TriangleMesh* m : {&more, &fewer}) {
            EXPECT_TRUE(isClosed(*m));
            EXPECT_GT(signedVolume(*m), 0.0);
            TriangleMesh copy = *m;
            EXPECT_FALSE(cleanup(copy).changed());
        }
    }
    // Very coarse settings still give a valid solid (the outline is then a rough polygon).
    LetterSettings rough;
    rough.refine = 0.05f;
    for (char c = 'A'; c <= 'Z'; ++c) {
        const TriangleMesh m = letter(c, rough);
        EXPECT_TRUE(isClosed(m)) << c;
        EXPECT_GT(signedVolume(m), 0.0) << c;
    }
}

TEST(Letters, HeightScalesWithoutChangingTheMeshAndDepthAddsRings) {
    LetterSettings tall;
    tall.height = 3.0f;
    const TriangleMesh unit = letter('K'), big = letter('K', tall);
    ASSERT_EQ(big.vertexCount(), unit.vertexCount());
    ASSERT_EQ(big.triangles, unit.triangles);
    for (size_t v = 0; v < unit.vertexCount(); ++v)
        EXPECT_LT(length(big.positions[v] - 3.0f * unit.positions[v]), 1e-5f);
    EXPECT_NEAR(signedVolume(big), 27.0 * signedVolume(unit), 1e-4 * signedVolume(big));

    LetterSettings deep;
    deep.depthRatio = 1.0f;
    const TriangleMesh d = letter('K', deep);
    EXPECT_GT(d.vertexCount(), unit.vertexCount());
    EXPECT_EQ(d.triangleCount() - unit.triangleCount(), 2 * (d.vertexCount() - unit.vertexCount()));
    EXPECT_NEAR(bounds(d).hi.z - bounds(d).lo.z, 1.0f, 1e-6f);
    EXPECT_NEAR(signedVolume(d), 4.0 * signedVolume(unit), 1e-3 * signedVolume(d));
}

TEST(Letters, Deterministic) {
    for (char c : std::string("BGQ")) EXPECT_TRUE(identical(letter(c), letter(c))) << c;
}

TEST(Letters, ThreadsGetTheSameMeshes) {
    std::vector<TriangleMesh> sequential;
    for (char c = 'A'; c <= 'H'; ++c) sequential.push_back(letter(c));
    std::vector<TriangleMesh> parallel(sequential.size());
    std::vector<std::thread> threads;
    for (size_t i = 0; i < parallel.size(); ++i)
        threads.emplace_back([&parallel, i] { parallel[i] = letter(char('A' + i)); });
    for (std::thread& t : threads) t.join();
    for (size_t i = 0; i < parallel.size(); ++i) EXPECT_TRUE(identical(parallel[i], sequential[i]));
}

TEST(Letters, OtherFontsWork) {
    const std::filesystem::path serif = "/usr/share/fonts/truetype/dejavu/DejaVuSerif.ttf";
    ASSERT_TRUE(std::filesystem::exists(serif)) << serif << " is missing: run scripts/setup.sh";
    LetterSettings s;
    s.fontFile = serif;
    const TriangleMesh m = letter('B', s);
    EXPECT_TRUE(isClosed(m));
    EXPECT_GT(signedVolume(m), 0.0);
    EXPECT_EQ(eulerCharacteristic(m), -2);
    EXPECT_FALSE(identical(m, letter('B'))); // the font setting is really used
}

TEST(Letters, RejectsCharactersOutsideAToZ) {
    const std::string lower = inputErrorMessage([] { letter('a'); });
    EXPECT_NE(lower.find("'a'"), std::string::npos) << lower;
    EXPECT_NE(lower.find("A-Z"), std::string::npos) << lower;
    const std::string digit = inputErrorMessage([] { letter('1'); });
    EXPECT_NE(digit.find("'1'"), std::string::npos) << digit;
    EXPECT_NE(digit.find("A-Z"), std::string::npos) << digit;
    const std::string nul = inputErrorMessage([] { letter('\0'); });
    EXPECT_NE(nul.find("code 0"), std::string::npos) << nul;
    EXPECT_NE(nul.find("A-Z"), std::string::npos) << nul;
    EXPECT_THROW(letter('@'), InputError); // just below 'A'
    EXPECT_THROW(letter('['), InputError); // just above 'Z'
}

TEST(Letters, RejectsMissingOrBrokenFontFiles) {
    test::TempDir dir;
    LetterSettings s;
    s.fontFile = dir / "no_such_font.ttf";
    const std::string missing = inputErrorMessage([&] { letter('A', s); });
    EXPECT_NE(missing.find(s.fontFile.string()), std::string::npos) << missing;

    s.fontFile = dir / "not_a_font.ttf";
    test::writeFile(s.fontFile, "this is plain text, not a TrueType font\n");
    const std::string broken = inputErrorMessage([&] { letter('A', s); });
    EXPECT_NE(broken.find(s.fontFile.string()), std::string::npos) << broken;

    s.fontFile = dir.path(); // a folder
    EXPECT_THROW(letter('A', s), InputError);
}

TEST(Letters, RejectsBadSettings) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    for (float bad : {0.0f, -1.0f, nan, inf}) {
        LetterSettings s;
        s.height = bad;
        EXPECT_NE(inputErrorMessage([&] { letter('A', s); }).find("height"), std::string::npos);
        s = {};
        s.depthRatio = bad;
        EXPECT_NE(inputErrorMessage([&] { letter('A', s); }).find("depthRatio"), std::string::npos);
        s = {};
        s.refine = bad;
        EXPECT_NE(inputErrorMessage([&] { letter('A', s); }).find("refine"), std::string::npos);
    }
}
