#pragma once
// One identification run: optimizer on the estimation windows, then the optimum judged
// on every window and its uncertainty estimated. What `tvid fit` does between reading
// the experiment and writing the report.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "tvid/estimation/evaluation.hpp"
#include "tvid/estimation/identification_problem.hpp"
#include "tvid/estimation/uncertainty.hpp"
#include "tvid/optim/pso.hpp"

namespace tvid {

struct FitOptions {
    int threads = 0;                        ///< <= 0: all cores
    std::optional<std::uint64_t> seed;      ///< overrides the experiment's seed
    PsoProgress progress;                   ///< called after every iteration
};

struct FitResult {
    std::string optimizer;                  ///< "pso"
    PsoSettings pso_settings;               ///< as run (seed resolved)
    PsoSummary pso;
    bool success = false;                   ///< a finite cost was reached
    std::vector<double> best_free;
    std::vector<double> best_params;        ///< full model parameter vector
    Evaluation evaluation;
    ParameterUncertainty uncertainty;
    double optimizer_seconds = 0.0;
    double wall_seconds = 0.0;
    int threads = 1;
};

FitResult run_fit(const IdentificationProblem& problem, const FitOptions& options);

}  // namespace tvid
