#pragma once
// A NetworkSpec bound to one parameter vector: the right-hand side of the equations of
// motion of the lumped torsional network, J_i θ_i'' = Σ torques on node i, written once
// for any scalar type T: double, Dual (sensitivities) or Pack<W> (W parameter vectors at
// once, one per lane). Buffers are sized at construction; `set_parameters`,
// `derivative` and `output` allocate nothing.
//
// State layout: x = [θ_0 … θ_{n−1}, ω_0 … ω_{n−1}].

#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

#include "tvid/model/network_spec.hpp"
#include "tvid/model/slider_crank.hpp"
#include "tvid/model/smooth_clearance.hpp"
#include "tvid/channels/crank_angle_channels.hpp"

namespace tvid {

template <class T>
class NetworkModel {
public:
    explicit NetworkModel(const NetworkSpec& spec)
        : spec_(&spec),
          node_count_(spec.nodes.size()),
          inverse_inertia_(spec.nodes.size()),
          node_torque_(spec.nodes.size()),
          springs_(spec.spring_dampers.size()),
          clearances_(spec.clearances.size()),
          frictions_(spec.frictions.size()),
          gears_(spec.gear_meshes.size()),
          torques_(spec.torques.size()),
          cylinders_(spec.cylinders.size()),
          cylinder_lever_(spec.cylinders.size()),
          pressure_cursor_(spec.cylinders.size(), AngleCursor<T>{}),
          inertia_(spec.nodes.size()),
          output_offsets_(spec.outputs.size()),
          parameters_(spec.parameter_names.size()) {
        const std::size_t counts[6] = {spec.spring_dampers.size(), spec.clearances.size(), spec.frictions.size(),
                                       spec.gear_meshes.size(),    spec.torques.size(),    spec.cylinders.size()};
        std::size_t at = 0;
        for (std::size_t kind = 0; kind < 6; ++kind) {
            first_of_kind_[kind] = at;
            at += counts[kind];
        }
        last_torques_.assign(at, T(0));
    }

    /// The crank-angle channels (cylinder pressures) the cylinders read; must outlive the model.
    void set_crank_angle_inputs(const CrankAngleChannels* channels) { angle_inputs_ = channels; }
    const CrankAngleChannels* crank_angle_inputs() const { return angle_inputs_; }

    std::size_t node_count() const { return node_count_; }
    std::size_t state_size() const { return 2 * node_count_; }
    std::size_t input_count() const { return spec_->input_names.size(); }
    const NetworkSpec& spec() const { return *spec_; }

    /// Resolves every field from the model parameter vector p (NetworkSpec::parameter_names order).
    void set_parameters(const T* p) {
        const NetworkSpec& s = *spec_;
        std::copy_n(p, parameters_.size(), parameters_.begin());
        auto v = [p](const Field& f) { return f.is_parameter() ? p[f.parameter] : T(f.constant); };
        for (std::size_t i = 0; i < node_count_; ++i) {
            const T j = v(s.nodes[i].inertia);
            inverse_inertia_[i] = s.nodes[i].inverse ? j : T(1) / j;
            inertia_[i] = s.nodes[i].inverse ? T(1) / j : j;
        }
        for (std::size_t i = 0; i < springs_.size(); ++i) {
            const auto& e = s.spring_dampers[i];
            springs_[i] = Spring{e.a, e.b, v(e.k), v(e.c)};
        }
        for (std::size_t i = 0; i < clearances_.size(); ++i) {
            const auto& e = s.clearances[i];
            clearances_[i] = Clearance{e.a, e.b,
                                       ClearanceLaw<T>{v(e.k_minus), v(e.k_plus), v(e.c_minus),
                                                       v(e.c_plus), v(e.mu), v(e.sigma), e.smooth}};
        }
        for (std::size_t i = 0; i < frictions_.size(); ++i)
            frictions_[i] = Friction{s.frictions[i].node, v(s.frictions[i].c)};
        for (std::size_t i = 0; i < gears_.size(); ++i) {
            const auto& e = s.gear_meshes[i];
            Gear g{e.a, e.b, v(e.ratio), v(e.k), v(e.c), e.has_clearance, {}};
            if (e.has_clearance)
                g.law = ClearanceLaw<T>{v(e.k_minus), v(e.k_plus), v(e.c_minus),
                                        v(e.c_plus),  v(e.mu),     v(e.sigma), e.smooth};
            gears_[i] = g;
        }
        for (std::size_t i = 0; i < torques_.size(); ++i) {
            const auto& e = s.torques[i];
            torques_[i] = Torque{e.node, e.input, v(e.offset), v(e.scale)};
        }
        for (std::size_t i = 0; i < cylinders_.size(); ++i) {
            const auto& e = s.cylinders[i];
            const T bore = v(e.bore);
            cylinders_[i] = Cylinder{e.node,          e.pressure,  e.phase, T(0.25 * kPi) * bore * bore, v(e.crank_radius),
                                     v(e.rod_length), v(e.mass),   v(e.p_atm),
                                     !e.crank_radius.is_parameter() && !e.rod_length.is_parameter(),
                                     e.crank_radius.constant, e.rod_length.constant};
        }
        for (std::size_t i = 0; i < output_offsets_.size(); ++i)
            output_offsets_[i] = v(s.outputs[i].offset);
    }

