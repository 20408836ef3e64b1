// Numbers that tell the truth, through the binary: a delay's init does not change the
// cost, spectra skip a recording's gaps, one Welch segment has no coherence, an undamped
// mode's response is infinite at its resonance, absurd weights are refused, a delay near 0
// is not "weak", and the starts read the speed column as the model's channel does.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <random>
#include <sstream>
#include <string>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
using nlohmann::json;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Recording {
    double seconds = 1.0;           ///< t = 0 … seconds at 1 kHz
    int late = 3;                   ///< w read this many samples late
    double noise = 0.02;            ///< on w and Tf
    double line_100hz = 0.0;        ///< a 100 Hz line added to w that the model cannot make
    bool gap = false;               ///< no rows for 1 < t < 2
};

double torque(double t) { return std::sin(2 * kPi * 5 * t) + 0.3 * std::sin(2 * kPi * 40 * t); }

// The shared recipe: T = sin(2π·5t) + 0.3 sin(2π·40t); 0.01·w' = T − 0.1·w from rest, read
// `late` samples late with noise; Tf = 0.1·w + noise. Columns t,T,w,Tf.
std::string recording(const Recording& r) {
    const int n = static_cast<int>(std::lround(r.seconds * 1000)) + 1;
    std::vector<double> w(static_cast<std::size_t>(n), 0.0);
    double state = 0.0;
    const double h = 1e-4;  // RK4 at 10 steps per sample
    const auto f = [](double t, double x) { return (torque(t) - 0.1 * x) / 0.01; };
    for (int i = 1; i < n; ++i) {
        for (int s = 0; s < 10; ++s) {
            const double t = (i - 1) * 1e-3 + s * h;
            const double k1 = f(t, state), k2 = f(t + h / 2, state + h / 2 * k1), k3 = f(t + h / 2, state + h / 2 * k2),
                         k4 = f(t + h, state + h * k3);
            state += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
        }
        w[static_cast<std::size_t>(i)] = state;
    }
    std::mt19937 random(7);
    std::normal_distribution<double> gauss(0.0, 1.0);
    std::ostringstream csv;
    csv.precision(17);
    csv << "t,T,w,Tf\n";
    for (int i = 0; i < n; ++i) {
        const double t = i * 1e-3;
        const double wl = w[static_cast<std::size_t>(std::max(0, i - r.late))] + r.noise * gauss(random) +
                          r.line_100hz * std::sin(2 * kPi * 100 * t);
        const double tf = 0.1 * w[static_cast<std::size_t>(i)] + r.noise * gauss(random);
        if (r.gap && t > 1.0 + 1e-9 && t < 2.0 - 1e-9) continue;
        csv << t << ',' << torque(t) << ',' << wl << ',' << tf << '\n';
    }
    return csv.str();
}

// one.yaml: one node a (J 0.01), a torque on a from T, friction on a with c, output w as
// a's speed; `output_extra` goes inside w's mapping, `extra` at the end.
std::string one_yaml(const std::string& output_extra = "", const std::string& extra = "",
                     const std::string& parameters = "", const std::string& window = "time: [0, 0.9]") {
    return "tvid: 1\n"
           "name: one\n"
           "data: { file: rec.csv, time: t }\n"
           "model:\n"
           "  nodes:\n"
           "    - { name: a, J: 0.01 }\n"
           "  elements:\n"
           "    - { type: torque, name: drive, node: a, input: T }\n"
           "    - { type: friction, name: fr, node: a, c: c }\n"
           "inputs: { T: T }\n"
           "outputs:\n"
           "  w: { column: w, speed: a" + output_extra + " }\n"
           "parameters:\n"
           "  c: { init: 0.1, min: 0.01, max: 1 }\n" + parameters +
           "windows:\n"
           "  estimation: [ { " + window + " } ]\n"
           "initial_state: rest\n"
           "estimation: { cost: l2, optimizer: lm }\n" + extra;
}

std::size_t lines_of(const std::string& text) { return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')); }

json run_json(const std::vector<std::string>& args) {
    const RunResult r = run_tvid(args);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    return json::parse(r.out);
}

}  // namespace

