// `tvid fit --optimizer lm`: the least-squares fit through the binary, its report, and
// the settings it refuses.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"

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
    CHECK(s["optimizer"]["jacobian"] == "fd");
    CHECK(s["optimizer"]["iterations"].get<int>() <= 5);
    CHECK(s["cost"]["kind"] == "l2");
    // Every iteration lowers or keeps the cost, from the initial cost down to the final one.
    const double initial = s["optimizer"]["initial_cost"].get<double>();
    const double final_cost = s["cost"]["value"].get<double>();
    CHECK(final_cost <= initial);
    CHECK(final_cost == Approx(s["estimation"]["pooled"]["Tds"]["cost_l2"].get<double>()).epsilon(1e-12));
    // 9 simulations per Jacobian here: the residuals and 2 per free parameter (8 free).
    CHECK(s["optimizer"]["evaluations"].get<long long>() >= 17);
}

TEST_CASE("the lm optimizer refuses an l1 cost and an unavailable Jacobian", "[e2e][lm]") {
    const std::string exp = (source_dir() / "configs/cvt_tipin_clean.yaml").string();
    const RunResult l1 = run_tvid({"fit", exp, "--optimizer", "lm"});
    CHECK(l1.exit_code == 2);
    CHECK(l1.err.find("estimation.cost") != std::string::npos);
    CHECK(l1.err.find("cost: l2") != std::string::npos);
    const RunResult jac = run_tvid({"fit", exp, "--optimizer", "lm", "--set", "estimation.cost=l2", "--set",
                                    "estimation.lm.jacobian=sensitivity"});
    CHECK(jac.exit_code == 2);
    CHECK(jac.err.find("estimation.lm.jacobian") != std::string::npos);
    const RunResult bad = run_tvid({"fit", exp, "--optimizer", "newton"});
    CHECK(bad.exit_code == 2);
    CHECK(bad.err.find("not one of: pso, lm") != std::string::npos);
}
