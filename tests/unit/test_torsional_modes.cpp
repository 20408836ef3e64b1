// Linearisation, modes and the model's frequency response against hand-derived results.

#include <Eigen/Eigenvalues>
#include <catch2/catch.hpp>
#include <cmath>
#include <complex>

#include "tvid/analysis/linear_network.hpp"
#include "tvid/analysis/torsional_modes.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

constexpr double kTwoPi = 6.283185307179586;

NodeSpec node(const std::string& name, double j) { return NodeSpec{name, Field::value(j), false}; }

SpringDamperSpec spring(const std::string& name, int a, int b, double k, double c) {
    SpringDamperSpec s;
    s.name = name;
    s.a = a;
    s.b = b;
    s.k = Field::value(k);
    s.c = Field::value(c);
    return s;
}

ModalAnalysis modes_of(const NetworkSpec& spec) {
    const std::vector<double> x(spec.state_size(), 0.0), u(spec.input_names.size() + spec.input_rates.size(), 0.0);
    const LinearNetwork sys = linearise_network(spec, {}, nullptr, x, u, AngleDependence::revolution_mean);
    return torsional_modes(sys, node_ratios(spec, {}, 0), 0);
}

bool close(double a, double b, double rel) { return std::abs(a - b) <= rel * std::abs(b); }

}  // namespace

TEST_CASE("two inertias on ground springs with a spring-damper between them: the analytic modes", "[modes]") {
    // Equal inertias J, each on a ground spring k0, joined by k and c. In phase (θ1 = θ2) the
    // coupling is idle: ω² = k0/J, ζ = 0. In antiphase, φ = θ1 − θ2 obeys
    // J φ'' + 2c φ' + (k0 + 2k) φ = 0: ω_n² = (k0 + 2k)/J, ζ = 2c/(2 J ω_n).
    const double j = 0.5, k0 = 200.0, k = 300.0, c = 2.0;
    NetworkSpec spec;
    spec.nodes = {node("a", j), node("b", j)};
    spec.spring_dampers = {spring("ga", 0, kGround, k0, 0.0), spring("gb", 1, kGround, k0, 0.0),
                           spring("ab", 0, 1, k, c)};
    const ModalAnalysis m = modes_of(spec);
    REQUIRE(m.modes.size() == 2);
    REQUIRE_FALSE(m.free_rotation);
    const double w1 = std::sqrt(k0 / j), w2 = std::sqrt((k0 + 2 * k) / j);
    const double zeta2 = c / (j * w2);
    CHECK(m.modes[0].kind == ModeKind::oscillating);
    CHECK(close(m.modes[0].frequency_hz, w1 / kTwoPi, 1e-9));
    CHECK(m.modes[0].damping_ratio == 0.0);  // undamped: exactly, not a rounding's ±1e-11
    CHECK(close(m.modes[1].frequency_hz, w2 / kTwoPi, 1e-9));
    CHECK(close(m.modes[1].damping_ratio, zeta2, 1e-9));
    CHECK(close(m.modes[1].damped_frequency_hz, w2 * std::sqrt(1 - zeta2 * zeta2) / kTwoPi, 1e-9));
    // Shapes: in phase (1, 1), antiphase (1, −1).
    CHECK(std::abs(m.modes[0].shape[0] - m.modes[0].shape[1]) < 1e-9);
    CHECK(std::abs(m.modes[1].shape[0] + m.modes[1].shape[1]) < 1e-9);
}

TEST_CASE("two inertias, one on a ground spring: roots of the characteristic polynomial", "[modes]") {
    // det(λ²M + λC + K) = (J1λ² + cλ + k0 + k)(J2λ² + cλ + k) − (cλ + k)²; undamped, the
    // frequencies solve J1J2 ω⁴ − (J1 k + J2 (k0 + k)) ω² + k0 k = 0.
    const double j1 = 0.03, j2 = 0.12, k0 = 900.0, k = 400.0;
    for (const double c : {0.0, 0.8}) {
        NetworkSpec spec;
        spec.nodes = {node("a", j1), node("b", j2)};
        spec.spring_dampers = {spring("ground", 0, kGround, k0, 0.0), spring("ab", 0, 1, k, c)};
        const ModalAnalysis m = modes_of(spec);
        REQUIRE(m.modes.size() == 2);
        for (const TorsionalMode& mode : m.modes) {
            const std::complex<double> l = mode.eigenvalue;
            const std::complex<double> p = (j1 * l * l + c * l + k0 + k) * (j2 * l * l + c * l + k) - (c * l + k) * (c * l + k);
            CHECK(std::abs(p) <= 1e-9 * (k0 + k) * k);
            if (c == 0.0)
                CHECK(mode.damping_ratio == 0.0);  // undamped: not the rounding of Re λ
            else
                CHECK(close(mode.damping_ratio, -l.real() / std::abs(l), 1e-12));
        }
        if (c == 0.0) {
            const double a = j1 * j2, b = j1 * k + j2 * (k0 + k), cc = k0 * k;
            const double lo = (b - std::sqrt(b * b - 4 * a * cc)) / (2 * a), hi = (b + std::sqrt(b * b - 4 * a * cc)) / (2 * a);
            CHECK(close(m.modes[0].frequency_hz, std::sqrt(lo) / kTwoPi, 1e-9));
            CHECK(close(m.modes[1].frequency_hz, std::sqrt(hi) / kTwoPi, 1e-9));
        } else {
            CHECK(m.modes[0].damping_ratio > 0.0);
            CHECK(m.modes[1].damping_ratio > 0.0);
        }
    }
}

