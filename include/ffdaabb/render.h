// Rendering a World: shaded deformed meshes on a floor with a grid and planar shadows, overlays
// of the collision pipeline (bounding spheres as in Fig. 3 of Jeon, Choi, Hong 2012, FFD-AABB
// cell boxes, lattices, contacts), images, PNG files and MP4 videos.
//
//   ffd::render::OffscreenRenderer renderer;            // EGL, no display needed
//   ffd::render::DrawOptions draw;  draw.overlays.spheres = true;
//   ffd::render::Image image = renderer.render(world, draw, 1280, 720);
//   ffd::render::writePng(image, "frame.png");
//
// Part of the optional library ffdaabb_render (OpenGL 3.3 core through EGL or GLFW, stb,
// ffmpeg); the core library has no GL. This header names no GL type, so it can be included by
// code that does not link GL itself. The viewer is in ffdaabb/viewer.h.
#pragma once

#include "ffdaabb/math.h"
#include "ffdaabb/world.h"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace ffd::render {

/// No OpenGL context could be made, a shader failed to build, or an encoder failed. Bad input
/// (paths, sizes, settings) raises ffd::InputError instead.
class RenderError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// An RGBA8 image, rows from the top.
struct Image {
    int width = 0, height = 0;
    std::vector<uint8_t> pixels; ///< width * height * 4 bytes

    uint8_t* pixel(int x, int y) { return pixels.data() + (size_t(y) * size_t(width) + x) * 4; }
    const uint8_t* pixel(int x, int y) const {
        return pixels.data() + (size_t(y) * size_t(width) + x) * 4;
    }
};

/// Writes `image` as a PNG: to a temporary name beside `path`, renamed into place when
/// complete. InputError when the folder is missing or the file cannot be written.
void writePng(const Image& image, const std::filesystem::path& path);
/// Reads a PNG (or any format stb_image reads) as RGBA8. InputError when unreadable.
Image readPng(const std::filesystem::path& path);

/// A perspective camera. +y is up in the world; nearPlane/farPlane <= 0 are chosen from the
/// distance between eye and target.
struct Camera {
    Vec3 eye{0, 3, 8};
    Vec3 target{0, 0.5f, 0};
    Vec3 up{0, 1, 0};
    float fovYDegrees = 40;
    float nearPlane = 0;
    float farPlane = 0;
};

/// How a camera frames a scene by itself: it looks at the centre of the scene's bounds from
/// the direction given by azimuth (about +y, from +z towards +x) and elevation (above the
/// horizon), from the nearest distance at which all eight corners of the bounds are in view.
struct Framing {
    float azimuthDegrees = 30;
    float elevationDegrees = 20;
    float fovYDegrees = 40;
    float margin = 1.1f; ///< > 1 leaves room around the scene (a scale on the corners' offsets)
};

/// A camera framing `box` for an image of aspect ratio width / height.
Camera frameBox(const Aabb& box, float aspect, const Framing& framing = {});
/// A camera framing every body of `world` (their bounds, extended down to the floor when the
/// world has one, so that bodies are seen standing on it). An empty world frames a unit box.
Camera frameWorld(const World& world, float aspect, const Framing& framing = {});

/// The pixel a world point projects to in a width x height image: x to the right and y down,
/// in pixels (pixel (i, j) covers [i, i+1) x [j, j+1)), z the depth in [-1, 1] (OpenGL's
/// normalised device depth). z is +infinity for points at or behind the eye plane.
Vec3 projectToPixel(const Camera& camera, int width, int height, Vec3 point);
/// The ray from the eye through pixel position (x, y) (same convention), direction unit length.
void pixelRay(const Camera& camera, int width, int height, float x, float y, Vec3& outOrigin,
              Vec3& outDirection);

/// What lies under a pixel.
struct Pick {
    BodyId body;           ///< null when the ray hits no body
    uint32_t particle = 0; ///< the body's lattice particle nearest the hit point
    Vec3 point;            ///< where the ray meets the deformed mesh
    float distance = 0;    ///< from the eye to `point`
    uint32_t triangle = 0; ///< the triangle hit (World::triangles(body)), ffd::raycast's
    Vec3 barycentric;      ///< the point's weights of the triangle's corners
    Vec3 normal;           ///< the triangle's unit normal
};
/// The body whose deformed mesh the ray through pixel position (x, y) meets first
/// (projectToPixel's convention), for picking and dragging: ffd::raycast (ffdaabb/queries.h).
Pick pickBody(const World& world, const Camera& camera, int width, int height, float x, float y);

