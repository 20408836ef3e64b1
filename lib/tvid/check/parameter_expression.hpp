#pragma once
// A combination of model parameters checked by `tvid check`, e.g. "rho1*k_plus",
// "mu/rho1" or "J1 + 4*J2 + J3": parameter names and numbers joined by + - * / and
// parentheses. The CVT preset's raw parameters are not identifiable, but such products
// and quotients are (docs/model-library.md).

#include <functional>
#include <string>
#include <vector>

namespace tvid {

class ParameterExpression {
public:
    /// Throws std::invalid_argument saying what is wrong and where.
    explicit ParameterExpression(const std::string& text);

    /// The parameter names used, in order of first appearance.
    const std::vector<std::string>& names() const { return names_; }

    /// The value, with `value_of(name)` for each parameter (IEEE arithmetic: x/0 is inf).
    double evaluate(const std::function<double(const std::string&)>& value_of) const;

    /// One step of the expression in postfix order.
    struct Step {
        enum class Kind { number, parameter, add, subtract, multiply, divide, negate };
        Kind kind = Kind::number;
        double number = 0;          ///< Kind::number
        std::size_t parameter = 0;  ///< Kind::parameter: index into names()
    };

private:
    std::vector<std::string> names_;
    std::vector<Step> steps_;
};

}  // namespace tvid