TEST_CASE("a geared three-node line matches the generalized eigenproblem K phi = w^2 M phi", "[modes]") {
    // Node 0 on a ground spring kg; a gear mesh of ratio n from 0 to 1 (twist θ0 − nθ1,
    // stiffness km); a shaft ks from 1 to 2. Potential ½kg θ0² + ½km (θ0 − nθ1)² + ½ks (θ1 − θ2)².
    const double j0 = 0.02, j1 = 0.005, j2 = 0.1, kg = 1000.0, n = 2.5, km = 5000.0, ks = 800.0;
    NetworkSpec spec;
    spec.nodes = {node("input", j0), node("output", j1), node("load", j2)};
    spec.spring_dampers = {spring("mount", 0, kGround, kg, 0.0), spring("shaft", 1, 2, ks, 0.0)};
    GearMeshSpec g;
    g.name = "mesh";
    g.a = 0;
    g.b = 1;
    g.ratio = Field::value(n);
    g.k = Field::value(km);
    g.c = Field::value(0.0);
    spec.gear_meshes = {g};
    const ModalAnalysis m = modes_of(spec);

    Eigen::Matrix3d kmat, mmat = Eigen::Vector3d(j0, j1, j2).asDiagonal();
    kmat << kg + km, -n * km, 0.0, -n * km, n * n * km + ks, -ks, 0.0, -ks, ks;
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix3d> ref(kmat, mmat);
    REQUIRE(m.modes.size() == 3);
    for (int i = 0; i < 3; ++i) {
        const TorsionalMode& mode = m.modes[static_cast<std::size_t>(i)];
        CHECK(mode.kind == ModeKind::oscillating);
        CHECK(close(mode.frequency_hz, std::sqrt(ref.eigenvalues()[i]) / kTwoPi, 1e-9));
        CHECK(mode.damping_ratio == 0.0);
        Eigen::Vector3d phi = ref.eigenvectors().col(i);
        Eigen::Index largest;
        phi.cwiseAbs().maxCoeff(&largest);
        phi /= phi[largest];
        for (int r = 0; r < 3; ++r) {
            CHECK(std::abs(mode.shape[static_cast<std::size_t>(r)] - phi[r]) < 1e-7);
        }
        // Referred to the input shaft: nodes 1 and 2 turn 1/n as fast, so their angle counts n times.
        const std::complex<double> ratio12 = mode.shape_common[1] / mode.shape_common[0];
        CHECK(std::abs(ratio12 - n * phi[1] / phi[0]) < 1e-6 * std::abs(n * phi[1] / phi[0]) + 1e-9);
    }
}

TEST_CASE("a line free of ground reports a rigid-body mode", "[modes]") {
    // Two inertias and a spring, geared: the rigid rotation (θ0, θ1) = (1, 1/n) is free;
    // the twisting mode has ω² = km (1/j0 + n²/j1) (reduced to the twist θ0 − nθ1).
    const double j0 = 0.01, j1 = 0.2, n = 3.0, km = 2000.0;
    NetworkSpec spec;
    spec.nodes = {node("motor", j0), node("load", j1)};
    GearMeshSpec g;
    g.name = "mesh";
    g.a = 0;
    g.b = 1;
    g.ratio = Field::value(n);
    g.k = Field::value(km);
    g.c = Field::value(0.0);
    spec.gear_meshes = {g};
    FrictionSpec f;
    f.name = "bearing";
    f.a = 1;
    f.c = Field::value(0.05);
    spec.frictions = {f};
    const ModalAnalysis m = modes_of(spec);
    CHECK(m.free_rotation);
    REQUIRE(m.modes.size() >= 2);
    CHECK(m.modes[0].kind == ModeKind::rigid_body);
    // On the motor's shaft the rigid body turns alike everywhere.
    CHECK(std::abs(m.modes[0].shape_common[0] - m.modes[0].shape_common[1]) < 1e-6);
    const TorsionalMode& twist = m.modes.back();
    CHECK(twist.kind == ModeKind::oscillating);
    CHECK(close(twist.frequency_hz, std::sqrt(km * (1 / j0 + n * n / j1)) / kTwoPi, 1e-5));  // the bearing shifts it by ~1e-7
    int rigid = 0;
    for (const TorsionalMode& mode : m.modes) rigid += mode.kind == ModeKind::rigid_body;
    CHECK(rigid == 2);  // the angle (λ = 0) and the speed's decay under the bearing's friction
}

