// Numerical faults through the binary: a parameter set whose simulation fails is an
// answer (exit status 1, one line naming the window and why), not a crash or bad input.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;

namespace {

// The shipped CVT experiment under dopri5 with a budget of 10 steps per window: no
// window of 500 samples can be simulated.
std::vector<std::string> starved(const std::string& command, std::vector<std::string> extra) {
    std::vector<std::string> args{command, (source_dir() / "configs/cvt_tipin.yaml").string(), "--set",
                                  "simulation.method=dopri5", "--set", "simulation.max_steps=10"};
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
}

}  // namespace

TEST_CASE("tvid simulate and validate exit 1 naming the window whose simulation failed", "[e2e][faults]") {
    TempDir tmp;
    const std::string expected_line =
        "tvid: the simulation failed in estimation window time 1.5 to 3: step budget exceeded (and in 2 more "
        "window(s))\n";
    SECTION("simulate") {
        const RunResult r = run_tvid(starved("simulate", {"-o", (tmp.path() / "sim.csv").string()}));
        CHECK(r.exit_code == 1);
        CHECK(r.err == expected_line);
    }
    SECTION("validate") {
        const auto params = tmp.write("p.json", "{ \"rho1\": 1.5 }");
        const RunResult r = run_tvid(starved("validate", {"--params", params.string(), "--json"}));
        CHECK(r.exit_code == 1);
        CHECK(r.err == expected_line);
        const nlohmann::json j = nlohmann::json::parse(r.out);  // the scores it could compute, as JSON
        CHECK(j["cost"].is_null());
    }
    SECTION("the same experiment with the default budget simulates") {
        const RunResult r = run_tvid({"simulate", (source_dir() / "configs/cvt_tipin.yaml").string(), "--set",
                                      "simulation.method=dopri5", "-o", (tmp.path() / "sim.csv").string()});
        CHECK(r.exit_code == 0);
        CHECK(r.err.empty());
    }
}

}  // namespace TVID_UNITY_ID
