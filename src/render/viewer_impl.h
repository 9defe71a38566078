// The viewer's state (viewer.cpp: the window, the loop, the public interface; viewer_ui.cpp:
// input and the controls), shared by its two files.
#pragma once

#include "ffdaabb/viewer.h"

#include "ffdaabb/error.h"
#include "ffdaabb/queries.h"
#include "render/camera_math.h"
#include "render/gl_drivers.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

namespace ffd::render {

namespace viewer_detail {

using Clock = std::chrono::steady_clock;

inline double msSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

/// The plot's colour of each Table 1 column (TableColumn order); a stage takes its column's.
inline const ImU32 kColumnColours[kTableColumnCount] = {
    IM_COL32(190, 110, 220, 255), // mesh updating
    IM_COL32(90, 150, 230, 255),  // min, max updating
    IM_COL32(240, 210, 40, 255),  // distance calculating
    IM_COL32(160, 160, 160, 255), // floor
    IM_COL32(80, 200, 110, 255),  // objects collision
    IM_COL32(230, 90, 70, 255),   // dynamics
};
inline const ImU32 kTotalColour = IM_COL32(255, 255, 255, 255);

constexpr size_t kHistory = 240;
constexpr float kDragStiffness = 60.0f;     // 1/s^2: pull per metre of offset, per kg of body
constexpr float kMaxDragAcceleration = 300; // m/s^2, so that a far cursor does not explode

} // namespace viewer_detail

using namespace viewer_detail; // the viewer's two files share these names

void releaseGlfw(); // viewer.cpp

struct Viewer::Impl {
    WorldFactory makeWorld;
    ViewerSettings settings;
    GLFWwindow* window = nullptr;
    bool glfwAcquired = false;
    ImGuiContext* imgui = nullptr;
    bool imguiGlfw = false, imguiGl = false;
    std::unique_ptr<Renderer> renderer;
    std::unique_ptr<World> world;
    DrawOptions draw;

    bool playing = true, stepRequested = false, restartRequested = false;
    bool captureRequested = false;
    Image capture;
    int frames = 0;
    uint64_t steps = 0;

    // Orbit camera.
    Vec3 target;
    float distance = 5, yaw = 0, pitch = 0.3f, fovY = 40;

    // Mouse.
    enum class Drag { None, Orbit, Pan, Body } drag = Drag::None;
    double lastX = 0, lastY = 0;
    double scroll = 0;
    BodyId dragBody;
    uint32_t dragParticle = 0;
    float dragDepth = 0;
    Vec3 dragTarget;
    // Dragging pins the picked point and moves the pin's target with the mouse (releasing
    // unpins); off: the older spring force on the nearest particle.
    bool dragPins = true;
    PinId dragPin;
    bool scriptedGrab = false;    // grab() rather than the mouse: the cursor does not move it
    std::vector<int> keys;        // pressed since the last frame
    std::vector<int> buttonsDown; // mouse buttons pressed since the last frame
    std::vector<int> buttonsUp;
    // What lies under the cursor (a ray cast each frame): shown in the controls and outlined.
    bool showHover = true;
    Pick hover;
    std::vector<BodyContact> hoverTouching;

    std::deque<Profile> history;
    double simulateMs = 0, renderMs = 0, frameMs = 16;
    Clock::time_point lastFrame = Clock::now();

    static Impl& of(GLFWwindow* w) { return *static_cast<Impl*>(glfwGetWindowUserPointer(w)); }

    Camera camera() const {
        Camera c;
        c.target = target;
        c.eye = target + Vec3{std::cos(pitch) * std::sin(yaw), std::sin(pitch),
                              std::cos(pitch) * std::cos(yaw)} *
                             distance;
        c.fovYDegrees = fovY;
        return c;
    }

    void setCamera(const Camera& c) {
        target = c.target;
        const Vec3 offset = c.eye - c.target;
        distance = std::max(length(offset), 1e-3f);
        pitch = std::asin(std::clamp(offset.y / distance, -1.0f, 1.0f));
        yaw = std::atan2(offset.x, offset.z);
        fovY = c.fovYDegrees;
    }

