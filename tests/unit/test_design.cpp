// tvid design's parts: the reference excitations (their RMS within their limits, their
// frequencies in the band), the covariance and criteria from a Fisher information, and the
// prediction of a one-mass line against its analytic sensitivities.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "support/test_files.hpp"
#include "tvid/design/design_experiment.hpp"
#include "tvid/design/design_spec.hpp"
#include "tvid/design/excitation_signals.hpp"
#include "tvid/design/multisine_design.hpp"
#include "tvid/design/parameter_draws.hpp"
#include "tvid/design/predicted_uncertainty.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/util/input_error.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

// The share of the signal's power (its mean removed) at DFT bins within [f_low, f_high].
double power_in_band(const std::vector<double>& v, double fs, double f_low, double f_high) {
    const std::size_t n = v.size();
    double mean = 0.0;
    for (double x : v) mean += x / static_cast<double>(n);
    double inside = 0.0, total = 0.0;
    for (std::size_t k = 1; k <= n / 2; ++k) {
        std::complex<double> sum = 0.0;
        for (std::size_t i = 0; i < n; ++i)
            sum += (v[i] - mean) * std::polar(1.0, -2 * std::numbers::pi * static_cast<double>(k * i) / static_cast<double>(n));
        const double f = static_cast<double>(k) * fs / static_cast<double>(n), p = std::norm(sum);
        total += p;
        if (f >= f_low - 1e-9 && f <= f_high + 1e-9) inside += p;
    }
    return inside / total;
}

}  // namespace

TEST_CASE("a Schroeder multisine holds its power in the band, scaled to its RMS within its limits", "[design]") {
    const double fs = 200.0;
    const std::vector<double> t = excitation_time_grid(400, fs);  // 2 s: the grid's frequencies every 0.5 Hz
    const std::vector<double> shape = schroeder_multisine_shape(t, fs, 5.0, 20.0);
    CHECK(power_in_band(shape, fs, 5.0, 20.0) > 1 - 1e-9);
    CHECK(power_in_band(shape, fs, 5.5, 20.0) < 0.97);  // 5 Hz carries its share: 1 of 31 lines
    const auto v = scaled_excitation(shape, 10.0, 3.0, 0.0, 30.0);
    REQUIRE(v);
    CHECK(rms_about(*v, 10.0) == Approx(3.0).epsilon(1e-9));
    CHECK(*std::min_element(v->begin(), v->end()) >= 0.0);
    // Schroeder's phases keep the crest factor near that of a sine's sqrt(2), far below the
    // sqrt(2 K) = 7.9 of equal phases.
    double peak = 0.0;
    for (double x : shape) peak = std::max(peak, std::abs(x));
    CHECK(peak / rms_about(shape, 0.0) < 2.2);
}

TEST_CASE("a banded multisine puts each band's power in its band, with Schroeder's phases", "[design]") {
    const double fs = 200.0;
    const std::vector<double> t = excitation_time_grid(400, fs);  // lines every 0.5 Hz
    // Bands [5, 10) and [10, 20]: 10 and 21 lines. Equal power per line is the flat multisine.
    const std::vector<double> edges{5.0, 10.0, 20.0};
    const std::vector<double> flat = schroeder_multisine_shape(t, fs, 5.0, 20.0);
    const std::vector<double> equal = banded_multisine_shape(t, fs, edges, {10.0, 21.0});
    for (std::size_t i = 0; i < t.size(); ++i) CHECK(equal[i] == Approx(flat[i]).margin(1e-9));
    // All the power in the upper band: none below 10 Hz.
    const std::vector<double> upper = banded_multisine_shape(t, fs, edges, {0.0, 1.0});
    CHECK(power_in_band(upper, fs, 10.0, 20.0) > 1 - 1e-12);
    // Nine tenths in the lower band.
    const std::vector<double> lower = banded_multisine_shape(t, fs, edges, {0.9, 0.1});
    CHECK(power_in_band(lower, fs, 5.0, 9.9) == Approx(0.9).epsilon(1e-9));
    double peak = 0.0;
    for (double x : lower) peak = std::max(peak, std::abs(x));
    CHECK(peak / rms_about(lower, 0.0) < 2.5);  // Schroeder's phases for an uneven spectrum keep the crest low
}

