// Shared parts of the mesh readers; see mesh_reader.h.
#include "mesh/mesh_reader.h"

#include "ffdaabb/error.h"

#include <charconv>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>

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

void fail(const std::string& source, const std::string& problem) {
    throw InputError(source, problem);
}

std::string fmt(const char* format, ...) {
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

bool isBlankLine(std::string_view s) {
    for (char c : s)
        if (!isBlank(c)) return false;
    return true;
}

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

bool LineReader::next(Line& line) {
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

bool LineReader::onlyBlankRemains() const {
    for (size_t i = pos_; i < data_.size(); ++i)
        if (!isBlank(data_[i]) && data_[i] != '\n' && data_[i] != '\r') return false;
    return true;
}

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

namespace {

bool isDigit(char c) {
    return c >= '0' && c <= '9';
}

// Reads decimal digits at t[i...] into a 64-bit value; at most `most` digits count (the rest
// are skipped); `read` receives how many counted. An overflow gives 0, as it always has.
uint64_t digits(std::string_view t, size_t& i, unsigned most, unsigned& read, bool& overflow) {
    uint64_t value = 0;
    read = 0;
    while (i < t.size() && isDigit(t[i])) {
        const uint64_t next = value * 10 + uint64_t(t[i] - '0');
        if (next < value) {
            overflow = true;
            return 0;
        }
        value = next;
        ++i;
        if (++read == most) {
            while (i < t.size() && isDigit(t[i])) ++i;
            break;
        }
    }
    return value;
}

template <class R>
R decimalTo(std::string_view t) {
    static constexpr double kScale[16] = {0.0,  1e-1, 1e-2,  1e-3,  1e-4,  1e-5,  1e-6,  1e-7,
                                          1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13, 1e-14, 1e-15};
    size_t i = 0;
    const bool negative = !t.empty() && t[0] == '-';
    if (negative || (!t.empty() && t[0] == '+')) ++i;
    R value = 0;
    bool overflow = false;
    unsigned read = 0;
    if (i < t.size() && t[i] != '.') {
        value = static_cast<R>(digits(t, i, 0, read, overflow));
        if (overflow) return R(0);
    }
    if (i + 1 < t.size() && t[i] == '.' && isDigit(t[i + 1])) {
        ++i;
        const double fraction = double(digits(t, i, 15, read, overflow)) * kScale[read];
        value += static_cast<R>(fraction);
    } else if (i < t.size() && t[i] == '.') {
        ++i;
    }
    if (i < t.size() && (t[i] == 'e' || t[i] == 'E')) {
        ++i;
        const bool negativeExponent = i < t.size() && t[i] == '-';
        if (i < t.size() && (t[i] == '-' || t[i] == '+')) ++i;
        R exponent = static_cast<R>(digits(t, i, 0, read, overflow));
        if (overflow) exponent = 0;
        if (negativeExponent) exponent = -exponent;
        value *= std::pow(static_cast<R>(10.0), exponent);
    }
    return negative ? -value : value;
}

} // namespace

float decimalToFloat(std::string_view token) {
    return decimalTo<float>(token);
}

double decimalToDouble(std::string_view token) {
    return decimalTo<double>(token);
}

void failNonFinite(const std::string& source, const char* what, uint64_t vertex,
                   const std::string& where, std::string_view token) {
    fail(source, fmt("non-finite coordinate in %s: vertex %llu%s has %s (expected finite "
                     "numbers that fit a 32-bit float)",
                     what, ull(vertex), where.c_str(), quoted(token).c_str()));
}

void failTooMany(const std::string& source, const char* what, uint64_t count, const char* things) {
    fail(source, fmt("%s declares %llu %s, more than the limit of %llu (2^28): the header is "
                     "corrupt or the mesh is too large",
                     what, ull(count), things, ull(kMaxMeshElements)));
}

// ---------------------------------------------------------------------------------------------
// Triangulation

namespace {

using Tri = std::array<uint32_t, 3>;

struct Vec2f {
    float x, y;
    bool operator!=(const Vec2f& o) const { return x != o.x || y != o.y; }
};

Vec3 normalized(Vec3 v) {
    const float length = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
    if (length == 0) return v;
    const float inverse = 1.0f / length;
    return {v.x * inverse, v.y * inverse, v.z * inverse};
}

float dot3(Vec3 a, Vec3 b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

double area2(const Vec2f& a, const Vec2f& b, const Vec2f& c) {
    return 0.5 *
           (a.x * (double(c.y) - b.y) + b.x * (double(a.y) - c.y) + c.x * (double(b.y) - a.y));
}

// Whether p2 lies left of the line p0-p1.
bool leftOfLine(const Vec2f& p0, const Vec2f& p1, const Vec2f& p2) {
    return area2(p0, p2, p1) > 0;
}

bool insideTriangle(const Vec2f& p0, const Vec2f& p1, const Vec2f& p2, const Vec2f& p) {
    const Vec2f v0{p1.x - p0.x, p1.y - p0.y}, v1{p2.x - p0.x, p2.y - p0.y},
        v2{p.x - p0.x, p.y - p0.y};
    double d00 = v0.x * v0.x + v0.y * v0.y;
    const double d01 = v0.x * v1.x + v0.y * v1.y;
    const double d02 = v0.x * v2.x + v0.y * v2.y;
    double d11 = v1.x * v1.x + v1.y * v1.y;
    const double d12 = v1.x * v2.x + v1.y * v2.y;
    const double denominator = d00 * d11 - d01 * d01;
    if (denominator == 0.0) return false;
    const double inverse = 1.0 / denominator;
    d11 = (d11 * d02 - d01 * d12) * inverse;
    d00 = (d00 * d12 - d01 * d02) * inverse;
    return d11 > 0 && d00 > 0 && d11 + d00 < 1;
}

// Splits one part's faces into triangles. Quads are split from their concave corner (the
// first corner whose two angles to the opposite corner sum past pi), or from corner 0; larger
// polygons are projected on the plane of their largest Newell-normal component and ear-clipped.
// A triangle whose first corner is the previous triangle's first corner is rotated, so that
// consecutive faces never look like one fan (and a quad's pair is rotated together).
class Triangulator {
public:
    explicit Triangulator(const std::vector<Vec3>& positions) : positions_(positions) {}

    void face(const uint32_t* idx, uint32_t n, std::vector<Tri>& out) {
        if (n < 3) return;
        if (n == 3) {
            Tri t{idx[0], idx[1], idx[2]};
            encodeTriangle(t);
            out.push_back(t);
            return;
        }
        if (n == 4) {
            quad(idx, out);
            return;
        }
        polygon(idx, n, out);
    }

private:
    void encodeTriangle(Tri& t) {
        if (t[0] == lastFirst_) t = {t[2], t[0], t[1]};
        lastFirst_ = t[0];
    }

    void quad(const uint32_t* idx, std::vector<Tri>& out) {
        unsigned start = 0;
        for (unsigned i = 0; i < 4; ++i) {
            const Vec3 v = positions_[idx[i]];
            const Vec3 left = normalized(positions_[idx[(i + 3) % 4]] - v);
            const Vec3 diagonal = normalized(positions_[idx[(i + 2) % 4]] - v);
            const Vec3 right = normalized(positions_[idx[(i + 1) % 4]] - v);
            const float angle = std::acos(dot3(left, diagonal)) + std::acos(dot3(right, diagonal));
            if (angle > 3.1415926538f) {
                start = i;
                break;
            }
        }
        Tri a{idx[start], idx[(start + 1) % 4], idx[(start + 2) % 4]};
        Tri b{idx[start], idx[(start + 2) % 4], idx[(start + 3) % 4]};
        if (a[0] == lastFirst_) {
            a = {a[2], a[0], a[1]};
            b = {b[1], b[2], b[0]};
        }
        lastFirst_ = a[0];
        out.push_back(a);
        out.push_back(b);
    }

    void polygon(const uint32_t* idx, uint32_t n, std::vector<Tri>& out) {
        const int max = int(n);
        points3_.assign(n + 2, Vec3{});
        for (int k = 0; k < max; ++k) points3_[size_t(k)] = positions_[idx[k]];
        points3_[n] = points3_[0];
        points3_[n + 1] = points3_[1];
        float xy = 0, yz = 0, zx = 0;
        for (int k = 0; k < max; ++k) {
            const Vec3 &low = points3_[size_t(k)], &mid = points3_[size_t(k) + 1],
                       &high = points3_[size_t(k) + 2];
            xy += mid.x * (high.y - low.y);
            yz += mid.y * (high.z - low.z);
            zx += mid.z * (high.x - low.x);
        }
        const Vec3 normal{yz, zx, xy};
        const float ax = std::fabs(normal.x), ay = std::fabs(normal.y), az = std::fabs(normal.z);
        int ac = 0, bc = 1;
        float inverse = normal.z;
        if (ax > ay) {
            if (ax > az) {
                ac = 1;
                bc = 2;
                inverse = normal.x;
            }
        } else if (ay > az) {
            ac = 2;
            bc = 0;
            inverse = normal.y;
        }
        if (inverse < 0.f) std::swap(ac, bc);
        points2_.resize(n);
        done_.assign(n, 0);
        for (int k = 0; k < max; ++k) {
            const Vec3 p = positions_[idx[k]];
            points2_[size_t(k)] = {p[ac], p[bc]};
        }

        const size_t first = out.size();
        int num = max, ear = 0, prev = max - 1, next = 0;
        while (num > 3) {
            int wraps = 0;
            for (ear = next;; prev = ear, ear = next) {
                next = ear + 1;
                for (;;) {
                    if (next >= max) next = 0;
                    if (!done_[size_t(next)]) break;
                    ++next;
                }
                if (next < ear && ++wraps == 2) break;
                const Vec2f &p1 = points2_[size_t(ear)], &p0 = points2_[size_t(prev)],
                            &p2 = points2_[size_t(next)];
                if (leftOfLine(p0, p2, p1)) continue;
                int k = 0;
                for (; k < max; ++k) {
                    const Vec2f& q = points2_[size_t(k)];
                    if (q != p1 && q != p2 && q != p0 && insideTriangle(p0, p1, p2, q)) break;
                }
                if (k != max) continue;
                break;
            }
            if (wraps == 2) {
                num = 0; // not a simple polygon: what was cut so far is kept
                break;
            }
            out.push_back({uint32_t(prev), uint32_t(ear), uint32_t(next)});
            done_[size_t(ear)] = 1;
            --num;
        }
        if (num > 0) {
            Tri t{};
            int k = 0;
            for (int c = 0; c < 3; ++c, ++k) {
                while (done_[size_t(k)]) ++k;
                t[size_t(c)] = uint32_t(k);
            }
            out.push_back(t);
        }
        for (size_t f = first; f < out.size(); ++f) {
            Tri& t = out[f];
            t = {idx[t[0]], idx[t[1]], idx[t[2]]};
            encodeTriangle(t);
        }
    }

    const std::vector<Vec3>& positions_;
    uint32_t lastFirst_ = UINT32_MAX;
    std::vector<Vec3> points3_;
    std::vector<Vec2f> points2_;
    std::vector<char> done_;
};

} // namespace

TriangleMesh assemble(std::vector<RawPart>& parts, MeshFormat format, const std::string& source) {
    TriangleMesh mesh;
    uint64_t vertexBase = 0;
    bool anyTriangle = false;
    for (RawPart& part : parts) {
        for (size_t v = 0; v < part.positions.size(); ++v) {
            const Vec3 p = part.positions[v];
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
                char buf[200];
                std::snprintf(buf, sizeof buf,
                              "non-finite coordinate: vertex %llu is (%g, %g, %g) (expected "
                              "finite numbers)",
                              ull(vertexBase + v), double(p.x), double(p.y), double(p.z));
                fail(source, buf);
            }
        }
        vertexBase += part.positions.size();
        for (uint32_t n : part.faceSizes) anyTriangle = anyTriangle || n >= 3;
    }
    if (!anyTriangle) {
        std::string name = formatExtension(format);
        for (char& c : name) c = char(c - 'a' + 'A');
        fail(source, "the " + name +
                         " file contains no triangles, only points or lines (expected faces "
                         "with at least 3 corners)");
    }

    std::vector<std::vector<Tri>> triangles(parts.size());
    size_t vertexCount = 0, triangleCount = 0;
    for (size_t m = 0; m < parts.size(); ++m) {
        RawPart& part = parts[m];
        std::vector<Tri>& out = triangles[m];
        const uint32_t* corner = part.corners.data();
        if (!part.polygons) {
            // Nothing to split: triangles stay as they are (no rotation either).
            for (uint32_t n : part.faceSizes) {
                if (n == 3) out.push_back({corner[0], corner[1], corner[2]});
                corner += n;
            }
        } else {
            Triangulator triangulator(part.positions);
            for (uint32_t n : part.faceSizes) {
                triangulator.face(corner, n, out);
                corner += n;
            }
        }
        if (out.empty()) continue; // points and lines only
        vertexCount += part.positions.size();
        triangleCount += out.size();
    }
    if (vertexCount >= UINT32_MAX)
        fail(source, "has " + std::to_string(vertexCount) +
                         " vertices, more than 32-bit indices can address");
    mesh.positions.reserve(vertexCount);
    mesh.triangles.reserve(triangleCount);
    for (size_t m = 0; m < parts.size(); ++m) {
        if (triangles[m].empty()) continue;
        const auto base = uint32_t(mesh.positions.size());
        for (const Tri& t : triangles[m])
            mesh.triangles.push_back({base + t[0], base + t[1], base + t[2]});
        mesh.positions.insert(mesh.positions.end(), parts[m].positions.begin(),
                              parts[m].positions.end());
        std::vector<Tri>().swap(triangles[m]);
    }
    return mesh;
}

} // namespace ffd::detail
