#include "tvid/model/presets.hpp"

#include <optional>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace tvid {

namespace {

double constant(const PresetConstants& c, const std::string& key, std::optional<double> fallback = std::nullopt) {
    const auto it = c.find(key);
    if (it == c.end()) {
        if (fallback) return *fallback;
        throw PresetConstantError(key, "missing (the engine_block preset needs it)");
    }
    if (it->second.size() != 1) throw PresetConstantError(key, "expected one number");
    return it->second.front();
}

double positive_constant(const PresetConstants& c, const std::string& key, std::optional<double> fallback = std::nullopt) {
    const double v = constant(c, key, fallback);
    if (!(v > 0)) throw PresetConstantError(key, "must be positive");
    return v;
}

// The usual firing orders; other cylinder counts must give theirs.
std::vector<int> default_firing_order(int cylinders) {
    switch (cylinders) {
        case 1: return {1};
        case 2: return {1, 2};
        case 3: return {1, 2, 3};
        case 4: return {1, 3, 4, 2};
        case 5: return {1, 2, 4, 5, 3};
        case 6: return {1, 5, 3, 6, 2, 4};
        case 8: return {1, 5, 4, 8, 6, 3, 7, 2};
        default: return {};
    }
}

// The methodology paper eqs. 1–4: damping wheel, one throw per cylinder, flywheel, joined by stiff
// shaft sections; friction to ground on every inertia; a cylinder on every throw.
NetworkSpec build_engine_block(const PresetConstants& c) {
    const double count = constant(c, "cylinders", 4.0);
    if (count < 1 || count > 16 || count != std::floor(count))
        throw PresetConstantError("cylinders", "must be a whole number from 1 to 16");
    const int n = static_cast<int>(count);
    std::vector<int> order = default_firing_order(n);
    if (const auto it = c.find("firing_order"); it != c.end()) {
        order.clear();
        for (double v : it->second) order.push_back(static_cast<int>(v));
        std::vector<int> sorted = order;
        std::sort(sorted.begin(), sorted.end());
        bool permutation = static_cast<int>(order.size()) == n;
        for (int i = 0; permutation && i < n; ++i) permutation = sorted[static_cast<std::size_t>(i)] == i + 1;
        for (double v : it->second) permutation = permutation && v == std::floor(v);
        if (!permutation)
            throw PresetConstantError("firing_order", "must list each cylinder 1 … " + std::to_string(n) + " once");
    }
    if (order.empty()) throw PresetConstantError("firing_order", "missing (no default for " + std::to_string(n) + " cylinders)");
    const double bore = positive_constant(c, "bore"), radius = positive_constant(c, "crank_radius");
    const double rod = positive_constant(c, "rod_length");
    if (!(rod > radius)) throw PresetConstantError("rod_length", "must be longer than the crank radius");
    const double k21 = positive_constant(c, "K21"), kxx = positive_constant(c, "Kxx"), k32 = positive_constant(c, "K32");
    const double p_atm = constant(c, "p_atm", 101325.0);

    NetworkSpec net;
    net.preset = "engine_block";
    net.parameter_names = {"J1", "J2", "J3", "m", "C1", "C2", "C3", "C21", "C32", "Cxx"};
    auto p = [&](const char* name) { return Field::param(net.parameter_index(name)); };
    const int wheel = 0, flywheel = n + 1;
    net.nodes.push_back(NodeSpec{"damping_wheel", p("J1"), false});
    for (int i = 1; i <= n; ++i) net.nodes.push_back(NodeSpec{"throw" + std::to_string(i), p("J2"), false});
    net.nodes.push_back(NodeSpec{"flywheel", p("J3"), false});

    net.spring_dampers.push_back(SpringDamperSpec{"wheel_throw1", 1, wheel, Field::value(k21), p("C21")});
    for (int i = 1; i < n; ++i)
        net.spring_dampers.push_back(SpringDamperSpec{"throw" + std::to_string(i) + "_throw" + std::to_string(i + 1),
                                                      i + 1, i, Field::value(kxx), p("Cxx")});
    net.spring_dampers.push_back(SpringDamperSpec{"throw" + std::to_string(n) + "_flywheel", flywheel, n,
                                                  Field::value(k32), p("C32")});
    net.frictions.push_back(FrictionSpec{"friction_wheel", wheel, p("C1")});
    for (int i = 1; i <= n; ++i) net.frictions.push_back(FrictionSpec{"friction_throw" + std::to_string(i), i, p("C2")});
    net.frictions.push_back(FrictionSpec{"friction_flywheel", flywheel, p("C3")});

    // Cylinder at firing position k fires at k·720°/N: its local angle is θ − k·4π/N.
    for (int cyl = 1; cyl <= n; ++cyl) {
        const auto pos = std::find(order.begin(), order.end(), cyl) - order.begin();
        net.angle_input_names.push_back("p_cyl" + std::to_string(cyl));
        CylinderSpec e;
        e.name = "cylinder" + std::to_string(cyl);
        e.node = cyl;
        e.pressure = cyl - 1;
        e.phase = -static_cast<double>(pos) * 4.0 * std::numbers::pi / n;
        e.bore = Field::value(bore);
        e.crank_radius = Field::value(radius);
        e.rod_length = Field::value(rod);
        e.mass = p("m");
        e.p_atm = Field::value(p_atm);
        net.cylinders.push_back(e);
    }
    auto output = [&](const char* name, OutputKind kind, int node) {
        OutputSpec o;
        o.name = name;
        o.kind = kind;
        o.node = node;
        net.outputs.push_back(o);
    };
    output("omega_dw", OutputKind::speed, wheel);
    output("omega_fw", OutputKind::speed, flywheel);
    output("theta_dw", OutputKind::angle, wheel);
    output("theta_fw", OutputKind::angle, flywheel);
    return net;
}

// Yoshida & Takamatsu eqs. 15–16: θ'' = ρ1 (Ttm − Δtm − Fσ(θ, θ')), Tds* = Fσ + Δds.
// As a network: one node with inverse inertia ρ1, the measured input torque with
// amplitude shift Δtm, and a clearance element from the node to ground whose
// transmitted torque Fσ, shifted by Δds, is the output.
NetworkSpec build_cvt_clearance() {
    NetworkSpec net;
    net.preset = "cvt_clearance";
    net.parameter_names = {"rho1", "k_minus", "k_plus", "c_minus", "c_plus",
                           "mu",   "sigma",   "d_ds",   "d_tm"};
    auto p = [&](const char* name) { return Field::param(net.parameter_index(name)); };
    net.input_names = {"Ttm"};
    net.nodes.push_back(NodeSpec{"cvt_input_shaft", p("rho1"), true});
    net.clearances.push_back(ClearanceSpec{"driveline", 0, kGround, p("k_minus"), p("k_plus"),
                                           p("c_minus"), p("c_plus"), p("mu"), p("sigma"), true});
    net.torques.push_back(TorqueSpec{"cvt_input_torque", 0, 0, p("d_tm"), Field::value(1.0)});
    OutputSpec tds;
    tds.name = "Tds";
    tds.kind = OutputKind::torque;
    tds.element = ElementRef{ElementKind::clearance, 0};
    tds.offset = p("d_ds");
    net.outputs.push_back(tds);
    return net;
}

}  // namespace

