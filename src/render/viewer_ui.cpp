// The viewer's input (keys, orbiting, panning, dragging bodies) and its controls window.
#include "render/viewer_impl.h"

namespace ffd::render {

void Viewer::Impl::handleInput() {
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
            case GLFW_KEY_5:
                draw.overlays.sleeping = !draw.overlays.sleeping;
                break;
            case GLFW_KEY_F:
                frameCamera();
                break;
            case GLFW_KEY_P:
                dragPins = !dragPins;
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
        releaseBody();
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
        const float scale = 2 * distance * std::tan(0.5f * fovY * std::numbers::pi_v<float> / 180) /
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

void Viewer::Impl::profilePlot() {
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
        if (points.size() >= 2) dl->AddPolyline(points.data(), int(points.size()), colour, 0, 1.5f);
    };
    for (const TableColumnInfo& c : tableColumns())
        line([&](const Profile& p) { return p.ms(c.column); }, kColumnColours[size_t(c.column)]);
    line([](const Profile& p) { return p.total; }, kTotalColour);
    char label[48];
    std::snprintf(label, sizeof label, "%.2f ms", top);
    dl->AddText(ImVec2(p0.x + 4, p0.y + 2), IM_COL32(220, 220, 220, 255), label);
}

void Viewer::Impl::ui() {
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
    static const CollisionMode kModeValues[] = {CollisionMode::Enhanced, CollisionMode::Previous,
                                                CollisionMode::Brute, CollisionMode::None};
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
    ImGui::SameLine();
    ImGui::Checkbox("sleeping", &draw.overlays.sleeping);
    ImGui::Checkbox("drag pins (P)", &dragPins);
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
    ImGui::Text("candidate pairs %d   node/box pairs %d   box pairs %d (%d with contacts)",
                p.candidatePairs, p.potentialPairs, p.boxPairs, p.contactBoxPairs);
    ImGui::Text("contacts %d   floor contacts %d", p.contacts, p.floorContacts);
    if (p.overlapPairs > 0)
        ImGui::Text("placed overlapping %d   pushed apart whole %d", p.overlapPairs, p.wholePairs);
    ImGui::Text("deepest contact %.2f mm", double(p.maxContactDepth) * 1000);
    ImGui::Text("step %.2f ms   draw %.2f ms", simulateMs, renderMs);
    ImGui::Checkbox("under the cursor", &showHover);
    if (showHover && !hover.body.isNull() && world->isValid(hover.body)) {
        // ffd::raycast's hit, and the body's contacts of the last step (ffdaabb/queries.h),
        // each as its mean force over the step.
        ImGui::Text("body %u   triangle %u   %.2f m away", hover.body.index, hover.triangle,
                    double(hover.distance));
        touchingBodies(*world, hover.body, hoverTouching);
        const double step = world->settings().frameStep;
        ImGui::Text("touches %zu in the last step%s", hoverTouching.size(),
                    hoverTouching.empty() ? "" : ":");
        for (size_t i = 0; i < hoverTouching.size() && i < 6; ++i) {
            const BodyContact& c = hoverTouching[i];
            if (c.other.isNull())
                ImGui::Text("  floor      %8.1f N", double(c.normalImpulse) / step);
            else
                ImGui::Text("  body %-5u %8.1f N", c.other.index, double(c.normalImpulse) / step);
        }
        if (hoverTouching.size() > 6) ImGui::Text("  ... %zu more", hoverTouching.size() - 6);
    }
    if (ImGui::Button("Save screenshot")) captureRequested = true, screenshotToFile = true;
    if (ImGui::CollapsingHeader("Controls")) {
        ImGui::TextUnformatted("space play/pause   N step   R restart\n"
                               "M enhanced/previous   1-4 overlays   F frame\n"
                               "left-drag a body: pin it and move the pin\n"
                               "  (P: pull it by a spring instead)\n"
                               "left/right-drag: orbit   middle or shift: pan\n"
                               "wheel: zoom   Esc: quit");
    }
    ImGui::End();
}

} // namespace ffd::render
