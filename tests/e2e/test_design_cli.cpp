// `tvid design --evaluate` through the binary: the report's files and what they say (each
// candidate at its RMS within its limits, standard errors that scale with the noise, the
// assumptions stated), a given input beside the generated ones, and the design section's
// mistakes refused in one line with exit status 2.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <random>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
using nlohmann::json;

namespace {

const std::string kDesign =
    "design={ input: T_motor, duration: 2.5, band: [0.5, 40], limits: [-20, 40], base: 10, rms: 8, "
    "noise: { w2: 0.05, T_shaft: 0.2 } }";

std::vector<std::string> design_args(const TempDir& dir, const std::string& out, const std::string& design = kDesign) {
    return {"design", (source_dir() / "configs/constant_load.yaml").string(), "--evaluate", "--quiet",
            "-o", (dir.path() / out).string(), "--set", design};
}

// candidate -> parameter -> relative standard error
std::map<std::string, std::map<std::string, double>> relative_se(const json& report) {
    std::map<std::string, std::map<std::string, double>> out;
    for (const json& c : report["candidates"])
        for (const json& p : c["parameters"]) out[c["name"]][p["name"]] = p["relative_se"].get<double>();
    return out;
}

// The design input column of a candidate's CSV.
std::vector<double> input_column(const std::filesystem::path& file) {
    std::istringstream in(read_text(file));
    std::string line;
    std::getline(in, line);
    CHECK(line == "t,T_motor");
    std::vector<double> v;
    while (std::getline(in, line)) v.push_back(std::stod(line.substr(line.find(',') + 1)));
    return v;
}

}  // namespace

TEST_CASE("tvid design --evaluate predicts each reference input's standard errors and writes the inputs", "[design]") {
    const TempDir dir;
    RunResult r = run_tvid(design_args(dir, "a"));
    REQUIRE(r.exit_code == 0);
    const json report = json::parse(read_text(dir.path() / "a/design.json"));
    CHECK(report["tool"] == "tvid");
    CHECK(report["assumptions"]["prediction"].get<std::string>().find("local") != std::string::npos);
    CHECK(report["assumptions"]["nominal"]["k"] == 560.0);  // the experiment's init
    CHECK(report["assumptions"]["noise"]["T_shaft"]["sigma"] == 0.2);
    CHECK(report["assumptions"]["operating_point"]["base"] == 10.0);
    REQUIRE(report["candidates"].size() == 3);
    for (const json& c : report["candidates"]) {
        INFO(c["name"]);
        CHECK(c["simulated"] == true);
        CHECK(c["rms"].get<double>() == Approx(8.0).epsilon(1e-6));
        CHECK(c["min"].get<double>() >= -20.0);
        CHECK(c["max"].get<double>() <= 40.0);
        CHECK(c["samples"] == 2501);
        REQUIRE(c["parameters"].size() == 6);
        for (const json& p : c["parameters"]) {
            CHECK(p["se"].get<double>() > 0);
            CHECK(p["relative_se"].get<double>() < 1);  // 2.5 s of a two-inertia line determine each
        }
        const std::vector<double> v = input_column(dir.path() / "a" / c["file"].get<std::string>());
        CHECK(v.size() == 2501);
        double sum = 0;
        for (double x : v) sum += (x - 10) * (x - 10);
        CHECK(std::sqrt(sum / static_cast<double>(v.size())) == Approx(8.0).epsilon(1e-6));
    }
    CHECK((report["best"] == "multisine" || report["best"] == "chirp" || report["best"] == "prbs"));
    const std::string csv = read_text(dir.path() / "a/predicted_se.csv");
    CHECK(csv.rfind("candidate,parameter,nominal,se,relative_se,determined\n", 0) == 0);

    // Twice the noise on every output: the information falls 4 times, every standard error doubles.
    r = run_tvid(design_args(dir, "b",
                             "design={ input: T_motor, duration: 2.5, band: [0.5, 40], limits: [-20, 40], base: 10, "
                             "rms: 8, noise: { w2: 0.1, T_shaft: 0.4 } }"));
    REQUIRE(r.exit_code == 0);
    const auto a = relative_se(report), b = relative_se(json::parse(read_text(dir.path() / "b/design.json")));
    for (const auto& [candidate, params] : a)
        for (const auto& [name, se] : params) CHECK(b.at(candidate).at(name) == Approx(2 * se).epsilon(1e-9));
    // Noise on the shaft torque alone raised: the shaft's parameters lose more than the load's friction.
    r = run_tvid(design_args(dir, "c",
                             "design={ input: T_motor, duration: 2.5, band: [0.5, 40], limits: [-20, 40], base: 10, "
                             "rms: 8, noise: { w2: 0.05, T_shaft: 20 } }"));
    REQUIRE(r.exit_code == 0);
    const auto c = relative_se(json::parse(read_text(dir.path() / "c/design.json")));
    CHECK(c.at("chirp").at("k") > 3 * a.at("chirp").at("k"));
}

