// `tvid check`: a reference written from a quick fit passes on it, a moved parameter
// fails by name (exit 1), and a missing report or a malformed reference is bad input (2).
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
using nlohmann::json;
using nlohmann::ordered_json;

namespace {

long count_lines(const std::string& text) { return std::count(text.begin(), text.end(), '\n'); }

// The noise-free CVT tip-in fitted by three LM iterations on the l2 cost into TMP/fit
// (stopped by the iteration limit, not converged); the report's path.
std::string quick_fit(const TempDir& tmp) {
    const auto report = (tmp.path() / "fit").string();
    const RunResult fit = run_tvid({"fit", (source_dir() / "configs/cvt_tipin_clean.yaml").string(), "-o", report,
                                    "--optimizer", "lm", "--set", "estimation.cost=l2", "--set",
                                    "estimation.lm.max_iterations=3", "--threads", "1", "--quiet"});
    INFO(fit.err);
    REQUIRE(fit.exit_code == 0);
    return report;
}

}  // namespace

TEST_CASE("tvid check passes on the report its reference came from and names a parameter that moved",
          "[e2e][check]") {
    TempDir tmp;
    const std::string report = quick_fit(tmp);

    const auto ref = (tmp.path() / "ref.json").string();
    const RunResult write = run_tvid({"check", report, "--write-reference", ref, "--rel", "0.02"});
    INFO(write.out << write.err);
    REQUIRE(write.exit_code == 0);
    CHECK(write.out.find("tvid check: wrote " + ref) != std::string::npos);
    ordered_json reference = ordered_json::parse(read_text(ref));
    CHECK(reference["tvid_reference"] == 1);
    CHECK(reference["defaults"]["rel"] == 0.02);
    REQUIRE_FALSE(reference["parameters"].empty());

    const RunResult pass = run_tvid({"check", report, "--reference", ref});
    INFO(pass.out << pass.err);
    CHECK(pass.exit_code == 0);
    CHECK(pass.out.find("quantity") != std::string::npos);
    CHECK(pass.out.find("FAIL") == std::string::npos);
    CHECK(pass.out.find("tvid check: PASS, all ") != std::string::npos);

    const RunResult quiet = run_tvid({"check", report, "--reference", ref, "--quiet"});
    CHECK(quiet.exit_code == 0);
    CHECK(count_lines(quiet.out) == 1);
    CHECK(quiet.out.rfind("tvid check: PASS", 0) == 0);

    // Move one parameter's expected value by 10 times its tolerance (2 %, or 5 standard errors).
    const std::string moved = reference["parameters"].begin().key();
    const ordered_json& check = reference["parameters"][moved];
    const double value = check.is_number() ? check.get<double>() : check["expected"].get<double>();
    const double allowed = check.is_number() ? 0.02 * std::abs(value) : check["abs"].get<double>();
    reference["parameters"][moved] = {{"expected", value + 10 * allowed}, {"abs", allowed}};
    const auto edited = tmp.write("edited.json", reference.dump(2));
    const RunResult fail = run_tvid({"check", report, "--reference", edited.string()});
    INFO(fail.out << fail.err);
    CHECK(fail.exit_code == 1);
    CHECK(fail.out.find("parameters." + moved) != std::string::npos);
    CHECK(fail.out.find("tvid check: FAIL, 1 of ") != std::string::npos);
    CHECK(fail.out.find("checks failed: parameters." + moved) != std::string::npos);
    // The failing row comes first, right under the header.
    const std::size_t first_row = fail.out.find('\n', fail.out.find("quantity")) + 1;
    CHECK(fail.out.substr(first_row, fail.out.find('\n', first_row) - first_row).find("FAIL") != std::string::npos);

    const RunResult as_json = run_tvid({"check", report, "--reference", edited.string(), "--json"});
    CHECK(as_json.exit_code == 1);
    const json j = json::parse(as_json.out);
    CHECK(j["passed"] == false);
    CHECK(j["failed"] == 1);
    for (const json& row : j["rows"]) CHECK(row["pass"] == (row["quantity"] != "parameters." + moved));
}

