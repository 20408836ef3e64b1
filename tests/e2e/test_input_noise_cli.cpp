// A logged input's declared noise, as a user meets it: configs/rigid_gear_noisy_input.yaml
// fits the rigid_gear recording (scripts/generate_rigid_gear_data.py: numpy, its own RK4) from
// its engine torque as a logger recorded it, with 1.5 N m of white noise the vehicle never
// felt, declared as `noise: 1.5`. The truth lies within 3 robust standard errors, the verdict
// at the optimum and at the truth has no error, and without the declaration the standard
// errors are several times too small. Bad entries are one line, exit 2.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "support/run_tvid.hpp"
#include "support/shipped_fit.hpp"
#include "support/test_files.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
using nlohmann::json;

namespace {

json truth() { return json::parse(read_text(source_dir() / "data" / "rigid_gear" / "truth.json"))["parameters"]; }

json fit_variant(const TempDir& tmp, const std::string& name, const std::string& text,
                 const std::vector<std::string>& extra = {}) {
    const auto file = tmp.write(name + ".yaml", text);
    std::vector<std::string> args{"fit", file.string(), "-o", (tmp.path() / name).string(), "--threads", "2", "--json"};
    args.insert(args.end(), extra.begin(), extra.end());
    const RunResult r = run_tvid(args);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    return json::parse(r.out);
}

int errors(const json& summary) { return summary["verdict"]["errors"].get<int>(); }

}  // namespace

TEST_CASE("a noisy logged input, declared: the truth within 3 robust standard errors and no verdict error",
          "[e2e][fits][input_noise]") {
    const TempDir tmp;
    const std::string text = shipped_config_text("rigid_gear_noisy_input");
    const json s = fit_variant(tmp, "declared", text);
    CHECK(errors(s) == 0);
    CHECK(s["standard_errors"]["input_noise"]["carried_rms"]["w_engine"].get<double>() > 0.05);
    const json t = truth();
    int beyond_plain = 0;
    for (const json& p : s["parameters"]) {
        const std::string name = p["name"];
        const double value = p["value"], se = p["std_error"], robust = p["robust_std_error"], want = t[name];
        INFO(name << " = " << value << " +- " << se << " (robust " << robust << "), truth " << want);
        CHECK(std::abs(value - want) < 3.0 * robust);
        CHECK(robust >= se);
        beyond_plain += std::abs(value - want) > 3.0 * se;
    }
    CHECK(beyond_plain == 0);
    // Judged against the noise model, each residual is as white as a noise of that shape.
    for (const auto& [output, w] : s["residuals"]["estimation"].items()) {
        INFO(output);
        CHECK(w["input_noise_rms"].get<double>() > 0);
        CHECK(w["systematic_share"].get<double>() < 0.1);
    }

    // At the truth (LM held there), with the noise declared: no error.
    std::vector<std::string> at_truth{"--set", "estimation.lm.max_iterations=0"};
    for (auto it = t.begin(); it != t.end(); ++it) {
        at_truth.push_back("--set");
        at_truth.push_back("parameters." + it.key() + ".init=" + std::to_string(it.value().get<double>()));
    }
    const json truth_fit = fit_variant(tmp, "truth", text, at_truth);
    std::string findings;
    for (const json& f : truth_fit["verdict"]["findings"]) findings += f["code"].get<std::string>() + "\n";
    INFO(findings);
    CHECK(errors(truth_fit) == 0);

    // Undeclared: the usual standard errors miss the carried noise by several times.
    std::string plain = text;
    replace_once(plain, ", noise: 1.5", "");
    const json u = fit_variant(tmp, "undeclared", plain);
    std::map<std::string, double> declared_se;
    for (const json& p : s["parameters"]) declared_se[p["name"]] = p["std_error"];
    int smaller = 0;
    for (const json& p : u["parameters"]) smaller += declared_se[p["name"]] > 2.0 * p["std_error"].get<double>();
    CHECK(smaller >= 5);
}

TEST_CASE("an input's noise: is a positive number of the input's own, one line and exit 2 otherwise",
          "[e2e][input_noise]") {
    const TempDir tmp;
    const auto run = [&](const std::string& from, const std::string& to) {
        std::string text = shipped_config_text("rigid_gear_noisy_input");
        replace_once(text, from, to);
        const auto file = tmp.write("variant.yaml", text);
        return run_tvid({"simulate", file.string(), "-o", (tmp.path() / "simulated.csv").string()});
    };
    struct Case {
        std::string from, to, says;
    };
    const Case cases[] = {
        {"noise: 1.5", "noise: 0", "inputs.T_engine.noise: the standard deviation of the input's noise must be a positive"},
        {"noise: 1.5", "noise: -2", "inputs.T_engine.noise: the standard deviation"},
        {"noise: 1.5", "noise: [1, 2]", "inputs.T_engine.noise"},
        {"w_wheel: { column: w_wheel, speed: wheel }", "w_wheel: { column: w_wheel, speed: wheel, noise: 0.05 }",
         "outputs.w_wheel.noise: noise: is declared on an input"},
    };
    for (const Case& c : cases) {
        INFO(c.to);
        const RunResult r = run(c.from, c.to);
        CHECK(r.exit_code == 2);
        CHECK(r.err.find(c.says) != std::string::npos);
        CHECK(r.err.find("variant.yaml:") != std::string::npos);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
        CHECK_FALSE(std::filesystem::exists(tmp.path() / "simulated.csv"));
    }
}

}  // namespace TVID_UNITY_ID
