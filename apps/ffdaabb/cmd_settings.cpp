// ffdaabb settings: the numeric settings of worlds and bodies, from the library's one table
// (ffd::worldSettingRanges, ffd::bodySettingRanges): scene key, C++ member, default, range,
// unit and what each sets. `--markdown` prints the table docs/LIMITS.md carries.
#include "commands.h"
#include "ffdaabb/world.h"

#include <fmt/core.h>

#include <memory>
#include <span>
#include <string>

namespace ffd::cli {

namespace {

struct SettingsOptions {
    bool markdown = false;
};

// A table cell's text: '|' would end the cell.
std::string cell(const char* text) {
    std::string out;
    for (const char* c = text; *c; ++c) out += *c == '|' ? std::string("\\|") : std::string(1, *c);
    return out;
}

int printSettings(const SettingsOptions& o) {
    const struct {
        const char* group; // the scene file's object
        const char* type;  // the C++ struct
        std::span<const SettingRange> table;
    } groups[] = {{"world", "WorldSettings", worldSettingRanges()},
                  {"material", "BodySettings", bodySettingRanges()}};
    if (o.markdown) {
        fmt::print("| scene key | C++ member | default | range | unit | what it sets |\n");
        fmt::print("|---|---|---|---|---|---|\n");
    }
    for (const auto& g : groups) {
        if (!o.markdown) fmt::print("{} ({}):\n", g.group, g.type);
        for (const SettingRange& r : g.table) {
            const std::string value = fmt::format("{:g}", settingDefault(r));
            if (o.markdown)
                fmt::print("| `{}.{}` | `{}` | {} | {} | {} | {} |\n", g.group, r.key, r.field,
                           value, cell(r.expected), *r.unit ? r.unit : "–", cell(r.doc));
            else
                fmt::print("  {:<24} {:>10} {:<8} {}  [{}]\n", r.key, value, r.unit, r.doc,
                           r.expected);
        }
    }
    return 0;
}

} // namespace

void addSettingsCommand(CLI::App& app, Action& action) {
    auto o = std::make_shared<SettingsOptions>();
    CLI::App* cmd = app.add_subcommand(
        "settings", "List the numeric world and material settings: default, range, unit, meaning");
    cmd->add_flag("--markdown", o->markdown, "As the Markdown table of docs/LIMITS.md");
    cmd->callback([o, &action] { action = [o] { return printSettings(*o); }; });
}

} // namespace ffd::cli
