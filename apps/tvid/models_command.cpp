// `tvid models`: the preset networks with their parameters, inputs and outputs, and the
// element kinds a custom network is built from, with their keys and fields.

#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include <memory>

#include "command_options.hpp"
#include "command_table.hpp"
#include "commands.hpp"
#include "tvid/model/element_catalogue.hpp"
#include "tvid/model/presets.hpp"
#include "tvid/io/json_text.hpp"

namespace tvid::cli {

namespace {

nlohmann::json element_kinds_json() {
    nlohmann::json kinds = nlohmann::json::array();
    for (const ElementKindDoc& k : element_kind_catalogue()) {
        nlohmann::json fields = nlohmann::json::array();
        for (const ElementFieldDoc& f : k.fields)
            fields.push_back({{"key", f.key}, {"unit", f.unit}, {"sign", f.sign}, {"meaning", f.role}});
        kinds.push_back({{"type", k.type}, {"summary", k.summary}, {"keys", k.keys}, {"fields", fields},
                         {"composite", k.composite}});
    }
    return kinds;
}

void print_element_kinds() {
    std::cout << "element kinds of a custom network, model: { nodes: [...], elements: [...] } "
                 "(docs/model-library.md):\n";
    for (const ElementKindDoc& k : element_kind_catalogue()) {
        std::cout << "\n" << k.type << "\n  " << k.summary << "\n  keys: ";
        for (std::size_t i = 0; i < k.keys.size(); ++i) std::cout << (i ? ", " : "") << k.keys[i];
        std::cout << '\n';
        for (const ElementFieldDoc& f : k.fields) {
            char line[256];
            std::snprintf(line, sizeof line, "    %-14s %-14s %-5s %s\n", f.key.c_str(), f.unit.c_str(), f.sign.c_str(),
                          f.role.c_str());
            std::cout << line;
        }
    }
}

}  // namespace

int run_models_command(bool json) {
    if (json) {
        nlohmann::json out = nlohmann::json::array();
        for (const PresetInfo& p : preset_catalogue()) {
            nlohmann::json params = nlohmann::json::array();
            for (std::size_t i = 0; i < p.parameters.size(); ++i)
                params.push_back({{"name", p.parameters[i]}, {"unit", p.parameter_units[i]},
                                  {"meaning", p.parameter_meanings[i]}});
            out.push_back({{"preset", p.name}, {"description", p.description}, {"reference", p.reference},
                           {"parameters", params}, {"inputs", p.inputs}, {"outputs", p.outputs},
                           {"constants", p.constants}});
        }
        std::cout << json_text({{"presets", out}, {"element_kinds", element_kinds_json()}}) << std::endl;
        return kExitDone;
    }
    for (const PresetInfo& p : preset_catalogue()) {
        std::cout << p.name << "\n  " << p.description << "\n  (" << p.reference << ")\n";
        std::cout << "  inputs:  ";
        for (const auto& s : p.inputs) std::cout << s << ' ';
        std::cout << "\n  outputs: ";
        for (const auto& s : p.outputs) std::cout << s << ' ';
        std::cout << "\n  parameters:\n";
        for (std::size_t i = 0; i < p.parameters.size(); ++i) {
            char line[256];
            std::snprintf(line, sizeof line, "    %-10s %-12s %s\n", p.parameters[i].c_str(),
                          p.parameter_units[i].c_str(), p.parameter_meanings[i].c_str());
            std::cout << line;
        }
        if (!p.constants.empty()) {
            std::cout << "  constants: ";
            for (const auto& s : p.constants) std::cout << s << ' ';
            std::cout << '\n';
        }
        std::cout << '\n';
    }
    print_element_kinds();
    return kExitDone;
}

CommandRow models_command_row() {
    return {"models", "list the preset models with their parameters, inputs, outputs", false,
            [](CLI::App& sub) -> CommandRunner {
                auto json = std::make_shared<bool>(false);
                sub.add_flag("--json", *json, "as JSON");
                return [json](const CommandContext&) { return run_models_command(*json); };
            }};
}

}  // namespace tvid::cli
