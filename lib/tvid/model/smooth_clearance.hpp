#pragma once
// The smoothed impact model of a gear clearance (Yoshida & Takamatsu eqs. 7–11), written once for
// any scalar type T: double, the dual numbers of the sensitivities, and packs of
// particles (every branch is a select, so a pack runs it lane by lane).

#include <algorithm>
#include <cmath>

#include "tvid/model/dual.hpp"
#include "tvid/model/packed_dual.hpp"
#include "tvid/simd/elementary_functions.hpp"
#include "tvid/simd/pack.hpp"
#include "tvid/simd/select.hpp"

namespace tvid {

template <class T>
struct RampStep {
    T ramp;  ///< φ1(x; σ)
    T step;  ///< φ2(x; σ)
};

/// φ1 and φ2 at the backward contact (`back`) and the forward one (`fore`).
template <class T>
struct ContactRampSteps {
    RampStep<T> back, fore;
};

/// The two contacts' exponentials e^{−|z_back|} and e^{−|z_fore|}.
template <class T>
struct ContactExponentials {
    T back, fore;
};

/// φ1 and φ2 (eq. 11) at z_back = σx_back and z_fore = σx_fore from e = e^{−|z|} of each
/// contact (in (0, 1], so nothing overflows however large σx is):
///   φ1(x) = ln(1 + e^{σx})/σ = (max(z, 0) + ln(1 + e))/σ,
///   φ2(x) = (1 + tanh(σx))/2 = 1/(1 + e^{−2z}) = 1/(1 + e²) for z ≥ 0, e²/(1 + e²) otherwise;
/// the two contacts share the divisions of their logistic functions and logarithms.
template <class T>
[[gnu::always_inline]] inline ContactRampSteps<T> contact_ramp_steps(const T& z_back, const T& z_fore,
                                                                     const ContactExponentials<T>& e,
                                                                     const T& inverse_sigma) {
    using std::max;
    const T e2_back = e.back * e.back, e2_fore = e.fore * e.fore;
    const T d_back = T(1) + e2_back, d_fore = T(1) + e2_fore;
    const T q = T(1) / (d_back * d_fore);
    const T r_back = q * d_fore, r_fore = q * d_back;  // 1/(1 + e²) of each
    T log_back, log_fore;
    math::log1p_unit_pair(e.back, e.fore, log_back, log_fore);
    return {{(max(z_back, T(0)) + log_back) * inverse_sigma, select(z_back >= T(0), r_back, e2_back * r_back)},
            {(max(z_fore, T(0)) + log_fore) * inverse_sigma, select(z_fore >= T(0), r_fore, e2_fore * r_fore)}};
}

/// Each contact's exponential of its own: e^{−|z|}.
template <class T>
[[gnu::always_inline]] inline ContactExponentials<T> two_exponentials(const T& z_back, const T& z_fore) {
    using std::abs;
    return {math::exp(-abs(z_back)), math::exp(-abs(z_fore))};
}

/// φ1(x; σ) and φ2(x; σ) at one point.
template <class T>
RampStep<T> smooth_ramp_step(const T& x, const T& sigma) {
    const T z = sigma * x;
    return contact_ramp_steps(z, z, two_exponentials(z, z), T(1) / sigma).back;
}

/// φ1(x; σ) = ln(1 + e^{σx}) / σ, the smoothed unit ramp (eq. 11).
template <class T>
T smooth_ramp(const T& x, const T& sigma) {
    return smooth_ramp_step(x, sigma).ramp;
}

/// φ2(x; σ) = (1 + tanh(σx)) / 2, the smoothed unit step (eq. 11).
template <class T>
T smooth_step(const T& x, const T& sigma) {
    return smooth_ramp_step(x, sigma).step;
}

/// Clearance law parameters with scalar type T.
///
/// Each contact takes its own exponential. (Both can come from one, e^{−|σθ|}, times
/// e^{∓σμ}, with a division for the near contact, where σμ <= 300; that saves work but
/// lengthens the chain of dependent operations that a simulation step waits for, and was
/// slower for the particle swarm's packs: 34 against 28 cycles per lane and evaluation.)
template <class T>
struct ClearanceLaw {
    T k_minus, k_plus, c_minus, c_plus, mu, sigma;
    bool smooth = true;
    T sigma_mu = T(0), inverse_sigma = T(0);  ///< σμ and 1/σ, set by prepare()

    ClearanceLaw() = default;
    ClearanceLaw(T k_minus_, T k_plus_, T c_minus_, T c_plus_, T mu_, T sigma_, bool smooth_)
        : k_minus(k_minus_), k_plus(k_plus_), c_minus(c_minus_), c_plus(c_plus_), mu(mu_), sigma(sigma_),
          smooth(smooth_) {
        prepare();
    }

    /// Computes the per-parameter-set factors again after a field was changed.
    void prepare() {
        sigma_mu = sigma * mu;
        inverse_sigma = T(1) / sigma;
    }

    /// Transmitted torque F(θ, θ') for twist θ and twist rate θ':
    /// smooth: Fσ = Gσ(θ) + Hσ(θ)·θ' (eqs. 8–10); non-smooth: eq. 7.
    [[gnu::always_inline]] T torque(const T& theta, const T& theta_rate) const {
        if (!smooth)
            return select(theta < -mu, k_minus * (theta + mu) + c_minus * theta_rate,
                          select(theta > mu, k_plus * (theta - mu) + c_plus * theta_rate, T(0)));
        // σ times the penetration into the backward contact (−θ − μ) and the forward one (θ − μ).
        const T a = sigma * theta;
        const T z_back = -a - sigma_mu, z_fore = a - sigma_mu;
        const ContactRampSteps<T> c = contact_ramp_steps(z_back, z_fore, two_exponentials(z_back, z_fore), inverse_sigma);
        const T g = -k_minus * c.back.ramp + k_plus * c.fore.ramp;  // eq. 9
        const T h = c_minus * c.back.step + c_plus * c.fore.step;   // eq. 10
        return g + h * theta_rate;
    }
};

}  // namespace tvid
