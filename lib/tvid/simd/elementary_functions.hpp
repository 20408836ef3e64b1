#pragma once
// exp and log1p for the model code, written once for double and for packs of doubles
// (tvid/simd/pack.hpp) with the same operations in the same order, so that a lane of a
// pack and the scalar code give the same bits: the particle swarm simulates several
// candidates at once, and each must score exactly as it would alone (and as the report's
// final evaluation scores the winner). The C library has no vector log1p, and its vector
// exp is not bound to agree with its scalar one.
//
// sincos is written the same way (the crank angles of the engine model).
// All are branch-free polynomial kernels; their coefficients come from
// scripts/derive_elementary_coefficients.py. Accuracy (tests/unit/test_elementary_functions.cpp,
// against long double): exp within 1 ulp, log1p within 1 ulp. Special values follow the
// C library: exp(±inf) = inf, 0; exp overflows to inf above 709.78 and rounds to 0 below
// −745.1 (subnormal results in between); log1p(−1) = −inf, log1p(x < −1) = NaN; NaN → NaN;
// log1p keeps the sign of a zero.

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "tvid/simd/pack.hpp"

namespace tvid::math {

namespace detail {

/// The bit pattern of a double (or of each lane of a pack) as a signed 64-bit integer.
template <class T>
struct Representation;

// A scalar's bits are unsigned so that sums wrap around modulo 2^64 like the pack lanes'.
template <>
struct Representation<double> {
    using Bits = std::uint64_t;
    static Bits bits(double x) { return std::bit_cast<Bits>(x); }
    static double value(Bits b) { return std::bit_cast<double>(b); }
    static Bits constant(std::int64_t c) { return static_cast<Bits>(c); }
    static Bits shift_right_logical(Bits b, int n) { return b >> n; }
    static Bits shift_left(Bits b, int n) { return b << n; }
};

template <int W>
struct Representation<Pack<W>> {
    using Bits = PackBits<W>;
    static Bits bits(const Pack<W>& x) { return x.bits(); }
    static Pack<W> value(const Bits& b) { return Pack<W>::from_bits(b); }
    static Bits constant(std::int64_t c) { return Bits(c); }
    static Bits shift_right_logical(const Bits& b, int n) { return b.shift_right_logical(n); }
    static Bits shift_left(const Bits& b, int n) { return b << n; }
};

inline double choose(bool c, double a, double b) { return c ? a : b; }
template <int W>
TVID_PACK_INLINE Pack<W> choose(const Mask<W>& m, const Pack<W>& a, const Pack<W>& b) {
    return select(m, a, b);
}

inline constexpr double kLog2e = 0x1.71547652b82fep+0;
inline constexpr double kLn2Hi = 0x1.62e42ff000000p-1;   // 32 significant bits: k·ln2_hi is exact
inline constexpr double kLn2Lo = -0x1.718432a1b0e26p-35;  // ln 2 − ln2_hi
inline constexpr double kShifter = 0x1.8p52;             // x + 1.5·2^52 rounds x to an integer in the low bits

// e^r = 1 + r + r²·Q(r) on |r| <= ln2/2 (scripts/derive_elementary_coefficients.py).
inline constexpr double kExpQ[] = {
    0x1.0000000000001p-1, 0x1.5555555555556p-3, 0x1.5555555553d68p-5, 0x1.11111111109b5p-7, 0x1.6c16c17889ef1p-10,
    0x1.a01a01a7c2efep-13, 0x1.a019b9149a41cp-16, 0x1.71de0db2f6b19p-19, 0x1.28917c89a43a7p-22, 0x1.af389ecfc4b9cp-26,
};

// log(1 + f) = 2s + s·z·P(z), s = f/(2 + f), z = s², on f in [√½ − 1, √2 − 1].
inline constexpr double kLogP[] = {
    0x1.5555555555558p-1, 0x1.99999999952e2p-2, 0x1.2492492df148dp-2, 0x1.c71c62e5800a1p-3,
    0x1.7462b4ab2ef6bp-3, 0x1.39fe606542ddep-3, 0x1.2b584aae78a57p-3,
};

// c[0] + x·c[1] + … + x^(N−1)·c[N−1] by Estrin's scheme for the two degrees used: pairs
// c[2i] + x·c[2i+1], then pairs of pairs with x², x⁴, x⁸. The dependency chain is 4
// multiply-adds deep instead of N − 1: a simulation waits for every step of it.
template <class T>
[[gnu::always_inline]] inline T polynomial(const T& x, const double (&c)[10]) {
    const T x2 = x * x;
    const T x4 = x2 * x2;
    const T x8 = x4 * x4;
    const T p01 = muladd(x, T(c[1]), T(c[0])), p23 = muladd(x, T(c[3]), T(c[2]));
    const T p45 = muladd(x, T(c[5]), T(c[4])), p67 = muladd(x, T(c[7]), T(c[6]));
    const T p89 = muladd(x, T(c[9]), T(c[8]));
    const T p0123 = muladd(x2, p23, p01), p4567 = muladd(x2, p67, p45);
    return muladd(x8, p89, muladd(x4, p4567, p0123));
}
template <class T>
[[gnu::always_inline]] inline T polynomial(const T& x, const double (&c)[7]) {
    const T x2 = x * x;
    const T x4 = x2 * x2;
    const T p01 = muladd(x, T(c[1]), T(c[0])), p23 = muladd(x, T(c[3]), T(c[2]));
    const T p45 = muladd(x, T(c[5]), T(c[4]));
    const T p0123 = muladd(x2, p23, p01), p456 = muladd(x2, T(c[6]), p45);
    return muladd(x4, p456, p0123);
}

template <class T>
[[gnu::always_inline]] inline T exp_kernel(const T& x_in) {
    using R = Representation<T>;
    using Bits = typename R::Bits;
    using std::max, std::min;
    // Beyond these the result is 0 or inf anyway; the clamp keeps k in range. NaN passes
    // through min and max (as a < b is false) and makes the polynomial NaN.
    const T x = min(max(x_in, T(-746.0)), T(710.0));
    // x = k·ln2 + r, k = round(x/ln2), |r| <= ln2/2 (Cody–Waite: k·ln2_hi is exact).
    const T t = muladd(x, T(kLog2e), T(kShifter));
    const T kd = t - T(kShifter);
    const Bits k = R::bits(t) - R::bits(T(kShifter));
    const T r = muladd(-kd, T(kLn2Lo), muladd(-kd, T(kLn2Hi), x));
    const T p = T(1.0) + muladd(r * r, polynomial(r, kExpQ), r);
    // 2^k as two factors 2^k1·2^k2, each a normal number for k in [−1076, 1025], so that
    // subnormal results are rounded once, by the last multiplication. (k1 = round(k/2) by
    // the same shifter: AVX2 has no arithmetic shift of 64-bit lanes.)
    const Bits k1 = R::bits(kd * T(0.5) + T(kShifter)) - R::bits(T(kShifter));
    const Bits k2 = k - k1;
    const T s1 = R::value((k1 + R::constant(1023)) << 52);
    const T s2 = R::value((k2 + R::constant(1023)) << 52);
    return p * s1 * s2;
}

template <class T>
[[gnu::always_inline]] inline T log1p_kernel(const T& x) {
    using R = Representation<T>;
    using Bits = typename R::Bits;
    const double inf = std::numeric_limits<double>::infinity();
    // Near zero (1 + x in [√½, √2)): f = x exactly, k = 0. Elsewhere u = fl(1 + x) = 2^k·m
    // with m in [√½, √2), f = m − 1 (exact), and c = log(1 + x) − log(u) ≈ (1 + x − u)/u
    // restores what the rounding of u lost.
    const auto near = (x > T(-0.2928932188134524)) & (x < T(0.41421356237309503));
    const T u = T(1.0) + x;
    const Bits sqrt_half = R::constant(0x3fe6a09e667f3bcdLL);  // the bits of √½
    const Bits hu = R::bits(u) + (R::constant(0x3ff0000000000000LL) - sqrt_half);
    // hu is positive for every u >= 0, so a logical shift gives the biased exponent.
    const Bits k_far = R::shift_right_logical(hu, 52) - R::constant(1023);
    const T m = R::value((hu & R::constant(0x000fffffffffffffLL)) + sqrt_half);
    const T k_as_double = R::value(k_far + R::bits(T(kShifter))) - T(kShifter);
    const T correction = choose(k_as_double >= T(2.0), T(1.0) - (u - x), x - (u - T(1.0))) / u;
    const T f = choose(near, x, m - T(1.0));
    const T kd = choose(near, T(0.0), k_as_double);
    const T c = choose(near, T(0.0), correction);
    const T s = f / (T(2.0) + f);
    const T z = s * s;
    const T hfsq = T(0.5) * f * f;
    const T tail = z * polynomial(z, kLogP);  // 2 atanh(s) − 2s = s·tail
    T result = muladd(kd, T(kLn2Hi), f - (hfsq - muladd(s, hfsq + tail, muladd(kd, T(kLn2Lo), c))));
    result = choose(x == T(0.0), x, result);           // log1p(±0) = ±0
    result = choose(x == T(inf), x, result);           // log1p(inf) = inf
    result = choose(x == T(-1.0), T(-inf), result);    // the pole
    result = choose(x < T(-1.0), T(std::numeric_limits<double>::quiet_NaN()), result);
    return choose(x != x, x, result);                  // NaN stays NaN
}

// sin(r) = r + r³·S(r²), cos(r) = 1 − r²/2 + r⁴·C(r²) on |r| <= π/4.
inline constexpr double kSinS[] = {-0x1.5555555555555p-3, 0x1.1111111110bb2p-7,  -0x1.a01a019e83aaep-13,
                                   0x1.71de37968a100p-19, -0x1.ae600b02b6262p-26, 0x1.5e0b19f8b1451p-33};
inline constexpr double kCosC[] = {0x1.5555555555555p-5,  -0x1.6c16c16c16967p-10, 0x1.a01a019f4eb01p-16,
                                   -0x1.27e4fa17da09ep-22, 0x1.1eeb68e93b64cp-29, -0x1.907da367a37cbp-37};
inline constexpr double kTwoOverPi = 0x1.45f306dc9c883p-1;
// π/2 = p1 + p2 + p3; p1 and p2 with 33 significant bits, so k·p1 and k·p2 are exact for |k| < 2^20.
inline constexpr double kHalfPi1 = 0x1.921fb54480000p+0, kHalfPi2 = -0x1.e973dcb400000p-35,
                        kHalfPi3 = 0x1.3198a2e037073p-69;
/// Beyond this |x| the reduction by π/2 loses digits: the C library's sin and cos take over.
inline constexpr double kSinCosReducible = 8.0e5;

template <class T>
[[gnu::always_inline]] inline T polynomial(const T& x, const double (&c)[6]) {
    const T x2 = x * x;
    const T p01 = muladd(x, T(c[1]), T(c[0])), p23 = muladd(x, T(c[3]), T(c[2])), p45 = muladd(x, T(c[5]), T(c[4]));
    return muladd(x2 * x2, p45, muladd(x2, p23, p01));
}
template <class T>
[[gnu::always_inline]] inline T polynomial(const T& x, const double (&c)[5]) {
    const T x2 = x * x;
    const T p01 = muladd(x, T(c[1]), T(c[0])), p23 = muladd(x, T(c[3]), T(c[2]));
    return muladd(x2 * x2, T(c[4]), muladd(x2, p23, p01));
}

inline constexpr double kSinTail[] = {kSinS[1], kSinS[2], kSinS[3], kSinS[4], kSinS[5]};

// sin x and cos x for |x| <= kSinCosReducible: x = k·π/2 + r, |r| <= π/4, with r as a head
// and a tail (Cody–Waite in three parts, the rounding of the second kept), then the
// quadrant k mod 4 picks ±sin r or ±cos r. The kernels on r = h + l (l the tail):
//   sin r = h − ((z·(l/2 − v·S') − l) − v·S1),  v = z·h, S = S1 + z·S'(z)
//   cos r = w + (((1 − w) − z/2) + (z²·C(z) − h·l)),  w = 1 − z/2 (its rounding kept)
template <class T>
[[gnu::always_inline]] inline void sincos_kernel(const T& x, T& sin_x, T& cos_x) {
    using R = Representation<T>;
    using Bits = typename R::Bits;
    const T t = muladd(x, T(kTwoOverPi), T(kShifter));
    const T kd = t - T(kShifter);
    const Bits k = R::bits(t) - R::bits(T(kShifter));
    const T r1 = muladd(-kd, T(kHalfPi1), x);  // exact
    const T w2 = kd * T(kHalfPi2);             // exact (33 + 20 bits)
    const T r2 = r1 - w2;
    const T tail = ((r1 - r2) - w2) - kd * T(kHalfPi3);
    const T h = r2 + tail;
    const T l = (r2 - h) + tail;
    const T z = h * h;
    const T v = z * h;
    const T sin_r = h - ((z * (T(0.5) * l - v * polynomial(z, kSinTail)) - l) - v * T(kSinS[0]));
    const T half_z = T(0.5) * z;
    const T w = T(1.0) - half_z;
    const T cos_r = w + (((T(1.0) - w) - half_z) + ((z * z) * polynomial(z, kCosC) - h * l));
    // Quadrant q = k mod 4: sin x = sin r, cos r, −sin r, −cos r; cos x = cos r, −sin r, −cos r, sin r.
    const Bits q = k & R::constant(3);
    const auto swap = R::value((q & R::constant(1)) + R::bits(T(kShifter))) - T(kShifter) > T(0.5);
    const Bits sin_sign = R::shift_left(q & R::constant(2), 62);
    const Bits cos_sign = R::shift_left((q + R::constant(1)) & R::constant(2), 62);
    sin_x = choose(x == T(0.0), x, R::value(R::bits(choose(swap, cos_r, sin_r)) ^ sin_sign));  // sin ±0 = ±0
    cos_x = R::value(R::bits(choose(swap, sin_r, cos_r)) ^ cos_sign);
}

inline constexpr double kSqrt2Minus1 = 0.41421356237309503;  // √2 − 1, rounded up
// 1/u ≈ α − β·u on [√2, 2] within 1.5 % (the rounding correction of log1p on [0, 1]).
inline constexpr double kReciprocalAlpha = 0x1.30672e53c83b2p+0;
inline constexpr double kReciprocalBeta = 0x1.64a15f184ed68p-2;

// log(1 + x) for x in [0, 1] up to the division s = f/(2 + f), which the caller supplies
// through `reciprocal` of (2 + f): for x < √2 − 1, f = x; above, 1 + x = 2·(1 + f) with
// f = (1 + x)/2 − 1 exact, and c restores what the rounding of 1 + x lost.
template <class T>
struct UnitLog1pParts {
    T f, d, kd, c;  ///< log(1 + x) = kd·ln2 + log(1 + f) + c, d = 2 + f
};

template <class T>
[[gnu::always_inline]] inline UnitLog1pParts<T> unit_log1p_parts(const T& x) {
    const auto near = x < T(kSqrt2Minus1);
    const T u = T(1.0) + x;
    // (1 + x − u)/u; the correction is about 1e-16 of u, so 1/u needs only a few digits.
    const T c = (x - (u - T(1.0))) * (T(kReciprocalAlpha) - T(kReciprocalBeta) * u);
    const T f = choose(near, x, T(0.5) * u - T(1.0));
    return {f, T(2.0) + f, choose(near, T(0.0), T(1.0)), choose(near, T(0.0), c)};
}

template <class T>
[[gnu::always_inline]] inline T unit_log1p_finish(const UnitLog1pParts<T>& p, const T& s) {
    const T z = s * s;
    const T hfsq = T(0.5) * p.f * p.f;
    const T tail = z * polynomial(z, kLogP);
    return muladd(p.kd, T(kLn2Hi), p.f - (hfsq - muladd(s, hfsq + tail, muladd(p.kd, T(kLn2Lo), p.c))));
}

}  // namespace detail

/// log(1 + x) and log(1 + y) for x, y in [0, 1] (the clearance law's arguments e^{−|z|}),
/// sharing one division; within 2 ulp. Written once for double and packs.
template <class T>
[[gnu::always_inline]] inline void log1p_unit_pair(const T& x, const T& y, T& log_x, T& log_y) {
    const detail::UnitLog1pParts<T> px = detail::unit_log1p_parts(x), py = detail::unit_log1p_parts(y);
    const T q = T(1.0) / (px.d * py.d);
    log_x = detail::unit_log1p_finish(px, px.f * (py.d * q));
    log_y = detail::unit_log1p_finish(py, py.f * (px.d * q));
}

/// sin x and cos x together, within about an ulp; as std::sin and std::cos beyond
/// |x| = 8e5 (where reducing by π/2 in double would lose digits) and for ±inf and NaN.
inline void sincos(double x, double& sin_x, double& cos_x) {
    if (!(std::abs(x) <= detail::kSinCosReducible)) {
        sin_x = std::sin(x);
        cos_x = std::cos(x);
        return;
    }
    detail::sincos_kernel(x, sin_x, cos_x);
}
template <int W>
[[gnu::always_inline]] inline void sincos(const Pack<W>& x, Pack<W>& sin_x, Pack<W>& cos_x) {
    detail::sincos_kernel(x, sin_x, cos_x);
    const Mask<W> beyond = !(abs(x) <= Pack<W>(detail::kSinCosReducible));
    if (beyond.any()) [[unlikely]]
        for (int lane = 0; lane < W; ++lane)
            if (beyond[lane]) {
                sin_x.set(lane, std::sin(x[lane]));
                cos_x.set(lane, std::cos(x[lane]));
            }
}

inline double exp(double x) { return detail::exp_kernel(x); }
template <int W>
[[gnu::always_inline]] inline Pack<W> exp(const Pack<W>& x) {
    return detail::exp_kernel(x);
}

inline double log1p(double x) { return detail::log1p_kernel(x); }
template <int W>
[[gnu::always_inline]] inline Pack<W> log1p(const Pack<W>& x) {
    return detail::log1p_kernel(x);
}

}  // namespace tvid::math
