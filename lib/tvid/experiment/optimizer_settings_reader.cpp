#include "tvid/experiment/optimizer_settings_reader.hpp"

#include <algorithm>
#include <climits>

#include "tvid/optim/nlopt_algorithms.hpp"
#include "tvid/optim/settings_validation.hpp"
#include "tvid/util/text.hpp"

namespace tvid {

namespace {

// An integer setting as an int. Out-of-range values stay out of range (saturated), so the
// settings' validation reports them.
int saturated_int(long long value) { return static_cast<int>(std::clamp<long long>(value, INT_MIN, INT_MAX)); }

// A seed: any integer that is not negative (checked here: the settings hold it unsigned).
std::uint64_t read_seed(const YamlMap& m) {
    const long long seed = m.integer("seed");
    if (seed < 0) m.fail("seed", "the seed must not be negative");
    return static_cast<std::uint64_t>(seed);
}

// The settings' first problem, if any, as "FILE:LINE: <section>.<key>: <message>".
void fail_on_problem(const YamlMap& m, const std::optional<SettingsProblem>& problem) {
    if (!problem) return;
    if (problem->missing) m.fail_missing(problem->key, problem->message);
    m.fail(problem->key, problem->message);
}

}  // namespace

OptimizerKind read_optimizer_kind(const YamlMap& estimation) {
    const std::string name = estimation.text("optimizer");
    std::vector<std::string> names;
    for (const OptimizerKindRow& row : optimizer_kinds()) {
        if (name == row.name) return row.kind;
        names.emplace_back(row.name);
    }
    estimation.fail("optimizer", "'" + name + "' is not one of: " + join_words(names));
}

PsoSettings read_pso(const YamlMap& m) {
    m.allow_only({"start", "grid", "particles", "iterations", "w", "c1", "c2", "seed", "draw", "velocity_first"});
    PsoSettings s;
    if (m.has("start")) {
        const std::string start = m.choice("start", {"grid", "latin_hypercube", "uniform"});
        s.start = start == "grid" ? PsoStart::grid : start == "uniform" ? PsoStart::uniform : PsoStart::latin_hypercube;
    }
    if (m.has("grid")) s.grid = saturated_int(m.integer("grid"));
    if (m.has("particles")) s.particles = saturated_int(m.integer("particles"));
    if (m.has("iterations")) s.iterations = saturated_int(m.integer("iterations"));
    if (m.has("w")) s.w = m.number("w");
    if (m.has("c1")) s.c1 = m.number("c1");
    if (m.has("c2")) s.c2 = m.number("c2");
    if (m.has("seed")) s.seed = read_seed(m);
    if (m.has("draw")) {
        const std::string d = m.choice("draw", {"per_iteration", "per_particle", "per_dimension"});
        s.draw = d == "per_iteration" ? PsoRandomDraw::per_iteration
                 : d == "per_particle" ? PsoRandomDraw::per_particle
                                       : PsoRandomDraw::per_dimension;
    }
    if (m.has("velocity_first")) s.velocity_first = m.flag("velocity_first");
    fail_on_problem(m, validate(s));
    return s;
}

LmSettings read_lm(const YamlMap& m) {
    m.allow_only({"max_iterations", "ftol", "xtol", "gtol", "stol", "jacobian"});
    LmSettings s;
    if (m.has("max_iterations")) s.max_iterations = saturated_int(m.integer("max_iterations"));
    if (m.has("ftol")) s.ftol = m.number("ftol");
    if (m.has("xtol")) s.xtol = m.number("xtol");
    if (m.has("gtol")) s.gtol = m.number("gtol");
    if (m.has("stol")) s.stol = m.number("stol");
    fail_on_problem(m, validate(s));
    return s;
}

NloptSettings read_nlopt(const YamlMap& m) {
    m.allow_only({"algorithm", "local_algorithm", "max_evaluations", "max_seconds", "xtol_rel", "ftol_rel",
                  "population", "seed"});
    NloptSettings s;
    if (m.has("algorithm")) s.algorithm = m.text("algorithm");
    if (m.has("local_algorithm")) s.local_algorithm = m.text("local_algorithm");
    if (m.has("max_evaluations")) s.max_evaluations = m.integer("max_evaluations");
    if (m.has("max_seconds")) s.max_seconds = m.number("max_seconds");
    if (m.has("xtol_rel")) s.xtol_rel = m.number("xtol_rel");
    if (m.has("ftol_rel")) s.ftol_rel = m.number("ftol_rel");
    if (m.has("population")) s.population = saturated_int(m.integer("population"));
    if (m.has("seed")) s.seed = read_seed(m);
    fail_on_problem(m, validate(s));
    // NLopt's own spelling of the names given.
    s.algorithm = find_nlopt_algorithm(s.algorithm)->name;
    if (!s.local_algorithm.empty()) s.local_algorithm = find_nlopt_algorithm(s.local_algorithm)->name;
    return s;
}

MultistartSettings read_multistart(const YamlMap& m) {
    m.allow_only({"starts", "seed", "max_iterations", "max_draws"});
    MultistartSettings s;
    if (m.has("starts")) s.starts = saturated_int(m.integer("starts"));
    if (m.has("seed")) s.seed = read_seed(m);
    if (m.has("max_iterations")) s.max_iterations = saturated_int(m.integer("max_iterations"));
    if (m.has("max_draws")) s.max_draws = saturated_int(m.integer("max_draws"));
    fail_on_problem(m, validate(s));
    return s;
}

void check_search_box(const YamlMap& parameters, const std::vector<ParameterSetting>& settings,
                      const EstimationSettings& estimation) {
    const OptimizerKindRow& optimizer = optimizer_kind_row(estimation.optimizer);
    if (optimizer.check_parameters) optimizer.check_parameters(parameters, settings, estimation);
    if (!optimizer.traits.samples_box) return;
    for (const ParameterSetting& p : settings)
        if (!p.fixed && !p.range && !(p.has_min && p.has_max))
            parameters.fail(p.name, std::string(optimizer.name) +
                                        " samples its starts in the search box: give range: [a, b] or both min and max");
}

}  // namespace tvid
