// Pre-checks of OBJ, PLY, STL and OFF files before Assimp reads them; see format_checks.h.
//
// Each check mirrors how Assimp 5.2.5 tokenises the format (line by line for OBJ, OFF and
// ASCII PLY; token by token for ASCII STL; byte offsets for binary PLY and STL) and rejects
// what Assimp would misread: anything accepted here is parsed by Assimp into the same
// vertices and faces that were checked.
#include "mesh/format_checks.h"

#include "ffdaabb/error.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <optional>
#include <vector>

namespace ffd::detail {

const char* formatExtension(MeshFormat format) {
    switch (format) {
    case MeshFormat::Obj:
        return "obj";
    case MeshFormat::Ply:
        return "ply";
    case MeshFormat::Stl:
        return "stl";
    case MeshFormat::Off:
        return "off";
    }
    return "?";
}

namespace {

__attribute__((format(printf, 1, 2))) std::string fmt(const char* format, ...) {
    va_list args;
    va_start(args, format);
    va_list copy;
    va_copy(copy, args);
    const int n = std::vsnprintf(nullptr, 0, format, copy);
    va_end(copy);
    std::string out(n > 0 ? size_t(n) : 0, '\0');
    if (n > 0) std::vsnprintf(out.data(), out.size() + 1, format, args);
    va_end(args);
    return out;
}

[[noreturn]] void fail(const std::string& source, const std::string& problem) {
    throw InputError(source, problem);
}

using ull = unsigned long long;

// Quotes a token for a message, shortened so that a binary blob cannot flood the message.
std::string quoted(std::string_view token) {
    constexpr size_t kMax = 40;
    std::string out = "'";
    for (size_t i = 0; i < token.size() && i < kMax; ++i) {
        const unsigned char c = static_cast<unsigned char>(token[i]);
        out += (c >= 0x20 && c < 0x7f) ? char(c) : '?';
    }
    if (token.size() > kMax) out += "...";
    return out + "'";
}

bool isBlank(char c) {
    return c == ' ' || c == '\t';
}

bool isBlankLine(std::string_view s) {
    for (char c : s)
        if (!isBlank(c)) return false;
    return true;
}

// Rejects bytes no text mesh format contains. Assimp's line readers treat NUL and form feed as
// line ends and then scan for the next '\n' without a bound, and a lone carriage return sends
// them the same way, so these are errors here rather than whitespace.
void checkText(std::string_view text, size_t offset, const std::string& source, const char* what) {
    for (size_t i = 0; i < text.size(); ++i) {
        const unsigned char c = static_cast<unsigned char>(text[i]);
        if (c >= 0x20 || c == '\t' || c == '\n') continue;
        if (c == '\r' && (i + 1 == text.size() || text[i + 1] == '\n')) continue;
        if (c == '\r')
            fail(source, fmt("malformed %s: carriage return without a line feed at byte %zu "
                             "(expected LF or CRLF line ends)",
                             what, offset + i));
        fail(source, fmt("malformed %s: byte 0x%02x at offset %zu is not text (expected a text "
                         "file; is this a binary file with the wrong extension?)",
                         what, unsigned(c), offset + i));
    }
}

struct Line {
    std::string_view text; // without "\n" or "\r\n"
    size_t number = 0;     // 1-based
    bool terminated = false;
    bool crlf = false;
};

class LineReader {
public:
    explicit LineReader(std::string_view data, size_t start = 0, size_t firstNumber = 1)
        : data_(data), pos_(start), number_(firstNumber) {}

