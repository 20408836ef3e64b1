// Forward sensitivities (the methodology paper eq. 9) against central finite differences of the
// residuals, on both shipped problems: the engine (measured start whose warm-up shooting
// depends on the parameters) and the CVT clearance model (equilibrium start whose angles
// depend on the parameters). A sensitivity column that missed either dependence would
// differ from the differences by far more than the tolerance.
#include <catch2/catch.hpp>
#include <Eigen/Dense>
#include <cmath>

#include "support/test_files.hpp"
#include "tvid/estimation/residual_evaluator.hpp"
#include "tvid/estimation/forward_sensitivity.hpp"
#include "tvid/experiment/experiment.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;
using tvid::test::source_dir;

namespace {

// Central differences of the residuals with a step of `relative` times each parameter.
Eigen::MatrixXd central_differences(const IdentificationProblem& problem, const std::vector<double>& x,
                                    double relative) {
    auto ws = problem.make_workspace();
    std::vector<double> rp, rm, p = x;
    Eigen::MatrixXd J;
    for (std::size_t j = 0; j < x.size(); ++j) {
        const double h = relative * std::abs(x[j]);
        p[j] = x[j] + h;
        REQUIRE(problem.residuals(p.data(), *ws, rp));
        p[j] = x[j] - h;
        REQUIRE(problem.residuals(p.data(), *ws, rm));
        p[j] = x[j];
        if (J.size() == 0) J.resize(static_cast<Eigen::Index>(rp.size()), static_cast<Eigen::Index>(x.size()));
        for (std::size_t i = 0; i < rp.size(); ++i)
            J(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = (rp[i] - rm[i]) / (2 * h);
    }
    return J;
}

void check_columns(const IdentificationProblem& problem, const std::vector<double>& x, double step,
                   double tolerance) {
    const Eigen::MatrixXd fd = central_differences(problem, x, step);
    const ForwardSensitivity sensitivity(problem);
    auto ws = sensitivity.make_workspace();
    Eigen::MatrixXd J(fd.rows(), fd.cols());
    REQUIRE(sensitivity.jacobian_columns(x.data(), 0, x.size(), *ws, J));
    for (Eigen::Index j = 0; j < fd.cols(); ++j) {
        INFO(problem.free_names()[static_cast<std::size_t>(j)]);
        const double error = (J.col(j) - fd.col(j)).norm() / fd.col(j).norm();
        CAPTURE(error, fd.col(j).norm());
        CHECK(error < tolerance);
    }
    // Blocks of columns give the same columns as all at once.
    Eigen::MatrixXd blocks(fd.rows(), fd.cols());
    const std::size_t half = x.size() / 2;
    REQUIRE(sensitivity.jacobian_columns(x.data(), 0, half, *ws, blocks));
    REQUIRE(sensitivity.jacobian_columns(x.data(), half, x.size(), *ws, blocks));
    CHECK((blocks - J).cwiseAbs().maxCoeff() == 0.0);
}

}  // namespace

TEST_CASE("engine: forward sensitivities through the warm-up shooting match central differences",
          "[sensitivity][engine][heavy]") {
    // Three cycles (two of warm-up) of the 6-node crank model at a 20 %-off point. The
    // differences carry the rounding noise of the warm-up shooting (~1e-10 rad/s), which
    // swamps the weak damping columns at small steps: a step of 1e-3 keeps both
    // truncation and noise near 1e-4. Without the shooting's dependence on the parameters
    // the inertia and friction columns would be off by 70-200 %.
    const Experiment ex = load_experiment(source_dir() / "configs/engine_idle_clean.yaml");
    const IdentificationProblem problem(ex);
    check_columns(problem, problem.initial(), 1e-3, 1e-3);
}

TEST_CASE("cvt: forward sensitivities from the equilibrium start match central differences",
          "[sensitivity][cvt]") {
    const Experiment ex = load_experiment(source_dir() / "configs/cvt_tipin_clean.yaml",
                                          {{"windows.estimation", "[{time: [1.0, 2.0]}]"}});
    const IdentificationProblem problem(ex);
    // The differences converge as h² here (no shooting): at a step of 1e-5 they agree to
    // ~1e-8. Without the equilibrium's dependence mu, sigma and d_tm would be off by 16-36 %.
    check_columns(problem, problem.initial(), 1e-5, 1e-6);
}

TEST_CASE("the least-squares Jacobian from sensitivities equals the one by differences to their accuracy",
          "[sensitivity][engine][heavy]") {
    const Experiment ex = load_experiment(source_dir() / "configs/engine_idle_clean.yaml");
    const IdentificationProblem problem(ex);
    ResidualEvaluator by_sensitivity(problem, EvaluatorOptions(2).with_jacobian(JacobianKind::sensitivity));
    ResidualEvaluator one_thread(problem, EvaluatorOptions(1).with_jacobian(JacobianKind::sensitivity));
    ResidualEvaluator by_differences(problem, EvaluatorOptions(2).with_jacobian(JacobianKind::fd));
    const auto rows = static_cast<Eigen::Index>(by_sensitivity.residual_count());
    const auto cols = static_cast<Eigen::Index>(problem.dimension());
    Eigen::MatrixXd Js(rows, cols), J1(rows, cols), Jf(rows, cols);
    Eigen::VectorXd rs(rows), r1(rows), rf(rows);
    REQUIRE(by_sensitivity.jacobian(problem.initial().data(), rs.data(), Js));
    REQUIRE(one_thread.jacobian(problem.initial().data(), r1.data(), J1));
    REQUIRE(by_differences.jacobian(problem.initial().data(), rf.data(), Jf));
    CHECK((rs - rf).cwiseAbs().maxCoeff() == 0.0);
    CHECK((Js - J1).cwiseAbs().maxCoeff() == 0.0);  // the same with 1 or 2 threads
    CHECK((Js - Jf).norm() / Jf.norm() < 1e-3);  // the differences' noise, see above
}

TEST_CASE("fixed-step RK4 sensitivities as PackedDual equal the augmented system's", "[sensitivity][engine][cvt][heavy]") {
    // The packed path integrates the same equations with the same RK4 arithmetic: on the
    // engine (no time inputs) every entry is the same double; on the CVT the augmented
    // system interpolates the input at the stage times where the packed path uses the
    // precomputed sample midpoints, equal to rounding.
    for (const auto& [config, tolerance] : {std::pair{"configs/engine_idle_clean.yaml", 0.0},
                                             std::pair{"configs/cvt_tipin_clean.yaml", 1e-9}}) {
        INFO(config);
        const Experiment ex = load_experiment(source_dir() / config);
        const IdentificationProblem problem(ex);
        ForwardSensitivity sensitivity(problem);
        auto ws = sensitivity.make_workspace();
        const auto rows = static_cast<Eigen::Index>(estimation_residual_count(ex));
        const auto cols = static_cast<Eigen::Index>(problem.dimension());
        Eigen::MatrixXd packed(rows, cols), augmented(rows, cols);
        const std::vector<double> x = problem.initial();
        REQUIRE(sensitivity.jacobian_columns(x.data(), 0, x.size(), *ws, packed));
        sensitivity.set_packed(false);
        REQUIRE(sensitivity.jacobian_columns(x.data(), 0, x.size(), *ws, augmented));
        for (Eigen::Index j = 0; j < cols; ++j) {
            INFO(problem.free_names()[static_cast<std::size_t>(j)]);
            CHECK((packed.col(j) - augmented.col(j)).norm() <= tolerance * augmented.col(j).norm());
        }
    }
}

TEST_CASE("a Jacobian after the residuals at the same point reuses their starts and equals a fresh one",
          "[sensitivity][engine][heavy]") {
    const Experiment ex = load_experiment(source_dir() / "configs/engine_idle_clean.yaml");
    const IdentificationProblem problem(ex);
    ResidualEvaluator reusing(problem, EvaluatorOptions(2).with_jacobian(JacobianKind::sensitivity)), fresh(problem, EvaluatorOptions(2).with_jacobian(JacobianKind::sensitivity));
    const auto rows = static_cast<Eigen::Index>(reusing.residual_count());
    const auto cols = static_cast<Eigen::Index>(problem.dimension());
    Eigen::MatrixXd J_reused(rows, cols), J_fresh(rows, cols);
    Eigen::VectorXd r(rows), r_reused(rows), r_fresh(rows);
    std::vector<double> x = problem.initial();
    x[3] *= 1.05;
    REQUIRE(reusing.residuals(x.data(), r.data()));
    const long long after_residuals = reusing.simulations();
    REQUIRE(reusing.jacobian(x.data(), r_reused.data(), J_reused));
    REQUIRE(fresh.jacobian(x.data(), r_fresh.data(), J_fresh));
    CHECK(reusing.simulations() - after_residuals == fresh.simulations() - 1);  // no second residual simulation
    CHECK((r_reused - r_fresh).cwiseAbs().maxCoeff() == 0.0);
    CHECK((J_reused - J_fresh).cwiseAbs().maxCoeff() == 0.0);
    // Elsewhere it simulates again.
    x[3] *= 1.01;
    REQUIRE(reusing.jacobian(x.data(), r_reused.data(), J_reused));
    REQUIRE(fresh.jacobian(x.data(), r_fresh.data(), J_fresh));
    CHECK((J_reused - J_fresh).cwiseAbs().maxCoeff() == 0.0);
}

TEST_CASE("the warm-up shooting meets the encoder at both of its samples", "[sensitivity][engine]") {
    const Experiment ex = load_experiment(source_dir() / "configs/engine_idle_clean.yaml");
    const IdentificationProblem problem(ex);
    auto ws = problem.make_workspace();
    for (const double scale : {1.0, 1.2, 0.8}) {
        std::vector<double> params = problem.full_parameters(problem.initial());
        for (double& p : params) p *= scale;
        ws->params = params;
        ws->model.set_parameters(ws->params.data());
        const Window& w = ex.estimation.at(0);
        const WindowStart start = problem.start_window(w, *ws, nullptr);
        REQUIRE(start.status == SimulationStatus::ok);
        REQUIRE(start.shot);
        // The start it found, simulated plainly, lands on the measured crank angle.
        std::vector<double> x = ws->x_start;
        double at_mid = 0.0;
        const auto watch = [&](std::size_t i, const std::vector<double>& state, const std::vector<double>&) {
            if (i == start.mid) at_mid = state[start.node];
            return true;
        };
        REQUIRE(simulate_samples(ws->model, problem.inputs(), w.start, w.first, x, ex.simulation, ws->buffers, watch) ==
                SimulationStatus::ok);
        CHECK(std::abs(at_mid - ex.crank_angle[start.mid]) < 1e-11);
        CHECK(std::abs(x[start.node] - ex.crank_angle[w.first]) < 1e-11);
        CHECK(x == ws->x);  // the shooting's own last state, bit for bit
    }
}

}  // namespace TVID_UNITY_ID
