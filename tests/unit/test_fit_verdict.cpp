// The verdict of a fit (fit/fit_verdict.hpp): each finding is triggered by a constructed
// case and absent on a good fit. The data are a two-inertia line simulated at known
// parameters, with white noise of a known level added.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "support/test_files.hpp"
#include "tvid/analysis/step_stability.hpp"
#include "tvid/estimation/forward_sensitivity.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/fit/fit_run.hpp"
#include "tvid/fit/fit_verdict.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

constexpr double kStiffness = 100.0, kDamping = 0.5;  // the truth
constexpr int kSamples = 3000;                         // 3 s at 1 kHz

std::string experiment_text(const std::string& parameters) {
    return R"(tvid: 1
name: two-inertia
data: { file: rec.csv, time: t }
model:
  nodes: [ { name: motor, J: 0.1 }, { name: load, J: 0.2 } ]
  elements:
    - { type: torque, name: drive, node: motor, input: T_in }
    - { type: spring_damper, name: shaft, between: [motor, load], k: k_s, c: c_s }
    - { type: friction, name: bearing, node: load, c: 0.3 }
inputs: { T_in: u }
outputs:
  w_load: { column: w, speed: load }
parameters:
)" + parameters + R"(
windows:
  estimation: [ { samples: [0, 1500] } ]
  validation: [ { samples: [0, 2999] } ]   # from rest too: every window starts at sample 0
initial_state: rest
estimation: { optimizer: lm, cost: l2 }
)";
}

const std::string kFree = "  k_s: { init: 80, min: 1, max: 1000 }\n  c_s: { init: 0.8, min: 0.01, max: 10 }";

// The recording: a multisine torque, the load speed simulated at the truth plus white noise
// of `noise` rad/s (seeded: the same data on every run).
struct Bench {
    test::TempDir dir;
    explicit Bench(double noise) {
        std::vector<double> u(kSamples + 1);
        std::mt19937 random(7);
        std::uniform_real_distribution<double> phase(0.0, 6.283185307179586);
        std::vector<double> phases(20);
        for (double& p : phases) p = phase(random);
        for (int i = 0; i <= kSamples; ++i)
            for (int f = 1; f <= 20; ++f) u[static_cast<std::size_t>(i)] += std::sin(6.283185307179586 * f * i * 1e-3 + phases[static_cast<std::size_t>(f - 1)]);
        write(u, std::vector<double>(kSamples + 1, 0.0));
        // Simulate the truth over the whole recording, then add the noise.
        const Experiment truth = load("  k_s: { value: 100 }\n  c_s: { value: 0.5 }",
                                      {parse_override("windows.estimation=[{samples: [0, 3000]}]")});
        const IdentificationProblem problem(truth);
        auto ws = problem.make_workspace();
        const WindowTrace tr = problem.trace(problem.full_parameters(std::vector<double>{}), truth.estimation[0], *ws);
        REQUIRE(tr.status == SimulationStatus::ok);
        std::vector<double> w(kSamples + 1, 0.0);
        std::normal_distribution<double> gauss(0.0, noise);
        for (std::size_t k = 0; k < tr.samples.size(); ++k) w[tr.samples[k]] = tr.simulated[0][k];
        for (double& v : w) v += gauss(random);
        write(u, w);
    }
    void write(const std::vector<double>& u, const std::vector<double>& w) {
        std::string csv = "t,u,w\n";
        char line[96];
        for (std::size_t i = 0; i < u.size(); ++i) {
            std::snprintf(line, sizeof line, "%.6f,%.17g,%.17g\n", static_cast<double>(i) * 1e-3, u[i], w[i]);
            csv += line;
        }
        dir.write("rec.csv", csv);
    }
    Experiment load(const std::string& parameters, const std::vector<Override>& overrides = {}) {
        return load_experiment(dir.write("exp.yaml", experiment_text(parameters)), overrides);
    }
};

Bench& noisy_bench() {
    static Bench bench(0.002);
    return bench;
}

bool has(const Verdict& v, const std::string& code, Severity severity) {
    return std::any_of(v.findings.begin(), v.findings.end(),
                       [&](const Finding& f) { return f.code == code && f.severity == severity; });
}
bool has(const Verdict& v, const std::string& code) {
    return std::any_of(v.findings.begin(), v.findings.end(), [&](const Finding& f) { return f.code == code; });
}

FitResult fit(const Experiment& ex) {
    const IdentificationProblem problem(ex);
    FitOptions options;
    options.threads = 1;
    return run_fit(problem, options);
}

}  // namespace

