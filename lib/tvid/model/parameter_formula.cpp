#include "tvid/model/parameter_formula.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>

namespace tvid {

namespace {

using Op = ParameterFormula::Op;

// Recursive descent over the text, emitting postfix steps.
class Parser {
public:
    Parser(const std::string& text, const std::vector<std::string>& names) : s_(text), names_(names) {}

    std::vector<ParameterFormula::Step> parse() {
        sum();
        skip();
        if (at_ < s_.size()) fail("unexpected '" + std::string(1, s_[at_]) + "'");
        return out_;
    }

private:
    [[noreturn]] void fail(const std::string& what) const {
        throw std::invalid_argument(what + " at character " + std::to_string(at_ + 1) + " of \"" + s_ + "\"");
    }
    void skip() {
        while (at_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[at_]))) ++at_;
    }
    bool take(char c) {
        skip();
        if (at_ < s_.size() && s_[at_] == c) {
            ++at_;
            return true;
        }
        return false;
    }
    void emit(Op op, double value = 0.0, int index = -1) { out_.push_back({op, value, index}); }

    void sum() { left_associative(&Parser::product, '+', Op::add, '-', Op::subtract); }
    void product() { left_associative(&Parser::unary, '*', Op::multiply, '/', Op::divide); }
    // One precedence level of two left-associative operators: operand (op operand)*, each op
    // emitted after its right operand (postfix order).
    void left_associative(void (Parser::*operand)(), char first, Op first_op, char second, Op second_op) {
        (this->*operand)();
        for (;;) {
            if (take(first)) (this->*operand)(), emit(first_op);
            else if (take(second)) (this->*operand)(), emit(second_op);
            else return;
        }
    }
    void unary() {
        // Each level of parentheses, sign or exponent recurses: a hostile formula is refused, not a stack overflow.
        if (++depth_ > kMaxNesting) fail("the formula is nested more than " + std::to_string(kMaxNesting) + " levels deep");
        if (take('-')) {
            unary();
            emit(Op::negate);
        } else {
            take('+');
            power();
        }
        --depth_;
    }
    // base ^ exponent, the exponent a number (or a formula of numbers), right to left.
    void power() {
        primary();
        if (!take('^')) return;
        const std::size_t from = out_.size();
        unary();
        std::vector<ParameterFormula::Step> exponent(out_.begin() + static_cast<std::ptrdiff_t>(from), out_.end());
        out_.resize(from);
        for (const auto& step : exponent)
            if (step.op == Op::parameter) fail("an exponent must be a number, not a parameter");
        ParameterFormula folded;
        folded.program = exponent;
        const double c = evaluate_parameter_formula<double>(folded, nullptr);
        if (!std::isfinite(c)) fail("the exponent is not a finite number");
        if (c == std::round(c) && std::abs(c) <= 16) emit(Op::integer_power, c);
        else emit(Op::real_power, c);
    }
    void primary() {
        skip();
        if (at_ >= s_.size()) fail("the formula ends where a number, a parameter or '(' was expected");
        const char c = s_[at_];
        if (c == '(') {
            ++at_;
            sum();
            if (!take(')')) fail("a ')' is missing");
            return;
        }
        if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
            const char* begin = s_.c_str() + at_;
            char* end = nullptr;
            const double v = std::strtod(begin, &end);
            if (end == begin) fail("a malformed number");
            at_ += static_cast<std::size_t>(end - begin);
            emit(Op::constant, v);
            return;
        }
        if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
            const std::size_t start = at_;
            while (at_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[at_])) || s_[at_] == '_' || s_[at_] == '.'))
                ++at_;
            const std::string word = s_.substr(start, at_ - start);
            skip();
            if (at_ < s_.size() && s_[at_] == '(') {
                const Op op = word == "exp" ? Op::exp : word == "log" ? Op::log : word == "sqrt" ? Op::real_power : Op::add;
                if (op == Op::add) fail("unknown function '" + word + "' (sqrt, exp and log are known)");
                ++at_;
                sum();
                if (!take(')')) fail("a ')' is missing");
                emit(op, word == "sqrt" ? 0.5 : 0.0);
                return;
            }
            const auto it = std::find(names_.begin(), names_.end(), word);
            if (it == names_.end()) fail("'" + word + "' is not a parameter declared under parameters");
            emit(Op::parameter, 0.0, static_cast<int>(it - names_.begin()));
            return;
        }
        fail("unexpected '" + std::string(1, c) + "'");
    }

    static constexpr int kMaxNesting = 100;
    const std::string& s_;
    const std::vector<std::string>& names_;
    std::size_t at_ = 0;
    int depth_ = 0;
    std::vector<ParameterFormula::Step> out_;
};

}  // namespace

