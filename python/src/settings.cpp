// WorldSettings, BodySettings, LatticeSettings and PinSettings. Their numeric fields come from the
// library's one table of settings (ffd::worldSettingRanges, bodySettingRanges), under the scene
// files' keys, so that Python, the scene files and the command line name, accept and describe
// the same values; a value out of range raises InputError when it is set.
#include "bindings.h"

#include "ffdaabb/error.h"
#include "world/settings_table.h"

#include <charconv>
#include <functional>
#include <string>
#include <type_traits>
#include <vector>

namespace ffd::python {

namespace {

// A float setting as the shortest decimal that reads back as the same float (0.05, not
// 0.05000000074505806): what the user wrote, and what the scene files show.
py::object shortest(float value) {
    char text[32];
    const auto end = std::to_chars(text, text + sizeof text, value).ptr;
    return py::float_(std::stod(std::string(text, end)));
}

template <class T>
py::object toPython(const T& value) {
    if constexpr (std::is_same_v<T, float>)
        return shortest(value);
    else
        return py::cast(value);
}

// A settings class with a keyword constructor, a repr listing its fields and equality by them.
template <class S>
struct SettingsClass {
    py::class_<S> cls;
    std::vector<std::string> fields;

    SettingsClass(py::module_& m, const char* name, const char* doc) : cls(m, name, doc) {}

    template <class Get, class Set>
    void field(const std::string& key, Get get, Set set, const std::string& doc) {
        cls.def_property(key.c_str(), get, set, doc.c_str());
        fields.push_back(key);
    }

