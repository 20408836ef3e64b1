// Loading the optimizer settings: the five optimizer names, estimation.nlopt and
// estimation.multistart, and every bad setting as one error naming file, line and key
// (an unknown NLopt algorithm lists the valid names).
#include <catch2/catch.hpp>
#include <optional>
#include <string>
#include <vector>

#include "support/test_files.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/util/input_error.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;
using tvid::test::source_dir;
using tvid::test::TempDir;

namespace {

// The CVT experiment on the shipped noise-free recording; line numbers are index + 1.
std::vector<std::string> experiment_lines(const std::string& estimation_line_1, const std::string& estimation_line_2,
                                          const std::string& d_ds_line) {
    const std::string data = (source_dir() / "data/cvt/tipin_clean.csv").string();
    return {
        "tvid: 1",                                                     // 1
        "data: { file: '" + data + "', time: t }",                     // 2
        "model: { preset: cvt_clearance }",                            // 3
        "inputs: { Ttm: Ttm }",                                        // 4
        "outputs: { Tds: Tds }",                                       // 5
        "parameters:",                                                 // 6
        "  rho1:    { min: 0.01, max: 100, range: [1, 2] }",           // 7
        "  k_minus: { min: 1, max: 1.0e6, range: [1.0e3, 1.0e4] }",    // 8
        "  k_plus:  { min: 1, max: 1.0e6, range: [1.0e3, 1.0e4] }",    // 9
        "  c_minus: { min: 0, max: 1.0e4, range: [10, 20] }",          // 10
        "  c_plus:  { min: 0, max: 1.0e4, range: [10, 20] }",          // 11
        "  mu:      { min: 0, max: 0.1, range: [1.0e-3, 5.0e-3] }",    // 12
        "  sigma:   { value: 1132.81 }",                               // 13
        d_ds_line,                                                     // 14
        "  d_tm:    { min: -100, max: 100, range: [10, 15] }",         // 15
        "windows: { estimation: [ { time: [1.5, 1.6] } ] }",           // 16
        "estimation:",                                                 // 17
        estimation_line_1,                                             // 18
        estimation_line_2,                                             // 19
    };
}

struct Loaded {
    std::optional<Experiment> experiment;
    std::optional<InputError> error;
    std::string file;
};

// d_ds has no bounds unless `d_ds_line` gives them.
Loaded load(const std::string& line_1, const std::string& line_2 = "  cost: l2",
            const std::string& d_ds_line = "  d_ds:    { init: -7 }") {
    TempDir dir;
    std::string text;
    for (const std::string& l : experiment_lines(line_1, line_2, d_ds_line)) text += l + "\n";
    Loaded out;
    out.file = dir.write("exp.yaml", text).string();
    try {
        out.experiment = load_experiment(out.file);
    } catch (const InputError& e) {
        out.error = e;
    }
    return out;
}

void expect_error(const Loaded& r, int line, const std::string& key, const std::string& fragment) {
    REQUIRE(r.error);
    const std::string what = r.error->what();
    INFO(what);
    CHECK(r.error->line() == line);
    CHECK(r.error->key() == key);
    CHECK(what.rfind(r.file + ":" + std::to_string(line) + ": " + key + ": ", 0) == 0);
    CHECK(what.find('\n') == std::string::npos);
    CHECK(what.find(fragment) != std::string::npos);
}

}  // namespace

TEST_CASE("an experiment that names no optimizer runs the swarm, and the settings say it is the default", "[swarm]") {
    const std::string d_ds = "  d_ds:    { min: -100, max: 100, range: [-10, -5] }";
    const Loaded plain = load("  cost: l1", "  strict: false", d_ds);
    REQUIRE(plain.experiment);
    CHECK(plain.experiment->estimation_settings.optimizer == OptimizerKind::pso);
    CHECK_FALSE(plain.experiment->estimation_settings.optimizer_given);
    const Loaded named = load("  optimizer: pso", "  cost: l1", d_ds);
    REQUIRE(named.experiment);
    CHECK(named.experiment->estimation_settings.optimizer == OptimizerKind::pso);
    CHECK(named.experiment->estimation_settings.optimizer_given);
}

