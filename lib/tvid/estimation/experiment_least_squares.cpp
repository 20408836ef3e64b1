#include "tvid/estimation/experiment_least_squares.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>

#include "tvid/estimation/parallel_evaluator.hpp"

namespace tvid {

namespace {

// The central-difference step for parameter j: ε^(1/3) of its magnitude (of the bound
// width, or 1, when it is zero), which balances truncation against rounding error.
double difference_step(double x, double lower, double upper) {
    double scale = std::abs(x);
    if (scale == 0.0) scale = std::isfinite(upper - lower) && upper - lower < 1e100 ? 1e-3 * (upper - lower) : 1.0;
    return 6e-6 * scale;
}

}  // namespace

std::size_t estimation_residual_count(const Experiment& experiment) {
    std::size_t n = 0;
    for (const Window& w : experiment.estimation) n += w.last - std::max(w.first, w.start + 1) + 1;
    return n * experiment.outputs.size();
}

ExperimentLeastSquares::ExperimentLeastSquares(const IdentificationProblem& problem, int threads, JacobianKind kind,
                                               const std::atomic<bool>* stop)
    : problem_(&problem), kind_(kind), sensitivity_(problem), threads_(resolve_thread_count(threads)),
      residual_count_(estimation_residual_count(problem.experiment())), stop_(stop) {
    for (int t = 0; t < threads_; ++t) {
        workspaces_.push_back(problem.make_workspace());
        workspaces_.back()->stop = stop;  // an interrupt ends the simulations in flight, not only the next ones
        if (kind_ == JacobianKind::sensitivity) {
            sensitivity_workspaces_.push_back(sensitivity_.make_workspace());
            sensitivity_workspaces_.back()->plain->stop = stop;
        }
    }
    const std::size_t m = problem.dimension();
    plus_.assign(m, std::vector<double>(residual_count_));
    minus_.assign(m, std::vector<double>(residual_count_));
    buffer_.reserve(residual_count_);
}

bool ExperimentLeastSquares::residuals(const double* x, double* r) {
    stopped_ = stop_requested();
    if (stopped_) return false;
    ++simulations_;
    last_valid_ = false;
    ProblemWorkspace& ws = *workspaces_[0];
    ws.shooting_guesses = guesses_;
    const bool ok = problem_->residuals(x, ws, buffer_, &last_starts_);
    ws.shooting_guesses.clear();
    if (!ok || buffer_.size() != residual_count_) {
        stopped_ = stop_requested();  // ended by the stop, or failed on its own
        return false;
    }
    std::copy(buffer_.begin(), buffer_.end(), r);
    last_point_.assign(x, x + problem_->dimension());
    last_valid_ = true;
    return true;
}

bool ExperimentLeastSquares::jacobian(const double* x, double* r, Eigen::MatrixXd& J) {
    const bool known = last_valid_ && std::equal(last_point_.begin(), last_point_.end(), x);
    if (known) {
        stopped_ = stop_requested();
        if (stopped_) return false;
        std::copy(buffer_.begin(), buffer_.end(), r);
    } else if (!residuals(x, r)) {
        return false;
    }
    keep_guesses();
    const bool ok = kind_ == JacobianKind::sensitivity ? sensitivity_jacobian(x, J) : finite_difference_jacobian(x, r, J);
    stopped_ = !ok && stop_requested();
    return ok;
}

void ExperimentLeastSquares::keep_guesses() {
    const std::vector<Window>& windows = problem_->experiment().estimation;
    guesses_.clear();
    for (std::size_t wi = 0; wi < last_starts_.size() && wi < windows.size(); ++wi)
        if (const WindowStart& s = last_starts_[wi].start; s.shot)
            guesses_.push_back({windows[wi].start, windows[wi].first, s.offset, s.speed, s.miss_jacobian});
}

bool ExperimentLeastSquares::sensitivity_jacobian(const double* x, Eigen::MatrixXd& J) {
    // Column blocks: one per thread with fixed-step RK4 (a column does not depend on its
    // block), otherwise blocks as large as the dual numbers carry.
    const std::size_t m = problem_->dimension();
    const bool fixed_step = problem_->experiment().simulation.method == IntegrationMethod::rk4;
    std::size_t blocks = (m + ForwardSensitivity::kMaxBlock - 1) / ForwardSensitivity::kMaxBlock;
    if (fixed_step) blocks = std::max(blocks, std::min(m, static_cast<std::size_t>(threads_)));
    const std::size_t width = (m + blocks - 1) / blocks;
    std::vector<char> ok(blocks, 1);
    const auto count = static_cast<long long>(blocks);
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads_)
    for (long long b = 0; b < count; ++b) {
        if (stop_requested()) {
            ok[static_cast<std::size_t>(b)] = 0;
            continue;
        }
        SensitivityWorkspace& ws = *sensitivity_workspaces_[static_cast<std::size_t>(omp_get_thread_num())];
        const std::size_t j0 = static_cast<std::size_t>(b) * width, j1 = std::min(m, j0 + width);
        ok[static_cast<std::size_t>(b)] = j0 >= j1 || sensitivity_.jacobian_columns(x, j0, j1, ws, J, &last_starts_) ? 1 : 0;
    }
    simulations_ += count;
    return std::all_of(ok.begin(), ok.end(), [](char c) { return c != 0; });
}

bool ExperimentLeastSquares::finite_difference_jacobian(const double* x, const double* r, Eigen::MatrixXd& J) {
    const std::size_t m = problem_->dimension();
    const std::vector<double>& lower = problem_->lower();
    const std::vector<double>& upper = problem_->upper();
    std::vector<double> step(m);
    std::vector<char> ok(m, 1);
    const auto columns = static_cast<long long>(m);
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads_)
    for (long long jj = 0; jj < columns; ++jj) {
        const auto j = static_cast<std::size_t>(jj);
        if (stop_requested()) {
            ok[j] = 0;
            continue;
        }
        ProblemWorkspace& ws = *workspaces_[static_cast<std::size_t>(omp_get_thread_num())];
        std::vector<double> point(x, x + m);
        const double h = difference_step(x[j], lower[j], upper[j]);
        // Stay inside the bounds: a one-sided difference when x sits on (or near) one.
        const double up = std::min(x[j] + h, upper[j]), down = std::max(x[j] - h, lower[j]);
        step[j] = up - down;
        point[j] = up;
        std::vector<double> out;
        ws.shooting_guesses = guesses_;  // the start solved at x: every column's guess, whichever thread runs it
        bool good = problem_->residuals(point.data(), ws, out) && out.size() == residual_count_;
        if (good) std::copy(out.begin(), out.end(), plus_[j].begin());
        point[j] = down;
        if (good && down != x[j]) {
            good = problem_->residuals(point.data(), ws, out) && out.size() == residual_count_;
            if (good) std::copy(out.begin(), out.end(), minus_[j].begin());
        } else if (good) {
            std::copy(r, r + residual_count_, minus_[j].begin());
        }
        ws.shooting_guesses.clear();
        ok[j] = good ? 1 : 0;
    }
    simulations_ += 2 * columns;
    for (std::size_t j = 0; j < m; ++j) {
        if (!ok[j] || !(step[j] > 0)) return false;
        for (std::size_t i = 0; i < residual_count_; ++i)
            J(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = (plus_[j][i] - minus_[j][i]) / step[j];
    }
    return true;
}

}  // namespace tvid
