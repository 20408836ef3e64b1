// The spectra of a fit's report: spectra.csv (Welch densities of the measured output, the
// simulated output and the residual, in unit²/Hz), orders.csv for an engine, and the
// residual's dominant band or order in summary.json and on the terminal.
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
using nlohmann::json;

namespace {

struct Table {
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;
    std::size_t column(const std::string& name) const {
        for (std::size_t i = 0; i < header.size(); ++i)
            if (header[i] == name) return i;
        FAIL("no column " << name);
        return 0;
    }
};

std::vector<std::string> cells(const std::string& line) {
    std::vector<std::string> out;
    std::stringstream in(line);
    std::string cell;
    while (std::getline(in, cell, ',')) out.push_back(cell);
    if (!line.empty() && line.back() == ',') out.emplace_back();
    return out;
}

Table read_table(const std::filesystem::path& file) {
    std::stringstream in(read_text(file));
    Table t;
    std::string line;
    std::getline(in, line);
    t.header = cells(line);
    while (std::getline(in, line)) t.rows.push_back(cells(line));
    return t;
}

// The column of a trace CSV whose name is `prefix` with or without a unit after it.
std::size_t trace_column(const Table& t, const std::string& prefix) {
    for (std::size_t i = 0; i < t.header.size(); ++i)
        if (t.header[i] == prefix || t.header[i].rfind(prefix + " [", 0) == 0) return i;
    FAIL("no column " << prefix);
    return 0;
}

}  // namespace

TEST_CASE("a fit report's spectra.csv holds densities in unit squared per Hz that integrate to the variance",
          "[e2e][spectra][fits]") {
    TempDir tmp;
    const auto out = tmp.path() / "bench";
    const RunResult r = run_tvid({"fit", (source_dir() / "configs/aalto_bench.yaml").string(), "-o", out.string()});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const Table spectra = read_table(out / "spectra.csv");
    CHECK(spectra.header == std::vector<std::string>{"split", "frequency [Hz]",
                                                     "torque_upper_measured_psd [(N m)^2/Hz]",
                                                     "torque_upper_simulated_psd [(N m)^2/Hz]",
                                                     "torque_upper_residual_psd [(N m)^2/Hz]",
                                                     "torque_lower_measured_psd [(N m)^2/Hz]",
                                                     "torque_lower_simulated_psd [(N m)^2/Hz]",
                                                     "torque_lower_residual_psd [(N m)^2/Hz]"});
    // The bench's motor encoder is a crank angle (data.angle): its cycles have orders too.
    CHECK(std::filesystem::exists(out / "orders.csv"));
    const json summary = json::parse(read_text(out / "summary.json"));
    const Table trace = read_table(out / "estimation.csv");
    for (const std::string output : {"torque_upper", "torque_lower"}) {
        INFO(output);
        // The residual's variance over the estimation windows, each about its own mean.
        const std::size_t e = trace_column(trace, output + "_residual"), w = trace_column(trace, "window");
        std::map<std::string, std::vector<double>> windows;
        for (const auto& row : trace.rows) windows[row[w]].push_back(std::stod(row[e]));
        double sum_sq = 0.0;
        std::size_t n = 0;
        for (const auto& [label, values] : windows) {
            double mean = 0.0;
            for (double v : values) mean += v;
            mean /= static_cast<double>(values.size());
            for (double v : values) sum_sq += (v - mean) * (v - mean);
            n += values.size();
        }
        const double variance = sum_sq / static_cast<double>(n);
        // Σ P Δf over the estimation rows: the one-sided density integrates to the variance
        // (Parseval), short of what varies slower than a Welch segment (its mean is removed).
        const std::size_t f = spectra.column("frequency [Hz]");
        const std::size_t p = spectra.column(output + "_residual_psd [(N m)^2/Hz]");
        std::vector<double> frequency, density;
        for (const auto& row : spectra.rows)
            if (row[0] == "estimation") {
                frequency.push_back(std::stod(row[f]));
                density.push_back(std::stod(row[p]));
            }
        REQUIRE(frequency.size() > 100);
        const double df = frequency[1] - frequency[0];
        CHECK(frequency.front() == 0.0);
        CHECK(frequency.back() == Approx(500.0).epsilon(1e-3));  // the Nyquist frequency of 1 kHz samples
        double integral = 0.0;
        for (double d : density) integral += d * df;
        CHECK(integral == Approx(variance).epsilon(0.05));
        // summary.json names the peak of that density and a band around it with its share.
        const json& band = summary["residual_spectrum"]["estimation"][output]["frequency"];
        CHECK(band["variance"].get<double>() == Approx(integral).epsilon(1e-6));
        const double peak = band["peak_hz"].get<double>();
        std::size_t top = 1;
        for (std::size_t k = 1; k < density.size(); ++k)
            if (density[k] > density[top]) top = k;
        CHECK(peak == Approx(frequency[top]).margin(1e-6));
        CHECK(band["band_hz"][0].get<double>() < peak);
        CHECK(band["band_hz"][1].get<double>() > peak);
        double in_band = 0.0;
        for (std::size_t k = 0; k < density.size(); ++k)
            if (frequency[k] >= band["band_hz"][0].get<double>() - 1e-9 && frequency[k] <= band["band_hz"][1].get<double>() + 1e-9)
                in_band += density[k] * df;
        CHECK(band["share"].get<double>() == Approx(in_band / integral).epsilon(1e-6));
        CHECK(summary["residual_spectrum"]["estimation"][output]["unit"] == "N m");
        CHECK(summary["residual_spectrum"]["estimation"][output]["order"]["cycles"].get<int>() > 100);
        // The terminal names the band: no input is read by crank angle, the bench is no engine.
        const std::size_t line = r.out.find("residual " + output + ": ");
        REQUIRE(line != std::string::npos);
        const std::string text = r.out.substr(line, r.out.find('\n', line) - line);
        CHECK(text.find(" Hz (peak ") != std::string::npos);
        CHECK(text.find("order") == std::string::npos);
    }
    CHECK(r.out.find("% of its variance at ") != std::string::npos);
    CHECK(r.out.find("; white noise would put ") != std::string::npos);  // the share read against the noise
    bool validation = false;
    for (const auto& row : spectra.rows) validation = validation || row[0] == "validation";
    CHECK(validation);
}

