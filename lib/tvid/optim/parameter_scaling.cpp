#include "tvid/optim/parameter_scaling.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace tvid {

namespace {

// A bound of this size or more (or infinite) is no bound.
constexpr double kUnbounded = 1e300;

bool log_scaled(ParameterScale s) { return s == ParameterScale::log; }

}  // namespace

ParameterScaling::ParameterScaling(std::vector<ParameterScale> scales, std::vector<double> lower,
                                   std::vector<double> upper)
    : scales_(std::move(scales)), lower_(std::move(lower)), upper_(std::move(upper)) {
    if (lower_.size() != scales_.size() || upper_.size() != scales_.size())
        throw std::invalid_argument("parameter scaling: one scale and two bounds per parameter");
    for (std::size_t j = 0; j < scales_.size(); ++j) {
        if (!log_scaled(scales_[j])) continue;
        linear_ = false;
        if (!(lower_[j] > 0.0))
            throw std::invalid_argument("parameter scaling: a log parameter needs a positive lower bound");
        if (!(upper_[j] < kUnbounded)) upper_[j] = std::numeric_limits<double>::infinity();
    }
}

double ParameterScaling::to_search(std::size_t j, double p) const { return log_scaled(scales_[j]) ? std::log(p) : p; }

double ParameterScaling::to_parameter(std::size_t j, double u) const {
    return log_scaled(scales_[j]) ? std::clamp(std::exp(u), lower_[j], upper_[j]) : u;
}

void ParameterScaling::to_search(const double* p, double* u) const {
    for (std::size_t j = 0; j < scales_.size(); ++j) u[j] = to_search(j, p[j]);
}

void ParameterScaling::to_parameters(const double* u, double* p) const {
    for (std::size_t j = 0; j < scales_.size(); ++j) p[j] = to_parameter(j, u[j]);
}

std::vector<double> ParameterScaling::to_search(const std::vector<double>& p) const {
    std::vector<double> u(p.size());
    to_search(p.data(), u.data());
    return u;
}

std::vector<double> ParameterScaling::to_parameters(const std::vector<double>& u) const {
    std::vector<double> p(u.size());
    to_parameters(u.data(), p.data());
    return p;
}

SearchBox ParameterScaling::to_search(const SearchBox& box) const {
    SearchBox out = box;
    const auto map = [&](std::vector<double>& v) {
        for (std::size_t j = 0; j < scales_.size() && j < v.size(); ++j)
            if (log_scaled(scales_[j]) && std::abs(v[j]) < kUnbounded) v[j] = std::log(v[j]);
    };
    map(out.lower);
    map(out.upper);
    map(out.range_lower);
    map(out.range_upper);
    return out;
}

void ParameterScaling::jacobian_to_search(const double* p, Eigen::MatrixXd& jacobian) const {
    for (std::size_t j = 0; j < scales_.size(); ++j)
        if (log_scaled(scales_[j])) jacobian.col(static_cast<Eigen::Index>(j)) *= p[j];
}

void ParameterScaling::jacobian_to_parameters(const double* p, Eigen::MatrixXd& jacobian) const {
    for (std::size_t j = 0; j < scales_.size(); ++j)
        if (log_scaled(scales_[j])) jacobian.col(static_cast<Eigen::Index>(j)) /= p[j];
}

void ParameterScaling::gradient_to_search(const double* p, double* gradient) const {
    for (std::size_t j = 0; j < scales_.size(); ++j)
        if (log_scaled(scales_[j])) gradient[j] *= p[j];
}

void ParameterScaling::map_point(std::vector<double>& point) const {
    if (point.size() == scales_.size()) to_parameters(point.data(), point.data());
}

ScaledLeastSquares::ScaledLeastSquares(LeastSquaresProblem& problem, ParameterScaling scaling)
    : problem_(&problem), scaling_(std::move(scaling)), p_(scaling_.dimension()) {}

ScaledLeastSquares::ScaledLeastSquares(std::unique_ptr<LeastSquaresProblem> owned, ParameterScaling scaling)
    : owned_(std::move(owned)), problem_(owned_.get()), scaling_(std::move(scaling)), p_(scaling_.dimension()) {}

bool ScaledLeastSquares::residuals(const double* u, double* r) {
    scaling_.to_parameters(u, p_.data());
    return problem_->residuals(p_.data(), r);
}

bool ScaledLeastSquares::jacobian(const double* u, double* r, Eigen::MatrixXd& J) {
    scaling_.to_parameters(u, p_.data());
    if (!problem_->jacobian(p_.data(), r, J)) return false;
    scaling_.jacobian_to_search(p_.data(), J);
    return true;
}

std::string ScaledLeastSquares::failure(const double* u) {
    scaling_.to_parameters(u, p_.data());
    return problem_->failure(p_.data());
}

void ScaledLeastSquares::residuals_side_by_side(std::size_t count, const double* const* u, double* const* r, char* ok,
                                                char* stopped) {
    if (side_by_side_.size() < count) side_by_side_.resize(count, std::vector<double>(scaling_.dimension()));
    side_by_side_points_.resize(count);
    for (std::size_t k = 0; k < count; ++k) {
        scaling_.to_parameters(u[k], side_by_side_[k].data());
        side_by_side_points_[k] = side_by_side_[k].data();
    }
    problem_->residuals_side_by_side(count, side_by_side_points_.data(), r, ok, stopped);
}

ScaledCandidateEvaluator::ScaledCandidateEvaluator(CandidateEvaluator& evaluator, ParameterScaling scaling)
    : evaluator_(&evaluator), scaling_(std::move(scaling)) {}

const double* ScaledCandidateEvaluator::to_parameters(const double* candidates, std::size_t count,
                                                      std::size_t dimension) {
    if (dimension != scaling_.dimension())
        throw std::invalid_argument("scaled candidates: the dimension differs from the scaling's");
    p_.resize(count * dimension);
    for (std::size_t i = 0; i < count; ++i) scaling_.to_parameters(candidates + i * dimension, p_.data() + i * dimension);
    return p_.data();
}

void ScaledCandidateEvaluator::evaluate(const double* candidates, std::size_t count, std::size_t dimension,
                                        double* costs) {
    evaluator_->evaluate(to_parameters(candidates, count, dimension), count, dimension, costs);
}

void ScaledCandidateEvaluator::evaluate_bounded(const double* candidates, std::size_t count, std::size_t dimension,
                                                const double* bounds, double* costs) {
    evaluator_->evaluate_bounded(to_parameters(candidates, count, dimension), count, dimension, bounds, costs);
}

ScaledCost::ScaledCost(DifferentiableCost& cost, ParameterScaling scaling)
    : cost_(&cost), scaling_(std::move(scaling)), p_(scaling_.dimension()) {}

double ScaledCost::value(const double* u) {
    scaling_.to_parameters(u, p_.data());
    return cost_->value(p_.data());
}

double ScaledCost::value_and_gradient(const double* u, double* gradient) {
    scaling_.to_parameters(u, p_.data());
    const double c = cost_->value_and_gradient(p_.data(), gradient);
    scaling_.gradient_to_search(p_.data(), gradient);
    return c;
}

}  // namespace tvid
