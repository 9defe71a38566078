// PLY files (ASCII, binary little- and big-endian): header, then elements; see mesh_reader.h.
#include "mesh/mesh_reader.h"

#include "ffdaabb/error.h"

#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <vector>

namespace ffd::detail {
namespace {

enum class PlyType : uint8_t { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

struct PlyTypeName {
    const char* name;
    PlyType type;
};
constexpr PlyTypeName kPlyTypeNames[] = {
    {"char", PlyType::Int8},      {"int8", PlyType::Int8},       {"uchar", PlyType::UInt8},
    {"uint8", PlyType::UInt8},    {"short", PlyType::Int16},     {"int16", PlyType::Int16},
    {"ushort", PlyType::UInt16},  {"uint16", PlyType::UInt16},   {"int", PlyType::Int32},
    {"int32", PlyType::Int32},    {"uint", PlyType::UInt32},     {"uint32", PlyType::UInt32},
    {"float", PlyType::Float32},  {"float32", PlyType::Float32}, {"double", PlyType::Float64},
    {"float64", PlyType::Float64}};

std::optional<PlyType> plyTypeFromName(std::string_view name) {
    for (const PlyTypeName& t : kPlyTypeNames)
        if (name == t.name) return t.type;
    return std::nullopt;
}

size_t plySize(PlyType t) {
    switch (t) {
    case PlyType::Int8:
    case PlyType::UInt8:
        return 1;
    case PlyType::Int16:
    case PlyType::UInt16:
        return 2;
    case PlyType::Int32:
    case PlyType::UInt32:
    case PlyType::Float32:
        return 4;
    case PlyType::Float64:
        return 8;
    }
    return 1;
}

bool plyIsInteger(PlyType t) {
    return t != PlyType::Float32 && t != PlyType::Float64;
}

bool plyIsSigned(PlyType t) {
    return t == PlyType::Int8 || t == PlyType::Int16 || t == PlyType::Int32;
}

const char* plyName(PlyType t) {
    for (const PlyTypeName& n : kPlyTypeNames)
        if (n.type == t) return n.name;
    return "?";
}

void plyIntegerRange(PlyType t, int64_t& lo, int64_t& hi) {
    const size_t bits = plySize(t) * 8;
    if (plyIsSigned(t)) {
        hi = (int64_t(1) << (bits - 1)) - 1;
        lo = -hi - 1;
    } else {
        lo = 0;
        hi = (int64_t(1) << bits) - 1;
    }
}

// Reads one binary value of type t at p, swapping bytes when the file's order differs.
double plyValue(const unsigned char* p, PlyType t, bool swap) {
    unsigned char b[8];
    const size_t n = plySize(t);
    for (size_t i = 0; i < n; ++i) b[i] = swap ? p[n - 1 - i] : p[i];
    switch (t) {
    case PlyType::Int8:
        return double(int8_t(b[0]));
    case PlyType::UInt8:
        return double(b[0]);
    case PlyType::Int16: {
        int16_t v;
        std::memcpy(&v, b, 2);
        return v;
    }
    case PlyType::UInt16: {
        uint16_t v;
        std::memcpy(&v, b, 2);
        return v;
    }
    case PlyType::Int32: {
        int32_t v;
        std::memcpy(&v, b, 4);
        return v;
    }
    case PlyType::UInt32: {
        uint32_t v;
        std::memcpy(&v, b, 4);
        return v;
    }
    case PlyType::Float32: {
        float v;
        std::memcpy(&v, b, 4);
        return v;
    }
    case PlyType::Float64: {
        double v;
        std::memcpy(&v, b, 8);
        return v;
    }
    }
    return 0;
}

enum class PlyRole : uint8_t { Other, X, Y, Z, Indices };

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::Float32;
    bool list = false;
    PlyType countType = PlyType::UInt8;
    PlyRole role = PlyRole::Other;
};

enum class PlyKind : uint8_t { Other, Vertex, Face, TriStrips };

struct PlyElement {
    std::string name;
    uint64_t count = 0;
    std::vector<PlyProperty> properties;
    PlyKind kind = PlyKind::Other;
};

enum class PlyEncoding { Ascii, BinaryLittle, BinaryBig };

struct PlyHeader {
    PlyEncoding encoding = PlyEncoding::Ascii;
    std::vector<PlyElement> elements;
    size_t dataOffset = 0;
    size_t dataLine = 0; // line number of the first data line (ASCII)
    uint64_t vertexCount = 0;
    uint64_t faceCount = 0;
};

std::string plyElementSummary(const PlyHeader& h) {
    std::string s;
    for (size_t i = 0; i < h.elements.size(); ++i) {
        if (i > 0) s += i + 1 == h.elements.size() ? " and " : ", ";
        s += std::to_string(h.elements[i].count) + " '" + h.elements[i].name + "'";
    }
    return s;
}

PlyHeader parsePlyHeader(std::string_view data, const std::string& source) {
    constexpr size_t kMaxHeaderBytes = size_t(1) << 20;
    PlyHeader h;
    LineReader reader(data);
    Line line;
    bool sawEnd = false;
    bool anyCrlf = false;
    while (!sawEnd && reader.next(line)) {
        if (line.number > 2 && reader.position() > kMaxHeaderBytes)
            fail(source, "malformed PLY: no end_header line within the first 1 MiB (expected a "
                         "header of element and property lines ending with 'end_header')");
        anyCrlf = anyCrlf || line.crlf;
        for (char ch : line.text) {
            const unsigned char c = static_cast<unsigned char>(ch);
            if (c < 0x20 && c != '\t')
                fail(source, fmt("malformed PLY: the header contains byte 0x%02x on line %zu "
                                 "(expected text up to 'end_header')",
                                 unsigned(c), line.number));
        }
        Tokenizer tokens(line.text);
        std::string_view keyword;
        const bool any = tokens.next(keyword);
        if (!line.terminated && keyword != "end_header")
            fail(source, fmt("truncated PLY: the file ends at line %zu, inside the header "
                             "(expected a header ending with 'end_header', then the data)",
                             line.number));
        if (line.number == 1) {
            if (!any || (keyword != "ply" && keyword != "PLY") || tokens.next(keyword))
                fail(source, "malformed PLY: not a PLY file (expected 'ply' on the first line)");
            continue;
        }
        if (line.number == 2) {
            std::string_view encoding, version;
            // Exactly one space after "format", as PLY writers produce.
            if (!any || keyword != "format" || line.text.substr(0, 7) != "format " ||
                line.text.size() < 8 || isBlank(line.text[7]) || !tokens.next(encoding) ||
                !tokens.next(version))
                fail(source, "malformed PLY: the second line must be 'format <ascii | "
                             "binary_little_endian | binary_big_endian> 1.0'");
            if (encoding == "ascii")
                h.encoding = PlyEncoding::Ascii;
            else if (encoding == "binary_little_endian")
                h.encoding = PlyEncoding::BinaryLittle;
            else if (encoding == "binary_big_endian")
                h.encoding = PlyEncoding::BinaryBig;
            else
                fail(source, fmt("malformed PLY: unknown format %s (expected ascii, "
                                 "binary_little_endian or binary_big_endian)",
                                 quoted(encoding).c_str()));
            if (version.substr(0, 2) != "1." && version != "1")
                fail(source, fmt("malformed PLY: unsupported format version %s (expected 1.0)",
                                 quoted(version).c_str()));
            continue;
        }
        if (!any)
            fail(source, fmt("malformed PLY: blank line %zu in the header (expected element, "
                             "property, comment or end_header)",
                             line.number));
        if (keyword == "comment" || keyword == "obj_info") continue;
        if (keyword == "end_header") {
            sawEnd = true;
            break;
        }
        if (keyword == "element") {
            std::string_view name, count, extra;
            int64_t n = 0;
            if (!tokens.next(name) || !tokens.next(count) || tokens.next(extra))
                fail(source,
                     fmt("malformed PLY: line %zu must be 'element <name> <count>'", line.number));
            if (!parseInteger(count, n, false))
                fail(source, fmt("malformed PLY: element %s on line %zu has count %s (expected "
                                 "a non-negative integer)",
                                 quoted(name).c_str(), line.number, quoted(count).c_str()));
            for (const PlyElement& e : h.elements)
                if (e.name == name)
                    fail(source, fmt("malformed PLY: element %s is declared twice (line %zu)",
                                     quoted(name).c_str(), line.number));
            if (uint64_t(n) > kMaxMeshElements)
                failTooMany(source, "the PLY header", uint64_t(n),
                            ("'" + std::string(name) + "' elements").c_str());
            PlyElement e;
            e.name = std::string(name);
            e.count = uint64_t(n);
            e.kind = name == "vertex"      ? PlyKind::Vertex
                     : name == "face"      ? PlyKind::Face
                     : name == "tristrips" ? PlyKind::TriStrips
                                           : PlyKind::Other;
            h.elements.push_back(std::move(e));
            continue;
        }
        if (keyword == "property") {
            if (h.elements.empty())
                fail(source, fmt("malformed PLY: property on line %zu comes before any element",
                                 line.number));
            PlyProperty p;
            std::string_view t1, t2, t3, extra;
            if (!tokens.next(t1) || !tokens.next(t2))
                fail(source, fmt("malformed PLY: line %zu must be 'property <type> <name>' or "
                                 "'property list <count type> <type> <name>'",
                                 line.number));
            std::string_view typeName = t1, name = t2, countName;
            if (t1 == "list") {
                if (!tokens.next(t3))
                    fail(source, fmt("malformed PLY: line %zu must be 'property list <count "
                                     "type> <type> <name>'",
                                     line.number));
                p.list = true;
                countName = t2;
                typeName = t3;
                if (!tokens.next(name))
                    fail(source, fmt("malformed PLY: the list property on line %zu has no name",
                                     line.number));
            }
            if (tokens.next(extra))
                fail(source, fmt("malformed PLY: unexpected %s at the end of line %zu",
                                 quoted(extra).c_str(), line.number));
            const auto type = plyTypeFromName(typeName);
            if (!type)
                fail(source, fmt("malformed PLY: unknown property type %s on line %zu (expected "
                                 "char, uchar, short, ushort, int, uint, float, double or their "
                                 "int8...float64 names)",
                                 quoted(typeName).c_str(), line.number));
            p.type = *type;
            if (p.list) {
                const auto countType = plyTypeFromName(countName);
                if (!countType || !plyIsInteger(*countType))
                    fail(source, fmt("malformed PLY: list count type %s on line %zu is not an "
                                     "integer type",
                                     quoted(countName).c_str(), line.number));
                p.countType = *countType;
            }
            p.name = std::string(name);
            PlyElement& e = h.elements.back();
            for (const PlyProperty& q : e.properties)
                if (q.name == p.name)
                    fail(source, fmt("malformed PLY: property %s of element '%s' is declared "
                                     "twice (line %zu)",
                                     quoted(name).c_str(), e.name.c_str(), line.number));
            e.properties.push_back(std::move(p));
            continue;
        }
        double number = 0;
        if (parseReal(keyword, number) != Real::Invalid)
            fail(source, fmt("malformed PLY: line %zu looks like data, but the header has not "
                             "ended (expected 'end_header' before the data)",
                             line.number));
        fail(source, fmt("malformed PLY: unknown header line %zu starting with %s (expected "
                         "element, property, comment, obj_info or end_header)",
                         line.number, quoted(keyword).c_str()));
    }
    if (!sawEnd) {
        if (line.number < 2)
            fail(source, "truncated PLY: the file ends after the first line (expected a format "
                         "line and a header ending with 'end_header')");
        fail(source, fmt("truncated PLY: the file ends at line %zu, inside the header (expected "
                         "'end_header')",
                         line.number));
    }
    if (h.encoding != PlyEncoding::Ascii && anyCrlf)
        fail(source, "malformed PLY: a binary PLY header must end its lines with LF, not CRLF "
                     "(the binary data would start one byte off)");
    h.dataOffset = reader.position();
    h.dataLine = line.number + 1;

    // What we need from the elements, with the roles the walkers check.
    const PlyElement* vertex = nullptr;
    uint64_t faceCount = 0;
    for (PlyElement& e : h.elements) {
        if (e.kind == PlyKind::Vertex) {
            vertex = &e;
            for (PlyProperty& p : e.properties) {
                if (p.name == "x") p.role = PlyRole::X;
                if (p.name == "y") p.role = PlyRole::Y;
                if (p.name == "z") p.role = PlyRole::Z;
                if (p.role != PlyRole::Other && p.list)
                    fail(source, fmt("malformed PLY: vertex property '%s' is a list (expected a "
                                     "number)",
                                     p.name.c_str()));
            }
            for (const char* axis : {"x", "y", "z"}) {
                bool found = false;
                for (const PlyProperty& p : e.properties) found = found || p.name == axis;
                if (!found)
                    fail(source, fmt("malformed PLY: the vertex element has no '%s' property "
                                     "(expected x, y and z)",
                                     axis));
            }
        }
        if (e.kind == PlyKind::TriStrips && e.count > 0)
            fail(source, "unsupported PLY element 'tristrips': triangle strips are not read "
                         "(convert them to a 'face' element)");
        if (e.kind == PlyKind::Face) {
            PlyProperty* indices = nullptr;
            for (PlyProperty& p : e.properties)
                if (p.name == "vertex_indices" || p.name == "vertex_index") {
                    if (indices)
                        fail(source, fmt("malformed PLY: element '%s' has both vertex_indices "
                                         "and vertex_index",
                                         e.name.c_str()));
                    indices = &p;
                }
            if (!indices || !indices->list || !plyIsInteger(indices->type))
                fail(source, fmt("malformed PLY: element '%s' has no list property "
                                 "vertex_indices of an integer type",
                                 e.name.c_str()));
            indices->role = PlyRole::Indices;
            faceCount += e.count;
        }
    }
    if (!vertex)
        fail(source, "malformed PLY: the header declares no 'vertex' element (expected vertex "
                     "and face elements)");
    h.vertexCount = vertex->count;
    h.faceCount = faceCount;
    if (h.vertexCount == 0)
        fail(source, "the PLY header declares 0 vertices: the mesh is empty (expected at least "
                     "3 vertices and 1 face)");
    if (faceCount == 0)
        fail(source, "the PLY file has no faces, so no triangles (a point cloud?); expected a "
                     "triangle mesh with at least 1 face");
    return h;
}

void store(RawPart& part, uint64_t vertex, PlyRole role, float value) {
    if (vertex >= part.positions.size()) part.positions.resize(size_t(vertex) + 1);
    Vec3& p = part.positions[size_t(vertex)];
    if (role == PlyRole::X) p.x = value;
    if (role == PlyRole::Y) p.y = value;
    if (role == PlyRole::Z) p.z = value;
}

[[noreturn]] void failPlyIndex(const std::string& source, const PlyElement& e, uint64_t i,
                               int64_t index, uint64_t vertexCount, const std::string& where) {
    fail(source, fmt("malformed PLY: %s %llu%s uses vertex index %lld, out of range: the file "
                     "has %llu vertices (expected 0 to %llu)",
                     e.name.c_str(), ull(i), where.c_str(), (long long)index, ull(vertexCount),
                     ull(vertexCount - 1)));
}

void readPlyBinary(const PlyHeader& h, std::string_view data, const std::string& source,
                   RawPart& part) {
    const bool fileBig = h.encoding == PlyEncoding::BinaryBig;
    const bool swap = fileBig != (std::endian::native == std::endian::big);
    const auto* bytes = reinterpret_cast<const unsigned char*>(data.data());
    const size_t size = data.size();
    size_t pos = h.dataOffset;

    // Cheap first: the least the declared elements can take.
    uint64_t least = 0;
    for (const PlyElement& e : h.elements) {
        uint64_t per = 0;
        for (const PlyProperty& p : e.properties)
            per += p.list ? plySize(p.countType) : plySize(p.type);
        least += per * e.count;
    }
    if (least > size - pos)
        fail(source, fmt("truncated binary PLY: the header declares %s elements, which need at "
                         "least %llu bytes of data, but only %zu bytes follow the header",
                         plyElementSummary(h).c_str(), ull(least), size - pos));

    for (const PlyElement& e : h.elements) {
        auto truncated = [&](uint64_t i) {
            fail(source,
                 fmt("truncated binary PLY: the header declares %s elements, but the "
                     "data ends inside %s %llu of %llu (at byte %zu)",
                     plyElementSummary(h).c_str(), e.name.c_str(), ull(i), ull(e.count), size));
        };
        for (uint64_t i = 0; i < e.count; ++i) {
            for (const PlyProperty& p : e.properties) {
                if (!p.list) {
                    const size_t n = plySize(p.type);
                    if (size - pos < n) truncated(i);
                    if (p.role != PlyRole::Other) {
                        const double v = plyValue(bytes + pos, p.type, swap);
                        if (!std::isfinite(v) ||
                            std::fabs(v) > double(std::numeric_limits<float>::max())) {
                            char text[32];
                            std::snprintf(text, sizeof text, "%s = %g", p.name.c_str(), v);
                            failNonFinite(source, "binary PLY", i, "", text);
                        }
                        store(part, i, p.role, float(v));
                    }
                    pos += n;
                    continue;
                }
                const size_t countSize = plySize(p.countType);
                if (size - pos < countSize) truncated(i);
                const double countValue = plyValue(bytes + pos, p.countType, swap);
                pos += countSize;
                if (countValue < 0)
                    fail(source, fmt("malformed binary PLY: %s %llu has a negative list length "
                                     "%g in '%s'",
                                     e.name.c_str(), ull(i), countValue, p.name.c_str()));
                const uint64_t count = uint64_t(countValue);
                const size_t itemSize = plySize(p.type);
                if (p.role == PlyRole::Indices) {
                    if (count == 0)
                        fail(source, fmt("malformed binary PLY: face %llu has no vertices "
                                         "(expected at least 3)",
                                         ull(i)));
                    if (count > kMaxPolygonCorners)
                        fail(source, fmt("binary PLY face %llu has %llu corners, more than the "
                                         "limit of %llu per polygon",
                                         ull(i), ull(count), ull(kMaxPolygonCorners)));
                }
                if ((size - pos) / itemSize < count) truncated(i);
                if (p.role == PlyRole::Indices) {
                    for (uint64_t k = 0; k < count; ++k) {
                        const auto index =
                            int64_t(plyValue(bytes + pos + k * itemSize, p.type, swap));
                        if (index < 0 || uint64_t(index) >= h.vertexCount)
                            failPlyIndex(source, e, i, index, h.vertexCount, "");
                        part.corners.push_back(uint32_t(index));
                    }
                    part.addFace(uint32_t(count));
                }
                pos += count * itemSize;
            }
        }
    }
}

void readPlyAscii(const PlyHeader& h, std::string_view data, const std::string& source,
                  RawPart& part) {
    checkText(data.substr(h.dataOffset), h.dataOffset, source, "ASCII PLY");
    LineReader reader(data, h.dataOffset, h.dataLine);
    Line line;
    for (const PlyElement& e : h.elements) {
        for (uint64_t i = 0; i < e.count; ++i) {
            const bool got = reader.next(line);
            if (!got || (isBlankLine(line.text) && reader.onlyBlankRemains()))
                fail(source, fmt("truncated ASCII PLY: the header declares %s elements, but the "
                                 "data ends before %s %llu",
                                 plyElementSummary(h).c_str(), e.name.c_str(), ull(i)));
            if (isBlankLine(line.text))
                fail(source, fmt("malformed ASCII PLY: line %zu is blank where %s %llu was "
                                 "expected (one element per line, no blank lines)",
                                 line.number, e.name.c_str(), ull(i)));
            auto bad = [&](const std::string& problem) {
                if (!line.terminated)
                    fail(source, fmt("truncated ASCII PLY: the last line (%zu, %s %llu) is "
                                     "incomplete: %s",
                                     line.number, e.name.c_str(), ull(i), problem.c_str()));
                fail(source, fmt("malformed ASCII PLY: line %zu (%s %llu): %s", line.number,
                                 e.name.c_str(), ull(i), problem.c_str()));
            };
            Tokenizer tokens(line.text);
            std::string_view token;
            auto integer = [&](PlyType type, const std::string& what) {
                if (!tokens.next(token)) bad("too few values, " + what + " is missing");
                int64_t v = 0, lo = 0, hi = 0;
                plyIntegerRange(type, lo, hi);
                if (!parseInteger(token, v, plyIsSigned(type)) || v < lo || v > hi)
                    bad(what + " is " + quoted(token) + ", expected an integer of type " +
                        plyName(type));
                return v;
            };
            for (const PlyProperty& p : e.properties) {
                if (!p.list) {
                    if (plyIsInteger(p.type)) {
                        const int64_t v = integer(p.type, "'" + p.name + "'");
                        if (p.role != PlyRole::Other) store(part, i, p.role, float(v));
                        continue;
                    }
                    if (!tokens.next(token)) bad("too few values, '" + p.name + "' is missing");
                    double v = 0;
                    const Real r = parseReal(token, v);
                    if (r == Real::Invalid)
                        bad("'" + p.name + "' is " + quoted(token) + ", expected a number");
                    if (r == Real::NonFinite && p.role != PlyRole::Other)
                        failNonFinite(source, "ASCII PLY", i,
                                      fmt(" (line %zu, %s)", line.number, p.name.c_str()), token);
                    if (p.role != PlyRole::Other)
                        store(part, i, p.role,
                              p.type == PlyType::Float64 ? float(decimalToDouble(token))
                                                         : decimalToFloat(token));
                    continue;
                }
                const int64_t count = integer(p.countType, "the length of list '" + p.name + "'");
                if (count < 0) bad("negative list length");
                if (p.role == PlyRole::Indices) {
                    if (count == 0) bad("a face without vertices (expected at least 3)");
                    if (uint64_t(count) > kMaxPolygonCorners)
                        fail(source,
                             fmt("ASCII PLY face %llu (line %zu) has %lld corners, more "
                                 "than the limit of %llu per polygon",
                                 ull(i), line.number, (long long)count, ull(kMaxPolygonCorners)));
                }
                for (int64_t k = 0; k < count; ++k) {
                    if (!plyIsInteger(p.type)) {
                        double v = 0;
                        if (!tokens.next(token)) bad("too few values in list '" + p.name + "'");
                        if (parseReal(token, v) == Real::Invalid)
                            bad("list '" + p.name + "' has " + quoted(token) +
                                ", expected a number");
                        continue;
                    }
                    const int64_t index = integer(p.type, "an item of list '" + p.name + "'");
                    if (p.role == PlyRole::Indices) {
                        if (index < 0 || uint64_t(index) >= h.vertexCount)
                            failPlyIndex(source, e, i, index, h.vertexCount,
                                         fmt(" (line %zu)", line.number));
                        part.corners.push_back(uint32_t(index));
                    }
                }
                if (p.role == PlyRole::Indices) part.addFace(uint32_t(count));
            }
        }
    }
}

} // namespace

// Vertices are shared by the faces that use them, in the file's order; face corners are indices
// into them.
std::vector<RawPart> readPly(std::string_view data, const std::string& source) {
    const PlyHeader h = parsePlyHeader(data, source);
    std::vector<RawPart> parts(1);
    RawPart& part = parts[0];
    // Storage is sized from the header only where the file is large enough to hold what it
    // declares (a vertex takes at least 2 bytes, a face 4); otherwise it grows as elements are
    // read, and the walk stops at the end of the file.
    if (h.vertexCount <= data.size() / 2) part.positions.resize(size_t(h.vertexCount), Vec3{});
    if (h.faceCount <= data.size() / 4) {
        part.faceSizes.reserve(size_t(h.faceCount));
        part.corners.reserve(size_t(h.faceCount) * 3);
    }
    if (h.encoding == PlyEncoding::Ascii)
        readPlyAscii(h, data, source, part);
    else
        readPlyBinary(h, data, source, part);
    part.positions.resize(size_t(h.vertexCount), Vec3{});
    return parts;
}

} // namespace ffd::detail
