#pragma once
// The description of a lumped torsional network: named nodes (rotating inertias with
// angle θ and speed ω) joined by elements. Every numeric field of a node or element is
// either a constant or a reference to a model parameter; a `NetworkSpec` is built once
// (from a preset or from the experiment file) and turned into a fast `NetworkModel`
// for each parameter vector.

#include <string>
#include <vector>

namespace tvid {

/// A number fixed in the experiment, or the index of a model parameter.
struct Field {
    double constant = 0.0;
    int parameter = -1;  ///< index into NetworkSpec::parameter_names, or -1 for a constant

    static Field value(double v) { return Field{v, -1}; }
    static Field param(int index) { return Field{0.0, index}; }
    bool is_parameter() const { return parameter >= 0; }
};

inline constexpr int kGround = -1;  ///< node index meaning "the fixed base"

struct NodeSpec {
    std::string name;
    Field inertia;               ///< J [kg m²], or 1/J when `inverse` is set
    bool inverse = false;        ///< the CVT paper estimates ρ1 = 1/I1
};

/// Linear spring and viscous damper between node a and node b (or ground, b = kGround).
/// Torque on a: −k(θa − θb) − c(ωa − ωb); the opposite on b.
struct SpringDamperSpec {
    std::string name;
    int a = 0, b = kGround;
    Field k, c;
};

/// Smoothed impact model with a clearance (Yoshida & Takamatsu eqs. 8–11) on the twist θa − θb.
/// Transmitted torque F = Gσ(θ) + Hσ(θ)·θ'; torque on a is −F, on b +F.
/// `smooth == false` selects the non-smooth law of eq. 7.
struct ClearanceSpec {
    std::string name;
    int a = 0, b = kGround;
    Field k_minus, k_plus, c_minus, c_plus, mu, sigma;
    bool smooth = true;
};

/// Viscous friction to ground on one node: torque −c·ω.
struct FrictionSpec {
    std::string name;
    int node = 0;
    Field c;
};

/// Gear mesh between a and b with ratio n: twist θa − n·θb; mesh torque T = k·twist + c·twist'
/// (or the clearance law when `has_clearance`); torque −T on a and +n·T on b.
struct GearMeshSpec {
    std::string name;
    int a = 0, b = 0;
    Field ratio, k, c;
    bool has_clearance = false;
    Field k_minus, k_plus, c_minus, c_plus, mu, sigma;  ///< used when has_clearance
    bool smooth = true;                                 ///< false: no sigma, eq. 7
};

/// External torque on a node from a measured input channel:
/// T = scale · (u(t) − offset); `offset` is the sensor's amplitude shift (Yoshida & Takamatsu eq. 14).
struct TorqueSpec {
    std::string name;
    int node = 0;
    int input = 0;  ///< index into NetworkSpec::input_names
    Field offset = Field::value(0.0);
    Field scale = Field::value(1.0);
};

/// A cylinder of a piston engine on a crank throw (the methodology paper eqs. 2, 4). Its local crank
/// angle is φ = θ_node + phase (phase = −k·720°/N for firing position k). Torque on the
/// throw: gas (p(θ_node) − p_atm)·(πB²/4)·s'(φ) and reciprocating mass −m·s'(φ)·s̈ with the
/// exact piston acceleration s̈ = s'(φ)·θ'' + s''(φ)·ω²; the θ'' part adds m·s'(φ)² to the
/// throw's inertia. The pressure is a crank-angle channel looked up at the throw's angle.
struct CylinderSpec {
    std::string name;
    int node = 0;
    int pressure = 0;  ///< index into NetworkSpec::angle_input_names
    double phase = 0.0;  ///< [rad]
    Field bore, crank_radius, rod_length, mass, p_atm;
};

enum class ElementKind { spring_damper, clearance, friction, gear_mesh, torque, cylinder };

struct ElementRef {
    ElementKind kind;
    int index;  ///< index into the vector of that kind
};

enum class OutputKind { speed, angle, torque };

/// A model output compared with a measured channel: y = quantity + offset
/// (`offset` is the measurement's amplitude shift, e.g. Δds of Yoshida & Takamatsu eq. 15c).
struct OutputSpec {
    std::string name;
    OutputKind kind = OutputKind::speed;
    int node = 0;              ///< for speed and angle
    ElementRef element{ElementKind::spring_damper, 0};  ///< for torque
    Field offset = Field::value(0.0);
};

struct NetworkSpec {
    std::string preset;                       ///< preset name, or "custom"
    std::vector<std::string> parameter_names; ///< model parameters, Field::parameter indexes these
    std::vector<std::string> input_names;     ///< model inputs by time, TorqueSpec::input indexes these
    std::vector<std::string> angle_input_names; ///< model inputs by crank angle, CylinderSpec::pressure indexes these
    std::vector<NodeSpec> nodes;
    std::vector<SpringDamperSpec> spring_dampers;
    std::vector<ClearanceSpec> clearances;
    std::vector<FrictionSpec> frictions;
    std::vector<GearMeshSpec> gear_meshes;
    std::vector<TorqueSpec> torques;
    std::vector<CylinderSpec> cylinders;
    std::vector<OutputSpec> outputs;          ///< every output the model offers

    int parameter_index(const std::string& name) const;  ///< -1 if absent
    int input_index(const std::string& name) const;
    int output_index(const std::string& name) const;
    int node_index(const std::string& name) const;
    std::size_t state_size() const { return 2 * nodes.size(); }
};

}  // namespace tvid
