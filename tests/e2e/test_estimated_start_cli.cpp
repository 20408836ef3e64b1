// `tvid fit` with an estimated start on a line not tied to ground that was recorded in
// motion by an independent numpy script (scripts/generate_free_line_data.py, its own RK4):
// on the noisy recording every parameter and every start coordinate lands within 3 standard
// errors of the truth and the validation (its own start estimated on its first tenth) is as
// good as the estimation; on the noise-free twin everything comes back exactly. The start is
// reported apart from the model's parameters and read back by --params.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>

#include "support/run_tvid.hpp"
#include "support/shipped_fit.hpp"
#include "support/test_files.hpp"

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
