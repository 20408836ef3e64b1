#include "tvid/estimation/problem_cost.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "tvid/estimation/window_score.hpp"

namespace tvid {

namespace {
double sign(double e) { return e > 0 ? 1.0 : (e < 0 ? -1.0 : 0.0); }
}  // namespace

ProblemCost::ProblemCost(const IdentificationProblem& problem, const EvaluatorOptions& options)
    : least_squares_(problem, options),
      cost_(problem.definition().cost),
      outputs_(problem.definition().measured.size()) {
    for (const Window& w : problem.definition().estimation) window_samples_.push_back(scored_sample_count(w));
    r_.resize(least_squares_.residual_count());
    J_.resize(static_cast<Eigen::Index>(r_.size()), static_cast<Eigen::Index>(problem.dimension()));
}

double ProblemCost::cost_of_residuals(const double* r) const {
    double total = 0.0;
    std::size_t at = 0;
    for (const std::size_t samples : window_samples_) {
        WindowScore<double> window(cost_, samples);
        for (std::size_t i = at; i < at + samples * outputs_; ++i) window.add(r[i]);
        total = window.partial_cost(total);
        at += samples * outputs_;
    }
    return finished_cost(total);
}

double ProblemCost::value(const double* x) {
    if (!least_squares_.residuals(x, r_.data())) return std::numeric_limits<double>::infinity();
    return cost_of_residuals(r_.data());
}

double ProblemCost::value_and_gradient(const double* x, double* gradient) {
    if (!least_squares_.jacobian(x, r_.data(), J_)) return std::numeric_limits<double>::infinity();
    const double f = cost_of_residuals(r_.data());
    const auto m = J_.cols();
    Eigen::Map<Eigen::VectorXd> g(gradient, m);
    const Eigen::Map<const Eigen::VectorXd> r(r_.data(), static_cast<Eigen::Index>(r_.size()));
    if (cost_ == CostKind::l2) {
        g.noalias() = 2.0 * J_.transpose() * r;
    } else {
        g.setZero();
        Eigen::Index at = 0;
        for (const std::size_t samples : window_samples_) {
            const double weight = 1.0 / static_cast<double>(samples);
            const auto n = static_cast<Eigen::Index>(samples * outputs_);
            for (Eigen::Index i = at; i < at + n; ++i)
                if (r(i) != 0.0) g.noalias() += (weight * sign(r(i))) * J_.row(i).transpose();
            at += n;
        }
    }
    if (!g.allFinite()) return std::numeric_limits<double>::infinity();
    return f;
}

}  // namespace tvid
