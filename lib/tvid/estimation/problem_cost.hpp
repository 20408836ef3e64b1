#pragma once
// The estimation cost of an IdentificationProblem as a DifferentiableCost for general
// minimizers (NLopt), with its gradient from the residuals' Jacobian (forward
// sensitivities, the methodology paper eq. 9, or finite differences, as `lm.jacobian` says):
//   l2: E = Σ e²                     ∇E = 2 Jᵀ e                          (the methodology paper eq. 7)
//   l1: E = Σ_windows mean_i Σ_k |e|  ∇E = Σ_windows (1/n_w) Σ sign(e) ∂e/∂p  (Yoshida & Takamatsu eq. 19)
// where n_w is the number of scored samples of window w (the rule of window_score.hpp,
// as IdentificationProblem::cost applies it). |e| has no derivative
// at e = 0: sign(0) = 0 gives the subgradient of least norm there.

#include <Eigen/Core>
#include <vector>

#include "tvid/estimation/residual_evaluator.hpp"
#include "tvid/optim/differentiable_cost.hpp"

namespace tvid {

class ProblemCost : public DifferentiableCost {
public:
    /// Its residuals' evaluator runs with `options` (the Jacobian's simulations in parallel).
    explicit ProblemCost(const IdentificationProblem& problem, const EvaluatorOptions& options = EvaluatorOptions());

    double value(const double* x) override;
    double value_and_gradient(const double* x, double* gradient) override;
    long long simulations() const override { return least_squares_.simulations(); }
    long long right_hand_sides() const override { return least_squares_.right_hand_sides(); }

    int threads() const { return least_squares_.threads(); }

    /// The cost of residuals laid out as IdentificationProblem::residuals gives them.
    double cost_of_residuals(const double* r) const;

private:
    ResidualEvaluator least_squares_;
    CostKind cost_;
    std::size_t outputs_;
    std::vector<std::size_t> window_samples_;  ///< scored samples per estimation window
    std::vector<double> r_;
    Eigen::MatrixXd J_;
};

}  // namespace tvid
