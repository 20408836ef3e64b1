// Levenberg–Marquardt on the noise-free CVT recording: with ρ1 fixed (which removes the
// model's scaling symmetry) and every other parameter started 5-15 % off the truth, the
// least-squares fit returns to the truth.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "support/test_files.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/fit/fit_run.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;
using tvid::test::read_text;
using tvid::test::source_dir;

TEST_CASE("noise-free CVT tip-in: LM from 5-15 % off returns to the truth", "[regression][cvt][lm]") {
    const auto truth = nlohmann::json::parse(read_text(source_dir() / "data/cvt/truth.json"))["parameters"];
    const std::vector<std::pair<std::string, double>> start = {
        {"k_minus", 1.10}, {"k_plus", 0.92}, {"c_minus", 1.10}, {"c_plus", 0.93},
        {"mu", 0.93},      {"sigma", 1.12},  {"d_ds", 0.95},    {"d_tm", 1.05}};
    std::vector<Override> overrides = {{"estimation.optimizer", "lm"},
                                       {"estimation.cost", "l2"},
                                       {"parameters.rho1", std::to_string(truth["rho1"].get<double>())}};
    for (const auto& [name, factor] : start)
        overrides.push_back({"parameters." + name + ".init", std::to_string(factor * truth[name].get<double>())});
    const Experiment ex = load_experiment(source_dir() / "configs/cvt_tipin_clean.yaml", overrides);
    const IdentificationProblem problem(ex);
    std::vector<double> p_true;
    for (const auto& s : ex.parameters) p_true.push_back(truth[s.name].get<double>());
    const double truth_cost = evaluate_parameters(problem, p_true).cost;

    const FitResult fit = run_fit(problem, FitOptions{});
    REQUIRE(fit.success);
    CHECK(fit.run.name == "lm");
    CHECK(fit.run.converged);
    CHECK(fit.run.iterations < 40);
    // The data restart from an equilibrium at 1.5 s while the recording was in motion, so
    // the truth is not an exact zero of the cost: the fit may sit slightly below it.
    CHECK(fit.evaluation.cost <= truth_cost * 1.0001);
    for (std::size_t i = 0; i < ex.parameters.size(); ++i) {
        INFO(ex.parameters[i].name);
        CHECK(fit.best_params[i] == Approx(p_true[i]).epsilon(0.01));
    }
    // History: simulations counted, cost never rising.
    for (std::size_t k = 1; k < fit.run.history.size(); ++k) {
        CHECK(fit.run.history[k].best_cost <= fit.run.history[k - 1].best_cost);
        CHECK(fit.run.history[k].evaluations >= fit.run.history[k - 1].evaluations);
    }
}

}  // namespace TVID_UNITY_ID