TEST_CASE("tvid design searches a multisine's band powers for the criterion, never worse than the flat one", "[design]") {
    const TempDir dir;
    const RunResult r = run_tvid({"design", (source_dir() / "configs/constant_load.yaml").string(), "--quiet", "-o",
                                  (dir.path() / "d").string(), "--set",
                                  "design={ input: T_motor, duration: 2.5, band: [0.5, 40], limits: [-20, 40], base: 10, "
                                  "rms: 8, noise: { w2: 0.05, T_shaft: 0.2 }, criterion: worst_relative_se, bands: 4, "
                                  "evaluations: 15 }"});
    REQUIRE(r.exit_code == 0);
    const json report = json::parse(read_text(dir.path() / "d/design.json"));
    CHECK(report["mode"] == "design");
    REQUIRE(report["candidates"].size() == 4);
    const json& designed = report["candidates"][0];
    CHECK(designed["name"] == "designed");
    CHECK(designed["file"] == "designed.csv");
    CHECK(designed["rms"].get<double>() == Approx(8.0).epsilon(1e-6));
    const json& search = designed["search"];
    CHECK(search["evaluations"].get<int>() <= 15);
    CHECK(search["band_edges_hz"].size() == 5);
    double total = 0;
    for (const json& p : search["band_power"]) total += p.get<double>();
    CHECK(total == Approx(1.0));
    // The search starts from the flat multisine and keeps the best it saw; the designed
    // input's prediction, made again, is the search's to the last digits.
    const double worst = designed["criteria"]["worst_relative_se"].get<double>();
    CHECK(worst == Approx(search["criterion"].get<double>()).epsilon(1e-12));
    CHECK(worst <= search["flat_multisine_criterion"].get<double>());
    CHECK(search["flat_multisine_criterion"].get<double>() ==
          Approx(report["candidates"][1]["criteria"]["worst_relative_se"].get<double>()).epsilon(1e-12));
    const std::vector<double> v = input_column(dir.path() / "d/designed.csv");
    CHECK(v.size() == 2501);
}

