#include "tvid/report/optimizer_report.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace tvid {

namespace {

using nlohmann::json;

json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

std::string cell(double v) {
    if (!std::isfinite(v)) return std::isnan(v) ? "" : (v > 0 ? "inf" : "-inf");
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

json swarm_json(const FitResult& fit) {
    const PsoSettings& ps = fit.pso_settings;
    return json{{"particles", fit.pso.particles}, {"seed", ps.seed}, {"w", ps.w}, {"c1", ps.c1}, {"c2", ps.c2}};
}

json lm_json(const Experiment& ex, const FitResult& fit) {
    const LmSettings& ls = fit.lm_settings;
    return json{{"jacobian", ex.estimation_settings.jacobian == JacobianKind::fd ? "fd" : "sensitivity"},
                {"ftol", ls.ftol},
                {"xtol", ls.xtol},
                {"gtol", ls.gtol},
                {"max_iterations", ls.max_iterations}};
}

}  // namespace

json optimizer_details_json(const Experiment& ex, const FitResult& fit) {
    json d = json::object();
    const std::string& name = fit.run.name;
    if (name == "pso") {
        d = swarm_json(fit);
    } else if (name == "lm") {
        d = lm_json(ex, fit);
        d["initial_cost"] = number(fit.lm.initial_cost);
    } else if (name == "nlopt") {
        const NloptSettings& ns = fit.nlopt_settings;
        d = json{{"algorithm", fit.nlopt.algorithm},
                 {"local_algorithm", fit.nlopt.local_algorithm.empty() ? json(nullptr) : json(fit.nlopt.local_algorithm)},
                 {"max_evaluations", ns.max_evaluations},
                 {"max_seconds", ns.max_seconds},
                 {"xtol_rel", ns.xtol_rel},
                 {"ftol_rel", ns.ftol_rel},
                 {"population", ns.population},
                 {"seed", ns.seed},
                 {"objective_evaluations", fit.nlopt.evaluations},
                 {"gradient_evaluations", fit.nlopt.gradient_evaluations},
                 {"initial_cost", number(fit.nlopt.initial_cost)}};
        if (fit.nlopt.gradient_evaluations > 0) d["jacobian"] = lm_json(ex, fit)["jacobian"];
    } else if (name == "pso+lm") {
        // Both phases minimize the l2 cost; the polish starts at the swarm's best particle.
        json swarm = swarm_json(fit);
        swarm["iterations"] = fit.pso.iterations;
        swarm["evaluations"] = fit.pso.evaluations;
        swarm["cost"] = number(fit.pso.best_cost);
        swarm["termination"] = fit.pso.termination;
        json polish = lm_json(ex, fit);
        polish["ran"] = !fit.lm.history.empty();
        polish["initial_cost"] = number(fit.lm.initial_cost);
        polish["cost"] = number(fit.lm.best_cost);
        polish["iterations"] = fit.lm.iterations;
        polish["termination"] = fit.lm.termination;
        d = json{{"swarm", swarm}, {"polish", polish}};
    } else if (name == "multistart") {
        const MultistartSummary& ms = fit.multistart;
        json starts = json::array();
        for (const StartResult& s : ms.starts)
            starts.push_back(json{{"start", s.start},
                                  {"initial_cost", number(s.initial_cost)},
                                  {"cost", number(s.best_cost)},
                                  {"iterations", s.iterations},
                                  {"evaluations", s.evaluations},
                                  {"termination", s.termination},
                                  {"converged", s.success}});
        d = json{{"starts", fit.multistart_settings.starts},
                 {"seed", fit.multistart_settings.seed},
                 {"best_start", ms.best_start},
                 {"parallel_starts", ms.threads},
                 {"threads_per_start", ms.threads_per_start},
                 {"lm", lm_json(ex, fit)},
                 {"start_results", starts}};
    }
    return d;
}

std::string starts_csv(const IdentificationProblem& problem, const FitResult& fit) {
    if (fit.run.name != "multistart") return "";
    std::ostringstream out;
    out << "start";
    for (const std::string& n : problem.free_names()) out << ",initial_" << n;
    for (const std::string& n : problem.free_names()) out << ",final_" << n;
    out << ",initial_cost,cost,iterations,evaluations,termination,best\n";
    for (const StartResult& s : fit.multistart.starts) {
        out << s.start;
        for (double v : s.initial) out << ',' << cell(v);
        for (double v : s.best) out << ',' << cell(v);
        out << ',' << cell(s.initial_cost) << ',' << cell(s.best_cost) << ',' << s.iterations << ',' << s.evaluations
            << ',' << s.termination << ',' << (s.start == fit.multistart.best_start ? "true" : "false") << '\n';
    }
    return out.str();
}

}  // namespace tvid
