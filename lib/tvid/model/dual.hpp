#pragma once
// Forward-mode dual numbers: a value and its derivatives along up to kDualCapacity
// directions, held in place (no allocation). The model code is written once for any
// scalar type; run with Dual it yields, besides every value, the derivatives of that value
// with respect to whatever the inputs were seeded with — the parameters for the
// forward sensitivities of the methodology paper eq. 9, the state for a stiff integrator's Jacobian.
//
// The number of live directions is carried at run time (`size()`); a constant has none,
// and an operation on two numbers uses the larger count, treating missing entries as 0.
// The value part of every operation is computed exactly as with double, so a simulation
// with Dual reproduces the double simulation's values bit for bit.

#include <algorithm>
#include <array>
#include <cmath>
#include <compare>
#include <cstddef>
#include <type_traits>

#include "tvid/simd/elementary_functions.hpp"

namespace tvid {

inline constexpr int kDualCapacity = 32;

class Dual {
public:
    Dual() = default;
    Dual(double value) : v_(value) {}  // NOLINT: a constant converts implicitly, as a double would
    template <class I, std::enable_if_t<std::is_integral_v<I>, int> = 0>
    Dual(I value) : v_(static_cast<double>(value)) {}  // NOLINT

    /// A variable: `value` with derivative 1 along direction `direction` of `size`.
    static Dual variable(double value, int direction, int size) {
        Dual x(value);
        x.n_ = size;
        std::fill_n(x.d_.begin(), size, 0.0);
        x.d_[static_cast<std::size_t>(direction)] = 1.0;
        return x;
    }

    double value() const { return v_; }
    int size() const { return n_; }
    /// Derivative along direction i (0 beyond size()).
    double derivative(int i) const { return i < n_ ? d_[static_cast<std::size_t>(i)] : 0.0; }
    double* derivatives() { return d_.data(); }
    const double* derivatives() const { return d_.data(); }
    void set_value(double v) { v_ = v; }
    /// Sets the number of directions; the derivatives are then written by the caller.
    void resize(int n) { n_ = n; }

    Dual operator-() const {
        Dual r(-v_);
        r.n_ = n_;
        for (int i = 0; i < n_; ++i) r.d_[i] = -d_[i];
        return r;
    }
    Dual operator+() const { return *this; }

    Dual& operator+=(const Dual& b) { return *this = *this + b; }
    Dual& operator-=(const Dual& b) { return *this = *this - b; }
    Dual& operator*=(const Dual& b) { return *this = *this * b; }
    Dual& operator/=(const Dual& b) { return *this = *this / b; }

    // r = α·a' + β·b' over the directions of a and b; the value set by the caller.
    static Dual combine(double value, double alpha, const Dual& a, double beta, const Dual& b) {
        Dual r(value);
        const int n = std::max(a.n_, b.n_);
        r.n_ = n;
        if (a.n_ == n && b.n_ == n) {
            for (int i = 0; i < n; ++i) r.d_[i] = alpha * a.d_[i] + beta * b.d_[i];
        } else {
            for (int i = 0; i < n; ++i) r.d_[i] = alpha * a.derivative(i) + beta * b.derivative(i);
        }
        return r;
    }
    // r = α·a'; the value set by the caller.
    static Dual scaled(double value, double alpha, const Dual& a) {
        Dual r(value);
        r.n_ = a.n_;
        for (int i = 0; i < a.n_; ++i) r.d_[i] = alpha * a.d_[i];
        return r;
    }

    friend Dual operator+(const Dual& a, const Dual& b) { return combine(a.v_ + b.v_, 1.0, a, 1.0, b); }
    friend Dual operator-(const Dual& a, const Dual& b) { return combine(a.v_ - b.v_, 1.0, a, -1.0, b); }
    friend Dual operator*(const Dual& a, const Dual& b) { return combine(a.v_ * b.v_, b.v_, a, a.v_, b); }
    friend Dual operator/(const Dual& a, const Dual& b) {
        const double q = a.v_ / b.v_;
        return combine(q, 1.0 / b.v_, a, -q / b.v_, b);
    }

