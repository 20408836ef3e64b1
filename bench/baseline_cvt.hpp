#pragma once
// The straightforward implementation of the CVT clearance identification (Yoshida & Takamatsu
// eqs. 15-21), kept apart from the library as the yardstick of its speed-ups: one
// candidate at a time, scalar double, odeint's runge_kutta4 over a std::vector state,
// the input found by binary search and interpolated at every right-hand side, the
// clearance law written as printed (φ1 with log1p/exp, φ2 with tanh), one thread.
// Its cost equals the library's to rounding (tvid_bench checks it at a few points).

#include <cstddef>
#include <vector>

namespace tvid::bench {

class BaselineCvt {
public:
    /// Samples `time`, input Ttm and measured Tds of a recording; the estimation window
    /// is (start, last]: the simulation starts at sample `start`, samples after it are scored.
    BaselineCvt(std::vector<double> time, std::vector<double> ttm, std::vector<double> tds, std::size_t start,
                std::size_t last);

    /// Mean |Tds* − Tds| over the window for p = (ρ1, k⁻, k⁺, c⁻, c⁺, μ, σ, Δds, Δtm);
    /// +inf when the simulation fails.
    double cost(const double* p);
    /// The same cost as a user of odeint would tune it: a fixed-size state and the input
    /// interpolated within the step, without a search (pagmo_cvt.cpp's yardstick).
    double cost_tuned(const double* p) const;

    std::size_t rhs_evaluations = 0;  ///< running total

private:
    double input(double t) const;
    std::vector<double> time_, ttm_, tds_;
    std::size_t start_, last_;
};

}  // namespace tvid::bench
