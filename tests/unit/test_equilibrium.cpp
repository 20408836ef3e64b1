// Static equilibrium (Yoshida & Takamatsu eq. 18) of one- and several-node networks.
#include <catch2/catch.hpp>

#include <cmath>

#include "tvid/model/damped_newton.hpp"
#include "tvid/model/equilibrium.hpp"
#include "tvid/model/presets.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {
const std::vector<double> kTableI = {1.42855, 2947.91, 8700.64, 4.10333, 19.2283, 3.55701e-3, 1132.81, -7.40521, 12.9998};
}

TEST_CASE("CVT equilibrium balances the shifted input torque", "[equilibrium]") {
    const NetworkSpec spec = build_preset("cvt_clearance", {});
    NetworkModel<double> model(spec);
    model.set_parameters(kTableI.data());
    const ClearanceLaw<double> law{2947.91, 8700.64, 4.10333, 19.2283, 3.55701e-3, 1132.81, true};
    for (double ttm : {-500.0, -20.0, 11.0, 12.9998, 13.5, 40.0, 90.0, 2000.0}) {
        const double u = ttm;
        const EquilibriumResult eq = solve_equilibrium(model, &u);
        REQUIRE(eq.found);
        REQUIRE(eq.theta.size() == 1);
        // F(θ̄, 0) = Ttm − Δtm (eq. 15a at rest).
        CHECK(law.torque(eq.theta[0], 0.0) == Approx(ttm - 12.9998).margin(1e-9));
        if (ttm > 12.9998 + 1) CHECK(eq.theta[0] > 3.55701e-3);   // forward contact
        if (ttm < 12.9998 - 1) CHECK(eq.theta[0] < -3.55701e-3);  // backward contact
    }
    // Steep smoothing: a nearly flat deadband still gives the unique root.
    std::vector<double> steep = kTableI;
    steep[6] = 1e5;
    model.set_parameters(steep.data());
    const double u = 12.9998;
    const EquilibriumResult eq = solve_equilibrium(model, &u);
    REQUIRE(eq.found);
    CHECK(std::abs(eq.theta[0]) < 3.55701e-3);
}

TEST_CASE("a chain of springs to ground settles where the static torques vanish", "[equilibrium]") {
    // ground -k1- n0 -k2- n1 -k3- n2, torque T on n2: every spring carries T.
    NetworkSpec spec;
    spec.input_names = {"T"};
    for (int i = 0; i < 3; ++i) spec.nodes.push_back(NodeSpec{"n" + std::to_string(i), Field::value(1.0), false});
    spec.spring_dampers.push_back(SpringDamperSpec{"k1", 0, kGround, Field::value(100.0), Field::value(1.0)});
    spec.spring_dampers.push_back(SpringDamperSpec{"k2", 1, 0, Field::value(50.0), Field::value(1.0)});
    spec.spring_dampers.push_back(SpringDamperSpec{"k3", 2, 1, Field::value(25.0), Field::value(1.0)});
    spec.torques.push_back(TorqueSpec{"drive", 2, 0, Field::value(0.0), Field::value(1.0)});
    NetworkModel<double> model(spec);
    model.set_parameters(nullptr);
    const double t = 10.0;
    const EquilibriumResult eq = solve_equilibrium(model, &t);
    REQUIRE(eq.found);
    CHECK(eq.theta[0] == Approx(10.0 / 100.0));
    CHECK(eq.theta[1] == Approx(10.0 / 100.0 + 10.0 / 50.0));
    CHECK(eq.theta[2] == Approx(10.0 / 100.0 + 10.0 / 50.0 + 10.0 / 25.0));
}

TEST_CASE("a network without elastic ground connection has no equilibrium", "[equilibrium]") {
    NetworkSpec spec;
    spec.input_names = {"T"};
    spec.nodes.push_back(NodeSpec{"a", Field::value(1.0), false});
    spec.nodes.push_back(NodeSpec{"b", Field::value(1.0), false});
    spec.spring_dampers.push_back(SpringDamperSpec{"s", 0, 1, Field::value(10.0), Field::value(0.0)});
    NetworkModel<double> model(spec);
    model.set_parameters(nullptr);
    const double t = 1.0;
    const EquilibriumResult eq = solve_equilibrium(model, &t);
    CHECK_FALSE(eq.found);
    CHECK(eq.problem.find("singular") != std::string::npos);
}

TEST_CASE("the missing ground connection is named, with the starts that need none", "[equilibrium]") {
    // a -s- b, and c held to ground: a and b float together.
    NetworkSpec spec;
    spec.input_names = {"T"};
    for (const char* name : {"a", "b", "c"}) spec.nodes.push_back(NodeSpec{name, Field::value(1.0), false});
    spec.spring_dampers.push_back(SpringDamperSpec{"s", 0, 1, Field::value(10.0), Field::value(0.0)});
    spec.spring_dampers.push_back(SpringDamperSpec{"g", 2, kGround, Field::value(10.0), Field::value(0.0)});
    NetworkModel<double> model(spec);
    model.set_parameters(nullptr);
    const double t = 1.0;
    const EquilibriumResult eq = solve_equilibrium(model, &t);
    CHECK_FALSE(eq.found);
    CHECK(eq.problem.find("nodes a and b have no elastic connection to ground") != std::string::npos);
    CHECK(eq.problem.find("steady") != std::string::npos);
    CHECK(eq.problem.find("measured") != std::string::npos);
}

TEST_CASE("the shared damped Newton converges to rounding and steps by one rule", "[equilibrium]") {
    CHECK(state_difference_step(0.0) == 1e-7);
    CHECK(state_difference_step(-1000.0) == Approx(1e-7 + 1e-7));
    // x² = 2 and y = x·3: converged to the last bits.
    NewtonSystem system;
    system.residual = [](const Eigen::VectorXd& z, Eigen::VectorXd& g) {
        g[0] = z[0] * z[0] - 2.0;
        g[1] = z[1] - 3.0 * z[0];
    };
    system.state_value = [](Eigen::Index j, const Eigen::VectorXd& z) { return z[j]; };
    Eigen::VectorXd start(2);
    start << 1.0, 0.0;
    const NewtonResult r = solve_damped_newton(system, start);
    REQUIRE(r.status == NewtonStatus::converged);
    CHECK(r.z[0] == Approx(std::sqrt(2.0)).epsilon(1e-15));
    CHECK(r.z[1] == Approx(3.0 * std::sqrt(2.0)).epsilon(1e-15));
    // A residual that does not depend on the second unknown: singular, and that unknown named.
    system.residual = [](const Eigen::VectorXd& z, Eigen::VectorXd& g) {
        g[0] = z[0] - 1.0;
        g[1] = 2.0 * z[0];
    };
    const NewtonResult s = solve_damped_newton(system, start);
    CHECK(s.status == NewtonStatus::singular);
    REQUIRE(s.free_unknowns.size() == 2);
    CHECK(s.free_unknowns[0] == 0);
    CHECK(s.free_unknowns[1] == 1);
}

}  // namespace TVID_UNITY_ID
