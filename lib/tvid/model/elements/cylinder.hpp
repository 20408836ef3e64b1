#pragma once
// A cylinder of a piston engine on a crank throw (the methodology paper eqs. 2, 4).

#include <cstddef>
#include <string>
#include <vector>

#include "tvid/channels/crank_angle_channels.hpp"
#include "tvid/model/element_source.hpp"
#include "tvid/model/element_traits.hpp"
#include "tvid/model/elements/node_motion.hpp"
#include "tvid/model/field.hpp"
#include "tvid/model/field_bounds.hpp"
#include "tvid/model/slider_crank.hpp"

namespace tvid {

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

namespace elements {

struct Cylinder {
    using Spec = CylinderSpec;
    template <class T>
    struct Bound : OnOneNode {
        int pressure = 0;
        double phase = 0.0;
        T bore, crank_radius, rod_length, mass, p_atm;
        T area;               ///< πB²/4
        bool fixed_geometry;  ///< crank radius and rod length are constants: the kinematics in double
        double r_fixed, l_fixed;
        // Of the last torque evaluation: the lookup cursor and the lever arms s'(φ), s''(φ).
        mutable AngleCursor<T> pressure_cursor{};
        mutable T lever, lever_rate;
    };

    // ---- the experiment file: `{ type: cylinder, node: THROW, pressure: CHANNEL, phase_deg: DEG, bore: B,
    // crank_radius: R, rod_length: L, mass: M, p_atm: P }`
    static constexpr const char* type_name = "cylinder";
    static constexpr const char* summary = "a piston engine cylinder on a crank throw: gas pressure by crank angle and the reciprocating mass (methodology paper eqs. 2, 4)";
    static constexpr const char* keys[] = {"node", "pressure", "phase_deg", "bore", "crank_radius",
                                           "rod_length", "mass", "p_atm"};

    static Spec read(ElementSource& src, const std::string& name) {
        Spec e = spec_at_ends<Cylinder>(src, name);
        e.pressure = src.angle_input("pressure");
        e.phase = src.has("phase_deg") ? src.number("phase_deg") * kPi / 180.0 : 0.0;
        e.bore = src.field("bore");
        e.crank_radius = src.field("crank_radius");
        e.rod_length = src.field("rod_length");
        e.mass = src.field_or("mass", Field::value(0.0));
        e.p_atm = src.field_or("p_atm", Field::value(101325.0));
        return e;
    }

    /// After the sign checks: a slider crank needs a rod longer than its crank.
    static void check(const Spec& e, const FieldBounds& b) {
        if (!b.known(e.crank_radius) || !b.known(e.rod_length)) return;
        if (!(b.highest(e.rod_length) > b.lowest(e.crank_radius))) {
            const bool given = !e.rod_length.is_parameter() && !e.crank_radius.is_parameter();
            b.fail("rod_length", {e.rod_length, e.crank_radius},
                   "the connecting rod must be longer than the crank radius" +
                       (given ? std::string()
                              : " (rod_length " + b.text(e.rod_length) + ", crank_radius " + b.text(e.crank_radius) +
                                    ")"));
        }
    }

    /// f(info, field...) for each numeric field, of each of e... (a spec first, then bound elements) in step.
    template <class F, class... E>
    static void for_each_field(F&& f, E&... e) {
        f(FieldInfo{"bore", "a cylinder dimension", SignRule::positive, "m"}, e.bore...);
        f(FieldInfo{"crank_radius", "a cylinder dimension", SignRule::positive, "m"}, e.crank_radius...);
        f(FieldInfo{"rod_length", "a cylinder dimension", SignRule::positive, "m"}, e.rod_length...);
        f(FieldInfo{"mass", "a reciprocating mass", SignRule::non_negative, "kg"}, e.mass...);
        f(FieldInfo{"p_atm", "an atmospheric pressure", SignRule::positive, "Pa"}, e.p_atm...);
    }

    static constexpr ChannelUse channel{"Pa", true};  ///< a measured cylinder pressure, by crank angle
    static int channel_of(const Spec& s) { return s.pressure; }
    static constexpr ElementOutputs outputs = ElementOutputs::torque;

