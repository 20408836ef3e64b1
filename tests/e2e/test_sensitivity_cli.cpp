// `tvid sensitivity`: the forward sensitivities ∂y/∂p of the outputs through the binary
// (the methodology paper Figs. 4–5), their files, their physics, and the input it refuses.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
using nlohmann::json;

namespace {

// A CSV file as a header and rows of cells.
struct Csv {
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;

    std::size_t column(const std::string& name) const {
        const auto it = std::find(header.begin(), header.end(), name);
        REQUIRE(it != header.end());
        return static_cast<std::size_t>(it - header.begin());
    }
    double number(std::size_t row, const std::string& name) const { return std::stod(rows[row][column(name)]); }
};

std::vector<std::string> cells(const std::string& line) {
    std::vector<std::string> out;
    std::stringstream in(line);
    for (std::string cell; std::getline(in, cell, ',');) out.push_back(cell);
    if (!line.empty() && line.back() == ',') out.emplace_back();
    return out;
}

Csv read_csv(const std::filesystem::path& file) {
    std::istringstream in(read_text(file));
    Csv csv;
    std::string line;
    std::getline(in, line);
    csv.header = cells(line);
    while (std::getline(in, line)) csv.rows.push_back(cells(line));
    return csv;
}

// The expected sensitivity.csv header for these free parameters.
std::vector<std::string> expected_header(const std::vector<std::string>& free) {
    std::vector<std::string> h{"window", "time", "output", "y"};
    for (const auto& p : free) h.push_back("d_" + p);
    for (const auto& p : free) h.push_back("s_" + p);
    return h;
}

// ranking.csv: per output, every free parameter once, ranks 1..M, sorted by rms_scaled,
// relative = rms_scaled / the first one. Returns rms_scaled by parameter of `output`.
std::map<std::string, double> check_ranking(const Csv& ranking, const std::string& output,
                                            const std::vector<std::string>& free) {
    CHECK(ranking.header == std::vector<std::string>{"output", "rank", "parameter", "value", "rms_scaled", "relative",
                                                     "rms_raw"});
    std::map<std::string, double> rms;
    double previous = INFINITY, largest = 0;
    int rank = 0;
    for (std::size_t r = 0; r < ranking.rows.size(); ++r) {
        if (ranking.rows[r][0] != output) continue;
        CHECK(std::stoi(ranking.rows[r][1]) == ++rank);
        const double s = ranking.number(r, "rms_scaled");
        CHECK(s <= previous);
        previous = s;
        if (rank == 1) largest = s;
        CHECK(ranking.number(r, "relative") == Approx(s / largest).margin(1e-9));
        CHECK(s == Approx(std::abs(ranking.number(r, "value")) * ranking.number(r, "rms_raw")).epsilon(1e-8));
        rms[ranking.rows[r][2]] = s;
    }
    CHECK(rms.size() == free.size());
    for (const auto& p : free) CHECK(rms.count(p) == 1);
    return rms;
}

std::vector<std::string> free_parameters(const json& j) { return j["free_parameters"].get<std::vector<std::string>>(); }

// The speed of the damping wheel from `tvid simulate` on the estimation window.
std::vector<double> simulated_speed(const std::string& experiment, const std::filesystem::path& params) {
    const RunResult r = run_tvid({"simulate", experiment, "--params", params.string(), "--set", "windows.validation=[]"});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    std::istringstream in(r.out);
    std::string line;
    std::getline(in, line);
    const std::vector<std::string> header = cells(line);
    const auto col = static_cast<std::size_t>(std::find(header.begin(), header.end(), "omega_dw_simulated [rad/s]") - header.begin());
    REQUIRE(col < header.size());
    std::vector<double> y;
    while (std::getline(in, line)) y.push_back(std::stod(cells(line)[col]));
    return y;
}

}  // namespace

