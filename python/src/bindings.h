// Shared pieces of the Python module (python/src): conversions of the library's small value
// types, the World wrapper that owns the views' layout, and the parts each file binds.
#pragma once

#include "ffdaabb/math.h"
#include "ffdaabb/mesh.h"
#include "ffdaabb/world.h"
#include "runner.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <vector>

namespace py = pybind11;

// Vec3 from any sequence or array of 3 numbers; to a float32 array of shape (3,).
// Quat from 4 numbers (w, x, y, z); to a tuple of 4 floats.
namespace pybind11::detail {

bool loadFloats(handle src, float* out, ssize_t count);

template <>
struct type_caster<ffd::Vec3> {
    PYBIND11_TYPE_CASTER(ffd::Vec3, const_name("Vec3"));
    bool load(handle src, bool) {
        float f[3];
        if (!loadFloats(src, f, 3)) return false;
        value = {f[0], f[1], f[2]};
        return true;
    }
    static handle cast(const ffd::Vec3& v, return_value_policy, handle) {
        array_t<float> a(3);
        float* d = a.mutable_data();
        d[0] = v.x, d[1] = v.y, d[2] = v.z;
        return a.release();
    }
};

template <>
struct type_caster<ffd::Quat> {
    PYBIND11_TYPE_CASTER(ffd::Quat, const_name("Quat"));
    bool load(handle src, bool) {
        float f[4];
        if (!loadFloats(src, f, 4)) return false;
        value = {f[0], f[1], f[2], f[3]};
        return true;
    }
    static handle cast(const ffd::Quat& q, return_value_policy, handle) {
        return py::make_tuple(q.w, q.x, q.y, q.z).release();
    }
};

} // namespace pybind11::detail

namespace ffd::python {

/// The scene `scene` with World.from_scene's and run's overrides, errors naming those
/// arguments (the command line's own function, cli::sceneFromOptions).
Scene sceneFor(const std::string& scene, const cli::SceneOverrides& overrides);

/// The pure-Python support module (ffdaabb._support): View, Mesh and the result tuples.
py::module_ support();

/// A World and the layout its views belong to. A view (World.vertices and the like) is a NumPy
/// array of the world's memory whose base is the Python World (so the memory lives as long as
/// the view) and which belongs to the current layout; adding or removing bodies or restoring a
/// state ends the layout (relayout), after which its views raise StaleViewError.
struct PyWorld {
    World world;
    py::object layout;
    std::atomic<bool> stepping{false};

    explicit PyWorld(World&& w);
    /// Marks the world as stepping; throws RuntimeError (as checkIdle) if it already is.
    void beginStep();
    /// Ends the current layout (its views are detached) and starts a new one.
    void relayout();
    /// Throws RuntimeError while step() runs in another thread (a World takes one call at a time).
    void checkIdle() const;
};

/// A view of `count` rows of `T[3]` at `data`, owned by the Python World `owner`.
template <class T>
py::object view(py::handle owner, PyWorld& w, const T* data, size_t count);

/// The parts of the module, one file each.
void bindSettings(py::module_& m);
void bindWorld(py::module_& m);
void bindContent(py::module_& m);

/// `settings` with the fields named in `kw` set (each checked as its property checks it);
/// TypeError naming `function` for a name that is not a field.
template <class S>
S withKeywords(const S& settings, const py::kwargs& kw, const char* function) {
    if (kw.empty()) return settings;
    py::object o = py::cast(settings);
    const auto fields = py::type::of(o).attr("fields").cast<std::vector<std::string>>();
    for (const auto& [key, value] : kw) {
        const std::string k = py::str(key);
        if (std::find(fields.begin(), fields.end(), k) == fields.end())
            throw py::type_error(std::string(function) + "() got an unexpected keyword argument '" +
                                 k + "'");
        py::setattr(o, k.c_str(), value);
    }
    return o.cast<S>();
}

/// Raises ValueError (ffdaabb.InputError) naming `argument`.
[[noreturn]] void badArgument(const std::string& argument, const std::string& problem);

/// An (N, 3) array of float32 from any array-like; ValueError naming `argument` otherwise.
py::array_t<float, py::array::c_style | py::array::forcecast> rows3(py::handle source,
                                                                    const char* argument);

/// A mesh from a (V, 3) array of positions and a (T, 3) array of integer indices, each index
/// checked against V; ValueError naming `vertices` or `triangles` otherwise.
TriangleMesh meshFromArrays(const py::handle& vertices, const py::handle& triangles);

/// A path or a name given as str or os.PathLike (os.fspath); TypeError otherwise.
std::string pathText(const py::handle& path);

/// The rows of an (N, 3) float32 array as points.
std::vector<Vec3> points(const py::array_t<float, py::array::c_style | py::array::forcecast>& rows);

} // namespace ffd::python
