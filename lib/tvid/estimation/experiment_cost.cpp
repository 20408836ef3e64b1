#include "tvid/estimation/experiment_cost.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tvid {

namespace {
double sign(double e) { return e > 0 ? 1.0 : (e < 0 ? -1.0 : 0.0); }
}  // namespace

ExperimentCost::ExperimentCost(const IdentificationProblem& problem, int threads)
    : problem_(&problem),
      least_squares_(problem, threads, problem.experiment().estimation_settings.jacobian),
      l1_(problem.experiment().estimation_settings.cost == CostKind::l1),
      outputs_(problem.experiment().outputs.size()) {
    // The scored samples of each window, as estimation_residual_count counts them.
    for (const Window& w : problem.experiment().estimation)
        window_residuals_.push_back((w.last - std::max(w.first, w.start + 1) + 1) * outputs_);
    r_.resize(least_squares_.residual_count());
    J_.resize(static_cast<Eigen::Index>(r_.size()), static_cast<Eigen::Index>(problem.dimension()));
}

double ExperimentCost::cost_of_residuals(const double* r) const {
    double total = 0.0;
    std::size_t at = 0;
    for (const std::size_t n : window_residuals_) {
        double window_sum = 0.0;
        for (std::size_t i = at; i < at + n; ++i) window_sum += l1_ ? std::abs(r[i]) : r[i] * r[i];
        total += l1_ ? window_sum / static_cast<double>(n / outputs_) : window_sum;  // l1: mean per window
        at += n;
    }
    return std::isfinite(total) ? total : std::numeric_limits<double>::infinity();
}

double ExperimentCost::value(const double* x) {
    if (!least_squares_.residuals(x, r_.data())) return std::numeric_limits<double>::infinity();
    return cost_of_residuals(r_.data());
}

double ExperimentCost::value_and_gradient(const double* x, double* gradient) {
    if (!least_squares_.jacobian(x, r_.data(), J_)) return std::numeric_limits<double>::infinity();
    const double f = cost_of_residuals(r_.data());
    const auto m = J_.cols();
    Eigen::Map<Eigen::VectorXd> g(gradient, m);
    const Eigen::Map<const Eigen::VectorXd> r(r_.data(), static_cast<Eigen::Index>(r_.size()));
    if (!l1_) {
        g.noalias() = 2.0 * J_.transpose() * r;
    } else {
        g.setZero();
        Eigen::Index at = 0;
        for (const std::size_t n : window_residuals_) {
            const double weight = 1.0 / static_cast<double>(n / outputs_);
            for (Eigen::Index i = at; i < at + static_cast<Eigen::Index>(n); ++i)
                if (r(i) != 0.0) g.noalias() += (weight * sign(r(i))) * J_.row(i).transpose();
            at += static_cast<Eigen::Index>(n);
        }
    }
    if (!g.allFinite()) return std::numeric_limits<double>::infinity();
    return f;
}

}  // namespace tvid
