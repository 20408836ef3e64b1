// The one validation of each optimizer's settings: defaults pass, and the first problem
// comes back as the key at fault and the message the experiment reader prints.
#include <catch2/catch.hpp>
#include <string>

#include "tvid/optim/settings_validation.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

void expect_problem(const std::optional<SettingsProblem>& problem, const std::string& key, const std::string& message) {
    REQUIRE(problem);
    CHECK(problem->key == key);
    CHECK(problem->message == message);
    CHECK_FALSE(problem->missing);
}

}  // namespace

TEST_CASE("the default settings of every optimizer are valid") {
    CHECK_FALSE(validate(PsoSettings{}));
    CHECK_FALSE(validate(LmSettings{}));
    CHECK_FALSE(validate(NloptSettings{}));
    CHECK_FALSE(validate(MultistartSettings{}));
}

TEST_CASE("swarm settings: each range, and the first problem in key order") {
    PsoSettings s;
    s.grid = 0;
    expect_problem(validate(s), "grid", "grid points per parameter must be between 1 and 1000");
    s.particles = 1000001;  // grid still wrong: grid comes first
    expect_problem(validate(s), "grid", "grid points per parameter must be between 1 and 1000");
    s.grid = 1000;
    expect_problem(validate(s), "particles", "particles must be between 1 and 1000000");
    s.particles = 1000000;
    s.iterations = -1;
    expect_problem(validate(s), "iterations", "iterations must be between 0 and 1e8");
    s.iterations = 0;
    CHECK_FALSE(validate(s));
    s.c2 = -0.1;
    expect_problem(validate(s), "c2", "must not be negative (the random factors are drawn from [0, value])");
}

TEST_CASE("least-squares settings: iterations and tolerances") {
    LmSettings s;
    s.max_iterations = 1000001;
    expect_problem(validate(s), "max_iterations", "must be between 0 and 1e6");
    s.max_iterations = 0;
    CHECK_FALSE(validate(s));
    s.xtol = -1e-9;
    expect_problem(validate(s), "xtol", "a tolerance cannot be negative");
    s.xtol = 0;
    s.gtol = std::nan("");
    expect_problem(validate(s), "gtol", "a tolerance cannot be negative");
}

TEST_CASE("NLopt settings: algorithm names, the local algorithm, budgets") {
    NloptSettings s;
    s.algorithm = "LN_BOBYQUA";
    const auto unknown = validate(s);
    REQUIRE(unknown);
    CHECK(unknown->key == "algorithm");
    CHECK(unknown->message.rfind("NLopt has no algorithm 'LN_BOBYQUA'; valid: ", 0) == 0);
    CHECK(unknown->message.find("LN_BOBYQA") != std::string::npos);

    s.algorithm = "G_MLSL_LDS";  // needs a local algorithm
    const auto missing = validate(s);
    REQUIRE(missing);
    CHECK(missing->key == "local_algorithm");
    CHECK(missing->missing);
    CHECK(missing->message == "(G_MLSL_LDS runs a local algorithm: e.g. local_algorithm: LN_BOBYQA)");
    s.local_algorithm = "GN_DIRECT";
    const auto global_local = validate(s);
    REQUIRE(global_local);
    CHECK(global_local->key == "local_algorithm");
    CHECK(global_local->message.rfind("'GN_DIRECT' is not a local NLopt algorithm; valid: ", 0) == 0);
    s.local_algorithm = "LN_SBPLX";
    CHECK_FALSE(validate(s));

    s.algorithm = "LN_BOBYQA";  // takes no local algorithm
    expect_problem(validate(s), "local_algorithm",
                   "LN_BOBYQA runs no local algorithm (only the MLSL and AUGLAG families do)");
    s.local_algorithm.clear();
    s.max_evaluations = 0;
    expect_problem(validate(s), "max_evaluations", "must be between 1 and 2e9");
    s.max_evaluations = 10;
    s.max_seconds = -1;
    expect_problem(validate(s), "max_seconds", "a time limit cannot be negative (0: none)");
    s.max_seconds = 0;
    s.ftol_rel = -1;
    expect_problem(validate(s), "ftol_rel", "a tolerance cannot be negative");
    s.ftol_rel = 0;
    s.population = -1;
    expect_problem(validate(s), "population", "must be between 0 (NLopt's default) and 1e6");
}

TEST_CASE("multistart settings: starts, and max_iterations only when given") {
    MultistartSettings s;
    s.starts = 0;
    expect_problem(validate(s), "starts", "starts must be between 1 and 1e5");
    s.starts = 100000;
    s.max_iterations = 0;  // given as 0: refused; not given: lm.max_iterations
    expect_problem(validate(s), "max_iterations", "must be between 1 and 1e6 (leave it out for lm.max_iterations)");
    s.max_iterations.reset();
    CHECK_FALSE(validate(s));
}

}  // namespace TVID_UNITY_ID
