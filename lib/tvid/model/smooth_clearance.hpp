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

/// φ1, φ2 at the backward penetration −θ−μ (`back`) and the forward one θ−μ (`fore`).
template <class T>
struct ContactRampSteps {
    RampStep<T> back, fore;
};

/// Both contacts from one exponential. With a = σθ, m = σμ ≥ 0 and E = e^{−|a|},
/// M = e^{−m} (given, computed once per parameter set): the far contact has |z| = |a| + m,
/// e^{−|z|} = E·M; the near one |z| = ||a| − m|, e^{−|z|} = E/M when |a| ≥ m, M/E otherwise.
/// Every factor is in (0, 1] and the quotients are <= 1, so nothing overflows; the caller
/// keeps m small enough (M not subnormal) for the quotients to stay accurate.
template <class T>
ContactRampSteps<T> contact_ramp_steps(const T& theta, const T& sigma, const T& sigma_mu, const T& exp_minus_sigma_mu) {
    using std::abs, std::exp, std::log1p, std::max;
    const T a = sigma * theta;
    const T z_back = -a - sigma_mu, z_fore = a - sigma_mu;
    const T abs_a = abs(a);
    const T e = exp(-abs_a);
    const T far = e * exp_minus_sigma_mu;
    const T near = abs_a >= sigma_mu ? e / exp_minus_sigma_mu : exp_minus_sigma_mu / e;
    const bool back_is_far = a >= T(0);
    auto ramp_step = [&](const T& z, const T& ez) {
        const T e2 = ez * ez;
        return RampStep<T>{(max(z, T(0)) + log1p(ez)) / sigma, z >= T(0) ? T(1) / (T(1) + e2) : e2 / (T(1) + e2)};
    };
    return {ramp_step(z_back, back_is_far ? far : near), ramp_step(z_fore, back_is_far ? near : far)};
}

/// Clearance law parameters with scalar type T.
template <class T>
struct ClearanceLaw {
    T k_minus, k_plus, c_minus, c_plus, mu, sigma;
    bool smooth = true;
    /// σμ and e^{−σμ} for contact_ramp_steps, set by prepare(); e^{−σμ} < 0: not prepared
    /// (then each contact takes its own exponential).
    T sigma_mu = T(0), exp_minus_sigma_mu = T(-1);

    /// Computes the per-parameter-set factors of the one-exponential law when it is exact
    /// to rounding: σμ in [0, 300] (e^{−σμ} ≥ 1e-131, a normal number).
    void prepare() {
        using std::exp;
        sigma_mu = sigma * mu;
        exp_minus_sigma_mu = smooth && sigma_mu >= T(0) && sigma_mu <= T(300) ? exp(-sigma_mu) : T(-1);
    }

    /// Transmitted torque F(θ, θ') for twist θ and twist rate θ':
    /// smooth: Fσ = Gσ(θ) + Hσ(θ)·θ' (eqs. 8–10); non-smooth: eq. 7.
    T torque(const T& theta, const T& theta_rate) const {
        if (!smooth) {
            if (theta < -mu) return k_minus * (theta + mu) + c_minus * theta_rate;
            if (theta > mu) return k_plus * (theta - mu) + c_plus * theta_rate;
            return T(0);
        }
        ContactRampSteps<T> c;
        if (exp_minus_sigma_mu > T(0)) {
            c = contact_ramp_steps(theta, sigma, sigma_mu, exp_minus_sigma_mu);
        } else {
            c.back = smooth_ramp_step(-theta - mu, sigma);  // penetration into backward contact
            c.fore = smooth_ramp_step(theta - mu, sigma);   // penetration into forward contact
        }
        const RampStep<T>& b = c.back;
        const RampStep<T>& f = c.fore;
        const T g = -k_minus * b.ramp + k_plus * f.ramp;  // eq. 9
        const T h = c_minus * b.step + c_plus * f.step;   // eq. 10
        return g + h * theta_rate;
    }
};

}  // namespace tvid
