#pragma once
// The smoothed impact model of a gear clearance (seed 001 eqs. 7–11), written once for
// any scalar type T (double, a derivative type, a batch of particles).

#include <cmath>

namespace tvid {

/// φ1(x; σ) = ln(1 + e^{σx}) / σ, the smoothed unit ramp (eq. 11), evaluated as
/// (max(z, 0) + ln(1 + e^{−|z|})) / σ with z = σx so that e^{z} never overflows
/// (σx up to 1e5 and beyond is exact to rounding).
template <class T>
T smooth_ramp(const T& x, const T& sigma) {
    using std::abs, std::exp, std::log1p, std::max;
    const T z = sigma * x;
    return (max(z, T(0)) + log1p(exp(-abs(z)))) / sigma;
}

/// φ2(x; σ) = (1 + tanh(σx)) / 2, the smoothed unit step (eq. 11), evaluated as the
/// logistic function 1 / (1 + e^{−2σx}) in a form that never overflows.
template <class T>
T smooth_step(const T& x, const T& sigma) {
    using std::abs, std::exp;
    const T z = sigma * x;
    const T e = exp(-2 * abs(z));  // in (0, 1]
    return z >= T(0) ? T(1) / (T(1) + e) : e / (T(1) + e);
}

template <class T>
struct RampStep {
    T ramp;  ///< φ1(x; σ)
    T step;  ///< φ2(x; σ)
};

/// φ1 and φ2 at the same point sharing one exponential: with e = e^{−|σx|},
/// φ1 = (max(σx, 0) + ln(1 + e)) / σ and φ2 = 1/(1 + e²) for x ≥ 0, e²/(1 + e²) otherwise.
template <class T>
RampStep<T> smooth_ramp_step(const T& x, const T& sigma) {
    using std::abs, std::exp, std::log1p, std::max;
    const T z = sigma * x;
    const T e = exp(-abs(z));
    const T e2 = e * e;
    const T ramp = (max(z, T(0)) + log1p(e)) / sigma;
    const T step = z >= T(0) ? T(1) / (T(1) + e2) : e2 / (T(1) + e2);
    return {ramp, step};
}

/// Clearance law parameters with scalar type T.
template <class T>
struct ClearanceLaw {
    T k_minus, k_plus, c_minus, c_plus, mu, sigma;
    bool smooth = true;

    /// Transmitted torque F(θ, θ') for twist θ and twist rate θ':
    /// smooth: Fσ = Gσ(θ) + Hσ(θ)·θ' (eqs. 8–10); non-smooth: eq. 7.
    T torque(const T& theta, const T& theta_rate) const {
        if (!smooth) {
            if (theta < -mu) return k_minus * (theta + mu) + c_minus * theta_rate;
            if (theta > mu) return k_plus * (theta - mu) + c_plus * theta_rate;
            return T(0);
        }
        const T back = -theta - mu;  // penetration into backward contact
        const T fore = theta - mu;   // penetration into forward contact
        const RampStep<T> b = smooth_ramp_step(back, sigma);
        const RampStep<T> f = smooth_ramp_step(fore, sigma);
        const T g = -k_minus * b.ramp + k_plus * f.ramp;  // eq. 9
        const T h = c_minus * b.step + c_plus * f.step;   // eq. 10
        return g + h * theta_rate;
    }
};

}  // namespace tvid