TEST_CASE("an engine fit's orders.csv holds orders 0.5 to 12 per cycle, the residual's the difference",
          "[e2e][spectra]") {
    TempDir tmp;
    const auto out = tmp.path() / "engine";
    // One LM step: the residual keeps a misfit at order 0.5 (after two it is white, and the
    // terminal then names no order).
    const RunResult r = run_tvid({"fit", (source_dir() / "configs/engine_idle.yaml").string(), "-o", out.string(),
                                  "--set", "estimation.lm.max_iterations=1", "--set",
                                  "windows.validation=[{cycle: 3}, {cycle: 4}]"});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const Table orders = read_table(out / "orders.csv");
    CHECK(orders.header == std::vector<std::string>{"split", "window", "cycle", "output", "unit", "order",
                                                    "measured_amplitude", "measured_phase [deg]",
                                                    "simulated_amplitude", "simulated_phase [deg]",
                                                    "residual_amplitude", "residual_phase [deg]"});
    // One estimation cycle and two validation cycles, 24 orders each (0.5 … 12 of a 720° cycle).
    REQUIRE(orders.rows.size() == 3 * 24);
    const std::vector<std::string> splits{"estimation", "validation", "validation"}, cycles{"2", "3", "4"};
    constexpr double kDeg = std::numbers::pi / 180.0;
    for (std::size_t i = 0; i < orders.rows.size(); ++i) {
        const auto& row = orders.rows[i];
        CHECK(row[0] == splits[i / 24]);
        CHECK(row[2] == cycles[i / 24]);
        CHECK(row[3] == "omega_dw");
        CHECK(row[4] == "rad/s");
        CHECK(std::stod(row[5]) == 0.5 * static_cast<double>(i % 24 + 1));
        // The order spectrum is linear: the residual's component is the measured one's minus
        // the simulated one's (to the CSV's 6 significant digits of a phase, ≤ 1e-5 rad).
        const auto phasor = [&](std::size_t a) { return std::polar(std::stod(row[a]), std::stod(row[a + 1]) * kDeg); };
        const std::complex<double> difference = phasor(6) - phasor(8);
        CHECK(std::abs(phasor(10) - difference) < 2e-5 * (std::abs(phasor(6)) + std::abs(phasor(8))) + 1e-9);
    }
    // The engine's speed fluctuates at the firing order, 2 for four cylinders: the measured
    // amplitude there is far above the neighbouring half orders.
    CHECK(std::stod(orders.rows[3][6]) > 10 * std::stod(orders.rows[2][6]));
    const json summary = json::parse(read_text(out / "summary.json"));
    const json& order = summary["residual_spectrum"]["estimation"]["omega_dw"]["order"];
    CHECK(order["cycles"] == 1);
    CHECK(order["share"].get<double>() > 0.0);
    CHECK(order["share"].get<double>() <= 1.0);
    CHECK(std::fmod(order["order"].get<double>(), 0.5) == 0.0);
    CHECK(r.out.find("residual omega_dw: ") != std::string::npos);
    CHECK(summary["residuals"]["estimation"]["omega_dw"]["white"] == false);
    CHECK(r.out.find("of its variance at order ") != std::string::npos);
    const Table spectra = read_table(out / "spectra.csv");
    CHECK(spectra.header[2] == "omega_dw_measured_psd [(rad/s)^2/Hz]");
}

