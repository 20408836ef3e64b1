// `tvid models`: the preset networks with their parameters, inputs and outputs.

#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "tvid/model/presets.hpp"
#include "tvid/io/json_text.hpp"

namespace tvid::cli {

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
        std::cout << json_text(out) << std::endl;
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
    std::cout << "custom networks: model: { nodes: [...], elements: [...] } (see docs/model-library.md)\n";
    return kExitDone;
}

}  // namespace tvid::cli