TEST_CASE("the five optimizers load with their settings", "[experiment][optimizers]") {
    const Loaded nlopt = load("  optimizer: nlopt",
                              "  nlopt: { algorithm: ld_lbfgs, max_evaluations: 300, max_seconds: 20, xtol_rel: 1e-6, "
                              "ftol_rel: 1e-9, population: 12, seed: 4 }");
    REQUIRE(nlopt.experiment);
    const EstimationSettings& n = nlopt.experiment->estimation_settings;
    CHECK(n.optimizer == OptimizerKind::nlopt);
    CHECK(n.nlopt.algorithm == "LD_LBFGS");  // NLopt's spelling
    CHECK(n.nlopt.max_evaluations == 300);
    CHECK(n.nlopt.max_seconds == 20);
    CHECK(n.nlopt.xtol_rel == 1e-6);
    CHECK(n.nlopt.ftol_rel == 1e-9);
    CHECK(n.nlopt.population == 12);
    CHECK(n.nlopt.seed == 4);
    CHECK(n.cost == CostKind::l1);  // NLopt minimizes either cost

    const Loaded mlsl = load("  optimizer: nlopt", "  nlopt: { algorithm: G_MLSL_LDS, local_algorithm: LN_BOBYQA }",
                             "  d_ds:    { min: -100, max: 100 }");
    REQUIRE(mlsl.experiment);
    CHECK(mlsl.experiment->estimation_settings.nlopt.local_algorithm == "LN_BOBYQA");

    const Loaded multistart = load("  optimizer: multistart\n  cost: l2", "  multistart: { starts: 5, seed: 9, max_iterations: 30 }",
                                   "  d_ds:    { init: -7, range: [-10, -5] }");
    REQUIRE(multistart.experiment);
    const EstimationSettings& m = multistart.experiment->estimation_settings;
    CHECK(m.optimizer == OptimizerKind::multistart);
    CHECK(m.multistart.starts == 5);
    CHECK(m.multistart.seed == 9);
    CHECK(m.multistart.max_iterations == 30);

    const Loaded hybrid = load("  optimizer: pso+lm", "  cost: l2", "  d_ds:    { min: -100, max: 100 }");
    REQUIRE(hybrid.experiment);
    CHECK(hybrid.experiment->estimation_settings.optimizer == OptimizerKind::pso_lm);
    CHECK(std::string(optimizer_name(OptimizerKind::pso_lm)) == "pso+lm");
}

TEST_CASE("an unknown NLopt algorithm is an error listing the valid names", "[experiment][optimizers]") {
    const Loaded r = load("  optimizer: nlopt", "  nlopt: { algorithm: LN_BOBYQUA }");
    expect_error(r, 19, "estimation.nlopt.algorithm", "NLopt has no algorithm 'LN_BOBYQUA'; valid: ");
    const std::string what = r.error->what();
    for (const char* name : {"LN_BOBYQA", "LD_LBFGS", "GN_DIRECT_L", "GN_ISRES", "G_MLSL_LDS"})
        CHECK(what.find(name) != std::string::npos);
}