TEST_CASE("a report without a crank angle has spectra and no orders", "[e2e][spectra]") {
    TempDir tmp;
    const auto out = tmp.path() / "cvt";
    // A stale orders.csv from an earlier report of tvid's in the same directory goes.
    std::filesystem::create_directories(out);
    tmp.write("cvt/summary.json", R"({ "tool": "tvid", "experiment": "cvt-tipin-clean" })");
    tmp.write("cvt/orders.csv", "split\n");
    const RunResult r = run_tvid({"fit", (source_dir() / "configs/cvt_tipin_clean.yaml").string(), "-o", out.string(),
                                  "--optimizer", "lm", "--set", "estimation.cost=l2", "--quiet"});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    CHECK(!std::filesystem::exists(out / "orders.csv"));
    const Table spectra = read_table(out / "spectra.csv");
    CHECK(spectra.header[2] == "Tds_measured_psd [(N m)^2/Hz]");
    const json summary = json::parse(read_text(out / "summary.json"));
    CHECK(summary["residual_spectrum"]["estimation"]["Tds"]["order"].is_null());
    CHECK(summary["residual_spectrum"]["estimation"]["Tds"]["frequency"]["share"].get<double>() > 0.0);
}

namespace {

// A one-node line 0.01·w' = T − c·w (c = 0.1), T = sin(2π·3t), recorded at `rate` Hz for
// `seconds`, its speed carrying a line at `line_hz` (0.05 rad/s): what the model misses.
std::string recording_at(double rate, double seconds, double line_hz) {
    const double pi = std::numbers::pi;
    const auto torque = [&](double t) { return std::sin(2 * pi * 3 * t); };
    const auto slope = [&](double t, double w) { return (torque(t) - 0.1 * w) / 0.01; };
    const auto n = static_cast<std::size_t>(std::lround(seconds * rate));
    std::ostringstream out;
    out.precision(12);
    out << "t,T,w\n";
    double w = 0.0;
    const double h = 1.0 / rate / 20;
    for (std::size_t i = 0; i <= n; ++i) {
        const double t = static_cast<double>(i) / rate;
        out << t << ',' << torque(t) << ',' << w + 0.05 * std::sin(2 * pi * line_hz * t) << '\n';
        for (int s = 0; s < 20; ++s) {
            const double ts = t + s * h;
            const double k1 = slope(ts, w), k2 = slope(ts + h / 2, w + h / 2 * k1), k3 = slope(ts + h / 2, w + h / 2 * k2),
                         k4 = slope(ts + h, w + h * k3);
            w += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
        }
    }
    return out.str();
}

}  // namespace

