// Figures for the CVT clearance identification (Yoshida & Takamatsu): cost of one simulation of
// the 1500-sample estimation window (RK4 at 1 ms), and the paper-sized particle swarm
// (512 particles on the 2^9 grid, 250 iterations) per thread count.
//
//   tvid_bench_cvt [--swarm] [--threads N]
//
// Without --swarm only the single-simulation figures are printed (a few seconds).

#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>

#include "tvid/estimation/identification_problem.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/fit/fit_run.hpp"

using namespace tvid;
using clock_type = std::chrono::steady_clock;

int main(int argc, char** argv) {
    bool swarm = false;
    int threads = 0;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--swarm")) swarm = true;
        if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) threads = std::atoi(argv[++i]);
    }
    const Experiment ex = load_experiment(std::string(TVID_SOURCE_DIR) + "/configs/cvt_tipin.yaml");
    const IdentificationProblem problem(ex);
    auto ws = problem.make_workspace();

    // One simulation per cost evaluation at the centre of the paper's domain (27).
    std::vector<double> centre(problem.dimension());
    for (std::size_t j = 0; j < centre.size(); ++j)
        centre[j] = 0.5 * (problem.range_lower()[j] + problem.range_upper()[j]);
    const std::size_t steps = ex.estimation[0].last - ex.estimation[0].start;
    const int repeats = 2000;
    double sink = 0;
    const auto t0 = clock_type::now();
    for (int r = 0; r < repeats; ++r) sink += problem.cost(centre.data(), *ws);
    const double seconds = std::chrono::duration<double>(clock_type::now() - t0).count();
    const double per_sim = seconds / repeats;
    std::printf("case                         value\n");
    std::printf("window samples               %zu (RK4, 4 right-hand sides per step)\n", steps);
    std::printf("one simulation + cost        %.1f us\n", per_sim * 1e6);
    std::printf("simulations per second       %.0f (1 thread)\n", 1.0 / per_sim);
    std::printf("ns per right-hand side       %.1f\n", per_sim * 1e9 / (4.0 * static_cast<double>(steps)));
    std::printf("(cost %.6g)\n", sink / repeats);

    if (swarm) {
        FitOptions o;
        o.threads = threads;
        const FitResult fit = run_fit(problem, o);
        std::printf("paper PSO (512 x 250)        %.2f s wall on %d threads, %lld simulations, %.0f sim/s, E = %.6g\n",
                    fit.optimizer_seconds, fit.threads, fit.run.evaluations,
                    static_cast<double>(fit.run.evaluations) / fit.optimizer_seconds, fit.run.best_cost);
    }
    return 0;
}