TEST_CASE("F1: the same parameters cost the same whatever a delay parameter's init", "[e2e][numerics]") {
    TempDir tmp;
    tmp.write("rec.csv", recording({}));
    const auto params = tmp.write("p.json", "{ \"c\": 0.1, \"d\": 0.003 }");
    // normalize: spread divides the residual by the measured spread, which must not
    // depend on where the delay started.
    double cost[2];
    int i = 0;
    for (const std::string init : {"0", "0.003"}) {
        const auto exp = tmp.write("one_" + std::to_string(i) + ".yaml",
                                   one_yaml(", delay: d", "", "  d: { init: " + init + ", min: -0.01, max: 0.01 }\n") +
                                       "");
        // estimation.normalize: spread (one output: the default is none).
        const json j = run_json({"validate", exp.string(), "--params", params.string(), "--json", "--set",
                                 "estimation.normalize=spread"});
        REQUIRE(j["cost"].is_number());
        cost[i++] = j["cost"].get<double>();
    }
    CHECK(std::abs(cost[0] - cost[1]) <= 1e-12 * std::abs(cost[0]));
}

TEST_CASE("F4: an absurd output weight is refused at load in one line", "[e2e][numerics]") {
    TempDir tmp;
    tmp.write("rec.csv", recording({}));
    const auto exp = tmp.write("one.yaml", one_yaml(", weight: 1e200"));
    const RunResult r = run_tvid({"fit", exp.string(), "-o", (tmp.path() / "r").string()});
    CHECK(r.exit_code == 2);
    CHECK(lines_of(r.err) == 1);
    CHECK(r.err.find("one.yaml:12: outputs.w.weight: an output's weight must be between 1e-08 and 1e+08") !=
          std::string::npos);
    CHECK_FALSE(std::filesystem::exists(tmp.path() / "r" / "summary.json"));
}

TEST_CASE("F13: a delay and an offset fitted near 0 are judged against their natural scale, not their value",
          "[e2e][numerics]") {
    TempDir tmp;
    tmp.write("rec.csv", recording({.late = 0}));
    const auto exp = tmp.write("one.yaml", one_yaml(", delay: d, offset: o", "",
                                                    "  d: { init: 0.0004, min: -0.005, max: 0.005 }\n"
                                                    "  o: { init: 0.01, min: -1, max: 1 }\n"));
    const RunResult r = run_tvid({"fit", exp.string(), "-o", (tmp.path() / "r").string()});
    INFO(r.out << r.err);
    REQUIRE(r.exit_code == 0);
    CHECK(r.out.find("% of a sample period (0.001 s)") != std::string::npos);
    const json s = json::parse(read_text(tmp.path() / "r" / "summary.json"));
    int found = 0;
    for (const json& p : s["identifiability"]["parameters"]) {
        const double se = p["std_error"].get<double>();
        if (p["name"] == "d") {
            ++found;
            CHECK(se < 1e-4);  // a small fraction of a sample period
            CHECK(p["flag"] == "ok");
            CHECK(p["judged_against"] == "a sample period (0.001 s)");
            CHECK(p["judged_std_error"].get<double>() == Approx(se / 1e-3).epsilon(1e-6));
        } else if (p["name"] == "o") {
            ++found;
            CHECK(p["flag"] == "ok");
            CHECK(p["judged_against"] == "its range (2)");
            CHECK(p["judged_std_error"].get<double>() == Approx(se / 2).epsilon(1e-6));
        }
    }
    CHECK(found == 2);
    for (const json& f : s["verdict"]["findings"]) CHECK(f["code"] != "weakly_determined");
}

namespace {

// 0 … 3 s at 1 kHz without the rows of 1 < t < 2, a 100 Hz line in w that no input
// explains; one window over all of it (dopri5 steps across the gap).
std::filesystem::path gap_experiment(const TempDir& tmp) {
    tmp.write("rec.csv", recording({.seconds = 3.0, .late = 0, .line_100hz = 2.0, .gap = true}));
    return tmp.write("one.yaml", one_yaml("", "simulation: { method: dopri5 }\n", "", "time: [0, 3]"));
}

}  // namespace

