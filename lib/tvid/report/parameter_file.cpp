#include "tvid/report/parameter_file.hpp"

#include <fstream>
#include <nlohmann/json.hpp>

#include "tvid/experiment/parameter_reader.hpp"
#include "tvid/io/json_file.hpp"
#include "tvid/util/input_error.hpp"

namespace tvid {

std::vector<double> initial_parameters(const Experiment& experiment) {
    std::vector<double> p;
    for (const ParameterSetting& s : experiment.parameters) p.push_back(s.init);
    return p;
}

std::vector<double> read_parameter_file(const std::filesystem::path& file, const Experiment& experiment) {
    const std::string name = file.string();
    const nlohmann::json j = read_json_file(file, "parameter file");
    std::vector<double> p = initial_parameters(experiment);
    auto set = [&](const std::string& key, const nlohmann::json& value) {
        const int i = experiment.network.parameter_index(key);
        if (i < 0) throw InputError(name, 0, key, "is not a parameter of the model");
        if (!value.is_number()) throw InputError(name, 0, key, "expected a number");
        const double v = value.get<double>();
        const auto index = static_cast<std::size_t>(i);
        if (const std::string problem = parameter_value_problem(experiment.network, experiment.parameters[index], index, v);
            !problem.empty())
            throw InputError(name, 0, key, problem);
        p[index] = v;
    };
    if (j.is_object() && j.contains("parameters") && j["parameters"].is_array()) {
        for (const auto& entry : j["parameters"]) {
            if (!entry.is_object() || !entry.contains("name") || !entry.contains("value") || !entry["name"].is_string())
                throw InputError(name, 0, "parameters", "each entry needs a name and a value");
            set(entry["name"].get<std::string>(), entry["value"]);
        }
        // An estimated start's corrections, where this experiment estimates the same ones
        // (another experiment starts its windows from its own recipe).
        if (j.contains("initial_states") && j["initial_states"].is_array())
            for (const auto& entry : j["initial_states"]) {
                if (!entry.is_object() || !entry.contains("parameter") || !entry["parameter"].is_string() ||
                    !entry.contains("correction"))
                    throw InputError(name, 0, "initial_states", "each entry needs its parameter and correction");
                const std::string key = entry["parameter"].get<std::string>();
                if (experiment.network.parameter_index(key) >= 0) set(key, entry["correction"]);
            }
    } else if (j.is_object()) {
        for (const auto& [key, value] : j.items()) set(key, value);
    } else {
        throw InputError(name, 0, "", "expected a JSON object of parameter values");
    }
    return p;
}

}  // namespace tvid
