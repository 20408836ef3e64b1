#pragma once
// A parameter that is a formula of others (`parameters: k_m: { expr: "k_s / (3.5^2 * eta)" }`,
// as lmfit's `expr`): compiled once into a small stack program over the parameter vector and
// evaluated for any scalar type T, so that the sensitivities (dual numbers) and packed lanes
// carry its derivatives through the parameters it reads.
//
// The grammar: numbers, parameter names, + − * / (left to right), ^ (a number or a formula of
// numbers as the exponent; right to left), unary −, parentheses, and sqrt(), exp(), log().

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "tvid/model/dual.hpp"
#include "tvid/model/packed_dual.hpp"
#include "tvid/simd/elementary_functions.hpp"
#include "tvid/simd/pack.hpp"

namespace tvid {

struct ParameterFormula {
    enum class Op { constant, parameter, add, subtract, multiply, divide, negate, integer_power, real_power, exp, log };
    struct Step {
        Op op = Op::constant;
        double value = 0.0;  ///< constant; the exponent of a power
        int index = -1;      ///< parameter
    };
    int parameter = -1;          ///< the parameter it defines
    std::string text;            ///< as written
    std::vector<Step> program;   ///< postfix
    std::vector<int> reads;      ///< the parameters it reads, each once

    /// The deepest stack the program needs (compile refuses deeper).
    static constexpr std::size_t kMaxDepth = 32;
};

/// `text` compiled against the parameter names; throws std::invalid_argument with a sentence
/// (an unknown name, a misplaced token, an exponent that is not a number) on bad input.
ParameterFormula compile_parameter_formula(const std::string& text, const std::vector<std::string>& names,
                                                  int parameter);

/// The expressions ordered so that each comes after those whose parameters it reads; throws
/// std::invalid_argument naming the cycle ("k_a -> k_b -> k_a") when they read each other.
std::vector<ParameterFormula> order_parameter_formulas(std::vector<ParameterFormula> expressions,
                                                             const std::vector<std::string>& names);

/// The expression's value at the parameter vector p (the parameters it reads already resolved).
template <class T>
T evaluate_parameter_formula(const ParameterFormula& e, const T* p) {
    std::array<T, ParameterFormula::kMaxDepth> stack{};
    std::size_t top = 0;
    using Op = ParameterFormula::Op;
    for (const ParameterFormula::Step& s : e.program) {
        switch (s.op) {
            case Op::constant: stack[top++] = T(s.value); break;
            case Op::parameter: stack[top++] = p[s.index]; break;
            case Op::add: --top; stack[top - 1] = stack[top - 1] + stack[top]; break;
            case Op::subtract: --top; stack[top - 1] = stack[top - 1] - stack[top]; break;
            case Op::multiply: --top; stack[top - 1] = stack[top - 1] * stack[top]; break;
            case Op::divide: --top; stack[top - 1] = stack[top - 1] / stack[top]; break;
            case Op::negate: stack[top - 1] = T(0.0) - stack[top - 1]; break;
            case Op::integer_power: {  // x^n by repeated products, exact for small n
                const T x = stack[top - 1];
                const int n = static_cast<int>(s.value);
                T r = T(1.0);
                for (int k = 0; k < (n < 0 ? -n : n); ++k) r = r * x;
                stack[top - 1] = n < 0 ? T(1.0) / r : r;
                break;
            }
            case Op::real_power:  // x^c = e^(c ln x), for x > 0
                stack[top - 1] = math::exp(T(s.value) * math::log1p(stack[top - 1] - T(1.0)));
                break;
            case Op::exp: stack[top - 1] = math::exp(stack[top - 1]); break;
            case Op::log: stack[top - 1] = math::log1p(stack[top - 1] - T(1.0)); break;
        }
    }
    return stack[0];
}

/// Each expression of `expressions` (in order) evaluated into p.
template <class T>
void resolve_parameter_formulas(const std::vector<ParameterFormula>& expressions, T* p) {
    for (const ParameterFormula& e : expressions) p[e.parameter] = evaluate_parameter_formula(e, p);
}

/// The standard error of parameter `parameter`'s formula by the delta method, √(gᵀ C g): g its
/// gradient in the free parameters (free[j] the parameter index of column j) at the full vector
/// p, C their covariance. Formulas it reads through are followed (all of `expressions`, in
/// order). NaN when no formula defines it or C does not match.
double formula_std_error(const std::vector<ParameterFormula>& expressions, int parameter,
                            const std::vector<double>& p, const std::vector<std::size_t>& free,
                            const std::vector<std::vector<double>>& covariance);

}  // namespace tvid
