// STL files (ASCII and binary); see mesh_reader.h.
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
namespace {

uint32_t loadLittle32(const unsigned char* p) {
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

float loadLittleFloat(const unsigned char* p) {
    const uint32_t bits = loadLittle32(p);
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
}

void readStlBinary(std::string_view data, uint32_t triangles, const std::string& source,
                   std::vector<RawPart>& parts) {
    if (triangles == 0)
        fail(source, "the binary STL declares 0 triangles: no triangles, the mesh is empty "
                     "(expected at least 1 triangle)");
    const auto* bytes = reinterpret_cast<const unsigned char*>(data.data());
    RawPart& part = parts.emplace_back();
    part.positions.resize(size_t(triangles) * 3);
    part.corners.resize(size_t(triangles) * 3);
    part.faceSizes.assign(triangles, 3);
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
                part.positions[size_t(t) * 3 + size_t(corner)][axis] = v;
            }
        for (size_t k = 0; k < part.corners.size(); ++k) part.corners[k] = uint32_t(k);
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

void readStlAscii(std::string_view data, const std::string& source, std::vector<RawPart>& parts) {
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
    // A facet's normal and a vertex's coordinates are on the keyword's line.
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
        return position ? decimalToFloat(token) : 0.0f;
    };
    // "solid" and "endsolid" are read as prefixes ("solidname" is a solid).
    for (;;) {
        if (!tokens.next(token) || token.substr(0, 5) != "solid")
            fail(source, fmt("malformed ASCII STL: line %zu has %s where 'solid' was expected",
                             tokens.line(), quoted(token).c_str()));
        tokens.skipLine();                    // the solid's name
        RawPart& part = parts.emplace_back(); // one part per solid
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
                Vec3 p;
                for (int k = 0; k < 3; ++k) p[k] = number(true, facets * 3 + unsigned(corner));
                part.corners.push_back(uint32_t(part.positions.size()));
                part.positions.push_back(p);
            }
            part.addFace(3);
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

} // namespace

// Binary when the size is exactly 84 + 50 x the triangle count at byte 80, else ASCII when it is
// text starting with "solid". Every facet has its own three vertices (loadMesh welds equal
// positions afterwards); each ASCII solid is a part.
std::vector<RawPart> readStl(std::string_view data, const std::string& source) {
    std::vector<RawPart> parts;
    const auto* bytes = reinterpret_cast<const unsigned char*>(data.data());
    const uint64_t size = data.size();
    const uint32_t triangles = size >= 84 ? loadLittle32(bytes + 80) : 0;
    const uint64_t binarySize = 84 + 50 * uint64_t(triangles);
    // The size rule for binary first, then "solid" for ASCII.
    if (size >= 84 && binarySize == size) {
        readStlBinary(data, triangles, source, parts);
        return parts;
    }
    size_t p = 0;
    while (p < data.size() && isBlank(data[p])) ++p;
    // Binary headers often start with "solid" too; only text is read as ASCII here, and the
    // rest gets the binary diagnosis below.
    const bool text = std::all_of(data.begin(), data.end(), [](char ch) {
        const auto c = static_cast<unsigned char>(ch);
        return c >= 0x20 || c == '\t' || c == '\n' || c == '\r';
    });
    const bool solid = data.size() > p + 5 && data.substr(p, 5) == "solid";
    if (solid && text) {
        readStlAscii(data, source, parts);
        return parts;
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

} // namespace ffd::detail