    /// revolution_mean: the reciprocating mass adds m·mean(s'²) to the throw's inertia, and
    /// neither it nor the gas torque stays in `lin` (their angle-dependent parts average
    /// out); operating_point: the slider crank as it is at the operating point's angle.
    static LinearNote linearise(const Spec& c, Spec& lin, const LinearisationPoint& at) {
        if (at.mode != AngleDependence::revolution_mean)
            return {"operating_point", "slider crank at the operating point's crank angle " +
                                           linear_number(at.angle(c.node) + c.phase) +
                                           " rad: inertia m*s'^2 there, and the gas pressure's slope there as a stiffness"};
        const double added =
            at.value(c.mass) * mean_lever_squared(at.value(c.crank_radius), at.value(c.rod_length));
        at.added_inertia[static_cast<std::size_t>(c.node)] += added;
        lin.mass = Field::value(0.0);
        lin.bore = Field::value(0.0);
        return {"revolution_mean", "reciprocating inertia at its mean over a revolution, m*mean(s'^2) = " +
                                       linear_number(added) + " kg m^2 added to " + at.node_name(c.node) +
                                       "; the gas torque is an excitation (its angle stiffness averages to zero over a cycle)"};
    }

    // ---- the equations of motion

    template <class T>
    static void bind(const Spec& s, Bound<T>& e) {
        e.pressure = s.pressure;
        e.phase = s.phase;
        e.area = T(0.25 * kPi) * e.bore * e.bore;
        e.fixed_geometry = !s.crank_radius.is_parameter() && !s.rod_length.is_parameter();
        e.r_fixed = s.crank_radius.constant;
        e.l_fixed = s.rod_length.constant;
    }

    static constexpr bool acts_at_rest = true;
    static constexpr ElementEnds ends = ElementEnds::one_node;

    /// The gas torque (p − p_atm)·(πB²/4)·s'(φ) (the methodology paper eq. 4, pressure force), with p
    /// the measured pressure at the throw's own angle; keeps s'(φ) and s''(φ) for load().
    template <class T>
    [[gnu::always_inline]] static T torque(const Bound<T>& e, const NodeMotion<T>& m) {
        const T& throw_angle = m.theta[e.node];
        const SliderCrankMotion<T> k = kinematics(e, throw_angle);
        e.lever = k.ds;
        e.lever_rate = k.dds;
        const T pressure = m.angle_inputs->at(static_cast<std::size_t>(e.pressure), throw_angle, e.pressure_cursor);
        return (pressure - e.p_atm) * e.area * k.ds;
    }

    /// The gas torque and the reciprocating mass's −m s' s'' ω² on the throw.
    template <class T>
    [[gnu::always_inline]] static void load(const Bound<T>& e, const T& t, const NodeMotion<T>& m, T* node_torque) {
        node_torque[e.node] += t;
        if (m.moving()) node_torque[e.node] -= e.mass * e.lever * e.lever_rate * m.omega[e.node] * m.omega[e.node];
    }

    /// A throw with a reciprocating mass: (J + Σ m s'(φ)²) θ'' = T (the methodology paper eq. 2 with the
    /// exact piston acceleration); the node's torque already holds −m s' s'' ω².
    template <class T>
    static void correct_accelerations(const std::vector<Bound<T>>& cylinders, const T* inertia, const T* node_torque,
                                      T* acceleration) {
        for (const Bound<T>& c : cylinders) {
            const auto node = static_cast<std::size_t>(c.node);
            T throw_inertia = inertia[node];
            for (const Bound<T>& o : cylinders)
                if (o.node == c.node) throw_inertia += o.mass * o.lever * o.lever;
            acceleration[node] = node_torque[node] / throw_inertia;
        }
    }

private:
    static constexpr double kPi = 3.14159265358979323846;

    // mean over φ of s'(φ)² for crank radius r and rod length l: the reciprocating mass's
    // inertia per kg over a revolution (s' is 2π-periodic; the trapezoid rule on a periodic
    // smooth function converges spectrally).
    static double mean_lever_squared(double r, double l) {
        constexpr int kPoints = 3600;
        constexpr double kTwoPi = 6.283185307179586;
        double sum = 0.0;
        for (int k = 0; k < kPoints; ++k) {
            const double ds = slider_crank(kTwoPi * k / kPoints, r, l).ds;
            sum += ds * ds;
        }
        return sum / kPoints;
    }

    // The slider-crank kinematics at the throw angle (plain numbers for the constant
    // geometry: for a derivative type the same values, with less work).
    template <class T>
    [[gnu::always_inline]] static SliderCrankMotion<T> kinematics(const Bound<T>& e, const T& throw_angle) {
        if (e.fixed_geometry) return slider_crank(throw_angle + e.phase, e.r_fixed, e.l_fixed);
        return slider_crank(throw_angle + e.phase, e.crank_radius, e.rod_length);
    }
};

}  // namespace elements
}  // namespace tvid
