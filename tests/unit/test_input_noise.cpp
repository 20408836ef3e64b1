// A logged input's declared noise (`inputs: { T: { column: u, noise: s } }`), carried to the
// outputs (analysis/input_noise.hpp), the residual tests against it (residual_whiteness.hpp,
// residual_correlation.hpp) and the standard errors that hold with it (uncertainty.hpp).
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "support/test_files.hpp"
#include "tvid/analysis/input_noise.hpp"
#include "tvid/analysis/residual_correlation.hpp"
#include "tvid/analysis/residual_whiteness.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/fit/fit_run.hpp"
#include "tvid/fit/fit_verdict.hpp"
#include "tvid/util/input_error.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

constexpr double kDt = 1e-3;
constexpr int kSamples = 10000;  // 10 s at 1 kHz

// One inertia J on a viscous bearing c, driven by a torque T: w' = (T − c w)/J, time constant
// J/c = 0.1 s. `noise` is the input channel's entry (", noise: s" or "").
std::string experiment_text(const std::string& input_column, const std::string& noise, const std::string& free) {
    return R"(tvid: 1
name: one-inertia
data: { file: rec.csv, time: t }
model:
  nodes: [ { name: m, J: J } ]
  elements:
    - { type: torque, name: drive, node: m, input: T }
    - { type: friction, name: bearing, node: m, c: c }
inputs: { T: { column: )" + input_column + noise + R"( } }
outputs:
  w: { column: w, speed: m }
parameters:
)" + free + R"(
windows:
  estimation: [ { samples: [0, 10000] } ]
initial_state: rest
estimation: { optimizer: lm, cost: l2 }
)";
}

const std::string kFixed = "  J: { value: 0.1 }\n  c: { value: 1 }";
const std::string kFree = "  J: { init: 0.12, min: 0.01, max: 1 }\n  c: { init: 0.8, min: 0.01, max: 10 }";

// The recording: a torque of a few sines (u), as logged with white noise of 1 N m (u_logged),
// and the speed the line made from u, simulated by tvid at the truth, with 0.002 rad/s of
// white sensor noise (seeded).
struct Bench {
    test::TempDir dir;
    Bench() {
        std::vector<double> u(kSamples + 1), logged(u.size()), w(u.size(), 0.0);
        std::mt19937 random(11);
        std::normal_distribution<double> gauss(0.0, 1.0);
        for (std::size_t i = 0; i < u.size(); ++i) {
            const double t = static_cast<double>(i) * kDt;
            u[i] = 2.0 * std::sin(6.283185307179586 * 0.7 * t) + std::sin(6.283185307179586 * 3.1 * t + 1.0) +
                   0.5 * std::sin(6.283185307179586 * 11.0 * t + 2.0);
            logged[i] = u[i] + gauss(random);
        }
        write(u, logged, w);
        const Experiment truth = load("u", "", kFixed);
        const IdentificationProblem problem(truth);
        auto ws = problem.make_workspace();
        const WindowTrace tr = problem.trace(problem.full_parameters(std::vector<double>{}), truth.estimation[0], *ws);
        REQUIRE(tr.status == SimulationStatus::ok);
        for (std::size_t k = 0; k < tr.samples.size(); ++k) w[tr.samples[k]] = tr.simulated[0][k] + 0.002 * gauss(random);
        write(u, logged, w);
    }
    void write(const std::vector<double>& u, const std::vector<double>& logged, const std::vector<double>& w) {
        std::string csv = "t,u,u_logged,w\n";
        char line[128];
        for (std::size_t i = 0; i < u.size(); ++i) {
            std::snprintf(line, sizeof line, "%.6f,%.17g,%.17g,%.17g\n", static_cast<double>(i) * kDt, u[i], logged[i], w[i]);
            csv += line;
        }
        dir.write("rec.csv", csv);
    }
    Experiment load(const std::string& column, const std::string& noise, const std::string& parameters) {
        return load_experiment(dir.write("exp.yaml", experiment_text(column, noise, parameters)));
    }
};

Bench& bench() {
    static Bench b;
    return b;
}

FitResult fit(const Experiment& ex) {
    const IdentificationProblem problem(ex);
    FitOptions options;
    options.threads = 1;
    return run_fit(problem, options);
}

}  // namespace

