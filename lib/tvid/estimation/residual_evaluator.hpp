#pragma once
// The one evaluator of an IdentificationProblem's residuals and their Jacobian (after Ceres'
// Evaluator, which its solver and its Covariance share): the residuals f·(y − y*) of every
// scored sample of every estimation window and output (output_residual, window_score.hpp;
// the methodology paper eq. 7) at a free-parameter vector, and their Jacobian ∂r/∂p with
// every kind of column:
//  - a model quantity, an output's gain or offset: forward sensitivities (the methodology
//    paper eq. 9; the free parameters split into column blocks, one augmented simulation
//    each, run in parallel), the start's own dependence included (forward_sensitivity.hpp);
//  - an output's delay: the recording's slope (forward_sensitivity.cpp);
//  - an input's delay, which the model's inputs carry no derivative for: central
//    differences;
//  - or every column by central differences (`lm.jacobian: fd`), with the one step rule of
//    difference_step.hpp.
// Levenberg–Marquardt minimizes through it, NLopt's gradient (ProblemCost) and the
// uncertainty after any optimizer (analysis/uncertainty.hpp, and so identifiability, the
// verdict and `tvid profile`) take their Jacobian from it, and `tvid sensitivity` its
// outputs' derivatives (output_sensitivity).
// Each column is computed from its own inputs, so the Jacobian is the same for any thread
// count (with an adaptive integrator the sensitivity blocks are fixed, not per thread,
// because the step control sees the whole block). Given a stop flag, an evaluation
// started after it is set returns false at once, one in flight ends at its simulations'
// next sample, and stopped() says why.

#include <atomic>
#include <memory>
#include <vector>

#include "tvid/estimation/evaluator_options.hpp"
#include "tvid/estimation/forward_sensitivity.hpp"
#include "tvid/estimation/identification_problem.hpp"
#include "tvid/optim/levenberg_marquardt.hpp"
#include "tvid/util/thread_budget.hpp"

namespace tvid {

class ResidualEvaluator : public LeastSquaresProblem {
public:
    /// Its threads, share of a batch's cores, Jacobian kind (unset: the problem's) and stop
    /// request from `options` (estimation/evaluator_options.hpp).
    explicit ResidualEvaluator(const IdentificationProblem& problem, const EvaluatorOptions& options = EvaluatorOptions());

    std::size_t residual_count() const override { return residual_count_; }
    bool residuals(const double* x, double* r) override;
    bool jacobian(const double* x, double* r, Eigen::MatrixXd& J) override;
    bool stopped() const override { return stopped_; }
    std::string failure(const double* x) override;
    /// As many as there are threads, one per thread, each with its own workspace.
    int concurrent_residuals() const override { return team(); }
    int max_concurrent_residuals() const override { return threads_; }
    void residuals_side_by_side(std::size_t count, const double* const* x, double* const* r, char* ok,
                                char* stopped) override;

    /// Window w's outputs and their derivatives ∂y/∂p for every free parameter, by the
    /// Jacobian's own column rules (`tvid sensitivity`: any window, validation too), on
    /// workspace `thread` (0 … threads() − 1, one per concurrent caller). Needs
    /// JacobianKind::sensitivity.
    WindowSensitivity output_sensitivity(const double* x, const Window& w, int thread);

    int threads() const { return threads_; }
    /// The threads of the next parallel region: threads(), or the budget's share of them.
    int team() const { return budget_ ? std::min(threads_, budget_->team()) : threads_; }
    JacobianKind jacobian_kind() const { return kind_; }
    long long simulations() const override { return simulations_; }  ///< simulations run so far
    long long right_hand_sides() const override;

private:
    // Columns `columns` of J by central differences (one-sided on a bound); r: the residuals at x.
    bool finite_difference_columns(const double* x, const double* r, const std::vector<std::size_t>& columns,
                                   Eigen::MatrixXd& J);
    // J from the forward sensitivities; an input's delay column, which the model's inputs
    // carry no derivative for, by central differences.
    bool sensitivity_jacobian(const double* x, const double* r, const std::vector<SolvedStart>& starts,
                              Eigen::MatrixXd& J);

    const IdentificationProblem* problem_;
    JacobianKind kind_;
    ForwardSensitivity sensitivity_;
    std::vector<std::unique_ptr<SensitivityWorkspace>> sensitivity_workspaces_;
    int threads_;
    const ThreadBudget* budget_ = nullptr;
    std::size_t residual_count_ = 0;
    std::vector<std::unique_ptr<ProblemWorkspace>> workspaces_;
    std::vector<std::vector<double>> plus_, minus_;  ///< residuals at x ± h e_j, per column
    std::vector<std::size_t> all_columns_;          ///< 0 … m − 1
    // The last residuals computed and where, one record per thread for the evaluations side
    // by side: a Jacobian asked for at one of these points (LM asks for it after accepting
    // the trial point just evaluated) reuses its residuals and the windows' solved starts
    // instead of simulating them again.
    struct EvaluatedPoint {
        std::vector<double> point, residuals;
        std::vector<SolvedStart> starts;
        bool valid = false;
    };
    std::vector<EvaluatedPoint> evaluated_;
    bool evaluate_into(std::size_t record, const double* x, ProblemWorkspace& ws);
    const EvaluatedPoint* find_evaluated(const double* x) const;
    // The warm-up shootings' solutions at the point of the last Jacobian: the first guesses
    // of the shootings at the next points (the solver's trial steps and the difference
    // columns), which lie near it. Set only by jacobian(), so they depend on the solver's
    // path alone, never on which thread evaluated what.
    std::vector<ShootingGuess> guesses_;
    // With sensitivities, also d(a, s)/dp of each window's solution there (rows 2w and 2w + 1)
    // and that point: a guess for point x is the first-order prediction
    // (a, s) + d(a, s)/dp · (x − guess_point_), which a step of LM leaves closer to the
    // solution than the Jacobian point's own (the miss then starts quadratic in the step).
    Eigen::MatrixXd start_slopes_;
    std::vector<std::size_t> guess_windows_;  ///< each guess's estimation window
    std::vector<double> guess_point_;
    bool slopes_valid_ = false;
    void predict_guesses(const double* x, std::vector<ShootingGuess>& out) const;
    void keep_guesses(const double* x, const std::vector<SolvedStart>& starts);
    long long simulations_ = 0;
    const std::atomic<bool>* stop_ = nullptr;
    bool stopped_ = false;
    bool stop_requested() const { return stop_ && stop_->load(std::memory_order_relaxed); }
};

/// The number of residuals of the estimation windows (scored samples × outputs).
std::size_t estimation_residual_count(const std::vector<Window>& windows, std::size_t outputs);
std::size_t estimation_residual_count(const Experiment& experiment);

}  // namespace tvid
