// The interactive viewer: a GLFW window with Dear ImGui controls that runs a World.
//
//   ffd::render::ViewerSettings settings;
//   ffd::render::runViewer([] { return makeMyScene(); }, settings);
//
// Controls: space play/pause, N (or the Step button) one frame, R restart (a fresh world from
// the factory), M toggles enhanced/previous collisions, 1-4 toggle the overlays (spheres,
// boxes, lattice, contacts), F reframes the camera, P switches what a drag does, Esc closes.
// Mouse: left-drag on a body pins the grabbed point (World::pinPoint, a hard pin) and moves the
// pin's target along the cursor ray at the grabbed depth, releasing unpins (after P: a spring
// force on its particle nearest the grabbed point instead), left- or right-drag elsewhere
// orbits, middle-drag or shift+drag pans, the wheel zooms.
//
// Scripted mode (ViewerSettings::frames > 0) runs that many frames without waiting for vsync,
// saves the window (UI included) to ViewerSettings::screenshot when set, and closes: what
// `--frames N --screenshot FILE` maps onto. Needs a display (use xvfb-run on a headless
// machine); RenderError when no window can be opened.
#pragma once

#include "ffdaabb/render.h"

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>

namespace ffd::render {

struct ViewerSettings {
    int width = 1280, height = 720; ///< window size, screen coordinates
    std::string title = "ffdaabb";
    bool startPaused = false;
    int stepsPerFrame = 1; ///< world.step() calls per displayed frame while playing
    DrawOptions draw;
    std::optional<Camera> camera; ///< unset: frameWorld on the first world
    Framing framing;
    int frames = 0;                   ///< > 0: scripted mode, close after this many frames
    std::filesystem::path screenshot; ///< scripted mode: save the last frame here (PNG)
    bool vsync = true;                ///< ignored in scripted mode (off)
    bool showUi = true;               ///< the ImGui panel
    /// "Drop more objects": adds bodies to the running world; the button is hidden when unset.
    std::function<void(World&)> dropObjects;
    /// Called after every displayed frame (frame index from 0), e.g. for scripted checks.
    std::function<void(int, World&)> onFrame;
};

/// What a viewer run did.
struct ViewerResult {
    int frames = 0;         ///< frames displayed
    uint64_t steps = 0;     ///< world steps since the last (re)start
    uint64_t stateHash = 0; ///< of the world at the end
    bool closedByUser = false;
};

/// A window running a world. Not copyable; one per thread (GLFW's rules: the main thread).
class Viewer {
public:
    /// Opens the window and makes the first world; RenderError without a display.
    Viewer(WorldFactory makeWorld, ViewerSettings settings);
    ~Viewer();
    Viewer(const Viewer&) = delete;
    Viewer& operator=(const Viewer&) = delete;

    /// One iteration: events, input, steps while playing, drawing, swap. False once the window
    /// was asked to close (Esc, the close button).
    bool frame();
    /// frame() until closed, or settings.frames frames in scripted mode (then the screenshot).
    ViewerResult run();

    /// Captures the window (framebuffer size, UI included) at the end of the next frame();
    /// lastCapture() has it after that frame.
    void captureNextFrame();
    /// The last captured frame (empty before any).
    const Image& lastCapture() const;

    // The controls the UI and keys use, for programs that drive the viewer themselves.
    World& world();
    bool playing() const;
    void setPlaying(bool playing);
    /// Steps once (stepsPerFrame steps) at the next frame, also while paused.
    void stepOnce();
    /// Replaces the world with a fresh one from the factory (camera kept).
    void restart();
    void setMode(CollisionMode mode);
    DrawOptions& drawOptions();
    Camera camera() const;
    void setCamera(const Camera& camera);
    /// The window's size in screen coordinates, which grab positions and the camera refer to.
    void windowSize(int& outWidth, int& outHeight) const;
    /// Grabs the body under window position (x, y) as a left-drag there would (pickBody);
    /// false when there is none. While held, the grabbed point is pinned to the grab point (or,
    /// after P, each step pulls the grabbed particle towards it); the mouse moves it in a real
    /// drag, moveGrab in a program; release() unpins.
    bool grab(float x, float y);
    /// Moves the grab point to window position (x, y) at the depth it was grabbed at.
    void moveGrab(float x, float y);
    void release();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Opens a viewer and runs it (Viewer::run).
ViewerResult runViewer(const WorldFactory& makeWorld, const ViewerSettings& settings);

} // namespace ffd::render
