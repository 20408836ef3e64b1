// A channel's delay as a parameter (`delay: NAME`): the same reading as the fixed delay
// of that value, a Jacobian column that matches differences, and a fit that finds a delay
// written into noise-free data: a whole number of samples on an output, a fraction of a
// sample on an input.
#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "support/test_files.hpp"
#include "tvid/analysis/frf_comparison.hpp"
#include "tvid/estimation/residual_evaluator.hpp"
#include "tvid/estimation/forward_sensitivity.hpp"
#include "tvid/estimation/identification_problem.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/fit/fit_run.hpp"
#include "tvid/model/parameter_units.hpp"
#include "tvid/util/input_error.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

// Two inertias on a shaft, driven by a measured torque; the load's speed and the shaft's
// torque are measured. INPUT and OUTPUTS are filled in per test.
std::string experiment_text(const std::string& input, const std::string& speed_output, const std::string& parameters) {
    return R"(tvid: 1
name: delays
data: { file: rec.csv, time: t }
model:
  nodes: [ { name: motor, J: 0.01 }, { name: load, J: 0.02 } ]
  elements:
    - { type: torque, name: drive, node: motor, input: T_in }
    - { type: spring_damper, name: shaft, between: [motor, load], k: k_s, c: 0.05 }
    - { type: friction, name: bearing, node: load, c: 0.02 }
inputs: { T_in: )" + input + R"( }
outputs:
  w_load:  )" + speed_output + R"(
  T_shaft: { column: T, torque: shaft }
parameters:
  k_s: { init: 40, min: 1, max: 1000 }
)" + parameters + R"(
windows: { estimation: [ { samples: [0, 1999] } ] }
initial_state: rest
simulation: { method: rk4, step: 1.0e-3 }
estimation: { cost: l2, optimizer: lm, lm: { max_iterations: 60 } }
)";
}

// The drive torque: two sines, 3 and 11 Hz.
double drive(double t) {
    return std::sin(2 * std::numbers::pi * 3 * t) + 0.5 * std::sin(2 * std::numbers::pi * 11 * t + 0.3);
}

struct Recording {
    std::vector<double> t, u, w, T;
    std::string csv() const {
        std::ostringstream out;
        out.precision(17);
        out << "t,u,w,T\n";
        for (std::size_t i = 0; i < t.size(); ++i) out << t[i] << ',' << u[i] << ',' << w[i] << ',' << T[i] << '\n';
        return out.str();
    }
};

// The model's outputs at k_s = 40 when the torque u is applied, at 1 kHz for 2 s.
Recording simulated(const test::TempDir& dir, const std::vector<double>& u) {
    Recording r;
    for (int i = 0; i < 2000; ++i) r.t.push_back(i * 1e-3);
    r.u = u;
    r.w.assign(r.t.size(), 0.0);
    r.T.assign(r.t.size(), 0.0);
    dir.write("rec.csv", r.csv());
    const Experiment ex = load_experiment(dir.write("truth.yaml", experiment_text("u", "{ column: w, speed: load }", "")));
    const IdentificationProblem problem(ex);
    auto ws = problem.make_workspace();
    const WindowTrace tr = problem.trace(problem.full_parameters(std::vector<double>{40.0}), ex.estimation[0], *ws);
    REQUIRE(tr.status == SimulationStatus::ok);
    for (std::size_t s = 0; s < tr.samples.size(); ++s) {
        r.w[tr.samples[s]] = tr.simulated[0][s];
        r.T[tr.samples[s]] = tr.simulated[1][s];
    }
    dir.write("rec.csv", r.csv());
    return r;
}

// The experiment scored short of the recording's end, where a delayed channel is held.
std::string scored_inside(std::string text) {
    const std::string all = "[0, 1999]";
    return text.replace(text.find(all), all.size(), "[0, 1989]");
}

// The experiment, scored short of the recording's end, fitted with lm on 2 threads to the
// recording in dir.
FitResult fitted(const test::TempDir& dir, const std::string& input, const std::string& speed_output,
                 const std::string& parameters) {
    const Experiment ex = load_experiment(dir.write("e.yaml", scored_inside(experiment_text(input, speed_output, parameters))));
    FitOptions options;
    options.threads = 2;
    FitResult fit = run_fit(IdentificationProblem(ex), options);
    REQUIRE(fit.success);
    return fit;
}

std::vector<double> drive_samples(double late) {
    std::vector<double> u;
    for (int i = 0; i < 2000; ++i) u.push_back(drive(i * 1e-3 - late));
    return u;
}

}  // namespace

