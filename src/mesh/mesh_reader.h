// What the four mesh readers (read_obj.cpp, read_ply.cpp, read_stl.cpp, read_off.cpp) share:
// limits, text tokenising, number parsing, and the step that turns their faces into triangles.
//
// Each reader walks the bytes of its format once, refuses what is malformed with a message that
// names the element and line, and fills a RawScene: one or more parts, each with its positions
// and its faces (corner lists into those positions). assemble() triangulates polygons and joins
// the parts into one TriangleMesh. The readers reproduce, bit for bit, the meshes that the
// library's earlier Assimp-based loader built from the same files (docs/ARCHITECTURE.md, "Mesh
// files"): the same decimal-to-float conversion, a vertex per face corner for OBJ and STL,
// shared vertices for PLY and OFF, and the same split of quads and polygons.
#pragma once

#include "ffdaabb/math.h"
#include "ffdaabb/mesh.h"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace ffd::detail {

/// Most vertices, faces or triangles a file may declare (2^28): beyond it the header is
/// treated as absurd and rejected before anything is allocated.
inline constexpr uint64_t kMaxMeshElements = uint64_t(1) << 28;
/// Largest file we read, compressed or after inflating (2 GiB).
inline constexpr uint64_t kMaxFileBytes = uint64_t(1) << 31;
/// Most corners of one polygon: ear clipping is quadratic in it.
inline constexpr uint64_t kMaxPolygonCorners = 1024;

enum class MeshFormat { Obj, Ply, Stl, Off };

/// Lower-case extension without the dot ("obj", "ply", "stl", "off").
const char* formatExtension(MeshFormat format);

/// One mesh as a reader found it: faces of any size (1 = point, 2 = line, 3+ = polygon).
struct RawPart {
    std::vector<Vec3> positions;
    std::vector<uint32_t> corners;   ///< all faces' corner indices, face after face
    std::vector<uint32_t> faceSizes; ///< corners per face
    bool polygons = false;           ///< some face has more than 3 corners
    void addFace(uint32_t size) {
        faceSizes.push_back(size);
        polygons = polygons || size > 3;
    }
};

/// Triangulates every part (quads split at their concave corner, larger polygons by ear
/// clipping), drops points and lines, and joins the parts that have triangles, in order.
TriangleMesh assemble(std::vector<RawPart>& parts, MeshFormat format, const std::string& source);

/// The readers: each throws InputError(source, ...) for a file it cannot read.
std::vector<RawPart> readObj(std::string_view data, const std::string& source);
std::vector<RawPart> readPly(std::string_view data, const std::string& source);
std::vector<RawPart> readStl(std::string_view data, const std::string& source);
std::vector<RawPart> readOff(std::string_view data, const std::string& source);

// --- shared by the readers --------------------------------------------------------------------

[[noreturn]] void fail(const std::string& source, const std::string& problem);
__attribute__((format(printf, 1, 2))) std::string fmt(const char* format, ...);
using ull = unsigned long long;

/// Quotes a token for a message, shortened so that a binary blob cannot flood the message.
std::string quoted(std::string_view token);

inline bool isBlank(char c) {
    return c == ' ' || c == '\t';
}
bool isBlankLine(std::string_view s);

/// Rejects bytes no text mesh format contains (NUL, form feed, a lone carriage return...).
void checkText(std::string_view text, size_t offset, const std::string& source, const char* what);

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
    bool next(Line& line);
    size_t position() const { return pos_; }
    /// True when nothing but blank lines follows.
    bool onlyBlankRemains() const;

private:
    std::string_view data_;
    size_t pos_;
    size_t number_;
};

/// Splits one line at blanks.
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

/// Checks a whole token as a real number (digits, point, exponent). Values a float cannot
/// hold count as non-finite.
Real parseReal(std::string_view token, double& value);

/// Parses a whole token as a decimal integer: digits only, or with a sign when allowed.
bool parseInteger(std::string_view token, int64_t& value, bool allowSign);

/// The value of a token parseReal accepted, converted as the formats' float readers have
/// always done (integer part, then up to 15 decimals scaled in double and added in float, then
/// the exponent as a float power of ten): not always the nearest float, but the value the
/// golden meshes were built from.
float decimalToFloat(std::string_view token);
double decimalToDouble(std::string_view token);

[[noreturn]] void failNonFinite(const std::string& source, const char* what, uint64_t vertex,
                                const std::string& where, std::string_view token);
[[noreturn]] void failTooMany(const std::string& source, const char* what, uint64_t count,
                              const char* things);

} // namespace ffd::detail
