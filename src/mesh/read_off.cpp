// OFF files; see mesh_reader.h.
#include "mesh/mesh_reader.h"

#include "ffdaabb/error.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <vector>

namespace ffd::detail {
namespace {} // namespace

// Vertices, then faces whose corners index them (vertices are shared, in the file's order).
std::vector<RawPart> readOff(std::string_view data, const std::string& source) {
    checkText(data, 0, source, "OFF");
    const size_t size = data.size();
    size_t pos = 0;
    size_t lineNumber = 1;
    // Skips blanks, line ends and whole comment lines.
    auto skip = [&] {
        for (;;) {
            while (pos < size && (isBlank(data[pos]) || data[pos] == '\n' || data[pos] == '\r')) {
                if (data[pos] == '\n') ++lineNumber;
                ++pos;
            }
            if (pos < size && data[pos] == '#') {
                while (pos < size && data[pos] != '\n') ++pos;
                continue;
            }
            return;
        }
    };
    auto token = [&] {
        skip();
        const size_t start = pos;
        while (pos < size && !isBlank(data[pos]) && data[pos] != '\n' && data[pos] != '\r') ++pos;
        return data.substr(start, pos - start);
    };
    const std::string_view keyword = token();
    static constexpr const char* kKeywords[] = {"OFF",   "COFF",   "NOFF",   "CNOFF",
                                                "STOFF", "STCOFF", "STNOFF", "STCNOFF"};
    int keywordIndex = -1;
    for (int k = 0; k < 8; ++k)
        if (keyword == kKeywords[k]) keywordIndex = k;
    if (keywordIndex < 0) {
        if (keyword.size() >= 3 && keyword.substr(keyword.size() - 3) == "OFF")
            fail(source, fmt("unsupported OFF variant %s (homogeneous '4OFF' and n-dimensional "
                             "'nOFF' are not supported; expected OFF, COFF, NOFF or STOFF)",
                             quoted(keyword).c_str()));
        fail(source, fmt("malformed OFF: the file starts with %s (expected the keyword 'OFF')",
                         quoted(keyword).c_str()));
    }
    const bool normals = keyword.find('N') != std::string_view::npos;
    const bool colors = keyword.find('C') != std::string_view::npos;
    const bool texcoords = keyword.substr(0, 2) == "ST";
    // A colour is 4 values (r g b a): all four are required.
    const size_t valuesPerVertex = 3 + (normals ? 3 : 0) + (colors ? 4 : 0) + (texcoords ? 2 : 0);

    uint64_t counts[3] = {0, 0, 0};
    static constexpr const char* kCountNames[] = {"vertex", "face", "edge"};
    for (int c = 0; c < 3; ++c) {
        const std::string_view t = token();
        if (t.empty())
            fail(source, fmt("truncated OFF: the file ends before the %s count (expected "
                             "'<vertices> <faces> <edges>' after the keyword)",
                             kCountNames[c]));
        int64_t v = 0;
        if (!parseInteger(t, v, false))
            fail(source, fmt("malformed OFF: the %s count is %s (expected a non-negative "
                             "integer; the header is '<vertices> <faces> <edges>')",
                             kCountNames[c], quoted(t).c_str()));
        counts[c] = uint64_t(v);
    }
    const uint64_t vertexCount = counts[0], faceCount = counts[1];
    if (vertexCount > kMaxMeshElements)
        failTooMany(source, "the OFF header", vertexCount, "vertices");
    if (faceCount > kMaxMeshElements) failTooMany(source, "the OFF header", faceCount, "faces");
    if (vertexCount == 0)
        fail(source, "the OFF header declares 0 vertices: the mesh is empty (expected at least 3 "
                     "vertices and 1 face)");
    if (faceCount == 0)
        fail(source, "the OFF header declares 0 faces, so no triangles (a point cloud?); "
                     "expected a triangle mesh with at least 1 face");
    skip();

    // The data: one element per line, empty lines skipped.
    LineReader reader(data, pos, lineNumber);
    Line line;
    auto nextLine = [&](const char* what, uint64_t i) {
        do {
            if (!reader.next(line))
                fail(source, fmt("truncated OFF: the header declares %llu vertices and %llu "
                                 "faces, but the file ends before %s %llu",
                                 ull(vertexCount), ull(faceCount), what, ull(i)));
        } while (line.text.empty());
    };
    auto bad = [&](const char* what, uint64_t i, const std::string& problem) {
        if (!line.terminated)
            fail(source, fmt("truncated OFF: the last line (%zu, %s %llu) is incomplete: %s",
                             line.number, what, ull(i), problem.c_str()));
        fail(source, fmt("malformed OFF: line %zu (%s %llu): %s", line.number, what, ull(i),
                         problem.c_str()));
    };
    std::vector<Vec3> vertices;
    vertices.reserve(size_t(std::min<uint64_t>(vertexCount, data.size() / 2 + 1)));
    for (uint64_t i = 0; i < vertexCount; ++i) {
        nextLine("vertex", i);
        Vec3& vertex = vertices.emplace_back();
        Tokenizer tokens(line.text);
        std::string_view t;
        for (size_t k = 0; k < valuesPerVertex; ++k) {
            if (!tokens.next(t) || t.front() == '#')
                bad("vertex", i,
                    fmt("%zu values, expected %zu (x y z%s%s%s)", k, valuesPerVertex,
                        normals ? " nx ny nz" : "", colors ? " r g b a" : "",
                        texcoords ? " s t" : ""));
            double v = 0;
            const Real r = parseReal(t, v);
            if (r == Real::Invalid) bad("vertex", i, quoted(t) + " is not a number");
            if (r == Real::NonFinite && k < 3)
                failNonFinite(source, "OFF", i, fmt(" (line %zu)", line.number), t);
            if (k < 3) vertex[int(k)] = decimalToFloat(t);
        }
    }
    std::vector<RawPart> parts(1);
    RawPart& part = parts[0];
    for (uint64_t i = 0; i < faceCount; ++i) {
        nextLine("face", i);
        Tokenizer tokens(line.text);
        std::string_view t;
        int64_t corners = 0;
        if (!tokens.next(t) || !parseInteger(t, corners, false))
            bad("face", i, "expected the number of corners, found " + quoted(t));
        if (corners == 0) bad("face", i, "a face without vertices (expected at least 3)");
        if (uint64_t(corners) > kMaxPolygonCorners)
            fail(source, fmt("OFF face %llu (line %zu) has %lld corners, more than the limit of "
                             "%llu per polygon",
                             ull(i), line.number, (long long)corners, ull(kMaxPolygonCorners)));
        for (int64_t k = 0; k < corners; ++k) {
            int64_t index = 0;
            if (!tokens.next(t))
                bad("face", i,
                    fmt("%lld of %lld vertex indices", (long long)k, (long long)corners));
            if (!parseInteger(t, index, false))
                bad("face", i, "vertex index " + quoted(t) + " is not a non-negative integer");
            if (uint64_t(index) >= vertexCount)
                fail(source, fmt("malformed OFF: face %llu (line %zu) uses vertex index %lld, "
                                 "out of range: the file has %llu vertices (expected 0 to %llu)",
                                 ull(i), line.number, (long long)index, ull(vertexCount),
                                 ull(vertexCount - 1)));
            part.corners.push_back(uint32_t(index));
        }
        part.addFace(uint32_t(corners));
    }
    part.positions = std::move(vertices);
    return parts;
}

} // namespace ffd::detail
