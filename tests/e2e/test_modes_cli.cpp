// `tvid modes` and `tvid frf` through the binary on the shipped experiments, the input they
// refuse, and the `modes` block of a fit's summary.json.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
using nlohmann::json;

namespace {

json modes_of(const std::string& config, const TempDir& tmp, std::vector<std::string> extra = {}) {
    const std::string dir = (tmp.path() / "modes").string();
    std::vector<std::string> args{"modes", (source_dir() / "configs" / config).string(), "-o", dir};
    args.insert(args.end(), extra.begin(), extra.end());
    const RunResult r = run_tvid(args);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    CHECK(r.out.find("f_n [Hz]") != std::string::npos);
    const std::string csv = read_text(tmp.path() / "modes" / "modes.csv");
    CHECK(csv.rfind("mode,kind,frequency_hz,damped_frequency_hz,damping_ratio,", 0) == 0);
    const json j = json::parse(read_text(tmp.path() / "modes" / "modes.json"));
    // One CSV row per mode.
    CHECK(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')) == j["modes"].size() + 1);
    return j;
}

int count_kind(const json& modes, const std::string& kind) {
    int n = 0;
    for (const json& m : modes["modes"]) n += m["kind"] == kind;
    return n;
}

std::size_t first_line_count(const std::string& text) { return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')); }

}  // namespace

TEST_CASE("tvid modes on the bench: the line's free angle and its lightly damped twisting modes", "[modes][e2e]") {
    const TempDir tmp;
    const json j = modes_of("aalto_bench.yaml", tmp);
    CHECK(j["operating_point"]["initial_state"] == "steady");
    CHECK(j["linearisation"]["angle_dependence"] == "revolution_mean");
    // The drive prescribes the motor's speed: its speed state is gone, its angle stays.
    const auto& states = j["linearisation"]["states"];
    CHECK(std::find(states.begin(), states.end(), "omega:motor") == states.end());
    CHECK(std::find(states.begin(), states.end(), "theta:motor") != states.end());
    CHECK(count_kind(j, "rigid_body") >= 1);
    CHECK(count_kind(j, "oscillating") >= 3);
    for (const json& m : j["modes"]) {
        if (m["kind"] != "oscillating") continue;
        CHECK(m["damping_ratio"].get<double>() > 0.0);
        CHECK(m["damping_ratio"].get<double>() < 1.0);
        CHECK(m["frequency_hz"].get<double>() >= m["damped_frequency_hz"].get<double>());
        // The motor is held by the drive: it takes no part in a twisting mode.
        CHECK(std::abs(m["shape"]["motor"].get<double>()) < 1e-9);
    }
    // Geared 1:3 and 1:4: the rigid body turns alike on the motor's shaft.
    CHECK(j["linearisation"]["ratios"]["load"].get<double>() == Approx(1.0 / 12.0).epsilon(1e-12));
    for (const json& m : j["modes"])
        if (m["kind"] == "rigid_body")
            for (const auto& [node, v] : m["shape_common_shaft"].items()) CHECK(v.get<double>() == Approx(1.0).epsilon(1e-6));
}

TEST_CASE("tvid modes on the engine and the CVT driveline", "[modes][e2e]") {
    {
        const TempDir tmp;
        const json j = modes_of("engine_idle.yaml", tmp);
        CHECK(j["operating_point"]["initial_state"] == "measured");
        CHECK(count_kind(j, "rigid_body") >= 1);  // a free crankshaft
        CHECK(count_kind(j, "oscillating") == 5);  // six inertias on a free line
        bool cylinder_noted = false;
        for (const json& e : j["linearisation"]["elements"])
            cylinder_noted = cylinder_noted || (e["kind"] == "cylinder" && e["method"] == "revolution_mean");
        CHECK(cylinder_noted);
    }
    {
        const TempDir tmp;
        const json j = modes_of("engine_idle.yaml", tmp, {"--angles", "operating_point"});
        for (const json& e : j["linearisation"]["elements"])
            if (e["kind"] == "cylinder") CHECK(e["method"] == "operating_point");
    }
    {
        const TempDir tmp;
        const json j = modes_of("cvt_tipin.yaml", tmp);
        CHECK(j["operating_point"]["initial_state"] == "equilibrium");
        REQUIRE(j["modes"].size() >= 1);
        for (const json& m : j["modes"]) CHECK(m["frequency_hz"].get<double>() > 0.0);
        bool clearance_noted = false;
        for (const json& e : j["linearisation"]["elements"])
            clearance_noted = clearance_noted || e["method"] == "operating_point";
        CHECK(clearance_noted);
    }
}

TEST_CASE("tvid modes refuses a window the experiment lacks and a missing parameter file", "[modes][e2e]") {
    const TempDir tmp;
    const std::string config = (source_dir() / "configs/aalto_bench.yaml").string();
    const RunResult window = run_tvid({"modes", config, "-o", (tmp.path() / "a").string(), "--window", "3"});
    CHECK(window.exit_code == 2);
    CHECK(first_line_count(window.err) == 1);
    CHECK(window.err.find("--window") != std::string::npos);
    const RunResult params =
        run_tvid({"modes", config, "-o", (tmp.path() / "b").string(), "--params", (tmp.path() / "nowhere.json").string()});
    CHECK(params.exit_code == 2);
    CHECK(first_line_count(params.err) == 1);
    CHECK(params.err.find("nowhere.json") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(tmp.path() / "a" / "modes.csv"));
    const RunResult input = run_tvid({"frf", config, "-o", (tmp.path() / "c").string(), "--input", "nothing", "--output",
                                      "torque_lower"});
    CHECK(input.exit_code == 2);
    CHECK(first_line_count(input.err) == 1);
    CHECK(input.err.find("T_prop") != std::string::npos);  // the inputs it has
}

TEST_CASE("tvid frf on the bench: the model's response and the measured H1 on one grid", "[modes][e2e]") {
    const TempDir tmp;
    const RunResult r = run_tvid({"frf", (source_dir() / "configs/aalto_bench.yaml").string(), "-o",
                                  (tmp.path() / "frf").string(), "--input", "T_prop", "--output", "torque_lower"});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const json j = json::parse(read_text(tmp.path() / "frf" / "frf.json"));
    CHECK(j["input_unit"] == "N m");
    CHECK(j["output_unit"] == "N m");
    const auto& rows = j["rows"];
    REQUIRE(rows.size() > 10);
    const double fs = j["measured"]["sample_rate_hz"].get<double>();
    const double n = j["measured"]["segment_length"].get<double>();
    CHECK(rows[0]["frequency_hz"].get<double>() == Approx(fs / n).epsilon(1e-12));
    CHECK(rows.back()["frequency_hz"].get<double>() == Approx(fs / 2).epsilon(1e-12));
    // The load motor's torque (through its 1:8 gear, scale −8) reaches the stage-2 output
    // shaft: well below the first resonance the load shaft carries it statically, |H| → 8.
    CHECK(rows[0]["model_magnitude"].get<double>() == Approx(8.0).epsilon(0.05));
    // The model's finer curve spans the same band, ascending, with more points than the grid.
    const auto& curve = j["model_curve"]["frequency_hz"];
    REQUIRE(curve.size() > rows.size());
    CHECK(curve.front().get<double>() == Approx(fs / n).epsilon(1e-12));
    CHECK(std::is_sorted(curve.begin(), curve.end()));
    CHECK(j["model_curve"]["magnitude"].size() == curve.size());
    const std::string csv = read_text(tmp.path() / "frf" / "frf.csv");
    CHECK(csv.rfind("frequency_hz,model_magnitude,model_phase_deg,measured_magnitude,measured_phase_deg,coherence\n", 0) == 0);
    if (j["measured"]["available"].get<bool>()) {
        for (const json& row : rows) {
            CHECK(row["coherence"].get<double>() >= 0.0);
            CHECK(row["coherence"].get<double>() <= 1.0 + 1e-9);
        }
    }
}

TEST_CASE("tvid frf --resolution and --segment choose Welch's segment and say so", "[modes][e2e]") {
    const TempDir tmp;
    const std::string config = (source_dir() / "configs/aalto_bench.yaml").string();
    const auto frf = [&](std::vector<std::string> extra) {
        std::vector<std::string> args{"frf", config, "-o", (tmp.path() / "frf").string(), "--input", "T_prop",
                                      "--output", "torque_lower", "--json"};
        args.insert(args.end(), extra.begin(), extra.end());
        return run_tvid(args);
    };
    const RunResult fine = frf({"--resolution", "0.25"});
    INFO(fine.err);
    REQUIRE(fine.exit_code == 0);
    const json j = json::parse(fine.out);
    const double fs = j["measured"]["sample_rate_hz"].get<double>();
    const double n = j["measured"]["segment_length"].get<double>();
    CHECK(n == std::ceil(fs / 0.25));                 // fs/HZ rounded up
    CHECK(j["measured"]["resolution_hz"].get<double>() <= 0.25);
    CHECK(j["measured"]["resolution_hz"].get<double>() == Approx(fs / n).epsilon(1e-12));
    CHECK(j["rows"][0]["frequency_hz"].get<double>() == Approx(fs / n).epsilon(1e-12));
    CHECK(j["report"] == (tmp.path() / "frf").string());  // --json names where the files went

    const RunResult segment = frf({"--segment", "300"});
    REQUIRE(segment.exit_code == 0);
    CHECK(json::parse(segment.out)["measured"]["segment_length"] == 300);
    // A segment the windows cannot give: exit 2, naming the finest resolution they allow.
    const RunResult too_long = frf({"--segment", "100000000"});
    CHECK(too_long.exit_code == 2);
    CHECK(too_long.err.find("--segment") != std::string::npos);
    CHECK(too_long.err.find("finest resolution") != std::string::npos);
    CHECK(frf({"--segment", "4"}).exit_code == 2);
    CHECK(frf({"--resolution", "-1"}).exit_code == 2);
    CHECK(frf({"--resolution", "1", "--segment", "512"}).exit_code == 2);  // one or the other
}

TEST_CASE("tvid fit writes the modes at the fitted parameters into summary.json", "[modes][e2e][fits]") {
    const TempDir tmp;
    const std::string dir = (tmp.path() / "fit").string();
    const RunResult r = run_tvid({"fit", (source_dir() / "configs/cvt_tipin_clean.yaml").string(), "-o", dir, "--json",
                                  "--threads", "2", "--set", "estimation.pso.iterations=5"});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const json summary = json::parse(read_text(tmp.path() / "fit" / "summary.json"));
    REQUIRE(summary.contains("modes"));
    const json& modes = summary["modes"];
    CHECK(modes["operating_point"]["initial_state"] == "equilibrium");
    REQUIRE(modes["modes"].size() >= 1);
    for (const json& m : modes["modes"]) {
        CHECK(m.contains("kind"));
        CHECK(m["frequency_hz"].get<double>() > 0.0);
        CHECK(m.contains("damped_frequency_hz"));
        CHECK(m.contains("damping_ratio"));
        CHECK(m["shape"].is_object());
    }
    // The printed summary is the file's.
    CHECK(json::parse(r.out)["modes"] == modes);
}

}  // namespace TVID_UNITY_ID
