// Extruded capital letters, the "letter" object of Jeon, Choi, Hong 2012 (Table 2: 1,141
// vertices and 2,279 triangles on average over the alphabet).
//
// The cap triangulation (mesh/cap_triangulation.h) is made a constrained Delaunay triangulation
// by Lawson's edge flips and refined by incremental insertion of lattice points with the same
// flips.
//
// Pipeline: FreeType outline -> contours sampled at a uniform spacing h -> GLU tessellation
// (nonzero winding, so holes and overlapping contours come out right) -> Delaunay flips ->
// interior points on a triangular lattice of spacing h, kept clear of the outline -> one pass of
// guarded Laplacian smoothing (it evens out the band where the lattice meets the outline) ->
// front and back caps joined by walls with rings at most h apart along the depth. One spacing
// everywhere keeps the triangles near equilateral; h is chosen so that the alphabet's average
// matches the paper's counts.
#include "ffdaabb/error.h"
#include "ffdaabb/generators.h"
#include "mesh/cap_triangulation.h"

#include <ft2build.h>
#include FT_FREETYPE_H
#include FT_OUTLINE_H

#include <GL/glu.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <optional>
#include <unordered_map>
#include <vector>

namespace ffd {

namespace {

using detail::CapTriangulation;
using detail::P2;

const char* const kDefaultFont = "/usr/share/fonts/truetype/dejavu/DejaVuSans-Bold.ttf";

// Target edge length as a fraction of the letter height at refine = 1. Calibrated so that the
// mean over A..Z of DejaVu Sans Bold at the default depth is close to the paper's counts.
constexpr double kSpacing = 0.0465;
// Lattice points closer than this (in units of h) to the outline are dropped: the outline's
// own samples already cover that band, and a closer point would make a sliver.
constexpr double kClearance = 0.55;
// Each Bezier arc is first flattened into this many chords, then resampled by arc length.
constexpr int kCurveChords = 64;
constexpr int kSmoothingPasses = 1;
constexpr float kMaxRefine = 64.0f;
constexpr float kMaxDepthRatio = 100.0f;

std::string describe(char c) {
    char buf[48];
    if (c >= 0x21 && c <= 0x7e)
        std::snprintf(buf, sizeof buf, "'%c' (code %d)", c, int(static_cast<unsigned char>(c)));
    else
        std::snprintf(buf, sizeof buf, "code %d", int(static_cast<unsigned char>(c)));
    return buf;
}

// Throws unless 0 < value <= maximum (and finite).
void checkSetting(float value, float maximum, const char* field) {
    if (value > 0.0f && std::isfinite(value) && value <= maximum) return;
    char buf[160];
    if (std::isfinite(maximum))
        std::snprintf(buf, sizeof buf, "value %g is out of range (expected 0 < value <= %g)",
                      double(value), double(maximum));
    else
        std::snprintf(buf, sizeof buf, "value %g is out of range (expected a positive number)",
                      double(value));
    throw InputError(field, buf);
}

// ---- the glyph outline ------------------------------------------------------------------------

// A contour as a list of pieces, each a fine polyline from one on-curve point to the next.
using Piece = std::vector<P2>;
using Contour = std::vector<Piece>;

struct OutlineSink {
    std::vector<Contour> contours;
    P2 current;
};

P2 toP2(const FT_Vector* v) {
    return {double(v->x), double(v->y)};
}

int onMoveTo(const FT_Vector* to, void* user) {
    auto& sink = *static_cast<OutlineSink*>(user);
    sink.contours.emplace_back();
    sink.current = toP2(to);
    return 0;
}
int onLineTo(const FT_Vector* to, void* user) {
    auto& sink = *static_cast<OutlineSink*>(user);
    const P2 end = toP2(to);
    sink.contours.back().push_back({sink.current, end});
    sink.current = end;
    return 0;
}
int onConicTo(const FT_Vector* control, const FT_Vector* to, void* user) {
    auto& sink = *static_cast<OutlineSink*>(user);
    const P2 p0 = sink.current, p1 = toP2(control), p2 = toP2(to);
    Piece piece;
    for (int i = 0; i <= kCurveChords; ++i) {
        const double t = double(i) / kCurveChords, s = 1 - t;
        piece.push_back({s * s * p0.x + 2 * s * t * p1.x + t * t * p2.x,
                         s * s * p0.y + 2 * s * t * p1.y + t * t * p2.y});
    }
    sink.contours.back().push_back(std::move(piece));
    sink.current = p2;
    return 0;
}
int onCubicTo(const FT_Vector* control1, const FT_Vector* control2, const FT_Vector* to,
              void* user) {
    auto& sink = *static_cast<OutlineSink*>(user);
    const P2 p0 = sink.current, p1 = toP2(control1), p2 = toP2(control2), p3 = toP2(to);
    Piece piece;
    for (int i = 0; i <= kCurveChords; ++i) {
        const double t = double(i) / kCurveChords, s = 1 - t;
        const double b0 = s * s * s, b1 = 3 * s * s * t, b2 = 3 * s * t * t, b3 = t * t * t;
        piece.push_back({b0 * p0.x + b1 * p1.x + b2 * p2.x + b3 * p3.x,
                         b0 * p0.y + b1 * p1.y + b2 * p2.y + b3 * p3.y});
    }
    sink.contours.back().push_back(std::move(piece));
    sink.current = p3;
    return 0;
}

// The glyph's contours in font units. FreeType is opened and closed here so that letter() is
// safe to call from several threads at once (an FT_Library must not be shared unguarded).
std::vector<Contour> loadOutline(char capital, const std::filesystem::path& fontFile) {
    const std::string source = fontFile.string();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(fontFile, ec))
        throw InputError(source, "the font file does not exist or is not a regular file "
                                 "(expected a TrueType or OpenType font)");

