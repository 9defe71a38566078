// Loading mesh files: OBJ, PLY, STL and OFF, optionally gzipped, read by Assimp 5.2.5.
//
// The file is read into memory once (inflated with zlib when gzipped), checked structurally by
// format_checks.h, handed to Assimp from memory with no file system behind it, and Assimp's
// scene is checked again before any post-processing step runs on it. Errors are InputErrors
// that name the file.
#include "ffdaabb/mesh_io.h"
#include "ffdaabb/error.h"
#include "mesh/format_checks.h"

#include <assimp/IOStream.hpp>
#include <assimp/IOSystem.hpp>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <new>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>

namespace ffd {
namespace {

using detail::kMaxFileBytes;
using detail::MeshFormat;

[[noreturn]] void fail(const std::string& source, const std::string& problem) {
    throw InputError(source, problem);
}

constexpr const char* kSupported =
    ".obj, .ply, .stl and .off, each optionally gzipped (e.g. .ply.gz)";

std::string lowerCase(std::string s) {
    for (char& c : s)
        if (c >= 'A' && c <= 'Z') c = char(c - 'A' + 'a');
    return s;
}

std::optional<MeshFormat> formatFromExtension(const std::string& extension) {
    if (extension == ".obj") return MeshFormat::Obj;
    if (extension == ".ply") return MeshFormat::Ply;
    if (extension == ".stl") return MeshFormat::Stl;
    if (extension == ".off") return MeshFormat::Off;
    return std::nullopt;
}

struct FileKind {
    MeshFormat format;
    bool gzipped;
};

FileKind classify(const std::filesystem::path& path, const std::string& source) {
    std::string extension = lowerCase(path.extension().string());
    const bool gzipped = extension == ".gz";
    if (gzipped) {
        extension = lowerCase(path.stem().extension().string());
        if (extension.empty())
            fail(source, std::string("unsupported file extension: a .gz file must name the "
                                     "format inside, e.g. model.ply.gz (supported: ") +
                             kSupported + ")");
    }
    if (extension.empty())
        fail(source,
             std::string("unsupported file: no file extension (supported: ") + kSupported + ")");
    const auto format = formatFromExtension(extension);
    if (!format)
        fail(source, "unsupported file extension '" + extension + "'" +
                         (gzipped ? " inside .gz" : "") + " (supported: " + kSupported + ")");
    return {*format, gzipped};
}

// Rules out paths that cannot be a mesh file. Devices and pipes are refused: reading /dev/zero
// or a FIFO would never end.
void checkRegularFile(const std::filesystem::path& path, const std::string& source) {
    std::error_code ec;
    const auto status = std::filesystem::status(path, ec);
    if (ec && ec != std::errc::no_such_file_or_directory && ec != std::errc::not_a_directory)
        fail(source, "cannot be accessed: " + ec.message());
    if (!std::filesystem::exists(status))
        fail(source, std::string("does not exist (expected a mesh file: ") + kSupported + ")");
    if (std::filesystem::is_directory(status))
        fail(source, "is a directory (expected a mesh file)");
    if (!std::filesystem::is_regular_file(status))
        fail(source, "is not a regular file (a device, pipe or socket; expected a mesh file)");
}

std::string readWholeFile(const std::filesystem::path& path, const std::string& source) {
    std::error_code ec;
    const uintmax_t size = std::filesystem::file_size(path, ec);
    if (ec) fail(source, "cannot be read: " + ec.message());
    if (size == 0) fail(source, "is empty (0 bytes; expected a mesh file)");
    if (size > kMaxFileBytes)
        fail(source,
             "is " + std::to_string(size) + " bytes, more than the limit of 2 GiB for a mesh file");

    std::FILE* file = std::fopen(path.c_str(), "rb");
    if (!file) fail(source, std::string("cannot be read: ") + std::strerror(errno));
    std::string data(size_t(size), '\0');
    const size_t got = std::fread(data.data(), 1, data.size(), file);
    const bool error = std::ferror(file) != 0;
    std::fclose(file);
    if (error) fail(source, "cannot be read: an I/O error occurred");
    if (got != data.size())
        fail(source, "cannot be read completely: it shrank while being read (" +
                         std::to_string(got) + " of " + std::to_string(size) + " bytes)");
    return data;
}

// Inflates a gzip file (concatenated members too, as gzip(1) does), refusing to grow past
// kMaxFileBytes so that a small "gzip bomb" cannot exhaust memory.
std::string gunzip(const std::string& compressed, const std::string& source) {
    if (compressed.size() < 2 || static_cast<unsigned char>(compressed[0]) != 0x1f ||
        static_cast<unsigned char>(compressed[1]) != 0x8b)
        fail(source, "malformed gzip file: it does not start with the gzip signature 1f 8b "
                     "(expected a gzip-compressed mesh file)");
    z_stream zs{};
    if (inflateInit2(&zs, 15 + 16) != Z_OK)
        fail(source, "cannot be inflated: zlib could not start");
    struct End {
        z_stream* zs;
        ~End() { inflateEnd(zs); }
    } end{&zs};

    std::string out(std::clamp<size_t>(compressed.size() * 4, 1 << 16, kMaxFileBytes), '\0');
    zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(compressed.data()));
    zs.avail_in = uInt(compressed.size()); // <= kMaxFileBytes < 4 GiB
    size_t produced = 0;
    for (;;) {
        if (produced == out.size()) {
            if (out.size() >= kMaxFileBytes)
                fail(source, "inflates to more than the limit of 2 GiB (a corrupt file or a "
                             "gzip bomb)");
            out.resize(std::min<size_t>(out.size() * 2, kMaxFileBytes));
        }
        zs.next_out = reinterpret_cast<Bytef*>(out.data() + produced);
        zs.avail_out = uInt(std::min<size_t>(out.size() - produced, UINT_MAX));
        const int r = inflate(&zs, Z_NO_FLUSH);
        produced = size_t(reinterpret_cast<char*>(zs.next_out) - out.data());
        if (r == Z_STREAM_END) {
            const bool anotherMember =
                zs.avail_in >= 2 && zs.next_in[0] == 0x1f && zs.next_in[1] == 0x8b;
            if (!anotherMember) break; // trailing bytes are ignored, as gzip(1) does
            inflateReset(&zs);
            continue;
        }
        if (r == Z_OK) continue;
        if (r == Z_BUF_ERROR && zs.avail_in == 0)
            fail(source, "truncated gzip stream: the compressed data ends before the end of the "
                         "stream (after " +
                             std::to_string(produced) + " inflated bytes)");
        if (r == Z_BUF_ERROR) continue; // output full: grown above
        if (r == Z_MEM_ERROR) fail(source, "cannot be inflated: out of memory");
        fail(source, std::string("malformed gzip stream: ") +
                         (zs.msg ? zs.msg : "corrupt compressed data") +
                         " (expected a valid gzip file)");
    }
    out.resize(produced);
    if (out.empty())
        fail(source, "is empty after decompression (0 bytes inside the gzip stream; expected a "
                     "mesh file)");
    return out;
}

// Assimp may read the buffer we hand it and nothing else: a material library or texture named
// inside the file could be /dev/zero, a FIFO or a file that makes the load fail.
class NoFileSystem final : public Assimp::IOSystem {
public:
    bool Exists(const char*) const override { return false; }
    char getOsSeparator() const override { return '/'; }
    Assimp::IOStream* Open(const char*, const char*) override { return nullptr; }
    void Close(Assimp::IOStream* stream) override { delete stream; }
};

std::string formatName(MeshFormat format) {
    std::string name = detail::formatExtension(format);
    for (char& c : name) c = char(c - 'a' + 'A');
    return name;
}

// Checks what Assimp built before a post-processing step trusts it: faces with indices in
// range, finite positions, and primitive-type flags recomputed from the faces (Triangulate
// asserts, i.e. aborts, when a mesh claims polygons it does not have).
void checkScene(const aiScene* scene, MeshFormat format, const std::string& source) {
    const std::string what = "malformed " + formatName(format) + " file: ";
    if (!scene->mMeshes && scene->mNumMeshes > 0) fail(source, what + "Assimp lost its meshes");
    size_t polygons = 0;
    uint64_t vertexBase = 0;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        aiMesh* mesh = scene->mMeshes[m];
        if (!mesh) continue;
        if ((mesh->mNumVertices > 0 && !mesh->mVertices) || (mesh->mNumFaces > 0 && !mesh->mFaces))
            fail(source, what + "Assimp returned a mesh without data");
        unsigned types = 0;
        for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
            const aiFace& face = mesh->mFaces[f];
            if (face.mNumIndices == 0 || !face.mIndices)
                fail(source, what + "a face without vertices");
            for (unsigned k = 0; k < face.mNumIndices; ++k)
                if (face.mIndices[k] >= mesh->mNumVertices)
                    fail(source, what + "a face uses vertex index " +
                                     std::to_string(face.mIndices[k]) + ", out of range (" +
                                     std::to_string(mesh->mNumVertices) + " vertices)");
            switch (face.mNumIndices) {
            case 1:
                types |= aiPrimitiveType_POINT;
                break;
            case 2:
                types |= aiPrimitiveType_LINE;
                break;
            case 3:
                types |= aiPrimitiveType_TRIANGLE;
                break;
            default:
                types |= aiPrimitiveType_POLYGON;
                break;
            }
            if (face.mNumIndices >= 3) ++polygons;
        }
        mesh->mPrimitiveTypes = types;
        for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
            const aiVector3D& p = mesh->mVertices[v];
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
                char buf[200];
                std::snprintf(buf, sizeof buf,
                              "non-finite coordinate: vertex %llu is (%g, %g, %g) (expected "
                              "finite numbers)",
                              static_cast<unsigned long long>(vertexBase + v), double(p.x),
                              double(p.y), double(p.z));
                fail(source, buf);
            }
        }
        vertexBase += mesh->mNumVertices;
    }
    if (polygons == 0)
        fail(source, "the " + formatName(format) +
                         " file contains no triangles, only points or lines (expected faces "
                         "with at least 3 corners)");
}

