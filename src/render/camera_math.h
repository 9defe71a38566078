// The matrices of a public Camera, shared by the renderer, projectToPixel and the viewer.
#pragma once

#include "ffdaabb/render.h"
#include "render/mat4.h"

namespace ffd::render::detail {

/// Near and far clip distances: the camera's own when set (> 0), else from the eye-target
/// distance d: [d / 100, d * 40], which holds the floor out to where it fades away.
void clipPlanes(const Camera& camera, float& outNear, float& outFar);
Mat4 viewMatrix(const Camera& camera);
Mat4 projectionMatrix(const Camera& camera, float aspect);

} // namespace ffd::render::detail
