// pso+lm on CVT data made with the fit's own simulation settings (Yoshida & Takamatsu model, truth of
// data/cvt/truth.json): the truth's cost is zero up to rounding, and the hybrid drives the
// cost down to that floor and recovers every identifiable combination within 0.1 %.
//
// The model has an exact symmetry: θ → λθ with ρ1 → λρ1, μ → λμ, k± → k±/λ, c± → c±/λ,
// σ → σ/λ leaves Tds unchanged (Yoshida & Takamatsu eqs. 15-21), so the nine raw parameters are not
// identifiable, only ρ1k±, ρ1c±, μ/ρ1, σρ1, Δds and Δtm are.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <map>
#include <sstream>

#include "support/test_files.hpp"
#include "tvid/analysis/evaluation.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/fit/fit_run.hpp"
#include "tvid/optim/hybrid_pso_lm.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;
using tvid::test::read_text;
using tvid::test::source_dir;
using tvid::test::TempDir;

namespace {

const auto kConfig = source_dir() / "configs/cvt_tipin_clean.yaml";

std::vector<double> true_parameters(const Experiment& ex) {
    const auto truth = nlohmann::json::parse(read_text(source_dir() / "data/cvt/truth.json"))["parameters"];
    std::vector<double> p;
    for (const auto& s : ex.parameters) p.push_back(truth[s.name].get<double>());
    return p;
}

// The shipped recording's t and Ttm with Tds replaced, at every scored sample of every
// window, by the model's output for the true parameters (the windows do not overlap).
std::string simulated_recording(const Experiment& ex, const std::vector<double>& p_true) {
    const IdentificationProblem problem(ex);
    auto ws = problem.make_workspace();
    std::vector<double> tds = ex.data.column("Tds");
    for (const auto* split : {&ex.estimation, &ex.validation})
        for (const Window& w : *split) {
            const WindowTrace tr = problem.trace(p_true, w, *ws);
            REQUIRE(tr.status == SimulationStatus::ok);
            for (std::size_t k = 0; k < tr.samples.size(); ++k) tds[tr.samples[k]] = tr.simulated[0][k];
        }
    std::ostringstream csv;
    csv << "t,Ttm,Tds\n";
    char row[96];
    for (std::size_t i = 0; i < tds.size(); ++i) {
        std::snprintf(row, sizeof row, "%.17g,%.17g,%.17g\n", ex.data.column("t")[i], ex.data.column("Ttm")[i], tds[i]);
        csv << row;
    }
    return csv.str();
}

std::map<std::string, double> combinations(const std::map<std::string, double>& p) {
    const double rho1 = p.at("rho1");
    return {{"rho1*k_minus", rho1 * p.at("k_minus")}, {"rho1*k_plus", rho1 * p.at("k_plus")},
            {"rho1*c_minus", rho1 * p.at("c_minus")}, {"rho1*c_plus", rho1 * p.at("c_plus")},
            {"mu/rho1", p.at("mu") / rho1},           {"sigma*rho1", p.at("sigma") * rho1},
            {"d_ds", p.at("d_ds")},                   {"d_tm", p.at("d_tm")}};
}

std::map<std::string, double> by_name(const Experiment& ex, const std::vector<double>& p) {
    std::map<std::string, double> out;
    for (std::size_t i = 0; i < ex.parameters.size(); ++i) out[ex.parameters[i].name] = p[i];
    return out;
}

}  // namespace

TEST_CASE("noise-free CVT data of the fit's own simulation: pso+lm reaches the floor and the combinations",
          "[regression][cvt][hybrid]") {
    const Experiment shipped = load_experiment(kConfig);
    const std::vector<double> p_true = true_parameters(shipped);
    TempDir tmp;
    const auto data = tmp.write("tipin_exact.csv", simulated_recording(shipped, p_true));

    // The paper's swarm cut to 30 of 250 iterations finds the basin; LM polishes.
    const Experiment ex = load_experiment(kConfig, {{"data.file", data.string()},
                                                    {"estimation.optimizer", "pso+lm"},
                                                    {"estimation.cost", "l2"},
                                                    {"estimation.pso.iterations", "30"}});
    const IdentificationProblem problem(ex);
    const double truth_cost = evaluate_parameters(problem, p_true).cost;
    double signal = 0.0;  // Σ y² over the estimation window: the scale of the cost
    const Evaluation at_truth = evaluate_parameters(problem, p_true);
    for (const double y : at_truth.estimation.windows[0].trace.measured[0]) signal += y * y;
    CHECK(truth_cost <= 1e-20 * signal);  // the same simulation: zero up to rounding

    const FitResult fit = run_fit(problem, FitOptions{});
    REQUIRE(fit.success);
    CHECK(fit.run.name == "pso+lm");
    const HybridSummary* hybrid = fit.summary_of<HybridSummary>();
    REQUIRE(hybrid != nullptr);
    CHECK(hybrid->pso.iterations == 30);
    INFO("swarm cost " << hybrid->pso.best_cost << ", LM steps " << hybrid->lm.iterations << ", polished " << fit.evaluation.cost << ", truth " << truth_cost
                       << ", signal " << signal);
    CHECK(hybrid->pso.best_cost > 1e-6 * signal);          // the cut swarm alone is far from the floor
    CHECK(fit.evaluation.cost <= 1e-16 * signal);      // the polish reaches it
    const auto fitted = combinations(by_name(ex, fit.best_params));
    for (const auto& [name, truth] : combinations(by_name(ex, p_true))) {
        INFO(name << ": fitted " << fitted.at(name) << ", truth " << truth);
        CHECK(fitted.at(name) == Approx(truth).epsilon(1e-3));
    }
}

}  // namespace TVID_UNITY_ID