TEST_CASE("a chirp sweeps its band: its zero crossings count its cycles", "[design]") {
    const double fs = 1000.0;
    const std::vector<double> t = excitation_time_grid(10001, fs);  // 10 s
    const std::vector<double> s = chirp_shape(t, 1.0, 21.0);
    // Cycles: f_low T + (f_high - f_low) T / 2 = 10 + 100 = 110, two crossings each.
    int crossings = 0;
    for (std::size_t i = 1; i < s.size(); ++i) crossings += (s[i - 1] < 0) != (s[i] < 0);
    CHECK(std::abs(crossings - 220) <= 2);
    CHECK(power_in_band(std::vector<double>(s.begin(), s.begin() + 2000), fs, 0.5, 6.0) > 0.9);  // first 2 s: 1-5 Hz
}

TEST_CASE("a PRBS is a maximum-length sequence of two levels, one bit per its clock", "[design]") {
    const double fs = 1000.0, f_high = 50.0;  // 10 samples a bit
    const std::vector<double> s = prbs_shape(5000, fs, f_high);
    std::set<double> levels(s.begin(), s.end());
    CHECK(levels == std::set<double>{-1.0, 1.0});
    // 500 bits: order 9, period 511; a maximum-length sequence of order n has 2^(n-1) ones a
    // period, and its bits change only on the clock.
    std::vector<double> bits;
    for (std::size_t k = 0; k < s.size(); k += 10) {
        bits.push_back(s[k]);
        for (std::size_t i = k; i < std::min(k + 10, s.size()); ++i) CHECK(s[i] == s[k]);
    }
    const std::vector<double> longer = prbs_shape(5110, fs, f_high);
    int ones = 0;
    for (std::size_t k = 0; k < 5110; k += 10) ones += longer[k] > 0;
    CHECK(ones == 256);
    // Its power lies mostly below the clock's half rate.
    CHECK(power_in_band(s, fs, 0.0, f_high) > 0.75);
}

TEST_CASE("a range that cannot hold the RMS is refused, a clipped one meets it", "[design]") {
    const std::vector<double> t = excitation_time_grid(1000, 1000.0);
    const std::vector<double> sine = chirp_shape(t, 10.0, 10.0);
    double reachable = 0.0;
    CHECK_FALSE(scaled_excitation(sine, 0.0, 2.5, -1.0, 3.0, &reachable));
    CHECK(reachable == Approx(std::sqrt(0.5 * 1 + 0.5 * 9)).epsilon(1e-2));  // a square wave between -1 and 3
    const auto v = scaled_excitation(sine, 0.0, 1.5, -1.0, 3.0);
    REQUIRE(v);
    CHECK(rms_about(*v, 0.0) == Approx(1.5).epsilon(1e-9));
    CHECK(*std::min_element(v->begin(), v->end()) == -1.0);  // clipped at the near limit
    CHECK(*std::max_element(v->begin(), v->end()) < 3.0);
}

