#pragma once
// Forward-mode dual numbers with a fixed number D of directions held in a pack
// (tvid/simd/pack.hpp): the value, and its derivatives along D directions as one SIMD
// number, so every operation is the double operation on the value plus a few vector
// operations on all directions at once. The forward sensitivities of a fixed-step RK4
// simulation use them (the methodology paper eq. 9): the free parameters of a column block and the
// warm-up shooting's two directions, D = 8 or 16.
//
// As with Dual (dual.hpp), the value of every operation is computed exactly as with
// double, so a simulation with PackedDual reproduces the double simulation's values bit
// for bit; and each direction is computed on its own, so a direction's derivatives do
// not depend on which other directions share the pack.

#include <cmath>
#include <compare>
#include <type_traits>

#include "tvid/simd/elementary_functions.hpp"
#include "tvid/simd/pack.hpp"

namespace tvid {

template <int D>
class PackedDual {
public:
    using Directions = Pack<D>;
    static constexpr int directions = D;

    PackedDual() : v_(0.0), d_(0.0) {}
    PackedDual(double value) : v_(value), d_(0.0) {}  // NOLINT: a constant converts implicitly, as a double would
    template <class I, std::enable_if_t<std::is_integral_v<I>, int> = 0>
    PackedDual(I value) : PackedDual(static_cast<double>(value)) {}  // NOLINT
    PackedDual(double value, const Directions& derivatives) : v_(value), d_(derivatives) {}

    /// A variable: `value` with derivative 1 along `direction`.
    static PackedDual variable(double value, int direction) {
        PackedDual x(value);
        x.d_.set(direction, 1.0);
        return x;
    }

    double value() const { return v_; }
    double derivative(int i) const { return d_[i]; }
    const Directions& derivatives() const { return d_; }
    void set_value(double v) { v_ = v; }
    void set_derivative(int i, double v) { d_.set(i, v); }
    void set_derivatives(const Directions& d) { d_ = d; }

    [[gnu::always_inline]] PackedDual operator-() const { return {-v_, -d_}; }
    PackedDual operator+() const { return *this; }
    PackedDual& operator+=(const PackedDual& b) { return *this = *this + b; }
    PackedDual& operator-=(const PackedDual& b) { return *this = *this - b; }
    PackedDual& operator*=(const PackedDual& b) { return *this = *this * b; }
    PackedDual& operator/=(const PackedDual& b) { return *this = *this / b; }

    [[gnu::always_inline]] friend PackedDual operator+(const PackedDual& a, const PackedDual& b) { return {a.v_ + b.v_, a.d_ + b.d_}; }
    [[gnu::always_inline]] friend PackedDual operator-(const PackedDual& a, const PackedDual& b) { return {a.v_ - b.v_, a.d_ - b.d_}; }
    [[gnu::always_inline]] friend PackedDual operator*(const PackedDual& a, const PackedDual& b) {
        return {a.v_ * b.v_, a.d_ * Directions(b.v_) + b.d_ * Directions(a.v_)};
    }
    [[gnu::always_inline]] friend PackedDual operator/(const PackedDual& a, const PackedDual& b) {
        const double q = a.v_ / b.v_;
        return {q, a.d_ * Directions(1.0 / b.v_) + b.d_ * Directions(-q / b.v_)};
    }

    [[gnu::always_inline]] friend PackedDual operator+(const PackedDual& a, double b) { return {a.v_ + b, a.d_}; }
    [[gnu::always_inline]] friend PackedDual operator+(double a, const PackedDual& b) { return {a + b.v_, b.d_}; }
    [[gnu::always_inline]] friend PackedDual operator-(const PackedDual& a, double b) { return {a.v_ - b, a.d_}; }
    [[gnu::always_inline]] friend PackedDual operator-(double a, const PackedDual& b) { return {a - b.v_, -b.d_}; }
    [[gnu::always_inline]] friend PackedDual operator*(const PackedDual& a, double b) { return {a.v_ * b, a.d_ * Directions(b)}; }
    [[gnu::always_inline]] friend PackedDual operator*(double a, const PackedDual& b) { return {a * b.v_, b.d_ * Directions(a)}; }
    [[gnu::always_inline]] friend PackedDual operator/(const PackedDual& a, double b) { return {a.v_ / b, a.d_ * Directions(1.0 / b)}; }
    [[gnu::always_inline]] friend PackedDual operator/(double a, const PackedDual& b) {
        const double q = a / b.v_;
        return {q, b.d_ * Directions(-q / b.v_)};
    }