TEST_CASE("tvid sensitivity of the engine at the true parameters", "[e2e][sensitivity]") {
    TempDir tmp;
    const std::string exp = (source_dir() / "configs/engine_idle_clean.yaml").string();
    const json truth = json::parse(read_text(source_dir() / "data/engine/truth.json"))["parameters"];
    const auto params = tmp.write("truth.json", truth.dump());
    const auto out = tmp.path() / "sens";
    const RunResult r = run_tvid({"sensitivity", exp, "--params", params.string(), "-o", out.string(), "--threads", "1"});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    CHECK(r.out.find("tvid sensitivity engine-idle-clean") != std::string::npos);
    CHECK(r.out.find("J3") != std::string::npos);
    CHECK(r.out.find(out.string()) != std::string::npos);

    const json j = json::parse(read_text(out / "sensitivity.json"));
    CHECK(j["experiment"] == "engine-idle-clean");
    CHECK(j["model"] == "engine_block");
    for (const auto& p : j["parameters"]) CHECK(p["value"].get<double>() == truth[p["name"].get<std::string>()].get<double>());
    const std::vector<std::string> free = free_parameters(j);
    CHECK(free.size() == 10);
    REQUIRE(j["windows"].size() == 1);  // cycle 2; no validation windows without --validation
    CHECK(j["windows"][0]["window"] == "cycle 2");
    const std::size_t samples = j["samples"].get<std::size_t>();
    CHECK(samples > 1000);  // one engine cycle at 0.5 deg

    const Csv csv = read_csv(out / "sensitivity.csv");
    CHECK(csv.header == expected_header(free));
    REQUIRE(csv.rows.size() == samples * 1);  // one output: omega_dw
    CHECK(std::all_of(csv.rows.begin(), csv.rows.end(), [&](auto& row) { return row.size() == csv.header.size(); }));
    // The scaled sensitivity is p·∂y/∂p.
    for (std::size_t i = 0; i < csv.rows.size(); i += 97)
        CHECK(csv.number(i, "s_J3") == Approx(0.12 * csv.number(i, "d_J3")).epsilon(1e-8).margin(1e-12));

    const std::map<std::string, double> rms = check_ranking(read_csv(out / "ranking.csv"), "omega_dw", free);
    // Every inertia moves the damping-wheel speed, and the ranking is not all zeros.
    for (const char* inertia : {"J1", "J2", "J3", "m"}) CHECK(rms.at(inertia) > 1e-3);
    CHECK(std::max_element(rms.begin(), rms.end(), [](auto& a, auto& b) { return a.second < b.second; })->second > 0.1);
    // Rigid-body physics: the friction torque on the crankshaft is −(C1 + 4·C2 + C3)·ω at
    // idle, so ∂ω/∂C2 = 4·∂ω/∂C1 = 4·∂ω/∂C3 up to the small twist of the shaft.
    const Csv ranking = read_csv(out / "ranking.csv");
    std::map<std::string, double> raw;
    for (std::size_t i = 0; i < ranking.rows.size(); ++i) raw[ranking.rows[i][2]] = ranking.number(i, "rms_raw");
    CHECK(raw.at("C2") == Approx(4 * raw.at("C1")).epsilon(0.02));
    CHECK(raw.at("C3") == Approx(raw.at("C1")).epsilon(0.02));

    // ∂ω/∂J3 is the slope of the simulated speed: central difference of `tvid simulate`.
    const double J3 = truth["J3"].get<double>(), h = 1e-3 * J3;
    json up = truth, down = truth;
    up["J3"] = J3 + h;
    down["J3"] = J3 - h;
    const std::vector<double> y_up = simulated_speed(exp, tmp.write("up.json", up.dump()));
    const std::vector<double> y_down = simulated_speed(exp, tmp.write("down.json", down.dump()));
    REQUIRE(y_up.size() == csv.rows.size());
    double largest = 0, worst = 0;
    for (std::size_t i = 0; i < csv.rows.size(); ++i) {
        const double d = csv.number(i, "d_J3");
        largest = std::max(largest, std::abs(d));
        worst = std::max(worst, std::abs((y_up[i] - y_down[i]) / (2 * h) - d));
    }
    CHECK(largest > 1.0);
    CHECK(worst < 1e-3 * largest);
}

TEST_CASE("tvid sensitivity of the CVT shows the scaling symmetry of its parameters", "[e2e][sensitivity]") {
    TempDir tmp;
    const std::string exp = (source_dir() / "configs/cvt_tipin_clean.yaml").string();
    const auto out = tmp.path() / "sens";
    const RunResult r = run_tvid({"sensitivity", exp, "-o", out.string(), "--validation", "--threads", "2"});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);

    const json j = json::parse(read_text(out / "sensitivity.json"));
    const std::vector<std::string> free = free_parameters(j);
    CHECK(free.size() == 9);
    REQUIRE(j["windows"].size() == 3);  // estimation, then the two validation windows
    CHECK(j["windows"][0]["split"] == "estimation");
    CHECK(j["windows"][0]["samples"] == 1500);
    CHECK(j["windows"][1]["split"] == "validation");
    CHECK(j["samples"] == 1500 + 500 + 500);

    const Csv csv = read_csv(out / "sensitivity.csv");
    CHECK(csv.header == expected_header(free));
    REQUIRE(csv.rows.size() == 2500);
    const std::map<std::string, double> rms = check_ranking(read_csv(out / "ranking.csv"), "Tds", free);
    // ∂Tds/∂Δds = 1: the offset's scaled sensitivity is Δds itself (init −7.5).
    CHECK(rms.at("d_ds") == Approx(7.5).epsilon(1e-9));
    // Yoshida & Takamatsu's parametrization is invariant under ρ1 → λρ1, μ → λμ, k±, c±, σ → ·/λ
    // (docs/model-library.md), so the scaled sensitivities along it cancel at every sample.
    double worst = 0, largest = 0;
    for (std::size_t i = 0; i < csv.rows.size(); ++i) {
        const double along = csv.number(i, "s_rho1") + csv.number(i, "s_mu") - csv.number(i, "s_k_minus") -
                             csv.number(i, "s_k_plus") - csv.number(i, "s_c_minus") - csv.number(i, "s_c_plus") -
                             csv.number(i, "s_sigma");
        worst = std::max(worst, std::abs(along));
        largest = std::max(largest, std::abs(csv.number(i, "s_rho1")));
    }
    CHECK(largest > 1.0);
    CHECK(worst < 1e-6 * largest);
}