TEST_CASE("input noise through one inertia on a bearing: the speed's variance is sigma^2 dt / (2 J c)", "[input_noise]") {
    const Experiment ex = bench().load("u_logged", ", noise: 1", kFixed);
    const IdentificationProblem problem(ex);
    const std::vector<const Window*> windows{&problem.definition().estimation[0]};
    const std::vector<double> params = problem.full_parameters(std::vector<double>{});
    const InputNoiseResponses responses = input_noise_responses(problem, params, windows, 8, 1);
    REQUIRE(responses.delta.size() == 8);
    const PropagatedInputNoise p = propagated_covariance(responses, 1, 1000);
    REQUIRE(p.available);
    // A white sequence of variance σ² per sample, held linearly between samples, acts as white
    // noise of intensity σ² dt; through 1/(J s + c) the stationary variance is σ² dt / (2 J c),
    // reached from rest within a few J/(2c) = 0.05 s of the 10 s window (a 0.5 % lower mean).
    const double stationary = 1.0 * kDt / (2.0 * 0.1 * 1.0);
    CHECK(p.covariance[0][0][0] == Approx(stationary * 0.995).epsilon(0.1));
    // An AR(1) of pole exp(−c dt / J): its covariance at lag l falls as exp(−l c dt / J).
    CHECK(p.covariance[0][0][50] / p.covariance[0][0][0] == Approx(std::exp(-50 * kDt / 0.1)).margin(0.08));
    // Its reach: below 5 % from ln 20 · J / (c dt) = 300 lags on, or below its estimate's
    // noise (three standard errors: about 0.1 here, from 230 lags on).
    CHECK(p.correlation_lags > 150);
    CHECK(p.correlation_lags < 400);
    // E[n(t) δ(t + τ)]: σ² times the impulse response's sample, dt/J · exp(−τ c dt / J), half a
    // sample's weight at τ = 0 (the interpolated noise acts from its sample on).
    REQUIRE(responses.input_cross.size() == 1);
    CHECK(responses.input_cross[0][0][10] == Approx(kDt / 0.1 * std::exp(-10 * kDt / 0.1)).epsilon(0.15));
}

TEST_CASE("the propagated input noise is the same on 1 and 2 threads", "[input_noise]") {
    const Experiment ex = bench().load("u_logged", ", noise: 1", kFixed);
    const IdentificationProblem problem(ex);
    const std::vector<const Window*> windows{&problem.definition().estimation[0]};
    const std::vector<double> params = problem.full_parameters(std::vector<double>{});
    const InputNoiseResponses one = input_noise_responses(problem, params, windows, 4, 1);
    const InputNoiseResponses two = input_noise_responses(problem, params, windows, 4, 2);
    CHECK(one.delta == two.delta);
    CHECK(one.input_cross == two.input_cross);
}

TEST_CASE("the whiteness test against a noise model: coloured noise of the declared level passes, a misfit does not",
          "[input_noise][whiteness]") {
    std::mt19937 random(5);
    std::normal_distribution<double> gauss(0.0, 1.0);
    // e = white (σ 0.5) + an AR(1) of pole 0.95 driven by unit innovations: c_l = 0.95^l / (1 − 0.95²).
    const double pole = 0.95, c0 = 1.0 / (1.0 - pole * pole);
    std::vector<double> e(20000), misfit(e.size());
    double ar = 0.0;
    for (std::size_t t = 0; t < e.size(); ++t) {
        ar = pole * ar + gauss(random);
        e[t] = ar + 0.5 * gauss(random);
        misfit[t] = e[t] + 6.0 * std::sin(0.3 * static_cast<double>(t));  // a ringing the model misses
    }
    std::vector<double> coloured(60);
    for (std::size_t l = 0; l < coloured.size(); ++l) coloured[l] = c0 * std::pow(pole, static_cast<double>(l));
    const ResidualWhiteness plain = assess_whiteness({e});
    CHECK(plain.systematic_share > 0.5);  // alone, the coloured noise looks like a misfit
    const ResidualWhiteness against = assess_whiteness_against({e}, coloured);
    CHECK(against.systematic_share < 0.05);
    CHECK(against.propagated_noise_rms == Approx(std::sqrt(c0)));
    CHECK(against.propagated_noise_level == Approx(1.0).epsilon(0.15));  // this recording's level
    CHECK(against.rms == Approx(plain.rms));
    const ResidualWhiteness wrong = assess_whiteness_against({misfit}, coloured);
    CHECK(wrong.systematic_share > 0.5);
    CHECK(wrong.p_value < 1e-6);
}

