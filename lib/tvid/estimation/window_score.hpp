#pragma once
// The cost's rule for one estimation window, written once for every path that scores:
// a simulation sample by sample (IdentificationProblem::cost), SIMD groups of candidates
// side by side (batch_cost.cpp) and residuals already computed (ProblemCost).
//
//   l1 (Yoshida & Takamatsu eq. 19): the window's share = (Σ_samples Σ_outputs |e|) / n_w,
//                         n_w the window's scored samples (the mean per sample);
//   l2 (the methodology paper eq. 7):  the window's share =  Σ_samples Σ_outputs e²;
//   cost = Σ_windows share, in window order, +inf unless finite.
//
// The terms are added one at a time in the order of the residuals (sample by sample,
// outputs within a sample) and each share is added to the total of the windows before.
// The cost so far, total + share, only grows (the terms are >= 0 and rounding is
// monotonic), so once it reaches a bound the full cost will too: an optimizer that only
// asks whether a candidate beats the bound can stop simulating it there.
//
// T is double, or Pack<W> with W candidates in its lanes: every lane computes exactly the
// bits the double code computes for its candidate (the same operations in the same order).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "tvid/experiment/experiment.hpp"

namespace tvid {

/// The samples of window w that are scored: after the start, from the first scored
/// sample on (after a warm-up from a measured state, w.first itself, which is after
/// w.start, so the same count), up to w.last.
inline std::size_t scored_sample_count(const Window& w) {
    const std::size_t from = std::max(w.start + 1, w.first);
    return w.last >= from ? w.last - from + 1 : 0;
}

/// The residual of one output at one sample, the only place its sign is set: e = f·(y − y*),
/// the simulated output y minus the measured y*, times the output's factor f (weight over
/// spread, ProblemDefinition::output_scale). T is double, a dual number or a Pack.
template <class T>
[[gnu::always_inline]] inline T output_residual(const T& factor, const T& simulated, const T& measured) {
    return factor * (simulated - measured);
}

/// One window's share of the cost, summed residual by residual.
template <class T>
class WindowScore {
public:
    /// A window of `scored_samples` scored samples (scored_sample_count), with the sum of
    /// the terms scored before (a window marched in pieces carries it from one to the next).
    WindowScore(CostKind kind, std::size_t scored_samples, const T& sum_so_far = T(0.0))
        : l1_(kind == CostKind::l1), samples_(static_cast<double>(scored_samples)), sum_(sum_so_far) {}

    /// Adds the term of residual e = y − y* (|e| or e²).
    void add(const T& e) {
        using std::abs;
        sum_ = sum_ + (l1_ ? abs(e) : e * e);
    }

    /// The sum of the terms so far.
    const T& sum() const { return sum_; }

    /// The window's share of the cost from the terms so far (l1: the sum over n_w).
    T share() const { return l1_ ? sum_ / T(samples_) : sum_; }

    /// The cost so far: `total` (the windows before) plus this window's share. At the
    /// window's end, the total of the windows up to this one.
    T partial_cost(const T& total) const { return total + share(); }

    /// Whether a partial cost has reached `bound`, from where the full cost cannot fall
    /// below it (a Mask of the lanes for packs).
    static auto reached(const T& partial, const T& bound) { return partial >= bound; }

private:
    bool l1_;
    double samples_;
    T sum_;
};

/// The cost from the total of every window's share: +inf unless finite.
inline double finished_cost(double total) {
    return std::isfinite(total) ? total : std::numeric_limits<double>::infinity();
}

}  // namespace tvid
