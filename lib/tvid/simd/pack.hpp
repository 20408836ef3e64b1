#pragma once
// A pack of W doubles handled as one number: the scalar type of the model code when W
// candidates (particles of a swarm) are simulated at once, lane i holding candidate i.
// Built on the GCC/Clang vector extensions and stored as W / N native vectors of N lanes
// (N = 8 with AVX-512, TVID_PACK_AVX512; 4 with AVX; 2 otherwise), each operation applied
// part by part: a Pack<8> on AVX2 is two ymm registers worked on side by side, which keeps
// both of the core's vector pipes busy where one long chain of dependent operations would
// leave one idle.
// Every arithmetic operation is the IEEE operation on each lane, so a lane computes
// exactly the bits that the same code computes with double (the build never fuses a
// multiply and an add: -ffp-contract=off).
//
// Comparisons give a Mask; branches of the model code are written with select(mask, a, b),
// which for double is the conditional operator (tvid/simd/select.hpp).

#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

#if defined(__FMA__)
#include <immintrin.h>
#endif

#define TVID_PACK_INLINE [[gnu::always_inline]] inline
// The loop over a pack's parts, unrolled: it must become straight-line code, or every
// part goes through memory.
#define TVID_FOR_PARTS(i) _Pragma("GCC unroll 16") for (int i = 0; i < parts; ++i)

namespace tvid {

/// a·b + c with one rounding where the build has FMA (-mfma, with AVX2), with two
/// otherwise; the same for double and for each lane of a pack (see Pack's muladd), so a
/// lane and the scalar code agree within a build. Used in the elementary functions.
inline double muladd(double a, double b, double c) {
#if defined(__FMA__)
    return __builtin_fma(a, b, c);
#else
    return a * b + c;
#endif
}

namespace detail {

#if defined(TVID_PACK_AVX512)  // set with AVX-512's instructions (its macros undefined: CMakeLists.txt)
inline constexpr int kNativeLanes = 8;
#elif defined(__AVX__)
inline constexpr int kNativeLanes = 4;
#else
inline constexpr int kNativeLanes = 2;
#endif

// The vector types of W lanes. Spelled out per width: GCC applies a vector_size that
// depends on a template parameter only at instantiation, too late for the template's code.
template <int W>
struct VectorTypes;
#define TVID_VECTOR_TYPES(W, ...)                                              \
    template <>                                                                \
    struct VectorTypes<W> {                                                    \
        typedef double Vector __attribute__((vector_size(8 * W)));             \
        typedef std::int64_t Signed __attribute__((vector_size(8 * W)));       \
        typedef std::uint64_t Unsigned __attribute__((vector_size(8 * W)));    \
        static Vector broadcast(double x) { return Vector{__VA_ARGS__}; }      \
        static Signed broadcast(std::int64_t x) { return Signed{__VA_ARGS__}; } \
    };
TVID_VECTOR_TYPES(1, x)
TVID_VECTOR_TYPES(2, x, x)
TVID_VECTOR_TYPES(4, x, x, x, x)
TVID_VECTOR_TYPES(8, x, x, x, x, x, x, x, x)
#undef TVID_VECTOR_TYPES

/// How a pack of W lanes is split: `parts` native vectors of `lanes` lanes each.
template <int W>
struct Layout {
    static constexpr int lanes = W < kNativeLanes ? W : kNativeLanes;
    static constexpr int parts = W / lanes;
    using Vector = typename VectorTypes<lanes>::Vector;
    using Signed = typename VectorTypes<lanes>::Signed;
    using Unsigned = typename VectorTypes<lanes>::Unsigned;
};

}  // namespace detail

/// The bit patterns of the lanes of a pack as signed 64-bit integers, with the integer
/// operations the elementary functions need (tvid/simd/elementary_functions.hpp).
template <int W>
class PackBits {
public:
    using L = detail::Layout<W>;
    using Part = typename L::Signed;
    static constexpr int parts = L::parts;

    PackBits() = default;
    TVID_PACK_INLINE explicit PackBits(std::int64_t x) {
        TVID_FOR_PARTS(i) p_[i] = detail::VectorTypes<L::lanes>::broadcast(x);
    }
    TVID_PACK_INLINE Part& part(int i) { return p_[i]; }
    TVID_PACK_INLINE const Part& part(int i) const { return p_[i]; }
    std::int64_t operator[](int lane) const { return p_[lane / L::lanes][lane % L::lanes]; }

