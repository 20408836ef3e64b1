// Forward-mode dual numbers: each operation's derivative against the calculus, the value
// part bit-identical to double, and the model's right-hand side differentiated through
// the templated element code against central differences.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "tvid/model/dual.hpp"
#include "tvid/model/network_model.hpp"
#include "tvid/model/presets.hpp"
#include "tvid/model/slider_crank.hpp"
#include "tvid/model/smooth_clearance.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

TEST_CASE("dual numbers carry exact first derivatives", "[dual]") {
    const Dual x = Dual::variable(0.7, 0, 2), y = Dual::variable(-1.3, 1, 2);
    const Dual f = sin(x) * y + exp(x) / y - sqrt(x) * 3 + 2 / (1 - x) + tanh(y) - log1p(x * x);
    const double xv = 0.7, yv = -1.3;
    const double dfdx = std::cos(xv) * yv + std::exp(xv) / yv - 1.5 / std::sqrt(xv) + 2 / ((1 - xv) * (1 - xv)) -
                        2 * xv / (1 + xv * xv);
    const double dfdy = std::sin(xv) - std::exp(xv) / (yv * yv) + 1 - std::tanh(yv) * std::tanh(yv);
    // The value is the double computation's, with tvid's own sin, exp and log1p.
    double sin_x = 0.0, cos_x = 0.0;
    math::sincos(xv, sin_x, cos_x);
    CHECK(f.value() == sin_x * yv + math::exp(xv) / yv - std::sqrt(xv) * 3 + 2 / (1 - xv) + std::tanh(yv) -
                           math::log1p(xv * xv));
    CHECK(f.derivative(0) == Approx(dfdx).epsilon(1e-14));
    CHECK(f.derivative(1) == Approx(dfdy).epsilon(1e-14));
    CHECK(abs(y).derivative(1) == -1.0);
    CHECK(max(x, y).derivative(0) == 1.0);
    CHECK((x - x).derivative(0) == 0.0);
    // A constant mixed with a variable keeps the variable's directions.
    const Dual c = 4.0;
    CHECK(c.size() == 0);
    CHECK((c * x).size() == 2);
    CHECK((c * x).derivative(0) == 4.0);
}

TEST_CASE("the engine model's right-hand side differentiates through Dual like central differences", "[dual]") {
    const PresetConstants engine = {{"bore", {0.079}}, {"crank_radius", {0.0405}}, {"rod_length", {0.129}},
                                    {"K21", {8.0e4}},  {"Kxx", {3.0e5}},           {"K32", {2.0e5}},
                                    {"p_atm", {101300.0}}};
    const NetworkSpec spec = build_preset("engine_block", engine);
    // A pressure trace against crank angle for the cylinder lookups.
    std::vector<double> angle, pressure;
    for (int i = 0; i <= 1440; ++i) {
        angle.push_back(i * 3.14159265358979 / 180.0 - 10.0);
        pressure.push_back(1e5 + 4e6 * std::exp(-std::pow(std::sin(0.5 * angle.back()), 2) * 20));
    }
    std::vector<std::vector<double>> channels(spec.cylinders.size(), pressure);
    const CrankAngleChannels by_angle(angle, channels);
    const std::vector<double> p = {0.0045, 0.0012, 0.12, 0.45, 0.010, 0.020, 0.025, 2.5, 4.0, 1.5};
    const std::size_t n = spec.nodes.size(), m = p.size();
    std::vector<double> x(2 * n);
    for (std::size_t i = 0; i < n; ++i) {
        x[i] = 1.1 + 0.003 * static_cast<double>(i);
        x[n + i] = 130.0 - 0.4 * static_cast<double>(i);
    }
    NetworkModel<Dual> dual_model(spec);
    dual_model.set_crank_angle_inputs(&by_angle);
    std::vector<Dual> pd(m);
    for (std::size_t j = 0; j < m; ++j) pd[j] = Dual::variable(p[j], static_cast<int>(j), static_cast<int>(m));
    dual_model.set_parameters(pd.data());
    std::vector<Dual> xd(x.begin(), x.end()), fd(2 * n);
    dual_model.derivative(xd.data(), nullptr, fd.data());

    NetworkModel<double> model(spec);
    model.set_crank_angle_inputs(&by_angle);
    std::vector<double> f(2 * n), fp(2 * n), fm(2 * n);
    model.set_parameters(p.data());
    model.derivative(x.data(), nullptr, f.data());
    for (std::size_t i = 0; i < 2 * n; ++i) CHECK(fd[i].value() == f[i]);  // values bit for bit
    for (std::size_t j = 0; j < m; ++j) {
        std::vector<double> q = p;
        const double h = 1e-6 * p[j];
        q[j] = p[j] + h;
        model.set_parameters(q.data());
        model.derivative(x.data(), nullptr, fp.data());
        q[j] = p[j] - h;
        model.set_parameters(q.data());
        model.derivative(x.data(), nullptr, fm.data());
        for (std::size_t i = n; i < 2 * n; ++i) {
            const double numeric = (fp[i] - fm[i]) / (2 * h);
            CHECK(fd[i].derivative(static_cast<int>(j)) == Approx(numeric).epsilon(1e-6).margin(1e-6 * std::abs(f[i])));
        }
    }
}

TEST_CASE("PackedDual numbers give the double values and Dual's derivatives", "[dual]") {
    const Dual x = Dual::variable(0.7, 0, 3), y = Dual::variable(-1.3, 1, 3);
    auto px = PackedDual<4>::variable(0.7, 0), py = PackedDual<4>::variable(-1.3, 1);
    auto f = [](const auto& a, const auto& b) {
        using std::abs, std::max, std::sin, std::cos, std::sqrt;
        return sin(a) * b + exp(a) / b - sqrt(a) * 3 + 2 / (1 - a) + log1p(a * a) - cos(b) / 4.0 + abs(b) * max(a, b) -
               (a - 1.5) * (0.5 + b);
    };
    const Dual d = f(x, y);
    const PackedDual<4> p = f(px, py);
    CHECK(p.value() == d.value());
    for (int i = 0; i < 2; ++i) CHECK(p.derivative(i) == Approx(d.derivative(i)).epsilon(1e-15));
    CHECK(p.derivative(2) == 0.0);
    CHECK(p.derivative(3) == 0.0);
    CHECK(p.all_finite());
    CHECK_FALSE((px / 0.0).all_finite());
}

}  // namespace TVID_UNITY_ID
