// A batch job's share of the cores (util/thread_budget.hpp): the team is the cores over the
// jobs running, and a least-squares fit whose share grows while it runs (the batch's other
// jobs finish) takes the same steps to the same bits as one on a single thread.
#include <catch2/catch.hpp>
#include <Eigen/Dense>
#include <vector>

#include "support/test_files.hpp"
#include "tvid/estimation/residual_evaluator.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/fit/fit_run.hpp"
#include "tvid/optim/levenberg_marquardt.hpp"
#include "tvid/util/thread_budget.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;
using tvid::test::source_dir;

TEST_CASE("a thread budget shares its cores among the running jobs", "[thread_budget]") {
    ThreadBudget budget(4);
    CHECK(budget.team() == 4);  // nothing running: a region would take every core
    budget.job_started();
    budget.job_started();
    budget.job_started();
    CHECK(budget.team() == 1);  // three jobs on four cores: one each (the fourth is the spare)
    budget.job_finished();
    CHECK(budget.team() == 2);
    budget.job_finished();
    CHECK(budget.team() == 4);  // the last job takes up the cores the others left
    CHECK(ThreadBudget(0).cores() == 1);
}

TEST_CASE("least squares whose share of the cores grows mid-fit ends on the single thread's bits",
          "[thread_budget][lm]") {
    const Experiment ex = load_experiment(source_dir() / "configs/cvt_tipin_clean.yaml",
                                          {{"windows.estimation", "[{time: [1.0, 2.0]}]"}});
    const IdentificationProblem problem(ex);
    LmSettings settings;
    settings.max_iterations = 12;
    const std::vector<double> lower = problem.lower(), upper = problem.upper();

    ResidualEvaluator one(problem, EvaluatorOptions(1).with_jacobian(JacobianKind::sensitivity));
    const LmSummary alone = run_levenberg_marquardt(settings, problem.initial(), lower, upper, one);

    ThreadBudget budget(2);
    budget.job_started();
    budget.job_started();  // two jobs: this one runs on one core
    ResidualEvaluator shared(problem, EvaluatorOptions(1).with_jacobian(JacobianKind::sensitivity).with_budget(&budget));
    CHECK(shared.threads() == 2);
    CHECK(shared.team() == 1);
    int iteration = 0;
    const LmProgress progress = [&](const HistoryRow&) {
        if (++iteration == 4) budget.job_finished();  // the other job is done: both cores from here
        return true;
    };
    const LmSummary grown = run_levenberg_marquardt(settings, problem.initial(), lower, upper, shared, progress);
    CHECK(shared.team() == 2);
    REQUIRE(grown.best.size() == alone.best.size());
    for (std::size_t j = 0; j < alone.best.size(); ++j) CHECK(grown.best[j] == alone.best[j]);
    CHECK(grown.best_cost == alone.best_cost);
    CHECK(grown.iterations == alone.iterations);
    CHECK((grown.jacobian_at_best - alone.jacobian_at_best).cwiseAbs().maxCoeff() == 0.0);
}

TEST_CASE("every optimizer of a batch job runs on the job's share of the cores", "[thread_budget][fit]") {
    ThreadBudget budget(2);
    budget.job_started();
    budget.job_started();  // two jobs on two cores: one each
    for (const char* optimizer : {"lm", "pso", "pso+lm", "multistart", "nlopt"}) {
        INFO(optimizer);
        const Experiment ex = load_experiment(source_dir() / "configs/constant_load.yaml",
                                              {{"estimation.optimizer", optimizer},
                                               {"estimation.pso.particles", "8"},
                                               {"estimation.pso.iterations", "2"},
                                               {"estimation.multistart.starts", "2"},
                                               {"estimation.lm.max_iterations", "3"},
                                               {"estimation.nlopt.max_evaluations", "10"}});
        const IdentificationProblem problem(ex);
        FitOptions options;
        options.threads = 8;  // eight threads, were it not for the budget
        options.budget = &budget;
        const FitResult fit = run_fit(problem, options);
        // The swarm takes the job's team when it starts (1); least squares keeps a
        // workspace per core of the budget and takes the team of the moment in each region.
        CHECK(fit.threads >= 1);
        CHECK(fit.threads <= budget.cores());
    }
}

}  // namespace TVID_UNITY_ID
