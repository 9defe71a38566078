// The interactive viewer: GLFW window, the shared Renderer for the scene, Dear ImGui (the
// GLFW and OpenGL3 back ends Debian's libimgui-dev ships) for the controls.
#include "ffdaabb/viewer.h"

#include "ffdaabb/error.h"
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
#include <mutex>
#include <numbers>
#include <string>
#include <vector>

namespace ffd::render {

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// GLFW is process-wide: initialised with the first viewer, terminated with the last.
std::mutex gGlfwMutex;
int gGlfwUsers = 0;
std::string gGlfwLastError;

void onGlfwError(int code, const char* description) {
    gGlfwLastError = std::to_string(code) + ": " + (description ? description : "");
}

void acquireGlfw() {
    std::lock_guard lock(gGlfwMutex);
    if (gGlfwUsers == 0) {
        glfwSetErrorCallback(onGlfwError);
        if (!glfwInit())
            throw RenderError("cannot open a window: GLFW found no display (" + gGlfwLastError +
                              "); on a machine without one, run under xvfb-run -a");
    }
    ++gGlfwUsers;
}

void releaseGlfw() {
    std::lock_guard lock(gGlfwMutex);
    if (--gGlfwUsers == 0) glfwTerminate();
}

/// The plot's colour of each Table 1 column (TableColumn order); a stage takes its column's.
const ImU32 kColumnColours[kTableColumnCount] = {
    IM_COL32(190, 110, 220, 255), // mesh updating
    IM_COL32(90, 150, 230, 255),  // min, max updating
    IM_COL32(240, 210, 40, 255),  // distance calculating
    IM_COL32(160, 160, 160, 255), // floor
    IM_COL32(80, 200, 110, 255),  // objects collision
    IM_COL32(230, 90, 70, 255),   // dynamics
};
const ImU32 kTotalColour = IM_COL32(255, 255, 255, 255);

constexpr size_t kHistory = 240;
constexpr float kDragStiffness = 60.0f;     // 1/s^2: pull per metre of offset, per kg of body
constexpr float kMaxDragAcceleration = 300; // m/s^2, so that a far cursor does not explode

} // namespace

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
    bool scriptedGrab = false;    // grab() rather than the mouse: the cursor does not move it
    std::vector<int> keys;        // pressed since the last frame
    std::vector<int> buttonsDown; // mouse buttons pressed since the last frame
    std::vector<int> buttonsUp;

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
        return true;
    }

    // A spring-damper force on the grabbed particle towards the grab point. One particle carries
    // a small share of the body's mass, so an explicit spring on it is stable only while
    // K dt^2 / m stays small: K is a quarter of that bound (and at most 60/s^2 times the body's
    // mass, a firm pull). Damping acts on the body's velocity (critical for the whole body
    // hanging on the spring) and on the particle's own motion relative to it, so that neither
    // the body swings nor the particle jitters.
    void applyDragForce() {
        if (drag != Drag::Body || !world->isValid(dragBody)) return;
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

    void handleInput() {
        const ImGuiIO& io = ImGui::GetIO();
        double x = 0, y = 0;
        glfwGetCursorPos(window, &x, &y);
        if (!io.WantCaptureKeyboard)
            for (int key : keys) {
                switch (key) {
                case GLFW_KEY_SPACE:
                    playing = !playing;
                    break;
                case GLFW_KEY_N:
                    stepRequested = true;
                    break;
                case GLFW_KEY_R:
                    restartRequested = true;
                    break;
                case GLFW_KEY_M:
                    world->setMode(world->settings().mode == CollisionMode::Enhanced
                                       ? CollisionMode::Previous
                                       : CollisionMode::Enhanced);
                    break;
                case GLFW_KEY_1:
                    draw.overlays.spheres = !draw.overlays.spheres;
                    break;
                case GLFW_KEY_2:
                    draw.overlays.boxes = !draw.overlays.boxes;
                    break;
                case GLFW_KEY_3:
                    draw.overlays.lattice = !draw.overlays.lattice;
                    break;
                case GLFW_KEY_4:
                    draw.overlays.contacts = !draw.overlays.contacts;
                    break;
                case GLFW_KEY_F:
                    frameCamera();
                    break;
                case GLFW_KEY_ESCAPE:
                    glfwSetWindowShouldClose(window, GLFW_TRUE);
                    break;
                default:
                    break;
                }
            }
        keys.clear();

        if (!io.WantCaptureMouse) {
            const bool shift = glfwGetKey(window, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ||
                               glfwGetKey(window, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
            for (int button : buttonsDown) {
                if (drag != Drag::None) continue;
                if (button == GLFW_MOUSE_BUTTON_MIDDLE || shift)
                    drag = Drag::Pan;
                else if (button == GLFW_MOUSE_BUTTON_LEFT && pick(x, y))
                    drag = Drag::Body, scriptedGrab = false;
                else
                    drag = Drag::Orbit;
                lastX = x, lastY = y;
            }
            if (scroll != 0) distance *= std::pow(0.88f, float(scroll));
            distance = std::clamp(distance, 1e-3f, 1e5f);
        }
        scroll = 0;
        buttonsDown.clear();
        bool released = false;
        for (int button : buttonsUp) {
            (void)button;
            released = true;
        }
        buttonsUp.clear();
        if (released && glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_LEFT) != GLFW_PRESS &&
            glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_RIGHT) != GLFW_PRESS &&
            glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_MIDDLE) != GLFW_PRESS) {
            if (drag == Drag::Body) draw.highlight = BodyId{};
            drag = Drag::None;
        }

        const float dx = float(x - lastX), dy = float(y - lastY);
        lastX = x, lastY = y;
        const Camera cam = camera();
        switch (drag) {
        case Drag::Orbit:
            yaw -= dx * 0.006f;
            pitch = std::clamp(pitch + dy * 0.006f, -1.55f, 1.55f);
            break;
        case Drag::Pan: {
            const detail::Mat4 v = detail::viewMatrix(cam);
            const Vec3 right{v.at(0, 0), v.at(0, 1), v.at(0, 2)};
            const Vec3 up{v.at(1, 0), v.at(1, 1), v.at(1, 2)};
            const float scale = 2 * distance *
                                std::tan(0.5f * fovY * std::numbers::pi_v<float> / 180) /
                                float(windowHeight());
            target = target - right * (dx * scale) + up * (dy * scale);
            break;
        }
        case Drag::Body: {
            if (!world->isValid(dragBody)) {
                drag = Drag::None;
                break;
            }
            if (scriptedGrab) break;
            Vec3 origin, dir;
            pixelRay(cam, windowWidth(), windowHeight(), float(x), float(y), origin, dir);
            dragTarget = origin + dir * dragDepth;
            break;
        }
        case Drag::None:
            break;
        }
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

    void profilePlot() {
        const ImVec2 size(ImGui::GetContentRegionAvail().x, 90);
        const ImVec2 p0 = ImGui::GetCursorScreenPos();
        ImGui::InvisibleButton("plot", size);
        ImDrawList* dl = ImGui::GetWindowDrawList();
        const ImVec2 p1(p0.x + size.x, p0.y + size.y);
        dl->AddRectFilled(p0, p1, IM_COL32(20, 20, 25, 200));
        double top = 1e-3;
        for (const Profile& p : history) top = std::max(top, p.total);
        top *= 1.1;
        std::vector<ImVec2> points;
        auto line = [&](auto&& ms, ImU32 colour) {
            points.clear();
            for (size_t i = 0; i < history.size(); ++i) {
                const float fx = float(i) / float(kHistory - 1);
                const float fy = float(ms(history[i]) / top);
                points.emplace_back(p0.x + fx * size.x, p1.y - fy * size.y);
            }
            if (points.size() >= 2)
                dl->AddPolyline(points.data(), int(points.size()), colour, 0, 1.5f);
        };
        for (const TableColumnInfo& c : tableColumns())
            line([&](const Profile& p) { return p.ms(c.column); },
                 kColumnColours[size_t(c.column)]);
        line([](const Profile& p) { return p.total; }, kTotalColour);
        char label[48];
        std::snprintf(label, sizeof label, "%.2f ms", top);
        dl->AddText(ImVec2(p0.x + 4, p0.y + 2), IM_COL32(220, 220, 220, 255), label);
    }

    void ui() {
        ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
        ImGui::SetNextWindowSize(ImVec2(340, 0), ImGuiCond_FirstUseEver);
        ImGui::Begin("ffdaabb");
        ImGui::Text("frame %llu   bodies %zu   %.0f fps", (unsigned long long)world->frame(),
                    world->bodyCount(), 1000.0 / std::max(frameMs, 1e-3));
        if (ImGui::Button(playing ? "Pause" : "Play")) playing = !playing;
        ImGui::SameLine();
        if (ImGui::Button("Step")) stepRequested = true;
        ImGui::SameLine();
        if (ImGui::Button("Restart")) restartRequested = true;
        if (settings.dropObjects) {
            ImGui::SameLine();
            if (ImGui::Button("Drop objects")) settings.dropObjects(*world);
        }
        static const char* kModes[] = {"enhanced", "previous", "brute", "none"};
        static const CollisionMode kModeValues[] = {CollisionMode::Enhanced,
                                                    CollisionMode::Previous, CollisionMode::Brute,
                                                    CollisionMode::None};
        int mode = 0;
        while (mode < 3 && kModeValues[mode] != world->settings().mode) ++mode;
        if (ImGui::Combo("collisions", &mode, kModes, 4)) world->setMode(kModeValues[mode]);
        ImGui::SliderInt("steps/frame", &settings.stepsPerFrame, 1, 8);

        ImGui::Checkbox("spheres", &draw.overlays.spheres);
        ImGui::SameLine();
        ImGui::Checkbox("boxes", &draw.overlays.boxes);
        ImGui::SameLine();
        ImGui::Checkbox("lattice", &draw.overlays.lattice);
        ImGui::SameLine();
        ImGui::Checkbox("contacts", &draw.overlays.contacts);
        ImGui::Checkbox("meshes", &draw.meshes);
        ImGui::SameLine();
        ImGui::Checkbox("floor", &draw.floor);
        ImGui::SameLine();
        ImGui::Checkbox("grid", &draw.grid);
        ImGui::SameLine();
        ImGui::Checkbox("shadows", &draw.shadows);

        if (ImGui::BeginTable("profile", 3, ImGuiTableFlags_Borders | ImGuiTableFlags_RowBg)) {
            ImGui::TableSetupColumn("stage");
            ImGui::TableSetupColumn("ms");
            ImGui::TableSetupColumn("mean ms");
            ImGui::TableHeadersRow();
            auto row = [&](const char* name, ImU32 colour, auto&& ms) {
                double mean = 0;
                for (const Profile& p : history) mean += ms(p);
                mean /= double(std::max<size_t>(history.size(), 1));
                ImGui::TableNextRow();
                ImGui::TableNextColumn();
                ImGui::TextColored(ImGui::ColorConvertU32ToFloat4(colour), "%s", name);
                ImGui::TableNextColumn();
                ImGui::Text("%.3f", history.empty() ? 0.0 : ms(history.back()));
                ImGui::TableNextColumn();
                ImGui::Text("%.3f", mean);
            };
            for (const StageInfo& s : stageTable())
                row(s.key, kColumnColours[size_t(s.column)],
                    [&](const Profile& p) { return p.ms(s.stage); });
            row("total", kTotalColour, [](const Profile& p) { return p.total; });
            ImGui::EndTable();
        }
        profilePlot();
        const Profile& p = world->profile();
        ImGui::Text("candidate pairs %d   potential pairs %d", p.candidatePairs, p.potentialPairs);
        ImGui::Text("contacts %d   floor contacts %d", p.contacts, p.floorContacts);
        if (p.overlapPairs > 0)
            ImGui::Text("placed overlapping %d   pushed apart whole %d", p.overlapPairs,
                        p.wholePairs);
        ImGui::Text("deepest contact %.2f mm", double(p.maxContactDepth) * 1000);
        ImGui::Text("step %.2f ms   draw %.2f ms", simulateMs, renderMs);
        if (ImGui::Button("Save screenshot")) captureRequested = true, screenshotToFile = true;
        if (ImGui::CollapsingHeader("Controls")) {
            ImGui::TextUnformatted("space play/pause   N step   R restart\n"
                                   "M enhanced/previous   1-4 overlays   F frame\n"
                                   "left-drag a body: pull it\n"
                                   "left/right-drag: orbit   middle or shift: pan\n"
                                   "wheel: zoom   Esc: quit");
        }
        ImGui::End();
    }

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
        if (settings.showUi) ui();
        ImGui::Render();

        int fbw = 0, fbh = 0;
        glfwGetFramebufferSize(window, &fbw, &fbh);
        if (fbw > 0 && fbh > 0) {
            const auto start = Clock::now();
            draw.lines.clear();
            if (drag == Drag::Body && world->isValid(dragBody))
                draw.lines.push_back(
                    {world->particles(dragBody)[dragParticle], dragTarget, {1, 1, 1}});
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

Viewer::Viewer(WorldFactory makeWorld, ViewerSettings settings) : impl_(std::make_unique<Impl>()) {
    Impl& v = *impl_;
    v.makeWorld = std::move(makeWorld);
    v.settings = std::move(settings);
    v.draw = v.settings.draw;
    v.playing = !v.settings.startPaused;
    if (v.settings.width < 64 || v.settings.height < 64)
        throw InputError("window size", std::to_string(v.settings.width) + " x " +
                                            std::to_string(v.settings.height) +
                                            " is below 64 x 64");
    if (!v.makeWorld) throw InputError("viewer", "no world factory given");
    try {
        acquireGlfw();
        v.glfwAcquired = true;
        glfwDefaultWindowHints();
        glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
        glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
#ifdef __APPLE__
        glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
#endif
        glfwWindowHint(GLFW_SAMPLES, 0); // the renderer multisamples in its own framebuffer
        v.window = glfwCreateWindow(v.settings.width, v.settings.height, v.settings.title.c_str(),
                                    nullptr, nullptr);
        if (!v.window)
            throw RenderError("cannot open a window with OpenGL 3.3 core (" + gGlfwLastError + ")");
        glfwMakeContextCurrent(v.window);
        detail::pinGlDrivers();
        glfwSwapInterval(v.settings.frames > 0 ? 0 : (v.settings.vsync ? 1 : 0));
        glfwSetWindowUserPointer(v.window, &v);
        // Installed before ImGui's back end, which chains to them.
        glfwSetKeyCallback(v.window, [](GLFWwindow* w, int key, int, int action, int) {
            if (action == GLFW_PRESS) Impl::of(w).keys.push_back(key);
        });
        glfwSetMouseButtonCallback(v.window, [](GLFWwindow* w, int button, int action, int) {
            if (action == GLFW_PRESS) Impl::of(w).buttonsDown.push_back(button);
            if (action == GLFW_RELEASE) Impl::of(w).buttonsUp.push_back(button);
        });
        glfwSetScrollCallback(v.window,
                              [](GLFWwindow* w, double, double dy) { Impl::of(w).scroll += dy; });

        v.renderer = std::make_unique<Renderer>();
        IMGUI_CHECKVERSION();
        v.imgui = ImGui::CreateContext();
        ImGui::SetCurrentContext(v.imgui);
        ImGui::GetIO().IniFilename = nullptr; // no imgui.ini left in the working folder
        ImGui::StyleColorsDark();
        v.imguiGlfw = ImGui_ImplGlfw_InitForOpenGL(v.window, true);
        v.imguiGl = ImGui_ImplOpenGL3_Init("#version 330 core");
        if (!v.imguiGlfw || !v.imguiGl) throw RenderError("Dear ImGui back ends failed to start");

        v.newWorld();
        if (v.draw.gridSpacing <= 0) v.draw.gridSpacing = autoGridSpacing(*v.world);
        if (v.settings.camera)
            v.setCamera(*v.settings.camera);
        else
            v.frameCamera();
    } catch (...) {
        v.shutdown();
        throw;
    }
}

Viewer::~Viewer() {
    impl_->shutdown();
}

bool Viewer::frame() {
    return impl_->frame();
}

ViewerResult Viewer::run() {
    Impl& v = *impl_;
    ViewerResult result;
    const int scripted = v.settings.frames;
    for (;;) {
        if (scripted > 0 && v.frames == scripted - 1) v.captureRequested = true;
        if (!v.frame()) {
            result.closedByUser = true;
            break;
        }
        if (scripted > 0 && v.frames >= scripted) break;
    }
    if (scripted > 0 && !v.settings.screenshot.empty() && !result.closedByUser)
        writePng(v.capture, v.settings.screenshot);
    result.frames = v.frames;
    result.steps = v.steps;
    result.stateHash = v.world->stateHash();
    return result;
}

void Viewer::captureNextFrame() {
    impl_->captureRequested = true;
}

const Image& Viewer::lastCapture() const {
    return impl_->capture;
}

World& Viewer::world() {
    return *impl_->world;
}

bool Viewer::playing() const {
    return impl_->playing;
}

void Viewer::setPlaying(bool playing) {
    impl_->playing = playing;
}

void Viewer::stepOnce() {
    impl_->stepRequested = true;
}

void Viewer::restart() {
    impl_->newWorld();
}

void Viewer::setMode(CollisionMode mode) {
    impl_->world->setMode(mode);
}

DrawOptions& Viewer::drawOptions() {
    return impl_->draw;
}

Camera Viewer::camera() const {
    return impl_->camera();
}

void Viewer::setCamera(const Camera& camera) {
    impl_->setCamera(camera);
}

void Viewer::windowSize(int& outWidth, int& outHeight) const {
    outWidth = impl_->windowWidth();
    outHeight = impl_->windowHeight();
}

bool Viewer::grab(float x, float y) {
    Impl& v = *impl_;
    if (!v.pick(x, y)) return false;
    v.drag = Impl::Drag::Body;
    v.scriptedGrab = true;
    return true;
}

void Viewer::moveGrab(float x, float y) {
    Impl& v = *impl_;
    if (v.drag != Impl::Drag::Body) return;
    Vec3 origin, dir;
    pixelRay(v.camera(), v.windowWidth(), v.windowHeight(), x, y, origin, dir);
    v.dragTarget = origin + dir * v.dragDepth;
}

void Viewer::release() {
    Impl& v = *impl_;
    if (v.drag == Impl::Drag::Body) v.drag = Impl::Drag::None, v.draw.highlight = BodyId{};
    v.scriptedGrab = false;
}

ViewerResult runViewer(const WorldFactory& makeWorld, const ViewerSettings& settings) {
    Viewer viewer(makeWorld, settings);
    return viewer.run();
}

} // namespace ffd::render