TEST_CASE("the covariance is the Fisher information's inverse, and a direction it does not see is named", "[design]") {
    PredictedUncertainty u;
    u.names = {"a", "b"};
    u.nominal = {1.0, 2.0};
    u.fisher = Eigen::MatrixXd(2, 2);
    u.fisher << 2.0, 1.0, 1.0, 2.0;
    fill_uncertainty(u);
    // F^-1 = [[2, -1], [-1, 2]] / 3
    CHECK(u.covariance(0, 0) == Approx(2.0 / 3));
    CHECK(u.covariance(0, 1) == Approx(-1.0 / 3));
    CHECK(u.standard_error[1] == Approx(std::sqrt(2.0 / 3)));
    CHECK(u.relative_se[1] == Approx(std::sqrt(2.0 / 3) / 2));
    CHECK(u.correlation(0, 1) == Approx(-0.5));
    CHECK(u.worst_relative_se == Approx(std::sqrt(2.0 / 3)));
    CHECK(u.a_optimal == Approx(std::sqrt((2.0 / 3 + 2.0 / 12) / 2)));
    // det of the scaled covariance: det(F^-1) / (1 * 2)^2 = (1/3) / 4
    CHECK(u.d_optimal == Approx(std::pow(1.0 / 12, 0.25)));

    PredictedUncertainty blind;
    blind.names = {"a", "b", "c"};
    blind.nominal = {1.0, 1.0, 1.0};
    blind.fisher = Eigen::MatrixXd::Zero(3, 3);
    blind.fisher << 1, 1, 0, 1, 1, 0, 0, 0, 4;  // a and b enter only as a + b
    fill_uncertainty(blind);
    CHECK_FALSE(blind.determined[0]);
    CHECK_FALSE(blind.determined[1]);
    CHECK(blind.determined[2]);
    CHECK(std::isnan(blind.standard_error[0]));
    CHECK(blind.standard_error[2] == Approx(0.5));
    CHECK(std::isinf(blind.d_optimal));
    CHECK(std::isinf(blind.worst_relative_se));
}

namespace {

// One inertia J driven by a torque from rest against viscous friction c to ground:
// w = (T0/c)(1 - exp(-c t/J)); the friction's torque c w is measured too.
constexpr double kJ = 0.05, kC = 0.2, kT0 = 2.0, kSigmaW = 0.1, kSigmaT = 0.5;

std::string one_mass(const std::string& design) {
    return R"(tvid: 1
name: one-mass
data: { file: rec.csv, time: t }
model:
  nodes: [ { name: m, J: J } ]
  elements:
    - { type: torque, name: drive, node: m, input: T_in }
    - { type: friction, name: bearing, node: m, c: c }
inputs: { T_in: u }
outputs:
  w: { column: w, speed: m }
  T_f: { column: T_f, torque: bearing }
parameters:
  J: { init: 0.05, min: 0.001, max: 1 }
  c: { init: 0.2, min: 0.001, max: 10 }
windows: { estimation: [ { time: [0, 1] } ] }
initial_state: rest
simulation: { method: rk4, step: 0.001 }
estimation: { cost: l2, optimizer: lm }
)" + design;
}

std::string recording() {
    std::ostringstream out;
    out << "t,u,w,T_f\n";
    for (int k = 0; k <= 100; ++k) out << k * 0.01 << ",0,0,0\n";
    return out.str();
}

}  // namespace