    bool next(Line& line) {
        if (pos_ >= data_.size()) return false;
        size_t end = data_.find('\n', pos_);
        line.terminated = end != std::string_view::npos;
        if (!line.terminated) end = data_.size();
        std::string_view text = data_.substr(pos_, end - pos_);
        line.crlf = !text.empty() && text.back() == '\r';
        if (line.crlf) text.remove_suffix(1);
        line.text = text;
        line.number = number_++;
        pos_ = line.terminated ? end + 1 : end;
        return true;
    }
    size_t position() const { return pos_; }
    bool atEnd() const { return pos_ >= data_.size(); }
    // True when nothing but blank lines follows.
    bool onlyBlankRemains() const {
        for (size_t i = pos_; i < data_.size(); ++i)
            if (!isBlank(data_[i]) && data_[i] != '\n' && data_[i] != '\r') return false;
        return true;
    }

private:
    std::string_view data_;
    size_t pos_;
    size_t number_;
};

class Tokenizer {
public:
    explicit Tokenizer(std::string_view s) : s_(s) {}
    bool next(std::string_view& token) {
        while (pos_ < s_.size() && isBlank(s_[pos_])) ++pos_;
        if (pos_ >= s_.size()) return false;
        const size_t start = pos_;
        while (pos_ < s_.size() && !isBlank(s_[pos_])) ++pos_;
        token = s_.substr(start, pos_ - start);
        return true;
    }

private:
    std::string_view s_;
    size_t pos_ = 0;
};

enum class Real { Ok, Invalid, NonFinite };

// Parses a whole token as a real number. Values a float cannot hold count as non-finite:
// Assimp stores single precision, where they become infinities.
Real parseReal(std::string_view token, double& value) {
    std::string_view t = token;
    if (!t.empty() && t.front() == '+') {
        t.remove_prefix(1);
        if (!t.empty() && t.front() == '-') return Real::Invalid;
    }
    if (t.empty()) return Real::Invalid;
    const char* first = t.data();
    const char* last = first + t.size();
    const auto [ptr, ec] = std::from_chars(first, last, value, std::chars_format::general);
    if (ec == std::errc::invalid_argument || ptr != last) return Real::Invalid;
    if (ec == std::errc::result_out_of_range) {
        // Too large or too small for a double: strtod says which (rare, so the copy is fine).
        const std::string copy(t);
        value = std::strtod(copy.c_str(), nullptr);
        return std::isinf(value) ? Real::NonFinite : Real::Ok;
    }
    if (!std::isfinite(value) || std::fabs(value) > double(std::numeric_limits<float>::max()))
        return Real::NonFinite;
    return Real::Ok;
}

// Parses a whole token as a decimal integer: digits only, or with a sign when allowed.
bool parseInteger(std::string_view token, int64_t& value, bool allowSign) {
    std::string_view t = token;
    if (t.empty()) return false;
    if (t.front() == '+' || t.front() == '-') {
        if (!allowSign) return false;
        if (t.front() == '+') t.remove_prefix(1);
    }
    if (t.empty() || t.front() == '+') return false;
    const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
    return ec == std::errc() && ptr == t.data() + t.size();
}

[[noreturn]] void failNonFinite(const std::string& source, const char* what, uint64_t vertex,
                                const std::string& where, std::string_view token) {
    fail(source, fmt("non-finite coordinate in %s: vertex %llu%s has %s (expected finite "
                     "numbers that fit a 32-bit float)",
                     what, ull(vertex), where.c_str(), quoted(token).c_str()));
}

[[noreturn]] void failTooMany(const std::string& source, const char* what, uint64_t count,
                              const char* things) {
    fail(source, fmt("%s declares %llu %s, more than the limit of %llu (2^28): the header is "
                     "corrupt or the mesh is too large",
                     what, ull(count), things, ull(kMaxMeshElements)));
}

// ---------------------------------------------------------------------------------------------
// PLY

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
            // Assimp expects exactly one space after "format".
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
            fail(source, "unsupported PLY element 'tristrips': Assimp 5.2.5 reads triangle "
                         "strips wrongly (convert them to a 'face' element)");
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
    if (h.vertexCount == 0)
        fail(source, "the PLY header declares 0 vertices: the mesh is empty (expected at least "
                     "3 vertices and 1 face)");
    if (faceCount == 0)
        fail(source, "the PLY file has no faces, so no triangles (a point cloud?); expected a "
                     "triangle mesh with at least 1 face");
    return h;
}

[[noreturn]] void failPlyIndex(const std::string& source, const PlyElement& e, uint64_t i,
                               int64_t index, uint64_t vertexCount, const std::string& where) {
    fail(source, fmt("malformed PLY: %s %llu%s uses vertex index %lld, out of range: the file "
                     "has %llu vertices (expected 0 to %llu)",
                     e.name.c_str(), ull(i), where.c_str(), (long long)index, ull(vertexCount),
                     ull(vertexCount - 1)));
}

void checkPlyBinary(const PlyHeader& h, std::string_view data, const std::string& source) {
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
                if (p.role == PlyRole::Indices)
                    for (uint64_t k = 0; k < count; ++k) {
                        const auto index =
                            int64_t(plyValue(bytes + pos + k * itemSize, p.type, swap));
                        if (index < 0 || uint64_t(index) >= h.vertexCount)
                            failPlyIndex(source, e, i, index, h.vertexCount, "");
                    }
                pos += count * itemSize;
            }
        }
    }
}