    void finish(const char* name) {
        const std::string className = name;
        const std::vector<std::string> names = fields;
        cls.def_property_readonly_static(
            "fields", [names](py::handle) { return names; }, "The fields' names, in order.");
        cls.def(py::init([className](const py::kwargs& kw) {
                    return withKeywords(S{}, kw, className.c_str());
                }),
                ("Default settings, with any field given by keyword: " + className + "(" +
                 names.front() + "=...)")
                    .c_str());
        cls.def("__repr__", [className, names](const py::object& self) {
            std::string out = className + "(";
            for (size_t i = 0; i < names.size(); ++i)
                out += (i ? ", " : "") + names[i] + "=" +
                       std::string(py::repr(self.attr(names[i].c_str())));
            return out + ")";
        });
        cls.def("__eq__", [names](const py::object& a, const py::object& b) {
            if (!py::type::of(a).is(py::type::of(b))) return false;
            const py::object equal = py::module_::import("numpy").attr("array_equal");
            for (const std::string& n : names) {
                if (!equal(a.attr(n.c_str()), b.attr(n.c_str())).cast<bool>()) return false;
            }
            return true;
        });
        cls.attr("__hash__") = py::none();
        cls.def(
            "copy", [](const S& s) { return s; }, "A copy.");
        cls.def("__copy__", [](const S& s) { return s; });
        cls.def("__deepcopy__", [](const S& s, py::handle) { return s; });
    }
};

// The numeric fields of the table, each checked by validate(S) when set.
template <class S>
void numericFields(SettingsClass<S>& c, std::span<const SettingRange> ranges,
                   std::span<const detail::SettingMember<S>> members) {
    for (size_t i = 0; i < ranges.size(); ++i) {
        const SettingRange& r = ranges[i];
        const detail::SettingMember<S> member = members[i];
        std::string doc = std::string(r.doc) + " [" + r.expected + "]";
        if (*r.unit) doc += " (" + std::string(r.unit) + ")";
        c.field(
            r.key,
            [member](const S& s) -> py::object {
                return std::visit([&](auto m) -> py::object { return toPython(s.*m); }, member);
            },
            [member](S& s, const py::object& value) {
                S changed = s;
                std::visit(
                    [&](auto m) {
                        using T = std::remove_reference_t<decltype(changed.*m)>;
                        changed.*m = value.cast<T>();
                    },
                    member);
                validate(changed);
                s = changed;
            },
            doc);
    }
}

// A string-valued enum field: `parse` accepts the names `toString` gives.
template <class S, class E>
void enumField(SettingsClass<S>& c, const char* key, E S::*member,
               bool (*parse)(std::string_view, E&), const char* expected, const std::string& doc) {
    c.field(
        key, [member](const S& s) { return std::string(toString(s.*member)); },
        [member, parse, key, expected](S& s, const std::string& value) {
            E e;
            if (!parse(value, e))
                throw InputError(key,
                                 "unknown value \"" + value + "\" (expected " + expected + ")");
            s.*member = e;
        },
        doc + " (" + expected + ")");
}

template <class S, class T>
void plainField(SettingsClass<S>& c, const char* key, T S::*member, const std::string& doc) {
    c.field(
        key, [member](const S& s) { return toPython(s.*member); },
        [member](S& s, const T& value) { s.*member = value; }, doc);
}

} // namespace

void bindSettings(py::module_& m) {
    SettingsClass<LatticeSettings> lattice(
        m, "LatticeSettings",
        "How a body's FFD lattice is made (a scene's \"lattice\"): cell_size, else resolution, "
        "else about `cells` cells.");
    plainField(lattice, "cells", &LatticeSettings::targetCells,
               "about this many cells, when cell_size and resolution are 0");
    plainField(lattice, "cell_size", &LatticeSettings::cellSize,
               "explicit cell size, metres (> 0 to use it)");
    plainField(lattice, "resolution", &LatticeSettings::resolution,
               "> 0: cell size = longest bounding-box extent / resolution");
    plainField(lattice, "fill_interior", &LatticeSettings::fillInterior,
               "add the cells enclosed by the surface");
    plainField(lattice, "box_skin", &LatticeSettings::boxSkin,
               "cell boxes inflated by box_skin x cell size on every side");
    lattice.finish("LatticeSettings");

    SettingsClass<WorldSettings> world(
        m, "WorldSettings",
        "World-wide settings (a scene's \"world\"). Vectors are set whole: s.gravity = (0, -5, "
        "0).");
    numericFields(world, worldSettingRanges(), detail::worldSettingMembers());
    plainField(world, "gravity", &WorldSettings::gravity, "m/s^2");
    plainField(world, "floor", &WorldSettings::floor, "an infinite plane y = floor_height");
    enumField(world, "mode", &WorldSettings::mode, &parseCollisionMode,
              "enhanced, previous, brute or none", "the collision pipeline between objects");
    plainField(world, "mesh_update", &WorldSettings::meshUpdate,
               "update the embedded mesh vertices at the end of each frame");
    world.finish("WorldSettings");

    SettingsClass<BodySettings> body(
        m, "BodySettings",
        "How a body is made and what it is made of (a scene's \"lattice\", \"material\", "
        "\"motion\"), and where it starts.");
    numericFields(body, bodySettingRanges(), detail::bodySettingMembers());
    body.cls.def_readwrite("lattice", &BodySettings::lattice,
                           "LatticeSettings (changed in place: s.lattice.cells = 20)");
    body.fields.push_back("lattice");
    enumField(body, "model", &BodySettings::model, &parseDynamicsModel,
              "shape-matching or mass-spring", "the lattice dynamics");
    plainField(body, "region_damping", &BodySettings::regionDamping,
               "shape matching: damp relative to each region's rigid motion");
    plainField(body, "allow_sleep", &BodySettings::allowSleep,
               "may fall asleep when it and its neighbours are at rest");
    enumField(body, "motion", &BodySettings::motion, &parseBodyMotion,
              "dynamic, static or kinematic", "how the body moves (colliders)");
    plainField(body, "position", &BodySettings::position, "the mesh's origin is placed here, m");
    plainField(
        body, "rotation", &BodySettings::rotation,
        "the mesh rotated about it: a quaternion (w, x, y, z), normalised when the body is made");
    plainField(body, "velocity", &BodySettings::velocity, "initial velocity, m/s");
    plainField(body, "angular_velocity", &BodySettings::angularVelocity,
               "initial angular velocity about the centre of mass, rad/s");
    body.finish("BodySettings");

    SettingsClass<PinSettings> pin(m, "PinSettings",
                                   "How a pin holds its point (a scene's \"pins\" entries).");
    auto pinField = [&](const char* key, float PinSettings::*member, const char* doc) {
        pin.field(
            key, [member](const PinSettings& s) { return shortest(s.*member); },
            [member](PinSettings& s, float value) {
                PinSettings changed = s;
                changed.*member = value;
                validate(changed);
                s = changed;
            },
            doc);
    };
    pinField("stiffness", &PinSettings::stiffness, "N/m; 0: hard");
    pinField("rigidity", &PinSettings::rigidity,
             "share of each correction made through the body's rigid motion, [0, 1]");
    pinField("swing_damping", &PinSettings::swingDamping,
             "rate (1/s) at which motion about the target is damped");
    pinField("max_speed", &PinSettings::maxSpeed, "m/s the pin follows its target at most; 0: any");
    pin.finish("PinSettings");
}

} // namespace ffd::python