TEST_CASE("F16: the residual spectrum of a recording with a gap keeps its frequencies", "[e2e][numerics]") {
    TempDir tmp;
    const auto exp = gap_experiment(tmp);
    const RunResult r = run_tvid({"fit", exp.string(), "-o", (tmp.path() / "r").string()});
    INFO(r.out << r.err);
    REQUIRE(r.exit_code == 0);
    const json s = json::parse(read_text(tmp.path() / "r" / "summary.json"));
    const json& band = s["residual_spectrum"]["estimation"]["w"]["frequency"];
    const double resolution = band["resolution_hz"].get<double>();
    CHECK(band["gaps"] == 1);
    CHECK(band["segments"].get<int>() >= 2);
    CHECK(resolution == Approx(1000.0 / band["segment_length"].get<double>()).epsilon(1e-9));
    CHECK(std::abs(band["peak_hz"].get<double>() - 100.0) <= resolution);
    // spectra.csv's grid is k·1000/L Hz.
    std::istringstream csv(read_text(tmp.path() / "r" / "spectra.csv"));
    std::string line;
    std::getline(csv, line);
    std::getline(csv, line);
    std::getline(csv, line);  // the second row: f_1
    CHECK(std::stod(line.substr(line.find(',') + 1)) == Approx(resolution).epsilon(1e-9));
}

TEST_CASE("F16: the FRF of a recording with a gap keeps its frequencies", "[e2e][numerics]") {
    TempDir tmp;
    const auto exp = gap_experiment(tmp);
    const RunResult f = run_tvid({"frf", exp.string(), "-o", (tmp.path() / "f").string(), "--input", "T", "--output", "w"});
    INFO(f.err);
    REQUIRE(f.exit_code == 0);
    const json j = json::parse(read_text(tmp.path() / "f" / "frf.json"));
    CHECK(j["measured"]["gaps"] == 1);
    CHECK(j["measured"]["sample_rate_hz"].get<double>() == Approx(1000.0).epsilon(1e-9));
    CHECK(j["rows"][0]["frequency_hz"].get<double>() ==
          Approx(j["measured"]["resolution_hz"].get<double>()).epsilon(1e-12));
    CHECK(f.out.find("cut at 1 gap(s)") != std::string::npos);
}

TEST_CASE("F3: one Welch segment gives no coherence", "[e2e][numerics]") {
    TempDir tmp;
    tmp.write("rec.csv", recording({}));
    const auto exp = tmp.write("one.yaml", one_yaml("", "", "", "samples: [0, 30]"));
    const RunResult r = run_tvid({"frf", exp.string(), "-o", (tmp.path() / "f").string(), "--input", "T", "--output", "w"});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const json j = json::parse(read_text(tmp.path() / "f" / "frf.json"));
    CHECK(j["measured"]["segments"] == 1);
    CHECK(j["measured"]["coherence_defined"] == false);
    REQUIRE(j["rows"].size() > 3);
    for (const json& row : j["rows"]) CHECK(row["coherence"].is_null());
    CHECK(r.out.find("coherence 1.000") == std::string::npos);
    CHECK(r.out.find("one segment: no coherence") != std::string::npos);
}

