// `tvid fit` with an estimated start on a line not tied to ground that was recorded in
// motion by an independent numpy script (scripts/generate_free_line_data.py, its own RK4):
// on the noisy recording every parameter and every start coordinate lands within 3 standard
// errors of the truth and the validation (its own start estimated on its first tenth, which is not scored) is as
// good as the estimation; on the noise-free twin everything comes back exactly. The start is
// reported apart from the model's parameters and read back by --params.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>

#include "support/run_tvid.hpp"
#include "support/shipped_fit.hpp"
#include "support/test_files.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
using nlohmann::json;

namespace {

const json& truth() {
    static const json t = json::parse(read_text(source_dir() / "data/free_line/truth.json"));
    return t;
}

// The start's coordinate "node.speed" or "node.angle" of an initial_states entry.
std::string coordinate(const json& entry) {
    return entry["node"].get<std::string>() + "." + entry["coordinate"].get<std::string>();
}

}  // namespace

TEST_CASE("an estimated start on a noisy free line: every parameter and start within 3 standard errors",
          "[e2e][estimated_start][fits]") {
    const TempDir tmp;
    const json s = fit_shipped(tmp, "free_line");
    CHECK(s["verdict"]["summary"] == "clean");
    for (const json& p : s["parameters"]) {
        const std::string name = p["name"];
        INFO(name << " = " << p["value"] << " ± " << p["std_error"]);
        REQUIRE(truth()["parameters"].contains(name));  // the start is not among the model's parameters
        CHECK(std::abs(p["value"].get<double>() - truth()["parameters"][name].get<double>()) <
              3 * p["std_error"].get<double>());
    }
    const json params = json::parse(read_text(tmp.path() / "free_line/params.json"));
    REQUIRE(params["initial_states"].size() == 5);
    for (const json& e : params["initial_states"]) {
        INFO(coordinate(e) << " = " << e["value"] << " ± " << e["std_error"]);
        CHECK(e["window"] == "time 0 to 8");
        CHECK(e["value"].get<double>() == Approx(e["seed"].get<double>() + e["correction"].get<double>()));
        CHECK(std::abs(e["value"].get<double>() - truth()["start"][coordinate(e)].get<double>()) <
              3 * e["std_error"].get<double>());
    }
    CHECK(s["initial_state"]["from"] == "measured");
    CHECK(s["initial_state"]["validation_windows"][0]["estimated_on"] == json::array({8.0, 8.4}));
    CHECK(s["information_criteria"]["parameters"] == 13);  // the start counts
    for (const std::string output : {"w_engine", "T_shaft", "w_vehicle"}) {
        INFO(output);
        const double estimation = s["estimation"]["pooled"][output]["rmse"];
        const double validation = s["validation"]["pooled"][output]["rmse"];
        CHECK(validation < 1.2 * estimation);
        CHECK(estimation < 1.1 * truth()["noise_std"][output].get<double>());  // at the noise floor
    }
    // validate --params reads the start back and scores the same.
    const RunResult v = run_tvid({"validate", (source_dir() / "configs/free_line.yaml").string(), "--params",
                                  (tmp.path() / "free_line/params.json").string(), "--json"});
    INFO(v.err);
    REQUIRE(v.exit_code == 0);
    const json vs = json::parse(v.out);
    CHECK(vs["estimation"]["pooled"]["T_shaft"]["rmse"].get<double>() ==
          Approx(s["estimation"]["pooled"]["T_shaft"]["rmse"].get<double>()).epsilon(1e-12));
    CHECK(vs["validation"]["pooled"]["T_shaft"]["rmse"].get<double>() ==
          Approx(s["validation"]["pooled"]["T_shaft"]["rmse"].get<double>()).epsilon(1e-12));
}

TEST_CASE("an estimated start on the noise-free free line gives every parameter and the start back",
          "[e2e][estimated_start][fits]") {
    const TempDir tmp;
    const json s = fit_shipped(tmp, "free_line_clean");
    for (const json& p : s["parameters"]) {
        INFO(p["name"]);
        CHECK(p["value"].get<double>() == Approx(truth()["parameters"][p["name"].get<std::string>()].get<double>()).epsilon(1e-6));
    }
    const json params = json::parse(read_text(tmp.path() / "free_line_clean/params.json"));
    for (const json& e : params["initial_states"]) {
        INFO(coordinate(e));
        CHECK(e["value"].get<double>() == Approx(truth()["start"][coordinate(e)].get<double>()).margin(1e-6));
    }
}

TEST_CASE("an estimated start without its recipe is one line naming the key, exit 2", "[e2e][estimated_start]") {
    const RunResult r = run_tvid({"fit", (source_dir() / "configs/free_line.yaml").string(), "--set",
                                  "initial_state={kind: estimated}", "-o", "/nonexistent/never-written"});
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("initial_state.from") != std::string::npos);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
}

TEST_CASE("validation worse with an estimated start whose validation windows start from the recipe names "
          "validation: estimated",
          "[e2e][estimated_start][fits]") {
    const TempDir tmp;
    const RunResult r = run_tvid({"fit", (source_dir() / "configs/free_line.yaml").string(), "-o",
                                  (tmp.path() / "from").string(), "--threads", "2", "--json", "--set",
                                  "initial_state.validation=from"});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const json s = json::parse(r.out);
    bool found = false;
    for (const json& f : s["verdict"]["findings"]) {
        if (f["code"] != "validation_worse") continue;
        found = true;
        INFO(f.dump());
        CHECK(f["advice"].get<std::string>().find("initial_state.validation: estimated") != std::string::npos);
    }
    CHECK(found);
}

