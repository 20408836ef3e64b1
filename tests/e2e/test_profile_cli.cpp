// `tvid profile`: the files it writes, its interval next to the linearised one, and its
// input errors (one line, exit 2, nothing written).
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
using nlohmann::json;

namespace {

std::vector<std::string> cvt_profile(const std::filesystem::path& out, const std::vector<std::string>& extra) {
    std::vector<std::string> args{"profile", (source_dir() / "configs/cvt_tipin.yaml").string(), "-o", out.string(),
                                  "--set", "estimation.optimizer=lm", "--set", "estimation.cost=l2",
                                  "--set", "parameters.rho1=1.42855"};
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
}

}  // namespace

TEST_CASE("tvid profile writes the grid and the 95 % interval, for an offset close to the linearised one",
          "[e2e][profile]") {
    TempDir tmp;
    const RunResult r = run_tvid(cvt_profile(tmp.path() / "p", {"--param", "d_ds", "--points", "11"}));
    INFO(r.out << r.err);
    REQUIRE(r.exit_code == 0);
    CHECK(r.out.find("95 % profile interval [") != std::string::npos);
    const json p = json::parse(read_text(tmp.path() / "p/profile.json"));
    CHECK(p["parameter"] == "d_ds");
    CHECK(p["points"] == 11);
    REQUIRE(p["interval95"]["low"].is_number());
    REQUIRE(p["interval95"]["high"].is_number());
    const double low = p["interval95"]["low"], high = p["interval95"]["high"];
    const double wald_low = p["linearised_interval95"][0], wald_high = p["linearised_interval95"][1];
    const double value = p["optimum"]["value"];
    CHECK(low < value);
    CHECK(value < high);
    // An output offset is nearly linear: the two intervals agree to a few per cent of their width.
    CHECK(std::abs(low - wald_low) < 0.05 * (wald_high - wald_low));
    CHECK(std::abs(high - wald_high) < 0.05 * (wald_high - wald_low));
    // profile.csv: a header, then one row per point with the other seven parameters.
    std::istringstream csv(read_text(tmp.path() / "p/profile.csv"));
    std::string header, line;
    std::getline(csv, header);
    CHECK(header.rfind("d_ds,cost,delta_chi2,converged,termination,k_minus", 0) == 0);
    int rows = 0;
    while (std::getline(csv, line)) ++rows;
    CHECK(rows == 11);
}

TEST_CASE("tvid profile input errors: one line, exit 2", "[e2e][profile]") {
    TempDir tmp;
    for (const auto& [args, expected] : std::vector<std::pair<std::vector<std::string>, std::string>>{
             {{"--param", "nope"}, "--param: nope: is not a parameter of the model"},
             {{"--param", "rho1"}, "is fixed in the experiment"},
             {{"--param", "d_ds", "--from", "-1000"}, "beyond the parameter's bounds"},
             {{"--param", "d_ds", "--points", "2"}, "--points"}}) {
        const RunResult r = run_tvid(cvt_profile(tmp.path() / "p", args));
        INFO(r.err);
        CHECK(r.exit_code == 2);
        CHECK(r.err.find(expected) != std::string::npos);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
        CHECK_FALSE(std::filesystem::exists(tmp.path() / "p/profile.json"));
    }
}

}  // namespace TVID_UNITY_ID