    // Sums and differences wrap around modulo 2^64, as the bit manipulations expect (a NaN's
    // bits plus an offset, say): computed on unsigned lanes, where that is defined.
    TVID_PACK_INLINE friend PackBits operator+(const PackBits& a, const PackBits& b) {
        return map(a, b, [](auto x, auto y) { return as_signed(as_unsigned(x) + as_unsigned(y)); });
    }
    TVID_PACK_INLINE friend PackBits operator-(const PackBits& a, const PackBits& b) {
        return map(a, b, [](auto x, auto y) { return as_signed(as_unsigned(x) - as_unsigned(y)); });
    }
    TVID_PACK_INLINE friend PackBits operator&(const PackBits& a, const PackBits& b) { return map(a, b, [](auto x, auto y) { return x & y; }); }
    TVID_PACK_INLINE friend PackBits operator|(const PackBits& a, const PackBits& b) { return map(a, b, [](auto x, auto y) { return x | y; }); }
    TVID_PACK_INLINE friend PackBits operator^(const PackBits& a, const PackBits& b) { return map(a, b, [](auto x, auto y) { return x ^ y; }); }
    TVID_PACK_INLINE friend PackBits operator~(const PackBits& a) {
        PackBits r;
        TVID_FOR_PARTS(i) r.p_[i] = ~a.p_[i];
        return r;
    }
    TVID_PACK_INLINE friend PackBits operator<<(const PackBits& a, int n) {
        PackBits r;
        TVID_FOR_PARTS(i) r.p_[i] = as_signed(as_unsigned(a.p_[i]) << n);
        return r;
    }
    /// Shift right filling with zeros (AVX2 has no arithmetic shift of 64-bit lanes).
    TVID_PACK_INLINE PackBits shift_right_logical(int n) const {
        PackBits r;
        TVID_FOR_PARTS(i) {
            r.p_[i] = std::bit_cast<Part>(std::bit_cast<typename L::Unsigned>(p_[i]) >> n);
        }
        return r;
    }

private:
    TVID_PACK_INLINE static typename L::Unsigned as_unsigned(Part x) { return std::bit_cast<typename L::Unsigned>(x); }
    TVID_PACK_INLINE static Part as_signed(typename L::Unsigned x) { return std::bit_cast<Part>(x); }
    template <class F>
    TVID_PACK_INLINE static PackBits map(const PackBits& a, const PackBits& b, F f) {
        PackBits r;
        TVID_FOR_PARTS(i) r.p_[i] = f(a.p_[i], b.p_[i]);
        return r;
    }
    Part p_[parts];
};

/// The lanes where a comparison of packs holds: all bits set (−1) where true, 0 where false.
template <int W>
class Mask {
public:
    using L = detail::Layout<W>;
    using Part = typename L::Signed;
    static constexpr int parts = L::parts;

    Mask() = default;
    TVID_PACK_INLINE explicit Mask(bool all) {
        TVID_FOR_PARTS(i) p_[i] = detail::VectorTypes<L::lanes>::broadcast(std::int64_t{all ? -1 : 0});
    }
    TVID_PACK_INLINE Part& part(int i) { return p_[i]; }
    TVID_PACK_INLINE const Part& part(int i) const { return p_[i]; }

    bool operator[](int lane) const { return p_[lane / L::lanes][lane % L::lanes] != 0; }
    void set(int lane, bool value) { p_[lane / L::lanes][lane % L::lanes] = value ? -1 : 0; }
    bool any() const {
        for (int i = 0; i < W; ++i)
            if ((*this)[i]) return true;
        return false;
    }
    bool all() const {
        for (int i = 0; i < W; ++i)
            if (!(*this)[i]) return false;
        return true;
    }

