#pragma once
// The coordinates an optimizer searches in: u_j = ln p_j for a parameter of scale log,
// u_j = p_j for a linear one (parameter_scale.hpp). The optimizers know nothing of it: they
// search in u over the box mapped to u, through adapters that hand the model p(u) and turn
// its derivatives into derivatives in u (∂r/∂u_j = p_j ∂r/∂p_j for a log parameter); their
// summaries are mapped back to p afterwards. With every parameter linear the mapping is a
// copy and the adapters pass every value through unchanged, bit for bit.

#include <Eigen/Core>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "tvid/optim/candidate_evaluator.hpp"
#include "tvid/optim/differentiable_cost.hpp"
#include "tvid/optim/levenberg_marquardt.hpp"
#include "tvid/optim/optimizer_summary.hpp"
#include "tvid/optim/parameter_scale.hpp"
#include "tvid/optim/pso.hpp"

namespace tvid {

class ParameterScaling {
public:
    /// No parameter (dimension 0).
    ParameterScaling() = default;
    /// One scale per parameter and the parameters' bounds (±1e300 or ±inf: none). Throws
    /// std::invalid_argument when the sizes differ or a log parameter's lower bound is not
    /// positive (its logarithm would leave the real numbers).
    ParameterScaling(std::vector<ParameterScale> scales, std::vector<double> lower, std::vector<double> upper);

    std::size_t dimension() const { return scales_.size(); }
    ParameterScale scale(std::size_t j) const { return scales_[j]; }
    /// True when every parameter is linear: the search coordinates are the parameters.
    bool linear() const { return linear_; }

    /// u of parameter value p (p > 0 for a log parameter).
    double to_search(std::size_t j, double p) const;
    /// p of search coordinate u; a log parameter's exp(u) is kept within its bounds, so that
    /// the image of a bound in u is the bound itself.
    double to_parameter(std::size_t j, double u) const;
    void to_search(const double* p, double* u) const;
    void to_parameters(const double* u, double* p) const;
    std::vector<double> to_search(const std::vector<double>& p) const;
    std::vector<double> to_parameters(const std::vector<double>& u) const;

    /// The box in search coordinates: bounds and range box mapped; an absent bound
    /// (±1e300 or ±inf) stays absent.
    SearchBox to_search(const SearchBox& box) const;

    /// ∂r/∂p (columns, at parameters p) into ∂r/∂u: column j times dp_j/du_j.
    void jacobian_to_search(const double* p, Eigen::MatrixXd& jacobian) const;
    /// ∂r/∂u (at parameters p) back into ∂r/∂p.
    void jacobian_to_parameters(const double* p, Eigen::MatrixXd& jacobian) const;
    /// A gradient ∂c/∂p at p into ∂c/∂u.
    void gradient_to_search(const double* p, double* gradient) const;

    /// A summary's best point, found in search coordinates, as parameters. Each optimizer's
    /// own file maps the rest of its summary (its starts, its first failure, LM's Jacobian
    /// at its best) with map_point and jacobian_to_parameters: to_parameters(scaling, summary).
    void best_to_parameters(OptimizerSummary& summary) const { map_point(summary.best); }
    /// u -> p in place, when the point has the dimension (an empty point stays empty).
    void map_point(std::vector<double>& point) const;

private:
    std::vector<ParameterScale> scales_;
    std::vector<double> lower_, upper_;
    bool linear_ = true;
};

/// A least-squares problem in parameters p seen in search coordinates u.
class ScaledLeastSquares : public LeastSquaresProblem {
public:
    ScaledLeastSquares(LeastSquaresProblem& problem, ParameterScaling scaling);
    ScaledLeastSquares(std::unique_ptr<LeastSquaresProblem> owned, ParameterScaling scaling);

    std::size_t residual_count() const override { return problem_->residual_count(); }
    bool residuals(const double* u, double* r) override;
    bool jacobian(const double* u, double* r, Eigen::MatrixXd& J) override;
    bool stopped() const override { return problem_->stopped(); }
    std::string failure(const double* u) override;
    int concurrent_residuals() const override { return problem_->concurrent_residuals(); }
    int max_concurrent_residuals() const override { return problem_->max_concurrent_residuals(); }
    void residuals_side_by_side(std::size_t count, const double* const* u, double* const* r, char* ok,
                                char* stopped) override;
    long long simulations() const override { return problem_->simulations(); }
    long long right_hand_sides() const override { return problem_->right_hand_sides(); }

private:
    std::unique_ptr<LeastSquaresProblem> owned_;
    LeastSquaresProblem* problem_;
    ParameterScaling scaling_;
    std::vector<double> p_;
    std::vector<std::vector<double>> side_by_side_;
    std::vector<const double*> side_by_side_points_;
};

/// A candidate evaluator of parameters p scoring candidates in search coordinates u.
class ScaledCandidateEvaluator : public CandidateEvaluator {
public:
    ScaledCandidateEvaluator(CandidateEvaluator& evaluator, ParameterScaling scaling);

    void evaluate(const double* candidates, std::size_t count, std::size_t dimension, double* costs) override;
    void evaluate_bounded(const double* candidates, std::size_t count, std::size_t dimension, const double* bounds,
                          double* costs) override;
    bool stopped() const override { return evaluator_->stopped(); }
    std::size_t right_hand_sides() const override { return evaluator_->right_hand_sides(); }

private:
    const double* to_parameters(const double* candidates, std::size_t count, std::size_t dimension);
    CandidateEvaluator* evaluator_;
    ParameterScaling scaling_;
    std::vector<double> p_;
};

/// A cost of parameters p and its gradient in search coordinates u.
class ScaledCost : public DifferentiableCost {
public:
    ScaledCost(DifferentiableCost& cost, ParameterScaling scaling);

    double value(const double* u) override;
    double value_and_gradient(const double* u, double* gradient) override;
    long long simulations() const override { return cost_->simulations(); }
    long long right_hand_sides() const override { return cost_->right_hand_sides(); }

private:
    DifferentiableCost* cost_;
    ParameterScaling scaling_;
    std::vector<double> p_;
};

}  // namespace tvid
