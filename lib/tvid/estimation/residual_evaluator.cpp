#include "tvid/estimation/residual_evaluator.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "tvid/estimation/parallel_evaluator.hpp"
#include "tvid/estimation/window_score.hpp"
#include "tvid/util/parallel_region.hpp"

namespace tvid {

std::size_t estimation_residual_count(const std::vector<Window>& windows, std::size_t outputs) {
    std::size_t n = 0;
    for (const Window& w : windows) n += scored_sample_count(w);
    return n * outputs;
}

std::size_t estimation_residual_count(const Experiment& experiment) {
    return estimation_residual_count(experiment.estimation, experiment.outputs.size());
}

ResidualEvaluator::ResidualEvaluator(const IdentificationProblem& problem, const EvaluatorOptions& options)
    : problem_(&problem), kind_(options.jacobian.value_or(problem.definition().jacobian)), sensitivity_(problem),
      threads_(options.most_threads()), budget_(options.budget),
      residual_count_(estimation_residual_count(problem.definition().estimation, problem.definition().measured.size())),
      stop_(options.stop) {
    for (int t = 0; t < threads_; ++t) {
        workspaces_.push_back(problem.make_workspace());
        workspaces_.back()->stop = stop_;  // an interrupt ends the simulations in flight, not only the next ones
        if (kind_ == JacobianKind::sensitivity) {
            sensitivity_workspaces_.push_back(sensitivity_.make_workspace());
            sensitivity_workspaces_.back()->plain->stop = stop_;
        }
    }
    const std::size_t m = problem.dimension();
    plus_.assign(m, std::vector<double>(residual_count_));
    minus_.assign(m, std::vector<double>(residual_count_));
    start_slopes_ = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(2 * problem.definition().estimation.size()),
                                          static_cast<Eigen::Index>(m));
    for (std::size_t j = 0; j < m; ++j) all_columns_.push_back(j);
    evaluated_.resize(static_cast<std::size_t>(threads_));
    for (EvaluatedPoint& e : evaluated_) e.residuals.reserve(residual_count_);
}

// x's residuals into evaluated_[record] with workspace ws, the shootings starting from
// the last Jacobian's solutions; false when the model fails there or a stop cut it short.
bool ResidualEvaluator::evaluate_into(std::size_t record, const double* x, ProblemWorkspace& ws) {
    EvaluatedPoint& e = evaluated_[record];
    e.valid = false;
    predict_guesses(x, ws.shooting_guesses);
    const bool ok = problem_->residuals(x, ws, e.residuals, &e.starts);
    ws.shooting_guesses.clear();
    if (!ok || e.residuals.size() != residual_count_) return false;
    e.point.assign(x, x + problem_->dimension());
    e.valid = true;
    return true;
}

const ResidualEvaluator::EvaluatedPoint* ResidualEvaluator::find_evaluated(const double* x) const {
    for (const EvaluatedPoint& e : evaluated_)
        if (e.valid && std::equal(e.point.begin(), e.point.end(), x)) return &e;
    return nullptr;
}

long long ResidualEvaluator::right_hand_sides() const {
    std::size_t total = 0;
    for (const auto& ws : workspaces_) total += ws->buffers.rhs_evaluations;
    for (const auto& ws : sensitivity_workspaces_) total += ws->buffers.rhs_evaluations + ws->plain->buffers.rhs_evaluations;
    return static_cast<long long>(total);
}

bool ResidualEvaluator::residuals(const double* x, double* r) {
    for (EvaluatedPoint& e : evaluated_) e.valid = false;
    stopped_ = stop_requested();
    if (stopped_) return false;
    ++simulations_;
    if (!evaluate_into(0, x, *workspaces_[0])) {
        stopped_ = stop_requested();  // ended by the stop, or failed on its own
        return false;
    }
    std::copy(evaluated_[0].residuals.begin(), evaluated_[0].residuals.end(), r);
    return true;
}

std::string ResidualEvaluator::failure(const double* x) {
    return problem_->failure(x, *workspaces_[0]);
}

void ResidualEvaluator::residuals_side_by_side(std::size_t count, const double* const* x, double* const* r,
                                                    char* ok, char* stopped) {
    if (count > evaluated_.size()) throw std::logic_error("ResidualEvaluator: more points side by side than threads");
    for (EvaluatedPoint& e : evaluated_) e.valid = false;
    const auto points = static_cast<long long>(count);
    FirstException errors;
    const int team = this->team();
#pragma omp parallel for schedule(static, 1) num_threads(team)
    for (long long kk = 0; kk < points; ++kk) try {
        const auto k = static_cast<std::size_t>(kk);
        ok[k] = !stop_requested() && evaluate_into(k, x[k], *workspaces_[static_cast<std::size_t>(omp_get_thread_num())]);
        if (ok[k]) std::copy(evaluated_[k].residuals.begin(), evaluated_[k].residuals.end(), r[k]);
    } catch (...) {
        errors.capture();
    }
    errors.rethrow();
    simulations_ += points;
    const bool stop = stop_requested();
    for (std::size_t k = 0; k < count; ++k) stopped[k] = !ok[k] && stop;
    stopped_ = count > 0 && stopped[0];
}

WindowSensitivity ResidualEvaluator::output_sensitivity(const double* x, const Window& w, int thread) {
    if (sensitivity_workspaces_.empty())
        throw std::logic_error("ResidualEvaluator: output sensitivities need JacobianKind::sensitivity");
    return sensitivity_.window_sensitivity(x, w, *sensitivity_workspaces_.at(static_cast<std::size_t>(thread)));
}

