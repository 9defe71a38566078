// The renderer's GLSL 3.30 shaders (renderer.cpp): lit meshes, planar shadows, the floor's
// procedural grid, overlay lines, and FXAA for single-sampled targets.
#pragma once

namespace ffd::render::shaders {

inline constexpr const char* kMeshVertex = R"(#version 330 core
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
uniform mat4 uViewProjection;
out vec3 vPosition;
out vec3 vNormal;
void main() {
    vPosition = aPosition;
    vNormal = aNormal;
    gl_Position = uViewProjection * vec4(aPosition, 1.0);
}
)";

inline constexpr const char* kMeshFragment = R"(#version 330 core
in vec3 vPosition;
in vec3 vNormal;
uniform vec3 uColour;
uniform vec3 uEye;
uniform vec3 uToLight;
out vec4 outColour;
void main() {
    float len = length(vNormal);
    vec3 n = len > 1e-8 ? vNormal / len : normalize(cross(dFdx(vPosition), dFdy(vPosition)));
    if (!gl_FrontFacing) n = -n; // the inside of an open mesh
    vec3 base = pow(uColour, vec3(2.2));
    vec3 v = normalize(uEye - vPosition);
    float key = max(dot(n, uToLight), 0.0);
    float fill = max(dot(n, normalize(vec3(-uToLight.x, 0.4, -uToLight.z))), 0.0);
    float ambient = 0.16 + 0.08 * n.y;
    float spec = key > 0.0 ? 0.22 * pow(max(dot(n, normalize(uToLight + v)), 0.0), 64.0) : 0.0;
    vec3 c = base * (ambient + 0.85 * key + 0.22 * fill) + vec3(spec);
    outColour = vec4(pow(clamp(c, 0.0, 1.0), vec3(1.0 / 2.2)), 1.0);
}
)";

inline constexpr const char* kShadowVertex = R"(#version 330 core
layout(location = 0) in vec3 aPosition;
uniform mat4 uViewProjection;
uniform mat4 uShadow;
out vec3 vPosition;
void main() {
    vec4 p = uShadow * vec4(aPosition, 1.0);
    vPosition = p.xyz;
    gl_Position = uViewProjection * p;
}
)";

inline constexpr const char* kShadowFragment = R"(#version 330 core
in vec3 vPosition;
uniform vec3 uEye;
uniform vec2 uFade;
uniform float uAlpha;
out vec4 outColour;
void main() {
    float fade = smoothstep(uFade.x, uFade.y, distance(vPosition, uEye));
    outColour = vec4(0.0, 0.0, 0.0, uAlpha * (1.0 - fade));
}
)";

inline constexpr const char* kFloorVertex = R"(#version 330 core
layout(location = 0) in vec3 aPosition;
uniform mat4 uViewProjection;
out vec3 vPosition;
void main() {
    vPosition = aPosition;
    gl_Position = uViewProjection * vec4(aPosition, 1.0);
}
)";

inline constexpr const char* kFloorFragment = R"(#version 330 core
in vec3 vPosition;
uniform vec3 uEye;
uniform vec2 uFade;
uniform vec3 uFloorColour;
uniform vec3 uLineColour;
uniform vec3 uBackground;
uniform float uSpacing;
uniform int uGrid;
out vec4 outColour;
float gridLines(vec2 c) {
    vec2 w = fwidth(c);
    vec2 g = abs(fract(c - 0.5) - 0.5) / max(w, vec2(1e-6));
    float line = 1.0 - min(min(g.x, g.y), 1.0);
    // Lines closer than a few pixels apart turn into moire: fade them out instead.
    return line * (1.0 - smoothstep(0.15, 0.4, max(w.x, w.y)));
}
void main() {
    vec3 c = uFloorColour;
    if (uGrid != 0) {
        float minor = gridLines(vPosition.xz / uSpacing);
        float major = gridLines(vPosition.xz / (10.0 * uSpacing));
        c = mix(c, uLineColour, max(0.45 * minor, 0.8 * major));
    }
    float fade = smoothstep(uFade.x, uFade.y, distance(vPosition, uEye));
    outColour = vec4(mix(c, uBackground, fade), 1.0);
}
)";

inline constexpr const char* kLineVertex = R"(#version 330 core
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aColour;
uniform mat4 uViewProjection;
out vec3 vColour;
void main() {
    vColour = aColour;
    gl_Position = uViewProjection * vec4(aPosition, 1.0);
}
)";

inline constexpr const char* kLineFragment = R"(#version 330 core
in vec3 vColour;
uniform float uAlpha;
out vec4 outColour;
void main() {
    outColour = vec4(vColour, uAlpha);
}
)";

// A full-screen triangle from gl_VertexID: no vertex buffer needed.
inline constexpr const char* kFullscreenVertex = R"(#version 330 core
void main() {
    vec2 p = vec2(float((gl_VertexID & 1) << 2) - 1.0, float((gl_VertexID & 2) << 1) - 1.0);
    gl_Position = vec4(p, 0.0, 1.0);
}
)";

// FXAA in its compact form (Lottes 2009; the widely used "FXAA 2" variant): an edge direction
// from the luma of the four diagonal neighbours, two or four samples along it, and the wider
// blend unless it leaves the local luma range. A pixel whose neighbours all equal it is
// returned unchanged, so flat areas stay exact.
inline constexpr const char* kFxaaFragment = R"(#version 330 core
uniform sampler2D uImage;
uniform vec2 uTexel;
out vec4 outColour;
void main() {
    vec2 uv = gl_FragCoord.xy * uTexel;
    vec3 nw = texture(uImage, uv + vec2(-1.0, -1.0) * uTexel).rgb;
    vec3 ne = texture(uImage, uv + vec2(1.0, -1.0) * uTexel).rgb;
    vec3 sw = texture(uImage, uv + vec2(-1.0, 1.0) * uTexel).rgb;
    vec3 se = texture(uImage, uv + vec2(1.0, 1.0) * uTexel).rgb;
    vec3 m = texture(uImage, uv).rgb;
    const vec3 toLuma = vec3(0.299, 0.587, 0.114);
    float lNW = dot(nw, toLuma), lNE = dot(ne, toLuma), lSW = dot(sw, toLuma);
    float lSE = dot(se, toLuma), lM = dot(m, toLuma);
    float lMin = min(lM, min(min(lNW, lNE), min(lSW, lSE)));
    float lMax = max(lM, max(max(lNW, lNE), max(lSW, lSE)));
    vec2 dir = vec2(-((lNW + lNE) - (lSW + lSE)), (lNW + lSW) - (lNE + lSE));
    float reduce = max((lNW + lNE + lSW + lSE) * (0.25 / 8.0), 1.0 / 128.0);
    float scale = 1.0 / (min(abs(dir.x), abs(dir.y)) + reduce);
    dir = clamp(dir * scale, vec2(-8.0), vec2(8.0)) * uTexel;
    vec3 a = 0.5 * (texture(uImage, uv + dir * (1.0 / 3.0 - 0.5)).rgb +
                    texture(uImage, uv + dir * (2.0 / 3.0 - 0.5)).rgb);
    vec3 b = a * 0.5 + 0.25 * (texture(uImage, uv - dir * 0.5).rgb +
                               texture(uImage, uv + dir * 0.5).rgb);
    float lB = dot(b, toLuma);
    outColour = vec4((lB < lMin || lB > lMax) ? a : b, 1.0);
}
)";

} // namespace ffd::render::shaders