TEST_CASE("tvid sensitivity writes into the report directory by default, --json and --quiet", "[e2e][sensitivity]") {
    TempDir tmp;
    const std::string exp = (source_dir() / "configs/cvt_tipin_clean.yaml").string();
    const auto report = tmp.path() / "report";
    const RunResult r = run_tvid({"sensitivity", exp, "--set", "report.dir=" + report.string(), "--json"});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    json printed = json::parse(r.out);
    const json written = json::parse(read_text(report / "sensitivity" / "sensitivity.json"));
    // --json prints the file's document and where the report went.
    CHECK(printed["report"] == (report / "sensitivity").string());
    printed.erase("report");
    CHECK(printed == written);
    CHECK(printed["experiment"] == "cvt-tipin-clean");
    CHECK(std::filesystem::exists(report / "sensitivity" / "ranking.csv"));

    const RunResult quiet = run_tvid({"sensitivity", exp, "-o", (tmp.path() / "q").string(), "--quiet"});
    CHECK(quiet.exit_code == 0);
    CHECK(quiet.out.empty());
    CHECK(std::filesystem::exists(tmp.path() / "q" / "sensitivity.csv"));
}

TEST_CASE("tvid sensitivity refuses a bad parameter file and an unwritable output folder", "[e2e][sensitivity]") {
    TempDir tmp;
    const std::string exp = (source_dir() / "configs/cvt_tipin_clean.yaml").string();
    const auto one_line = [](const std::string& err) { return std::count(err.begin(), err.end(), '\n') == 1; };

    const auto bad = tmp.write("bad.json", R"({"rho1": "heavy"})");
    const RunResult r1 = run_tvid({"sensitivity", exp, "--params", bad.string(), "-o", (tmp.path() / "o1").string()});
    CHECK(r1.exit_code == 2);
    CHECK(r1.err.find(bad.string()) != std::string::npos);
    CHECK(r1.err.find("rho1") != std::string::npos);
    CHECK(one_line(r1.err));
    CHECK(!std::filesystem::exists(tmp.path() / "o1"));

    const auto missing = tmp.path() / "missing.json";
    const RunResult r2 = run_tvid({"sensitivity", exp, "--params", missing.string()});
    CHECK(r2.exit_code == 2);
    CHECK(r2.err.find(missing.string()) != std::string::npos);

    // A folder below a plain file cannot be created, whoever runs the test (even root).
    const auto blocker = tmp.write("blocker", "a file, not a folder");
    const RunResult r3 = run_tvid({"sensitivity", exp, "-o", (blocker / "sens").string()});
    CHECK(r3.exit_code == 2);
    CHECK(r3.err.find((blocker / "sens").string()) != std::string::npos);
    CHECK(one_line(r3.err));
    CHECK(r3.out.empty());
}

TEST_CASE("tvid sensitivity exits 1 and names the window when its simulation fails", "[e2e][sensitivity]") {
    TempDir tmp;
    const std::string exp = (source_dir() / "configs/cvt_tipin_clean.yaml").string();
    const auto out = tmp.path() / "sens";
    const RunResult r = run_tvid({"sensitivity", exp, "-o", out.string(), "--set", "simulation.method=dopri5", "--set",
                                  "simulation.max_steps=10"});
    CHECK(r.exit_code == 1);
    CHECK(r.err.find("estimation window time 1.5 to 3") != std::string::npos);
    CHECK(r.err.find("step budget exceeded") != std::string::npos);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK(r.out.empty());
    // The directory was claimed before the work; nothing was written into it.
    CHECK(!std::filesystem::exists(out / "sensitivity.json"));
    CHECK(!std::filesystem::exists(out / "sensitivity.csv"));
}

}  // namespace TVID_UNITY_ID
