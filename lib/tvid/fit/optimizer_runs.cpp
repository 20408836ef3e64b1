#include "tvid/fit/optimizer_runs.hpp"

#include "tvid/estimation/experiment_cost.hpp"
#include "tvid/estimation/experiment_least_squares.hpp"
#include "tvid/estimation/parallel_evaluator.hpp"
#include "tvid/optim/hybrid_pso_lm.hpp"
#include "tvid/parallel/distributed_evaluator.hpp"

namespace tvid {

OptimizerRun run_nlopt_fit(const IdentificationProblem& problem, const FitOptions& options, FitResult& r) {
    r.nlopt_settings = problem.experiment().estimation_settings.nlopt;
    if (options.seed) r.nlopt_settings.seed = *options.seed;
    ExperimentCost cost(problem, options.threads);
    r.threads = cost.threads();
    r.nlopt = run_nlopt(r.nlopt_settings, problem.initial(), problem.lower(), problem.upper(), cost, options.progress);
    OptimizerRun run{"nlopt",
                        r.nlopt.best,
                        r.nlopt.best_cost,
                        static_cast<int>(r.nlopt.evaluations),
                        cost.simulations(),
                        r.nlopt.failed_evaluations,
                        r.nlopt.history,
                        r.nlopt.termination,
                        r.nlopt.success};
    run.right_hand_sides = cost.right_hand_sides();
    return run;
}

OptimizerRun run_hybrid_fit(const IdentificationProblem& problem, const FitOptions& options, FitResult& r) {
    const EstimationSettings& settings = problem.experiment().estimation_settings;
    r.pso_settings = settings.pso;
    if (options.seed) r.pso_settings.seed = *options.seed;
    r.lm_settings = settings.lm;
    // The swarm's candidates are scored by every process under mpirun, as for pso alone;
    // the polish runs on the root.
    ParallelEvaluator local(problem, options.threads, options.stop);
    DistributedEvaluator swarm_cost(options.processes, local);
    ExperimentLeastSquares residuals(problem, options.threads, settings.jacobian, options.stop);
    r.threads = local.threads();
    r.processes = swarm_cost.processes();
    const SearchBox box{problem.lower(), problem.upper(), problem.range_lower(), problem.range_upper()};
    HybridSummary h = run_pso_then_lm(r.pso_settings, r.lm_settings, box, swarm_cost, residuals, options.progress);
    r.pso = std::move(h.pso);
    r.lm = std::move(h.lm);
    OptimizerRun run{"pso+lm",     h.best,         h.best_cost, h.iterations, h.evaluations, h.failed_evaluations,
                     h.history,    h.termination,  h.success};
    run.right_hand_sides = static_cast<long long>(swarm_cost.right_hand_sides()) + residuals.right_hand_sides();
    return run;
}

OptimizerRun run_multistart_fit(const IdentificationProblem& problem, const FitOptions& options, FitResult& r) {
    const EstimationSettings& settings = problem.experiment().estimation_settings;
    r.multistart_settings = settings.multistart;
    if (options.seed) r.multistart_settings.seed = *options.seed;
    r.lm_settings = settings.lm;
    if (r.multistart_settings.max_iterations) r.lm_settings.max_iterations = *r.multistart_settings.max_iterations;
    const SearchBox box{problem.lower(), problem.upper(), problem.range_lower(), problem.range_upper()};
    const JacobianKind jacobian = settings.jacobian;
    const std::atomic<bool>* stop = options.stop;
    const LeastSquaresFactory make = [&problem, jacobian, stop](int threads) {
        return std::make_unique<ExperimentLeastSquares>(problem, threads, jacobian, stop);
    };
    r.multistart = run_multistart(r.multistart_settings, r.lm_settings, box, resolve_thread_count(options.threads), make,
                                  options.progress);
    r.threads = r.multistart.threads * r.multistart.threads_per_start;
    const MultistartSummary& m = r.multistart;
    OptimizerRun run{"multistart", m.best,        m.best_cost, m.iterations, m.evaluations, m.failed_evaluations,
                     m.history,    m.termination, m.success};
    run.right_hand_sides = m.right_hand_sides;
    return run;
}

}  // namespace tvid
