// `tvid fit --optimizer lm`: the least-squares fit through the binary, its report, and
// the settings it refuses.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
using nlohmann::json;

TEST_CASE("tvid fit --optimizer lm writes a least-squares report", "[e2e][lm]") {
    TempDir tmp;
    const auto out = tmp.path() / "lm";
    const RunResult r = run_tvid({"fit", (source_dir() / "configs/cvt_tipin_clean.yaml").string(), "-o", out.string(),
                                  "--optimizer", "lm", "--set", "estimation.cost=l2", "--set",
                                  "estimation.lm.max_iterations=5", "--set", "parameters.rho1=1.42855", "--threads",
                                  "2"});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    CHECK(r.out.find("lm (") != std::string::npos);
    const json s = json::parse(read_text(out / "summary.json"));
    CHECK(s["optimizer"]["name"] == "lm");
    CHECK(s["optimizer"]["jacobian"] == "sensitivity");  // the default
    CHECK(s["optimizer"]["iterations"].get<int>() <= 5);
    CHECK(s["cost"]["kind"] == "l2");
    // Every iteration lowers or keeps the cost, from the initial cost down to the final one.
    const double initial = s["optimizer"]["initial_cost"].get<double>();
    const double final_cost = s["cost"]["value"].get<double>();
    CHECK(final_cost <= initial);
    CHECK(final_cost == Approx(s["estimation"]["pooled"]["Tds"]["cost_l2"].get<double>()).epsilon(1e-12));
    // Per Jacobian: the residuals and one sensitivity simulation per column block.
    CHECK(s["optimizer"]["evaluations"].get<long long>() >= 2);
}

TEST_CASE("tvid fit --optimizer lm with jacobian: fd reaches the sensitivity fit's cost", "[e2e][lm]") {
    TempDir tmp;
    const std::string exp = (source_dir() / "configs/cvt_tipin_clean.yaml").string();
    json cost;
    for (const std::string jacobian : {"fd", "sensitivity"}) {
        const auto out = tmp.path() / jacobian;
        const RunResult r = run_tvid({"fit", exp, "-o", out.string(), "--optimizer", "lm", "--set",
                                      "estimation.cost=l2", "--set", "estimation.lm.jacobian=" + jacobian, "--set",
                                      "estimation.lm.max_iterations=8", "--set", "parameters.rho1=1.42855"});
        INFO(r.err);
        REQUIRE(r.exit_code == 0);
        const json s = json::parse(read_text(out / "summary.json"));
        CHECK(s["optimizer"]["jacobian"] == jacobian);
        cost[jacobian] = s["cost"]["value"];
        // Central differences: 2 simulations per free parameter (8 free) and the residuals.
        if (jacobian == "fd") CHECK(s["optimizer"]["evaluations"].get<long long>() >= 17);
    }
    // Both Jacobians lead down the same valley: the same cost to a few per cent after 8 steps.
    CHECK(cost["fd"].get<double>() == Approx(cost["sensitivity"].get<double>()).epsilon(0.05));
}

TEST_CASE("the lm optimizer refuses an l1 cost and an unknown Jacobian", "[e2e][lm]") {
    const std::string exp = (source_dir() / "configs/cvt_tipin_clean.yaml").string();
    const RunResult l1 = run_tvid({"fit", exp, "--optimizer", "lm"});
    CHECK(l1.exit_code == 2);
    CHECK(l1.err.find("estimation.cost") != std::string::npos);
    CHECK(l1.err.find("cost: l2") != std::string::npos);
    const RunResult jac = run_tvid({"fit", exp, "--optimizer", "lm", "--set", "estimation.cost=l2", "--set",
                                    "estimation.lm.jacobian=adjoint"});
    CHECK(jac.exit_code == 2);
    CHECK(jac.err.find("estimation.lm.jacobian") != std::string::npos);
    CHECK(jac.err.find("sensitivity, fd") != std::string::npos);
    const RunResult bad = run_tvid({"fit", exp, "--optimizer", "newton"});
    CHECK(bad.exit_code == 2);
    CHECK(bad.err.rfind("tvid: --optimizer: newton not in {pso,lm,", 0) == 0);
}

}  // namespace TVID_UNITY_ID