void checkPlyAscii(const PlyHeader& h, std::string_view data, const std::string& source) {
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
                        integer(p.type, "'" + p.name + "'");
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
                    }
                }
            }
        }
    }
}

void checkPly(std::string_view data, const std::string& source, PrecheckResult& result) {
    const PlyHeader h = parsePlyHeader(data, source);
    if (h.encoding == PlyEncoding::Ascii) {
        checkPlyAscii(h, data, source);
        result.text = true;
    } else {
        checkPlyBinary(h, data, source);
    }
}

// ---------------------------------------------------------------------------------------------
// STL

uint32_t loadLittle32(const unsigned char* p) {
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

float loadLittleFloat(const unsigned char* p) {
    const uint32_t bits = loadLittle32(p);
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
}

void checkStlBinary(std::string_view data, uint32_t triangles, const std::string& source) {
    if (triangles == 0)
        fail(source, "the binary STL declares 0 triangles: no triangles, the mesh is empty "
                     "(expected at least 1 triangle)");
    const auto* bytes = reinterpret_cast<const unsigned char*>(data.data());
    for (uint32_t t = 0; t < triangles; ++t) {
        const unsigned char* record = bytes + 84 + size_t(t) * 50;
        for (int corner = 0; corner < 3; ++corner)
            for (int axis = 0; axis < 3; ++axis) {
                const float v = loadLittleFloat(record + 12 + corner * 12 + axis * 4);
                if (!std::isfinite(v)) {
                    char text[48];
                    std::snprintf(text, sizeof text, "%c = %g", "xyz"[axis], double(v));
                    failNonFinite(source, "binary STL", uint64_t(t) * 3 + unsigned(corner),
                                  fmt(" (triangle %u, corner %d)", t, corner), text);
                }
            }
    }
}

// A token stream over a whole text, with line numbers for messages.
class TextTokens {
public:
    explicit TextTokens(std::string_view text) : text_(text) {}
    bool next(std::string_view& token) {
        skip();
        if (pos_ >= text_.size()) return false;
        const size_t start = pos_;
        while (pos_ < text_.size() && !isSeparator(text_[pos_])) ++pos_;
        token = text_.substr(start, pos_ - start);
        tokenLine_ = line_;
        return true;
    }
    // Drops the rest of the current line (a solid's name).
    void skipLine() {
        while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    }
    size_t line() const { return tokenLine_; }
    bool onlySpaceRemains() {
        skip();
        return pos_ >= text_.size();
    }

private:
    static bool isSeparator(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
    void skip() {
        while (pos_ < text_.size() && isSeparator(text_[pos_])) {
            if (text_[pos_] == '\n') ++line_;
            ++pos_;
        }
    }
    std::string_view text_;
    size_t pos_ = 0;
    size_t line_ = 1;
    size_t tokenLine_ = 1;
};

void checkStlAscii(std::string_view data, const std::string& source) {
    checkText(data, 0, source, "ASCII STL");
    TextTokens tokens(data);
    std::string_view token;
    uint64_t facets = 0;
    auto expect = [&](std::string_view keyword) {
        if (!tokens.next(token))
            fail(source, fmt("truncated ASCII STL: the file ends after %llu facets, where '%.*s' "
                             "was expected",
                             ull(facets), int(keyword.size()), keyword.data()));
        if (token != keyword)
            fail(source,
                 fmt("malformed ASCII STL: line %zu has %s where '%.*s' was expected",
                     tokens.line(), quoted(token).c_str(), int(keyword.size()), keyword.data()));
    };
    // Assimp reads a facet's normal and a vertex's coordinates from the keyword's line only.
    size_t keywordLine = 0;
    auto number = [&](bool position, uint64_t vertex) {
        if (!tokens.next(token))
            fail(source, fmt("truncated ASCII STL: the file ends inside facet %llu", ull(facets)));
        if (tokens.line() != keywordLine)
            fail(source, fmt("malformed ASCII STL: line %zu: the three numbers of 'vertex' and "
                             "'facet normal' must be on the keyword's line",
                             keywordLine));
        double v = 0;
        const Real r = parseReal(token, v);
        if (r == Real::Invalid)
            fail(source, fmt("malformed ASCII STL: line %zu has %s where a number was expected",
                             tokens.line(), quoted(token).c_str()));
        if (r == Real::NonFinite && position)
            failNonFinite(source, "ASCII STL", vertex,
                          fmt(" (facet %llu, line %zu)", ull(facets), tokens.line()), token);
    };
    // Assimp reads "solid" and "endsolid" as prefixes; so do we.
    for (;;) {
        if (!tokens.next(token) || token.substr(0, 5) != "solid")
            fail(source, fmt("malformed ASCII STL: line %zu has %s where 'solid' was expected",
                             tokens.line(), quoted(token).c_str()));
        tokens.skipLine(); // the solid's name
        for (;;) {
            if (!tokens.next(token))
                fail(source, fmt("truncated ASCII STL: the file ends after %llu facets without "
                                 "'endsolid'",
                                 ull(facets)));
            if (token.substr(0, 8) == "endsolid") {
                tokens.skipLine();
                break;
            }
            if (token != "facet")
                fail(source, fmt("malformed ASCII STL: line %zu has %s where 'facet' or "
                                 "'endsolid' was expected",
                                 tokens.line(), quoted(token).c_str()));
            keywordLine = tokens.line();
            expect("normal");
            if (tokens.line() != keywordLine)
                fail(source, fmt("malformed ASCII STL: line %zu: 'facet' without 'normal' on "
                                 "the same line",
                                 keywordLine));
            for (int k = 0; k < 3; ++k) number(false, 0);
            expect("outer");
            expect("loop");
            for (int corner = 0; corner < 3; ++corner) {
                expect("vertex");
                keywordLine = tokens.line();
                for (int k = 0; k < 3; ++k) number(true, facets * 3 + unsigned(corner));
            }
            expect("endloop");
            expect("endfacet");
            ++facets;
        }
        if (tokens.onlySpaceRemains()) break;
    }
    if (facets == 0)
        fail(source, "the ASCII STL has no facets, so no triangles: the mesh is empty (expected "
                     "at least 1 triangle)");
}

void checkStl(std::string_view data, const std::string& source, PrecheckResult& result) {
    const auto* bytes = reinterpret_cast<const unsigned char*>(data.data());
    const uint64_t size = data.size();
    const uint32_t triangles = size >= 84 ? loadLittle32(bytes + 80) : 0;
    const uint64_t binarySize = 84 + 50 * uint64_t(triangles);
    // Assimp's order: the size rule for binary first, then "solid" for ASCII.
    if (size >= 84 && binarySize == size) {
        checkStlBinary(data, triangles, source);
        return;
    }
    size_t p = 0;
    while (p < data.size() && isBlank(data[p])) ++p;
    // Binary headers often start with "solid" too; only text is read as ASCII here, and the
    // rest gets the binary diagnosis below (Assimp would try it as ASCII and find nothing).
    const bool text = std::all_of(data.begin(), data.end(), [](char ch) {
        const auto c = static_cast<unsigned char>(ch);
        return c >= 0x20 || c == '\t' || c == '\n' || c == '\r';
    });
    const bool solid = data.size() > p + 5 && data.substr(p, 5) == "solid";
    if (solid && text) {
        // Assimp computes the binary size in 32 bits: a wrap-around match would make it read
        // this text as a binary file of billions of triangles.
        if (size >= 84 && uint32_t(84 + 50 * triangles) == size)
            fail(source, "malformed STL: an ASCII STL whose size matches a wrapped-around binary "
                         "triangle count (Assimp would misread it as binary)");
        checkStlAscii(data, source);
        result.text = true;
        return;
    }
    bool printable = size >= 84;
    for (size_t i = 0; i < 84 && printable; ++i) {
        const unsigned char c = bytes[i];
        printable = (c >= 0x20 && c < 0x7f) || c == '\n' || c == '\r' || c == '\t';
    }
    // Text that starts like ASCII STL: say where it stops being text.
    if (solid && (size < 84 || printable)) checkText(data, 0, source, "ASCII STL");
    if (size < 84)
        fail(source, fmt("truncated or malformed STL: %llu bytes is too short for a binary STL "
                         "(80-byte header and a 4-byte triangle count) and the file does not "
                         "start with 'solid' like an ASCII STL",
                         ull(size)));
    if (printable)
        fail(source, "malformed STL: the file is text but does not start with 'solid' (an ASCII "
                     "STL starts with 'solid <name>'; a binary STL has a 4-byte triangle count "
                     "at byte 80)");
    if (triangles > kMaxMeshElements)
        failTooMany(source, "the binary STL header", triangles, "triangles");
    if (binarySize > size)
        fail(source, fmt("truncated binary STL: the header declares %u triangles, which need "
                         "84 + 50 x %u = %llu bytes, but the file has only %llu bytes",
                         triangles, triangles, ull(binarySize), ull(size)));
    fail(source, fmt("malformed binary STL: the header declares %u triangles (84 + 50 x %u = %llu "
                     "bytes), but the file has %llu bytes, %llu too many",
                     triangles, triangles, ull(binarySize), ull(size), ull(size - binarySize)));
}

// ---------------------------------------------------------------------------------------------
// OFF

// Assimp copies each OFF line into a 4096-byte buffer (and writes one byte past it for a line
// of exactly that length).
constexpr size_t kMaxOffLine = 4000;

void checkOff(std::string_view data, const std::string& source, PrecheckResult& result) {
    checkText(data, 0, source, "OFF");
    result.text = true;
    const size_t size = data.size();
    size_t pos = 0;
    size_t lineNumber = 1;
    // Like Assimp's NextToken: skips blanks, line ends and whole comment lines.
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
    // Assimp reads a colour as 4 values unless a comment follows: demand all four.
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

    // The data: one element per line, empty lines skipped (as Assimp's GetNextLine does).
    LineReader reader(data, pos, lineNumber);
    Line line;
    auto nextLine = [&](const char* what, uint64_t i) {
        do {
            if (!reader.next(line))
                fail(source, fmt("truncated OFF: the header declares %llu vertices and %llu "
                                 "faces, but the file ends before %s %llu",
                                 ull(vertexCount), ull(faceCount), what, ull(i)));
        } while (line.text.empty());
        if (line.text.size() > kMaxOffLine)
            fail(source, fmt("malformed OFF: line %zu is longer than %zu characters", line.number,
                             kMaxOffLine));
    };
    auto bad = [&](const char* what, uint64_t i, const std::string& problem) {
        if (!line.terminated)
            fail(source, fmt("truncated OFF: the last line (%zu, %s %llu) is incomplete: %s",
                             line.number, what, ull(i), problem.c_str()));
        fail(source, fmt("malformed OFF: line %zu (%s %llu): %s", line.number, what, ull(i),
                         problem.c_str()));
    };
    for (uint64_t i = 0; i < vertexCount; ++i) {
        nextLine("vertex", i);
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
        }
    }
    for (uint64_t i = 0; i < faceCount; ++i) {
        nextLine("face", i);
        Tokenizer tokens(line.text);
        std::string_view t;
        int64_t corners = 0;
        if (!tokens.next(t) || !parseInteger(t, corners, false))
            bad("face", i, "expected the number of corners, found " + quoted(t));
        if (corners == 0) bad("face", i, "a face without vertices (expected at least 3)");
        if (corners > 9)
            fail(source, fmt("unsupported OFF face %llu (line %zu): %lld corners; Assimp reads "
                             "at most 9 per face (split the polygon)",
                             ull(i), line.number, (long long)corners));
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
        }
    }
}

