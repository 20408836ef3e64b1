#include "tvid/model/presets.hpp"

#include <stdexcept>

namespace tvid {

namespace {

// Seed 001 eqs. 15–16: θ'' = ρ1 (Ttm − Δtm − Fσ(θ, θ')), Tds* = Fσ + Δds.
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
    };
    return catalogue;
}

const PresetInfo* find_preset(const std::string& name) {
    for (const auto& p : preset_catalogue())
        if (p.name == name) return &p;
    return nullptr;
}

NetworkSpec build_preset(const std::string& name, const std::map<std::string, double>& constants) {
    (void)constants;
    if (name == "cvt_clearance") return build_cvt_clearance();
    throw std::invalid_argument("unknown preset '" + name + "'");
}

}  // namespace tvid