ParameterFormula compile_parameter_formula(const std::string& text, const std::vector<std::string>& names,
                                                  int parameter) {
    ParameterFormula e;
    e.parameter = parameter;
    e.text = text;
    e.program = Parser(text, names).parse();
    std::size_t depth = 0, deepest = 0;
    for (const auto& s : e.program) {
        if (s.op == Op::constant || s.op == Op::parameter) ++depth;
        else if (s.op == Op::add || s.op == Op::subtract || s.op == Op::multiply || s.op == Op::divide) --depth;
        deepest = std::max(deepest, depth);
        if (s.op == Op::parameter && std::find(e.reads.begin(), e.reads.end(), s.index) == e.reads.end())
            e.reads.push_back(s.index);
    }
    if (deepest > ParameterFormula::kMaxDepth)
        throw std::invalid_argument("the formula \"" + text + "\" nests too deeply (at most " +
                                    std::to_string(ParameterFormula::kMaxDepth) + " pending terms)");
    if (std::find(e.reads.begin(), e.reads.end(), parameter) != e.reads.end())
        throw std::invalid_argument("the formula of " + names[static_cast<std::size_t>(parameter)] + " reads " +
                                    names[static_cast<std::size_t>(parameter)] + " itself");
    return e;
}

std::vector<ParameterFormula> order_parameter_formulas(std::vector<ParameterFormula> expressions,
                                                             const std::vector<std::string>& names) {
    const auto defining = [&](int parameter) -> const ParameterFormula* {
        for (const auto& e : expressions)
            if (e.parameter == parameter) return &e;
        return nullptr;
    };
    std::vector<ParameterFormula> ordered;
    std::vector<int> state(names.size(), 0);  // 0 unvisited, 1 on the path, 2 placed
    std::vector<int> path;
    const auto visit = [&](auto&& self, const ParameterFormula& e) -> void {
        const auto p = static_cast<std::size_t>(e.parameter);
        if (state[p] == 2) return;
        if (state[p] == 1) {
            std::string cycle;
            const auto from = std::find(path.begin(), path.end(), e.parameter);
            for (auto it = from; it != path.end(); ++it) cycle += names[static_cast<std::size_t>(*it)] + " -> ";
            throw std::invalid_argument("the formulas read each other in a cycle: " + cycle + names[p]);
        }
        state[p] = 1;
        path.push_back(e.parameter);
        for (int r : e.reads)
            if (const ParameterFormula* d = defining(r)) self(self, *d);
        path.pop_back();
        state[p] = 2;
        ordered.push_back(e);
    };
    for (const auto& e : expressions) visit(visit, e);
    return ordered;
}

double formula_std_error(const std::vector<ParameterFormula>& expressions, int parameter,
                            const std::vector<double>& p, const std::vector<std::size_t>& free,
                            const std::vector<std::vector<double>>& covariance) {
    const std::size_t m = free.size();
    const bool defined = std::any_of(expressions.begin(), expressions.end(),
                                     [&](const ParameterFormula& e) { return e.parameter == parameter; });
    if (!defined || covariance.size() != m) return std::numeric_limits<double>::quiet_NaN();
    // g by dual numbers: the free parameters seeded in blocks, the expressions resolved in order.
    std::vector<double> g(m, 0.0);
    const auto capacity = static_cast<std::size_t>(kDualCapacity);
    for (std::size_t j0 = 0; j0 < m; j0 += capacity) {
        const std::size_t j1 = std::min(m, j0 + capacity);
        std::vector<Dual> d(p.begin(), p.end());
        for (std::size_t j = j0; j < j1; ++j)
            d[free[j]] = Dual::variable(p[free[j]], static_cast<int>(j - j0), static_cast<int>(j1 - j0));
        resolve_parameter_formulas(expressions, d.data());
        const Dual& v = d[static_cast<std::size_t>(parameter)];
        for (std::size_t j = j0; j < j1; ++j) g[j] = v.derivative(static_cast<int>(j - j0));
    }
    double variance = 0.0;
    for (std::size_t a = 0; a < m; ++a)
        for (std::size_t b = 0; b < m; ++b) variance += g[a] * covariance[a][b] * g[b];
    return std::sqrt(std::max(variance, 0.0));
}

}  // namespace tvid
