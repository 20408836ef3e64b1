#pragma once
// An IdentificationProblem seen as nonlinear least squares for the Levenberg–Marquardt
// solver: the residuals y* − y of every scored sample of every estimation window and
// output (seed 000 eq. 7), and their Jacobian by central finite differences, its
// 2M perturbed simulations run in parallel on all cores. Each column is computed by one
// thread from its own inputs, so the Jacobian is the same for any thread count.

#include <memory>
#include <vector>

#include "tvid/estimation/identification_problem.hpp"
#include "tvid/optim/levenberg_marquardt.hpp"

namespace tvid {

class ExperimentLeastSquares : public LeastSquaresProblem {
public:
    /// threads <= 0: all hardware threads.
    ExperimentLeastSquares(const IdentificationProblem& problem, int threads);

    std::size_t residual_count() const override { return residual_count_; }
    bool residuals(const double* x, double* r) override;
    bool jacobian(const double* x, double* r, Eigen::MatrixXd& J) override;

    int threads() const { return threads_; }
    long long simulations() const { return simulations_; }  ///< simulations run so far

private:
    const IdentificationProblem* problem_;
    int threads_;
    std::size_t residual_count_ = 0;
    std::vector<std::unique_ptr<ProblemWorkspace>> workspaces_;
    std::vector<std::vector<double>> plus_, minus_;  ///< residuals at x ± h e_j, per column
    std::vector<double> buffer_;
    long long simulations_ = 0;
};

/// The number of residuals of the estimation windows (scored samples × outputs).
std::size_t estimation_residual_count(const Experiment& experiment);

}  // namespace tvid