TEST_CASE("tvid check: a missing or incomplete report and a malformed reference are bad input", "[e2e][check]") {
    TempDir tmp;
    const auto ref = tmp.write("ref.json", R"({"tvid_reference": 1, "parameters": {"d_tm": 13}})");

    const RunResult missing = run_tvid({"check", (tmp.path() / "no-such-report").string(), "--reference", ref.string()});
    CHECK(missing.exit_code == 2);
    CHECK(missing.err.find("no-such-report: no such report directory") != std::string::npos);
    CHECK(count_lines(missing.err) == 1);

    const RunResult incomplete = run_tvid({"check", tmp.path().string(), "--reference", ref.string()});
    CHECK(incomplete.exit_code == 2);
    CHECK(incomplete.err.find("summary.json: missing: not a complete tvid fit report") != std::string::npos);

    const auto bad = tmp.write("bad.json", R"({"tvid_reference": 1, "parameters": {"d_tm": {"expected": 13, "rel": "1 %"}}})");
    const RunResult malformed = run_tvid({"check", tmp.path().string(), "--reference", bad.string()});
    CHECK(malformed.exit_code == 2);
    CHECK(malformed.err == bad.string() + ": parameters.d_tm.rel: expected a number\n");

    const RunResult not_json = run_tvid({"check", tmp.path().string(), "--reference", tmp.write("x.json", "{").string()});
    CHECK(not_json.exit_code == 2);
    CHECK(not_json.err.find("x.json:1: not valid JSON") != std::string::npos);

    const RunResult neither = run_tvid({"check", tmp.path().string()});
    CHECK(neither.exit_code == 2);
    CHECK(neither.err.find("--reference") != std::string::npos);
    const RunResult rel_alone = run_tvid({"check", tmp.path().string(), "--reference", ref.string(), "--rel", "0.1"});
    CHECK(rel_alone.exit_code == 2);
}

TEST_CASE("check --write-reference refuses an interrupted fit's report and warns for one that did not converge",
          "[e2e][check]") {
    TempDir tmp;
    const std::string report = quick_fit(tmp);  // stopped by the iteration limit
    json summary = json::parse(read_text(tmp.path() / "fit" / "summary.json"));
    REQUIRE(summary["optimizer"]["converged"] == false);

    const auto ref = (tmp.path() / "ref.json").string();
    const RunResult unconverged = run_tvid({"check", report, "--write-reference", ref, "--quiet"});
    CHECK(unconverged.exit_code == 0);
    CHECK(unconverged.err.find("tvid check: warning: the fit of " + report + " did not converge (" +
                               summary["optimizer"]["termination"].get<std::string>() +
                               "): a converged refit may move beyond the reference's tolerances; fit to convergence "
                               "first\n") != std::string::npos);

    // Tolerances beyond a double: the option is named, not a reference that was never written.
    const auto huge = (tmp.path() / "huge.json").string();
    const RunResult sigmas = run_tvid({"check", report, "--write-reference", huge, "--sigmas", "1e308", "--quiet"});
    CHECK(sigmas.exit_code == 2);
    CHECK(count_lines(sigmas.err) == 1);
    CHECK(sigmas.err.find("--sigmas: --sigmas 1e+308 and --rel ") != std::string::npos);
    CHECK(sigmas.err.find("huge.json") == std::string::npos);
    CHECK_FALSE(std::filesystem::exists(huge));

    // The same report marked interrupted, as a Ctrl-C'd fit writes it.
    summary["interrupted"] = true;
    tmp.write("fit/summary.json", summary.dump(2));
    const auto ref2 = (tmp.path() / "ref2.json").string();
    const RunResult interrupted = run_tvid({"check", report, "--write-reference", ref2});
    CHECK(interrupted.exit_code == 2);
    CHECK(count_lines(interrupted.err) == 1);
    CHECK(interrupted.err.rfind(report + "/summary.json: interrupted: the report is of an interrupted fit", 0) == 0);
    CHECK_FALSE(std::filesystem::exists(ref2));
}

}  // namespace TVID_UNITY_ID
