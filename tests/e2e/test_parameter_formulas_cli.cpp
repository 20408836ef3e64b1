// A parameter written as a formula of others (`parameters: k: { expr: "k_s / (3^2 * eta)" }`):
// `tvid fit` on the lossy gear's noise-free recording fits the shaft stiffness the mesh stands
// for, reports the mesh's value and its standard error by the delta method (against the hand
// conversion from the reported covariance), and bad formulas are one line naming the key.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <cmath>
#include <string>

#include "support/run_tvid.hpp"
#include "support/shipped_fit.hpp"
#include "support/test_files.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
using nlohmann::json;

namespace {

const std::string kMesh = "  k:   { init: 2600,  min: 1,      max: 1.0e5 }";

// The lossy gear (ratio 3) with its mesh stiffness k given as `formula` and k_s declared.
std::string with_formula(const std::string& formula, const std::string& k_s = "{ init: 20000, min: 1, max: 1.0e6 }") {
    std::string text = shipped_config_text("lossy_gear_clean");
    replace_once(text, kMesh, "  k:   { expr: \"" + formula + "\" }\n  k_s: " + k_s);
    // The first 1.5 s hold both directions of power flow: a fit of about a second.
    replace_once(text, "estimation: [ { time: [0, 3] } ]", "estimation: [ { time: [0, 1.5] } ]");
    return text;
}

}  // namespace

TEST_CASE("a mesh stiffness as a formula of the shaft it stands for, with its delta-method error", "[e2e][expressions]") {
    const TempDir tmp;
    const auto config = tmp.write("gear.yaml", with_formula("k_s / (3^2 * eta)"));
    const RunResult r = run_tvid({"fit", config.string(), "-o", (tmp.path() / "fit").string(), "--threads", "2"});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    CHECK(r.out.find("= k_s / (3^2 * eta)") != std::string::npos);  // the terminal's table
    const json params = json::parse(read_text(tmp.path() / "fit" / "params.json"));
    json k, k_s, eta;
    for (const json& p : params["parameters"]) {
        if (p["name"] == "k") k = p;
        if (p["name"] == "k_s") k_s = p;
        if (p["name"] == "eta") eta = p;
    }
    // The truth: k = 2000, eta = 0.9, so the shaft is 2000 * 9 * 0.9 = 16200.
    CHECK(k_s["value"].get<double>() == Approx(16200.0).epsilon(1e-6));
    CHECK(k["value"].get<double>() == Approx(2000.0).epsilon(1e-6));
    CHECK(k["expr"] == "k_s / (3^2 * eta)");
    CHECK(k["fixed"] == true);
    // By hand: g = (1/(9 eta), -k_s/(9 eta^2)) over (k_s, eta), SE = sqrt(g' C g).
    const auto& names = params["covariance"]["parameters"];
    const auto at = [&](const std::string& n) {
        return static_cast<std::size_t>(std::find(names.begin(), names.end(), n) - names.begin());
    };
    const auto& c = params["covariance"]["matrix"];
    const std::size_t s = at("k_s"), e = at("eta");
    REQUIRE(s < names.size());
    REQUIRE(e < names.size());
    const double ks = k_s["value"].get<double>(), et = eta["value"].get<double>();
    const double g0 = 1.0 / (9 * et), g1 = -ks / (9 * et * et);
    const double by_hand = std::sqrt(g0 * g0 * c[s][s].get<double>() + 2 * g0 * g1 * c[s][e].get<double>() +
                                     g1 * g1 * c[e][e].get<double>());
    CHECK(k["std_error"].get<double>() == Approx(by_hand).epsilon(1e-6));
    CHECK(by_hand > 0);
}

TEST_CASE("a formula that reads itself through others, or an unknown name, is one line naming expr, exit 2",
          "[e2e][expressions]") {
    const TempDir tmp;
    struct Case {
        std::string formula, k_s, says;
    };
    const Case cases[] = {
        {"k_s / (3^2 * eta)", "{ expr: \"k * 9 * eta\" }", "the formulas read each other in a cycle: k -> k_s -> k"},
        {"k_shaft / 9", "{ init: 20000, min: 1, max: 1.0e6 }", "'k_shaft' is not a parameter"},
        {"k_s ^ eta", "{ init: 20000, min: 1, max: 1.0e6 }", "an exponent must be a number"},
        {"k_s - 1.0e9", "{ init: 20000, min: 1, max: 1.0e6 }", "cannot be negative"},
    };
    for (const Case& c : cases) {
        const auto config = tmp.write("bad.yaml", with_formula(c.formula, c.k_s));
        const RunResult r = run_tvid({"fit", config.string(), "-o", (tmp.path() / "bad").string()});
        INFO(c.formula << "\n" << r.err);
        CHECK(r.exit_code == 2);
        CHECK(r.err.find("bad.yaml:") != std::string::npos);
        CHECK(r.err.find("expr:") != std::string::npos);
        CHECK(r.err.find(c.says) != std::string::npos);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
        CHECK_FALSE(std::filesystem::exists(tmp.path() / "bad"));
    }
}

}  // namespace TVID_UNITY_ID
