#include "tvid/analysis/uncertainty.hpp"

#include "tvid/estimation/residual_evaluator.hpp"
#include "tvid/analysis/input_noise.hpp"
#include "tvid/analysis/residual_whiteness.hpp"
#include "tvid/analysis/robust_covariance.hpp"
#include "tvid/estimation/window_score.hpp"

#include <Eigen/Dense>
#include <complex>
#include <unsupported/Eigen/FFT>
#include <algorithm>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <limits>

namespace tvid {

namespace {
// Singular values of the scaled Jacobian below this fraction of the largest count as zero
// (a condition number of JᵀJ above 1e12).
constexpr double kRankTolerance = 1e-6;
// The residuals at free_best (Σe² into ssr) and their Jacobian from the problem's one
// evaluator (every column kind: sensitivities, delays, differences) in scaled parameters
// into js; false with `problem_text` set when they cannot be computed.
bool scaled_jacobian(const IdentificationProblem& problem, const std::vector<double>& free_best,
                     const EvaluatorOptions& evaluators,
                     const std::vector<double>& scale, Eigen::MatrixXd& js, std::vector<double>& r, double& ssr,
                     std::string& problem_text) {
    const std::size_t m = problem.dimension();
    ResidualEvaluator evaluator(problem, evaluators);
    const std::size_t n = evaluator.residual_count();
    if (n <= m) { problem_text = "fewer residuals than free parameters"; return false; }
    r.assign(n, 0.0);
    js.resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(m));
    if (!evaluator.residuals(free_best.data(), r.data())) { problem_text = "the simulation at the optimum failed"; return false; }
    if (!evaluator.jacobian(free_best.data(), r.data(), js) || !js.allFinite()) {
        problem_text = "the Jacobian could not be formed at the optimum (a simulation near it failed)";
        return false;
    }
    for (std::size_t j = 0; j < m; ++j) js.col(static_cast<Eigen::Index>(j)) *= scale[j];
    ssr = 0.0;
    for (double e : r) ssr += e * e;
    return true;
}

// ‖r‖² projected on the columns of js of the parameters strictly inside their bounds: what a
// Gauss–Newton step that keeps the bound parameters where they are would remove from Σe².
double gauss_newton_decrease(const IdentificationProblem& problem, const std::vector<double>& free_best,
                             const Eigen::MatrixXd& js, const std::vector<double>& r) {
    std::vector<Eigen::Index> inside;
    for (std::size_t j = 0; j < free_best.size(); ++j) {
        const double lo = problem.lower()[j], hi = problem.upper()[j], width = hi - lo;
        const double margin = std::isfinite(width) ? 1e-9 * width : 0.0;
        if (free_best[j] > lo + margin && free_best[j] < hi - margin) inside.push_back(static_cast<Eigen::Index>(j));
    }
    if (inside.empty()) return 0.0;
    Eigen::MatrixXd a(js.rows(), static_cast<Eigen::Index>(inside.size()));
    for (std::size_t k = 0; k < inside.size(); ++k) a.col(static_cast<Eigen::Index>(k)) = js.col(inside[k]);
    const Eigen::Map<const Eigen::VectorXd> e(r.data(), static_cast<Eigen::Index>(r.size()));
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
    const Eigen::VectorXd step = qr.solve(e);  // the least-squares fit of r by the columns
    return (a * step).squaredNorm();
}

// The declared input noise carried to the residuals (analysis/input_noise.hpp), as the
// residual vector holds them: each output's scale and filter applied, window by window. Its
// covariance between samples and outputs, at lags up to twice its reach.
PropagatedInputNoise residual_input_noise(const IdentificationProblem& problem, const std::vector<double>& free_best,
                                          std::size_t rows, const InputNoiseResponses* known,
                                          const EvaluatorOptions& evaluators) {
    const ProblemDefinition& d = problem.definition();
    std::vector<const Window*> windows;
    for (const Window& w : d.estimation) windows.push_back(&w);
    InputNoiseResponses responses =
        known && !known->delta.empty()
            ? *known
            : input_noise_responses(problem, problem.full_parameters(free_best), windows, kInputNoiseDraws, evaluators.team());
    const std::size_t outputs = d.measured.size();
    std::vector<double> block;
    for (auto& draw : responses.delta) {
        std::size_t total = 0;
        for (std::size_t w = 0; w < windows.size(); ++w) {
            auto& y = draw[w];
            const std::size_t n = y.empty() ? 0 : y.front().size();
            if (n != scored_sample_count(*windows[w])) return {};  // not the residuals' rows
            total += n * outputs;
            block.assign(n * outputs, 0.0);
            for (std::size_t a = 0; a < outputs; ++a)
                for (std::size_t i = 0; i < n; ++i) block[i * outputs + a] = d.output_scale[a] * y[a][i];
            problem.filter_window_residuals(*windows[w], block.data(), 1, 0);
            for (std::size_t a = 0; a < outputs; ++a)
                for (std::size_t i = 0; i < n; ++i) y[a][i] = block[i * outputs + a];
        }
        if (total != rows) return {};
    }
    // Every lag up to half the shortest window: a slow mode's memory can be long.
    PropagatedInputNoise p = propagated_covariance(responses, outputs, std::numeric_limits<int>::max());
    return p;
}

// Jᵀ Σ J, window by window, with Σ between the residuals of scored samples t and s = t + d
// the covariance C(d) between outputs (C_ab(d) = E[δ_a(t) δ_b(t + d)], C(−d) = C(d)ᵀ), tapered
// by w_d = 1 up to `reach` and linearly to 0 at 2·reach, plus each output's white part on the
// diagonal at d = 0. By the DFT over at least n + 2·reach points (no lag wraps around):
// Σ_{t,s} x[t] c[s − t] y[s] = (1/N) Σ_f conj(X_f) conj(C_f) Y_f for real x, c, y.
Eigen::MatrixXd noise_model_meat(const Eigen::MatrixXd& js, const PropagatedInputNoise& noise,
                                 const std::vector<double>& white, const std::vector<std::size_t>& window_samples,
                                 std::size_t outputs, std::size_t reach) {
    using Complex = std::complex<double>;
    const auto m = static_cast<std::size_t>(js.cols());
    Eigen::MatrixXd meat = Eigen::MatrixXd::Zero(js.cols(), js.cols());
    const std::size_t last = std::min<std::size_t>(2 * reach, static_cast<std::size_t>(noise.lags));
    Eigen::FFT<double> fft;
    std::size_t offset = 0;
    for (const std::size_t n : window_samples) {
        std::size_t size = 16;
        while (size < n + last + 1) size *= 2;
        // The spectra of each output's Jacobian columns and of the tapered covariances.
        std::vector<std::vector<std::vector<Complex>>> columns(outputs, std::vector<std::vector<Complex>>(m));
        std::vector<double> x(size);
        for (std::size_t a = 0; a < outputs; ++a)
            for (std::size_t j = 0; j < m; ++j) {
                std::fill(x.begin(), x.end(), 0.0);
                for (std::size_t t = 0; t < n; ++t)
                    x[t] = js(static_cast<Eigen::Index>((offset + t) * outputs + a), static_cast<Eigen::Index>(j));
                fft.fwd(columns[a][j], x);
            }
        std::vector<std::vector<std::vector<Complex>>> spectrum(outputs, std::vector<std::vector<Complex>>(outputs));
        for (std::size_t a = 0; a < outputs; ++a)
            for (std::size_t b = 0; b < outputs; ++b) {
                std::fill(x.begin(), x.end(), 0.0);
                for (std::size_t d = 0; d <= last && d < n; ++d) {
                    const double w = d <= reach ? 1.0 : static_cast<double>(2 * reach - d) / static_cast<double>(reach);
                    x[d] = w * noise.covariance[a][b][d];               // s = t + d
                    if (d > 0) x[size - d] = w * noise.covariance[b][a][d];  // s = t − d
                }
                if (a == b) x[0] += white[a];
                fft.fwd(spectrum[a][b], x);
            }
        for (std::size_t i = 0; i < m; ++i)
            for (std::size_t j = i; j < m; ++j) {
                Complex sum = 0.0;
                for (std::size_t a = 0; a < outputs; ++a)
                    for (std::size_t b = 0; b < outputs; ++b) {
                        const std::vector<Complex>&xa = columns[a][i], &yb = columns[b][j], &c = spectrum[a][b];
                        for (std::size_t f = 0; f < size; ++f) sum += std::conj(xa[f] * c[f]) * yb[f];
                    }
                const double v = sum.real() / static_cast<double>(size);
                meat(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) += v;
                if (j != i) meat(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(i)) += v;
            }
        offset += n;
    }
    return meat;
}

// The scaled Jacobian's null directions into u (rank, condition number, null_directions);
// per parameter, whether it takes part in one.
std::vector<bool> null_directions(const Eigen::VectorXd& sv, const Eigen::MatrixXd& v, ParameterUncertainty& u) {
    const auto m = static_cast<std::size_t>(v.rows());
    const double smax = sv[0];
    u.rank = 0;
    for (Eigen::Index k = 0; k < sv.size(); ++k)
        if (sv[k] > kRankTolerance * smax) ++u.rank;
    const double smin = sv[sv.size() - 1];
    u.condition_number = u.rank == static_cast<int>(m) ? (smax / smin) * (smax / smin) : std::numeric_limits<double>::infinity();
    std::vector<bool> in_null(m, false);
    for (Eigen::Index k = u.rank; k < sv.size(); ++k) {
        std::vector<double> dir(m);
        // Signed so that the first component of at least half the largest magnitude is
        // positive: a choice that near-equal components (a scaling symmetry) do not flip.
        const double largest = v.col(k).cwiseAbs().maxCoeff();
        Eigen::Index lead = 0;
        while (std::abs(v(lead, k)) < 0.5 * largest) ++lead;
        const double sign = v(lead, k) < 0 ? -1.0 : 1.0;
        for (std::size_t j = 0; j < m; ++j) {
            dir[j] = sign * v(static_cast<Eigen::Index>(j), k);
            if (std::abs(dir[j]) > kNullDirectionComponent) in_null[j] = true;
        }
        u.null_directions.push_back(dir);
    }
    return in_null;
}

// With a declared input noise: the covariance of the scaled parameters by the sandwich
// bread·Jᵀ Σ J·bread with the noise model's Σ (each output's white part: its residual
// variance less the carried noise's); false, and nothing set, when it cannot be formed.
bool noise_model_covariance(const IdentificationProblem& problem, const std::vector<double>& free_best,
                            const JacobianAtOptimum& known, const EvaluatorOptions& evaluators, const Eigen::MatrixXd& js,
                            const std::vector<double>& r, const Eigen::MatrixXd& bread,
                            const std::vector<std::size_t>& window_samples, double dof, ParameterUncertainty& u,
                            Eigen::MatrixXd& cov) {
    const std::size_t outputs = problem.definition().measured.size();
    if (!declares_input_noise(problem.definition()) || r.size() != static_cast<std::size_t>(js.rows()) || outputs == 0)
        return false;
    const PropagatedInputNoise noise = residual_input_noise(problem, free_best, r.size(), known.input_noise, evaluators);
    if (!noise.available) return false;
    const double n = static_cast<double>(r.size());
    std::vector<double> white(outputs, 0.0);
    for (std::size_t i = 0; i < r.size(); ++i) white[i % outputs] += r[i] * r[i];
    const double per_output = static_cast<double>(r.size() / outputs);
    for (std::size_t a = 0; a < outputs; ++a) {
        const double variance = white[a] / per_output * (n / dof);
        white[a] = std::max(variance - noise.covariance[a][a][0], kWhiteShareFloor * variance);
        const double scale_a = problem.definition().output_scale[a];
        u.propagated_noise_rms.push_back(scale_a != 0.0 ? noise.rms(a) / std::abs(scale_a) : noise.rms(a));
    }
    u.input_noise = true;
    u.input_noise_lags = static_cast<std::size_t>(noise.correlation_lags);
    const Eigen::MatrixXd meat = noise_model_meat(js, noise, white, window_samples, outputs, u.input_noise_lags);
    cov = bread.lazyProduct(meat).lazyProduct(bread);  // unthreaded products: the same bits on any thread count
    return true;
}

// Standard errors, intervals, correlations and covariance from `cov`, the covariance of the
// scaled parameters, for the parameters outside every null direction.
void fill_errors(const IdentificationProblem& problem, const std::vector<double>& free_best,
                 const std::vector<double>& scale, const std::vector<bool>& in_null, const Eigen::MatrixXd& cov,
                 double dof, ParameterUncertainty& u) {
    const std::size_t m = free_best.size();
    const boost::math::students_t t_dist(dof);
    const double t975 = boost::math::quantile(t_dist, 0.975);
    for (std::size_t j = 0; j < m; ++j) {
        u.determined[j] = !in_null[j];
        if (!u.determined[j]) continue;
        const auto jj = static_cast<Eigen::Index>(j);
        const double sigma = std::sqrt(std::max(cov(jj, jj), 0.0));
        u.std_error[j] = scale[j] * sigma;
        if (problem.scales()[j] == ParameterScale::log && free_best[j] > 0) {
            // A log-scaled parameter's scaled column is ∂r/∂ln p: the interval is symmetric in
            // ln p, so p·exp(∓t·σ), asymmetric in p and positive.
            u.ci_low[j] = free_best[j] * std::exp(-t975 * sigma);
            u.ci_high[j] = free_best[j] * std::exp(t975 * sigma);
            continue;
        }
        u.ci_low[j] = free_best[j] - t975 * u.std_error[j];
        u.ci_high[j] = free_best[j] + t975 * u.std_error[j];
    }
    for (std::size_t a = 0; a < m; ++a)
        for (std::size_t b = 0; b < m; ++b) {
            if (!u.determined[a] || !u.determined[b]) continue;
            const auto ia = static_cast<Eigen::Index>(a), ib = static_cast<Eigen::Index>(b);
            u.correlation[a][b] = cov(ia, ib) / std::sqrt(cov(ia, ia) * cov(ib, ib));
            u.covariance[a][b] = scale[a] * scale[b] * cov(ia, ib);
        }
}

// The sandwich bread·S·bread with S the Newey–West long-run covariance of the scores, scaled
// by N/(N − M) as s² is; with a declared input noise, at least std_error: Newey–West's few
// lags miss a memory as long as the one a vehicle's inertia gives its speed's noise.
void fill_robust_errors(const Eigen::MatrixXd& js, const std::vector<double>& r, const Eigen::MatrixXd& bread,
                        const std::vector<double>& scale, std::size_t outputs,
                        const std::vector<std::size_t>& window_samples, double dof, ParameterUncertainty& u) {
    const std::size_t m = scale.size();
    const auto n = js.rows();
    u.robust_std_error.assign(m, std::numeric_limits<double>::quiet_NaN());
    if (r.size() != static_cast<std::size_t>(n) || n == 0) return;
    const Eigen::MatrixXd meat =
        long_run_score_covariance(js, r, outputs, window_samples, u.robust_lags) * (static_cast<double>(n) / dof);
    const Eigen::MatrixXd sandwich = bread.lazyProduct(meat).lazyProduct(bread);  // the same bits on any thread count
    for (std::size_t j = 0; j < m; ++j) {
        if (!u.determined[j]) continue;
        const auto jj = static_cast<Eigen::Index>(j);
        u.robust_std_error[j] = scale[j] * std::sqrt(std::max(sandwich(jj, jj), 0.0));
        if (u.input_noise) u.robust_std_error[j] = std::max(u.robust_std_error[j], u.std_error[j]);
    }
}

}  // namespace

