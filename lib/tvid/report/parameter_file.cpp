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

std::vector<double> read_parameter_file(const std::filesystem::path& file, const Experiment& experiment,
                                        const std::vector<std::vector<double>>* seeds, std::vector<std::string>* notes) {
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
        // An estimated start, where this experiment estimates the same coordinate of the same
        // window; else that window starts from its recipe, and the notes say so.
        if (j.contains("initial_states") && !j["initial_states"].is_array())
            throw InputError(name, 0, "initial_states", "expected a list of start coordinates, as tvid fit writes it");
        if (j.contains("initial_states"))
            for (const auto& entry : j["initial_states"]) {
                if (!entry.is_object() || !entry.contains("parameter") || !entry["parameter"].is_string() ||
                    !entry.contains("correction"))
                    throw InputError(name, 0, "initial_states", "each entry needs its parameter and correction");
                const std::string key = entry["parameter"].get<std::string>();
                const int index = experiment.network.parameter_index(key);
                const NetworkSpec::StartCoordinate* coordinate = nullptr;
                for (const NetworkSpec::StartCoordinate& c : experiment.network.start_coordinates)
                    if (c.parameter == index && index >= 0) coordinate = &c;
                if (coordinate == nullptr) {
                    if (notes) notes->push_back("the start coordinate " + key + " of " + name +
                                                " is not one this experiment estimates: left out");
                    continue;
                }
                const std::string window = experiment.estimation[coordinate->window].label;
                if (entry.contains("window") && entry["window"].is_string() && entry["window"].get<std::string>() != window) {
                    if (notes) notes->push_back("the start " + key + " of " + name + " was estimated for the window '" +
                                                entry["window"].get<std::string>() + "', not '" + window +
                                                "': left out, that window starts from its recipe");
                    continue;
                }
                // The start as stored: its value less this experiment's seed now.
                if (seeds && entry.contains("value") && entry["value"].is_number() && coordinate->window < seeds->size() &&
                    coordinate->state < (*seeds)[coordinate->window].size())
                    set(key, entry["value"].get<double>() - (*seeds)[coordinate->window][coordinate->state]);
                else
                    set(key, entry["correction"]);
            }
    } else if (j.is_object()) {
        for (const auto& [key, value] : j.items()) set(key, value);
    } else {
        throw InputError(name, 0, "", "expected a JSON object of parameter values");
    }
    return p;
}

}  // namespace tvid