// Turns every OBJ statement that starts with 'm' or 'u' (mtllib, usemtl, and whatever else
// Assimp's OBJ reader dispatches to its material code by that first letter) into a comment.
// Materials mean nothing here, and Assimp 5.2's material path crashes (a wild write) on some
// malformed lines (found by fuzz_mesh_load; tests/mesh LoadMesh.ObjMaterialLinesAreIgnored).
void dropObjMaterialStatements(std::string& data) {
    size_t start = data.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;
    for (size_t i = start; i < data.size(); ++i) {
        const bool lineStart = i == start || data[i - 1] == '\n' || data[i - 1] == '\r';
        if (lineStart && (data[i] == 'm' || data[i] == 'u')) data[i] = '#';
    }
}

TriangleMesh importWithAssimp(std::string& data, MeshFormat format, bool text,
                              const std::string& source) {
    // Assimp's text readers look for a line end after the last line.
    if (text && format != MeshFormat::Stl && data.back() != '\n') data.push_back('\n');
    if (format == MeshFormat::Obj) dropObjMaterialStatements(data);

    Assimp::Importer importer;
    importer.SetIOHandler(new NoFileSystem); // the importer owns and deletes it
    const aiScene* scene =
        importer.ReadFileFromMemory(data.data(), data.size(), 0, detail::formatExtension(format));
    if (!scene)
        fail(source, "malformed " + formatName(format) +
                         " file: Assimp could not read it: " + importer.GetErrorString());
    checkScene(scene, format, source);
    scene = importer.ApplyPostProcessing(aiProcess_Triangulate);
    if (!scene)
        fail(source, "malformed " + formatName(format) +
                         " file: Assimp could not triangulate it: " + importer.GetErrorString());

    // Node transforms are not applied: none of these four formats can express one (Assimp gives
    // identity nodes), and merging scene->mMeshes takes each mesh exactly once.
    TriangleMesh mesh;
    size_t vertexCount = 0, triangleCount = 0;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const aiMesh* part = scene->mMeshes[m];
        if (!part) continue;
        size_t triangles = 0;
        for (unsigned f = 0; f < part->mNumFaces; ++f)
            triangles += part->mFaces[f].mNumIndices == 3 ? 1 : 0;
        if (triangles == 0) continue; // points and lines only
        vertexCount += part->mNumVertices;
        triangleCount += triangles;
    }
    if (vertexCount >= UINT32_MAX)
        fail(source, "has " + std::to_string(vertexCount) +
                         " vertices, more than 32-bit indices can address");
    mesh.positions.reserve(vertexCount);
    mesh.triangles.reserve(triangleCount);
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const aiMesh* part = scene->mMeshes[m];
        if (!part) continue;
        const auto base = uint32_t(mesh.positions.size());
        bool used = false;
        for (unsigned f = 0; f < part->mNumFaces; ++f) {
            const aiFace& face = part->mFaces[f];
            if (face.mNumIndices != 3) continue;
            mesh.triangles.push_back(
                {base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
            used = true;
        }
        if (!used) continue;
        for (unsigned v = 0; v < part->mNumVertices; ++v) {
            const aiVector3D& p = part->mVertices[v];
            mesh.positions.push_back({float(p.x), float(p.y), float(p.z)});
        }
    }
    return mesh;
}

} // namespace