bool ResidualEvaluator::jacobian(const double* x, double* r, Eigen::MatrixXd& J) {
    const EvaluatedPoint* known = find_evaluated(x);
    if (known) {
        stopped_ = stop_requested();
        if (stopped_) return false;
        std::copy(known->residuals.begin(), known->residuals.end(), r);
    } else if (!residuals(x, r)) {
        return false;
    } else {
        known = &evaluated_[0];
    }
    keep_guesses(x, known->starts);
    const bool ok = kind_ == JacobianKind::sensitivity ? sensitivity_jacobian(x, r, known->starts, J)
                                                       : finite_difference_columns(x, r, all_columns_, J);
    stopped_ = !ok && stop_requested();
    return ok;
}

void ResidualEvaluator::keep_guesses(const double* x, const std::vector<SolvedStart>& starts) {
    const std::vector<Window>& windows = problem_->definition().estimation;
    guesses_.clear();
    guess_windows_.clear();
    for (std::size_t wi = 0; wi < starts.size() && wi < windows.size(); ++wi)
        if (const WindowStart& s = starts[wi].start; s.shot) {
            guesses_.push_back({windows[wi].start, windows[wi].first, s.offset, s.speed, s.miss_jacobian});
            guess_windows_.push_back(wi);
        }
    guess_point_.assign(x, x + problem_->dimension());
    slopes_valid_ = false;  // until the sensitivities at x are in
}

void ResidualEvaluator::predict_guesses(const double* x, std::vector<ShootingGuess>& out) const {
    out = guesses_;
    if (!slopes_valid_) return;
    for (std::size_t g = 0; g < out.size(); ++g) {
        const auto row = static_cast<Eigen::Index>(2 * guess_windows_[g]);
        double da = 0.0, ds = 0.0;
        for (std::size_t j = 0; j < guess_point_.size(); ++j) {
            const double dx = x[j] - guess_point_[j];
            da += start_slopes_(row, static_cast<Eigen::Index>(j)) * dx;
            ds += start_slopes_(row + 1, static_cast<Eigen::Index>(j)) * dx;
        }
        out[g].offset += da;
        out[g].speed += ds;
    }
}

bool ResidualEvaluator::sensitivity_jacobian(const double* x, const double* r,
                                                  const std::vector<SolvedStart>& starts, Eigen::MatrixXd& J) {
    // Column blocks: one per thread with fixed-step RK4 (a column does not depend on its
    // block), otherwise blocks as large as the dual numbers carry.
    const std::size_t m = problem_->dimension();
    const bool fixed_step = takes_fixed_steps(problem_->definition().simulation.method);
    std::size_t blocks = (m + ForwardSensitivity::kMaxBlock - 1) / ForwardSensitivity::kMaxBlock;
    const int team = this->team();
    if (fixed_step) blocks = std::max(blocks, std::min(m, static_cast<std::size_t>(team)));
    const std::size_t width = (m + blocks - 1) / blocks;
    std::vector<char> ok(blocks, 1);
    const auto count = static_cast<long long>(blocks);
    FirstException errors;
#pragma omp parallel for schedule(dynamic, 1) num_threads(team)
    for (long long b = 0; b < count; ++b) try {
        if (stop_requested()) {
            ok[static_cast<std::size_t>(b)] = 0;
            continue;
        }
        SensitivityWorkspace& ws = *sensitivity_workspaces_[static_cast<std::size_t>(omp_get_thread_num())];
        const std::size_t j0 = static_cast<std::size_t>(b) * width, j1 = std::min(m, j0 + width);
        ok[static_cast<std::size_t>(b)] =
            j0 >= j1 || sensitivity_.jacobian_columns(x, j0, j1, ws, J, &starts, &start_slopes_) ? 1 : 0;
    } catch (...) {
        errors.capture();
    }
    errors.rethrow();
    simulations_ += count;
    slopes_valid_ = std::all_of(ok.begin(), ok.end(), [](char c) { return c != 0; });
    if (!slopes_valid_ || problem_->input_delay_columns().empty()) return slopes_valid_;
    return finite_difference_columns(x, r, problem_->input_delay_columns(), J);
}

bool ResidualEvaluator::finite_difference_columns(const double* x, const double* r,
                                                       const std::vector<std::size_t>& which, Eigen::MatrixXd& J) {
    const std::size_t m = problem_->dimension();
    std::vector<double> step(m);
    std::vector<char> ok(m, 1);
    const auto columns = static_cast<long long>(which.size());
    FirstException errors;
    const int team = this->team();
#pragma omp parallel for schedule(dynamic, 1) num_threads(team)
    for (long long jj = 0; jj < columns; ++jj) try {
        const std::size_t j = which[static_cast<std::size_t>(jj)];
        if (stop_requested()) {
            ok[j] = 0;
            continue;
        }
        ProblemWorkspace& ws = *workspaces_[static_cast<std::size_t>(omp_get_thread_num())];
        std::vector<double> point(x, x + m);
        const auto [up, down] = problem_->difference_points(j, x[j]);
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
    } catch (...) {
        errors.capture();
    }
    errors.rethrow();
    simulations_ += 2 * columns;
    for (std::size_t j : which) {
        if (!ok[j] || !(step[j] > 0)) return false;
        for (std::size_t i = 0; i < residual_count_; ++i)
            J(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = (plus_[j][i] - minus_[j][i]) / step[j];
    }
    return true;
}

}  // namespace tvid