TEST_CASE("tvid design with robust draws ranks the candidates by the criterion averaged over them", "[design]") {
    const TempDir dir;
    const RunResult r = run_tvid({"design", (source_dir() / "configs/constant_load.yaml").string(), "--quiet", "-o",
                                  (dir.path() / "r").string(), "--set",
                                  "design={ input: T_motor, duration: 2.5, band: [0.5, 40], limits: [-20, 40], base: 10, "
                                  "rms: 8, noise: { w2: 0.05, T_shaft: 0.2 }, criterion: a_optimal, bands: 3, "
                                  "evaluations: 6, robust: { draws: 2, spread: 0.4, seed: 3 } }"});
    REQUIRE(r.exit_code == 0);
    const json report = json::parse(read_text(dir.path() / "r/design.json"));
    const json& robust = report["assumptions"]["robust"];
    CHECK(robust["draws"] == 2);
    REQUIRE(robust["parameter_sets"].size() == 2);
    for (const json& set : robust["parameter_sets"]) {
        const double k = set["k"].get<double>(), nominal = report["assumptions"]["nominal"]["k"].get<double>();
        CHECK(k != nominal);
        CHECK(k / nominal >= 1 / 1.4 - 1e-12);
        CHECK(k / nominal <= 1.4 + 1e-12);
    }
    std::string best;
    double lowest = 1e300;
    for (const json& c : report["candidates"]) {
        INFO(c["name"]);
        const json& draws = c["robust"];
        REQUIRE(draws["criterion_per_draw"].size() == 2);
        // The geometric mean of the nominal criterion and the two draws'.
        const double product = c["criteria"]["a_optimal"].get<double>() * draws["criterion_per_draw"][0].get<double>() *
                               draws["criterion_per_draw"][1].get<double>();
        CHECK(draws["averaged_criterion"].get<double>() == Approx(std::cbrt(product)).epsilon(1e-12));
        if (draws["averaged_criterion"].get<double>() < lowest) {
            lowest = draws["averaged_criterion"].get<double>();
            best = c["name"];
        }
    }
    CHECK(report["best"] == best);
    CHECK(report["candidates"][0]["search"]["criterion"].get<double>() ==
          Approx(report["candidates"][0]["robust"]["averaged_criterion"].get<double>()).epsilon(1e-12));
}

TEST_CASE("tvid design --evaluate takes a given input from a CSV beside the reference ones", "[design]") {
    const TempDir dir;
    std::vector<std::string> args = design_args(dir, "g");
    args.insert(args.end(), {"--input", (source_dir() / "data/constant_load/constant_load.csv").string()});
    const RunResult r = run_tvid(args);
    REQUIRE(r.exit_code == 0);
    const json report = json::parse(read_text(dir.path() / "g/design.json"));
    REQUIRE(report["candidates"].size() == 4);
    const json& given = report["candidates"][0];
    CHECK(given["name"] == "given");
    CHECK(given["file"].is_null());
    CHECK(given["samples"].get<int>() > 2500);  // the whole recording
    CHECK(given["simulated"] == true);
    CHECK_FALSE(std::filesystem::exists(dir.path() / "g/given.csv"));

    std::vector<std::string> wrong = design_args(dir, "w");
    wrong.insert(wrong.end(), {"--input", (source_dir() / "data/constant_load/constant_load.csv").string(), "--column", "T_x"});
    const RunResult bad = run_tvid(wrong);
    CHECK(bad.exit_code == 2);
    CHECK(bad.err.find("column T_x") != std::string::npos);
}

TEST_CASE("tvid design refuses a design it cannot evaluate in one line, writing nothing", "[design]") {
    const TempDir dir;
    const std::vector<std::pair<std::string, std::string>> cases{
        {"design={ input: T_motor, band: [1, 600], limits: [-20, 40], base: 10, rms: 8, noise: { w2: 0.05, T_shaft: 0.2 } }",
         "design.band: its high end 600 Hz is above the Nyquist frequency 500 Hz"},
        {"design={ input: T_motor, band: [1, 40], limits: [12, 40], base: 10, rms: 8, noise: { w2: 0.05, T_shaft: 0.2 } }",
         "design.limits: [12, 40] excludes the operating point base = 10"},
        {"design={ input: w2, band: [1, 40], limits: [-20, 40], base: 10, rms: 8, noise: { w2: 0.05, T_shaft: 0.2 } }",
         "design.input: 'w2' is not an input of the model"},
        {"design={ input: T_motor, band: [1, 40], limits: [-20, 40], base: 10, rms: 8, noise: { w2: 0, T_shaft: 0.2 } }",
         "design.noise.w2: the noise standard deviation must be above 0"},
        {"design={ input: T_motor, band: [1, 40], limits: [-20, 40], base: 10, rms: 80, noise: { w2: 0.05, T_shaft: 0.2 } }",
         "design.rms: 80 is more than the limits [-20, 40] allow"},
    };
    for (const auto& [design, message] : cases) {
        INFO(design);
        const RunResult r = run_tvid(design_args(dir, "x", design));
        CHECK(r.exit_code == 2);
        CHECK(r.err.find(message) != std::string::npos);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
        CHECK_FALSE(std::filesystem::exists(dir.path() / "x/design.json"));
    }
    // Without a design section, the line names it.
    const RunResult none = run_tvid({"design", (source_dir() / "configs/constant_load.yaml").string(), "--evaluate",
                                     "-o", (dir.path() / "y").string()});
    CHECK(none.exit_code == 2);
    CHECK(none.err.find("constant_load.yaml:") != std::string::npos);
    CHECK(none.err.find("design: missing") != std::string::npos);
}