TEST_CASE("F20: an undamped mode's response is infinite at its resonance, and no false peak is printed",
          "[e2e][numerics]") {
    TempDir tmp;
    tmp.write("rec.csv", recording({}));
    // Two inertias of 0.01 on an undamped spring of 100 N m/rad: f_n = sqrt(100·200)/2π.
    const std::string exp_text = "tvid: 1\n"
                                 "name: undamped\n"
                                 "data: { file: rec.csv, time: t }\n"
                                 "model:\n"
                                 "  nodes:\n"
                                 "    - { name: a, J: 0.01 }\n"
                                 "    - { name: b, J: 0.01 }\n"
                                 "  elements:\n"
                                 "    - { type: torque, name: drive, node: a, input: T }\n"
                                 "    - { type: spring_damper, name: shaft, between: [a, b], k: k, c: 0 }\n"
                                 "inputs: { T: T }\n"
                                 "outputs:\n"
                                 "  w: { column: w, speed: b }\n"
                                 "parameters:\n"
                                 "  k: { init: 100, min: 1, max: 1000 }\n"
                                 "windows:\n"
                                 "  estimation: [ { time: [0, 0.9] } ]\n"
                                 "initial_state: rest\n"
                                 "estimation: { cost: l2, optimizer: lm }\n";
    const auto exp = tmp.write("undamped.yaml", exp_text);
    const RunResult r = run_tvid({"frf", exp.string(), "-o", (tmp.path() / "f").string(), "--input", "T", "--output", "w"});
    INFO(r.out << r.err);
    REQUIRE(r.exit_code == 0);
    const double fn = std::sqrt(100.0 * 200.0) / (2 * kPi);
    const json j = json::parse(read_text(tmp.path() / "f" / "frf.json"));
    REQUIRE(j["undamped_resonances_hz"].size() == 1);
    CHECK(j["undamped_resonances_hz"][0].get<double>() == Approx(fn).epsilon(1e-9));
    const json& curve = j["model_curve"];
    double nearest = 1e300, largest = 0.0;
    for (std::size_t k = 0; k < curve["frequency_hz"].size(); ++k) {
        const double f = curve["frequency_hz"][k].get<double>();
        REQUIRE(curve["magnitude"][k].is_number());
        nearest = std::min(nearest, std::abs(f - fn));
        if (std::abs(f - fn) < 0.02 * fn) largest = std::max(largest, curve["magnitude"][k].get<double>());
    }
    CHECK(nearest > 1e-6 * fn);  // no point at the pole itself
    CHECK(largest > 500.0);      // the curve climbs towards it
    CHECK(r.out.find("model resonance") != std::string::npos);
    CHECK(r.out.find("infinite (an undamped mode)") != std::string::npos);
    CHECK(r.out.find("model peak") == std::string::npos);  // nothing else peaks: a free mass and one mode
}

TEST_CASE("F15: a P-only speed controller under a steady start is named", "[e2e][numerics]") {
    TempDir tmp;
    tmp.write("rec.csv", recording({}));
    const std::string exp_text = "tvid: 1\n"
                                 "name: p-only\n"
                                 "data: { file: rec.csv, time: t }\n"
                                 "model:\n"
                                 "  nodes:\n"
                                 "    - { name: a, J: 0.01 }\n"
                                 "  elements:\n"
                                 "    - { type: torque, name: drive, node: a, input: T }\n"
                                 "    - { type: speed_controller, name: pi, node: a, setpoint: 10, kp: 0.5, ki: 0 }\n"
                                 "inputs: { T: T }\n"
                                 "outputs:\n"
                                 "  w: { column: w, speed: a }\n"
                                 "parameters: {}\n"
                                 "windows:\n"
                                 "  estimation: [ { time: [0, 0.9] } ]\n"
                                 "initial_state: { kind: steady, node: a, speed: 10 }\n";
    const auto exp = tmp.write("p.yaml", exp_text);
    const RunResult r = run_tvid({"simulate", exp.string(), "-o", (tmp.path() / "sim.csv").string()});
    INFO(r.err);
    CHECK(r.exit_code == 1);
    CHECK(lines_of(r.err) == 1);
    CHECK(r.err.find("node pi.reference") != std::string::npos);
    CHECK(r.err.find("speed_controller pi has ki = 0") != std::string::npos);
    CHECK(r.err.find("start from initial_state: measured") != std::string::npos);
}

TEST_CASE("F18: a steady start on a line held to ground is refused at load", "[e2e][numerics]") {
    TempDir tmp;
    tmp.write("rec.csv", recording({}));
    const std::string exp_text = "tvid: 1\n"
                                 "name: grounded\n"
                                 "data: { file: rec.csv, time: t }\n"
                                 "model:\n"
                                 "  nodes:\n"
                                 "    - { name: a, J: 0.01 }\n"
                                 "  elements:\n"
                                 "    - { type: torque, name: drive, node: a, input: T }\n"
                                 "    - { type: spring_damper, name: mount, between: [a, ground], k: 50, c: 0.1 }\n"
                                 "inputs: { T: T }\n"
                                 "outputs:\n"
                                 "  w: { column: w, speed: a }\n"
                                 "parameters: {}\n"
                                 "windows:\n"
                                 "  estimation: [ { time: [0, 0.9] } ]\n"
                                 "initial_state: { kind: steady, node: a, speed: 0 }\n";
    const auto exp = tmp.write("g.yaml", exp_text);
    const RunResult r = run_tvid({"simulate", exp.string(), "-o", (tmp.path() / "sim.csv").string()});
    CHECK(r.exit_code == 2);
    CHECK(lines_of(r.err) == 1);
    CHECK(r.err.find("g.yaml:16: initial_state.kind: steady on a line held to ground by 'mount' (node a to ground)") !=
          std::string::npos);
}