TEST_CASE("a good fit of the true model on noisy data has a clean verdict", "[verdict]") {
    const Experiment ex = noisy_bench().load(kFree);
    const FitResult r = fit(ex);
    REQUIRE(r.success);
    CHECK(r.best_free[0] == Approx(kStiffness).epsilon(0.02));
    CHECK(r.best_free[1] == Approx(kDamping).epsilon(0.1));
    std::string findings;
    for (const Finding& f : r.verdict.findings) findings += f.code + ": " + f.message + "\n";
    INFO(findings);
    CHECK(r.verdict.summary() == "clean");
    REQUIRE(r.whiteness_estimation.size() == 1);
    // The residual is the added noise: its sample-to-sample estimate finds the level.
    CHECK(r.whiteness_estimation[0].noise_rms == Approx(0.002).epsilon(0.05));
    CHECK(r.whiteness_estimation[0].systematic_share < kSystematicShareWarning);
    CHECK(r.uncertainty.interval == std::vector<std::string>{"two-sided", "two-sided"});
}

TEST_CASE("a systematic misfit is an error, and --strict's rule sees it", "[verdict]") {
    // The stiffness fixed 30 % off: the resonance sits elsewhere, the residual is the misfit.
    const Experiment ex = noisy_bench().load("  k_s: { value: 70 }\n  c_s: { init: 0.8, min: 0.01, max: 10 }");
    const FitResult r = fit(ex);
    REQUIRE(r.success);
    CHECK(has(r.verdict, "residuals_not_white", Severity::error));
    CHECK(r.verdict.has_errors());
    CHECK(r.whiteness_estimation[0].systematic_share > kSystematicShareError);
    CHECK(r.whiteness_estimation[0].p_value < 1e-10);
}

TEST_CASE("a parameter on its bound is flagged and its interval is one-sided", "[verdict]") {
    const Experiment ex = noisy_bench().load("  k_s: { init: 50, min: 1, max: 80 }\n  c_s: { init: 0.8, min: 0.01, max: 10 }");
    const FitResult r = fit(ex);
    REQUIRE(r.success);
    CHECK(r.best_free[0] == Approx(80.0));
    CHECK(has(r.verdict, "at_bound"));
    REQUIRE(r.uncertainty.available);
    CHECK(r.uncertainty.interval[0] == "one-sided");
    CHECK(r.uncertainty.ci_high[0] == 80.0);  // from the bound inwards, never past it
    CHECK(r.uncertainty.ci_low[0] < 80.0);
}

TEST_CASE("an optimizer stopped by its budget is not converged", "[verdict]") {
    const Experiment ex = noisy_bench().load(kFree, {parse_override("estimation.lm.max_iterations=1")});
    const FitResult r = fit(ex);
    REQUIRE(r.success);
    CHECK_FALSE(r.run.converged);
    CHECK(has(r.verdict, "not_converged", Severity::warning));
}

TEST_CASE("a stiff mode close to RK4's stability limit is flagged", "[verdict]") {
    // ω² = k (1/J1 + 1/J2) = k · 15: with k = 3.85e5, ω ≈ 2403 rad/s and ωh = 2.40 against
    // the limit 2√2 on the imaginary axis (lightly damped): 85 % of it, within the 90 % a
    // simulation keeps (stable_step.hpp), and past the 80 % the verdict warns of.
    const Experiment ex = noisy_bench().load("  k_s: { init: 3.85e5, min: 1e5, max: 3.9e5 }\n  c_s: { value: 0.5 }",
                                             {parse_override("estimation.lm.max_iterations=0")});
    const IdentificationProblem problem(ex);
    const StepStability s = assess_step_stability(problem, problem.full_parameters(problem.initial()));
    REQUIRE(s.assessed);
    CHECK(s.substeps == 1);
    CHECK(s.margin == Approx(std::sqrt(3.85e5 * 15) * 1e-3 / rk4_stability_radius(1.5707963267948966)).epsilon(0.01));
    CHECK(s.margin > kStepMarginWarning);
    CHECK(s.frequency_hz == Approx(std::sqrt(3.85e5 * 15) / (2 * 3.141592653589793)).epsilon(0.01));
    // The fit's verdict says it; the true stiffness does not come near.
    CHECK(has(fit(ex).verdict, "near_instability", Severity::warning));
    CHECK_FALSE(has(fit(noisy_bench().load(kFree)).verdict, "near_instability"));
}

