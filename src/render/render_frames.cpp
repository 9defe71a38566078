#include "ffdaabb/error.h"
#include "ffdaabb/render.h"

#include <chrono>
#include <cstdio>
#include <system_error>
#include <vector>

namespace ffd::render {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

void validate(const RenderSettings& s) {
    if (s.width < 2 || s.height < 2 || s.width > 16384 || s.height > 16384)
        throw InputError("size", std::to_string(s.width) + " x " + std::to_string(s.height) +
                                     " is outside 2 .. 16384");
    if (s.frames < 1) throw InputError("frames", std::to_string(s.frames) + " must be >= 1");
    if (s.stepsPerFrame < 1)
        throw InputError("steps per frame", std::to_string(s.stepsPerFrame) + " must be >= 1");
    if (!(s.fps > 0 && s.fps <= 1000))
        throw InputError("fps", std::to_string(s.fps) + " is outside (0, 1000]");
}

/// A PNG file name pattern: the text around one "%d" or "%0Nd".
struct Pattern {
    std::string before, after;
    int width = 0;
    bool zeroPad = false;

    std::string name(int index) const {
        std::string digits = std::to_string(index);
        if (int(digits.size()) < width)
            digits.insert(0, size_t(width) - digits.size(), zeroPad ? '0' : ' ');
        return before + digits + after;
    }
};

bool parsePattern(const std::string& text, Pattern& out) {
    const size_t percent = text.find('%');
    if (percent == std::string::npos) return false;
    size_t i = percent + 1;
    Pattern p;
    if (i < text.size() && text[i] == '0') p.zeroPad = true, ++i;
    while (i < text.size() && text[i] >= '0' && text[i] <= '9')
        p.width = p.width * 10 + (text[i++] - '0');
    if (i >= text.size() || text[i] != 'd' || p.width > 12)
        throw InputError(text,
                         "a frame pattern needs exactly one %d or %0Nd (e.g. frame_%05d.png)");
    p.before = text.substr(0, percent);
    p.after = text.substr(i + 1);
    if (p.after.find('%') != std::string::npos)
        throw InputError(text, "a frame pattern needs exactly one %d or %0Nd");
    out = p;
    return true;
}

namespace fs = std::filesystem;

/// The PNG files of one sequence and the folders made for them. Unless committed, the
/// destructor removes them again (files written, then the folders made, deepest first), so
/// that a render that fails or is interrupted by an exception leaves nothing half-written.
class SequenceOutput {
public:
    SequenceOutput() = default;
    SequenceOutput(const SequenceOutput&) = delete;
    SequenceOutput& operator=(const SequenceOutput&) = delete;
    ~SequenceOutput() {
        if (committed_) return;
        std::error_code ec;
        for (const fs::path& file : written_) fs::remove(file, ec);
        for (auto it = created_.rbegin(); it != created_.rend(); ++it) fs::remove(*it, ec);
    }

    /// Makes `folder` and the parents it lacks (InputError naming `text` when a part of it is a
    /// file or cannot be made).
    void makeFolder(const std::string& text, const fs::path& folder) {
        std::vector<fs::path> missing;
        fs::path p = folder.has_filename() ? folder : folder.parent_path(); // "a/b/" -> "a/b"
        while (!p.empty() && !fs::exists(p)) {
            missing.push_back(p);
            if (!p.has_parent_path() || p.parent_path() == p) break;
            p = p.parent_path();
        }
        if (!p.empty() && fs::exists(p) && !fs::is_directory(p))
            throw InputError(text, "cannot make the folder: " + p.string() +
                                       " exists and is not a folder");
        for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
            std::error_code ec;
            if (!fs::create_directory(*it, ec) && !fs::is_directory(*it))
                throw InputError(text, "cannot make the folder " + it->string() + ": " +
                                           (ec ? ec.message() : "unknown error"));
            created_.push_back(*it);
        }
    }

    void write(const Image& image, const fs::path& file) {
        writePng(image, file); // atomic: nothing at `file` when it throws
        written_.push_back(file);
    }