TEST_CASE("F5, F19: a steady start reads its speed column as the channel does: unit and delay", "[e2e][numerics]") {
    // A speed source drives a over a spring into b; the shaft torque is the output. The
    // start read from the rpm column with unit: rpm (or the delayed column) must equal the
    // start read from the same column converted (or shifted) by hand.
    TempDir tmp;
    std::ostringstream csv;
    csv.precision(17);
    csv << "t,w_rpm,w_rad,w_late,T\n";
    const int n = 1001;
    const auto speed = [](double t) { return 100.0 + 5.0 * std::sin(2 * kPi * 3 * t); };
    for (int i = 0; i < n; ++i) {
        const double t = i * 1e-3;
        const double late = speed(std::min(t + 0.003, 1.0));  // read 3 ms late: held at the end
        csv << t << ',' << speed(t) * 60 / (2 * kPi) << ',' << speed(t) << ',' << late << ",0\n";
    }
    tmp.write("rec.csv", csv.str());
    const auto experiment = [&](const std::string& input, const std::string& column) {
        return "tvid: 1\n"
               "name: speed-start\n"
               "data: { file: rec.csv, time: t }\n"
               "model:\n"
               "  nodes:\n"
               "    - { name: a, J: 0.01 }\n"
               "    - { name: b, J: 0.02 }\n"
               "  elements:\n"
               "    - { type: speed_source, name: drive, node: a, input: w_in }\n"
               "    - { type: spring_damper, name: shaft, between: [a, b], k: 500, c: 0.5 }\n"
               "    - { type: friction, name: load, node: b, c: 0.07 }\n"
               "inputs: { w_in: " + input + " }\n"
               "outputs:\n"
               "  T_shaft: { column: T, torque: shaft }\n"
               "parameters: {}\n"
               "windows:\n"
               "  estimation: [ { time: [0.1, 0.9] } ]\n"
               "initial_state: { kind: steady, node: a, speed: " + column + ", samples: 20 }\n";
    };
    const auto shaft_torque = [&](const std::string& name, const std::string& input, const std::string& column) {
        const auto exp = tmp.write(name, experiment(input, column));
        const json j = run_json({"simulate", exp.string(), "--json"});
        return j["traces"]["estimation"]["outputs"]["T_shaft"]["simulated"];
    };
    SECTION("unit: rpm") {
        const json by_hand = shaft_torque("rad.yaml", "w_rad", "w_rad");
        const json rpm = shaft_torque("rpm.yaml", "{ column: w_rpm, unit: rpm }", "w_rpm");
        REQUIRE(by_hand.size() == rpm.size());
        REQUIRE(by_hand.size() > 100);
        double worst = 0.0, largest = 0.0;
        for (std::size_t i = 0; i < by_hand.size(); ++i) {
            worst = std::max(worst, std::abs(by_hand[i].get<double>() - rpm[i].get<double>()));
            largest = std::max(largest, std::abs(by_hand[i].get<double>()));
        }
        CHECK(largest > 0.1);
        CHECK(worst <= 1e-9 * largest);
    }
    SECTION("delay: 0.003") {
        const json by_hand = shaft_torque("late.yaml", "w_late", "w_late");
        const json delayed = shaft_torque("delay.yaml", "{ column: w_rad, delay: 0.003 }", "w_rad");
        REQUIRE(by_hand.size() == delayed.size());
        double worst = 0.0, largest = 0.0;
        for (std::size_t i = 0; i < by_hand.size(); ++i) {
            worst = std::max(worst, std::abs(by_hand[i].get<double>() - delayed[i].get<double>()));
            largest = std::max(largest, std::abs(by_hand[i].get<double>()));
        }
        CHECK(largest > 0.1);
        CHECK(worst <= 1e-6 * largest);
    }
}

}  // namespace TVID_UNITY_ID
