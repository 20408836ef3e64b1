#include "tvid/report/optimizer_report.hpp"

#include "tvid/fit/optimizer_table.hpp"

namespace tvid {

nlohmann::json optimizer_details_json(const Experiment& ex, const FitResult& fit) {
    const OptimizerEntry* optimizer = find_optimizer(fit.run.name);
    return optimizer ? optimizer->details(ex, fit) : nlohmann::json::object();
}

std::string starts_csv(const IdentificationProblem& problem, const FitResult& fit) {
    const OptimizerEntry* optimizer = find_optimizer(fit.run.name);
    return optimizer && optimizer->starts_csv ? optimizer->starts_csv(problem, fit) : "";
}

}  // namespace tvid
