// Loading mesh files: OBJ, PLY, STL and OFF, optionally gzipped.
//
// The file is read into memory once (inflated with zlib when gzipped), read by the reader of
// its format (mesh_reader.h: read_obj.cpp, read_ply.cpp, read_stl.cpp, read_off.cpp), which
// refuses malformed input itself, and the result is validated. Errors are InputErrors that
// name the file.
#include "ffdaabb/mesh_io.h"
#include "ffdaabb/error.h"
#include "mesh/mesh_reader.h"

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

using detail::fail;
using detail::kMaxFileBytes;
using detail::MeshFormat;

constexpr const char* kSupported =
    ".obj, .ply, .stl and .off, each optionally gzipped (e.g. .ply.gz)";

std::string lowerCase(std::string s) {
    for (char& c : s)
        if (c >= 'A' && c <= 'Z') c = char(c - 'A' + 'a');
    return s;
}

// The format whose extension (detail::formatExtension) `extension` is, with its dot.
std::optional<MeshFormat> formatFromExtension(const std::string& extension) {
    for (const MeshFormat format :
         {MeshFormat::Obj, MeshFormat::Ply, MeshFormat::Stl, MeshFormat::Off})
        if (extension == std::string(".") + detail::formatExtension(format)) return format;
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

std::string formatName(MeshFormat format) {
    std::string name = detail::formatExtension(format);
    for (char& c : name) c = char(c - 'a' + 'A');
    return name;
}

std::vector<detail::RawPart> readFormat(MeshFormat format, std::string_view data,
                                        const std::string& source) {
    switch (format) {
    case MeshFormat::Obj:
        return detail::readObj(data, source);
    case MeshFormat::Ply:
        return detail::readPly(data, source);
    case MeshFormat::Stl:
        return detail::readStl(data, source);
    case MeshFormat::Off:
        return detail::readOff(data, source);
    }
    return {};
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
        std::vector<detail::RawPart> parts = readFormat(kind.format, data, source);
        data = std::string(); // the bytes are no longer needed
        mesh = detail::assemble(parts, kind.format, source);
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

    // Formats read with a vertex per face corner (OBJ, OFF, STL) repeat positions:
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