TEST_CASE("the FRF of a spring-mass-damper is 1/(k - J w^2 + i c w)", "[modes]") {
    const double j = 0.4, k = 1.0e4, c = 3.0;
    NetworkSpec spec;
    spec.nodes = {node("mass", j)};
    spec.spring_dampers = {spring("mount", 0, kGround, k, c)};
    spec.input_names = {"T"};
    TorqueSpec t;
    t.name = "drive";
    t.node = 0;
    t.input = 0;
    spec.torques = {t};
    OutputSpec angle;
    angle.name = "theta";
    angle.kind = OutputKind::angle;
    angle.node = 0;
    spec.outputs = {angle};
    const LinearNetwork sys = linearise_network(spec, {}, nullptr, {0.0, 0.0}, {0.0}, AngleDependence::revolution_mean);
    const std::vector<double> f{0.5, 10.0, std::sqrt(k / j) / kTwoPi, 40.0, 200.0};
    const auto h = frequency_response(sys, 0, 0, f);
    for (std::size_t i = 0; i < f.size(); ++i) {
        const double w = kTwoPi * f[i];
        const std::complex<double> expected = 1.0 / std::complex<double>(k - j * w * w, c * w);
        CHECK(std::abs(h[i] - expected) <= 1e-9 * std::abs(expected));
    }
}

TEST_CASE("a prescribed speed's FRF includes its slope: H = (k + i w c) i w J / (k - J w^2 + i w c)", "[modes]") {
    // Node 0 turns at the input speed w; a spring-damper (k, c) drives node 1 (J). The torque
    // in the spring-damper per unit speed: θ0 = w/(iω), θ1 = (k + iωc) θ0 / (k − Jω² + iωc).
    const double j = 0.05, k = 800.0, c = 0.4;
    NetworkSpec spec;
    spec.nodes = {node("drive", 1.0), node("load", j)};
    spec.spring_dampers = {spring("shaft", 0, 1, k, c)};
    spec.input_names = {"w"};
    spec.input_rates = {0};
    SpeedSourceSpec s;
    s.name = "motor";
    s.node = 0;
    s.input = 0;
    s.rate = 1;
    spec.speed_sources = {s};
    OutputSpec torque;
    torque.name = "T";
    torque.kind = OutputKind::torque;
    torque.element = ElementRef{ElementKind::spring_damper, 0};
    spec.outputs = {torque};
    const LinearNetwork sys =
        linearise_network(spec, {}, nullptr, {0.0, 0.0, 10.0, 10.0}, {10.0, 0.0}, AngleDependence::revolution_mean);
    CHECK(sys.A.rows() == 3);  // the drive's speed is the input's
    const std::vector<double> f{1.0, 5.0, 20.0, 100.0};
    const auto h = frequency_response(sys, 0, 0, f);
    for (std::size_t i = 0; i < f.size(); ++i) {
        const double w = kTwoPi * f[i];
        const std::complex<double> iw(0.0, w);
        const std::complex<double> expected = (k + iw * c) * iw * j / (k - j * w * w + iw * c);
        CHECK(std::abs(h[i] - expected) <= 1e-7 * std::abs(expected));
    }
}