    TVID_PACK_INLINE friend Mask operator&(const Mask& a, const Mask& b) {
        Mask r;
        TVID_FOR_PARTS(i) r.p_[i] = a.p_[i] & b.p_[i];
        return r;
    }
    TVID_PACK_INLINE friend Mask operator|(const Mask& a, const Mask& b) {
        Mask r;
        TVID_FOR_PARTS(i) r.p_[i] = a.p_[i] | b.p_[i];
        return r;
    }
    TVID_PACK_INLINE friend Mask operator!(const Mask& a) {
        Mask r;
        TVID_FOR_PARTS(i) r.p_[i] = ~a.p_[i];
        return r;
    }
    TVID_PACK_INLINE friend Mask operator&&(const Mask& a, const Mask& b) { return a & b; }
    TVID_PACK_INLINE friend Mask operator||(const Mask& a, const Mask& b) { return a | b; }

private:
    Part p_[parts];
};

template <int W>
class Pack {
public:
    static_assert(W >= 1 && (W & (W - 1)) == 0 && W <= 32, "a pack holds 1, 2, 4, 8, 16 or 32 lanes");
    using L = detail::Layout<W>;
    using Part = typename L::Vector;
    using Bits = PackBits<W>;
    static constexpr int width = W;
    static constexpr int parts = L::parts;

    Pack() = default;
    TVID_PACK_INLINE Pack(double x) {  // NOLINT: a constant converts implicitly, as for double
        TVID_FOR_PARTS(i) p_[i] = detail::VectorTypes<L::lanes>::broadcast(x);
    }
    template <class I, std::enable_if_t<std::is_integral_v<I>, int> = 0>
    TVID_PACK_INLINE Pack(I x) : Pack(static_cast<double>(x)) {}  // NOLINT

    TVID_PACK_INLINE double operator[](int lane) const { return p_[lane / L::lanes][lane % L::lanes]; }
    TVID_PACK_INLINE void set(int lane, double x) { p_[lane / L::lanes][lane % L::lanes] = x; }
    TVID_PACK_INLINE Part& part(int i) { return p_[i]; }
    TVID_PACK_INLINE const Part& part(int i) const { return p_[i]; }

    TVID_PACK_INLINE Bits bits() const {
        Bits b;
        TVID_FOR_PARTS(i) b.part(i) = std::bit_cast<typename Bits::Part>(p_[i]);
        return b;
    }
    TVID_PACK_INLINE static Pack from_bits(const Bits& b) {
        Pack r;
        TVID_FOR_PARTS(i) r.p_[i] = std::bit_cast<Part>(b.part(i));
        return r;
    }

    TVID_PACK_INLINE Pack operator-() const {
        Pack r;
        TVID_FOR_PARTS(i) r.p_[i] = -p_[i];
        return r;
    }
    Pack operator+() const { return *this; }
    TVID_PACK_INLINE Pack& operator+=(const Pack& b) { return *this = *this + b; }
    TVID_PACK_INLINE Pack& operator-=(const Pack& b) { return *this = *this - b; }
    TVID_PACK_INLINE Pack& operator*=(const Pack& b) { return *this = *this * b; }
    TVID_PACK_INLINE Pack& operator/=(const Pack& b) { return *this = *this / b; }

    TVID_PACK_INLINE friend Pack operator+(const Pack& a, const Pack& b) { return map(a, b, [](auto x, auto y) { return x + y; }); }
    TVID_PACK_INLINE friend Pack operator-(const Pack& a, const Pack& b) { return map(a, b, [](auto x, auto y) { return x - y; }); }
    TVID_PACK_INLINE friend Pack operator*(const Pack& a, const Pack& b) { return map(a, b, [](auto x, auto y) { return x * y; }); }
    TVID_PACK_INLINE friend Pack operator/(const Pack& a, const Pack& b) { return map(a, b, [](auto x, auto y) { return x / y; }); }

    TVID_PACK_INLINE friend Mask<W> operator<(const Pack& a, const Pack& b) { return compare(a, b, [](auto x, auto y) { return x < y; }); }
    TVID_PACK_INLINE friend Mask<W> operator>(const Pack& a, const Pack& b) { return compare(a, b, [](auto x, auto y) { return x > y; }); }
    TVID_PACK_INLINE friend Mask<W> operator<=(const Pack& a, const Pack& b) { return compare(a, b, [](auto x, auto y) { return x <= y; }); }
    TVID_PACK_INLINE friend Mask<W> operator>=(const Pack& a, const Pack& b) { return compare(a, b, [](auto x, auto y) { return x >= y; }); }
    TVID_PACK_INLINE friend Mask<W> operator==(const Pack& a, const Pack& b) { return compare(a, b, [](auto x, auto y) { return x == y; }); }
    TVID_PACK_INLINE friend Mask<W> operator!=(const Pack& a, const Pack& b) { return compare(a, b, [](auto x, auto y) { return x != y; }); }

