#include "tvid/estimation/stable_step.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "tvid/sim/rk4_stability.hpp"

namespace tvid {

namespace {

// The experiment's step at window w: max_step, or the sample interval at its start.
double base_step(const ProblemDefinition& d, const Window& w) {
    const std::vector<double>& time = d.inputs.time();
    const double interval = w.start + 1 < time.size() ? time[w.start + 1] - time[w.start] : 0.0;
    return d.simulation.max_step > 0 ? std::min(d.simulation.max_step, interval) : interval;
}

}  // namespace

StepPlan stable_step_plan(const ProblemDefinition& d, const Window& w, ProblemWorkspace& ws) {
    if (!steps_by_rk4(d.simulation.method)) return {};
    const double h = base_step(d, w);
    if (!(h > 0)) return {};
    ws.state_jacobian.bind(ws.model);
    const auto n = static_cast<Eigen::Index>(ws.state_jacobian.state_size());
    ws.jacobian_values.assign(static_cast<std::size_t>(n * n), 0.0);
    ws.state_jacobian.evaluate(ws.x.data(), ws.u0.data(), ws.jacobian_values.data());
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> A(
        ws.jacobian_values.data(), n, n);
    if (!A.allFinite()) return {};
    const Eigen::EigenSolver<Eigen::MatrixXd> eigen(A, false);
    if (eigen.info() != Eigen::Success) return {};
    // Within the margin in every direction when the fastest mode is within it at the edge's
    // nearest point: the edge's search (140 complex moduli a mode) is then not needed.
    double fastest = 0.0;
    for (Eigen::Index k = 0; k < n; ++k) fastest = std::max(fastest, std::abs(eigen.eigenvalues()[k]) * h);
    if (fastest <= kStableMargin * kRk4RadiusLowerBound) return {};
    double margin = 0.0;
    for (Eigen::Index k = 0; k < n; ++k) margin = std::max(margin, rk4_margin(eigen.eigenvalues()[k], h));
    if (!(margin > kStableMargin) || !std::isfinite(margin)) return {};
    const double needed = std::ceil(margin / kStableMargin);
    if (needed > static_cast<double>(kMaxStableSubsteps)) return {1, true};
    return {static_cast<std::size_t>(needed), false};
}

double window_max_step(const ProblemDefinition& d, const Window& w, const ProblemWorkspace& ws) {
    if (ws.substeps <= 1) return d.simulation.max_step;
    return base_step(d, w) / static_cast<double>(ws.substeps);
}

SimulationSettings window_settings(const ProblemDefinition& d, const Window& w, const ProblemWorkspace& ws) {
    SimulationSettings s = d.simulation;
    s.max_step = window_max_step(d, w, ws);
    if (ws.implicit_steps) s.method = IntegrationMethod::sdirk3;  // at the experiment's step
    return s;
}

}  // namespace tvid
