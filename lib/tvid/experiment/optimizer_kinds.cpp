#include "tvid/experiment/optimizer_kinds.hpp"

#include <stdexcept>
#include <string>

#include "tvid/experiment/experiment.hpp"
#include "tvid/experiment/yaml_reader.hpp"
#include "tvid/optim/nlopt_algorithms.hpp"

namespace tvid {

namespace {

// A global NLopt algorithm searches within the bounds.
void check_nlopt_parameters(const YamlMap& parameters, const std::vector<ParameterSetting>& settings,
                            const EstimationSettings& estimation) {
    if (!find_nlopt_algorithm(estimation.nlopt.algorithm)->global) return;
    for (const ParameterSetting& p : settings)
        if (!p.fixed && !(p.has_min && p.has_max))
            parameters.fail(p.name, "the global NLopt algorithm " + estimation.nlopt.algorithm +
                                        " searches within the bounds: give both min and max");
}

}  // namespace

const std::vector<OptimizerKindRow>& optimizer_kinds() {
    static const std::vector<OptimizerKindRow> rows{
        {OptimizerKind::pso, "pso", "the particle swarm (Yoshida & Takamatsu) over the search box",
         {.swarm = true}},
        {OptimizerKind::lm, "lm", "Levenberg-Marquardt least squares from init (the methodology paper)",
         {.least_squares = true, .starts_at_init = true}},
        {OptimizerKind::nlopt, "nlopt", "any NLopt algorithm by name, from init",
         {}, check_nlopt_parameters},
        {OptimizerKind::pso_lm, "pso+lm", "the swarm, then Levenberg-Marquardt from its best particle",
         {.least_squares = true, .swarm = true}},
        {OptimizerKind::multistart, "multistart", "Levenberg-Marquardt from Latin-hypercube starts of the box",
         {.least_squares = true, .samples_box = true}},
    };
    return rows;
}

const OptimizerKindRow& optimizer_kind_row(OptimizerKind kind) {
    for (const OptimizerKindRow& row : optimizer_kinds())
        if (row.kind == kind) return row;
    throw std::logic_error("no optimizer row for kind " + std::to_string(static_cast<int>(kind)));
}

const OptimizerKindRow* find_optimizer_kind(std::string_view name) {
    for (const OptimizerKindRow& row : optimizer_kinds())
        if (name == row.name) return &row;
    return nullptr;
}

const char* optimizer_name(OptimizerKind kind) { return optimizer_kind_row(kind).name; }

}  // namespace tvid
