// The identifiability block of summary.json and the one warning line of the terminal
// summary, on the CVT preset whose nine parameters have an exact scaling symmetry.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
using nlohmann::json;

namespace {

// Least squares on the noise-free recording: < 1 s.
std::vector<std::string> lm_fit(const std::filesystem::path& out) {
    return {"fit", (source_dir() / "configs/cvt_tipin_clean.yaml").string(), "-o", out.string(),
            "--optimizer", "lm", "--set", "estimation.cost=l2"};
}

std::vector<std::string> warning_lines(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);)
        if (l.find("warning") != std::string::npos) lines.push_back(l);
    return lines;
}

}  // namespace

TEST_CASE("all nine CVT parameters free: summary.json names the scaling symmetry, the summary warns once",
          "[e2e][identifiability]") {
    TempDir tmp;
    const RunResult r = run_tvid(lm_fit(tmp.path() / "r"));
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const json id = json::parse(read_text(tmp.path() / "r/summary.json"))["identifiability"];
    CHECK(id["available"] == true);
    CHECK(id["rank"] == 8);
    CHECK(id["of"] == 9);
    CHECK(id["condition_number"].is_null());
    REQUIRE(id["parameters"].size() == 9);
    for (const json& p : id["parameters"]) {
        INFO(p.dump());
        const bool offset = p["name"] == "d_ds" || p["name"] == "d_tm";
        CHECK(p["flag"] == (offset ? "ok" : "undetermined"));
        CHECK(p["relative_std_error"].is_number() == offset);
    }
    REQUIRE(id["null_directions"].size() == 1);
    const json& d = id["null_directions"][0];
    const std::string text = d["combination"];
    CHECK(text ==
          "scaling rho1 and mu by s and k_minus, k_plus, c_minus, c_plus and sigma by 1/s leaves the output unchanged");
    const double c = 1.0 / std::sqrt(7.0);
    for (const char* up : {"rho1", "mu"}) CHECK(d["vector"][up].get<double>() == Approx(c).margin(1e-3));
    for (const char* down : {"k_minus", "k_plus", "c_minus", "c_plus", "sigma"})
        CHECK(d["vector"][down].get<double>() == Approx(-c).margin(1e-3));
    for (const char* offset : {"d_ds", "d_tm"}) CHECK(std::abs(d["vector"][offset].get<double>()) < 1e-3);
    CHECK(d["exponents"]["rho1"] == 1.0);
    CHECK(d["exponents"]["sigma"] == -1.0);
    CHECK_FALSE(d["exponents"].contains("d_ds"));

    // The verdict says it once, with what to do.
    const auto warnings = warning_lines(r.out);
    const auto said = std::count_if(warnings.begin(), warnings.end(),
                                    [](const std::string& w) { return w.find("parameter directions") != std::string::npos; });
    CHECK(said == 1);
    CHECK(r.out.find("    warning undetermined: the data determine only 8 of 9 parameter directions: " + text + "\n"
                     "      try: fix one of these parameters at a known value") != std::string::npos);
    const json findings = json::parse(read_text(tmp.path() / "r/summary.json"))["verdict"]["findings"];
    CHECK(std::count_if(findings.begin(), findings.end(), [](const json& f) { return f["code"] == "undetermined"; }) == 1);
}

TEST_CASE("with rho1 fixed the other eight CVT parameters are determined", "[e2e][identifiability]") {
    TempDir tmp;
    auto args = lm_fit(tmp.path() / "r");
    for (const char* s : {"parameters.rho1=1.42855", "estimation.lm.max_iterations=20"}) {
        args.push_back("--set");
        args.push_back(s);
    }
    const RunResult r = run_tvid(args);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const json id = json::parse(read_text(tmp.path() / "r/summary.json"))["identifiability"];
    CHECK(id["rank"] == 8);
    CHECK(id["of"] == 8);
    CHECK(id["condition_number"].is_number());
    CHECK(id["null_directions"].empty());
    CHECK(id["undetermined"].empty());
    for (const json& p : id["parameters"]) CHECK(p["flag"] != "undetermined");
    for (const std::string& w : warning_lines(r.out)) CHECK(w.find("parameter directions") == std::string::npos);
}

}  // namespace TVID_UNITY_ID
