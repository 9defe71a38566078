// MP4 through an ffmpeg child process: raw RGB frames on its stdin, its stderr into a temporary
// file that becomes the error message when it fails.
#include "ffdaabb/error.h"
#include "ffdaabb/render.h"

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <spawn.h>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace ffd::render {

namespace {

std::string formatFloat(float v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", double(v));
    return text;
}

/// write() that reports a closed pipe as EPIPE instead of killing the process with SIGPIPE:
/// the signal is blocked on this thread for the call, and a SIGPIPE it raised is consumed.
bool writeAll(int fd, const uint8_t* data, size_t size) {
    sigset_t pipeSet, old;
    sigemptyset(&pipeSet);
    sigaddset(&pipeSet, SIGPIPE);
    pthread_sigmask(SIG_BLOCK, &pipeSet, &old);
    sigset_t pending;
    sigpending(&pending);
    const bool wasPending = sigismember(&pending, SIGPIPE);
    bool ok = true;
    while (size > 0) {
        const ssize_t n = ::write(fd, data, size);
        if (n < 0) {
            if (errno == EINTR) continue;
            ok = false;
            break;
        }
        data += n, size -= size_t(n);
    }
    if (!ok && errno == EPIPE && !wasPending) {
        const timespec zero{0, 0};
        sigtimedwait(&pipeSet, nullptr, &zero);
    }
    pthread_sigmask(SIG_SETMASK, &old, nullptr);
    return ok;
}

} // namespace

struct VideoWriter::Impl {
    std::filesystem::path path, temp, log;
    int width = 0, height = 0;
    int frames = 0;
    int pipe = -1;
    pid_t child = -1;
    bool finished = false;
    std::vector<uint8_t> rgb;

    std::string ffmpegMessage() const {
        std::ifstream in(log);
        std::stringstream ss;
        ss << in.rdbuf();
        std::string text = ss.str();
        while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
        if (text.size() > 2000) text = "..." + text.substr(text.size() - 2000);
        return text.empty() ? "(no message)" : text;
    }

    /// Closes the pipe and waits for ffmpeg; its exit status, or -1.
    int wait(bool kill) {
        if (pipe >= 0) ::close(pipe), pipe = -1;
        if (child <= 0) return -1;
        if (kill) ::kill(child, SIGTERM);
        int status = 0;
        while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
        }
        child = -1;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    }

    void cleanUp() {
        std::error_code ec;
        std::filesystem::remove(temp, ec);
        std::filesystem::remove(log, ec);
    }

    [[noreturn]] void fail(const std::string& what) {
        wait(true);
        const std::string message = ffmpegMessage();
        cleanUp();
        finished = true;
        throw RenderError(path.string() + ": " + what + ": " + message);
    }
};

VideoWriter::VideoWriter(const std::filesystem::path& path, int width, int height, float fps,
                         const VideoSettings& settings)
    : impl_(std::make_unique<Impl>()) {
    Impl& w = *impl_;
    if (width < 2 || height < 2 || width > 16384 || height > 16384)
        throw InputError(path.string(), "video size " + std::to_string(width) + " x " +
                                            std::to_string(height) + " is outside 2 .. 16384");
    if (!(fps > 0 && fps <= 1000))
        throw InputError(path.string(), "frame rate " + formatFloat(fps) + " is outside (0, 1000]");
    if (path.has_parent_path() && !std::filesystem::is_directory(path.parent_path()))
        throw InputError(path.string(), "cannot write: the folder " + path.parent_path().string() +
                                            " does not exist");
    w.path = path;
    w.width = width, w.height = height;
    w.temp = path.string() + ".tmp-" + std::to_string(::getpid());
    w.log = std::filesystem::temp_directory_path() /
            ("ffdaabb-ffmpeg-" + std::to_string(::getpid()) + "-" +
             std::to_string(reinterpret_cast<uintptr_t>(this)) + ".log");

    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0)
        throw RenderError(std::string("cannot create a pipe for ffmpeg: ") + std::strerror(errno));
    const std::string size = std::to_string(width) + "x" + std::to_string(height);
    // libx264 with yuv420p needs even sizes: odd ones get a black row or column.
    const std::vector<std::string> args = {settings.ffmpeg,
                                           "-hide_banner",
                                           "-nostdin",
                                           "-loglevel",
                                           "error",
                                           "-f",
                                           "rawvideo",
                                           "-pix_fmt",
                                           "rgb24",
                                           "-s",
                                           size,
                                           "-r",
                                           formatFloat(fps),
                                           "-i",
                                           "-",
                                           "-an",
                                           "-vf",
                                           "pad=ceil(iw/2)*2:ceil(ih/2)*2",
                                           "-c:v",
                                           "libx264",
                                           "-preset",
                                           settings.preset,
                                           "-crf",
                                           std::to_string(settings.crf),
                                           "-pix_fmt",
                                           "yuv420p",
                                           "-movflags",
                                           "+faststart",
                                           "-f",
                                           "mp4",
                                           "-y",
                                           w.temp.string()};
    std::vector<char*> argv;
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);

    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, fds[0], 0);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, w.log.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0600);
    pid_t pid = -1;
    const int error =
        ::posix_spawnp(&pid, settings.ffmpeg.c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    ::close(fds[0]);
    if (error != 0) {
        ::close(fds[1]);
        w.cleanUp();
        throw RenderError("cannot start " + settings.ffmpeg + " (" + std::strerror(error) +
                          "); install ffmpeg or set VideoSettings::ffmpeg");
    }
    w.pipe = fds[1];
    w.child = pid;
}

VideoWriter::~VideoWriter() {
    if (!impl_->finished) {
        impl_->wait(true);
        impl_->cleanUp();
    }
}

void VideoWriter::addFrame(const Image& image) {
    Impl& w = *impl_;
    if (w.finished) throw RenderError(w.path.string() + ": addFrame after finish");
    if (image.width != w.width || image.height != w.height ||
        image.pixels.size() != size_t(w.width) * size_t(w.height) * 4)
        throw InputError(w.path.string(), "frame of " + std::to_string(image.width) + " x " +
                                              std::to_string(image.height) + ", the video is " +
                                              std::to_string(w.width) + " x " +
                                              std::to_string(w.height));
    w.rgb.resize(size_t(w.width) * size_t(w.height) * 3);
    for (size_t i = 0, n = size_t(w.width) * size_t(w.height); i < n; ++i) {
        w.rgb[i * 3 + 0] = image.pixels[i * 4 + 0];
        w.rgb[i * 3 + 1] = image.pixels[i * 4 + 1];
        w.rgb[i * 3 + 2] = image.pixels[i * 4 + 2];
    }
    if (!writeAll(w.pipe, w.rgb.data(), w.rgb.size())) w.fail("ffmpeg stopped reading frames");
    ++w.frames;
}

void VideoWriter::finish() {
    Impl& w = *impl_;
    if (w.finished) return;
    if (w.frames == 0) w.fail("no frames to encode");
    const int status = w.wait(false);
    if (status != 0) w.fail("ffmpeg failed with exit status " + std::to_string(status));
    std::error_code ec;
    std::filesystem::rename(w.temp, w.path, ec);
    if (ec) {
        w.cleanUp();
        w.finished = true;
        throw InputError(w.path.string(),
                         "cannot rename the finished video into place: " + ec.message());
    }
    std::filesystem::remove(w.log, ec);
    w.finished = true;
}

int VideoWriter::frames() const {
    return impl_->frames;
}

} // namespace ffd::render