namespace {

// A noisy record of `input` (t, T_engine) through the clutch damper at its true parameters:
// tvid simulate's noise-free outputs plus white noise of 0.05 rad/s from `seed` (Box–Muller
// on mt19937_64's raw numbers: the same on every machine).
std::string noisy_record(const TempDir& dir, const std::string& name, const std::vector<double>& t,
                         const std::vector<double>& u, const std::string& truth, std::uint64_t seed,
                         std::vector<std::vector<double>>& clean) {
    if (clean.empty()) {
        std::ostringstream rec;
        rec << "t,T_engine,w1,w2\n";
        for (std::size_t i = 0; i < t.size(); ++i) rec << t[i] << ',' << u[i] << ",0,0\n";
        const std::string file = dir.write(name + "_input.csv", rec.str()).string();
        const RunResult sim = run_tvid({"simulate", (source_dir() / "configs/clutch_damper.yaml").string(), "--params",
                                        truth, "-o", (dir.path() / (name + "_sim.csv")).string(), "--set",
                                        "data={ file: " + file + ", time: t }", "--set",
                                        "windows={ estimation: [ { time: [0, " + std::to_string(t.back()) + "] } ] }"});
        REQUIRE(sim.exit_code == 0);
        std::istringstream in(read_text(dir.path() / (name + "_sim.csv")));
        std::string line;
        std::getline(in, line);
        clean.assign(2, std::vector<double>(1, 0.0));  // the start at rest: both speeds 0
        while (std::getline(in, line)) {
            std::vector<std::string> cells;
            std::stringstream row(line);
            for (std::string c; std::getline(row, c, ',');) cells.push_back(c);
            clean[0].push_back(std::stod(cells[3]));  // w1_simulated
            clean[1].push_back(std::stod(cells[7]));  // w2_simulated
        }
        REQUIRE(clean[0].size() == t.size());
    }
    std::mt19937_64 rng(seed);
    const auto normal = [&] {
        const double a = (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53, b = static_cast<double>(rng() >> 11) * 0x1.0p-53;
        return std::sqrt(-2 * std::log(a)) * std::cos(2 * 3.141592653589793 * b);
    };
    std::ostringstream rec;
    rec.precision(12);
    rec << "t,T_engine,w1,w2\n";
    for (std::size_t i = 0; i < t.size(); ++i)
        rec << t[i] << ',' << u[i] << ',' << clean[0][i] + 0.05 * normal() << ',' << clean[1][i] + 0.05 * normal() << '\n';
    return dir.write(name + "_" + std::to_string(seed) + ".csv", rec.str()).string();
}

std::vector<std::vector<double>> csv_columns(const std::filesystem::path& file) {
    std::istringstream in(read_text(file));
    std::string line;
    std::getline(in, line);
    std::vector<std::vector<double>> cols(2);
    while (std::getline(in, line)) {
        const auto comma = line.find(',');
        cols[0].push_back(std::stod(line.substr(0, comma)));
        cols[1].push_back(std::stod(line.substr(comma + 1)));
    }
    return cols;
}

}  // namespace

TEST_CASE("a designed input's fits spread as tvid design predicts, and less than a chirp's", "[design][fits]") {
    const TempDir dir;
    const json truth = json::parse(read_text(source_dir() / "data/clutch_damper/truth.json"))["parameters"];
    const std::string truth_file = dir.write("truth.json", truth.dump()).string();
    const RunResult d = run_tvid({"design", (source_dir() / "configs/clutch_damper.yaml").string(), "--quiet", "--params",
                                  truth_file, "-o", (dir.path() / "design").string(), "--set",
                                  "design={ input: T_engine, duration: 2, band: [0.5, 40], limits: [-100, 150], base: 20, "
                                  "rms: 30, noise: { w1: 0.05, w2: 0.05 }, criterion: worst_relative_se, evaluations: 30 }"});
    REQUIRE(d.exit_code == 0);
    const json report = json::parse(read_text(dir.path() / "design/design.json"));
    std::map<std::string, json> candidate;
    for (const json& c : report["candidates"]) candidate[c["name"]] = c;
    const double designed_worst = candidate["designed"]["criteria"]["worst_relative_se"].get<double>();
    CHECK(designed_worst < candidate["chirp"]["criteria"]["worst_relative_se"].get<double>());

    // Eight noisy records of each input, each fitted as the prediction assumes (weights 1/σ).
    std::map<std::string, double> worst_spread;
    for (const std::string name : {"designed", "chirp"}) {
        INFO(name);
        const auto cols = csv_columns(dir.path() / "design" / (name + ".csv"));
        std::vector<std::vector<double>> clean;
        std::map<std::string, std::vector<double>> fitted;
        for (std::uint64_t seed = 1; seed <= 8; ++seed) {
            const std::string rec = noisy_record(dir, name, cols[0], cols[1], truth_file, seed, clean);
            const std::string out = (dir.path() / (name + "_fit")).string();
            const RunResult f = run_tvid({"fit", (source_dir() / "configs/clutch_damper.yaml").string(), "--quiet",
                                          "--force", "-o", out, "--set", "data={ file: " + rec + ", time: t }", "--set",
                                          "windows={ estimation: [ { time: [0, 2] } ] }", "--set",
                                          "estimation.normalize=none", "--set", "outputs.w1.weight=20", "--set",
                                          "outputs.w2.weight=20"});
            REQUIRE(f.exit_code == 0);
            const json summary = json::parse(read_text(std::filesystem::path(out) / "summary.json"));
            REQUIRE(summary["optimizer"]["converged"] == true);
            for (const json& p : summary["parameters"]) fitted[p["name"]].push_back(p["value"].get<double>());
        }
        for (const json& p : candidate[name]["parameters"]) {
            const std::vector<double>& v = fitted[p["name"]];
            double mean = 0, sq = 0;
            for (double x : v) mean += x / static_cast<double>(v.size());
            for (double x : v) sq += (x - mean) * (x - mean);
            const double sd = std::sqrt(sq / static_cast<double>(v.size() - 1));
            const double se = p["se"].get<double>();
            INFO(p["name"] << ": fitted SD " << sd << ", predicted SE " << se);
            // A standard deviation of 8 values is uncertain by about 27 %: these bounds are 3 of those.
            CHECK(sd / se > 0.35);
            CHECK(sd / se < 1.9);
            CHECK(std::abs(mean - p["nominal"].get<double>()) < 4 * se);
            worst_spread[name] = std::max(worst_spread[name], sd / std::abs(p["nominal"].get<double>()));
        }
    }
    CHECK(worst_spread["designed"] < worst_spread["chirp"]);
}

}  // namespace TVID_UNITY_ID
