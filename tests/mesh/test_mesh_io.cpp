// loadMesh: every format and encoding on a known cube, the OBJ round trip, and every kind of
// bad input (missing, empty, truncated, malformed, non-finite, absurd counts, garbage) ending in
// an InputError that names the file.
#include "ffdaabb/error.h"
#include "ffdaabb/generators.h"
#include "ffdaabb/lattice.h"
#include "ffdaabb/mesh.h"
#include "ffdaabb/mesh_io.h"
#include "support/test_support.h"

#include <gtest/gtest.h>
#include <unistd.h>
#include <zlib.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <sys/stat.h>
#include <vector>

using namespace ffd;
using ffd::test::TempDir;
using ffd::test::writeFile;
namespace fs = std::filesystem;

namespace {

// The unit cube [0,1]^3: 8 corners, 6 quads, counter-clockwise seen from outside.
const std::vector<Vec3> kCorners = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                    {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
const std::vector<std::array<int, 4>> kQuads = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                                {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};

std::vector<std::array<int, 3>> cubeTriangles() {
    std::vector<std::array<int, 3>> out;
    for (const auto& q : kQuads) {
        out.push_back({q[0], q[1], q[2]});
        out.push_back({q[0], q[2], q[3]});
    }
    return out;
}

std::string num(float v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", double(v));
    return buf;
}

std::string objCube() {
    std::string s = "# unit cube\no cube\n";
    for (const Vec3& p : kCorners) s += "v " + num(p.x) + " " + num(p.y) + " " + num(p.z) + "\n";
    for (const auto& q : kQuads)
        s += "f " + std::to_string(q[0] + 1) + " " + std::to_string(q[1] + 1) + " " +
             std::to_string(q[2] + 1) + " " + std::to_string(q[3] + 1) + "\n";
    return s;
}

std::string plyAsciiHeader(const std::string& vertices, const std::string& faces) {
    return "ply\nformat ascii 1.0\ncomment unit cube\nelement vertex " + vertices +
           "\nproperty float x\nproperty float y\nproperty float z\nelement face " + faces +
           "\nproperty list uchar int vertex_indices\nend_header\n";
}

std::string plyAsciiVertices() {
    std::string s;
    for (const Vec3& p : kCorners) s += num(p.x) + " " + num(p.y) + " " + num(p.z) + "\n";
    return s;
}

std::string plyAsciiFaces() {
    std::string s;
    for (const auto& q : kQuads)
        s += "4 " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " + std::to_string(q[2]) +
             " " + std::to_string(q[3]) + "\n";
    return s;
}

std::string plyAsciiCube() {
    return plyAsciiHeader("8", "6") + plyAsciiVertices() + plyAsciiFaces();
}

template <class T>
void put(std::string& out, T value, bool bigEndian = false) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    if (bigEndian != (std::endian::native == std::endian::big))
        for (size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
    out.append(bytes, sizeof(T));
}

std::string plyBinary(const std::vector<Vec3>& vertices, const std::vector<std::vector<int>>& faces,
                      bool bigEndian, const std::string& declaredVertices = "") {
    std::string s =
        std::string("ply\nformat ") + (bigEndian ? "binary_big_endian" : "binary_little_endian") +
        " 1.0\nelement vertex " +
        (declaredVertices.empty() ? std::to_string(vertices.size()) : declaredVertices) +
        "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
        std::to_string(faces.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
    for (const Vec3& p : vertices) {
        put(s, p.x, bigEndian);
        put(s, p.y, bigEndian);
        put(s, p.z, bigEndian);
    }
    for (const auto& f : faces) {
        put(s, uint8_t(f.size()));
        for (int i : f) put(s, int32_t(i), bigEndian);
    }
    return s;
}

std::string plyBinaryCube(bool bigEndian = false) {
    std::vector<std::vector<int>> faces;
    for (const auto& q : kQuads) faces.push_back({q[0], q[1], q[2], q[3]});
    return plyBinary(kCorners, faces, bigEndian);
}

std::string stlAsciiCube(const std::string& name = "cube") {
    std::string s = "solid " + name + "\n";
    for (const auto& t : cubeTriangles()) {
        s += "  facet normal 0 0 0\n    outer loop\n";
        for (int k : t) {
            const Vec3 p = kCorners[size_t(k)];
            s += "      vertex " + num(p.x) + " " + num(p.y) + " " + num(p.z) + "\n";
        }
        s += "    endloop\n  endfacet\n";
    }
    return s + "endsolid " + name + "\n";
}

std::string stlBinary(const std::vector<std::array<Vec3, 3>>& triangles,
                      uint32_t declared = UINT32_MAX) {
    std::string s(80, ' ');
    s.replace(0, 14, "binary ffdaabb");
    put(s, declared == UINT32_MAX ? uint32_t(triangles.size()) : declared);
    for (const auto& t : triangles) {
        for (int k = 0; k < 3; ++k) put(s, 0.0f); // normal
        for (const Vec3& p : t) {
            put(s, p.x);
            put(s, p.y);
            put(s, p.z);
        }
        put(s, uint16_t(0));
    }
    return s;
}

std::vector<std::array<Vec3, 3>> cubeTriangleCorners() {
    std::vector<std::array<Vec3, 3>> out;
    for (const auto& t : cubeTriangles())
        out.push_back({kCorners[size_t(t[0])], kCorners[size_t(t[1])], kCorners[size_t(t[2])]});
    return out;
}

std::string stlBinaryCube() {
    return stlBinary(cubeTriangleCorners());
}

std::string offCube() {
    return "OFF\n# unit cube\n8 6 12\n" + plyAsciiVertices() + plyAsciiFaces();
}

std::string gzip(const std::string& data) {
    z_stream zs{};
    EXPECT_EQ(deflateInit2(&zs, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY), Z_OK);
    std::string out(deflateBound(&zs, uLong(data.size())) + 64, '\0');
    zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
    zs.avail_in = uInt(data.size());
    zs.next_out = reinterpret_cast<Bytef*>(out.data());
    zs.avail_out = uInt(out.size());
    EXPECT_EQ(deflate(&zs, Z_FINISH), Z_STREAM_END);
    out.resize(zs.total_out);
    deflateEnd(&zs);
    return out;
}

// Loads `path` expecting an InputError about it whose message contains `phrase`.
void expectError(const fs::path& path, const std::string& phrase) {
    try {
        const TriangleMesh m = loadMesh(path);
        ADD_FAILURE() << path << " loaded (" << m.vertexCount() << " vertices); expected an "
                      << "InputError containing '" << phrase << "'";
    } catch (const InputError& e) {
        EXPECT_EQ(e.source(), path.string());
        EXPECT_NE(std::string(e.what()).find(phrase), std::string::npos)
            << "expected '" << phrase << "' in: " << e.what();
    }
}

void expectError(const TempDir& dir, const std::string& name, const std::string& content,
                 const std::string& phrase) {
    SCOPED_TRACE(name);
    writeFile(dir / name, content);
    expectError(dir / name, phrase);
}

void expectCube(const TriangleMesh& m) {
    EXPECT_EQ(m.vertexCount(), 8u);
    EXPECT_EQ(m.triangleCount(), 12u);
    const Aabb box = bounds(m);
    EXPECT_EQ(box.lo, (Vec3{0, 0, 0}));
    EXPECT_EQ(box.hi, (Vec3{1, 1, 1}));
    EXPECT_TRUE(isClosed(m));
    EXPECT_NEAR(signedVolume(m), 1.0, 1e-6); // the winding survived triangulation
}

std::string replaceAll(std::string s, const std::string& from, const std::string& to) {
    for (size_t pos = s.find(from); pos != std::string::npos; pos = s.find(from, pos + to.size()))
        s.replace(pos, from.size(), to);
    return s;
}

// ---------------------------------------------------------------------------------------------

TEST(LoadMesh, ReadsTheCubeInEveryFormat) {
    TempDir dir;
    const std::vector<std::pair<std::string, std::string>> files = {
        {"cube.obj", objCube()},
        {"cube.ply", plyAsciiCube()},
        {"cube_le.ply", plyBinaryCube(false)},
        {"cube_be.ply", plyBinaryCube(true)},
        {"cube.ply.gz", gzip(plyBinaryCube())},
        {"cube_ascii.ply.gz", gzip(plyAsciiCube())},
        {"cube.obj.gz", gzip(objCube())},
        {"cube_ascii.stl", stlAsciiCube()},
        {"cube_binary.stl", stlBinaryCube()},
        {"cube.off", offCube()},
        {"cube.off.gz", gzip(offCube())},
        {"CUBE_UPPER.OBJ", objCube()},
        {"cube_upper.PLY.GZ", gzip(plyAsciiCube())},
    };
    for (const auto& [name, content] : files) {
        SCOPED_TRACE(name);
        writeFile(dir / name, content);
        const TriangleMesh m = loadMesh(dir / name);
        expectCube(m);
        EXPECT_EQ(m.name, name);
    }
}

TEST(LoadMesh, SaveObjRoundTripReproducesPositionsAndTriangles) {
    TempDir dir;
    TriangleMesh original = icosphere(3);
    transform(original, 1.2345f, {0.1f, -2.0f, 3.3f}); // coordinates with many digits
    saveObj(original, dir / "sphere.obj");
    const TriangleMesh loaded = loadMesh(dir / "sphere.obj");
    ASSERT_EQ(loaded.vertexCount(), original.vertexCount());
    ASSERT_EQ(loaded.triangleCount(), original.triangleCount());
    // Vertices may be renumbered (OBJ is read with a vertex per face corner, welded in order of
    // first use), but triangle order and corner positions are exact (%.9g round-trips floats).
    for (size_t t = 0; t < original.triangleCount(); ++t)
        for (int k = 0; k < 3; ++k)
            ASSERT_EQ(loaded.positions[loaded.triangles[t][k]],
                      original.positions[original.triangles[t][k]])
                << "triangle " << t << " corner " << k;
    EXPECT_TRUE(isClosed(loaded));
}

TEST(LoadMesh, LargeBinaryPlyLoadsExactly) {
    // 1.5 MB of binary data in both byte orders: every value survives, in order.
    TempDir dir;
    const TriangleMesh sphere = icosphere(6); // 40,962 vertices: 1.5 MB of binary data
    std::vector<std::vector<int>> faces;
    for (const auto& t : sphere.triangles) faces.push_back({int(t[0]), int(t[1]), int(t[2])});
    for (bool bigEndian : {false, true}) {
        writeFile(dir / "sphere.ply", plyBinary(sphere.positions, faces, bigEndian));
        const TriangleMesh m = loadMesh(dir / "sphere.ply");
        ASSERT_EQ(m.vertexCount(), sphere.vertexCount());
        ASSERT_EQ(m.triangleCount(), sphere.triangleCount());
        EXPECT_EQ(m.positions, sphere.positions);
        EXPECT_EQ(m.triangles, sphere.triangles);
    }
}

TEST(LoadMesh, MergesObjectsAndSolids) {
    TempDir dir;
    // Two cubes in separate OBJ objects and groups, the second shifted by 2 in x.
    std::string obj = objCube() + "o second\ng part\n";
    for (const Vec3& p : kCorners)
        obj += "v " + num(p.x + 2) + " " + num(p.y) + " " + num(p.z) + "\n";
    for (const auto& q : kQuads)
        obj += "f " + std::to_string(q[0] - 8) + " " + std::to_string(q[1] - 8) + " " +
               std::to_string(q[2] - 8) + " " + std::to_string(q[3] - 8) + "\n"; // relative
    writeFile(dir / "two.obj", obj);
    const TriangleMesh m = loadMesh(dir / "two.obj");
    EXPECT_EQ(m.vertexCount(), 16u);
    EXPECT_EQ(m.triangleCount(), 24u);
    EXPECT_EQ(bounds(m).hi, (Vec3{3, 1, 1}));

    writeFile(dir / "two.stl", stlAsciiCube("a") + stlAsciiCube("b"));
    const TriangleMesh s = loadMesh(dir / "two.stl");
    EXPECT_EQ(s.vertexCount(), 8u); // identical positions are joined across solids
    EXPECT_EQ(s.triangleCount(), 24u);
}

TEST(LoadMesh, AcceptsCommonObjAndPlyVariants) {
    TempDir dir;
    // OBJ: CRLF, a byte order mark, texture and normal references, comments, a continuation
    // line, a material library that is not there, lines and points (ignored).
    std::string obj = "\xEF\xBB\xBFmtllib missing.mtl\r\n";
    for (const Vec3& p : kCorners)
        obj += "v " + num(p.x) + " " + num(p.y) + " " + num(p.z) + " # corner\r\n";
    obj += "vt 0 0\r\nvt 1 0\r\nvt 1 1\r\nvn 0 0 1\r\nusemtl none\r\ns off\r\n";
    obj += "f 1/1/1 4/2/1 3/3/1 2/1/1\r\nf 5//1 6//1 7//1 8//1\r\n";
    obj += "f 1/1 2/2 \\\r\n6/3 5/1\r\nf 2 3 7 6\r\nf -6 -5 -1 -2\r\nf 4 1 5 8\r\n";
    obj += "l 1 2 3\r\np 4\r\n";
    writeFile(dir / "variants.obj", obj);
    expectCube(loadMesh(dir / "variants.obj"));

    // PLY with more properties than positions (normals, colours, doubles), int8 list counts and
    // unsigned indices, and an extra element that is skipped.
    std::string ply = "ply\r\nformat ascii 1.0\r\nobj_info made by hand\r\n"
                      "element vertex 8\r\nproperty double x\r\nproperty double y\r\n"
                      "property double z\r\nproperty float nx\r\nproperty uchar red\r\n"
                      "element face 6\r\nproperty list int8 uint vertex_index\r\n"
                      "element extra 2\r\nproperty int value\r\nend_header\r\n";
    for (const Vec3& p : kCorners)
        ply += num(p.x) + " " + num(p.y) + " " + num(p.z) + " 0.5 255\r\n";
    ply += replaceAll(plyAsciiFaces(), "\n", "\r\n") + "1\r\n2\r\n";
    writeFile(dir / "variants.ply", ply);
    expectCube(loadMesh(dir / "variants.ply"));
}

// A UTF-8 byte order mark before the first vertex: that vertex is the file's first (the earlier
// Assimp-based loader lost it, shifting every index or refusing the file as out of range).
TEST(LoadMesh, ObjByteOrderMarkBeforeAVertex) {
    TempDir dir;
    writeFile(dir / "bom.obj", "\xEF\xBB\xBF" + objCube());
    expectCube(loadMesh(dir / "bom.obj"));
    std::string obj = "\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n";
    writeFile(dir / "bom_first.obj", obj);
    const TriangleMesh m = loadMesh(dir / "bom_first.obj");
    ASSERT_EQ(m.triangleCount(), 1u);
    EXPECT_EQ(m.positions[m.triangles[0][0]], (Vec3{0, 0, 0}));
    EXPECT_EQ(m.positions[m.triangles[0][2]], (Vec3{0, 1, 0}));
}

// Corners 'v/vt/vn' in a file with normals but no texture coordinates: every corner is read
// (the earlier Assimp-based loader took vt for the normal, then vn for an unsupported token, and
// dropped the rest of the face and the first characters of the next line; found by fuzzing).
TEST(LoadMesh, ObjCornersWithTextureIndicesButNoTextureCoordinates) {
    TempDir dir;
    std::string obj = "vn 0 0 1\n";
    for (const Vec3& p : kCorners) obj += "v " + num(p.x) + " " + num(p.y) + " " + num(p.z) + "\n";
    for (const auto& q : kQuads)
        obj += "f " + std::to_string(q[0] + 1) + "/1/-1 " + std::to_string(q[1] + 1) + "/1/-1 " +
               std::to_string(q[2] + 1) + "/1/-1 " + std::to_string(q[3] + 1) + "/1/-1\n";
    writeFile(dir / "no_vt.obj", obj);
    expectCube(loadMesh(dir / "no_vt.obj"));
}

// Decimals become the floats the golden meshes were built from (integer part, up to 15 decimals
// scaled in double and added in float, then a float power of ten): for these three, not the
// nearest float (strtof gives 0x1.cd1ae2p-18, 0x1.e83d7p+5 and 0x1.a40b78p-3).
TEST(LoadMesh, DecimalsConvertAsBefore) {
    TempDir dir;
    const Vec3 expected{0x1.cd1aep-18f, 0x1.e83d72p+5f, 0x1.a40b7ap-3f};
    const std::string first = "6.871e-6 6.103e1 2.051e-1";
    const std::string rest = "1 0 0\n0 1 0\n";
    const std::vector<std::pair<std::string, std::string>> files = {
        {"decimals.obj", "v " + first + "\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"},
        {"decimals.off", "OFF\n3 1 0\n" + first + "\n" + rest + "3 0 1 2\n"},
        {"decimals.ply", plyAsciiHeader("3", "1") + first + "\n" + rest + "3 0 1 2\n"},
        {"decimals.stl", "solid d\nfacet normal 0 0 1\nouter loop\nvertex " + first +
                             "\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid d\n"},
    };
    for (const auto& [name, content] : files) {
        SCOPED_TRACE(name);
        writeFile(dir / name, content);
        const TriangleMesh m = loadMesh(dir / name);
        ASSERT_EQ(m.vertexCount(), 3u);
        EXPECT_EQ(m.positions[0], expected);
    }
}

// OFF faces are no longer limited to 9 corners: a 12-gon is ear-clipped into 10 triangles.
TEST(LoadMesh, OffPolygonsOfManyCorners) {
    TempDir dir;
    std::string off = "OFF\n12 1 0\n";
    std::string face = "12";
    for (int i = 0; i < 12; ++i) {
        const double a = 2 * 3.14159265358979 * i / 12;
        off += num(float(std::cos(a))) + " " + num(float(std::sin(a))) + " 0\n";
        face += ' ';
        face += std::to_string(i);
    }
    writeFile(dir / "dodecagon.off", off + face + "\n");
    const TriangleMesh m = loadMesh(dir / "dodecagon.off");
    EXPECT_EQ(m.vertexCount(), 12u);
    EXPECT_EQ(m.triangleCount(), 10u);
}

// Material statements are ignored: a library that cannot be found, a material never defined,
// and the malformed material lines on which the earlier Assimp-based loader wrote through a wild
// pointer (found by fuzz_mesh_load: lines starting with 'm' carrying bytes above 0x7f).
TEST(LoadMesh, ObjMaterialLinesAreIgnored) {
    TempDir dir;
    std::string obj = "mtllib missing.mtl\nusemtl nowhere\n";
    for (const Vec3& p : kCorners) obj += "v " + num(p.x) + " " + num(p.y) + " " + num(p.z) + "\n";
    obj += "f 1 2 3\n";
    writeFile(dir / "materials.obj", obj);
    const TriangleMesh m = loadMesh(dir / "materials.obj");
    EXPECT_EQ(m.triangleCount(), 1u);

    const std::string crash = "v 0 0 1\nv 1 0 0\nv 0 1 0\n"
                              "map_Psmtllib x.mllib x.mtl\xe8\xe8\xe8\xe8\xe8\xe8//1 3//1 2//1\n"
                              "mtllib x.mllib x.mtl\xe8\xe8\xe8\xe8\xe8\xe8//1 f 2 0 1\n"
                              "f 2 3 3\n";
    writeFile(dir / "fuzzed.obj", crash);
    try {
        const TriangleMesh fuzzed = loadMesh(dir / "fuzzed.obj");
        EXPECT_EQ(fuzzed.triangleCount(), 1u);
    } catch (const ffd::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("fuzzed.obj"), std::string::npos) << e.what();
    }
}

TEST(LoadMesh, PointsAndLinesAloneAreNotAMesh) {
    TempDir dir;
    std::string obj;
    for (const Vec3& p : kCorners) obj += "v " + num(p.x) + " " + num(p.y) + " " + num(p.z) + "\n";
    expectError(dir, "lines.obj", obj + "l 1 2 3 4\np 5 6\n", "no triangles");
    expectError(dir, "points.ply", plyAsciiHeader("8", "0") + plyAsciiVertices(), "no triangles");
    std::string cloud = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty "
                        "float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
    expectError(dir, "cloud.ply", cloud, "no triangles");
    expectError(dir, "lines.off", "OFF\n8 2 0\n" + plyAsciiVertices() + "2 0 1\n1 4\n",
                "no triangles");
}

// --- paths and files -------------------------------------------------------------------------

TEST(LoadMeshErrors, MissingDirectoryEmptyUnsupported) {
    TempDir dir;
    expectError(dir / "missing.obj", "does not exist");
    expectError(dir / "missing.xyz", "does not exist");
    fs::create_directory(dir / "folder.obj");
    expectError(dir / "folder.obj", "is a directory");
    for (const char* name : {"empty.obj", "empty.ply", "empty.stl", "empty.off", "empty.ply.gz"})
        expectError(dir, name, "", "empty");
    expectError(dir, "empty_inside.ply.gz", gzip(""), "empty after decompression");
    expectError(dir, "cube.xyz", objCube(), "unsupported file extension '.xyz'");
    expectError(dir, "cube.3ds", objCube(), ".obj, .ply, .stl and .off");
    expectError(dir, "cube.gz", gzip(objCube()), "unsupported");
    expectError(dir, "cube.tar.gz", gzip(objCube()), "unsupported");
    expectError(dir, "cube", objCube(), "unsupported");
}

TEST(LoadMeshErrors, NotARegularFile) {
    TempDir dir;
    ASSERT_EQ(::mkfifo((dir / "pipe.obj").c_str(), 0600), 0);
    expectError(dir / "pipe.obj", "not a regular file");
}

TEST(LoadMeshErrors, Unreadable) {
    TempDir dir;
    writeFile(dir / "secret.obj", objCube());
    fs::permissions(dir / "secret.obj", fs::perms::none);
    // Root reads any file, so the load runs in a child process that first drops to the
    // unprivileged user `nobody` (uid 65534) when started as root.
    const fs::path file = dir / "secret.obj";
    EXPECT_EXIT(
        {
            if (::geteuid() == 0 && ::setuid(65534) != 0) std::_Exit(3);
            try {
                loadMesh(file);
            } catch (const InputError& e) {
                const bool named = std::string(e.what()).find(file.string()) != std::string::npos;
                const bool said = std::string(e.what()).find("cannot be read") != std::string::npos;
                std::_Exit(named && said ? 0 : 1);
            }
            std::_Exit(2);
        },
        ::testing::ExitedWithCode(0), "");
}

// --- truncated -------------------------------------------------------------------------------

TEST(LoadMeshErrors, Truncated) {
    TempDir dir;
    const std::string stl = stlBinaryCube();
    expectError(dir, "short.stl", stl.substr(0, stl.size() - 20), "truncated");
    expectError(dir, "header_only.stl", stl.substr(0, 60), "truncated");
    const std::string ascii = stlAsciiCube();
    expectError(dir, "cut.stl", ascii.substr(0, ascii.size() / 2), "truncated");
    expectError(dir, "no_endsolid.stl", ascii.substr(0, ascii.rfind("endsolid")), "truncated");

    const std::string binary = plyBinaryCube();
    expectError(dir, "short_bin.ply", binary.substr(0, binary.size() - 10), "truncated");
    expectError(dir, "short_bin2.ply", binary.substr(0, binary.size() - 100), "truncated");
    expectError(dir, "fewer_faces.ply",
                plyAsciiHeader("8", "7") + plyAsciiVertices() + plyAsciiFaces(), "truncated");
    expectError(dir, "fewer_vertices.ply", plyAsciiHeader("9", "6") + plyAsciiVertices(),
                "truncated");
    const std::string plyText = plyAsciiCube();
    expectError(dir, "cut_line.ply", plyText.substr(0, plyText.size() - 4), "truncated");
    expectError(dir, "cut_header.ply", plyText.substr(0, 40), "truncated");

    const std::string obj = objCube();
    expectError(dir, "cut_face.obj", obj.substr(0, obj.size() - 6), "truncated");
    expectError(dir, "cut_vertex.obj", obj.substr(0, obj.find("v 1 1 1") + 5), "truncated");
    expectError(dir, "cut_continuation.obj", obj + "f 1 2 \\\n", "truncated");

    const std::string off = offCube();
    expectError(dir, "cut.off", off.substr(0, off.size() - 15), "truncated");
    expectError(dir, "cut_line.off", off.substr(0, off.size() - 3), "truncated");
    expectError(dir, "no_faces.off", "OFF\n8 6 12\n" + plyAsciiVertices(), "truncated");
    expectError(dir, "no_counts.off", "OFF\n", "truncated");

    const std::string gz = gzip(plyBinaryCube());
    expectError(dir, "cut.ply.gz", gz.substr(0, gz.size() / 2), "truncated");
    // The compressed stream is whole but the file inside it is cut.
    expectError(dir, "inner_cut.ply.gz", gzip(binary.substr(0, binary.size() - 10)), "truncated");
}

// --- malformed -------------------------------------------------------------------------------

TEST(LoadMeshErrors, MalformedHeadersAndStructure) {
    TempDir dir;
    const std::string ply = plyAsciiCube();
    expectError(dir, "magic.ply", "plx" + ply.substr(3), "not a PLY file");
    expectError(dir, "format.ply", replaceAll(ply, "format ascii", "format utf16"), "malformed");
    expectError(dir, "type.ply", replaceAll(ply, "property float z", "property quad z"),
                "unknown property type");
    expectError(dir, "count.ply", replaceAll(ply, "element vertex 8", "element vertex eight"),
                "malformed");
    expectError(dir, "no_z.ply", replaceAll(ply, "property float z\n", ""), "no 'z' property");
    expectError(dir, "no_end.ply", replaceAll(ply, "end_header\n", ""), "malformed");
    expectError(dir, "letters.ply", replaceAll(ply, "1 1 1\n", "1 one 1\n"), "malformed");
    expectError(dir, "blank.ply", replaceAll(ply, "1 1 1\n", "\n1 1 1\n"), "malformed");
    expectError(dir, "crlf_binary.ply", replaceAll(plyBinaryCube(), "1.0\n", "1.0\r\n"),
                "malformed");
    expectError(dir, "bad_index.ply", replaceAll(ply, "4 2 3 7 6", "4 2 3 7 60"), "out of range");
    expectError(dir, "negative_index.ply", replaceAll(ply, "4 2 3 7 6", "4 2 3 -7 6"),
                "out of range");
    std::vector<std::vector<int>> badFaces = {{0, 1, 2}, {0, 2, 8}};
    expectError(dir, "bad_index_bin.ply", plyBinary(kCorners, badFaces, false), "out of range");
    expectError(dir, "empty_face.ply", replaceAll(ply, "4 2 3 7 6", "0"), "malformed");

    const std::string obj = objCube();
    expectError(dir, "bad_index.obj", obj + "f 1 2 9\n", "out of range");
    expectError(dir, "bad_relative.obj", obj + "f 1 2 -9\n", "out of range");
    expectError(dir, "zero_index.obj", obj + "f 0 1 2\n", "malformed");
    expectError(dir, "letters.obj", obj + "f 1 2 x\n", "malformed");
    expectError(dir, "two_corners.obj", obj + "f 1 2\n", "malformed");
    expectError(dir, "bad_vertex.obj", "v 1 2\n" + obj, "malformed");
    expectError(dir, "word_vertex.obj", "v 1 2 three\n" + obj, "malformed");
    expectError(dir, "indented.obj", "  v 1 2 3\n" + obj, "malformed");
    expectError(dir, "w_zero.obj", "v 1 2 3 0\n" + obj, "malformed");

    const std::string off = offCube();
    expectError(dir, "keyword.off", "FOO" + off.substr(3), "malformed");
    expectError(dir, "four.off", "4OFF" + off.substr(3), "unsupported");
    expectError(dir, "counts.off", replaceAll(off, "8 6 12", "8 six 12"), "malformed");
    expectError(dir, "bad_index.off", replaceAll(off, "4 2 3 7 6", "4 2 3 7 60"), "out of range");
    expectError(dir, "letters.off", replaceAll(off, "1 1 1\n", "1 x 1\n"), "malformed");
    expectError(dir, "short_vertex.off", replaceAll(off, "1 1 1\n", "1 1\n"), "malformed");

    const std::string stl = stlAsciiCube();
    expectError(dir, "keyword.stl", replaceAll(stl, "outer loop", "outer lop"), "malformed");
    expectError(dir, "four_corners.stl", replaceAll(stl, "endloop", "vertex 0 0 0\n endloop"),
                "malformed");
    expectError(dir, "text.stl",
                "this is not an STL file, but it is long enough to have a header "
                "of 84 bytes and a triangle count, and more\n",
                "malformed");
    std::string longStl = stlBinaryCube() + std::string(30, '\0');
    expectError(dir, "too_long.stl", longStl, "malformed");
    expectError(dir, "zero.stl", stlBinary({}), "no triangles");

    const std::string gz = gzip(plyBinaryCube());
    expectError(dir, "magic.ply.gz", "xx" + gz.substr(2), "malformed");
    std::string corrupt = gz;
    for (size_t i = 20; i < 40 && i < corrupt.size(); ++i) corrupt[i] = char(corrupt[i] ^ 0x5a);
    expectError(dir, "corrupt.ply.gz", corrupt, "malformed");
    std::string badCrc = gz;
    badCrc[badCrc.size() - 6] = char(badCrc[badCrc.size() - 6] ^ 1);
    expectError(dir, "crc.ply.gz", badCrc, "malformed");
    expectError(dir, "plain.ply.gz", plyBinaryCube(), "malformed");
}

// --- non-finite coordinates ------------------------------------------------------------------

TEST(LoadMeshErrors, NonFiniteCoordinatesNameTheVertex) {
    TempDir dir;
    for (const char* bad : {"nan", "inf", "-inf", "NaN", "1e39", "-1e300"}) {
        SCOPED_TRACE(bad);
        const std::string b = bad;
        expectError(dir, "bad.obj", replaceAll(objCube(), "v 1 1 1", "v 1 " + b + " 1"),
                    "vertex 6");
        expectError(dir, "bad.ply", replaceAll(plyAsciiCube(), "\n1 1 1\n", "\n1 " + b + " 1\n"),
                    "vertex 6");
        expectError(dir, "bad.off", replaceAll(offCube(), "\n1 1 1\n", "\n1 " + b + " 1\n"),
                    "vertex 6");
        expectError(dir, "bad.stl", replaceAll(stlAsciiCube(), "vertex 1 1 1", "vertex 1 1 " + b),
                    "non-finite");
        expectError(dir, "bad.ply", replaceAll(plyAsciiCube(), "\n1 1 1\n", "\n1 " + b + " 1\n"),
                    "non-finite");
    }
    std::vector<Vec3> corners = kCorners;
    corners[5].z = std::numeric_limits<float>::quiet_NaN();
    std::vector<std::vector<int>> faces;
    for (const auto& q : kQuads) faces.push_back({q[0], q[1], q[2], q[3]});
    expectError(dir, "nan_bin.ply", plyBinary(corners, faces, false), "vertex 5");
    expectError(dir, "nan_bin.ply", plyBinary(corners, faces, true), "non-finite");
    auto triangles = cubeTriangleCorners();
    triangles[4][2].y = std::numeric_limits<float>::infinity();
    expectError(dir, "inf_bin.stl", stlBinary(triangles), "vertex 14");
    expectError(dir, "inf_bin.stl", stlBinary(triangles), "non-finite");
    expectError(dir, "nan.obj.gz", gzip(replaceAll(objCube(), "v 1 1 1", "v 1 nan 1")),
                "non-finite");
}

// --- absurd counts ---------------------------------------------------------------------------

// Finite coordinates whose extent a float cannot hold (found by fuzzing a binary STL with
// vertices at -3.4e38 and 3.4e38: the lattice's grid size became NaN): refused with the span.
TEST(LoadMeshErrors, AnExtentBeyondFloatIsRefused) {
    TempDir dir;
    const std::string huge =
        replaceAll(replaceAll(objCube(), "v 1 1 1", "v 1 3e38 1"), "v 0 0 0", "v 0 -3e38 0");
    expectError(dir, "huge.obj", huge, "extent too large");
    TriangleMesh mesh = icosphere(1);
    mesh.positions[0].x = -3e38f;
    mesh.positions[1].x = 3e38f;
    EXPECT_THROW(validate(mesh, "mesh"), InputError);
    EXPECT_THROW(buildLattice(mesh, LatticeSettings{}), InputError);
}

TEST(LoadMeshErrors, AbsurdCountsAreRejectedBeforeAllocating) {
    TempDir dir;
    expectError(dir, "huge.ply", plyAsciiHeader("1000000000000", "6") + plyAsciiVertices(),
                "limit");
    expectError(dir, "huge_faces.ply", plyAsciiHeader("8", "4000000000") + plyAsciiVertices(),
                "limit");
    expectError(dir, "huge_bin.ply", plyBinary(kCorners, {{0, 1, 2}}, false, "1000000000000"),
                "limit");
    // Below the limit but far beyond the file: truncated, found without reading that much.
    expectError(dir, "big_bin.ply", plyBinary(kCorners, {{0, 1, 2}}, false, "200000000"),
                "truncated");
    expectError(dir, "huge.off", "OFF\n1000000000000 6 0\n" + plyAsciiVertices(), "limit");
    expectError(dir, "huge_faces.off", "OFF\n8 300000000 0\n" + plyAsciiVertices(), "limit");
    expectError(dir, "huge.stl", stlBinary(cubeTriangleCorners(), 4000000000u), "limit");
    expectError(dir, "big.stl", stlBinary(cubeTriangleCorners(), 1000u), "truncated");
    std::string polygon = objCube() + "f";
    for (int i = 0; i < 2000; ++i) {
        polygon += ' ';
        polygon += std::to_string(i % 8 + 1);
    }
    expectError(dir, "polygon.obj", polygon + "\n", "limit");
}

// --- garbage ---------------------------------------------------------------------------------

// Loads every file it is given, accepting only a valid mesh or an InputError about the file.
int loadOrReject(const fs::path& path) {
    try {
        const TriangleMesh m = loadMesh(path);
        validate(m, path.string());
        return 0;
    } catch (const InputError& e) {
        EXPECT_EQ(e.source(), path.string());
        EXPECT_FALSE(std::string(e.problem()).empty());
        return 1;
    }
}

TEST(LoadMeshErrors, RandomGarbageIsRejected) {
    TempDir dir;
    const char* const names[] = {"g.obj", "g.ply", "g.stl", "g.off", "g.ply.gz", "g.stl.gz"};
    for (uint32_t seed = 1; seed <= 40; ++seed) {
        std::mt19937 rng(seed);
        const size_t size = 1 + rng() % 3000;
        std::string bytes(size, '\0');
        const bool text = seed % 2 == 0; // half printable text with line breaks
        for (char& c : bytes)
            c = text ? " \n0123456789.-efvlnaOFFplysoid/#"[rng() % 31] : char(rng() & 0xff);
        for (const char* name : names) {
            SCOPED_TRACE(std::string(name) + " seed " + std::to_string(seed));
            writeFile(dir / name, bytes);
            EXPECT_EQ(loadOrReject(dir / name), 1) << "random bytes loaded as a mesh";
        }
    }
    // Valid headers followed by garbage.
    for (uint32_t seed = 1; seed <= 20; ++seed) {
        std::mt19937 rng(seed);
        std::string tail(size_t(200 + rng() % 500), '\0');
        for (char& c : tail) c = char(rng() & 0xff);
        const std::vector<std::pair<std::string, std::string>> files = {
            {"h.ply", plyAsciiHeader("8", "6") + tail},
            {"hb.ply", plyBinaryCube().substr(0, plyBinaryCube().find("end_header") + 11) + tail},
            {"h.off", "OFF\n8 6 0\n" + tail},
            {"h.stl", "solid x\n" + tail},
            {"h.obj", "v 0 0 0\n" + tail},
        };
        for (const auto& [name, content] : files) {
            SCOPED_TRACE(name + " seed " + std::to_string(seed));
            writeFile(dir / name, content);
            EXPECT_EQ(loadOrReject(dir / name), 1);
        }
    }
}

TEST(LoadMeshErrors, MutatedFilesNeverCrash) {
    // Valid files with bytes flipped, inserted, deleted or cut: each must load or throw an
    // InputError, never crash or throw anything else (Assimp, the earlier reader, segfaulted or
    // aborted on several of these).
    TempDir dir;
    TriangleMesh sphere = icosphere(1);
    std::vector<std::vector<int>> faces;
    for (const auto& t : sphere.triangles) faces.push_back({int(t[0]), int(t[1]), int(t[2])});
    const std::vector<std::pair<std::string, std::string>> seeds = {
        {"m.obj", objCube()},        {"m.ply", plyAsciiCube()},
        {"mb.ply", plyBinaryCube()}, {"mbe.ply", plyBinary(sphere.positions, faces, true)},
        {"m.stl", stlAsciiCube()},   {"mb.stl", stlBinaryCube()},
        {"m.off", offCube()},        {"m.ply.gz", gzip(plyAsciiCube())},
    };
    int loaded = 0, rejected = 0;
    for (const auto& [name, original] : seeds) {
        std::mt19937 rng(12345);
        for (int round = 0; round < 120; ++round) {
            std::string s = original;
            const int edits = 1 + int(rng() % 4);
            for (int e = 0; e < edits && !s.empty(); ++e) {
                const size_t at = rng() % s.size();
                switch (rng() % 5) {
                case 0:
                    s[at] = char(rng() & 0xff);
                    break;
                case 1:
                    s.insert(at, 1, " \n0-9e.#/\r"[rng() % 10]);
                    break;
                case 2:
                    s.erase(at, 1 + rng() % 8);
                    break;
                case 3:
                    s.resize(at);
                    break;
                default:
                    s[at] = "0123456789"[rng() % 10];
                    break;
                }
            }
            SCOPED_TRACE(name + " round " + std::to_string(round));
            writeFile(dir / name, s);
            (loadOrReject(dir / name) ? rejected : loaded)++;
        }
    }
    EXPECT_GT(rejected, 0);
    EXPECT_GT(loaded, 0); // some edits keep the file valid (e.g. a digit changed)
}

TEST(LoadMesh, LoadingStaysQuiet) {
    TempDir dir;
    // Nothing is printed about the missing material library or the unknown material.
    writeFile(dir / "quiet.obj", "mtllib nowhere.mtl\nusemtl nothing\n" + objCube());
    writeFile(dir / "quiet.stl", stlAsciiCube());
    testing::internal::CaptureStdout();
    testing::internal::CaptureStderr();
    loadMesh(dir / "quiet.obj");
    loadMesh(dir / "quiet.stl");
    EXPECT_THROW(loadMesh(dir / "missing.ply"), InputError);
    const std::string out = testing::internal::GetCapturedStdout();
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_EQ(out, "");
    EXPECT_EQ(err, "");
}

} // namespace