TEST_CASE("validate --params takes an estimated start as stored, whatever the experiment's init, and says which it "
          "leaves out",
          "[e2e][estimated_start][fits]") {
    const TempDir tmp;
    // The free line with its start seeded by the steady recipe, whose twist depends on the
    // stiffnesses' init values.
    std::string text = shipped_config_text("free_line");
    replace_once(text, "initial_state: { kind: estimated, from: measured, validation: estimated }",
                 "initial_state: { kind: estimated, from: steady, node: engine, speed: w_engine, validation: estimated }");
    const std::filesystem::path config = tmp.write("steady_seed.yaml", text);
    const RunResult fit = run_tvid({"fit", config.string(), "-o", (tmp.path() / "fit").string(), "--quiet", "--set",
                                    "estimation.lm.max_iterations=2"});
    INFO(fit.err);
    REQUIRE(fit.exit_code == 0);
    const std::string params = (tmp.path() / "fit/params.json").string();
    const auto validate = [&](const std::vector<std::string>& extra) {
        std::vector<std::string> args{"validate", config.string(), "--params", params, "--json"};
        args.insert(args.end(), extra.begin(), extra.end());
        const RunResult r = run_tvid(args);
        INFO(r.err);
        REQUIRE(r.exit_code == 0);
        return json::parse(r.out)["estimation"]["pooled"]["T_shaft"]["rmse"].get<double>();
    };
    const double as_fitted = validate({});
    // Another init moves the steady seed; the stored start is the same start.
    for (const std::string moved : {"parameters.k_ds.init=5000", "parameters.k_cl.init=400", "parameters.c_v.init=2"}) {
        INFO(moved);
        CHECK(validate({"--set", moved}) == Approx(as_fitted).epsilon(1e-9));
    }

    // A start estimated for another window is left out, and said.
    json p = json::parse(read_text(params));
    REQUIRE_FALSE(p["initial_states"].empty());
    for (json& e : p["initial_states"]) e["window"] = "time 0 to 4";
    const std::filesystem::path other = tmp.write("other_window.json", p.dump(1));
    const RunResult moved = run_tvid({"validate", config.string(), "--params", other.string(), "--quiet"});
    CHECK(moved.exit_code == 0);
    CHECK(moved.err.find("tvid: note: the start " + p["initial_states"][0]["parameter"].get<std::string>() + " of " +
                         other.string() + " was estimated for the window 'time 0 to 4', not 'time 0 to 8'") == 0);
    // initial_states that is not a list: refused, naming the key.
    p["initial_states"] = 5;
    const std::filesystem::path five = tmp.write("five.json", p.dump(1));
    const RunResult bad = run_tvid({"validate", config.string(), "--params", five.string(), "--quiet"});
    CHECK(bad.exit_code == 2);
    CHECK(bad.err == five.string() + ": initial_states: expected a list of start coordinates, as tvid fit writes it\n");
}

TEST_CASE("validation: estimated leaves the samples its start is fitted on out of the score, and refuses a window "
          "too short to score beyond them",
          "[e2e][estimated_start]") {
    const TempDir tmp;
    const std::filesystem::path config = source_dir() / "configs/free_line.yaml";
    const std::filesystem::path truth_params = tmp.write("truth.json", truth()["parameters"].dump());
    // Every parameter 10 times off (the vehicle 10 times light): a start fitted on the very
    // samples it is scored on hid it on a short window.
    const std::filesystem::path wrong_params = tmp.write(
        "wrong.json", R"({"J_e": 2.5, "J_g": 0.6, "J_v": 0.9, "k_cl": 60, "c_cl": 15, "k_ds": 40000, "c_ds": 60, "c_v": 9})");
    const auto validate = [&](const std::filesystem::path& params, const std::string& window) {
        return run_tvid({"validate", config.string(), "--params", params.string(), "--json", "--set",
                         "windows.validation=[{time: " + window + "}]"});
    };
    // 11 samples at 500 Hz: the start's 5 coordinates are fitted on 10 of them.
    const RunResult short_window = validate(wrong_params, "[8, 8.02]");
    CHECK(short_window.exit_code == 2);
    CHECK(std::count(short_window.err.begin(), short_window.err.end(), '\n') == 1);
    CHECK(short_window.err.find("windows.validation[0].time") != std::string::npos);
    CHECK(short_window.err.find("holds 11 samples") != std::string::npos);
    CHECK(short_window.err.find("at least 21 samples") != std::string::npos);
    CHECK(short_window.out.empty());

    // 21 samples: the 10 after the first fit the start, the last 10 are scored.
    const RunResult at_truth = validate(truth_params, "[8, 8.04]"), wrong = validate(wrong_params, "[8, 8.04]");
    INFO(at_truth.err << wrong.err);
    REQUIRE(at_truth.exit_code == 0);
    REQUIRE(wrong.exit_code == 0);
    const json t = json::parse(at_truth.out)["validation"]["pooled"], w = json::parse(wrong.out)["validation"]["pooled"];
    for (const std::string output : {"w_engine", "T_shaft", "w_vehicle"}) {
        INFO(output);
        CHECK(t[output]["samples"] == 10);
        CHECK(t[output]["rmse"].get<double>() < 2.5 * truth()["noise_std"][output].get<double>());
    }
    CHECK(w["T_shaft"]["rmse"].get<double>() > 10 * t["T_shaft"]["rmse"].get<double>());
    CHECK(w["w_vehicle"]["rmse"].get<double>() > 10 * t["w_vehicle"]["rmse"].get<double>());
}

}  // namespace TVID_UNITY_ID