TEST_CASE("a delay parameter reads the channel as the fixed delay of its value does", "[delay]") {
    test::TempDir dir;
    simulated(dir, drive_samples(0.0));
    const auto cost_of = [&](const std::string& input, const std::string& output, const std::string& parameters) {
        const Experiment ex = load_experiment(dir.write("e.yaml", experiment_text(input, output, parameters)));
        const IdentificationProblem problem(ex);
        auto ws = problem.make_workspace();
        std::vector<double> out;
        REQUIRE(problem.residuals(problem.initial().data(), *ws, out));
        return out;
    };
    const std::string speed = "{ column: w, speed: load }";
    SECTION("on an input") {
        const std::vector<double> fixed = cost_of("{ column: u, delay: 0.0037 }", speed, "");
        const std::vector<double> free =
            cost_of("{ column: u, delay: d_u }", speed, "  d_u: { init: 0.0037, min: -0.01, max: 0.01 }");
        REQUIRE(free.size() == fixed.size());
        for (std::size_t i = 0; i < free.size(); ++i) REQUIRE(free[i] == fixed[i]);
        const std::vector<double> none = cost_of("u", speed, "");
        CHECK(none != fixed);  // the delay changed the residuals
    }
    SECTION("on an output") {
        const std::vector<double> fixed = cost_of("u", "{ column: w, speed: load, delay: -0.0021 }", "");
        const std::vector<double> free = cost_of("u", "{ column: w, speed: load, delay: d_w }",
                                                 "  d_w: { init: -0.0021, min: -0.01, max: 0.01 }");
        REQUIRE(free.size() == fixed.size());
        for (std::size_t i = 0; i < free.size(); ++i) REQUIRE(free[i] == fixed[i]);
    }
}

TEST_CASE("a delay parameter's Jacobian column matches central differences", "[delay][jacobian]") {
    test::TempDir dir;
    simulated(dir, drive_samples(0.0));
    const std::string text = experiment_text("{ column: u, delay: d_u }", "{ column: w, speed: load, delay: d_w }",
                                             "  d_u: { init: 0.0013, min: -0.01, max: 0.01 }\n"
                                             "  d_w: { init: 0.0024, min: -0.01, max: 0.01 }");
    const Experiment ex = load_experiment(dir.write("e.yaml", text));
    const IdentificationProblem problem(ex);
    REQUIRE(problem.dimension() == 3);
    const std::vector<double> x{55.0, 0.0013, 0.0024};  // a k_s off the truth: the residuals are not small
    const auto jacobian = [&](JacobianKind kind) {
        ResidualEvaluator ls(problem, EvaluatorOptions(1).with_jacobian(kind));
        Eigen::MatrixXd J(static_cast<Eigen::Index>(ls.residual_count()), 3);
        std::vector<double> r(ls.residual_count());
        REQUIRE(ls.jacobian(x.data(), r.data(), J));
        return J;
    };
    const Eigen::MatrixXd sens = jacobian(JacobianKind::sensitivity), fd = jacobian(JacobianKind::fd);
    for (Eigen::Index j = 0; j < 3; ++j) {
        INFO("column " << j);
        CHECK(sens.col(j).norm() > 0);
        CHECK((sens.col(j) - fd.col(j)).norm() <= 1e-4 * fd.col(j).norm());
    }
    // tvid sensitivity's columns are the residuals' too: row s·2 + k of J is output k's
    // derivative at scored sample s, times the output's factor.
    const ForwardSensitivity forward(problem);
    auto ws = forward.make_workspace();
    const WindowSensitivity ranked = forward.window_sensitivity(x.data(), ex.estimation[0], *ws);
    REQUIRE(ranked.status == SimulationStatus::ok);
    const std::vector<double>& factor = problem.definition().output_scale;
    for (std::size_t j = 0; j < 3; ++j)
        for (std::size_t k = 0; k < 2; ++k) {
            INFO("column " << j << ", output " << k);
            Eigen::VectorXd column(static_cast<Eigen::Index>(ranked.time.size()));
            Eigen::VectorXd reference(column.size());
            for (std::size_t s = 0; s < ranked.time.size(); ++s) {
                column(static_cast<Eigen::Index>(s)) = factor[k] * ranked.dydp[k][j][s];
                reference(static_cast<Eigen::Index>(s)) = fd(static_cast<Eigen::Index>(2 * s + k), static_cast<Eigen::Index>(j));
            }
            CHECK((column - reference).norm() <= 1e-4 * reference.norm() + 1e-12);
        }
}