/// The overlays of the collision pipeline, all off by default.
struct Overlays {
    bool spheres = false;  ///< bounding spheres, yellow wireframes (the paper's Fig. 3)
    bool boxes = false;    ///< FFD-AABB cell boxes, wire hexahedra through the boundary nodes
    bool lattice = false;  ///< lattice cell edges through the particles
    bool contacts = false; ///< last substep's contacts: points and short normal lines
    bool sleeping = false; ///< sleeping bodies drawn grey (WorldSettings::sleepSpeed)
};

/// A line segment drawn over the scene (e.g. the viewer's drag line).
struct Line {
    Vec3 a, b;
    Vec3 colour{1, 1, 1}; ///< sRGB, [0, 1]
};

/// How edges are smoothed.
enum class Antialiasing : uint8_t {
    Auto, ///< Msaa on GPUs; Fxaa on software renderers (llvmpipe), where multisampling costs
          ///< about 2.5 times the frame
    Msaa, ///< multisampling with DrawOptions::samples samples
    Fxaa, ///< a post-process on the single-sampled image (Lottes, "FXAA", NVIDIA 2009)
    None,
};

/// What to draw and how.
struct DrawOptions {
    Overlays overlays;
    bool meshes = true;
    bool floor = true;     ///< drawn only when the world has a floor
    bool grid = true;      ///< grid lines on the floor
    bool shadows = true;   ///< planar shadows of the meshes on the floor
    float gridSpacing = 0; ///< metres between grid lines; <= 0 chooses from the scene's size
    Antialiasing antialiasing = Antialiasing::Auto;
    int samples = 4;        ///< multisampling samples for Msaa; clamped to what the context offers
    float lineWidth = 1.5f; ///< overlay lines, pixels (clamped to the context's range)
    Vec3 background{0.82f, 0.86f, 0.90f}; ///< sRGB
    /// Overlays also show faintly where they are hidden behind meshes.
    bool hiddenOverlays = true;
    BodyId highlight;        ///< drawn lighter (the viewer's picked body); null for none
    std::vector<Line> lines; ///< extra segments, drawn last
};

/// The deterministic palette: saturated, well-separated colours (sRGB), cycling.
Vec3 paletteColour(size_t index);
/// A body's colour: the palette entry of its slot index, so it stays the same for the body's
/// life whatever is added or removed around it.
Vec3 bodyColour(BodyId body);
/// The grid spacing used when DrawOptions::gridSpacing <= 0: a power of ten fitted to the
/// bodies' bounds (1 m for a scene a few metres across).
float autoGridSpacing(const World& world);

/// Draws worlds with OpenGL 3.3 core into its own multisampled framebuffer, whichever context
/// is current: an EGL one without a display (OffscreenRenderer) or a window's (Viewer). Create,
/// use and destroy it with the same context current.
class Renderer {
public:
    /// Builds shaders and buffers in the current context; RenderError without a GL 3.3 one.
    Renderer();
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    /// Draws `world` as seen by `camera` into a width x height target (resized as needed).
    /// Reads the world only: rendering never changes the simulation.
    void draw(const World& world, const Camera& camera, const DrawOptions& options, int width,
              int height);
    /// The last draw's pixels.
    Image readImage();
    /// Copies the last draw into the current context's default framebuffer (a window) at its
    /// lower-left corner, scaled to framebufferWidth x framebufferHeight.
    void present(int framebufferWidth, int framebufferHeight);
    /// GL_VERSION and GL_RENDERER of the context, e.g. "4.5 (Core Profile) Mesa 22.3.6,
    /// llvmpipe (LLVM 15.0.6, 256 bits)".
    std::string glInfo() const;
    /// Whether the context renders on the CPU (llvmpipe, softpipe): Antialiasing::Auto's choice.
    bool softwareRenderer() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// A Renderer in its own headless EGL context (no display, no window): a GPU's EGL device
/// first, then Mesa's surfaceless platform (llvmpipe without a GPU), then software EGL devices,
/// then the default display; $FFD_EGL_PLATFORM = device | surfaceless | default keeps one kind.
/// Each call makes its context current on the calling thread.
class OffscreenRenderer {
public:
    OffscreenRenderer();
    ~OffscreenRenderer();
    OffscreenRenderer(const OffscreenRenderer&) = delete;
    OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