// ---------------------------------------------------------------------------------------------
// OBJ

// Parses an OBJ index: what C's atoi reads and Assimp steps over exactly (no '+', no leading
// zeros, no zero), within int range.
bool parseObjIndex(std::string_view t, int64_t& value) {
    if (t.empty()) return false;
    size_t i = t.front() == '-' ? 1 : 0;
    if (i >= t.size() || t[i] < '1' || t[i] > '9') return false;
    if (!parseInteger(t, value, true)) return false;
    return value >= std::numeric_limits<int32_t>::min() &&
           value <= std::numeric_limits<int32_t>::max();
}

void checkObj(std::string_view data, const std::string& source, PrecheckResult& result) {
    checkText(data, 0, source, "OBJ");
    result.text = true;
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
        // Line continuation: Assimp joins a line ending in '\' with the next one.
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
                // Assimp copies the first character after a continuation unchecked: an empty
                // line there would embed a line break and swallow the line after it.
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
            // Assimp skips free-form curve and surface bodies up to "end".
            if (text.front() == 'e' && keyword == "end") inCurveSection = false;
            continue;
        }
        if (isBlank(text.front())) {
            // Assimp dispatches on the first character, so it would silently drop these.
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
                bad(fmt("unsupported statement %s (Assimp would read it as %s)",
                        quoted(keyword).c_str(), text[1] == 't' ? "vt" : "vn"));
            // Assimp counts the values of v, vt and vn before reading them, and counts only
            // tokens that start with a digit, a sign, "nan" or "inf": ".5" would not count.
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
            ++vertices;
            break;
        }
        case 'f':
        case 'l':
        case 'p': {
            if (keyword != "f" && keyword != "fo" && keyword != "l" && keyword != "p")
                bad(fmt("unsupported statement %s (Assimp would read it as a face)",
                        quoted(keyword).c_str()));
            if (statement.size() != text.size())
                bad("a comment on a face, line or point statement (Assimp 5.2.5 reads '#' as a "
                    "bad index there; put comments on their own lines)");
            Tokenizer refs(statement);
            std::string_view ref;
            refs.next(ref); // the keyword
            uint64_t corners = 0;
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
                ++corners;
            }
            if (keyword == "f" || keyword == "fo") {
                if (corners < 3)
                    bad(fmt("a face with %llu corners (expected at least 3)", ull(corners)));
                if (corners > kMaxPolygonCorners)
                    fail(source, fmt("OBJ face on line %zu has %llu corners, more than the limit "
                                     "of %llu per polygon",
                                     number, ull(corners), ull(kMaxPolygonCorners)));
                ++faces;
            }
            if (keyword == "l" && corners == 1)
                bad("a line statement with 1 point (expected at least 2)");
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
}

} // namespace

PrecheckResult precheck(MeshFormat format, std::string_view data, const std::string& source) {
    PrecheckResult result;
    switch (format) {
    case MeshFormat::Obj:
        checkObj(data, source, result);
        break;
    case MeshFormat::Ply:
        checkPly(data, source, result);
        break;
    case MeshFormat::Stl:
        checkStl(data, source, result);
        break;
    case MeshFormat::Off:
        checkOff(data, source, result);
        break;
    }
    return result;
}

} // namespace ffd::detail