TEST_CASE("a fit finds a delay written into noise-free data", "[delay][fit]") {
    test::TempDir dir;
    SECTION("an output recorded two samples late") {
        Recording r = simulated(dir, drive_samples(0.0));
        std::vector<double> late(r.w.size(), 0.0);
        for (std::size_t i = 2; i < r.w.size(); ++i) late[i] = r.w[i - 2];  // w(t) recorded at t + 2 ms
        r.w = late;
        dir.write("rec.csv", r.csv());
        const FitResult fit = fitted(dir, "u", "{ column: w, speed: load, delay: d_w }",
                                     "  d_w: { init: 0.0005, min: -0.01, max: 0.01 }");
        CHECK(fit.best_free[0] == Approx(40.0).epsilon(1e-6));
        CHECK(fit.best_free[1] == Approx(0.002).margin(1e-8));
    }
    SECTION("an input recorded 3.3 ms late, a third of a sample past three") {
        Recording r = simulated(dir, drive_samples(0.0));
        r.u = drive_samples(0.0033);  // the torque as a logger 3.3 ms behind recorded it
        dir.write("rec.csv", r.csv());
        const FitResult fit = fitted(dir, "{ column: u, delay: d_u }", "{ column: w, speed: load }",
                                     "  d_u: { init: 0.001, min: -0.01, max: 0.01 }");
        // Interpolating the late recording is the only error: 1 kHz samples of 3 and 11 Hz.
        CHECK(fit.best_free[0] == Approx(40.0).epsilon(1e-3));
        CHECK(fit.best_free[1] == Approx(0.0033).margin(2e-5));
        REQUIRE(fit.uncertainty.available);
        CHECK(fit.uncertainty.std_error[1] < 1e-5);  // a delay the data pin down
    }
    SECTION("an input recorded 2.5 ms late: half way between samples, and not taken for smoothing") {
        Recording r = simulated(dir, drive_samples(0.0));
        r.u = drive_samples(0.0025);
        dir.write("rec.csv", r.csv());
        const FitResult fit = fitted(dir, "{ column: u, delay: d_u }", "{ column: w, speed: load }",
                                     "  d_u: { init: 0.001, min: -0.01, max: 0.01 }");
        CHECK(fit.best_free[1] == Approx(0.0025).margin(2e-5));
        // The cost one sample on is far above: a delay, which delay_smoothing must not flag.
        for (const Finding& f : fit.verdict.findings) CHECK(f.code != "delay_smoothing");
    }
}

TEST_CASE("an input delay has its standard error after every optimizer", "[delay][uncertainty][heavy]") {
    // The torque logged 3.3 ms late and the outputs noisy: every optimizer's uncertainty
    // comes from the one evaluator, whose Jacobian has the input delay's column, so no
    // optimizer reports the delay as having no effect on the output.
    test::TempDir dir;
    Recording r = simulated(dir, drive_samples(0.0));
    r.u = drive_samples(0.0033);
    std::mt19937 noise_source(7);
    std::normal_distribution<double> noise(0.0, 0.01);
    for (std::size_t i = 0; i < r.t.size(); ++i) {
        r.w[i] += noise(noise_source);
        r.T[i] += noise(noise_source);
    }
    dir.write("rec.csv", r.csv());
    const auto fit_with = [&](const std::string& estimation) {
        std::string text = scored_inside(experiment_text("{ column: u, delay: d_u }", "{ column: w, speed: load }",
                                                         "  d_u: { init: 0.001, min: -0.01, max: 0.01 }"));
        const std::string lm = "estimation: { cost: l2, optimizer: lm, lm: { max_iterations: 60 } }";
        text.replace(text.find(lm), lm.size(), estimation);
        FitOptions options;
        options.threads = 2;
        FitResult fit = run_fit(IdentificationProblem(load_experiment(dir.write("e.yaml", text))), options);
        REQUIRE(fit.success);
        return fit;
    };
    const FitResult lm = fit_with("estimation: { cost: l2, optimizer: lm, lm: { max_iterations: 60 } }");
    REQUIRE(lm.uncertainty.available);
    const double lm_error = lm.uncertainty.std_error[1];
    CHECK(lm_error > 0);
    CHECK(lm_error < 1e-4);
    for (const std::string estimation :
         {"estimation: { cost: l2, optimizer: pso, pso: { start: latin_hypercube, particles: 48, iterations: 150, seed: 3 } }",
          "estimation: { cost: l2, optimizer: multistart, multistart: { starts: 4, seed: 3 } }",
          "estimation: { cost: l2, optimizer: nlopt, nlopt: { algorithm: LN_BOBYQA } }"}) {
        INFO(estimation);
        const FitResult fit = fit_with(estimation);
        CHECK(fit.best_free[1] == Approx(0.0033).margin(2e-4));
        REQUIRE(fit.uncertainty.available);
        CHECK(fit.uncertainty.determined[1]);
        CHECK(std::isfinite(fit.uncertainty.std_error[1]));
        // Near the same optimum the same Jacobian column: the same standard error.
        CHECK(fit.uncertainty.std_error[1] == Approx(lm_error).epsilon(0.25));
        for (const Finding& f : fit.verdict.findings) {
            INFO(f.code << ": " << f.message);
            const bool names_delay = f.subject == "d_u" || f.message.find("d_u") != std::string::npos;
            CHECK_FALSE((names_delay && f.code == "undetermined"));
            CHECK_FALSE((names_delay && f.message.find("no effect") != std::string::npos));
        }
    }
}

