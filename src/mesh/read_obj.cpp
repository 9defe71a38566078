// OBJ files; see mesh_reader.h.
#include "mesh/mesh_reader.h"

#include "ffdaabb/error.h"

#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <unordered_set>
#include <vector>

namespace ffd::detail {
namespace {

// Parses an OBJ index: an integer without '+', leading zeros or zero, within int range.
bool parseObjIndex(std::string_view t, int64_t& value) {
    if (t.empty()) return false;
    size_t i = t.front() == '-' ? 1 : 0;
    if (i >= t.size() || t[i] < '1' || t[i] > '9') return false;
    if (!parseInteger(t, value, true)) return false;
    return value >= std::numeric_limits<int32_t>::min() &&
           value <= std::numeric_limits<int32_t>::max();
}

// Where faces go: a part per object ('o' with a new name) or group ('g' with a name other than
// the active group's), created when named; faces before any name go to a default part.
struct ObjParts {
    std::vector<RawPart> parts;
    std::vector<std::vector<int64_t>> indices; // per part: corners as 0-based file vertices
    std::unordered_set<std::string> objects;   // names of the objects and groups so far
    int current = -1;
    std::string activeGroup;

    void newPart(std::string name) {
        objects.insert(std::move(name));
        parts.emplace_back();
        indices.emplace_back();
        current = int(parts.size()) - 1;
    }
    void object(std::string_view name) {
        // An existing object becomes active again, but its faces keep going where they went.
        if (objects.count(std::string(name)) == 0) newPart(std::string(name));
    }
    void group(std::string_view name) {
        if (name == activeGroup) return;
        newPart(std::string(name));
        activeGroup = std::string(name);
    }
    void face(const std::vector<int64_t>& corners, bool polygon) {
        if (current < 0) newPart("defaultobject");
        auto& out = indices[size_t(current)];
        RawPart& part = parts[size_t(current)];
        if (polygon) {
            out.insert(out.end(), corners.begin(), corners.end());
            part.addFace(uint32_t(corners.size()));
            return;
        }
        for (int64_t c : corners) { // lines and points: their vertices only
            out.push_back(c);
            part.addFace(1);
        }
    }
};

} // namespace

// Statements are read line by line; every face corner becomes its own vertex (loadMesh welds
// equal positions afterwards), so vertices no face uses are not part of the mesh. Lines and
// points add their vertices to their part but no triangles.
std::vector<RawPart> readObj(std::string_view data, const std::string& source) {
    checkText(data, 0, source, "OBJ");
    ObjParts out;
    std::vector<Vec3> positions;
    std::vector<int64_t> corners;
    size_t start = 0;
    if (data.substr(0, 3) == "\xEF\xBB\xBF") start = 3; // UTF-8 byte order mark

    uint64_t vertices = 0, faces = 0;
    int64_t furthestVertex = 0; // largest positive vertex index used (1-based)
    size_t furthestLine = 0;
    bool inCurveSection = false;
    LineReader reader(data, start);
    Line physical;
    std::string joined;
    while (reader.next(physical)) {
        // Line continuation: a line ending in '\' joins the next one.
        std::string_view text = physical.text;
        const size_t number = physical.number;
        bool terminated = physical.terminated;
        if (!text.empty() && text.back() == '\\') {
            joined.assign(text.substr(0, text.size() - 1));
            for (;;) {
                if (!reader.next(physical))
                    fail(source, fmt("truncated OBJ: line %zu ends with a '\\' continuation "
                                     "but the file ends there",
                                     number));
                // An empty line after a continuation is refused (it would end the statement
                // ambiguously).
                if (physical.text.empty() || physical.text == "\\")
                    fail(source, fmt("malformed OBJ: the '\\' continuation on line %zu is "
                                     "followed by an empty line",
                                     physical.number - 1));
                terminated = physical.terminated;
                if (!physical.text.empty() && physical.text.back() == '\\') {
                    joined.append(physical.text.substr(0, physical.text.size() - 1));
                    continue;
                }
                joined.append(physical.text);
                break;
            }
            text = joined;
        }
        if (text.empty()) continue;
        const bool last = !terminated;
        auto bad = [&](const std::string& problem) {
            if (last)
                fail(source, fmt("truncated OBJ: the last line (%zu) is incomplete: %s", number,
                                 problem.c_str()));
            fail(source, fmt("malformed OBJ: line %zu: %s", number, problem.c_str()));
        };

        Tokenizer tokens(text);
        std::string_view keyword;
        tokens.next(keyword);
        if (inCurveSection) {
            // Free-form curve and surface bodies are skipped up to "end".
            if (text.front() == 'e' && keyword == "end") inCurveSection = false;
            continue;
        }
        if (isBlank(text.front())) {
            // Statements start at the beginning of the line: refused rather than dropped.
            if (keyword == "v" || keyword == "vt" || keyword == "vn" || keyword == "f" ||
                keyword == "l" || keyword == "p")
                bad(fmt("indented %s statement; statements must start at the beginning of the "
                        "line",
                        quoted(keyword).c_str()));
            continue;
        }
        // Comments end a vertex or face statement wherever they start.
        const std::string_view statement = text.substr(0, text.find('#'));
        switch (text.front()) {
        case 'v': {
            if (text.size() == 1)
                bad("a vertex statement without coordinates (expected 'v x y z')");
            const bool position = isBlank(text[1]);
            if (!position && text[1] != 't' && text[1] != 'n') break; // vp and the like
            if (!position && keyword != "vt" && keyword != "vn")
                bad(fmt("unsupported statement %s (expected %s)", quoted(keyword).c_str(),
                        text[1] == 't' ? "vt" : "vn"));
            // Values of v, vt and vn must start with a digit or a sign (".5" is refused; "nan"
            // and "inf" are read, then refused as non-finite).
            Tokenizer values(statement.substr(position ? 1 : 2));
            std::string_view t;
            double v[7] = {};
            std::string_view texts[7];
            size_t n = 0;
            while (values.next(t)) {
                if (n == 7) bad("too many values in a " + std::string(keyword) + " statement");
                const char c = t.front();
                const bool counted = (c >= '0' && c <= '9') || c == '+' || c == '-' || c == 'n' ||
                                     c == 'N' || c == 'i' || c == 'I';
                const Real r = parseReal(t, v[n]);
                if (r == Real::Invalid || !counted)
                    bad(quoted(t) + " is not a number (write numbers like 0.5, -2 or 1e-3)");
                if (r == Real::NonFinite && position && n < 4)
                    failNonFinite(source, "OBJ", vertices, fmt(" (line %zu)", number), t);
                texts[n++] = t;
            }
            if (keyword == "vt") {
                if (n != 2 && n != 3)
                    bad(fmt("a texture coordinate with %zu values (expected 'vt u v [w]')", n));
                break;
            }
            if (keyword == "vn") {
                if (n < 3) bad(fmt("a normal with %zu values (expected 'vn x y z')", n));
                break;
            }
            if (n != 3 && n != 4 && n != 6)
                bad(fmt("a vertex with %zu values (expected 'v x y z', optionally with w or an "
                        "r g b colour)",
                        n));
            if (n == 4) {
                if (v[3] == 0) bad("a homogeneous vertex with w = 0");
                for (int k = 0; k < 3; ++k) {
                    const double q = v[k] / v[3];
                    if (!std::isfinite(q) ||
                        std::fabs(q) > double(std::numeric_limits<float>::max()))
                        failNonFinite(source, "OBJ", vertices,
                                      fmt(" (line %zu, after dividing by w)", number), texts[k]);
                }
            }
            Vec3 p{decimalToFloat(texts[0]), decimalToFloat(texts[1]), decimalToFloat(texts[2])};
            if (n == 4) {
                const float w = decimalToFloat(texts[3]);
                p = {p.x / w, p.y / w, p.z / w};
            }
            positions.push_back(p);
            ++vertices;
            break;
        }
        case 'f':
        case 'l':
        case 'p': {
            if (keyword != "f" && keyword != "fo" && keyword != "l" && keyword != "p")
                bad(fmt("unsupported statement %s (expected f, l or p)", quoted(keyword).c_str()));
            if (statement.size() != text.size())
                bad("a comment on a face, line or point statement (put comments on their own "
                    "lines)");
            Tokenizer refs(statement);
            std::string_view ref;
            refs.next(ref); // the keyword
            corners.clear();
            while (refs.next(ref)) {
                std::string_view parts[3];
                size_t partCount = 0;
                size_t from = 0;
                for (;;) {
                    const size_t slash = ref.find('/', from);
                    if (partCount == 3) bad("face corner " + quoted(ref) + " has too many '/'");
                    parts[partCount++] =
                        ref.substr(from, slash == std::string_view::npos ? slash : slash - from);
                    if (slash == std::string_view::npos) break;
                    from = slash + 1;
                }
                int64_t index = 0;
                if (!parseObjIndex(parts[0], index))
                    bad("face corner " + quoted(ref) +
                        " is not 'v', 'v/vt', 'v//vn' or 'v/vt/vn' with non-zero integers");
                for (size_t k = 1; k < partCount; ++k) {
                    int64_t other = 0;
                    const bool emptyTexture = k == 1 && partCount == 3 && parts[1].empty();
                    if (!emptyTexture && !parseObjIndex(parts[k], other))
                        bad("face corner " + quoted(ref) +
                            " is not 'v', 'v/vt', 'v//vn' or 'v/vt/vn' with non-zero integers");
                }
                if (index < 0) {
                    if (uint64_t(-index) > vertices)
                        fail(source, fmt("malformed OBJ: line %zu uses relative vertex index "
                                         "%lld, out of range: only %llu vertices precede it",
                                         number, (long long)index, ull(vertices)));
                } else if (index > furthestVertex) {
                    furthestVertex = index;
                    furthestLine = number;
                }
                corners.push_back(index < 0 ? int64_t(vertices) + index : index - 1);
            }
            if (keyword == "f" || keyword == "fo") {
                if (corners.size() < 3)
                    bad(fmt("a face with %zu corners (expected at least 3)", corners.size()));
                if (corners.size() > kMaxPolygonCorners)
                    fail(source, fmt("OBJ face on line %zu has %zu corners, more than the limit "
                                     "of %llu per polygon",
                                     number, corners.size(), ull(kMaxPolygonCorners)));
                ++faces;
            }
            if (keyword == "l" && corners.size() == 1)
                bad("a line statement with 1 point (expected at least 2)");
            out.face(corners, keyword == "f" || keyword == "fo");
            break;
        }
        case 'o': {
            std::string_view name;
            tokens.next(name);
            out.object(name);
            break;
        }
        case 'g': {
            size_t at = 1;
            while (at < text.size() && isBlank(text[at])) ++at;
            out.group(text.substr(at));
            break;
        }
        case 'c':
            if (keyword == "cstype") inCurveSection = true;
            break;
        default:
            break; // comments, names, groups, materials: not geometry
        }
    }
    if (uint64_t(furthestVertex) > vertices)
        fail(source, fmt("malformed OBJ: line %zu uses vertex index %lld, out of range: the file "
                         "has %llu vertices (expected 1 to %llu, or negative relative indices)",
                         furthestLine, (long long)furthestVertex, ull(vertices), ull(vertices)));
    if (faces == 0)
        fail(source, vertices == 0
                         ? "the OBJ file has no vertices and no faces, so no triangles: the "
                           "mesh is empty (expected 'v x y z' and 'f a b c' statements)"
                         : "the OBJ file has no faces ('f' statements): no triangles to load "
                           "(expected a triangle or polygon mesh)");

    for (size_t m = 0; m < out.parts.size(); ++m) {
        RawPart& part = out.parts[m];
        const std::vector<int64_t>& used = out.indices[m];
        part.positions.reserve(used.size());
        part.corners.reserve(used.size());
        for (int64_t v : used) {
            part.corners.push_back(uint32_t(part.positions.size()));
            part.positions.push_back(positions[size_t(v)]);
        }
    }
    return std::move(out.parts);
}

} // namespace ffd::detail
