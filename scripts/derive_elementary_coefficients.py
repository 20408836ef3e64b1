#!/usr/bin/python3
"""Derives the polynomial coefficients of tvid's exp and log1p (lib/tvid/simd/elementary_functions.hpp).

The particle swarm simulates several candidates at once, one per SIMD lane, and each lane must
compute exactly the bits the scalar model code computes. glibc's exp/log1p have no vector form
that is guaranteed to agree with the scalar one (and libmvec has no log1p), so tvid evaluates
both with its own polynomial kernels, written once for double and for packs of doubles. This
script produces their coefficients (needs Debian's python3-mpmath):

  exp:   e^r = 1 + r + r^2 Q(r)        for |r| <= ln(2)/2, Q of degree 9
  sin:   sin(r) = r + r^3 S(r^2), cos(r) = 1 - r^2/2 + r^4 C(r^2) for |r| <= pi/4, S and C of degree 5
  log1p: log(1+f) = 2 atanh(s) = 2s + s z P(z),   s = f / (2 + f), z = s^2,
         for f in [sqrt(1/2) - 1, sqrt(2) - 1], so z <= ((sqrt 2 - 1)/(sqrt 2 + 1))^2; P of degree 6

Each polynomial interpolates its function at the Chebyshev points of its interval (close to
the minimax polynomial) in 60-digit arithmetic, and the coefficients are rounded to double.
It also prints the line alpha - beta*u closest to 1/u on [sqrt 2, 2] (log1p on [0, 1] divides
its rounding correction, about 1e-16, by u with it instead of a division), and the split of ln 2 into a high part with trailing zero bits (so k * ln2_hi is exact
for |k| < 2^11) and a low part (Cody and Waite). Run: scripts/derive_elementary_coefficients.py
"""
import mpmath as mp

mp.mp.dps = 60


def chebyshev_interpolant(f, a, b, degree):
    """Monomial coefficients c[0..degree] of the interpolant of f at the Chebyshev points of [a, b]."""
    n = degree + 1
    nodes = [(a + b) / 2 + (b - a) / 2 * mp.cos(mp.pi * (k + mp.mpf(1) / 2) / n) for k in range(n)]
    values = [f(x) for x in nodes]
    # Solve the Vandermonde system exactly enough in 60 digits.
    matrix = mp.matrix([[x ** j for j in range(n)] for x in nodes])
    return list(mp.lu_solve(matrix, mp.matrix(values)))


def max_relative_error(f, approx, a, b, samples=4000):
    worst = mp.mpf(0)
    for i in range(samples + 1):
        x = a + (b - a) * i / samples
        exact = f(x)
        if exact != 0:
            worst = max(worst, abs((approx(x) - exact) / exact))
    return worst


def as_double(x):
    return float(x)


def horner(coefficients, x):
    result = mp.mpf(0)
    for c in reversed(coefficients):
        result = result * x + c
    return result


def exp_coefficients():
    half_ln2 = mp.log(2) / 2

    def q(r):
        if abs(r) < mp.mpf("1e-20"):
            return mp.mpf(1) / 2 + r / 6
        return (mp.exp(r) - 1 - r) / (r * r)

    c = [as_double(x) for x in chebyshev_interpolant(q, -half_ln2, half_ln2, 9)]
    err = max_relative_error(mp.exp, lambda r: 1 + r + r * r * horner([mp.mpf(x) for x in c], r), -half_ln2, half_ln2)
    return c, err


def log1p_coefficients():
    s_max = (mp.sqrt(2) - 1) / (mp.sqrt(2) + 1)
    z_max = s_max * s_max

    def p(z):
        if z < mp.mpf("1e-30"):
            return mp.mpf(2) / 3 + 2 * z / 5
        s = mp.sqrt(z)
        return (2 * mp.atanh(s) - 2 * s) / (s * z)

    c = [as_double(x) for x in chebyshev_interpolant(p, mp.mpf(0), z_max, 6)]

    def log_of(f):
        s = f / (2 + f)
        z = s * s
        return 2 * s + s * z * horner([mp.mpf(x) for x in c], z)

    err = max_relative_error(lambda f: mp.log(1 + f), log_of, mp.sqrt(mp.mpf(1) / 2) - 1, mp.sqrt(2) - 1)
    return c, err


