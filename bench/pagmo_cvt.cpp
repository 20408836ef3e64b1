// The paper's swarm against pagmo2 in the same run: the CVT clearance identification
// (Yoshida & Takamatsu), 512 particles for 250 iterations, timed
//   (a) as tvid runs it (`configs/cvt_tipin.yaml`'s pso through run_fit), and
//   (b) as a scripted C++ fit would: pagmo2's generational particle swarm (pso_gen, the
//       canonical inertia-weight variant with the paper's w = 1, c1 = c2 = 0.4) over the
//       same box, the population evaluated by pagmo's thread_bfe on every core, each
//       candidate scored with odeint's runge_kutta4 twice over: by the straightforward
//       implementation (baseline_cvt.cpp: a std::vector state, the input searched at every
//       right-hand side; it computes tvid's cost to rounding, `tvid_bench cvt-check`), and
//       by the same as a user would tune it (a fixed-size state, the input interpolated
//       within the step).
// Both run the same number of swarm iterations; pagmo simulates every candidate to the
// window's end, as a fitness function does. Prints the three wall times and tvid's ratio
// to each pagmo2 run.
//
//   tvid_bench_pagmo [--iterations K] [--threads N]
//
// Built when pagmo2 is installed (scripts/install-deps.sh installs libpagmo-dev; not a
// dependency of tvid itself).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <pagmo/algorithms/pso_gen.hpp>
#include <pagmo/batch_evaluators/thread_bfe.hpp>
#include <pagmo/bfe.hpp>
#include <pagmo/population.hpp>
#include <pagmo/problem.hpp>
#include <tbb/global_control.h>

#include "baseline_cvt.hpp"
#include "tvid/estimation/identification_problem.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/fit/fit_run.hpp"

namespace {

using clock_type = std::chrono::steady_clock;

// The CVT cost as a pagmo2 problem: one odeint simulation of the window per fitness call.
struct CvtCost {
    // pagmo's fitness() is const and the baseline counts its right-hand sides: each thread
    // of thread_bfe runs on its own copy of the problem (basic thread safety, pagmo's default).
    mutable tvid::bench::BaselineCvt cvt{{0.0, 1.0}, {0.0, 0.0}, {0.0, 0.0}, 0, 0};
    std::vector<double> lower, upper;
    bool tuned = false;

    pagmo::vector_double fitness(const pagmo::vector_double& x) const {
        return {tuned ? cvt.cost_tuned(x.data()) : cvt.cost(x.data())};
    }
    std::pair<pagmo::vector_double, pagmo::vector_double> get_bounds() const { return {lower, upper}; }
};

double seconds_since(clock_type::time_point t0) { return std::chrono::duration<double>(clock_type::now() - t0).count(); }

}  // namespace

int main(int argc, char** argv) {
    int iterations = 250, threads = 0;
    for (int i = 1; i + 1 < argc; ++i) {
        if (!std::strcmp(argv[i], "--iterations")) iterations = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--threads")) threads = std::atoi(argv[++i]);
    }
    const tvid::Experiment ex = tvid::load_experiment(std::string(TVID_SOURCE_DIR) + "/configs/cvt_tipin.yaml",
                                                      {{"estimation.pso.iterations", std::to_string(iterations)}});
    const tvid::IdentificationProblem problem(ex);

    // (a) tvid's swarm.
    tvid::FitOptions options;
    options.threads = threads;
    const auto t_tvid = clock_type::now();
    const tvid::FitResult fit = tvid::run_fit(problem, options);
    const double tvid_s = seconds_since(t_tvid);

    // (b) pagmo2 with odeint, the same particles, iterations and cores.
    const int cores = fit.threads;
    const tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(cores));
    const auto& w = ex.estimation[0];
    CvtCost cost;
    cost.cvt = tvid::bench::BaselineCvt(problem.inputs().time(), ex.data.column("Ttm"), ex.data.column("Tds"), w.start,
                                        w.last);
    cost.lower = problem.range_lower();
    cost.upper = problem.range_upper();
    const tvid::PsoSettings& pso = ex.estimation_settings.pso;
    std::size_t particles = static_cast<std::size_t>(pso.particles);
    if (pso.start == tvid::PsoStart::grid) {  // eq. 26: n^M
        particles = 1;
        for (std::size_t j = 0; j < problem.dimension(); ++j) particles *= static_cast<std::size_t>(pso.grid);
    }
    // The tuned fitness computes the straightforward one's cost to rounding: checked at
    // tvid's best point and the box's corners.
    double worst = 0.0;
    std::vector<std::vector<double>> points = {fit.run.best, cost.lower, cost.upper};
    for (const auto& x : points) {
        const double a = cost.cvt.cost(x.data()), b = cost.cvt.cost_tuned(x.data());
        if (std::isfinite(a) != std::isfinite(b)) worst = std::numeric_limits<double>::infinity();  // one failed
        else if (std::isfinite(a)) worst = std::max(worst, std::abs(a - b) / std::abs(a));
    }
    std::printf("case                           wall_s   simulations  best cost  (tuned / straightforward cost: %.1e apart at most)\n",
                worst);
    std::printf("tvid swarm                     %7.2f   %11lld  %.6g\n", tvid_s, fit.run.evaluations, fit.run.best_cost);
    for (const bool tuned : {false, true}) {
        cost.tuned = tuned;
        const pagmo::problem prob{cost};
        const auto t_pagmo = clock_type::now();
        pagmo::population pop{prob, pagmo::bfe{pagmo::thread_bfe{}}, particles, 1u};
        pagmo::pso_gen swarm(static_cast<unsigned>(iterations), 1.0, 0.4, 0.4, 0.5, 1u, 2u, 4u, false, 1u);
        swarm.set_bfe(pagmo::bfe{pagmo::thread_bfe{}});
        pop = swarm.evolve(pop);
        const double pagmo_s = seconds_since(t_pagmo);
        std::printf("pagmo2 + odeint, %-13s %7.2f   %11llu  %.6g   tvid %.1fx faster\n",
                    tuned ? "tuned" : "as printed", pagmo_s, static_cast<unsigned long long>(pop.get_problem().get_fevals()),
                    pop.champion_f()[0], pagmo_s / tvid_s);
    }
    std::printf("threads %d, %zu particles, %d iterations\n", cores, particles, iterations);
    return 0;
}