TEST_CASE("the predicted standard errors of a one-mass line are those of its analytic sensitivities", "[design]") {
    const test::TempDir dir;
    dir.write("rec.csv", recording());
    const Experiment ex = load_experiment(dir.write(
        "one.yaml", one_mass("design: { input: T_in, duration: 1, band: [1, 20], limits: [-5, 5], rms: 1, "
                             "noise: { w: 0.1, T_f: 0.5 } }\n")));
    const DesignSpec spec = read_design_spec(ex, {});
    CHECK(spec.sample_rate == Approx(100.0));
    CHECK(spec.samples() == 101);
    CHECK(spec.noise == std::vector<double>{kSigmaW, kSigmaT});

    // A step to T0 at t = 0, held.
    const std::vector<double> time = excitation_time_grid(201, 100.0);  // 2 s
    const std::vector<double> input(time.size(), kT0);
    const PredictedUncertainty u = predict_uncertainty(design_experiment(ex, spec, time, input), {kJ, kC}, spec.noise);
    REQUIRE(u.simulated);
    REQUIRE(u.names == std::vector<std::string>{"J", "c"});

    Eigen::Matrix2d F = Eigen::Matrix2d::Zero();
    for (std::size_t i = 1; i < time.size(); ++i) {  // the start sample is the initial condition, not scored
        const double t = time[i], E = std::exp(-kC * t / kJ);
        const double w = kT0 / kC * (1 - E);
        const Eigen::Vector2d dw(-kT0 * t * E / (kJ * kJ), -kT0 / (kC * kC) * (1 - E) + kT0 / kC * (t / kJ) * E);
        const Eigen::Vector2d dT(kC * dw(0), w + kC * dw(1));
        F += dw * dw.transpose() / (kSigmaW * kSigmaW) + dT * dT.transpose() / (kSigmaT * kSigmaT);
    }
    const Eigen::Matrix2d C = F.inverse();
    CHECK(u.fisher(0, 0) == Approx(F(0, 0)).epsilon(1e-6));
    CHECK(u.fisher(0, 1) == Approx(F(0, 1)).epsilon(1e-6));
    CHECK(u.fisher(1, 1) == Approx(F(1, 1)).epsilon(1e-6));
    CHECK(u.standard_error[0] == Approx(std::sqrt(C(0, 0))).epsilon(1e-5));
    CHECK(u.standard_error[1] == Approx(std::sqrt(C(1, 1))).epsilon(1e-5));
    CHECK(u.relative_se[0] == Approx(std::sqrt(C(0, 0)) / kJ).epsilon(1e-5));
    CHECK(u.correlation(0, 1) == Approx(C(0, 1) / std::sqrt(C(0, 0) * C(1, 1))).epsilon(1e-5));
}

TEST_CASE("the design section's mistakes are named by their key", "[design]") {
    const test::TempDir dir;
    dir.write("rec.csv", recording());
    const auto refused = [&](const std::string& design, const std::string& key, const std::string& words) {
        const Experiment ex = load_experiment(dir.write("bad.yaml", one_mass(design)));
        try {
            (void)read_design_spec(ex, {});
            FAIL("accepted: " << design);
        } catch (const InputError& e) {
            CHECK(e.key() == key);
            CHECK_THAT(e.problem(), Catch::Contains(words));
            CHECK(e.line() > 0);
        }
    };
    const std::string noise = "noise: { w: 0.1, T_f: 0.5 }";
    refused("design: { input: T_in, band: [1, 80], limits: [-5, 5], rms: 1, " + noise + " }\n", "design.band", "Nyquist");
    refused("design: { input: T_in, band: [1, 20], limits: [1, 5], rms: 1, " + noise + " }\n", "design.limits",
            "excludes the operating point");
    refused("design: { input: T_load, band: [1, 20], limits: [-5, 5], rms: 1, " + noise + " }\n", "design.input",
            "not an input of the model");
    refused("design: { input: T_in, band: [1, 20], limits: [-5, 5], rms: 1, noise: { w: 0.1, T_f: -1 } }\n",
            "design.noise.T_f", "above 0");
    refused("design: { input: T_in, band: [1, 20], limits: [-5, 5], rms: 1, noise: { w: 0.1 } }\n", "design.noise",
            "T_f");
    refused("design: { input: T_in, band: [1, 20], limits: [-5, 5], rms: 1, noise: { w: 0.1, T_f: 0.5, x: 1 } }\n",
            "design.noise.x", "not an output");
    refused("design: { input: T_in, duration: 0.5, band: [0.1, 1], limits: [-5, 5], rms: 1, " + noise + " }\n",
            "design.band", "no frequency of the record's grid");
}