    /// Lane-wise choice: a where the mask is set, b elsewhere.
    TVID_PACK_INLINE friend Pack select(const Mask<W>& m, const Pack& a, const Pack& b) {
        Pack r;
        TVID_FOR_PARTS(i) r.p_[i] = m.part(i) ? a.p_[i] : b.p_[i];
        return r;
    }
    /// a·b + c lane by lane, rounded as muladd(double, double, double) rounds it.
    TVID_PACK_INLINE friend Pack muladd(const Pack& a, const Pack& b, const Pack& c) {
        Pack r;
        TVID_FOR_PARTS(i) r.p_[i] = fused(a.p_[i], b.p_[i], c.p_[i]);
        return r;
    }
    /// |a|: the sign bit cleared, as std::abs does.
    TVID_PACK_INLINE friend Pack abs(const Pack& a) { return from_bits(a.bits() & ~Bits(INT64_MIN)); }
    /// max and min as std::max and std::min: max(a, b) = a < b ? b : a, min(a, b) = b < a ? b : a.
    TVID_PACK_INLINE friend Pack max(const Pack& a, const Pack& b) { return select(a < b, b, a); }
    TVID_PACK_INLINE friend Pack min(const Pack& a, const Pack& b) { return select(b < a, b, a); }
    // IEEE square root, lane by lane (correctly rounded, so equal to std::sqrt).
    TVID_PACK_INLINE friend Pack sqrt(const Pack& a) { return lanewise(a, [](double x) { return std::sqrt(x); }); }

private:
    TVID_PACK_INLINE static Part fused(const Part& a, const Part& b, const Part& c) {
#if defined(__FMA__)
        if constexpr (L::lanes == 8) {
            return reinterpret_cast<Part>(_mm512_fmadd_pd(reinterpret_cast<__m512d>(a), reinterpret_cast<__m512d>(b),
                                                          reinterpret_cast<__m512d>(c)));
        } else if constexpr (L::lanes == 4) {
            return reinterpret_cast<Part>(_mm256_fmadd_pd(reinterpret_cast<__m256d>(a), reinterpret_cast<__m256d>(b),
                                                          reinterpret_cast<__m256d>(c)));
        } else if constexpr (L::lanes == 2) {
            return reinterpret_cast<Part>(_mm_fmadd_pd(reinterpret_cast<__m128d>(a), reinterpret_cast<__m128d>(b),
                                                       reinterpret_cast<__m128d>(c)));
        } else {
            Part r;
            for (int i = 0; i < L::lanes; ++i) r[i] = __builtin_fma(a[i], b[i], c[i]);
            return r;
        }
#else
        return a * b + c;
#endif
    }
    template <class F>
    TVID_PACK_INLINE static Pack map(const Pack& a, const Pack& b, F f) {
        Pack r;
        TVID_FOR_PARTS(i) r.p_[i] = f(a.p_[i], b.p_[i]);
        return r;
    }
    template <class F>
    TVID_PACK_INLINE static Mask<W> compare(const Pack& a, const Pack& b, F f) {
        Mask<W> m;
        TVID_FOR_PARTS(i) m.part(i) = f(a.p_[i], b.p_[i]);
        return m;
    }
    template <class F>
    TVID_PACK_INLINE static Pack lanewise(const Pack& a, F f) {
        Pack r;
        for (int i = 0; i < W; ++i) r.set(i, f(a[i]));
        return r;
    }
    Part p_[parts];
};

/// Lanes whose value is finite (not NaN, not ±inf).
template <int W>
Mask<W> isfinite(const Pack<W>& a) {
    return abs(a) <= Pack<W>(1.7976931348623157e308);
}

/// The number of lanes of a scalar type of the model code: W for Pack<W>, 1 otherwise.
template <class T>
struct lanes_of {
    static constexpr int value = 1;
};
template <int W>
struct lanes_of<Pack<W>> {
    static constexpr int value = W;
};

}  // namespace tvid
