// `tvid check`'s library: the reference format, the tolerance arithmetic, combinations
// of parameters, and the rows a hand-made report gives against a reference.
#include <catch2/catch.hpp>
#include <cmath>

#include "support/test_files.hpp"
#include "tvid/check/parameter_expression.hpp"
#include "tvid/check/reference_check.hpp"
#include "tvid/util/input_error.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;
using nlohmann::json;
using nlohmann::ordered_json;

namespace {

// A report as `tvid fit` writes it, trimmed to what `tvid check` reads: two parameters
// free (rho1 undetermined), one fixed; one output; two validation windows.
FitReportFiles example_report() {
    FitReportFiles r;
    r.dir = "results/example";
    r.params = json::parse(R"({"experiment": "example", "model": "cvt_clearance", "parameters": [
        {"name": "rho1", "value": 2.0, "fixed": false, "min": 0.01, "max": 100},
        {"name": "k_plus", "value": 5000.0, "fixed": false, "min": 1, "max": 1e6},
        {"name": "d_ds", "value": 0.0, "fixed": false, "min": -100, "max": 100},
        {"name": "sigma", "value": 1132.81, "fixed": true, "min": null, "max": null}]})");
    const json metrics = {{"samples", 100}, {"q_index_percent", 99.5}, {"max_abs_residual_ratio_percent", 2.0},
                          {"rmse", 0.1}, {"cost_l1", 0.05}, {"cost_l2", 1.0}, {"e0", 10.0}, {"fit_percent", 98.0}};
    json worse = metrics;
    worse["q_index_percent"] = 97.0;
    r.summary = {{"tool", "tvid"},
                 {"experiment", "example"},
                 {"status", "ok"},
                 {"command", "tvid fit example.yaml"},
                 {"cost", {{"kind", "l1"}, {"value", 0.05}}},
                 {"optimizer", {{"name", "pso"}, {"converged", true}, {"iterations", 250}}},
                 {"estimation", {{"pooled", {{"Tds", metrics}}},
                                 {"windows", json::array({{{"window", "time 1.5 to 3"}, {"outputs", {{"Tds", metrics}}}}})}}},
                 {"validation", {{"pooled", {{"Tds", metrics}}},
                                 {"windows", json::array({{{"window", "time 1 to 1.5"}, {"outputs", {{"Tds", metrics}}}},
                                                          {{"window", "time 3 to 3.5"}, {"outputs", {{"Tds", worse}}}}})}}},
                 {"identifiability", {{"available", true}, {"undetermined", json::array({"rho1"})}}}};
    return r;
}

Reference reference(const std::string& text) { return parse_reference(ordered_json::parse(text), "ref.json"); }

const CheckRow& row(const CheckResult& r, const std::string& quantity) {
    for (const CheckRow& x : r.rows)
        if (x.quantity == quantity) return x;
    FAIL("no row " << quantity);
    return r.rows.front();
}