    /// The parameter vector last given to set_parameters (zeros before the first call).
    const std::vector<T>& parameters() const { return parameters_; }

    /// dx/dt = f(x, u) with u the input values at the current time.
    void derivative(const T* x, const double* u, T* dxdt) {
        const T* theta = x;
        const T* omega = x + node_count_;
        accumulate_torques(theta, omega, u, node_torque_.data(), true);
        for (std::size_t i = 0; i < node_count_; ++i) {
            dxdt[i] = omega[i];
            dxdt[node_count_ + i] = node_torque_[i] * inverse_inertia_[i];  // θ'' = T / J
        }
        // A throw with a reciprocating mass: (J + Σ m s'(φ)²) θ'' = T (the methodology paper eq. 2 with
        // the exact piston acceleration). The node's torque already holds −m s' s'' ω².
        for (std::size_t c = 0; c < cylinders_.size(); ++c) {
            const std::size_t node = static_cast<std::size_t>(cylinders_[c].node);
            T inertia = inertia_[node];
            for (std::size_t o = 0; o < cylinders_.size(); ++o)
                if (cylinders_[o].node == cylinders_[c].node)
                    inertia += cylinders_[o].mass * cylinder_lever_[o] * cylinder_lever_[o];
            dxdt[node_count_ + node] = node_torque_[node] / inertia;
        }
    }

    /// Net torque on each node with all speeds zero (for the static equilibrium).
    void static_torques(const T* theta, const double* u, T* torque) {
        accumulate_torques(theta, nullptr, u, torque, false);
    }

    /// The offset (amplitude shift) of output k.
    const T& output_offset(std::size_t k) const { return output_offsets_[k]; }

    /// Model output k (NetworkSpec::outputs order) including its offset.
    T output(std::size_t k, const T* x, const double* u) const {
        return output_from(k, x, [&](const ElementRef& ref, const T* theta, const T* omega) {
            return element_torque(ref, theta, omega, u);
        });
    }

    /// Model output k at the state x and inputs u of the last derivative() call: the value
    /// output(k, x, u) computes, with an element's torque taken from that call instead of
    /// evaluating the element again (a simulation that scores every sample needs the
    /// derivative there anyway, as the first stage of its next step).
    T output_after_derivative(std::size_t k, const T* x) const {
        return output_from(k, x, [&](const ElementRef& ref, const T*, const T*) { return last_torque(ref); });
    }

private:
    template <class ElementTorque>
    T output_from(std::size_t k, const T* x, ElementTorque&& torque_of) const {
        const OutputSpec& o = spec_->outputs[k];
        const T* theta = x;
        const T* omega = x + node_count_;
        T y{};
        switch (o.kind) {
            case OutputKind::speed: y = omega[o.node]; break;
            case OutputKind::angle: y = theta[o.node]; break;
            case OutputKind::torque: y = torque_of(o.element, theta, omega); break;
        }
        return y + output_offsets_[k];
    }

    // The torque element `ref` transmitted in the last derivative() call.
    const T& last_torque(const ElementRef& ref) const {
        return last_torques_[first_of_kind_[static_cast<std::size_t>(ref.kind)] + static_cast<std::size_t>(ref.index)];
    }

public:

    /// The torque an element transmits (spring_damper, clearance, gear_mesh: the torque
    /// from a to b; friction: the friction torque c·ω; torque: the applied torque).
    T element_torque(const ElementRef& ref, const T* theta, const T* omega, const double* u) const {
        const auto i = static_cast<std::size_t>(ref.index);
        switch (ref.kind) {
            case ElementKind::spring_damper: {
                const Spring& e = springs_[i];
                return e.k * twist(theta, e.a, e.b) + e.c * twist(omega, e.a, e.b);
            }
            case ElementKind::clearance: {
                const Clearance& e = clearances_[i];
                return e.law.torque(twist(theta, e.a, e.b), twist(omega, e.a, e.b));
            }
            case ElementKind::friction: return frictions_[i].c * omega[frictions_[i].node];
            case ElementKind::gear_mesh: {
                const Gear& e = gears_[i];
                return gear_torque(e, theta[e.a] - e.ratio * theta[e.b], omega[e.a] - e.ratio * omega[e.b]);
            }
            case ElementKind::torque: return torques_[i].scale * (u[torques_[i].input] - torques_[i].offset);
            case ElementKind::cylinder: {  // the gas torque
                const Cylinder& e = cylinders_[i];
                const T& th = theta[e.node];
                return gas_force(e, i, th) * kinematics(e, th).ds;
            }
        }
        return T(0);
    }

private:
    struct Spring { int a, b; T k, c; };
    struct Clearance { int a, b; ClearanceLaw<T> law; };
    struct Friction { int node; T c; };
    struct Gear { int a, b; T ratio, k, c; bool has_clearance; ClearanceLaw<T> law; };
    struct Torque { int node, input; T offset, scale; };
    struct Cylinder {
        int node, pressure;
        double phase;
        T area, r, l, mass, p_atm;
        bool fixed_geometry;  ///< crank radius and rod length are constants: the kinematics in double
        double r_fixed, l_fixed;
    };