ParameterUncertainty estimate_uncertainty(const IdentificationProblem& problem, const std::vector<double>& free_best,
                                          const JacobianAtOptimum& known, const EvaluatorOptions& evaluators) {
    ParameterUncertainty u;
    const std::size_t m = problem.dimension();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    u.std_error.assign(m, nan);
    u.ci_low.assign(m, nan);
    u.ci_high.assign(m, nan);
    u.determined.assign(m, false);
    u.correlation.assign(m, std::vector<double>(m, nan));
    u.covariance.assign(m, std::vector<double>(m, nan));
    u.interval.assign(m, "two-sided");
    if (m == 0) { u.problem = "no free parameters"; return u; }

    // The Jacobian in scaled parameters: column j = s_j ∂r/∂p_j, from the evaluator the
    // least-squares fit used (given) or from a new one.
    std::vector<double> scale(m);
    for (std::size_t j = 0; j < m; ++j) scale[j] = free_best[j] != 0.0 ? std::abs(free_best[j]) : 1.0;
    // An estimated start's correction (near 0 by design): at the scale of its coordinate.
    for (std::size_t j = 0; j < m; ++j)
        if (const double s = problem.start_scale(j); s > 0) scale[j] = std::max(std::abs(free_best[j]), s);
    u.column_scale = scale;
    const Eigen::MatrixXd* given = known.jacobian;
    const bool use_given = given && given->cols() == static_cast<Eigen::Index>(m) &&
                           given->rows() > static_cast<Eigen::Index>(m) && given->allFinite() &&
                           std::isfinite(known.sum_of_squares);
    Eigen::MatrixXd js;
    double ssr = 0.0;
    std::vector<double> r;
    if (use_given) {
        js = *given;
        ssr = known.sum_of_squares;
        for (std::size_t j = 0; j < m; ++j) js.col(static_cast<Eigen::Index>(j)) *= scale[j];
        // The residuals themselves, for the robust standard errors: one simulation.
        ResidualEvaluator evaluator(problem, evaluators);
        r.assign(evaluator.residual_count(), 0.0);
        if (r.size() != static_cast<std::size_t>(js.rows()) || !evaluator.residuals(free_best.data(), r.data())) r.clear();
    } else {
        if (!scaled_jacobian(problem, free_best, evaluators, scale, js, r, ssr, u.problem)) return u;
        u.gauss_newton_decrease = gauss_newton_decrease(problem, free_best, js, r);
    }
    u.sum_of_squares = ssr;
    const auto n = js.rows();
    u.residuals = static_cast<std::size_t>(n);
    const double dof = static_cast<double>(n) - static_cast<double>(m);

    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(js, Eigen::ComputeThinV);
    const Eigen::VectorXd& sv = svd.singularValues();
    const Eigen::MatrixXd& v = svd.matrixV();
    if (!(sv.size() > 0 && sv[0] > 0.0)) { u.problem = "the output does not depend on any free parameter"; return u; }
    u.available = true;
    const std::vector<bool> in_null = null_directions(sv, v, u);

    // The covariance of the scaled parameters on the determined subspace: s² V Σ⁻² Vᵀ, or with
    // a declared input noise the noise model's sandwich; bread = (JᵀJ)⁺ = V Σ⁻² Vᵀ.
    Eigen::MatrixXd bread = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(m), static_cast<Eigen::Index>(m));
    for (Eigen::Index k = 0; k < u.rank; ++k) bread += v.col(k) * v.col(k).transpose() / (sv[k] * sv[k]);
    std::vector<std::size_t> window_samples;
    for (const Window& w : problem.definition().estimation) window_samples.push_back(scored_sample_count(w));
    Eigen::MatrixXd cov;
    if (!noise_model_covariance(problem, free_best, known, evaluators, js, r, bread, window_samples, dof, u, cov)) {
        // s² V Σ⁻² Vᵀ, summed term by term (as the reports have always been computed, to the last bit).
        const double s2 = ssr / dof;
        cov = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(m), static_cast<Eigen::Index>(m));
        for (Eigen::Index k = 0; k < u.rank; ++k) cov += (s2 / (sv[k] * sv[k])) * v.col(k) * v.col(k).transpose();
    }
    fill_errors(problem, free_best, scale, in_null, cov, dof, u);
    fill_robust_errors(js, r, bread, scale, problem.definition().measured.size(), window_samples, dof, u);
    return u;
}

}  // namespace tvid