    FT_Library library = nullptr;
    if (FT_Init_FreeType(&library) != 0)
        throw InputError(source, "FreeType could not be initialised to read the font");
    struct LibraryGuard {
        FT_Library lib;
        ~LibraryGuard() { FT_Done_FreeType(lib); } // also frees the face
    } libraryGuard{library};

    FT_Face face = nullptr;
    if (const FT_Error err = FT_New_Face(library, source.c_str(), 0, &face); err != 0)
        throw InputError(source, "the file cannot be read as a font (FreeType error " +
                                     std::to_string(err) +
                                     "); expected a TrueType or OpenType font");
    if (FT_Get_Char_Index(face, FT_ULong(static_cast<unsigned char>(capital))) == 0)
        throw InputError(source, "the font has no glyph for " + describe(capital));
    // Unscaled and unhinted: the exact design outline in font units.
    if (FT_Load_Char(face, FT_ULong(static_cast<unsigned char>(capital)),
                     FT_LOAD_NO_SCALE | FT_LOAD_NO_HINTING | FT_LOAD_NO_BITMAP) != 0 ||
        face->glyph->format != FT_GLYPH_FORMAT_OUTLINE || face->glyph->outline.n_contours <= 0)
        throw InputError(source, "the font has no outline for " + describe(capital) +
                                     " (expected a scalable font)");

