#include "tvid/design/predicted_uncertainty.hpp"

#include <cmath>
#include <limits>

#include "tvid/estimation/identification_problem.hpp"
#include "tvid/estimation/residual_evaluator.hpp"
#include "tvid/sim/simulation_status.hpp"

namespace tvid {

double PredictedUncertainty::criterion(DesignCriterion c) const {
    switch (c) {
        case DesignCriterion::d_optimal: return d_optimal;
        case DesignCriterion::a_optimal: return a_optimal;
        case DesignCriterion::worst_relative_se: return worst_relative_se;
    }
    return d_optimal;
}

void fill_uncertainty(PredictedUncertainty& u) {
    const auto m = static_cast<Eigen::Index>(u.nominal.size());
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    // Each parameter scaled by its nominal value: the scaled F's eigenvalues compare
    // directions of relative change, whatever the units.
    Eigen::VectorXd scale(m);
    for (Eigen::Index j = 0; j < m; ++j) {
        const double v = std::abs(u.nominal[static_cast<std::size_t>(j)]);
        scale(j) = v > 0 ? v : 1.0;
    }
    const Eigen::MatrixXd scaled = scale.asDiagonal() * u.fisher * scale.asDiagonal();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(scaled);
    const Eigen::VectorXd lambda = eig.eigenvalues();
    const double largest = m > 0 ? std::max(lambda.maxCoeff(), 0.0) : 0.0;
    u.determined.assign(static_cast<std::size_t>(m), true);
    Eigen::MatrixXd inverse = Eigen::MatrixXd::Zero(m, m);
    double log_det = 0.0;
    bool singular = false;
    for (Eigen::Index i = 0; i < m; ++i) {
        const Eigen::VectorXd v = eig.eigenvectors().col(i);
        if (!(lambda(i) > 1e-12 * largest) || largest == 0.0) {
            singular = true;
            for (Eigen::Index j = 0; j < m; ++j)
                if (std::abs(v(j)) > 0.1) u.determined[static_cast<std::size_t>(j)] = false;
            continue;
        }
        inverse += v * v.transpose() / lambda(i);
        log_det -= std::log(lambda(i));
    }
    u.covariance = scale.asDiagonal() * inverse * scale.asDiagonal();
    u.correlation = Eigen::MatrixXd::Constant(m, m, nan);
    u.standard_error.assign(static_cast<std::size_t>(m), nan);
    u.relative_se.assign(static_cast<std::size_t>(m), nan);
    double sum_sq = 0.0, worst = 0.0;
    for (Eigen::Index j = 0; j < m; ++j) {
        const auto sj = static_cast<std::size_t>(j);
        if (!u.determined[sj]) {
            u.covariance.row(j).setConstant(nan);
            u.covariance.col(j).setConstant(nan);
            continue;
        }
        u.standard_error[sj] = std::sqrt(u.covariance(j, j));
        u.relative_se[sj] = std::sqrt(inverse(j, j));
        sum_sq += inverse(j, j);
        worst = std::max(worst, u.relative_se[sj]);
    }
    for (Eigen::Index i = 0; i < m; ++i)
        for (Eigen::Index j = 0; j < m; ++j)
            if (u.determined[static_cast<std::size_t>(i)] && u.determined[static_cast<std::size_t>(j)])
                u.correlation(i, j) = inverse(i, j) / std::sqrt(inverse(i, i) * inverse(j, j));
    if (singular || m == 0) {
        u.d_optimal = u.a_optimal = u.worst_relative_se = inf;
        return;
    }
    u.d_optimal = std::exp(log_det / (2.0 * static_cast<double>(m)));
    u.a_optimal = std::sqrt(sum_sq / static_cast<double>(m));
    u.worst_relative_se = worst;
}

PredictedUncertainty predict_uncertainty(const Experiment& design, const std::vector<double>& params,
                                         const std::vector<double>& noise) {
    PredictedUncertainty u;
    const IdentificationProblem problem(design);
    ResidualEvaluator evaluator(problem, EvaluatorOptions(1).with_jacobian(JacobianKind::sensitivity));
    std::vector<double> free;
    for (std::size_t i : problem.free_indices()) {
        free.push_back(params[i]);
        u.nominal.push_back(params[i]);
    }
    u.names = problem.free_names();
    const auto m = static_cast<Eigen::Index>(free.size());
    // What a candidate that does not simulate reports: nothing determined.
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    u.standard_error.assign(free.size(), nan);
    u.relative_se.assign(free.size(), nan);
    u.determined.assign(free.size(), false);
    u.correlation = Eigen::MatrixXd::Constant(m, m, nan);
    u.d_optimal = u.a_optimal = u.worst_relative_se = inf;
    const WindowSensitivity s = evaluator.output_sensitivity(free.data(), problem.definition().estimation.front(), 0);
    if (s.status != SimulationStatus::ok) {
        u.problem = s.problem.empty() ? to_string(s.status) : s.problem;
        return u;
    }
    u.simulated = true;
    u.fisher = Eigen::MatrixXd::Zero(m, m);
    Eigen::VectorXd g(m);
    for (std::size_t k = 0; k < s.dydp.size(); ++k) {
        const double w = 1.0 / (noise[k] * noise[k]);
        for (std::size_t i = 0; i < s.time.size(); ++i) {
            for (Eigen::Index j = 0; j < m; ++j) g(j) = s.dydp[k][static_cast<std::size_t>(j)][i];
            u.fisher.selfadjointView<Eigen::Lower>().rankUpdate(g, w);
        }
    }
    const Eigen::MatrixXd full = u.fisher.selfadjointView<Eigen::Lower>();
    u.fisher = full;
    if (!u.fisher.allFinite()) {
        u.simulated = false;
        u.problem = "the sensitivities are not finite numbers";
        return u;
    }
    fill_uncertainty(u);
    return u;
}

}  // namespace tvid