const std::vector<PresetInfo>& preset_catalogue() {
    static const std::vector<PresetInfo> catalogue = {
        PresetInfo{
            "cvt_clearance",
            "1-DOF CVT drivetrain with a smoothed gear clearance, from CVT input torque Ttm "
            "to driveshaft torque Tds",
            "Yoshida & Takamatsu, PSO-based model identification of a full-scale CVT "
            "drivetrain, eqs. 15-21",
            {"rho1", "k_minus", "k_plus", "c_minus", "c_plus", "mu", "sigma", "d_ds", "d_tm"},
            {"1/(kg m^2)", "N m/rad", "N m/rad", "N m s/rad", "N m s/rad", "rad", "1/rad", "N m",
             "N m"},
            {"inverse inertia 1/I1", "backward-contact stiffness", "forward-contact stiffness",
             "backward-contact damping", "forward-contact damping", "half clearance width",
             "smoothing steepness", "driveshaft torque amplitude shift",
             "CVT input torque amplitude shift"},
            {"Ttm"},
            {"Tds"},
            {},
        },
        PresetInfo{
            "engine_block",
            "piston engine crankshaft at idle: damping wheel, one throw per cylinder, flywheel; "
            "cylinder torque from measured in-cylinder pressure by crank angle (slider-crank, "
            "reciprocating mass with exact piston acceleration)",
            "Methodology for modeling, parameter estimation, and validation of powertrain "
            "torsional vibration, eqs. 1-5",
            {"J1", "J2", "J3", "m", "C1", "C2", "C3", "C21", "C32", "Cxx"},
            {"kg m^2", "kg m^2", "kg m^2", "kg", "N m s/rad", "N m s/rad", "N m s/rad", "N m s/rad", "N m s/rad",
             "N m s/rad"},
            {"damping wheel inertia", "inertia of each crank throw", "flywheel inertia",
             "reciprocating mass per cylinder", "damping wheel friction", "friction of each throw",
             "flywheel friction", "damping wheel - throw 1 damping", "last throw - flywheel damping",
             "damping between neighbouring throws"},
            {"p_cyl1", "...", "p_cylN"},
            {"omega_dw", "omega_fw", "theta_dw", "theta_fw"},
            {"cylinders", "firing_order", "bore", "crank_radius", "rod_length", "K21", "Kxx", "K32", "p_atm"},
        },
    };
    return catalogue;
}

const PresetInfo* find_preset(const std::string& name) {
    for (const auto& p : preset_catalogue())
        if (p.name == name) return &p;
    return nullptr;
}

NetworkSpec build_preset(const std::string& name, const PresetConstants& constants) {
    if (name == "cvt_clearance") return build_cvt_clearance();
    if (name == "engine_block") return build_engine_block(constants);
    throw std::invalid_argument("unknown preset '" + name + "'");
}

}  // namespace tvid
