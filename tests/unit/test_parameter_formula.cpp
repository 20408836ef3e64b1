// Parameters given by a formula of others (lib/tvid/model/parameter_formula.hpp): the value,
// its derivatives through the model, the delta method's standard error against a hand
// conversion, and the formulas refused (a cycle, an unknown name, a parameter exponent).
#include <catch2/catch.hpp>
#include <cmath>
#include <stdexcept>

#include "tvid/model/dual.hpp"
#include "tvid/model/network_model.hpp"
#include "tvid/model/parameter_formula.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

const std::vector<std::string> kNames = {"k_s", "eta", "k_m", "d"};

// What a message says, or "" when nothing was thrown.
template <class F>
std::string refusal(F&& f) {
    try {
        f();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("a formula's value, and its derivatives for any scalar type", "[model][expressions]") {
    const ParameterFormula e = compile_parameter_formula("k_s / (3.5^2 * eta)", kNames, 2);
    CHECK(e.reads == std::vector<int>{0, 1});
    const double p[4] = {6000.0, 0.93, 0.0, 0.0};
    CHECK(evaluate_parameter_formula(e, p) == Approx(6000.0 / (12.25 * 0.93)).epsilon(1e-15));
    const Dual d[4] = {Dual::variable(6000.0, 0, 2), Dual::variable(0.93, 1, 2), Dual(0.0), Dual(0.0)};
    const Dual v = evaluate_parameter_formula(e, d);
    CHECK(v.derivative(0) == Approx(1.0 / (12.25 * 0.93)).epsilon(1e-14));
    CHECK(v.derivative(1) == Approx(-6000.0 / (12.25 * 0.93 * 0.93)).epsilon(1e-14));
    // precedence, unary minus, right-to-left powers, functions
    const auto value = [&](const std::string& text) { return evaluate_parameter_formula(compile_parameter_formula(text, kNames, 3), p); };
    CHECK(value("1 + 2 * 3 - 4 / 2") == 5.0);
    CHECK(value("-2^2") == -4.0);
    CHECK(value("2^3^2") == 512.0);
    CHECK(value("(1 + 1)^-2") == 0.25);
    CHECK(value("sqrt(k_s * 1.5)") == Approx(std::sqrt(9000.0)).epsilon(1e-14));
    CHECK(value("exp(log(eta))") == Approx(0.93).epsilon(1e-14));
    CHECK(value("eta^0.5") == Approx(std::sqrt(0.93)).epsilon(1e-14));
    CHECK(value("2.5e3 + k_s") == 8500.0);
}

TEST_CASE("a model reads the formula's value and passes its derivatives through", "[model][expressions]") {
    // One node (J 2) on a ground spring of stiffness k_m = k_s / (3.5^2 eta).
    NetworkSpec spec;
    spec.preset = "custom";
    spec.parameter_names = {"k_s", "eta", "k_m"};
    spec.nodes = {NodeSpec{"out", Field::value(2.0), false}};
    spec.spring_dampers.push_back(SpringDamperSpec{"mesh", 0, kGround, Field::param(2), Field::value(0.0)});
    spec.parameter_formulas = {compile_parameter_formula("k_s / (3.5^2 * eta)", spec.parameter_names, 2)};
    NetworkModel<Dual> model(spec);
    const Dual p[3] = {Dual::variable(6000.0, 0, 2), Dual::variable(0.93, 1, 2), Dual(123.0)};  // k_m's slot ignored
    model.set_parameters(p);
    const Dual x[2] = {Dual(0.01), Dual(0.0)};
    Dual f[2];
    model.derivative(x, nullptr, f);
    const double k_m = 6000.0 / (12.25 * 0.93);
    CHECK(model.parameters()[2].value() == Approx(k_m).epsilon(1e-15));
    CHECK(f[1].value() == Approx(-k_m * 0.01 / 2.0).epsilon(1e-14));
    CHECK(f[1].derivative(0) == Approx(-0.01 / 2.0 / (12.25 * 0.93)).epsilon(1e-12));
    CHECK(f[1].derivative(1) == Approx(0.01 / 2.0 * 6000.0 / (12.25 * 0.93 * 0.93)).epsilon(1e-12));
}

TEST_CASE("a formula's standard error by the delta method matches the hand conversion", "[model][expressions]") {
    // k_m = k_s / (n² eta) with k_s and eta free, their covariance C: the gradient
    // g = (1/(n² eta), −k_s/(n² eta²)) and SE = √(gᵀ C g), worked out by hand.
    const std::vector<std::string> names = {"k_s", "eta", "k_m", "twice"};
    const std::vector<ParameterFormula> expressions = order_parameter_formulas(
        {compile_parameter_formula("2 * k_m", names, 3), compile_parameter_formula("k_s / (3.5^2 * eta)", names, 2)},
        names);
    CHECK(expressions[0].parameter == 2);  // k_m first: twice reads it
    const double ks = 6000.0, eta = 0.93, n2 = 12.25;
    std::vector<double> p = {ks, eta, 0.0, 0.0};
    resolve_parameter_formulas(expressions, p.data());
    CHECK(p[2] == Approx(ks / (n2 * eta)).epsilon(1e-15));
    CHECK(p[3] == Approx(2 * ks / (n2 * eta)).epsilon(1e-15));
    const double s_ks = 180.0, s_eta = 0.0005, r = -0.4;
    const std::vector<std::vector<double>> c = {{s_ks * s_ks, r * s_ks * s_eta}, {r * s_ks * s_eta, s_eta * s_eta}};
    const double g0 = 1.0 / (n2 * eta), g1 = -ks / (n2 * eta * eta);
    const double by_hand = std::sqrt(g0 * g0 * c[0][0] + 2 * g0 * g1 * c[0][1] + g1 * g1 * c[1][1]);
    CHECK(formula_std_error(expressions, 2, p, {0, 1}, c) == Approx(by_hand).epsilon(1e-12));
    CHECK(formula_std_error(expressions, 3, p, {0, 1}, c) == Approx(2 * by_hand).epsilon(1e-12));  // through k_m
    // eta held: only k_s's share
    CHECK(formula_std_error(expressions, 2, p, {0}, {{s_ks * s_ks}}) == Approx(g0 * s_ks).epsilon(1e-12));
    CHECK(std::isnan(formula_std_error(expressions, 0, p, {0, 1}, c)));  // k_s is no formula
}

TEST_CASE("formulas that read each other, unknown names and parameter exponents are refused", "[model][expressions]") {
    const std::vector<std::string> names = {"a", "b", "c"};
    const std::string cycle = refusal([&] {
        order_parameter_formulas({compile_parameter_formula("b + 1", names, 0),
                                     compile_parameter_formula("2 * c", names, 1),
                                     compile_parameter_formula("a / 3", names, 2)},
                                    names);
    });
    CHECK(cycle.find("cycle: a -> b -> c -> a") != std::string::npos);
    CHECK(refusal([&] { compile_parameter_formula("a + a", names, 0); }).find("reads a itself") != std::string::npos);
    CHECK(refusal([&] { compile_parameter_formula("b * q", names, 0); }).find("'q' is not a parameter") !=
          std::string::npos);
    CHECK(refusal([&] { compile_parameter_formula("b ^ c", names, 0); }).find("an exponent must be a number") !=
          std::string::npos);
    CHECK(refusal([&] { compile_parameter_formula("(b + 1", names, 0); }).find("')' is missing") != std::string::npos);
    CHECK(refusal([&] { compile_parameter_formula("b +", names, 0); }).find("the formula ends") != std::string::npos);
    CHECK(refusal([&] { compile_parameter_formula("tan(b)", names, 0); }).find("unknown function 'tan'") !=
          std::string::npos);
    CHECK(refusal([&] { compile_parameter_formula("b c", names, 0); }).find("unexpected 'c'") != std::string::npos);
    // hostile nesting: refused, not a stack overflow
    CHECK(refusal([&] { compile_parameter_formula(std::string(100000, '(') + "b", names, 0); }).find("nested more than") !=
          std::string::npos);
    CHECK(refusal([&] { compile_parameter_formula(std::string(100000, '-') + "b", names, 0); }).find("nested more than") !=
          std::string::npos);
}

}  // namespace TVID_UNITY_ID