// The InputError message of parsing `text`, "" if it parses.
std::string reference_error(const std::string& text) {
    try {
        reference(text);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("a report is checked row by row against the reference", "[reference-check]") {
    const CheckResult r = check_report(example_report(), reference(R"({
        "tvid_reference": 1,
        "experiment": "example",
        "defaults": {"rel": 0.01},
        "parameters": {"k_plus": 5040, "rho1": {"expected": 2.5, "rel": 0.1}, "d_ds": {"expected": 0.2, "abs": 0.25}},
        "combinations": {"rho1*k_plus": {"expected": 1.0e4}},
        "cost": {"max": 0.06},
        "estimation": {"q_index_percent": {"min": 99}},
        "validation": {"Tds": {"q_index_percent": {"min": 98, "each_window": true}, "max_abs_residual_ratio": {"max": 0.01}}},
        "status": "ok",
        "converged": true,
        "fields": {"/optimizer/iterations": {"max": 300}}
    })"));
    // In reference order: parameters, combinations, cost, metrics, then the fields.
    REQUIRE(r.rows.size() == 13);
    CHECK(r.rows[0].quantity == "parameters.k_plus");
    CHECK(r.rows[0].pass);  // |5000 − 5040| = 40 ≤ 0.01·5040
    CHECK(*r.rows[0].deviation == Approx(-40.0 / 5040));
    CHECK_FALSE(row(r, "parameters.rho1").pass);  // 2.0 is 20 % off 2.5, 10 % allowed
    CHECK(*row(r, "parameters.rho1").deviation == Approx(-0.2));
    CHECK(row(r, "parameters.d_ds").pass);        // |0 − 0.2| ≤ 0.25 (abs replaces the default rel)
    CHECK(row(r, "combinations.rho1*k_plus").pass);
    CHECK(row(r, "combinations.rho1*k_plus").actual == 1.0e4);
    CHECK(row(r, "cost (l1)").pass);
    CHECK(row(r, "estimation.Tds.q_index_percent").pass);
    CHECK(row(r, "validation.Tds.q_index_percent [time 1 to 1.5]").pass);
    CHECK_FALSE(row(r, "validation.Tds.q_index_percent [time 3 to 3.5]").pass);  // 97 < 98
    CHECK_FALSE(row(r, "validation.Tds.max_abs_residual_ratio").pass);           // 0.02 > 0.01
    CHECK(*row(r, "validation.Tds.max_abs_residual_ratio").deviation == Approx(1.0));
    CHECK(row(r, "experiment").pass);
    CHECK(row(r, "status").pass);
    CHECK(row(r, "converged").pass);
    CHECK(row(r, "/optimizer/iterations").pass);
    CHECK(r.failures() == 3);
    CHECK_FALSE(r.passed());

    const json j = check_result_json(r);
    CHECK(j["passed"] == false);
    CHECK(j["failed"] == 3);
    CHECK(j["rows"][0]["quantity"] == "parameters.k_plus");
    CHECK(j["rows"][0]["allowed"].get<double>() == Approx(50.4));
    CHECK(j["rows"][0]["min"].is_null());
}

TEST_CASE("the tolerance holds at its boundary: |value − expected| <= abs + rel·|expected|", "[reference-check]") {
    Expectation e;
    e.expected = 1.0;
    e.tolerance = {0.01, 0.0};
    CHECK(e.holds(1.01));  // exactly on the decimal boundary, despite binary rounding
    CHECK(e.holds(0.99));
    CHECK_FALSE(e.holds(1.0100001));
    CHECK_FALSE(e.holds(0.9899999));
    e.expected = -200.0;  // rel is of |expected|
    CHECK(e.holds(-202.0));
    CHECK(e.holds(-198.0));
    CHECK_FALSE(e.holds(-202.001));
    e.expected = 0.0;  // abs and rel add up
    e.tolerance = {0.5, 0.25};
    CHECK(e.holds(0.25));
    CHECK(e.holds(-0.25));
    CHECK_FALSE(e.holds(0.2500001));
    e.expected = 4.0;
    CHECK(e.holds(6.25));  // 0.25 + 0.5·4
    CHECK_FALSE(e.holds(6.2500001));
    e.tolerance = {};  // no tolerance: equal to within rounding
    CHECK(e.holds(4.0));
    CHECK_FALSE(e.holds(4.0 + 1e-12));
    // Bounds are inclusive; a value that is not a finite number never passes.
    Expectation b;
    b.min = 99.0;
    b.max = 100.0;
    CHECK(b.holds(99.0));
    CHECK(b.holds(100.0));
    CHECK_FALSE(b.holds(98.9999999));
    CHECK_FALSE(b.holds(json(nullptr)));
    CHECK_FALSE(b.holds("99.5"));
    // Deviation: from the expected value, else from the failing or nearer bound.
    CHECK(*b.deviation(98.0) == Approx(-1.0 / 99));
    CHECK(*b.deviation(99.9) == Approx(-0.1 / 100));
    CHECK_FALSE(b.deviation(json(nullptr)).has_value());
    Expectation zero;
    zero.expected = 0.0;
    CHECK_FALSE(zero.deviation(0.1).has_value());
}

TEST_CASE("combinations of parameters: products, quotients, sums and parentheses", "[reference-check]") {
    const auto value = [](const std::string& n) {
        if (n == "rho1") return 2.0;
        if (n == "k_plus") return 5000.0;
        if (n == "mu") return 0.004;
        return 1.0;
    };
    CHECK(ParameterExpression("rho1*k_plus").evaluate(value) == 1.0e4);
    CHECK(ParameterExpression("mu/rho1").evaluate(value) == Approx(0.002));
    CHECK(ParameterExpression(" J1 + 4*J2 + J3 ").evaluate(value) == 6.0);
    CHECK(ParameterExpression("k_plus / (rho1 * 2) - -1").evaluate(value) == 1251.0);
    CHECK(ParameterExpression("1e3*mu").evaluate(value) == Approx(4.0));
    CHECK(ParameterExpression("rho1*k_plus*rho1").names() == std::vector<std::string>{"rho1", "k_plus"});
    CHECK(std::isinf(ParameterExpression("rho1/0").evaluate(value)));
    for (const char* bad : {"", "rho1*", "rho1 k_plus", "(rho1", "rho1)", "rho1^2", "*rho1"})
        CHECK_THROWS_AS(ParameterExpression(bad), std::invalid_argument);
    CHECK_THROWS_WITH(ParameterExpression("rho1 ** k_plus"),
                      "expected a parameter name, a number or '(' at '* k_plus'");
}

TEST_CASE("a combination of a parameter the report lacks, or that is not finite", "[reference-check]") {
    const FitReportFiles report = example_report();
    CHECK_THROWS_WITH(check_report(report, reference(R"({"tvid_reference": 1, "combinations": {"rho1*k_minus": 1}})")),
                      Catch::Contains("ref.json: combinations.rho1*k_minus: no parameter k_minus in"));
    const CheckResult r =
        check_report(report, reference(R"({"tvid_reference": 1, "combinations": {"k_plus/d_ds": {"min": 0}}})"));
    CHECK_FALSE(r.rows[0].pass);
    CHECK(r.rows[0].note == "not finite");
}

TEST_CASE("a malformed reference is one error naming the file and the key", "[reference-check]") {
    CHECK(reference_error(R"({"parameters": {}})") ==
          "ref.json: tvid_reference: missing: not a tvid reference file (it starts with \"tvid_reference\": 1)");
    CHECK(reference_error(R"({"tvid_reference": 2})") ==
          "ref.json: tvid_reference: version 2 is not supported (this tvid reads version 1)");
    CHECK(reference_error(R"([1])") == "ref.json: expected a JSON object with \"tvid_reference\": 1");
    CHECK(reference_error(R"({"tvid_reference": 1, "tolerance": 1})").rfind("ref.json: tolerance: unknown key", 0) == 0);
    CHECK(reference_error(R"({"tvid_reference": 1, "defaults": {"rel": -0.1}})") ==
          "ref.json: defaults.rel: must not be negative");
    CHECK(reference_error(R"({"tvid_reference": 1, "parameters": {"J1": "0.0045"}})") ==
          "ref.json: parameters.J1: expected a number or an object with expected, min or max");
    CHECK(reference_error(R"({"tvid_reference": 1, "parameters": {"J1": {"expected": 1, "tol": 0.1}}})") ==
          "ref.json: parameters.J1.tol: unknown key (known: expected, rel, abs, min, max)");
    CHECK(reference_error(R"({"tvid_reference": 1, "parameters": {"J1": {"rel": 0.1, "min": 0}}})") ==
          "ref.json: parameters.J1.rel: a tolerance needs an expected value");
    CHECK(reference_error(R"({"tvid_reference": 1, "parameters": {"J1": {"rel": 0.1}}})") ==
          "ref.json: parameters.J1: give expected, min or max");
    CHECK(reference_error(R"({"tvid_reference": 1, "cost": {"min": 2, "max": 1}})") ==
          "ref.json: cost.min: is greater than max");
    CHECK(reference_error(R"({"tvid_reference": 1, "combinations": {"rho1*": 1}})") ==
          "ref.json: combinations.rho1*: expected a parameter name, a number or '(' at the end");
    CHECK(reference_error(R"({"tvid_reference": 1, "estimation": {"q_index": {"min": 99}}})")
              .rfind("ref.json: estimation.q_index: unknown metric (metrics: q_index_percent, ", 0) == 0);
    CHECK(reference_error(R"({"tvid_reference": 1, "validation": {"Tds": {"q": {"min": 99}}}})")
              .rfind("ref.json: validation.Tds.q: unknown metric", 0) == 0);
    CHECK(reference_error(R"({"tvid_reference": 1, "converged": "yes"})") == "ref.json: converged: expected true or false");
    CHECK(reference_error(R"({"tvid_reference": 1, "fields": {"optimizer/iterations": {"max": 3}}})") ==
          "ref.json: fields.optimizer/iterations: not a JSON pointer into summary.json (e.g. /optimizer/iterations)");
    CHECK(reference_error(R"({"tvid_reference": 1, "estimation": {"rmse": {"max": 1, "each_window": 1}}})") ==
          "ref.json: estimation.rmse.each_window: expected true or false");
    CHECK(reference_error(R"({"tvid_reference": 1, "parameters": {"J1": 0.0045}, "estimation": {"rmse": 0.1}})").empty());
}

TEST_CASE("a reference naming what the report does not have is bad input", "[reference-check]") {
    const FitReportFiles report = example_report();
    CHECK_THROWS_WITH(check_report(report, reference(R"({"tvid_reference": 1, "parameters": {"J9": 1}})")),
                      "ref.json: parameters.J9: no parameter J9 in results/example/params.json "
                      "(parameters: rho1, k_plus, d_ds, sigma)");
    CHECK_THROWS_WITH(check_report(report, reference(R"({"tvid_reference": 1, "validation": {"omega_dw": {"rmse": 1}}})")),
                      "ref.json: validation.omega_dw: no output omega_dw in results/example/summary.json (outputs: Tds)");
    CHECK_THROWS_WITH(check_report(report, reference(R"({"tvid_reference": 1, "fields": {"/optimizer/seed": 1}})")),
                      "ref.json: fields./optimizer/seed: no field /optimizer/seed in results/example/summary.json");
}

TEST_CASE("a reference written from a report passes on it and leaves out undetermined parameters",
          "[reference-check]") {
    const FitReportFiles report = example_report();
    const ordered_json written = reference_from_report(report, 0.05);
    CHECK(written.begin().key() == "tvid_reference");
    CHECK(written["defaults"]["rel"] == 0.05);
    CHECK_FALSE(written["parameters"].contains("rho1"));   // undetermined
    CHECK_FALSE(written["parameters"].contains("sigma"));  // fixed
    CHECK(written["parameters"]["k_plus"] == 5000.0);
    CHECK(written["parameters"]["d_ds"]["abs"].get<double>() == Approx(10.0));  // 0: 5 % of the bound span
    CHECK(written["cost"]["max"].get<double>() == Approx(0.0525));
    CHECK(written["estimation"]["Tds"]["q_index_percent"]["min"].get<double>() == Approx(100 - 0.5 * 1.05));
    CHECK(written["validation"]["Tds"]["max_abs_residual_ratio_percent"]["max"].get<double>() == Approx(2.1));
    CHECK(written["description"].get<std::string>().find("left out the undetermined parameters rho1") != std::string::npos);

    const CheckResult r = check_report(report, parse_reference(written, "written.json"));
    CHECK(r.passed());
    CHECK(r.rows.size() == 10);  // 2 parameters, cost, 2 × (Q, max ratio), experiment, status, converged

    FitReportFiles moved = report;
    moved.params["parameters"][1]["value"] = 5300.0;  // k_plus 6 % up
    const CheckResult f = check_report(moved, parse_reference(written, "written.json"));
    CHECK(f.failures() == 1);
    CHECK_FALSE(row(f, "parameters.k_plus").pass);

    FitReportFiles failed = report;
    failed.summary["status"] = "failed";
    CHECK_THROWS_AS(reference_from_report(failed, 0.01), InputError);
}

TEST_CASE("a reference's tolerances come from the standard errors and the noise", "[reference-check]") {
    FitReportFiles report = example_report();
    report.params["parameters"][1]["std_error"] = 60.0;   // k_plus: 5 se = 300, 6 % of 5000
    report.params["parameters"][2]["std_error"] = 0.3;    // d_ds at 0: 5 se = 1.5, below 1 % of the span 200
    report.summary["cost"]["kind"] = "l2";
    // 100 samples whose autocorrelation ρ(1) = 0.5 (and 0 beyond): N_eff = 100/1.5.
    const json acf = {{"samples", 100}, {"acf", {1.0, 0.5, 0.0}}, {"band", 0.26}, {"lags_outside", {1}}};
    report.summary["residual_analysis"] = {{"estimation", {{"lags", 2}, {"outputs", {{"Tds", acf}}}, {"inputs", json::object()}}},
                                           {"validation", nullptr}};
    report.summary["estimation"]["pooled"]["Tds"]["residual_ratio_min_abs_y"] = 4.0;
    report.summary["residuals"] = {{"estimation", {{"Tds", {{"noise_rms", 0.08}}}}}};
    const ordered_json written = reference_from_report(report, 0.01, 5.0);
    CHECK(written["parameters"]["k_plus"]["expected"] == 5000.0);
    CHECK(written["parameters"]["k_plus"]["abs"].get<double>() == Approx(300.0));
    CHECK(written["parameters"]["d_ds"]["abs"].get<double>() == Approx(2.0));  // the floor: 1 % of the span
    const double spread_l2 = std::sqrt(2.0 / (100.0 / 1.5));  // Σe² over N_eff Gaussian residuals
    CHECK(written["cost"]["max"].get<double>() == Approx(0.05 * (1 + 5 * spread_l2)));
    const double spread_l1 = std::sqrt(std::acos(-1.0) / 2 - 1) / std::sqrt(100.0 / 1.5);
    CHECK(written["estimation"]["Tds"]["q_index_percent"]["min"].get<double>() == Approx(100 - 0.5 * (1 + 5 * spread_l1)));
    // The validation split has no residual analysis: rel.
    CHECK(written["validation"]["Tds"]["q_index_percent"]["min"].get<double>() == Approx(100 - 0.5 * 1.01));
    // The ratio: 2 % · 1.01 + 5 · 0.08 / 4 · 100 % = 12.02 %.
    CHECK(written["estimation"]["Tds"]["max_abs_residual_ratio_percent"]["max"].get<double>() == Approx(12.02));
    CHECK(written["description"].get<std::string>().find("each parameter 5 standard errors (1 of them") !=
          std::string::npos);
    CHECK(check_report(report, parse_reference(written, "written.json")).passed());
    FitReportFiles moved = report;
    moved.params["parameters"][1]["value"] = 5200.0;  // 3.3 standard errors: within 5
    CHECK(check_report(moved, parse_reference(written, "written.json")).passed());
    moved.params["parameters"][1]["value"] = 5400.0;  // 6.7 standard errors
    CHECK_FALSE(check_report(moved, parse_reference(written, "written.json")).passed());
}

TEST_CASE("a report directory that is missing, incomplete or not a tvid report", "[reference-check]") {
    test::TempDir tmp;
    CHECK_THROWS_WITH(read_fit_report(tmp.path() / "nothing"), Catch::EndsWith("nothing: no such report directory"));
    CHECK_THROWS_WITH(read_fit_report(tmp.path()),
                      Catch::EndsWith("summary.json: missing: not a complete tvid fit report (summary.json is written last)"));
    tmp.write("summary.json", R"({"tool": "other"})");
    CHECK_THROWS_WITH(read_fit_report(tmp.path()), Catch::EndsWith("summary.json: tool: not \"tvid\": not a tvid fit report"));
    tmp.write("summary.json", R"({"tool": "tvid", "status": "ok", "cost": {}, "optimizer": {}, "estimation": {}})");
    CHECK_THROWS_WITH(read_fit_report(tmp.path()),
                      Catch::EndsWith("summary.json: estimation.pooled: missing: not a tvid fit report"));
    const FitReportFiles example = example_report();
    tmp.write("summary.json", example.summary.dump());
    CHECK_THROWS_WITH(read_fit_report(tmp.path()), Catch::EndsWith("params.json: missing: not a complete tvid fit report"));
    tmp.write("params.json", "{\"parameters\": [");
    CHECK_THROWS_WITH(read_fit_report(tmp.path()), Catch::Contains("params.json:1: not valid JSON"));
    tmp.write("params.json", example.params.dump());
    CHECK(read_fit_report(tmp.path()).params["parameters"].size() == 4);
}

TEST_CASE("the largest residual ratio checks in percent and in the older fraction alike", "[reference-check]") {
    // A report in percent against a reference in the fraction an older tvid wrote …
    const FitReportFiles report = example_report();  // validation max ratio 2 %
    const CheckResult old_reference = check_report(report, reference(R"({"tvid_reference": 1,
        "validation": {"Tds": {"max_abs_residual_ratio": {"max": 0.025}}}})"));
    REQUIRE(old_reference.rows.size() == 1);
    CHECK(old_reference.rows[0].pass);
    CHECK(old_reference.rows[0].actual.get<double>() == Approx(0.02));
    // … and a report in the fraction against a reference in percent.
    FitReportFiles older = report;
    for (const char* split : {"estimation", "validation"}) {
        json& m = older.summary[split]["pooled"]["Tds"];
        m.erase("max_abs_residual_ratio_percent");
        m["max_abs_residual_ratio"] = 0.03;
    }
    const CheckResult new_reference = check_report(older, reference(R"({"tvid_reference": 1,
        "validation": {"Tds": {"max_abs_residual_ratio_percent": {"max": 2.5}}}})"));
    REQUIRE(new_reference.rows.size() == 1);
    CHECK_FALSE(new_reference.rows[0].pass);  // 3 % > 2.5 %
    CHECK(new_reference.rows[0].actual.get<double>() == Approx(3.0));
}

}  // namespace TVID_UNITY_ID