TriangleMesh loadMesh(const std::filesystem::path& path) {
    const std::string source = path.string();
    checkRegularFile(path, source);
    const FileKind kind = classify(path, source);
    std::string data = readWholeFile(path, source);
    if (kind.gzipped) data = gunzip(data, source);

    TriangleMesh mesh;
    try {
        const detail::PrecheckResult checked = detail::precheck(kind.format, data, source);
        mesh = importWithAssimp(data, kind.format, checked.text, source);
    } catch (const InputError&) {
        throw;
    } catch (const std::bad_alloc&) {
        fail(source, "ran out of memory while reading the mesh");
    } catch (const std::exception& e) {
        fail(source, "malformed " + formatName(kind.format) + " file: " + e.what());
    } catch (...) {
        fail(source, "malformed " + formatName(kind.format) + " file: the reader failed");
    }
    validate(mesh, source);

    // Formats that store corners per face (STL, and Assimp's OBJ reader) repeat positions:
    // join exactly equal ones so that a cube has 8 vertices. Nothing else is cleaned up.
    CleanupSettings weldOnly;
    weldOnly.dropDegenerate = false;
    weldOnly.dropDuplicates = false;
    weldOnly.dropUnreferenced = false;
    cleanup(mesh, weldOnly);
    mesh.name = path.filename().string();
    return mesh;
}

} // namespace ffd