    FT_Outline_Funcs funcs{};
    funcs.move_to = onMoveTo;
    funcs.line_to = onLineTo;
    funcs.conic_to = onConicTo;
    funcs.cubic_to = onCubicTo;
    OutlineSink sink;
    if (FT_Outline_Decompose(&face->glyph->outline, &funcs, &sink) != 0)
        throw InputError(source, "the outline of " + describe(capital) + " cannot be decomposed");
    return std::move(sink.contours);
}

// Maps font units to the output frame (x centred, y from 0, height `height`) and resamples
// every piece at spacing ~h by arc length. Piece ends (the on-curve points, where the corners
// are) are kept exactly.
std::vector<std::vector<P2>> sampleContours(std::vector<Contour> contours, double height,
                                            double h) {
    double xMin = INFINITY, xMax = -INFINITY, yMin = INFINITY, yMax = -INFINITY;
    for (const Contour& c : contours)
        for (const Piece& piece : c)
            for (const P2& p : piece) {
                xMin = std::min(xMin, p.x), xMax = std::max(xMax, p.x);
                yMin = std::min(yMin, p.y), yMax = std::max(yMax, p.y);
            }
    const double scale = height / (yMax - yMin), xMid = 0.5 * (xMin + xMax);
    std::vector<std::vector<P2>> loops;
    for (Contour& contour : contours) {
        std::vector<P2> loop;
        for (Piece& piece : contour) {
            for (P2& p : piece) p = {(p.x - xMid) * scale, (p.y - yMin) * scale};
            std::vector<double> along(piece.size(), 0.0);
            for (size_t i = 1; i < piece.size(); ++i)
                along[i] = along[i - 1] + dist(piece[i - 1], piece[i]);
            const double length = along.back();
            if (length <= 0) continue;
            const long n = std::max(1L, std::lround(length / h));
            size_t chord = 0;
            // The piece's end is the next piece's start: emit [start, end).
            for (long k = 0; k < n; ++k) {
                const double s = length * double(k) / double(n);
                while (chord + 2 < piece.size() && along[chord + 1] <= s) ++chord;
                const double span = along[chord + 1] - along[chord];
                const double t = span > 0 ? (s - along[chord]) / span : 0.0;
                const P2 a = piece[chord], b = piece[chord + 1];
                loop.push_back(k == 0 ? a : P2{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
            }
        }
        // Drop repeated points (zero-length chords), including across the seam.
        std::vector<P2> clean;
        for (const P2& p : loop)
            if (clean.empty() || dist(clean.back(), p) > 1e-12 * height) clean.push_back(p);
        while (clean.size() > 1 && dist(clean.back(), clean.front()) <= 1e-12 * height)
            clean.pop_back();
        if (clean.size() >= 3) loops.push_back(std::move(clean));
    }
    return loops;
}

// ---- GLU tessellation -------------------------------------------------------------------------

struct TessOutput {
    std::vector<P2> vertices; // the input points, then any the combine callback made
    std::vector<std::array<uint32_t, 3>> triangles;
    std::array<uint32_t, 3> pending{};
    int pendingCount = 0;
    bool notTriangles = false;
    GLenum error = 0;
};

// GLU passes opaque vertex data around; we use index + 1 so that no vertex is a null pointer.
void* indexData(size_t index) {
    return reinterpret_cast<void*>(uintptr_t(index + 1));
}
uint32_t dataIndex(void* data) {
    return uint32_t(reinterpret_cast<uintptr_t>(data) - 1);
}

void GLAPIENTRY tessBegin(GLenum type, void* polygon) {
    auto& out = *static_cast<TessOutput*>(polygon);
    if (type != GL_TRIANGLES) out.notTriangles = true;
    out.pendingCount = 0;
}
// Registering an edge-flag callback is what makes GLU emit plain triangles (no fans/strips).
void GLAPIENTRY tessEdgeFlag(GLboolean, void*) {}
void GLAPIENTRY tessVertex(void* vertex, void* polygon) {
    auto& out = *static_cast<TessOutput*>(polygon);
    out.pending[size_t(out.pendingCount++)] = dataIndex(vertex);
    if (out.pendingCount == 3) {
        out.triangles.push_back(out.pending);
        out.pendingCount = 0;
    }
}
void GLAPIENTRY tessEnd(void*) {}
// Called where contours cross or points coincide: a new vertex at the given position.
void GLAPIENTRY tessCombine(GLdouble coords[3], void* [4], GLfloat[4], void** outData,
                            void* polygon) {
    auto& out = *static_cast<TessOutput*>(polygon);
    out.vertices.push_back({coords[0], coords[1]});
    *outData = indexData(out.vertices.size() - 1);
}
void GLAPIENTRY tessError(GLenum code, void* polygon) {
    static_cast<TessOutput*>(polygon)->error = code;
}

template <typename F>
_GLUfuncptr gluCallback(F* f) {
    // GLU stores every callback as void(*)(); it casts back by `which` before calling.
    return reinterpret_cast<_GLUfuncptr>(f);
}

TessOutput tessellate(const std::vector<std::vector<P2>>& loops) {
    TessOutput out;
    std::vector<std::array<GLdouble, 3>> coords;
    for (const auto& loop : loops)
        for (const P2& p : loop) {
            coords.push_back({p.x, p.y, 0.0});
            out.vertices.push_back(p);
        }
    GLUtesselator* tess = gluNewTess();
    if (!tess) return out;
    gluTessCallback(tess, GLU_TESS_BEGIN_DATA, gluCallback(tessBegin));
    gluTessCallback(tess, GLU_TESS_EDGE_FLAG_DATA, gluCallback(tessEdgeFlag));
    gluTessCallback(tess, GLU_TESS_VERTEX_DATA, gluCallback(tessVertex));
    gluTessCallback(tess, GLU_TESS_END_DATA, gluCallback(tessEnd));
    gluTessCallback(tess, GLU_TESS_COMBINE_DATA, gluCallback(tessCombine));
    gluTessCallback(tess, GLU_TESS_ERROR_DATA, gluCallback(tessError));
    // TrueType draws outer contours one way and holes the other; nonzero winding fills the
    // outer ones, empties the holes, and merges overlapping outer contours.
    gluTessProperty(tess, GLU_TESS_WINDING_RULE, GLU_TESS_WINDING_NONZERO);
    gluTessNormal(tess, 0.0, 0.0, 1.0);
    gluTessBeginPolygon(tess, &out);
    size_t index = 0;
    for (const auto& loop : loops) {
        gluTessBeginContour(tess);
        for (size_t i = 0; i < loop.size(); ++i, ++index)
            gluTessVertex(tess, coords[index].data(), indexData(index));
        gluTessEndContour(tess);
    }
    gluTessEndPolygon(tess);
    gluDeleteTess(tess);
    return out;
}

// The refined cap, or nothing when the outline touches itself at a vertex (a vertex with two
// outgoing outline edges), which coarse sampling of a curvy font can cause: the walls there
// could not be a manifold, so the caller retries with a finer outline.
std::optional<CapTriangulation> triangulateCap(const std::vector<std::vector<P2>>& loops, double h,
                                               const std::string& source, char capital) {
    const TessOutput tess = tessellate(loops);
    auto fail = [&](const std::string& why) {
        return InputError(source, "the outline of " + describe(capital) +
                                      " cannot be triangulated: " + why);
    };
    if (tess.error != 0)
        throw fail("GLU tessellator error " + std::to_string(tess.error) + " (" +
                   reinterpret_cast<const char*>(gluErrorString(tess.error)) + ")");
    if (tess.notTriangles || tess.pendingCount != 0 || tess.triangles.empty())
        throw fail("the tessellator returned no plain triangles");

    // GLU merges coincident points by making new ones at the same place: weld them back.
    CapTriangulation cap;
    std::map<std::pair<double, double>, uint32_t> index;
    std::vector<uint32_t> remap(tess.vertices.size());
    for (size_t v = 0; v < tess.vertices.size(); ++v) {
        const P2 p = tess.vertices[v];
        auto [it, inserted] = index.emplace(std::pair{p.x, p.y}, uint32_t(cap.points.size()));
        if (inserted) cap.points.push_back(p);
        remap[v] = it->second;
    }
    double area = 0;
    for (auto t : tess.triangles) {
        for (uint32_t& v : t) v = remap[v];
        if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) continue;
        cap.tris.push_back(t);
        area += orient(cap.points[t[0]], cap.points[t[1]], cap.points[t[2]]);
    }
    // GLU emits all triangles with one orientation; which one depends on its projection.
    if (area < 0)
        for (auto& t : cap.tris) std::swap(t[1], t[2]);
    if (!cap.build()) throw fail("the tessellation is not an edge-manifold");
    cap.makeDelaunay();
    if (!(cap.minOrientation() > 0)) throw fail("a zero-area triangle could not be flipped away");
    std::vector<int> outgoing(cap.points.size(), 0);
    for (size_t t = 0; t < cap.tris.size(); ++t)
        for (int i = 0; i < 3; ++i)
            if (cap.neighbours[t][size_t(i)] < 0 && ++outgoing[cap.tris[t][size_t(i)]] > 1)
                return std::nullopt;

    // Interior points on a triangular lattice of spacing h, rows alternately offset by h/2.
    std::vector<std::pair<P2, P2>> outline;
    std::vector<bool> onOutline(cap.points.size(), false);
    double xMin = INFINITY, xMax = -INFINITY, yMin = INFINITY, yMax = -INFINITY;
    for (size_t t = 0; t < cap.tris.size(); ++t)
        for (int i = 0; i < 3; ++i)
            if (cap.neighbours[t][size_t(i)] < 0) {
                const uint32_t a = cap.tris[t][size_t(i)], b = cap.tris[t][size_t((i + 1) % 3)];
                outline.push_back({cap.points[a], cap.points[b]});
                onOutline[a] = onOutline[b] = true;
                xMin = std::min(xMin, cap.points[a].x), xMax = std::max(xMax, cap.points[a].x);
                yMin = std::min(yMin, cap.points[a].y), yMax = std::max(yMax, cap.points[a].y);
            }
    const double rowStep = h * std::sqrt(3.0) / 2.0, clearance2 = kClearance * kClearance * h * h;
    for (long row = 0; yMin + double(row) * rowStep <= yMax; ++row) {
        const double y = yMin + double(row) * rowStep;
        const double x0 = xMin + ((row & 1) ? 0.5 * h : 0.0);
        for (long col = 0; x0 + double(col) * h <= xMax; ++col) {
            const P2 p{x0 + double(col) * h, y};
            if (winding(p, outline) == 0) continue;
            bool clear = true;
            for (const auto& [a, b] : outline)
                if (segmentDistanceSquared(p, a, b) < clearance2) {
                    clear = false;
                    break;
                }
            if (clear) cap.insert(p, 1e-6 * h);
        }
    }
    onOutline.resize(cap.points.size(), false);
    cap.smooth(kSmoothingPasses, onOutline);
    if (!(cap.minOrientation() > 0)) throw fail("refinement produced a zero-area triangle");
    return cap;
}

} // namespace

TriangleMesh letter(char capital, const LetterSettings& settings) {
    if (capital < 'A' || capital > 'Z')
        throw InputError("letter", "character " + describe(capital) +
                                       " is not a capital letter (expected A-Z)");
    checkSetting(settings.height, INFINITY, "LetterSettings.height");
    checkSetting(settings.depthRatio, kMaxDepthRatio, "LetterSettings.depthRatio");
    checkSetting(settings.refine, kMaxRefine, "LetterSettings.refine");
    const std::filesystem::path font =
        settings.fontFile.empty() ? std::filesystem::path(kDefaultFont) : settings.fontFile;

    // Work at unit height (the spacing is relative to it) and scale at the end.
    const double h = kSpacing / double(settings.refine);
    const std::vector<Contour> outline = loadOutline(capital, font);
    std::optional<CapTriangulation> refined;
    for (int attempt = 0; attempt < 6 && !refined; ++attempt) {
        const auto loops = sampleContours(outline, 1.0, h / double(1 << attempt));
        if (loops.empty())
            throw InputError(font.string(), "the outline of " + describe(capital) + " is empty");
        refined = triangulateCap(loops, h, font.string(), capital);
    }
    if (!refined)
        throw InputError(font.string(), "the outline of " + describe(capital) +
                                            " touches itself; an extruded solid would not be a "
                                            "manifold there");
    CapTriangulation& cap = *refined;

    // Exact bounds: x centred, y from 0 to the height (the resampled outline may miss the
    // design outline's extremes by a hair, so normalise on the final points).
    double xMin = INFINITY, xMax = -INFINITY, yMin = INFINITY, yMax = -INFINITY;
    for (const P2& p : cap.points) {
        xMin = std::min(xMin, p.x), xMax = std::max(xMax, p.x);
        yMin = std::min(yMin, p.y), yMax = std::max(yMax, p.y);
    }
    const double height = double(settings.height), depth = height * double(settings.depthRatio);
    const double scale = height / (yMax - yMin), xMid = 0.5 * (xMin + xMax);

    // Outline vertices get a column of ring vertices along z; interior ones only the two caps.
    const uint32_t m = uint32_t(cap.points.size());
    std::vector<int32_t> column(m, -1);
    std::vector<std::array<uint32_t, 2>> outlineEdges;
    uint32_t columns = 0;
    for (size_t t = 0; t < cap.tris.size(); ++t)
        for (int i = 0; i < 3; ++i)
            if (cap.neighbours[t][size_t(i)] < 0) {
                const uint32_t a = cap.tris[t][size_t(i)], b = cap.tris[t][size_t((i + 1) % 3)];
                outlineEdges.push_back({a, b});
                for (uint32_t v : {a, b})
                    if (column[v] < 0) column[v] = int32_t(columns++);
            }
    const long rings = std::max(1L, long(std::ceil(double(settings.depthRatio) / h - 1e-9)));

    TriangleMesh mesh;
    char name[32];
    std::snprintf(name, sizeof name, "letter(%c)", capital);
    mesh.name = name;
    mesh.positions.resize(2 * size_t(m) + size_t(rings - 1) * columns);
    auto zAt = [&](long k) {
        // The last ring exactly at +depth/2 so that the bounds come out exact.
        return k == rings ? 0.5 * depth : -0.5 * depth + depth * double(k) / double(rings);
    };
    auto vertexAt = [&](uint32_t v, long k) -> uint32_t {
        if (k == 0) return m + v; // back cap
        if (k == rings) return v; // front cap
        return 2 * m + uint32_t(k - 1) * columns + uint32_t(column[v]);
    };
    for (uint32_t v = 0; v < m; ++v) {
        const float x = float((cap.points[v].x - xMid) * scale);
        const float y = float((cap.points[v].y - yMin) * scale);
        for (long k = 0; k <= rings; ++k)
            if (k == 0 || k == rings || column[v] >= 0)
                mesh.positions[vertexAt(v, k)] = {x, y, float(zAt(k))};
    }

    mesh.triangles.reserve(2 * cap.tris.size() + 2 * outlineEdges.size() * size_t(rings));
    for (const auto& t : cap.tris) mesh.triangles.push_back(t); // front, facing +z
    for (const auto& t : cap.tris) mesh.triangles.push_back({m + t[0], m + t[2], m + t[1]});
    // The outline runs with the cap on its left, so (a, b, b', a') with z rising faces out.
    for (const auto& [a, b] : outlineEdges)
        for (long k = 0; k < rings; ++k) {
            const uint32_t a0 = vertexAt(a, k), b0 = vertexAt(b, k), a1 = vertexAt(a, k + 1),
                           b1 = vertexAt(b, k + 1);
            mesh.triangles.push_back({a0, b0, b1});
            mesh.triangles.push_back({a0, b1, a1});
        }
    return mesh;
}

} // namespace ffd
