// Loads an experiment through the installed tvid library, simulates it at its initial
// parameters on every window and prints the estimation cost and the pooled estimation
// RMSE of each output, one "name value" per line.

#include <cstdio>
#include <exception>

#include "tvid/analysis/evaluation.hpp"
#include "tvid/estimation/identification_problem.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/report/parameter_file.hpp"

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: simulate_experiment EXPERIMENT.yaml\n");
        return 2;
    }
    try {
        const tvid::Experiment experiment = tvid::load_experiment(argv[1]);
        const tvid::IdentificationProblem problem(experiment);
        const tvid::Evaluation evaluation =
            tvid::evaluate_parameters(problem, tvid::initial_parameters(experiment), 2);
        std::printf("cost %.17g\n", evaluation.cost);
        for (std::size_t o = 0; o < experiment.outputs.size(); ++o)
            std::printf("rmse_%s %.17g\n", experiment.outputs[o].model_name.c_str(),
                        evaluation.estimation.pooled[o].rmse);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "simulate_experiment: %s\n", e.what());
        return 1;
    }
}