    // Comparisons look at the values only (branches of the model code).
    friend std::partial_ordering operator<=>(const PackedDual& a, const PackedDual& b) { return a.v_ <=> b.v_; }
    friend bool operator==(const PackedDual& a, const PackedDual& b) { return a.v_ == b.v_; }

    [[gnu::always_inline]] friend PackedDual sin(const PackedDual& a) {
        double s = 0.0, c = 0.0;
        math::sincos(a.v_, s, c);
        return {s, a.d_ * Directions(c)};
    }
    [[gnu::always_inline]] friend PackedDual cos(const PackedDual& a) {
        double s = 0.0, c = 0.0;
        math::sincos(a.v_, s, c);
        return {c, a.d_ * Directions(-s)};
    }
    [[gnu::always_inline]] friend PackedDual sqrt(const PackedDual& a) {
        const double r = std::sqrt(a.v_);
        return {r, a.d_ * Directions(0.5 / r)};
    }
    [[gnu::always_inline]] friend PackedDual exp(const PackedDual& a) {
        const double e = math::exp(a.v_);
        return {e, a.d_ * Directions(e)};
    }
    [[gnu::always_inline]] friend PackedDual log1p(const PackedDual& a) { return {math::log1p(a.v_), a.d_ * Directions(1.0 / (1.0 + a.v_))}; }
    [[gnu::always_inline]] friend PackedDual abs(const PackedDual& a) { return {std::abs(a.v_), a.v_ < 0.0 ? -a.d_ : a.d_}; }
    [[gnu::always_inline]] friend PackedDual max(const PackedDual& a, const PackedDual& b) { return a.v_ < b.v_ ? b : a; }
    [[gnu::always_inline]] friend PackedDual min(const PackedDual& a, const PackedDual& b) { return b.v_ < a.v_ ? b : a; }
    friend bool isfinite(const PackedDual& a) { return std::isfinite(a.v_); }

    /// The value and every derivative finite.
    bool all_finite() const { return std::isfinite(v_) && isfinite(d_).all(); }

private:
    double v_;
    Directions d_;
};

namespace math {
template <int D>
PackedDual<D> exp(const PackedDual<D>& a) {
    const double e = exp(a.value());
    return {e, a.derivatives() * Pack<D>(e)};
}
template <int D>
PackedDual<D> log1p(const PackedDual<D>& a) {
    return {log1p(a.value()), a.derivatives() * Pack<D>(1.0 / (1.0 + a.value()))};
}
template <int D>
void sincos(const PackedDual<D>& x, PackedDual<D>& sin_x, PackedDual<D>& cos_x) {
    double s = 0.0, c = 0.0;
    sincos(x.value(), s, c);
    sin_x = {s, x.derivatives() * Pack<D>(c)};
    cos_x = {c, x.derivatives() * Pack<D>(-s)};
}
template <int D>
void log1p_unit_pair(const PackedDual<D>& x, const PackedDual<D>& y, PackedDual<D>& log_x, PackedDual<D>& log_y) {
    double lx = 0.0, ly = 0.0;
    log1p_unit_pair(x.value(), y.value(), lx, ly);
    log_x = {lx, x.derivatives() * Pack<D>(1.0 / (1.0 + x.value()))};
    log_y = {ly, y.derivatives() * Pack<D>(1.0 / (1.0 + y.value()))};
}
}  // namespace math

}  // namespace tvid
