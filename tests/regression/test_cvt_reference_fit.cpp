// Reference fits of the CVT clearance model (Yoshida & Takamatsu) on the shipped synthetic
// recordings, whose true parameters are known (data/cvt/truth.json). Both run the
// shipped experiments unchanged: the paper's swarm of 2^9 = 512 grid particles,
// 250 iterations, w = 1, c1 = c2 = 0.4 (Yoshida & Takamatsu Section V-A).
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "support/test_files.hpp"
#include "tvid/analysis/evaluation.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/fit/fit_run.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;
using tvid::test::read_text;
using tvid::test::source_dir;

namespace {

nlohmann::json truth_file() { return nlohmann::json::parse(read_text(source_dir() / "data/cvt/truth.json")); }

std::vector<double> true_parameters(const Experiment& ex) {
    const auto truth = truth_file();
    std::vector<double> p;
    for (const auto& s : ex.parameters) p.push_back(truth["parameters"][s.name].get<double>());
    return p;
}

double estimation_q(const Evaluation& ev) { return ev.estimation.pooled.at(0).q_index; }

// The combinations the data determine: θ can be rescaled by λ with ρ1 → λρ1, μ → λμ,
// k± → k±/λ, c± → c±/λ, σ → σ/λ without changing Tds, so single parameters are not
// identifiable but ρ1·k±, ρ1·c±, μ/ρ1 and the amplitude shifts are.
struct Combinations {
    double rho_k_plus, rho_c_plus, mu_over_rho, d_ds, d_tm;
};
Combinations combinations(const std::vector<double>& p) {
    return {p[0] * p[2], p[0] * p[4], p[5] / p[0], p[7], p[8]};
}

}  // namespace

TEST_CASE("noise-free CVT tip-in: the paper's swarm reaches Q >= 99 % and the identifiable combinations",
          "[regression][cvt]") {
    const Experiment ex = load_experiment(source_dir() / "configs/cvt_tipin_clean.yaml");
    const IdentificationProblem problem(ex);
    const std::vector<double> p_true = true_parameters(ex);
    const Evaluation truth = evaluate_parameters(problem, p_true);
    // The data were made with the same scheme: the truth fits to the restart transient.
    CHECK(estimation_q(truth) > 99.9);
    CHECK(truth.cost == Approx(truth_file()["reference_costs"]["clean"]["E"].get<double>()).epsilon(1e-6));

    const FitResult fit = run_fit(problem, FitOptions{});
    REQUIRE(fit.success);
    REQUIRE(fit.summary_of<PsoSummary>() != nullptr);
    CHECK(fit.summary_of<PsoSummary>()->particles == 512);
    CHECK(fit.run.iterations == 250);
    INFO("fit cost " << fit.evaluation.cost << ", truth cost " << truth.cost);
    CHECK(estimation_q(fit.evaluation) >= 99.0);
    CHECK(fit.run.failed_evaluations < fit.run.evaluations);
    // The validation windows are predicted as well (noise-free, same model).
    CHECK(fit.evaluation.validation.pooled.at(0).q_index > 99.0);

    const Combinations c = combinations(fit.best_params), t = combinations(p_true);
    CHECK(c.rho_k_plus == Approx(t.rho_k_plus).epsilon(0.05));
    CHECK(c.rho_c_plus == Approx(t.rho_c_plus).epsilon(0.05));
    CHECK(c.mu_over_rho == Approx(t.mu_over_rho).epsilon(0.15));
    CHECK(c.d_ds == Approx(t.d_ds).margin(0.5));
    CHECK(c.d_tm == Approx(t.d_tm).margin(0.5));
    // The scaling symmetry is reported: 8 of 9 directions determined.
    REQUIRE(fit.uncertainty.available);
    CHECK(fit.uncertainty.rank == 8);
}

TEST_CASE("noisy CVT tip-in: the paper's swarm reaches the Q of the true parameters within 1 point",
          "[regression][cvt]") {
    const Experiment ex = load_experiment(source_dir() / "configs/cvt_tipin.yaml");
    const IdentificationProblem problem(ex);
    const Evaluation truth = evaluate_parameters(problem, true_parameters(ex));
    // The generator's own evaluation of the truth agrees with the tool's.
    CHECK(estimation_q(truth) == Approx(truth_file()["reference_costs"]["noisy"]["Q"].get<double>()).epsilon(1e-6));

    const FitResult fit = run_fit(problem, FitOptions{});
    REQUIRE(fit.success);
    INFO("fit Q " << estimation_q(fit.evaluation) << ", truth Q " << estimation_q(truth));
    CHECK(estimation_q(fit.evaluation) >= estimation_q(truth) - 1.0);
    // The noise floor: no fit can be much below the truth's cost on the same noisy data.
    CHECK(fit.evaluation.cost > 0.8 * truth.cost);
    CHECK(fit.evaluation.validation.pooled.at(0).q_index > 97.0);
}

}  // namespace TVID_UNITY_ID
