// Numerical faults: a simulation that diverges, turns NaN or runs out of its step budget
// ends with a status under every integrator, a failing candidate costs +inf, and the
// optimizer counts it.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "support/test_files.hpp"
#include "tvid/analysis/evaluation.hpp"
#include "tvid/estimation/identification_problem.hpp"
#include "tvid/estimation/parallel_evaluator.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/optim/levenberg_marquardt.hpp"
#include "tvid/optim/pso.hpp"
#include "tvid/sim/simulate.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;
using tvid::test::source_dir;

namespace {

// J θ'' = −k θ − c θ' with J = 1, started at θ = 1: k < 0 grows exponentially, k = NaN
// poisons the first derivative, a large k with a tight tolerance needs many steps.
NetworkSpec oscillator(double k, double c = 0.0) {
    NetworkSpec spec;
    spec.nodes.push_back(NodeSpec{"mass", Field::value(1.0), false});
    spec.spring_dampers.push_back(SpringDamperSpec{"spring", 0, kGround, Field::value(k), Field::value(c)});
    spec.outputs.push_back(OutputSpec{"angle", OutputKind::angle, 0, {}, Field::value(0.0)});
    return spec;
}

SimulationStatus simulate_oscillator(double k, IntegrationMethod method, std::size_t max_steps) {
    const NetworkSpec spec = oscillator(k);
    NetworkModel<double> model(spec);
    model.set_parameters(nullptr);
    std::vector<double> t(1001);
    for (std::size_t i = 0; i < t.size(); ++i) t[i] = 0.01 * static_cast<double>(i);  // 10 s at 100 Hz
    const InputChannels inputs(t, {});
    SimulationSettings s;
    s.method = method;
    s.rtol = 1e-8;
    s.atol = 1e-10;
    s.max_steps = max_steps;
    SimulationBuffers buffers;
    std::vector<double> x{1.0, 0.0};
    std::size_t observed = 0;
    const SimulationStatus status =
        simulate_samples(model, inputs, 0, 1000, x, s, buffers,
                         [&](std::size_t, const std::vector<double>&, const std::vector<double>&) {
                             ++observed;
                             return true;
                         });
    if (status == SimulationStatus::ok) CHECK(observed == 1000);
    return status;
}

const char* method_name(IntegrationMethod m) {
    return m == IntegrationMethod::rk4 ? "rk4" : m == IntegrationMethod::dopri5 ? "dopri5" : "rosenbrock4";
}

}  // namespace

TEST_CASE("every integrator ends a diverging, NaN or over-budget simulation with its status", "[simulate][faults]") {
    for (IntegrationMethod method : {IntegrationMethod::rk4, IntegrationMethod::dopri5, IntegrationMethod::rosenbrock4}) {
        INFO(method_name(method));
        // The healthy oscillator (ω = 20 rad/s) runs to the end: the faults below are the faults'.
        CHECK(simulate_oscillator(400.0, method, 10'000'000) == SimulationStatus::ok);
        // Negative stiffness: θ grows like e^{200 t} and passes the divergence limit long
        // before it overflows.
        CHECK(simulate_oscillator(-4.0e4, method, 10'000'000) == SimulationStatus::diverged);
        // A NaN stiffness: NaN at the first step.
        CHECK(simulate_oscillator(std::numeric_limits<double>::quiet_NaN(), method, 10'000'000) ==
              SimulationStatus::not_finite);
        // ω = 1e4 rad/s over 10 s at rtol 1e-8 needs far more than 500 adaptive steps; RK4
        // takes its fixed steps (one per sample) whatever the budget, so it cannot run away.
        const SimulationStatus budget = simulate_oscillator(1.0e8, method, 500);
        if (method == IntegrationMethod::rk4)
            CHECK(budget != SimulationStatus::step_budget_exceeded);
        else
            CHECK(budget == SimulationStatus::step_budget_exceeded);
    }
}

namespace {

const std::filesystem::path kCvt = source_dir() / "configs/cvt_tipin_clean.yaml";

// The CVT clean experiment's free parameters (rho1, k_minus, k_plus, c_minus, c_plus, mu,
// sigma, d_ds, d_tm) at the middle of their search box, with some replaced.
std::vector<double> candidate(std::initializer_list<std::pair<std::size_t, double>> changes = {}) {
    std::vector<double> c{1.5, 5000, 5000, 15, 15, 0.003, 3000, -7.5, 12.5};
    for (const auto& [j, v] : changes) c[j] = v;
    return c;
}

// The status of the estimation window's simulation for this candidate.
SimulationStatus window_status(const IdentificationProblem& problem, const std::vector<double>& free) {
    const auto ws = problem.make_workspace();
    return problem.trace(problem.full_parameters(free), problem.experiment().estimation[0], *ws).status;
}

// Passes the costs through and counts the +inf ones.
struct CountingEvaluator : CandidateEvaluator {
    explicit CountingEvaluator(CandidateEvaluator& wrapped) : inner(&wrapped) {}
    void evaluate(const double* c, std::size_t count, std::size_t dim, double* costs) override {
        inner->evaluate(c, count, dim, costs);
        for (std::size_t i = 0; i < count; ++i) failed += std::isinf(costs[i]) ? 1 : 0;
    }
    CandidateEvaluator* inner;
    long long failed = 0;
};

}  // namespace