TEST_CASE("a window in substeps near their limit is information on time, not a warning of instability", "[verdict]") {
    // k = 1.54e6: ωh at the experiment's step of 1 ms is 170 % of RK4's limit, so the window
    // takes two substeps, each at 85 %: past the 80 % that warns for one step, yet no
    // candidate can blow up, since a stiffer one takes more substeps.
    const Experiment ex = noisy_bench().load("  k_s: { init: 1.54e6, min: 1e5, max: 1.6e6 }\n  c_s: { value: 0.5 }",
                                             {parse_override("estimation.lm.max_iterations=0")});
    const IdentificationProblem problem(ex);
    const StepStability s = assess_step_stability(problem, problem.full_parameters(problem.initial()));
    REQUIRE(s.assessed);
    CHECK(s.substeps == 2);
    CHECK(s.margin > kStepMarginWarning);
    const FitResult r = fit(ex);
    CHECK_FALSE(has(r.verdict, "near_instability"));
    CHECK(has(r.verdict, "substeps", Severity::info));
}

TEST_CASE("a stiff mode past RK4's stability limit takes substeps and is simulated within it", "[verdict]") {
    // k = 4.6e5: ωh = 2.63, 93 % of the limit at the experiment's step of 1 ms. The window
    // takes two substeps (stable_step.hpp), so its simulation sits at 46 %.
    const Experiment ex = noisy_bench().load("  k_s: { init: 4.6e5, min: 1e5, max: 4.7e5 }\n  c_s: { value: 0.5 }",
                                             {parse_override("estimation.lm.max_iterations=0")});
    const IdentificationProblem problem(ex);
    const StepStability s = assess_step_stability(problem, problem.full_parameters(problem.initial()));
    REQUIRE(s.assessed);
    CHECK(s.substeps == 2);
    CHECK(s.step == Approx(0.5e-3));
    CHECK(s.margin == Approx(0.5 * std::sqrt(4.6e5 * 15) * 1e-3 / rk4_stability_radius(1.5707963267948966)).epsilon(0.01));
    const FitResult r = fit(ex);
    CHECK_FALSE(has(r.verdict, "near_instability"));
    CHECK(problem.subdivided_starts() > 0);
    // Its cost is the cost at the substep given as the experiment's step, to the bit.
    const Experiment halved = noisy_bench().load("  k_s: { init: 4.6e5, min: 1e5, max: 4.7e5 }\n  c_s: { value: 0.5 }",
                                                 {parse_override("simulation.step=5e-4")});
    const IdentificationProblem fine(halved);
    auto ws = problem.make_workspace();
    auto fine_ws = fine.make_workspace();
    const double cost = problem.cost(problem.initial().data(), *ws);
    CHECK(std::isfinite(cost));
    CHECK(cost == fine.cost(fine.initial().data(), *fine_ws));
    CHECK(fine.subdivided_starts() == 0);
}

TEST_CASE("a candidate too stiff for the substeps takes sdirk3's steps: sdirk3's cost and Jacobian to the bit",
          "[verdict]") {
    // k = 1e10: ωh = 387 at the 1 ms step, 137 times RK4's limit, beyond the 64 substeps a
    // window may take (stable_step.hpp). The window is simulated by sdirk3 at the step, as
    // `method: sdirk3` simulates it: the shaft's mode decays within the step, the cost is
    // finite where RK4 at the step would blow up.
    const std::string stiff = "  k_s: { init: 1e10, min: 1e5, max: 1e11 }\n  c_s: { init: 0.5, min: 0.01, max: 10 }";
    const IdentificationProblem problem(noisy_bench().load(stiff));
    const IdentificationProblem sdirk3(noisy_bench().load(stiff, {parse_override("simulation.method=sdirk3")}));
    const std::vector<double> x = problem.initial();
    auto ws = problem.make_workspace();
    auto sdirk3_ws = sdirk3.make_workspace();
    const double cost = problem.cost(x.data(), *ws);
    CHECK(std::isfinite(cost));
    CHECK(cost == sdirk3.cost(x.data(), *sdirk3_ws));
    CHECK(problem.implicit_starts() > 0);
    CHECK(problem.subdivided_starts() == 0);
    CHECK(sdirk3.implicit_starts() == 0);
    // The sensitivities: the packed RK4 path hands such a window to sdirk3's augmented one.
    std::vector<double> r;
    REQUIRE(problem.residuals(x.data(), *ws, r));
    const ForwardSensitivity forward(problem), forward_sdirk3(sdirk3);
    auto fws = forward.make_workspace();
    auto sfws = forward_sdirk3.make_workspace();
    const auto rows = static_cast<Eigen::Index>(r.size());
    Eigen::MatrixXd J(rows, 2), J_sdirk3(rows, 2);
    REQUIRE(forward.jacobian_columns(x.data(), 0, 2, *fws, J));
    REQUIRE(forward_sdirk3.jacobian_columns(x.data(), 0, 2, *sfws, J_sdirk3));
    CHECK(J.allFinite());
    CHECK(J.col(1).norm() > 0);
    CHECK(J == J_sdirk3);
    // The verdict says so, as information: no candidate can blow up for it.
    const StepStability s = assess_step_stability(problem, problem.full_parameters(x));
    CHECK(s.assessed);
    CHECK(s.implicit);
    const FitResult fitted = fit(noisy_bench().load(stiff, {parse_override("estimation.lm.max_iterations=0")}));
    CHECK(has(fitted.verdict, "implicit_steps", Severity::info));
    CHECK_FALSE(has(fitted.verdict, "near_instability"));
    CHECK_FALSE(has(fitted.verdict, "substeps"));
}

