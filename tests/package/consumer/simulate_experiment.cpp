// Loads an experiment through the installed tvid library's public API, scores it at its
// initial parameters on every window and prints the estimation cost and the pooled
// estimation RMSE of each output, one "name value" per line. With `fit` after the file, it
// then identifies the free parameters (with the overrides that follow) and prints the cost
// at the optimum and each parameter.

#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include <tvid/tvid.hpp>

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: simulate_experiment EXPERIMENT.yaml [fit [KEY=VALUE ...]]\n");
        return 2;
    }
    try {
        const bool fit = argc > 2 && std::strcmp(argv[2], "fit") == 0;
        const std::vector<std::string> overrides(argv + (fit ? 3 : 2), argv + argc);
        const tvid::api::Experiment experiment = tvid::api::Experiment::load(argv[1], overrides);
        const tvid::api::Score score = tvid::api::evaluate(experiment, experiment.initial_values(), 2);
        std::printf("version %s\n", tvid::api::version().c_str());
        std::printf("cost %.17g\n", score.cost);
        for (const tvid::api::OutputScore& o : score.estimation) std::printf("rmse_%s %.17g\n", o.output.c_str(), o.rmse);
        if (fit) {
            const tvid::api::FitOutcome outcome = tvid::api::fit(experiment, {.threads = 2});
            std::printf("fit_cost %.17g\n", outcome.score.cost);
            std::printf("optimizer %s converged %d\n", outcome.optimizer.c_str(), outcome.converged ? 1 : 0);
            for (const tvid::api::FittedParameter& p : outcome.parameters)
                std::printf("param %s %.17g %.17g %s\n", p.name.c_str(), p.value, p.standard_error, p.unit.c_str());
        }
        return 0;
    } catch (const tvid::api::InputError& e) {
        std::fprintf(stderr, "simulate_experiment: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "simulate_experiment: %s\n", e.what());
        return 1;
    }
}