    // The slider-crank kinematics of cylinder e at its throw angle (plain numbers for the
    // constant geometry: for a derivative type the same values, with less work).
    static SliderCrankMotion<T> kinematics(const Cylinder& e, const T& throw_angle) {
        if (e.fixed_geometry) return slider_crank(throw_angle + e.phase, e.r_fixed, e.l_fixed);
        return slider_crank(throw_angle + e.phase, e.r, e.l);
    }

    static constexpr double kPi = 3.14159265358979323846;

    // (p − p_atm)·(πB²/4) with p the measured pressure at the throw's own angle.
    T gas_force(const Cylinder& e, std::size_t c, const T& throw_angle) const {
        return (angle_inputs_->at(static_cast<std::size_t>(e.pressure), throw_angle, pressure_cursor_[c]) - e.p_atm) *
               e.area;
    }

    static T twist(const T* q, int a, int b) { return b == kGround ? q[a] : q[a] - q[b]; }

    static T gear_torque(const Gear& e, const T& tw, const T& rate) {
        return e.has_clearance ? e.law.torque(tw, rate) : e.k * tw + e.c * rate;
    }

    // Sums every element's torque on every node. With `with_speed` false the speeds are
    // taken as zero (omega may be null).
    void accumulate_torques(const T* theta, const T* omega, const double* u, T* torque, bool with_speed) const {
        for (std::size_t i = 0; i < node_count_; ++i) torque[i] = T(0);
        auto rate = [&](int a, int b) { return with_speed ? twist(omega, a, b) : T(0); };
        // Each element's transmitted torque is kept (as element_torque() computes it) for
        // output_after_derivative().
        T* kept = with_speed ? last_torques_.data() : nullptr;
        auto keep = [&](const T& t) {
            if (kept) *kept++ = t;
        };
        for (const Spring& e : springs_) {
            const T t = e.k * twist(theta, e.a, e.b) + e.c * rate(e.a, e.b);
            keep(t);
            torque[e.a] -= t;
            if (e.b != kGround) torque[e.b] += t;
        }
        for (const Clearance& e : clearances_) {
            const T t = e.law.torque(twist(theta, e.a, e.b), rate(e.a, e.b));
            keep(t);
            torque[e.a] -= t;
            if (e.b != kGround) torque[e.b] += t;
        }
        if (with_speed)
            for (const Friction& e : frictions_) {
                const T t = e.c * omega[e.node];
                keep(t);
                torque[e.node] -= t;
            }
        for (const Gear& e : gears_) {
            const T tw = theta[e.a] - e.ratio * theta[e.b];
            const T tw_rate = with_speed ? omega[e.a] - e.ratio * omega[e.b] : T(0);
            const T t = gear_torque(e, tw, tw_rate);
            keep(t);
            torque[e.a] -= t;           // mesh torque T on a
            torque[e.b] += e.ratio * t; // and n·T on b
        }
        for (const Torque& e : torques_) {
            const T t = e.scale * (u[e.input] - e.offset);
            keep(t);
            torque[e.node] += t;
        }
        for (std::size_t c = 0; c < cylinders_.size(); ++c) {
            const Cylinder& e = cylinders_[c];
            const T& th = theta[e.node];
            const SliderCrankMotion<T> k = kinematics(e, th);
            cylinder_lever_[c] = k.ds;
            const T gas = gas_force(e, c, th) * k.ds;  // the methodology paper eq. 4, pressure force
            keep(gas);
            torque[e.node] += gas;
            if (with_speed) torque[e.node] -= e.mass * k.ds * k.dds * omega[e.node] * omega[e.node];  // −m s' s'' ω²
        }
    }

    const NetworkSpec* spec_;
    std::size_t node_count_;
    std::vector<T> inverse_inertia_;
    std::vector<T> node_torque_;
    std::vector<Spring> springs_;
    std::vector<Clearance> clearances_;
    std::vector<Friction> frictions_;
    std::vector<Gear> gears_;
    std::vector<Torque> torques_;
    std::vector<Cylinder> cylinders_;
    mutable std::vector<T> cylinder_lever_;              ///< s'(φ) of each cylinder at the last evaluation
    mutable std::vector<AngleCursor<T>> pressure_cursor_;  ///< lookup cursors, one per cylinder (and lane)
    std::vector<T> inertia_;
    const CrankAngleChannels* angle_inputs_ = nullptr;
    std::vector<T> output_offsets_;
    std::vector<T> parameters_;  ///< copy of the last set_parameters argument
    /// Where each element kind starts in last_torques_ (ElementKind order: spring_damper,
    /// clearance, friction, gear_mesh, torque, cylinder, as accumulate_torques keeps them).
    std::array<std::size_t, 6> first_of_kind_{};
    mutable std::vector<T> last_torques_;  ///< every element's torque in the last derivative() call
};

}  // namespace tvid
