// The verdict through the binary: summary.json and the terminal carry it, --strict (and
// estimation.strict) exit 1 on a poor fit and 0 on a good one, and batch rows carry each
// job's verdict. The poor fit: the CVT block with the drive-shaft torque offset d_ds fixed
// at 0 instead of about −7.4 N m, which leaves a systematic residual.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"
#include "tvid/batch/batch_table.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// Levenberg–Marquardt on the noisy CVT recording with rho1 fixed at its true value (which
// removes the model's scaling symmetry): it converges in about a second.
std::vector<std::string> cvt_lm(const std::string& verb, const fs::path& out, const std::vector<std::string>& extra) {
    std::vector<std::string> args{verb, (source_dir() / "configs/cvt_tipin.yaml").string(), "-o", out.string(),
                                  "--set", "estimation.optimizer=lm", "--set", "estimation.cost=l2",
                                  "--set", "parameters.rho1=1.42855"};
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
}

const std::vector<std::string> kPoor{"--set", "parameters.d_ds=0"};

std::vector<std::string> joined(std::vector<std::string> a, const std::vector<std::string>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

bool has_code(const json& findings, const std::string& code, const std::string& severity) {
    return std::any_of(findings.begin(), findings.end(),
                       [&](const json& f) { return f["code"] == code && f["severity"] == severity; });
}

}  // namespace

TEST_CASE("strict mode exits 1 on a poor fit and 0 on a good one, the report written either way", "[e2e][verdict][fits]") {
    TempDir tmp;
    SECTION("a good fit") {
        const RunResult r = run_tvid(cvt_lm("fit", tmp.path() / "good", {"--strict"}));
        INFO(r.out << r.err);
        CHECK(r.exit_code == 0);
        const json v = json::parse(read_text(tmp.path() / "good/summary.json"))["verdict"];
        CHECK(v["errors"] == 0);
        CHECK_FALSE(has_code(v["findings"], "residuals_not_white", "error"));
        CHECK(r.out.find("  verdict: ") != std::string::npos);
    }
    SECTION("a poor fit") {
        const RunResult r = run_tvid(cvt_lm("fit", tmp.path() / "poor", joined(kPoor, {"--strict"})));
        INFO(r.out << r.err);
        CHECK(r.exit_code == 1);
        // One line on stderr naming the first error.
        CHECK(r.err == r.err.substr(0, r.err.find('\n') + 1));
        CHECK(r.err.find("tvid: --strict: the verdict has 1 error") == 0);
        CHECK(r.err.find("residuals_not_white") != std::string::npos);
        const json s = json::parse(read_text(tmp.path() / "poor/summary.json"));
        CHECK(has_code(s["verdict"]["findings"], "residuals_not_white", "error"));
        CHECK(s["residuals"]["estimation"]["Tds"]["systematic_share"].get<double>() > 0.5);
        CHECK(r.out.find("    error residuals_not_white: Tds: ") != std::string::npos);
        CHECK(r.out.find("      try: ") != std::string::npos);
    }
    SECTION("without --strict the same poor fit exits 0, with estimation.strict 1") {
        CHECK(run_tvid(cvt_lm("fit", tmp.path() / "a", kPoor)).exit_code == 0);
        const RunResult r =
            run_tvid(cvt_lm("fit", tmp.path() / "b", joined(kPoor, {"--set", "estimation.strict=true"})));
        CHECK(r.exit_code == 1);
        CHECK(r.err.find("tvid: estimation.strict: the verdict has") == 0);
    }
}

TEST_CASE("summary.json has the information criteria and the residual statistics, params.json the covariance",
          "[e2e][verdict]") {
    TempDir tmp;
    const RunResult r = run_tvid(cvt_lm("fit", tmp.path() / "r", {}));
    REQUIRE(r.exit_code == 0);
    const json s = json::parse(read_text(tmp.path() / "r/summary.json"));
    const json& c = s["information_criteria"];
    REQUIRE(c.is_object());
    CHECK(c["parameters"] == 8);
    CHECK(c["samples"] == 1500);
    const double n = 1500, v = c["loss"].get<double>();
    // V is the mean square of the estimation residual: RMSE².
    const double rmse = s["estimation"]["pooled"]["Tds"]["rmse"].get<double>();
    CHECK(v == Approx(rmse * rmse).epsilon(1e-9));
    CHECK(c["bic"].get<double>() - c["aic"].get<double>() == Approx(8 * std::log(n) - 16).epsilon(1e-9));
    const json p = json::parse(read_text(tmp.path() / "r/params.json"));
    const json& cov = p["covariance"]["matrix"];
    REQUIRE(cov.size() == 8);
    // Its diagonal is the square of each standard error.
    for (const json& q : p["parameters"]) {
        if (q["fixed"] == true) continue;
        const auto names = p["covariance"]["parameters"].get<std::vector<std::string>>();
        const auto j = static_cast<std::size_t>(std::find(names.begin(), names.end(), q["name"]) - names.begin());
        REQUIRE(j < names.size());
        CHECK(cov[j][j].get<double>() == Approx(std::pow(q["std_error"].get<double>(), 2)).epsilon(1e-9));
        CHECK(q["interval"] == "two-sided");
    }
    // The terminal: fit % per window under each split, the residual ratio in percent.
    CHECK(r.out.find("      window time 1 to 1.5 ") != std::string::npos);
    CHECK(r.out.find("      window time 3 to 3.5 ") != std::string::npos);
    CHECK(r.out.find("max |residual ratio| ") != std::string::npos);
    CHECK(r.out.find("AIC ") != std::string::npos);
}

TEST_CASE("batch rows carry each job verdict, and strict mode exits 1 when one has an error", "[e2e][verdict]") {
    TempDir tmp;
    const std::vector<std::string> data{"--data", (source_dir() / "data/cvt/tipin_a.csv").string(), "--quiet"};
    auto args = cvt_lm("batch", tmp.path() / "poor", kPoor);
    args.insert(args.end(), data.begin(), data.end());
    args.push_back("--strict");
    const RunResult r = run_tvid(args);
    INFO(r.err);
    CHECK(r.exit_code == 1);
    CHECK(r.err.find("tvid: --strict: 1 job's verdict has an error") == 0);
    const auto table = tvid::read_batch_file(tmp.path() / "poor/batch.csv");
    REQUIRE(table);
    REQUIRE(table->rows.size() == 1);
    const auto column = [&](const std::string& name) {
        return static_cast<std::size_t>(std::find(table->header.begin(), table->header.end(), name) - table->header.begin());
    };
    CHECK(table->rows[0][column("verdict")].find("1 error") == 0);
    CHECK(table->rows[0][column("findings")].find("error:residuals_not_white(Tds)") == 0);
    const json summary = json::parse(read_text(tmp.path() / "poor/batch_summary.json"));
    CHECK(summary["verdicts"]["errors"] == 1);
    CHECK(summary["verdicts"]["jobs_with_errors"].size() == 1);

    auto good = cvt_lm("batch", tmp.path() / "good", {});
    good.insert(good.end(), data.begin(), data.end());
    good.push_back("--strict");
    CHECK(run_tvid(good).exit_code == 0);
}

}  // namespace TVID_UNITY_ID
