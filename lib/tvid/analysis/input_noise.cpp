#include "tvid/analysis/input_noise.hpp"

#include <omp.h>

#include <algorithm>
#include <complex>
#include <unsupported/Eigen/FFT>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <thread>

#include "tvid/channels/channel_delay.hpp"
#include "tvid/util/parallel_region.hpp"

namespace tvid {

namespace {

constexpr std::uint64_t kNoiseSeed = 0x7476'6964'6e6f'6973ULL;  // a fixed seed: the same draws in every run

// Standard normal numbers from a generator whose sequence the standard fixes (mt19937_64),
// by Box and Muller: the same on every library, unlike std::normal_distribution.
class NormalDraws {
public:
    explicit NormalDraws(std::uint64_t seed) : engine_(seed) {}
    double next() {
        if (has_spare_) {
            has_spare_ = false;
            return spare_;
        }
        const double u1 = (static_cast<double>(engine_() >> 11) + 0.5) * 0x1.0p-53;  // in (0, 1)
        const double u2 = static_cast<double>(engine_() >> 11) * 0x1.0p-53;
        const double radius = std::sqrt(-2.0 * std::log(u1)), angle = 2.0 * std::numbers::pi * u2;
        spare_ = radius * std::sin(angle);
        has_spare_ = true;
        return radius * std::cos(angle);
    }

private:
    std::mt19937_64 engine_;
    double spare_ = 0.0;
    bool has_spare_ = false;
};

// The inputs of ws shifted by ±σ z (sign `sign`) on every noisy input, a rate following its input.
void perturb_inputs(const ProblemDefinition& d, const std::vector<std::vector<double>>& base,
                    const std::vector<std::vector<double>>& z, double sign, ProblemWorkspace& ws) {
    const std::vector<double>& time = d.inputs.time();
    std::vector<double> values;
    for (std::size_t k = 0; k < base.size(); ++k) {
        if (z[k].empty()) continue;
        values = base[k];
        for (std::size_t i = 0; i < values.size(); ++i) values[i] += sign * d.input_noise[k] * z[k][i];
        ws.shifted_inputs.set_channel(k, values);
        const std::vector<int>& rates = d.network.input_rates;
        for (std::size_t j = 0; j < rates.size(); ++j)
            if (static_cast<std::size_t>(rates[j]) == k)
                ws.shifted_inputs.set_channel(d.network.input_names.size() + j, sample_slopes(values, time, d.recordings));
    }
}

// One draw's figures: δy per window, output and scored sample, and per noisy input, output
// and lag τ the sum of n(t) δ(t + τ) over the pairs of scored samples, and the pairs per lag.
struct DrawResult {
    bool ok = false;
    std::vector<std::vector<std::vector<double>>> delta;
    std::vector<std::vector<std::vector<double>>> cross;
    std::vector<double> pairs;
};

// One draw; ok false when a simulation failed.
void one_draw(const IdentificationProblem& problem, const std::vector<double>& params,
              const std::vector<const Window*>& windows, int draw, ProblemWorkspace& ws, DrawResult& result) {
    std::vector<std::vector<std::vector<double>>>& delta = result.delta;
    const ProblemDefinition& d = problem.definition();
    problem.use_parameters(params, ws);
    if (ws.inputs != &ws.shifted_inputs) {  // a copy of the channels to perturb
        ws.shifted_inputs = *ws.inputs;
        ws.inputs = &ws.shifted_inputs;
    }
    const std::size_t samples = d.inputs.samples();
    std::vector<std::vector<double>> base(d.input_noise.size()), z(d.input_noise.size());
    for (std::size_t k = 0; k < d.input_noise.size(); ++k) {
        if (!(d.input_noise[k] > 0)) continue;
        NormalDraws normal(kNoiseSeed + 1000003ULL * static_cast<std::uint64_t>(draw) + k);
        base[k].resize(samples);
        z[k].resize(samples);
        for (std::size_t i = 0; i < samples; ++i) {
            base[k][i] = ws.shifted_inputs.value(k, i);
            z[k][i] = normal.next();
        }
    }
    delta.assign(windows.size(), {});
    const std::size_t outputs = d.measured.size(), lags = kCrossCovarianceLags;
    result.cross.assign(base.size(), {});
    for (std::size_t k = 0; k < base.size(); ++k)
        if (!z[k].empty() && k < d.network.input_names.size())
            result.cross[k].assign(outputs, std::vector<double>(lags + 1, 0.0));
    result.pairs.assign(lags + 1, 0.0);
    bool ok = true;
    for (const double sign : {1.0, -1.0}) {
        perturb_inputs(d, base, z, sign, ws);
        for (std::size_t w = 0; w < windows.size() && ok; ++w) {
            const WindowTrace tr = problem.trace(params, *windows[w], ws);
            if (tr.status != SimulationStatus::ok) { ok = false; break; }
            if (sign > 0) {
                delta[w] = tr.simulated;
                continue;
            }
            for (std::size_t a = 0; a < tr.simulated.size(); ++a)
                for (std::size_t i = 0; i < tr.simulated[a].size(); ++i)
                    delta[w][a][i] = 0.5 * (delta[w][a][i] - tr.simulated[a][i]);
            const std::size_t n = tr.samples.size();
            for (std::size_t tau = 0; tau <= lags && tau < n; ++tau) result.pairs[tau] += static_cast<double>(n - tau);
            for (std::size_t k = 0; k < result.cross.size(); ++k)
                for (std::size_t a = 0; a < result.cross[k].size(); ++a)
                    for (std::size_t tau = 0; tau <= lags && tau < n; ++tau) {
                        double sum = 0.0;
                        for (std::size_t i = 0; i + tau < n; ++i) sum += z[k][tr.samples[i]] * delta[w][a][i + tau];
                        result.cross[k][a][tau] += d.input_noise[k] * sum;
                    }
        }
    }
    perturb_inputs(d, base, z, 0.0, ws);  // the workspace's channels back as the parameters read them
    result.ok = ok;
}

}  // namespace

bool declares_input_noise(const ProblemDefinition& d) {
    return std::any_of(d.input_noise.begin(), d.input_noise.end(), [](double s) { return s > 0; });
}

InputNoiseResponses input_noise_responses(const IdentificationProblem& problem, const std::vector<double>& params,
                                          const std::vector<const Window*>& windows, int draws, int threads) {
    InputNoiseResponses out;
    if (!declares_input_noise(problem.definition()) || draws <= 0) return out;
    if (threads <= 0) threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
    threads = std::min(threads, draws);
    std::vector<DrawResult> results(static_cast<std::size_t>(draws));
    std::vector<std::unique_ptr<ProblemWorkspace>> workspaces;
    for (int t = 0; t < threads; ++t) workspaces.push_back(problem.make_workspace());
    FirstException errors;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (int r = 0; r < draws; ++r) try {
        const auto k = static_cast<std::size_t>(r);
        one_draw(problem, params, windows, r, *workspaces[static_cast<std::size_t>(omp_get_thread_num())], results[k]);
    } catch (...) {
        errors.capture();
    }
    errors.rethrow();
    std::vector<double> pairs;
    for (DrawResult& r : results) {  // in draw order: the same on any thread count
        if (!r.ok) {
            ++out.failed_draws;
            continue;
        }
        out.delta.push_back(std::move(r.delta));
        if (out.input_cross.empty()) {
            out.input_cross = r.cross;
            pairs = r.pairs;
            continue;
        }
        for (std::size_t k = 0; k < r.cross.size(); ++k)
            for (std::size_t a = 0; a < r.cross[k].size(); ++a)
                for (std::size_t tau = 0; tau < r.cross[k][a].size(); ++tau) out.input_cross[k][a][tau] += r.cross[k][a][tau];
        for (std::size_t tau = 0; tau < pairs.size(); ++tau) pairs[tau] += r.pairs[tau];
    }
    for (auto& input : out.input_cross)
        for (auto& output : input)
            for (std::size_t tau = 0; tau < output.size(); ++tau) output[tau] = pairs[tau] > 0 ? output[tau] / pairs[tau] : 0.0;
    return out;
}

double PropagatedInputNoise::rms(std::size_t a) const {
    return a < covariance.size() && !covariance[a][a].empty() ? std::sqrt(std::max(covariance[a][a][0], 0.0)) : 0.0;
}

PropagatedInputNoise propagated_covariance(const InputNoiseResponses& responses, std::size_t outputs, int lags) {
    PropagatedInputNoise p;
    if (responses.delta.empty() || outputs == 0) return p;
    std::size_t shortest = std::numeric_limits<std::size_t>::max();
    for (const auto& window : responses.delta.front())
        if (!window.empty()) shortest = std::min(shortest, window.front().size());
    if (shortest == std::numeric_limits<std::size_t>::max() || shortest < 2) return p;
    p.lags = std::max(0, std::min(lags, static_cast<int>(shortest / 2)));
    p.draws = static_cast<int>(responses.delta.size());
    const auto L = static_cast<std::size_t>(p.lags);
    std::vector<std::vector<std::vector<double>>> sum(outputs, std::vector<std::vector<double>>(outputs, std::vector<double>(L + 1, 0.0)));
    std::vector<double> pairs(L + 1, 0.0);
    // Σ_t δ_a(t) δ_b(t + l) for every lag at once: the inverse DFT of conj(D_a) D_b, over at
    // least n + L points (no lag wraps around).
    Eigen::FFT<double> fft;
    std::vector<std::vector<std::complex<double>>> spectra(outputs);
    std::vector<std::complex<double>> product;
    std::vector<double> padded, lagged;
    for (const auto& draw : responses.delta)
        for (const auto& window : draw) {
            if (window.size() != outputs) continue;
            const std::size_t n = window.front().size();
            std::size_t size = 16;
            while (size < n + L + 1) size *= 2;
            padded.assign(size, 0.0);
            for (std::size_t a = 0; a < outputs; ++a) {
                std::copy(window[a].begin(), window[a].end(), padded.begin());
                fft.fwd(spectra[a], padded);
            }
            product.resize(size);
            for (std::size_t l = 0; l <= L && l < n; ++l) pairs[l] += static_cast<double>(n - l);
            for (std::size_t a = 0; a < outputs; ++a)
                for (std::size_t b = 0; b < outputs; ++b) {
                    for (std::size_t f = 0; f < size; ++f) product[f] = std::conj(spectra[a][f]) * spectra[b][f];
                    fft.inv(lagged, product);
                    for (std::size_t l = 0; l <= L && l < n; ++l) sum[a][b][l] += lagged[l];
                }
        }
    for (std::size_t a = 0; a < outputs; ++a)
        for (std::size_t b = 0; b < outputs; ++b)
            for (std::size_t l = 0; l <= L; ++l) sum[a][b][l] = pairs[l] > 0 ? sum[a][b][l] / pairs[l] : 0.0;
    p.covariance = std::move(sum);
    p.available = true;
    // The correlation's reach: the first lag from which every auto-covariance stays within
    // the floor, or within three of its estimate's standard errors (Bartlett's formula,
    // c_0 sqrt((1 + 2 Σ_{k<l} ρ_k²) / N) over the N products of every draw), for as many lags
    // again (an oscillating one crosses zero on its way).
    double products = 0.0;
    for (const auto& draw : responses.delta)
        for (const auto& window : draw)
            if (!window.empty()) products += static_cast<double>(window.front().size());
    std::vector<std::vector<double>> threshold(outputs, std::vector<double>(L + 1, 0.0));
    for (std::size_t a = 0; a < outputs; ++a) {
        const std::vector<double>& c = p.covariance[a][a];
        double sum_rho2 = 0.0;
        for (std::size_t l = 0; l <= L; ++l) {
            if (l > 0) sum_rho2 += c[0] > 0 ? (c[l - 1] / c[0]) * (c[l - 1] / c[0]) * (l > 1 ? 2.0 : 0.0) : 0.0;
            threshold[a][l] = std::max(kPropagatedCorrelationFloor * c[0], 3.0 * c[0] * std::sqrt((1.0 + sum_rho2) / products));
        }
    }
    for (std::size_t l = 1; l <= L; ++l) {
        bool small = true;
        for (std::size_t a = 0; a < outputs && small; ++a) {
            const std::vector<double>& c = p.covariance[a][a];
            if (!(c[0] > 0)) continue;
            for (std::size_t k = l; k <= std::min(2 * l, L) && small; ++k) small = std::abs(c[k]) < threshold[a][k];
        }
        if (small || l == L) {
            p.correlation_lags = static_cast<int>(l);
            break;
        }
    }
    return p;
}

}  // namespace tvid
