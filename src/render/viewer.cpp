// The interactive viewer: GLFW window, the shared Renderer for the scene, Dear ImGui (the
// GLFW and OpenGL3 back ends Debian's libimgui-dev ships) for the controls. Input and the
// controls window: viewer_ui.cpp; the state both share: viewer_impl.h.
#include "render/viewer_impl.h"

#include <mutex>

namespace ffd::render {

namespace {

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

} // namespace

void releaseGlfw() {
    std::lock_guard lock(gGlfwMutex);
    if (--gGlfwUsers == 0) glfwTerminate();
}

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
    v.releaseBody();
    if (v.drag == Impl::Drag::Body) v.drag = Impl::Drag::None;
    v.scriptedGrab = false;
}

ViewerResult runViewer(const WorldFactory& makeWorld, const ViewerSettings& settings) {
    Viewer viewer(makeWorld, settings);
    return viewer.run();
}

} // namespace ffd::render