    void commit() { committed_ = true; }

private:
    std::vector<fs::path> created_, written_;
    bool committed_ = false;
};

} // namespace

RenderStats renderFrames(const WorldFactory& makeWorld, const RenderSettings& settings,
                         const FrameSink& sink) {
    validate(settings);
    RenderStats stats;
    World world = makeWorld();
    OffscreenRenderer renderer;
    stats.context = renderer.description();
    const Camera camera =
        settings.camera
            ? *settings.camera
            : frameWorld(world, float(settings.width) / float(settings.height), settings.framing);
    DrawOptions draw = settings.draw;
    // Fixed from the first world, so that the grid does not jump as bodies move.
    if (draw.gridSpacing <= 0) draw.gridSpacing = autoGridSpacing(world);
    for (int f = 0; f < settings.frames; ++f) {
        auto start = Clock::now();
        for (int s = 0; s < settings.stepsPerFrame; ++s) world.step();
        stats.steps += uint64_t(settings.stepsPerFrame);
        stats.simulateSeconds += secondsSince(start);
        start = Clock::now();
        const Image image = renderer.render(world, camera, draw, settings.width, settings.height);
        stats.renderSeconds += secondsSince(start);
        start = Clock::now();
        sink(f, image);
        stats.writeSeconds += secondsSince(start);
        ++stats.frames;
        if (settings.progress) settings.progress(f + 1, settings.frames);
    }
    stats.stateHash = world.stateHash();
    return stats;
}

RenderStats renderFrames(const WorldFactory& makeWorld, const RenderSettings& settings,
                         const std::filesystem::path& output) {
    validate(settings);
    const std::string text = output.string();
    if (text.empty()) throw InputError("output", "no output path given");
    const std::string extension = output.extension().string();

    if (extension == ".mp4" && text.find('%') == std::string::npos) {
        VideoWriter video(output, settings.width, settings.height, settings.fps, settings.video);
        RenderStats stats = renderFrames(makeWorld, settings,
                                         [&](int, const Image& image) { video.addFrame(image); });
        const auto start = Clock::now();
        video.finish();
        stats.writeSeconds += secondsSince(start);
        return stats;
    }

    Pattern pattern;
    bool sequence = parsePattern(text, pattern);
    SequenceOutput files;
    // A folder: one that exists, a path ending in '/', or a path without an extension (made,
    // with the parents it lacks).
    if (!sequence && (text.back() == '/' || fs::is_directory(output) || extension.empty())) {
        if (fs::exists(output) && !fs::is_directory(output))
            throw InputError(text, "exists and is not a folder (a path without an extension is "
                                   "a folder for the frames)");
        files.makeFolder(text, output);
        pattern.before = (output / "frame_").string();
        pattern.after = ".png";
        pattern.width = 5, pattern.zeroPad = true;
        sequence = true;
    }
    if (sequence) {
        const fs::path first(pattern.name(0));
        if (first.has_parent_path() && !fs::is_directory(first.parent_path()))
            throw InputError(text, "cannot write: the folder " + first.parent_path().string() +
                                       " does not exist");
        RenderStats stats = renderFrames(makeWorld, settings, [&](int index, const Image& image) {
            files.write(image, pattern.name(index));
        });
        files.commit();
        return stats;
    }
    if (extension != ".png")
        throw InputError(text, "unknown output kind \"" + extension + "\"" +
                                   ": expected FILE.mp4 (a video), FILE.png (the last frame), a "
                                   "frame pattern such as frame_%05d.png, or a folder (a path "
                                   "without an extension, or ending in '/')");
    if (output.has_parent_path() && !fs::is_directory(output.parent_path()))
        throw InputError(text, "cannot write: the folder " + output.parent_path().string() +
                                   " does not exist");
    Image last;
    RenderStats stats =
        renderFrames(makeWorld, settings, [&](int, const Image& image) { last = image; });
    const auto start = Clock::now();
    writePng(last, output);
    stats.writeSeconds += secondsSince(start);
    return stats;
}

} // namespace ffd::render