TEST_CASE("NLopt settings errors name the line and the key", "[experiment][optimizers]") {
    expect_error(load("  optimizer: nlopt", "  nlopt: { algorithm: G_MLSL }"), 19, "estimation.nlopt.local_algorithm",
                 "G_MLSL runs a local algorithm");
    expect_error(load("  optimizer: nlopt", "  nlopt: { algorithm: GN_MLSL, local_algorithm: GN_DIRECT }"), 19,
                 "estimation.nlopt.local_algorithm", "not a local NLopt algorithm");
    expect_error(load("  optimizer: nlopt", "  nlopt: { algorithm: LN_BOBYQA, local_algorithm: LN_SBPLX }"), 19,
                 "estimation.nlopt.local_algorithm", "runs no local algorithm");
    expect_error(load("  optimizer: nlopt", "  nlopt: { max_evaluations: 0 }"), 19, "estimation.nlopt.max_evaluations",
                 "between");
    expect_error(load("  optimizer: nlopt", "  nlopt: { max_seconds: -1 }"), 19, "estimation.nlopt.max_seconds",
                 "negative");
    expect_error(load("  optimizer: nlopt", "  nlopt: { algorithm: LN_BOBYQA, xtol: 1 }"), 19, "estimation.nlopt.xtol",
                 "xtol_rel");
    // A global algorithm searches the bounds: d_ds has none.
    expect_error(load("  optimizer: nlopt", "  nlopt: { algorithm: GN_DIRECT_L }"), 14, "parameters.d_ds",
                 "global NLopt algorithm GN_DIRECT_L searches within the bounds");
}

TEST_CASE("least-squares optimizers need the l2 cost, multistart needs a search box", "[experiment][optimizers]") {
    expect_error(load("  optimizer: pso+lm", "  cost: l1"), 19, "estimation.cost",
                 "the pso+lm optimizer minimizes a sum of squares: set cost: l2");
    expect_error(load("  optimizer: multistart", "  cost: l1"), 19, "estimation.cost",
                 "the multistart optimizer minimizes a sum of squares");
    expect_error(load("  optimizer: multistart", "  cost: l2"), 14, "parameters.d_ds",
                 "multistart samples its starts in the search box");
    expect_error(load("  optimizer: multistart\n  cost: l2", "  multistart: { starts: 0 }"), 20,
                 "estimation.multistart.starts", "between 1");
    expect_error(load("  optimizer: newton"), 18, "estimation.optimizer", "pso+lm");
    expect_error(load("  optimizer: pso+lm"), 14, "parameters.d_ds", "search box");
}

TEST_CASE("settings are read whole, then validated: the problem names its key and line", "[experiment][optimizers]") {
    // A count beyond int is still out of range, not wrapped around into it.
    expect_error(load("  optimizer: pso", "  pso: { start: latin_hypercube, particles: 5000000000 }"), 19,
                 "estimation.pso.particles", "particles must be between 1 and 1000000");
    expect_error(load("  optimizer: pso", "  pso: { iterations: -5, seed: 3 }"), 19, "estimation.pso.iterations",
                 "iterations must be between 0 and 1e8");
    expect_error(load("  optimizer: pso", "  pso: { seed: -1 }"), 19, "estimation.pso.seed",
                 "the seed must not be negative");
    expect_error(load("  optimizer: lm\n  cost: l2", "  lm: { gtol: -1 }"), 20, "estimation.lm.gtol",
                 "a tolerance cannot be negative");
    // multistart.max_iterations given as 0 is refused (left out, each start runs lm.max_iterations).
    expect_error(load("  optimizer: multistart\n  cost: l2", "  multistart: { max_iterations: 0 }"), 20,
                 "estimation.multistart.max_iterations", "must be between 1 and 1e6 (leave it out for lm.max_iterations)");
    const Loaded without = load("  optimizer: multistart\n  cost: l2", "  multistart: { starts: 2 }",
                                "  d_ds:    { init: -7, range: [-10, -5] }");
    REQUIRE(without.experiment);
    CHECK_FALSE(without.experiment->estimation_settings.multistart.max_iterations);
    // Every optimizer name of the table is read back as its kind.
    for (const OptimizerKindRow& row : optimizer_kinds()) {
        const OptimizerKind kind = row.kind;
        const Loaded r = load(std::string("  optimizer: ") + optimizer_name(kind), "  cost: l2",
                              "  d_ds:    { min: -100, max: 100, range: [-10, -5] }");
        INFO(optimizer_name(kind));
        REQUIRE(r.experiment);
        CHECK(r.experiment->estimation_settings.optimizer == kind);
    }
}

}  // namespace TVID_UNITY_ID
