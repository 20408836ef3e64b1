// Which reading of Yoshida & Takamatsu eq. 24 finds the lower cost? The paper does not say whether
// the random factors η0, η1, η2 are drawn once per iteration, once per particle or once
// per dimension, nor whether the position moves with v(k) (as printed) or v(k+1). This
// program runs the paper-sized swarm (512 grid particles, 250 iterations) on a shipped
// experiment for each variant and several seeds and prints the final cost E and Q.
//
//   tvid_pso_variants [EXPERIMENT.yaml] [--seeds N] [--iterations K] [--threads T]
//
// It prints figures; it never passes or fails.

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "tvid/estimation/identification_problem.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/fit/fit_run.hpp"

using namespace tvid;

int main(int argc, char** argv) {
    std::string config = std::string(TVID_SOURCE_DIR) + "/configs/cvt_tipin_clean.yaml";
    int seeds = 3, threads = 0, iterations = -1;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--seeds") && i + 1 < argc) seeds = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) threads = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--iterations") && i + 1 < argc) iterations = std::atoi(argv[++i]);
        else config = argv[i];
    }
    std::vector<Override> overrides;
    if (iterations >= 0) overrides.push_back({"estimation.pso.iterations", std::to_string(iterations)});
    const Experiment ex = load_experiment(config, overrides);
    const IdentificationProblem problem(ex);

    struct Variant {
        const char* name;
        PsoRandomDraw draw;
        bool velocity_first;
    };
    const Variant variants[] = {
        {"per_iteration", PsoRandomDraw::per_iteration, false},
        {"per_particle", PsoRandomDraw::per_particle, false},
        {"per_dimension", PsoRandomDraw::per_dimension, false},
        {"per_particle, v(k+1)", PsoRandomDraw::per_particle, true},
    };
    std::printf("experiment %s, %d seeds, %s\n", ex.name.c_str(), seeds, config.c_str());
    std::printf("%-22s %6s %12s %9s %9s\n", "eta drawn", "seed", "E", "Q %", "wall s");
    for (const Variant& v : variants) {
        double sum = 0;
        for (int s = 1; s <= seeds; ++s) {
            Experiment variant = ex;
            variant.estimation_settings.pso.draw = v.draw;
            variant.estimation_settings.pso.velocity_first = v.velocity_first;
            variant.estimation_settings.pso.seed = static_cast<std::uint64_t>(s);
            const IdentificationProblem p(variant);
            FitOptions o;
            o.threads = threads;
            const FitResult fit = run_fit(p, o);
            sum += fit.run.best_cost;
            std::printf("%-22s %6d %12.6g %9.3f %9.2f\n", v.name, s, fit.run.best_cost,
                        fit.evaluation.estimation.pooled.at(0).q_index, fit.optimizer_seconds);
            std::fflush(stdout);
        }
        std::printf("%-22s %6s %12.6g  (mean E)\n", v.name, "", sum / seeds);
    }
    return 0;
}