TEST_CASE("the cross-correlation test expects what an input's noise leaves in the residual", "[input_noise][correlation]") {
    std::mt19937 random(9);
    std::normal_distribution<double> gauss(0.0, 1.0);
    // The simulation reads u + n; the residual holds −δ, δ = an AR(1) of the noise n.
    const double pole = 0.8;
    std::vector<double> u(20000), e(u.size());
    double delta = 0.0;
    for (std::size_t t = 0; t < u.size(); ++t) {
        const double n = gauss(random);
        delta = pole * delta + n;
        u[t] = gauss(random) + n;  // a white excitation, logged with the noise
        e[t] = -delta + 0.1 * gauss(random);
    }
    std::vector<double> expected(kCorrelationLags + 1);  // E[n(t) δ(t + τ)] = pole^τ
    for (std::size_t l = 0; l < expected.size(); ++l) expected[l] = std::pow(pole, static_cast<double>(l));
    const CorrelationTest plain = cross_correlation_test({u}, {e}, kCorrelationLags);
    const CorrelationTest with_noise = cross_correlation_test({u}, {e}, kCorrelationLags, expected);
    CHECK(plain.outside_from(0) > 10);
    CHECK(with_noise.outside_from(0) <= 2);
    REQUIRE(with_noise.expected.size() == with_noise.values.size());
    CHECK(with_noise.expected[kCorrelationLags] < 0);  // τ = 0: −E[n δ] / norm
}

TEST_CASE("with the input's noise declared, the standard errors grow to hold it and the verdict is clean",
          "[input_noise][uncertainty]") {
    const FitResult declared = fit(bench().load("u_logged", ", noise: 1", kFree));
    const FitResult undeclared = fit(bench().load("u_logged", "", kFree));
    REQUIRE(declared.success);
    REQUIRE(undeclared.success);
    CHECK(declared.best_free == undeclared.best_free);  // the noise changes the judgement, not the fit
    CHECK(declared.uncertainty.input_noise);
    CHECK_FALSE(undeclared.uncertainty.input_noise);
    const double truth[] = {0.1, 1.0};
    for (std::size_t j = 0; j < 2; ++j) {
        const double se = declared.uncertainty.std_error[j], plain = undeclared.uncertainty.std_error[j];
        INFO("parameter " << j << ": " << declared.best_free[j] << " +- " << se << " (undeclared +- " << plain << ")");
        CHECK(se > 3.0 * plain);  // the sensor's 0.002 rad/s is a small part of the residual
        CHECK(std::abs(declared.best_free[j] - truth[j]) < 3.0 * declared.uncertainty.robust_std_error[j]);
        CHECK(declared.uncertainty.robust_std_error[j] >= se);
    }
    std::string findings;
    for (const Finding& f : declared.verdict.findings) findings += f.code + ": " + f.message + "\n";
    INFO(findings);
    CHECK_FALSE(declared.verdict.has_errors());
    REQUIRE(declared.whiteness_estimation.size() == 1);
    CHECK(declared.whiteness_estimation[0].propagated_noise_rms > 0.02);
    CHECK(declared.whiteness_estimation[0].systematic_share < kSystematicShareWarning);
}

TEST_CASE("an input's noise must be a positive number, in the column's unit", "[input_noise][loader]") {
    for (const std::string bad : {", noise: 0", ", noise: -1", ", noise: lots"}) {
        INFO(bad);
        try {
            bench().load("u_logged", bad, kFixed);
            FAIL("accepted");
        } catch (const InputError& e) {
            CHECK(std::string(e.what()).find("inputs.T.noise") != std::string::npos);
        }
    }
    const Experiment ex = bench().load("u_logged", ", scale: 2, noise: 0.5", kFixed);
    CHECK(ex.inputs[0].noise == 1.0);  // in the column's unit, converted with it
}

}  // namespace TVID_UNITY_ID