TEST_CASE("RK4's stability region: 2.785 on the negative real axis, 2√2 on the imaginary", "[verdict]") {
    CHECK(rk4_stability_radius(3.141592653589793) == Approx(2.785293563).epsilon(1e-6));
    CHECK(rk4_stability_radius(1.5707963267948966) == Approx(2.0 * std::sqrt(2.0)).epsilon(1e-6));
    CHECK(rk4_stability_radius(0.1) == rk4_stability_radius(1.5707963267948966));  // right half-plane: as the axis
}

TEST_CASE("RK4's stability edge is nowhere nearer the origin than kRk4RadiusLowerBound, and the bound is tight",
          "[verdict]") {
    // stable_step_plan skips the edge's search below kStableMargin · the bound: a bound above
    // the edge anywhere would leave a stiff candidate without its substeps.
    double nearest = 4.0, where = 0.0;
    for (int i = 0; i <= 8000; ++i) {
        const double angle = 1.5707963267948966 * (1.0 + i / 8000.0);
        const double r = rk4_stability_radius(angle);
        if (r < nearest) nearest = r, where = angle;
    }
    CHECK(nearest > kRk4RadiusLowerBound);
    CHECK(nearest < kRk4RadiusLowerBound * 1.01);
    CHECK(where == Approx(2.142).margin(0.01));
}

