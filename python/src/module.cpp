// The Python module ffdaabb._ffdaabb: errors, views, the data folders and `run`; the settings,
// the World and the content (generators, mesh files, scenes) are bound in their own files.
#include "bindings.h"

#include "ffdaabb/data.h"
#include "ffdaabb/error.h"
#include "runner.h"

#include <string>

namespace pybind11::detail {

bool loadFloats(handle src, float* out, ssize_t count) {
    if (!src || src.is_none() || isinstance<str>(src) || isinstance<bytes>(src)) return false;
    if (!isinstance<array>(src) && !PySequence_Check(src.ptr())) return false;
    auto a = array_t<double, array::forcecast>::ensure(src);
    if (!a) {
        PyErr_Clear();
        return false;
    }
    if (a.ndim() != 1 || a.shape(0) != count) return false;
    for (ssize_t i = 0; i < count; ++i) out[i] = float(a.at(i));
    return true;
}

} // namespace pybind11::detail

namespace ffd::python {

namespace {

// The InputError class: a reference kept for the process's life (never released, so that
// nothing is freed after the interpreter has finalised).
PyObject* inputErrorType = nullptr;

// Shrinks a view's shape to empty (its layout ended): a read through any path gets nothing.
void detach(py::handle array) {
    auto* proxy = py::detail::array_proxy(array.ptr());
    for (int i = 0; i < proxy->nd; ++i) proxy->dimensions[i] = 0;
}

} // namespace

py::module_ support() {
    // Kept for the process's life, like every module object (see inputErrorType).
    static PyObject* module = py::module_::import("ffdaabb._support").release().ptr();
    return py::reinterpret_borrow<py::module_>(module);
}

void badArgument(const std::string& argument, const std::string& problem) {
    throw InputError(argument, problem);
}

py::array_t<float, py::array::c_style | py::array::forcecast> rows3(py::handle source,
                                                                    const char* argument) {
    using Rows = py::array_t<float, py::array::c_style | py::array::forcecast>;
    Rows a;
    try {
        a = py::cast<Rows>(source);
    } catch (const py::cast_error&) {
        badArgument(argument, "expected an array of shape (N, 3) of numbers, got " +
                                  std::string(py::str(py::type::of(source).attr("__name__"))));
    } catch (const py::error_already_set& e) {
        badArgument(argument,
                    "expected an array of shape (N, 3) of numbers: " + std::string(e.what()));
    }
    if (a.ndim() != 2 || a.shape(1) != 3) {
        std::string shape = "(";
        for (ssize_t i = 0; i < a.ndim(); ++i)
            shape += (i ? ", " : "") + std::to_string(a.shape(i));
        badArgument(argument, "expected an array of shape (N, 3), got shape " + shape +
                                  (a.ndim() == 1 ? ",)" : ")"));
    }
    return a;
}

std::vector<Vec3>
points(const py::array_t<float, py::array::c_style | py::array::forcecast>& rows) {
    std::vector<Vec3> out(size_t(rows.shape(0)));
    const float* d = rows.data();
    for (size_t i = 0; i < out.size(); ++i) out[i] = {d[3 * i], d[3 * i + 1], d[3 * i + 2]};
    return out;
}

std::string pathText(const py::handle& path) {
    return py::str(py::module_::import("os").attr("fspath")(path));
}

TriangleMesh meshFromArrays(const py::handle& vertices, const py::handle& triangles) {
    TriangleMesh mesh;
    mesh.positions = points(rows3(vertices, "vertices"));
    using Indices = py::array_t<int64_t, py::array::c_style | py::array::forcecast>;
    Indices t;
    try {
        t = py::cast<Indices>(triangles);
    } catch (const py::cast_error&) {
        badArgument("triangles", "expected an integer array of shape (T, 3)");
    }
    if (t.ndim() != 2 || t.shape(1) != 3)
        badArgument("triangles", "expected an integer array of shape (T, 3)");
    if (py::isinstance<py::array>(triangles)) {
        const char kind = py::cast<py::array>(triangles).dtype().kind();
        if (kind != 'i' && kind != 'u')
            badArgument("triangles",
                        std::string("expected integers, got an array of kind '") + kind + "'");
    }
    mesh.triangles.resize(size_t(t.shape(0)));
    const int64_t* d = t.data();
    for (size_t i = 0; i < mesh.triangles.size() * 3; ++i) {
        if (d[i] < 0 || d[i] >= int64_t(mesh.positions.size()))
            badArgument("triangles", "index " + std::to_string(d[i]) + " at triangle " +
                                         std::to_string(i / 3) + " is out of range (expected 0.." +
                                         std::to_string(mesh.positions.size() - 1) + ")");
        mesh.triangles[i / 3][i % 3] = uint32_t(d[i]);
    }
    mesh.name = "array";
    return mesh;
}

PyWorld::PyWorld(World&& w) : world(std::move(w)), layout(support().attr("_Layout")()) {}

void PyWorld::relayout() {
    static PyObject* detachFn = py::cpp_function(&detach).release().ptr(); // kept, as above
    layout.attr("invalidate")(py::handle(detachFn));
    layout = support().attr("_Layout")();
}

namespace {

[[noreturn]] void refuseWhileStepping() {
    throw std::runtime_error("World: step() is running in another thread; a World takes one "
                             "call at a time");
}

} // namespace

void PyWorld::checkIdle() const {
    if (stepping.load()) refuseWhileStepping();
}

void PyWorld::beginStep() {
    bool expected = false;
    if (!stepping.compare_exchange_strong(expected, true)) refuseWhileStepping();
}

Scene sceneFor(const std::string& scene, const cli::SceneOverrides& overrides) {
    return cli::sceneFromOptions(scene, overrides, {"objects", "mode", "threads", "seed"});
}

template <class T>
py::object view(py::handle owner, PyWorld& w, const T* data, size_t count) {
    const std::vector<ssize_t> shape{ssize_t(count), 3}, strides{ssize_t(3 * sizeof(T)), sizeof(T)};
    py::array array;
    if (count == 0)
        array = py::array(py::dtype::of<T>(), shape, strides);
    else
        array = py::array(py::dtype::of<T>(), shape, strides, data, owner);
    py::detail::array_proxy(array.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
    return support().attr("_make_view")(array, w.layout);
}

template py::object view<float>(py::handle, PyWorld&, const float*, size_t);
template py::object view<uint32_t>(py::handle, PyWorld&, const uint32_t*, size_t);

namespace {

py::dict jsonToPython(const nlohmann::json& j) {
    return py::module_::import("json").attr("loads")(j.dump());
}

py::dict run(const py::object& sceneName, int frames, int warmup, std::optional<int> objects,
             std::optional<long long> seed, std::optional<std::string> mode,
             std::optional<int> threads, int measureEvery) {
    if (frames < 1)
        badArgument("frames",
                    "value " + std::to_string(frames) + " is out of range (expected >= 1)");
    if (warmup < 0)
        badArgument("warmup",
                    "value " + std::to_string(warmup) + " is out of range (expected >= 0)");
    if (measureEvery < 0)
        badArgument("measure_every",
                    "value " + std::to_string(measureEvery) + " is out of range (expected >= 0)");
    cli::SceneOverrides o{objects, mode, threads, seed};
    const std::string scene = pathText(sceneName);
    nlohmann::json stats;
    {
        py::gil_scoped_release released;
        const Scene s = sceneFor(scene, o);
        cli::RunOptions ro;
        ro.frames = frames;
        ro.warmup = warmup;
        ro.measureEvery = measureEvery;
        stats = cli::statsJson(cli::runScene(s, ro));
    }
    return jsonToPython(stats);
}

} // namespace

} // namespace ffd::python

PYBIND11_MODULE(_ffdaabb, m) {
    using namespace ffd;
    using namespace ffd::python;
    m.doc() = "ffdaabb: real-time deformable objects (FFD lattices, shape matching, Enhanced "
              "FFD-AABB collisions). The module's API is documented in ffdaabb/__init__.py.";
    m.attr("__version__") = FFD_VERSION;

    // InputError: the library's errors for bad input, a ValueError whose message is the one the
    // command line prints after "ffdaabb: error: ".
    inputErrorType = PyErr_NewExceptionWithDoc(
        "ffdaabb.InputError",
        "Bad input (a file, a field, a setting, an argument): a ValueError whose message names "
        "the source first, as the command line's. Attributes: source, problem.",
        PyExc_ValueError, nullptr);
    if (!inputErrorType) throw py::error_already_set();
    m.attr("InputError") = py::handle(inputErrorType);
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const InputError& e) {
            py::object error = py::handle(inputErrorType)(e.what());
            error.attr("source") = e.source();
            error.attr("problem") = e.problem();
            PyErr_SetObject(inputErrorType, error.ptr());
        }
    });

    m.def("_detach", &detach, "Empties a view's shape (used when its layout ends).");
    m.def(
        "add_data_folder", [](const py::object& folder) { addDataFolder(pathText(folder)); },
        py::arg("folder"),
        "Searches this folder first for scenes (scenes/NAME.json) and models (models/), after "
        "folders added before.");
    m.def(
        "data_folders",
        [] {
            std::vector<std::string> out;
            for (const auto& f : dataFolders()) out.push_back(f.string());
            return out;
        },
        "The data folders, in the order they are searched.");

    bindSettings(m);
    bindWorld(m);
    bindContent(m);

    m.def("run", &run, py::arg("scene"), py::kw_only(), py::arg("frames") = 300,
          py::arg("warmup") = 0, py::arg("objects") = py::none(), py::arg("seed") = py::none(),
          py::arg("mode") = py::none(), py::arg("threads") = py::none(),
          py::arg("measure_every") = 10,
          "Runs a scene as `ffdaabb run --stats` does and returns the same statistics (a dict "
          "with the same keys: stage_ms, table1_ms, frames_per_second, contacts, "
          "interpenetration, state_hash, ...). Releases the GIL while it runs.");
}