TEST_CASE("recordings at two sample rates: the spectrum keeps one rate, puts its line where it is, and says what it "
          "left out",
          "[e2e][spectra][recordings]") {
    const TempDir tmp;
    const auto fast = tmp.write("fast.csv", recording_at(1000.0, 2.0, 100.0));  // 2001 samples, a 100 Hz line
    const auto slow = tmp.write("slow.csv", recording_at(250.0, 4.0, 20.0));    // 1001 samples, a 20 Hz line
    const auto config = tmp.write("two_rates.yaml",
                                  "tvid: 1\n"
                                  "name: two-rates\n"
                                  "data:\n"
                                  "  recordings:\n"
                                  "    - { name: fast, file: " + fast.string() + ", time: t }\n"
                                  "    - { name: slow, file: " + slow.string() + ", time: t }\n"
                                  "model:\n"
                                  "  nodes:\n"
                                  "    - { name: a, J: 0.01 }\n"
                                  "  elements:\n"
                                  "    - { type: torque, name: drive, node: a, input: T }\n"
                                  "    - { type: friction, name: loss, node: a, c: c }\n"
                                  "inputs: { T: T }\n"
                                  "outputs:\n"
                                  "  w: { column: w, speed: a }\n"
                                  "parameters:\n"
                                  "  c: { init: 0.12, min: 0.01, max: 1 }\n"
                                  "windows:\n"
                                  "  estimation: [ { recording: fast }, { recording: slow } ]\n"
                                  "initial_state: rest\n"
                                  "estimation: { cost: l2, optimizer: lm }\n");
    const RunResult r = run_tvid({"fit", config.string(), "-o", (tmp.path() / "out").string(), "--threads", "1", "--json"});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const json s = json::parse(r.out);
    const json& band = s["residual_spectrum"]["estimation"]["w"]["frequency"];
    INFO(band.dump());
    // The 1 kHz recording holds most samples: its 100 Hz line, at 100 Hz.
    CHECK(std::abs(band["peak_hz"].get<double>() - 100.0) <= band["resolution_hz"].get<double>());
    CHECK(band["sample_rate_hz"].get<double>() == Approx(1000.0).epsilon(1e-6));
    CHECK(band["other_rate_samples"].get<std::size_t>() > 900);
    CHECK(band["gaps"] == 0);  // neither recording's own steps are gaps
    // The terminal says so.
    const RunResult text = run_tvid({"fit", config.string(), "-o", (tmp.path() / "out").string(), "--threads", "1"});
    CHECK(text.out.find("samples at 250 Hz left out") != std::string::npos);
    // The FRF likewise: H1 at the first window's rate, the other window named, no false gaps.
    const RunResult frf = run_tvid({"frf", config.string(), "-o", (tmp.path() / "frf").string(), "--input", "T",
                                    "--output", "w"});
    INFO(frf.out << frf.err);
    REQUIRE(frf.exit_code == 0);
    CHECK(frf.out.find("left out at another sample rate than its 1000 Hz: slow: whole recording (250 Hz)") !=
          std::string::npos);
    CHECK(frf.out.find("gap(s)") == std::string::npos);
    const json f = json::parse(read_text(tmp.path() / "frf" / "frf.json"));
    CHECK(f["measured"]["sample_rate_hz"].get<double>() == Approx(1000.0).epsilon(1e-6));
    CHECK(f["measured"]["left_out_windows"].size() == 1);
}

}  // namespace TVID_UNITY_ID