def sincos_coefficients():
    """sin(r) = r + r^3 S(r^2), cos(r) = 1 - r^2/2 + r^4 C(r^2) on |r| <= pi/4, S and C of degree 5."""
    z_max = (mp.pi / 4) ** 2

    def s_of(z):
        if z < mp.mpf("1e-30"):
            return -mp.mpf(1) / 6 + z / 120
        r = mp.sqrt(z)
        return (mp.sin(r) - r) / (r * z)

    def c_of(z):
        if z < mp.mpf("1e-30"):
            return mp.mpf(1) / 24 - z / 720
        r = mp.sqrt(z)
        return (mp.cos(r) - 1 + z / 2) / (z * z)

    s_c = [as_double(x) for x in chebyshev_interpolant(s_of, mp.mpf(0), z_max, 5)]
    c_c = [as_double(x) for x in chebyshev_interpolant(c_of, mp.mpf(0), z_max, 5)]
    s_err = max_relative_error(mp.sin, lambda r: r + r ** 3 * horner([mp.mpf(x) for x in s_c], r * r),
                               mp.mpf("1e-9"), mp.pi / 4)
    c_err = max_relative_error(mp.cos, lambda r: 1 - r * r / 2 + r ** 4 * horner([mp.mpf(x) for x in c_c], r * r),
                               mp.mpf(0), mp.pi / 4)
    return s_c, c_c, s_err, c_err


def pi_over_2_split():
    """pi/2 = p1 + p2 + p3, p1 and p2 with 33 significant bits (k * p1, k * p2 exact for |k| < 2^20)."""
    half_pi = mp.pi / 2
    scale = mp.mpf(2) ** 33
    p1 = mp.floor(half_pi * scale + mp.mpf(1) / 2) / scale
    rest = half_pi - p1
    e = mp.floor(mp.log(abs(rest), 2))
    scale2 = mp.mpf(2) ** (32 - e)
    p2 = mp.floor(rest * scale2 + mp.mpf(1) / 2) / scale2
    p3 = half_pi - p1 - p2
    return float(p1), float(p2), float(p3)


def reciprocal_line():
    """alpha - beta*u, the line closest to 1/u on [sqrt 2, 2] in relative error (equioscillation)."""
    a, b = mp.sqrt(2), mp.mpf(2)

    def relative(alpha, beta, u):
        return 1 - (alpha - beta * u) * u

    def conditions(alpha, beta):
        interior = alpha / (2 * beta)
        return [relative(alpha, beta, a) - relative(alpha, beta, b), relative(alpha, beta, a) + relative(alpha, beta, interior)]

    alpha, beta = mp.findroot(conditions, (mp.mpf("1.06"), mp.mpf("0.28")))
    return float(alpha), float(beta), float(abs(relative(alpha, beta, a)))


def ln2_split():
    ln2 = mp.log(2)
    # High part: ln 2 rounded to 32 significant bits, so k * ln2_hi is exact for |k| < 2^21.
    scale = mp.mpf(2) ** 32
    hi = mp.floor(ln2 * scale + mp.mpf(1) / 2) / scale
    lo = ln2 - hi
    return float(hi), float(lo)


def main():
    exp_c, exp_err = exp_coefficients()
    log_c, log_err = log1p_coefficients()
    hi, lo = ln2_split()
    alpha, beta, line_err = reciprocal_line()
    s_c, c_c, s_err, c_err = sincos_coefficients()
    p1, p2, p3 = pi_over_2_split()
    print("// exp: e^r = 1 + r + r^2 Q(r), |r| <= ln2/2; Q's coefficients, constant term first")
    print("// (polynomial relative error %.2e before rounding of the evaluation)" % exp_err)
    for c in exp_c:
        print("    %s," % c.hex())
    print("// log1p: log(1+f) = 2s + s z P(z); P's coefficients, constant term first")
    print("// (polynomial relative error %.2e)" % log_err)
    for c in log_c:
        print("    %s," % c.hex())
    print("// log1p on [0, 1]: 1/u ~ alpha - beta u on [sqrt 2, 2] (relative error %.4f), for the rounding correction" % line_err)
    print("    alpha = %s, beta = %s" % (alpha.hex(), beta.hex()))
    print("// sin(r) = r + r^3 S(r^2) (relative error %.2e), cos(r) = 1 - r^2/2 + r^4 C(r^2) (%.2e), |r| <= pi/4" % (s_err, c_err))
    print("    S: " + ", ".join(c.hex() for c in s_c))
    print("    C: " + ", ".join(c.hex() for c in c_c))
    print("// pi/2 = p1 + p2 + p3")
    print("    p1 = %s, p2 = %s, p3 = %s" % (p1.hex(), p2.hex(), p3.hex()))
    print("    2/pi = %s" % float(2 / mp.pi).hex())
    print("// ln 2 = ln2_hi + ln2_lo")
    print("    ln2_hi = %s, ln2_lo = %s" % (hi.hex(), lo.hex()))
    print("    log2(e) = %s" % float(1 / mp.log(2)).hex())


if __name__ == "__main__":
    main()
