#include "tvid/check/parameter_expression.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <stdexcept>

namespace tvid {

namespace {

using Step = ParameterExpression::Step;
using Kind = Step::Kind;

Step step(Kind kind, double number = 0, std::size_t parameter = 0) {
    Step s;
    s.kind = kind;
    s.number = number;
    s.parameter = parameter;
    return s;
}

// Recursive descent, emitting postfix steps:
//   sum     = product { ("+" | "-") product }
//   product = factor { ("*" | "/") factor }
//   factor  = "-" factor | NUMBER | NAME | "(" sum ")"
class Parser {
public:
    Parser(const std::string& text, std::vector<std::string>& names, std::vector<Step>& steps)
        : text_(text), names_(names), steps_(steps) {}

    void parse() {
        skip_spaces();
        if (pos_ == text_.size()) throw std::invalid_argument("empty expression");
        sum();
        if (pos_ != text_.size()) fail("expected + - * / or the end");
    }

private:
    void sum() {
        product();
        for (char op = peek(); (op == '+' || op == '-') && accept(op); op = peek()) {
            product();
            steps_.push_back(step(op == '+' ? Kind::add : Kind::subtract));
        }
    }

    void product() {
        factor();
        for (char op = peek(); (op == '*' || op == '/') && accept(op); op = peek()) {
            factor();
            steps_.push_back(step(op == '*' ? Kind::multiply : Kind::divide));
        }
    }

    void factor() {
        // Each nesting ("-", "(") recurses once: bound it, or a hostile expression
        // overflows the stack.
        if (++depth_ > kMaxNesting) fail("nested more than " + std::to_string(kMaxNesting) + " levels deep");
        struct Leave {
            int& depth;
            ~Leave() { --depth; }
        } leave{depth_};
        if (accept('-')) {
            factor();
            steps_.push_back(step(Kind::negate));
            return;
        }
        if (accept('(')) {
            sum();
            if (!accept(')')) fail("expected ')'");
            return;
        }
        if (pos_ < text_.size() && (std::isdigit(static_cast<unsigned char>(text_[pos_])) || text_[pos_] == '.')) {
            const char* begin = text_.c_str() + pos_;
            char* end = nullptr;
            const double v = std::strtod(begin, &end);
            if (end == begin) fail("expected a number");
            pos_ += static_cast<std::size_t>(end - begin);
            steps_.push_back(step(Kind::number, v));
            skip_spaces();
            return;
        }
        if (pos_ < text_.size() && (std::isalpha(static_cast<unsigned char>(text_[pos_])) || text_[pos_] == '_')) {
            const std::size_t start = pos_;
            while (pos_ < text_.size() && (std::isalnum(static_cast<unsigned char>(text_[pos_])) || text_[pos_] == '_'))
                ++pos_;
            const std::string name = text_.substr(start, pos_ - start);
            auto it = std::find(names_.begin(), names_.end(), name);
            if (it == names_.end()) it = names_.insert(names_.end(), name);
            steps_.push_back(step(Kind::parameter, 0, static_cast<std::size_t>(it - names_.begin())));
            skip_spaces();
            return;
        }
        fail("expected a parameter name, a number or '('");
    }

    char peek() const { return pos_ < text_.size() ? text_[pos_] : '\0'; }

    bool accept(char c) {
        if (pos_ < text_.size() && text_[pos_] == c) {
            ++pos_;
            skip_spaces();
            return true;
        }
        return false;
    }

    void skip_spaces() {
        while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    }

    [[noreturn]] void fail(const std::string& what) const {
        const std::string rest = pos_ >= text_.size() ? "at the end"
                                 : text_.size() - pos_ <= 40 ? "at '" + text_.substr(pos_) + "'"
                                                             : "at '" + text_.substr(pos_, 40) + "...'";
        throw std::invalid_argument(what + " " + rest);
    }

    static constexpr int kMaxNesting = 100;

    const std::string& text_;
    std::vector<std::string>& names_;
    std::vector<Step>& steps_;
    std::size_t pos_ = 0;
    int depth_ = 0;
};

}  // namespace

ParameterExpression::ParameterExpression(const std::string& text) { Parser(text, names_, steps_).parse(); }

double ParameterExpression::evaluate(const std::function<double(const std::string&)>& value_of) const {
    std::vector<double> values;
    for (const std::string& n : names_) values.push_back(value_of(n));
    std::vector<double> stack;
    for (const Step& s : steps_) {
        if (s.kind == Kind::number) {
            stack.push_back(s.number);
            continue;
        }
        if (s.kind == Kind::parameter) {
            stack.push_back(values[s.parameter]);
            continue;
        }
        if (s.kind == Kind::negate) {
            stack.back() = -stack.back();
            continue;
        }
        const double b = stack.back();
        stack.pop_back();
        double& a = stack.back();
        switch (s.kind) {
            case Kind::add: a += b; break;
            case Kind::subtract: a -= b; break;
            case Kind::multiply: a *= b; break;
            default: a /= b; break;
        }
    }
    return stack.back();
}

}  // namespace tvid
