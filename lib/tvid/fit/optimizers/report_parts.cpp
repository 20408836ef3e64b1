#include "tvid/fit/optimizers/report_parts.hpp"

#include <cmath>
#include <cstdio>

namespace tvid::optimizer_report {

using nlohmann::json;

json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

std::string csv_cell(double v) {
    if (!std::isfinite(v)) return std::isnan(v) ? "" : (v > 0 ? "inf" : "-inf");
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

std::string first_failure(const IdentificationProblem& problem, const PsoSummary& swarm) {
    if (swarm.first_failed.size() != problem.dimension()) return {};
    auto ws = problem.make_workspace();
    return problem.failure(swarm.first_failed.data(), *ws);
}

json swarm_settings(const PsoSettings& ps, const PsoSummary& swarm) {
    return json{{"particles", swarm.particles}, {"seed", ps.seed}, {"w", ps.w}, {"c1", ps.c1}, {"c2", ps.c2}};
}

json swarm_convergence(const Experiment& ex, const PsoConvergence& c) {
    json spread = json::object();
    std::size_t j = 0;
    for (const ParameterSetting& p : ex.parameters)
        if (!p.fixed && j < c.spread.size()) spread[p.name] = number(c.spread[j++]);
    return json{{"spread", spread},
                {"max_spread", number(c.max_spread)},
                {"recent_improvement", number(c.recent_improvement)},
                {"window", c.window}};
}

const char* jacobian_name(const Experiment& ex) {
    return ex.estimation_settings.jacobian == JacobianKind::fd ? "fd" : "sensitivity";
}

json lm_settings(const Experiment& ex, const LmSettings& ls) {
    return json{{"jacobian", jacobian_name(ex)},
                {"ftol", ls.ftol},
                {"xtol", ls.xtol},
                {"gtol", ls.gtol},
                {"stol", ls.stol},
                {"max_iterations", ls.max_iterations}};
}

}  // namespace tvid::optimizer_report