    Image render(const World& world, const Camera& camera, const DrawOptions& options = {},
                 int width = 1280, int height = 720);
    /// With a camera that frames the world (frameWorld).
    Image render(const World& world, const DrawOptions& options = {}, int width = 1280,
                 int height = 720);
    /// The EGL platform and GL context in use, e.g. "EGL 1.5 (Mesa Project), platform
    /// surfaceless; GL 4.5 (Core Profile) Mesa 22.3.6, llvmpipe ...".
    std::string description() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// How VideoWriter encodes.
struct VideoSettings {
    std::string ffmpeg = "ffmpeg"; ///< the program, looked up in PATH when it has no '/'
    int crf = 20;                  ///< libx264 quality (0 best .. 51 worst)
    std::string preset = "veryfast";
};

/// Encodes frames into an H.264 MP4 through an ffmpeg pipe (raw RGB frames on its stdin).
/// The video goes to a temporary name beside `path` and is renamed into place by finish() when
/// ffmpeg succeeded; on any failure, or when the writer is destroyed unfinished, nothing is
/// left behind.
class VideoWriter {
public:
    /// Starts ffmpeg; InputError for a bad size/rate or a missing folder, RenderError when
    /// ffmpeg cannot be started.
    VideoWriter(const std::filesystem::path& path, int width, int height, float fps,
                const VideoSettings& settings = {});
    ~VideoWriter();
    VideoWriter(const VideoWriter&) = delete;
    VideoWriter& operator=(const VideoWriter&) = delete;

    /// Appends a frame of the size given at construction; RenderError when ffmpeg has failed.
    void addFrame(const Image& image);
    /// Waits for ffmpeg, checks its exit status and moves the video into place; RenderError
    /// with ffmpeg's message on failure (the partial output is removed).
    void finish();
    int frames() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Makes a fresh World (a scene) each time it is called: for restarting the viewer and for
/// renderFrames.
using WorldFactory = std::function<World()>;

/// What renderFrames produces.
struct RenderSettings {
    int width = 1280, height = 720;
    int frames = 120;      ///< images to produce
    int stepsPerFrame = 1; ///< world.step() calls before each image
    float fps = 60;        ///< video frame rate
    /// The camera; unset: frameWorld on the world before the first step (and kept).
    std::optional<Camera> camera;
    Framing framing;
    DrawOptions draw;
    VideoSettings video;
    /// Called after each image (frames done, frames in all), e.g. for a progress bar.
    std::function<void(int, int)> progress;
};

/// What a renderFrames run did.
struct RenderStats {
    int frames = 0;
    uint64_t steps = 0;
    uint64_t stateHash = 0; ///< world.stateHash() at the end
    double simulateSeconds = 0, renderSeconds = 0, writeSeconds = 0;
    std::string context; ///< OffscreenRenderer::description()
};

/// Receives each image: its index (0-based) and pixels.
using FrameSink = std::function<void(int, const Image&)>;

/// Makes a world, then `frames` times: steps it stepsPerFrame times and renders an image, which
/// goes to `sink`. InputError for invalid settings.
RenderStats renderFrames(const WorldFactory& makeWorld, const RenderSettings& settings,
                         const FrameSink& sink);
/// Same, written to `output`:
///   "*.mp4"                      a video (VideoWriter);
///   a pattern with "%d" / "%0Nd"  one PNG per image, the image index substituted;
///   an existing folder, a path ending in '/' or a path without an extension (made, with the
///   parents it lacks): frame_00000.png, ... inside it;
///   any other "*.png"            the last image only (a still after `frames` frames);
///   anything else (another extension) is an InputError naming the kinds above.
/// When it fails (InputError, RenderError, or an exception from `makeWorld` or `progress`), the
/// PNG files it wrote and the folders it made are removed: nothing is left half-written.
RenderStats renderFrames(const WorldFactory& makeWorld, const RenderSettings& settings,
                         const std::filesystem::path& output);

} // namespace ffd::render