    int windowWidth() const {
        int w = 0, h = 0;
        glfwGetWindowSize(window, &w, &h);
        return std::max(w, 1);
    }
    int windowHeight() const {
        int w = 0, h = 0;
        glfwGetWindowSize(window, &w, &h);
        return std::max(h, 1);
    }

    void frameCamera() {
        setCamera(
            frameWorld(*world, float(windowWidth()) / float(windowHeight()), settings.framing));
    }

    void newWorld() {
        world = std::make_unique<World>(makeWorld());
        steps = 0;
        history.clear();
        drag = drag == Drag::Body ? Drag::None : drag;
        draw.highlight = BodyId{};
        dragPin = PinId{}; // the old world's
    }

    // Grabs the body under window position (x, y).
    bool pick(double x, double y) {
        const Pick p =
            pickBody(*world, camera(), windowWidth(), windowHeight(), float(x), float(y));
        if (p.body.isNull()) return false;
        dragBody = p.body;
        dragParticle = p.particle;
        dragDepth = p.distance;
        dragTarget = p.point;
        draw.highlight = p.body;
        if (world->isValid(dragPin)) world->unpin(dragPin);
        // A hard pin, followed at 10 m/s at most: the body comes along as a whole.
        dragPin = dragPins ? world->pinPoint(p.body, p.point) : PinId{};
        return true;
    }

    // Ends a drag of a body: its pin goes.
    void releaseBody() {
        if (drag == Drag::Body) draw.highlight = BodyId{};
        if (world->isValid(dragPin)) world->unpin(dragPin);
        dragPin = PinId{};
    }

    // A spring-damper force on the grabbed particle towards the grab point. One particle carries
    // a small share of the body's mass, so an explicit spring on it is stable only while
    // K dt^2 / m stays small: K is a quarter of that bound (and at most 60/s^2 times the body's
    // mass, a firm pull). Damping acts on the body's velocity (critical for the whole body
    // hanging on the spring) and on the particle's own motion relative to it, so that neither
    // the body swings nor the particle jitters.
    void applyDragForce() {
        if (drag != Drag::Body || !world->isValid(dragBody)) return;
        if (world->isValid(dragPin)) {
            world->setPinTarget(dragPin, dragTarget);
            return;
        }
        const float particleMass = world->particleMass(dragBody, dragParticle);
        const float bodyMass = world->info(dragBody).mass;
        const float dt = world->settings().frameStep / float(world->settings().substeps);
        const float k = std::min(0.25f * particleMass / (dt * dt), kDragStiffness * bodyMass);
        const Vec3 x = world->particles(dragBody)[dragParticle];
        const Vec3 v = world->velocities(dragBody)[dragParticle];
        const Vec3 body = world->linearVelocity(dragBody);
        Vec3 f = (dragTarget - x) * k - body * (2 * std::sqrt(k * bodyMass)) -
                 (v - body) * (0.3f * particleMass / dt);
        const float len = length(f), most = kMaxDragAcceleration * bodyMass;
        if (len > most) f = f * (most / len);
        world->applyParticleForce(dragBody, dragParticle, f);
    }

    void handleInput(); // keys and mouse (viewer_ui.cpp)

    // The body under the cursor after the step, unless the cursor is over the controls or
    // outside the window.
    void updateHover() {
        hover = Pick{};
        if (!showHover || ImGui::GetIO().WantCaptureMouse ||
            !glfwGetWindowAttrib(window, GLFW_HOVERED))
            return;
        double x = 0, y = 0;
        glfwGetCursorPos(window, &x, &y);
        hover = pickBody(*world, camera(), windowWidth(), windowHeight(), float(x), float(y));
    }

    // The hovered triangle's edges and its normal at the point, yellow.
    void hoverLines() {
        if (hover.body.isNull() || !world->isValid(hover.body)) return;
        const auto v = world->vertices(hover.body);
        const auto t = world->triangles(hover.body)[hover.triangle];
        const Vec3 yellow{1.0f, 0.85f, 0.1f};
        for (int k = 0; k < 3; ++k) draw.lines.push_back({v[t[k]], v[t[(k + 1) % 3]], yellow});
        const float size = length(v[t[1]] - v[t[0]]) + length(v[t[2]] - v[t[0]]);
        draw.lines.push_back({hover.point, hover.point + hover.normal * size, yellow});
    }