TEST_CASE("a cylinder's reciprocating mass enters at its mean over a revolution, m r^2/2 for a long rod", "[modes]") {
    // With l >> r, s'(φ) = r sin φ, so mean(s'²) = r²/2: a throw J on a ground spring k with a
    // reciprocating mass m turns at ω² = k / (J + m r²/2). The gas torque (constant pressure
    // here) is an excitation and adds no stiffness.
    const double j = 0.01, k = 5.0e4, m = 0.5, r = 0.04, l = 4.0e5;
    NetworkSpec spec;
    spec.nodes = {node("throw", j)};
    spec.spring_dampers = {spring("shaft", 0, kGround, k, 0.0)};
    spec.angle_input_names = {"p"};
    CylinderSpec c;
    c.name = "cylinder1";
    c.node = 0;
    c.pressure = 0;
    c.bore = Field::value(0.08);
    c.crank_radius = Field::value(r);
    c.rod_length = Field::value(l);
    c.mass = Field::value(m);
    c.p_atm = Field::value(1.0e5);
    spec.cylinders = {c};
    const CrankAngleChannels pressure({-100.0, 100.0}, {{3.0e5, 3.0e5}});
    const std::vector<double> x{0.3, 0.0};
    const LinearNetwork mean = linearise_network(spec, {}, &pressure, x, {}, AngleDependence::revolution_mean);
    const ModalAnalysis modes = torsional_modes(mean, {1.0}, 0);
    REQUIRE(modes.modes.size() == 1);
    CHECK(close(modes.modes[0].frequency_hz, std::sqrt(k / (j + m * r * r / 2)) / kTwoPi, 1e-8));
    REQUIRE(mean.elements.size() == 2);
    CHECK(mean.elements[1].method == "revolution_mean");
    // At the operating point θ = 0.3 rad: T(θ) = −kθ + P·A·r sin θ (P = p − p_atm, the gas
    // torque's lever r sin θ) over J(θ) = J + m (r sin θ)², so at ω = 0
    // ∂θ''/∂θ = T'/J(θ) − T·J'(θ)/J(θ)², and the frequency is √(−∂θ''/∂θ)/2π.
    const LinearNetwork at = linearise_network(spec, {}, &pressure, x, {}, AngleDependence::operating_point);
    const double th = 0.3, p = 3.0e5 - 1.0e5, area = 0.25 * 3.14159265358979323846 * 0.08 * 0.08;
    const double torque = -k * th + p * area * r * std::sin(th), torque_slope = -k + p * area * r * std::cos(th);
    const double inertia = j + m * std::pow(r * std::sin(th), 2), inertia_slope = 2 * m * r * r * std::sin(th) * std::cos(th);
    const double slope = torque_slope / inertia - torque * inertia_slope / (inertia * inertia);
    const ModalAnalysis point = torsional_modes(at, {1.0}, 0);
    REQUIRE(point.modes.size() == 1);
    CHECK(close(point.modes[0].frequency_hz, std::sqrt(-slope) / kTwoPi, 1e-6));
    CHECK(at.elements[1].method == "operating_point");
}

TEST_CASE("an overdamped degree of freedom is one mode with its real zeta > 1", "[modes]") {
    // J θ'' + c θ' + k θ = 0 with c² > 4Jk: two real roots λ1,2 = (−c ± √(c² − 4Jk))/(2J),
    // ω_n = √(k/J), ζ = c/(2√(kJ)) > 1.
    const double j = 0.2, k = 50.0, c = 30.0;  // ζ = 30/(2·√10) = 4.743
    NetworkSpec spec;
    spec.nodes = {node("a", j)};
    spec.spring_dampers = {spring("ground", 0, kGround, k, c)};
    const ModalAnalysis m = modes_of(spec);
    REQUIRE(m.modes.size() == 1);
    const TorsionalMode& mode = m.modes[0];
    CHECK(mode.kind == ModeKind::overdamped);
    const double zeta = c / (2.0 * std::sqrt(k * j)), wn = std::sqrt(k / j);
    CHECK(close(mode.damping_ratio, zeta, 1e-9));
    CHECK(mode.damping_ratio > 1.0);
    CHECK(close(mode.frequency_hz, wn / kTwoPi, 1e-9));
    CHECK(mode.damped_frequency_hz == 0.0);
    const double disc = std::sqrt(c * c - 4 * j * k);
    CHECK(close(mode.eigenvalue.real(), (-c + disc) / (2 * j), 1e-9));  // the slower root
    CHECK(close(mode.second_eigenvalue, (-c - disc) / (2 * j), 1e-9));  // the faster
}

TEST_CASE("an overdamped mode beside an oscillating one: each keeps its own zeta", "[modes]") {
    // Two uncoupled single-degree-of-freedom systems: a heavily damped one and a lightly damped one.
    const double j1 = 0.1, k1 = 40.0, c1 = 12.0, j2 = 0.05, k2 = 2000.0, c2 = 0.5;
    NetworkSpec spec;
    spec.nodes = {node("slow", j1), node("fast", j2)};
    spec.spring_dampers = {spring("g1", 0, kGround, k1, c1), spring("g2", 1, kGround, k2, c2)};
    const ModalAnalysis m = modes_of(spec);
    REQUIRE(m.modes.size() == 2);
    const TorsionalMode& over = m.modes[0].kind == ModeKind::overdamped ? m.modes[0] : m.modes[1];
    const TorsionalMode& osc = m.modes[0].kind == ModeKind::overdamped ? m.modes[1] : m.modes[0];
    REQUIRE(over.kind == ModeKind::overdamped);
    REQUIRE(osc.kind == ModeKind::oscillating);
    CHECK(close(over.damping_ratio, c1 / (2 * std::sqrt(k1 * j1)), 1e-9));
    CHECK(close(osc.damping_ratio, c2 / (2 * std::sqrt(k2 * j2)), 1e-9));
    CHECK(std::isnan(osc.second_eigenvalue));
    CHECK(std::abs(over.shape[1]) < 1e-9);  // the overdamped motion leaves the other node still
}

}  // namespace TVID_UNITY_ID