TEST_CASE("validation much worse than estimation, and a second optimum among the starts", "[verdict]") {
    const Experiment ex = noisy_bench().load(kFree);
    const IdentificationProblem problem(ex);
    FitOptions options;
    options.threads = 1;
    FitResult r = run_fit(problem, options);
    REQUIRE(r.success);
    REQUIRE_FALSE(has(r.verdict, "validation_worse"));
    REQUIRE_FALSE(has(r.verdict, "non_unique_optimum"));

    SECTION("a slow misfit of 5 times the noise added to the validation") {
        for (WindowEvaluation& w : r.evaluation.validation.windows)
            for (std::size_t i = 0; i < w.trace.simulated[0].size(); ++i)
                w.trace.simulated[0][i] += 0.01 * std::sin(2 * 3.141592653589793 * 2.0 * w.trace.time[i]);
        judge_fit(problem, r);
        CHECK(has(r.verdict, "validation_worse", Severity::error));
    }
    SECTION("more noise in the validation is not a worse fit") {
        for (WindowEvaluation& w : r.evaluation.validation.windows)
            for (std::size_t i = 0; i < w.trace.simulated[0].size(); ++i)
                w.trace.simulated[0][i] = w.trace.measured[0][i] - 3.0 * (w.trace.measured[0][i] - w.trace.simulated[0][i]);
        judge_fit(problem, r);
        CHECK_FALSE(has(r.verdict, "validation_worse"));
    }
    SECTION("another start as low, at a stiffness twice as high") {
        StartResult best, other;
        best.start = 1;
        best.best = r.best_free;
        best.best_cost = r.run.best_cost;
        other = best;
        other.start = 2;
        other.best[0] *= 2.0;
        other.best_cost *= 1.001;
        r.run.starts = {best, other};
        r.run.best_start = 1;
        judge_fit(problem, r);
        CHECK(has(r.verdict, "non_unique_optimum", Severity::warning));
        SECTION("but not when its cost is clearly higher") {
            r.run.starts[1].best_cost = 1.5 * r.run.best_cost;
            judge_fit(problem, r);
            CHECK_FALSE(has(r.verdict, "non_unique_optimum"));
        }
    }
    SECTION("a weakly determined and an undetermined parameter") {
        r.uncertainty.std_error[1] = 2.0 * r.best_free[1];  // twice its value
        judge_fit(problem, r);
        CHECK(has(r.verdict, "weakly_determined", Severity::warning));
        r.uncertainty.rank = 1;
        r.uncertainty.determined = {false, false};
        r.uncertainty.std_error = {std::nan(""), std::nan("")};
        r.uncertainty.null_directions = {{0.6, 0.8}};
        judge_fit(problem, r);
        CHECK(has(r.verdict, "undetermined", Severity::warning));
    }
    SECTION("a window with a systematic misfit that the pooled figure hides") {
        WindowEvaluation second = r.evaluation.validation.windows[0];
        for (std::size_t i = 0; i < second.trace.simulated[0].size(); ++i)
            second.trace.simulated[0][i] += 0.05 * std::sin(2 * 3.141592653589793 * second.trace.time[i]);
        second.metrics[0].fit_percent = -12.0;
        r.evaluation.validation.windows.push_back(second);
        judge_fit(problem, r);
        CHECK(has(r.verdict, "poor_window", Severity::warning));
    }
    SECTION("a window that cannot be simulated at the optimum") {
        r.evaluation.validation.windows[0].trace.status = SimulationStatus::diverged;
        r.evaluation.validation.windows[0].trace.problem = "simulation diverged";
        judge_fit(problem, r);
        CHECK(has(r.verdict, "window_failed", Severity::error));
    }
    SECTION("a fit without a result, and an interrupted one") {
        r.interrupted = true;
        judge_fit(problem, r);
        CHECK(has(r.verdict, "interrupted", Severity::warning));
        r.success = false;
        judge_fit(problem, r);
        CHECK(has(r.verdict, "no_result", Severity::error));
    }
    SECTION("a share of failed simulations, and failed starts") {
        r.run.evaluations = 100;
        r.run.failed_evaluations = 40;
        StartResult failed;
        failed.start = 1;
        failed.best_cost = std::numeric_limits<double>::infinity();
        r.run.starts = {failed};
        judge_fit(problem, r);
        CHECK(has(r.verdict, "failed_simulations", Severity::warning));
        CHECK(has(r.verdict, "failed_starts", Severity::warning));
    }
}

TEST_CASE("the verdict orders findings by severity and counts them", "[verdict]") {
    Verdict v;
    CHECK(v.summary() == "clean");
    v.add({"a", Severity::warning, "", "", ""});
    v.add({"b", Severity::info, "", "", ""});
    v.add({"c", Severity::error, "", "", ""});
    v.add({"d", Severity::warning, "", "", ""});
    REQUIRE(v.findings.size() == 4);
    CHECK(v.findings[0].code == "c");
    CHECK(v.findings[1].code == "a");
    CHECK(v.findings[2].code == "d");
    CHECK(v.findings[3].code == "b");
    CHECK(v.summary() == "1 error, 2 warnings");
    CHECK(v.has_errors());
}

TEST_CASE("a linear search box of three decades is flagged, and scale: log clears it", "[verdict]") {
    // k_s in [1, 1000] with no range: multistart samples it linearly.
    const std::vector<Override> multistart{parse_override("estimation.optimizer=multistart"),
                                           parse_override("estimation.multistart.starts=2")};
    const FitResult linear = fit(noisy_bench().load(kFree, multistart));
    REQUIRE(linear.success);
    CHECK(has(linear.verdict, "wide_linear_box", Severity::warning));
    const FitResult log = fit(noisy_bench().load(
        "  k_s: { init: 80, min: 1, max: 1000, scale: log }\n  c_s: { init: 0.8, min: 0.01, max: 10, scale: log }", multistart));
    REQUIRE(log.success);
    CHECK_FALSE(has(log.verdict, "wide_linear_box"));
    CHECK(log.best_free[0] == Approx(linear.best_free[0]).epsilon(1e-4));
    // lm starts at init: its box is only a bound.
    CHECK_FALSE(has(fit(noisy_bench().load(kFree)).verdict, "wide_linear_box"));
}

}  // namespace TVID_UNITY_ID
