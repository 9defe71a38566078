// Writing output files so that a failure never leaves a half-written file that looks complete:
// everything goes to "<name>.tmp-<pid>" and is renamed into place by commit(). If commit() is
// never reached (an exception, a crash), the destructor removes the temporary file.
#pragma once

#include "ffdaabb/error.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <system_error>
#include <unistd.h>

namespace ffd {

class AtomicFile {
public:
    explicit AtomicFile(std::filesystem::path path, const char* mode = "wb")
        : path_(std::move(path)), temp_(path_.string() + ".tmp-" + std::to_string(::getpid())) {
        if (path_.has_parent_path() && !path_.parent_path().empty() &&
            !std::filesystem::is_directory(path_.parent_path()))
            throw InputError(path_.string(), "cannot write: the folder " +
                                                 path_.parent_path().string() + " does not exist");
        // The finished file is renamed into place, which would replace a folder's entry or a
        // device such as /dev/null itself.
        std::error_code ec;
        const auto status = std::filesystem::status(path_, ec);
        if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status))
            throw InputError(path_.string(), "cannot write: it exists and is not a regular file "
                                             "(a folder, device, pipe or socket)");
        file_ = std::fopen(temp_.c_str(), mode);
        if (!file_)
            throw InputError(path_.string(),
                             std::string("cannot open for writing: ") + std::strerror(errno));
    }
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;
    ~AtomicFile() {
        if (file_) std::fclose(file_);
        if (!committed_) std::remove(temp_.c_str());
    }

    std::FILE* handle() { return file_; }

    /// Flushes, closes and renames the temporary file into place; throws InputError on failure.
    void commit() {
        const bool writeFailed = std::ferror(file_) != 0;
        const bool closeFailed = std::fclose(file_) != 0;
        file_ = nullptr;
        if (writeFailed || closeFailed)
            throw InputError(path_.string(), "write failed (disk full?)");
        if (std::rename(temp_.c_str(), path_.c_str()) != 0)
            throw InputError(path_.string(), std::string("cannot rename the finished file into "
                                                         "place: ") +
                                                 std::strerror(errno));
        committed_ = true;
    }

    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
    std::string temp_;
    std::FILE* file_ = nullptr;
    bool committed_ = false;
};

} // namespace ffd