TEST_CASE("a delay parameter is in seconds and needs bounds within the recording", "[delay][experiment]") {
    test::TempDir dir;
    simulated(dir, drive_samples(0.0));
    const std::string input = "{ column: u, delay: d_u }", speed = "{ column: w, speed: load }";
    const Experiment ex =
        load_experiment(dir.write("ok.yaml", experiment_text(input, speed, "  d_u: { init: 0, min: -0.01, max: 0.01 }")));
    const int d = ex.network.parameter_index("d_u");
    REQUIRE(d >= 0);
    CHECK(parameter_units(ex.network)[static_cast<std::size_t>(d)] == "s");
    const auto error_of = [&](const std::string& parameters) {
        try {
            load_experiment(dir.write("bad.yaml", experiment_text(input, speed, parameters)));
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    CHECK_THAT(error_of("  d_u: { init: 0, min: -0.01 }"), Catch::Contains("needs min and max"));
    CHECK_THAT(error_of("  d_u: { init: 0, min: -0.01, max: 5 }"), Catch::Contains("the recording is"));
    CHECK_THAT(error_of("  d_u: 3"), Catch::Contains("the recording is"));
    CHECK_THAT(error_of(""), Catch::Contains("neither a number nor a parameter"));
    try {  // a stiffness named as a delay
        load_experiment(dir.write("both.yaml", experiment_text("{ column: u, delay: k_s }", speed, "")));
        FAIL("no error");
    } catch (const InputError& e) {
        CHECK_THAT(std::string(e.what()), Catch::Contains("also a quantity of the model"));
    }
}

TEST_CASE("the measured frequency response reads the channels as the parameters delay them", "[delay][frf]") {
    // A multisine torque (1 to 60 Hz) recorded 3.3 ms late: read at a delay of 0 instead
    // of its true one, the measured H1 from the torque to the load's speed leads by
    // 2π·f·3.3 ms at every frequency.
    const auto multisine = [](double late) {
        std::vector<double> u;
        for (int i = 0; i < 2000; ++i) {
            const double t = i * 1e-3 - late;
            double v = 0.0;
            for (int k = 1; k <= 60; ++k) v += std::sin(2 * std::numbers::pi * k * t + 0.37 * k * k);
            u.push_back(0.2 * v);
        }
        return u;
    };
    test::TempDir dir;
    Recording r = simulated(dir, multisine(0.0));
    r.u = multisine(0.0033);
    dir.write("rec.csv", r.csv());
    const Experiment ex = load_experiment(dir.write(
        "e.yaml", experiment_text("{ column: u, delay: d_u }", "{ column: w, speed: load }",
                                  "  d_u: { init: 0, min: -0.01, max: 0.01 }")));
    const IdentificationProblem problem(ex);
    const auto frf = [&](double delay) {
        return compare_frf(problem, problem.full_parameters(std::vector<double>{40.0, delay}), 0,
                           static_cast<std::size_t>(ex.output_indices[0]), 0, AngleDependence::revolution_mean);
    };
    const FrfComparison at_delay = frf(0.0033), undelayed = frf(0.0);
    REQUIRE(at_delay.measured);
    REQUIRE(undelayed.frequency_hz == at_delay.frequency_hz);
    int bins = 0;
    for (std::size_t k = 0; k < at_delay.frequency_hz.size(); ++k) {
        const double f = at_delay.frequency_hz[k];
        if (f < 5 || f > 40) continue;
        ++bins;
        // The input read 3.3 ms late: H1 = Y / (U e^(−jωτ)) leads by ωτ.
        INFO(f << " Hz");
        CHECK(std::arg(undelayed.measured_h1[k] / at_delay.measured_h1[k]) ==
              Approx(2 * std::numbers::pi * f * 0.0033).epsilon(0.12).margin(0.06));  // Welch segments of 128 samples: leakage
    }
    CHECK(bins >= 3);
}

}  // namespace TVID_UNITY_ID