TEST_CASE("a candidate whose simulation fails costs +inf", "[faults]") {
    const Experiment ex = load_experiment(kCvt);
    const IdentificationProblem problem(ex);
    REQUIRE(problem.dimension() == 9);
    const auto ws = problem.make_workspace();
    std::vector<double> r;
    const std::vector<double> healthy = candidate();
    REQUIRE(std::isfinite(problem.cost(healthy.data(), *ws)));
    REQUIRE(problem.residuals(healthy.data(), *ws, r));

    SECTION("diverged: contact stiffness far beyond what RK4 at the sampling interval can follow") {
        // ω = √(ρ1 k) = 1e4 rad/s in contact against h = 1 ms: RK4 amplifies every step.
        const std::vector<double> stiff = candidate({{0, 100.0}, {1, 1e6}, {2, 1e6}});
        CHECK(window_status(problem, stiff) == SimulationStatus::diverged);
        CHECK(std::isinf(problem.cost(stiff.data(), *ws)));
        CHECK_FALSE(problem.residuals(stiff.data(), *ws, r));
    }
    SECTION("not finite: a NaN parameter") {
        const std::vector<double> nan = candidate({{3, std::numeric_limits<double>::quiet_NaN()}});
        CHECK(std::isinf(problem.cost(nan.data(), *ws)));
        CHECK_FALSE(problem.residuals(nan.data(), *ws, r));
    }
    SECTION("step budget exceeded: dopri5 with a budget below one step per sample") {
        const Experiment tight = load_experiment(kCvt, {{"simulation.method", "dopri5"}, {"simulation.max_steps", "100"}});
        const IdentificationProblem tight_problem(tight);
        const auto tight_ws = tight_problem.make_workspace();
        CHECK(window_status(tight_problem, healthy) == SimulationStatus::step_budget_exceeded);
        CHECK(std::isinf(tight_problem.cost(healthy.data(), *tight_ws)));
    }
    // The workspace that saw a failure scores the next candidate as if fresh.
    CHECK(problem.cost(healthy.data(), *ws) == problem.cost(healthy.data(), *problem.make_workspace()));
}

TEST_CASE("the particle swarm counts every candidate whose simulation failed", "[faults][pso]") {
    // A search box reaching into contact stiffness RK4 cannot follow at 1 ms: part of the
    // swarm diverges. Every such candidate is +inf and counted, none stops the fit.
    const Experiment ex = load_experiment(kCvt, {{"parameters.rho1.range", "[1, 100]"},
                                                 {"parameters.k_minus.range", "[1.0e3, 1.0e6]"},
                                                 {"parameters.k_plus.range", "[1.0e3, 1.0e6]"}});
    const IdentificationProblem problem(ex);
    ParallelEvaluator parallel(problem, EvaluatorOptions(2));
    CountingEvaluator counting(parallel);
    PsoSettings s = ex.estimation_settings.pso;
    s.iterations = 3;
    const SearchBox box{problem.lower(), problem.upper(), problem.range_lower(), problem.range_upper()};
    const PsoSummary summary = run_pso(s, box, counting);
    CHECK(counting.failed > 0);                          // the box does reach the unstable corner
    CHECK(summary.failed_evaluations == counting.failed);  // each failure counted, once
    CHECK(summary.failed_evaluations < summary.evaluations);
    CHECK(std::isfinite(summary.best_cost));
    CHECK(summary.termination != "all candidates failed");
}

TEST_CASE("an evaluation says which window failed first and how many did", "[faults]") {
    const Experiment healthy = load_experiment(kCvt);
    const IdentificationProblem problem(healthy);
    const Evaluation ok = evaluate_parameters(problem, problem.full_parameters(candidate()));
    CHECK(first_failed_window(ok).empty());
    CHECK(failed_window_count(ok) == 0);
    // Contact stiffness RK4 cannot follow at the recording's step. The window that starts
    // in contact, [3, 3.5] s, is linearised there and takes substeps (stable_step.hpp); the
    // one that starts out of contact and crosses the tip-in (from 1.54 s) does not see the
    // contact coming and diverges; the quiet window before it, [1, 1.5] s, stays out of
    // contact.
    const Evaluation stiff =
        evaluate_parameters(problem, problem.full_parameters(candidate({{0, 100.0}, {1, 1e6}, {2, 1e6}})));
    // The account names the node, the sample interval and what to try.
    CHECK(first_failed_window(stiff).rfind(
              "estimation window time 1.5 to 3: diverged: node cvt_input_shaft's speed reached ", 0) == 0);
    CHECK(first_failed_window(stiff).find("after t = 1.701 s (by t = 1.702 s); a stiff candidate") != std::string::npos);
    CHECK(failed_window_count(stiff) == 1);
    REQUIRE(stiff.validation.windows.size() == 2);
    CHECK(stiff.validation.windows[0].trace.status == SimulationStatus::ok);
    CHECK(stiff.validation.windows[1].trace.status == SimulationStatus::ok);
    CHECK(problem.subdivided_starts() > 0);
}

}  // namespace TVID_UNITY_ID