    friend Dual operator+(const Dual& a, double b) { Dual r = a; r.v_ = a.v_ + b; return r; }
    friend Dual operator+(double a, const Dual& b) { Dual r = b; r.v_ = a + b.v_; return r; }
    friend Dual operator-(const Dual& a, double b) { Dual r = a; r.v_ = a.v_ - b; return r; }
    friend Dual operator-(double a, const Dual& b) { return scaled(a - b.v_, -1.0, b); }
    friend Dual operator*(const Dual& a, double b) { return scaled(a.v_ * b, b, a); }
    friend Dual operator*(double a, const Dual& b) { return scaled(a * b.v_, a, b); }
    friend Dual operator/(const Dual& a, double b) { return scaled(a.v_ / b, 1.0 / b, a); }
    friend Dual operator/(double a, const Dual& b) {
        const double q = a / b.v_;
        return scaled(q, -q / b.v_, b);
    }

    // Comparisons look at the values only (branches of the model code).
    friend std::partial_ordering operator<=>(const Dual& a, const Dual& b) { return a.v_ <=> b.v_; }
    friend bool operator==(const Dual& a, const Dual& b) { return a.v_ == b.v_; }

    // sin and cos with tvid's own values (math::sincos), as the double code computes them.
    friend Dual sin(const Dual& a) {
        double s = 0.0, c = 0.0;
        math::sincos(a.v_, s, c);
        return scaled(s, c, a);
    }
    friend Dual cos(const Dual& a) {
        double s = 0.0, c = 0.0;
        math::sincos(a.v_, s, c);
        return scaled(c, -s, a);
    }
    friend Dual sqrt(const Dual& a) {
        const double r = std::sqrt(a.v_);
        return scaled(r, 0.5 / r, a);
    }
    // exp and log1p with tvid's own values (tvid/simd/elementary_functions.hpp), as the
    // double and pack code computes them: a simulation with Dual keeps the double one's values.
    static Dual exponential(const Dual& a) {
        const double e = math::exp(a.v_);
        return scaled(e, e, a);
    }
    static Dual log_one_plus(const Dual& a) { return scaled(math::log1p(a.v_), 1.0 / (1.0 + a.v_), a); }
    friend Dual exp(const Dual& a) { return exponential(a); }
    friend Dual log1p(const Dual& a) { return log_one_plus(a); }
    friend Dual tanh(const Dual& a) {
        const double t = std::tanh(a.v_);
        return scaled(t, 1.0 - t * t, a);
    }
    friend Dual abs(const Dual& a) { return a.v_ < 0.0 ? -a : a; }
    friend Dual max(const Dual& a, const Dual& b) { return a.v_ < b.v_ ? b : a; }
    friend Dual min(const Dual& a, const Dual& b) { return b.v_ < a.v_ ? b : a; }
    friend bool isfinite(const Dual& a) { return std::isfinite(a.v_); }

private:
    double v_ = 0.0;
    int n_ = 0;
    std::array<double, kDualCapacity> d_;  // only the first n_ entries are meaningful
};

/// x[0 … n) as dual numbers into xd, states first … first + width − 1 carrying a unit
/// direction each: one block of columns of a Jacobian by the state (width ≤ kDualCapacity).
inline void seed_state_directions(const double* x, std::size_t n, std::size_t first, std::size_t width, Dual* xd) {
    for (std::size_t j = 0; j < n; ++j)
        xd[j] = j >= first && j < first + width ? Dual::variable(x[j], static_cast<int>(j - first), static_cast<int>(width))
                                                : Dual(x[j]);
}

namespace math {
inline Dual exp(const Dual& a) { return Dual::exponential(a); }
inline Dual log1p(const Dual& a) { return Dual::log_one_plus(a); }
inline void sincos(const Dual& x, Dual& sin_x, Dual& cos_x) {
    double s = 0.0, c = 0.0;
    sincos(x.value(), s, c);
    sin_x = Dual::scaled(s, c, x);
    cos_x = Dual::scaled(c, -s, x);
}
inline void log1p_unit_pair(const Dual& x, const Dual& y, Dual& log_x, Dual& log_y) {
    double lx = 0.0, ly = 0.0;
    log1p_unit_pair(x.value(), y.value(), lx, ly);
    log_x = Dual::scaled(lx, 1.0 / (1.0 + x.value()), x);
    log_y = Dual::scaled(ly, 1.0 / (1.0 + y.value()), y);
}
}  // namespace math

}  // namespace tvid