    void stepWorld() {
        const auto start = Clock::now();
        for (int s = 0; s < std::max(settings.stepsPerFrame, 1); ++s) {
            applyDragForce();
            world->step();
            ++steps;
        }
        simulateMs = msSince(start);
        history.push_back(world->profile());
        if (history.size() > kHistory) history.pop_front();
    }

    void profilePlot(); // the stage timings plot (viewer_ui.cpp)
    void ui();          // the controls window (viewer_ui.cpp)

    bool screenshotToFile = false;

    void readWindow(Image& out) {
        int w = 0, h = 0;
        glfwGetFramebufferSize(window, &w, &h);
        out.width = w, out.height = h;
        out.pixels.resize(size_t(w) * size_t(h) * 4);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
        glReadBuffer(GL_BACK);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, out.pixels.data());
        const size_t row = size_t(w) * 4;
        std::vector<uint8_t> swap(row);
        for (int yy = 0; yy < h / 2; ++yy) {
            uint8_t* a = out.pixels.data() + size_t(yy) * row;
            uint8_t* b = out.pixels.data() + size_t(h - 1 - yy) * row;
            std::copy(a, a + row, swap.data());
            std::copy(b, b + row, a);
            std::copy(swap.data(), swap.data() + row, b);
        }
        // The window's alpha is whatever the UI blending left: a saved image is opaque.
        for (size_t i = 3; i < out.pixels.size(); i += 4) out.pixels[i] = 255;
    }

    bool frame() {
        glfwPollEvents();
        if (glfwWindowShouldClose(window)) return false;
        glfwMakeContextCurrent(window);
        const auto frameStart = Clock::now();
        frameMs = 0.9 * frameMs +
                  0.1 * std::chrono::duration<double, std::milli>(frameStart - lastFrame).count();
        lastFrame = frameStart;

        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        handleInput();
        if (restartRequested) {
            restartRequested = false;
            newWorld();
        }
        if (playing || stepRequested) stepWorld();
        stepRequested = false;
        updateHover();
        if (settings.showUi) ui();
        ImGui::Render();

        int fbw = 0, fbh = 0;
        glfwGetFramebufferSize(window, &fbw, &fbh);
        if (fbw > 0 && fbh > 0) {
            const auto start = Clock::now();
            draw.lines.clear();
            if (drag == Drag::Body && world->isValid(dragBody))
                draw.lines.push_back({world->isValid(dragPin)
                                          ? world->pin(dragPin).point
                                          : world->particles(dragBody)[dragParticle],
                                      dragTarget,
                                      {1, 1, 1}});
            hoverLines();
            renderer->draw(*world, camera(), draw, fbw, fbh);
            renderer->present(fbw, fbh);
            renderMs = msSince(start);
        }
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        if (captureRequested && fbw > 0 && fbh > 0) {
            readWindow(capture);
            captureRequested = false;
            if (screenshotToFile) {
                screenshotToFile = false;
                const std::string name = "ffdaabb-" + std::to_string(world->frame()) + ".png";
                try {
                    writePng(capture, name);
                    std::fprintf(stderr, "ffdaabb: saved %s\n", name.c_str());
                } catch (const InputError& e) {
                    std::fprintf(stderr, "ffdaabb: %s\n", e.what());
                }
            }
        }
        glfwSwapBuffers(window);
        if (settings.onFrame) settings.onFrame(frames, *world);
        ++frames;
        return true;
    }

    void shutdown() {
        if (window) glfwMakeContextCurrent(window);
        renderer.reset();
        if (imgui) {
            ImGui::SetCurrentContext(imgui);
            if (imguiGl) ImGui_ImplOpenGL3_Shutdown();
            if (imguiGlfw) ImGui_ImplGlfw_Shutdown();
            ImGui::DestroyContext(imgui);
            imgui = nullptr;
        }
        if (window) glfwDestroyWindow(window), window = nullptr;
        if (glfwAcquired) releaseGlfw(), glfwAcquired = false;
    }
};

} // namespace ffd::render