TEST_CASE("parameter draws for a robust design: log-uniform factors within the spread, in the bounds, from the seed", "[design]") {
    const test::TempDir dir;
    dir.write("rec.csv", recording());
    // c's upper bound 0.25 lies inside the spread: its draws above it are held there.
    std::string text = one_mass("design: { input: T_in, duration: 1, band: [1, 20], limits: [-5, 5], rms: 1, "
                                "noise: { w: 0.1, T_f: 0.5 }, robust: { draws: 40, spread: 0.5, seed: 7 } }\n");
    text.replace(text.find("max: 10 }"), 9, "max: 0.25 }");
    const Experiment ex = load_experiment(dir.write("robust.yaml", text));
    const DesignSpec spec = read_design_spec(ex, {});
    REQUIRE(spec.draws == 40);
    const std::vector<double> nominal{0.05, 0.2};
    const auto sets = design_parameter_sets(ex, spec, nominal);
    REQUIRE(sets.size() == 41);
    CHECK(sets[0] == nominal);
    int held = 0, below = 0;
    for (std::size_t d = 1; d < sets.size(); ++d) {
        CHECK(sets[d][0] >= 0.05 / 1.5 - 1e-15);
        CHECK(sets[d][0] <= 0.05 * 1.5 + 1e-15);
        CHECK(sets[d][1] <= 0.25);
        held += sets[d][1] == 0.25;
        below += sets[d][0] < 0.05;
    }
    CHECK(held > 5);                   // about 40 * (1 - ln(1.25)/ln(1.5)) / 2 = 9 of them
    CHECK(below > 10);                 // about half
    CHECK(design_parameter_sets(ex, spec, nominal) == sets);  // the seed alone decides
    DesignSpec other = spec;
    other.draw_seed = 8;
    CHECK(design_parameter_sets(ex, other, nominal) != sets);

    // The averaged criterion is the geometric mean; one failed set makes it infinite.
    std::vector<PredictedUncertainty> p(2);
    p[0].simulated = p[1].simulated = true;
    p[0].worst_relative_se = 0.01;
    p[1].worst_relative_se = 0.04;
    CHECK(averaged_criterion(p, DesignCriterion::worst_relative_se) == Approx(0.02));
    p[1].simulated = false;
    CHECK(std::isinf(averaged_criterion(p, DesignCriterion::worst_relative_se)));
}

TEST_CASE("a steady start read from the designed input's column starts at the design's base", "[design]") {
    // The measured bench starts steady at the motor speed w1, the column its speed source
    // reads: a design about 100 rad/s starts there, not at the recording's 338 rad/s.
    const std::vector<Override> overrides{
        parse_override("design={ input: w_motor, duration: 2, band: [1, 40], limits: [0, 200], base: 100, rms: 10, "
                       "noise: { torque_upper: 0.05, torque_lower: 0.2 } }")};
    const Experiment ex = load_experiment(test::source_dir() / "configs/aalto_bench.yaml", overrides);
    REQUIRE(ex.steady.speed_column == "w1");
    const DesignSpec spec = read_design_spec(ex, overrides);
    const std::vector<double> time = excitation_time_grid(spec.samples(), spec.sample_rate);
    const Experiment held = design_experiment(ex, spec, time, std::vector<double>(time.size(), spec.base));
    CHECK(held.steady.speed_column.empty());
    CHECK(held.steady.speed == 100.0);
    // A column the design does not play keeps the recording's mean over the first window's samples.
    const std::vector<Override> other{overrides[0], parse_override("initial_state={ kind: steady, node: motor, speed: w2, samples: 200 }")};
    const Experiment ex2 = load_experiment(test::source_dir() / "configs/aalto_bench.yaml", other);
    const Experiment recorded = design_experiment(ex2, read_design_spec(ex2, other), time, std::vector<double>(time.size(), 100.0));
    double mean = 0;
    for (std::size_t i = 0; i < 200; ++i) mean += ex2.data.column("w2")[ex2.estimation.front().first + i] / 200;
    CHECK(recorded.steady.speed == Approx(mean).epsilon(1e-12));
    CHECK(recorded.steady.speed > 300);
}

}  // namespace TVID_UNITY_ID
