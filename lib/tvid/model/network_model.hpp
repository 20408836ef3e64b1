#pragma once
// A NetworkSpec bound to one parameter vector: the right-hand side of the equations of
// motion of the lumped torsional network, J_i θ_i'' = Σ torques on node i, written once
// for any scalar type T: double, Dual (sensitivities) or Pack<W> (W parameter vectors at
// once, one per lane). Each element kind's torque and how it loads its nodes are in its
// file under elements/; this class stores the bound elements of every kind of
// elements/element_kinds.hpp and sums their torques in the table's order. Buffers are
// sized at construction; `set_parameters`, `derivative` and `output` allocate nothing.
//
// State layout: x = [θ_0 … θ_{n−1}, ω_0 … ω_{n−1}].

#include <algorithm>
#include <array>
#include <cstddef>
#include <tuple>
#include <vector>

#include "tvid/channels/crank_angle_channels.hpp"
#include "tvid/model/elements/node_motion.hpp"
#include "tvid/model/network_spec.hpp"
#include "tvid/model/rigid_gears.hpp"

namespace tvid {

template <class T>
class NetworkModel {
    template <class Kind>
    using BoundList = std::vector<typename Kind::template Bound<T>>;

    template <class Types>
    struct StorageOf;
    template <class... Kinds>
    struct StorageOf<std::tuple<Kinds...>> {
        using type = std::tuple<BoundList<Kinds>...>;
    };

public:
    explicit NetworkModel(const NetworkSpec& spec)
        : spec_(&spec),
          node_count_(spec.nodes.size()),
          inverse_inertia_(spec.nodes.size()),
          node_torque_(spec.nodes.size()),
          inertia_(spec.nodes.size()),
          seen_speeds_(spec.nodes.size()),
          other_torques_(spec.nodes.size()),
          output_offsets_(spec.outputs.size()),
          output_gains_(spec.outputs.size()),
          parameters_(spec.parameter_names.size()),
          rigid_(plan_rigid_gears(spec)) {
        for_each_element_kind([&](auto kind) {
            using Kind = decltype(kind);
            elements_of<Kind>().resize(ElementRow<Kind>::list(spec).size());
        });
        const auto counts = element_counts(spec);
        std::size_t at = 0;
        for (std::size_t kind = 0; kind < kElementKindCount; ++kind) {
            first_of_kind_[kind] = at;
            at += counts[kind];
        }
        last_torques_.assign(at, T(0));
        prescribes_motion_ = prescribes_motion(spec);
        samples_ = has_sampled_elements(spec);
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
        // A parameter given by a formula of others (parameter_formula.hpp) takes its value here.
        resolve_parameter_formulas(s.parameter_formulas, parameters_.data());
        auto v = [this](const Field& f) { return f.is_parameter() ? parameters_[static_cast<std::size_t>(f.parameter)] : T(f.constant); };
        for (std::size_t i = 0; i < node_count_; ++i) {
            const T j = v(s.nodes[i].inertia);
            inverse_inertia_[i] = s.nodes[i].inverse ? j : T(1) / j;
            inertia_[i] = s.nodes[i].inverse ? T(1) / j : j;
        }
        for_each_element_kind([&](auto kind) {
            using Kind = decltype(kind);
            const auto& specs = ElementRow<Kind>::list(s);
            auto& bound = elements_of<Kind>();
            for (std::size_t i = 0; i < bound.size(); ++i) {
                Kind::for_each_field([&](const FieldInfo&, const Field& field, T& value) { value = v(field); },
                                     specs[i], bound[i]);
                bind_ends<Kind>(specs[i], bound[i]);
                if constexpr (requires { Kind::bind(specs[i], bound[i]); }) Kind::bind(specs[i], bound[i]);
            }
        });
        rigid_.set_ratios(elements_of<elements::IdealGear>());
        for (std::size_t i = 0; i < output_offsets_.size(); ++i) {
            output_offsets_[i] = v(s.outputs[i].offset);
            output_gains_[i] = v(s.outputs[i].gain);
        }
    }

    /// The parameter vector last given to set_parameters, its formulas resolved (zeros before the first call).
    const std::vector<T>& parameters() const { return parameters_; }

    /// dx/dt = f(x, u) with u the input values at the current time.
    void derivative(const T* x, const double* u, T* dxdt) {
        const T* omega = speeds_seen(x, u);
        accumulate_torques(NodeMotion<T>{x, omega, u, angle_inputs_, true}, node_torque_.data(), last_torques_.data());
        for (std::size_t i = 0; i < node_count_; ++i) {
            dxdt[i] = omega[i];
            dxdt[node_count_ + i] = node_torque_[i] * inverse_inertia_[i];  // θ'' = T / J
        }
        // Kinds that add to their nodes' inertia (a cylinder's reciprocating mass) set
        // those nodes' accelerations again.
        for_each_element_kind([&](auto kind) __attribute__((always_inline)) {
            using Kind = decltype(kind);
            if constexpr (requires { Kind::correct_accelerations(elements_of<Kind>(), inertia_.data(),
                                                                 node_torque_.data(), dxdt); })
                Kind::correct_accelerations(elements_of<Kind>(), inertia_.data(), node_torque_.data(),
                                            dxdt + node_count_);
        });
        // Nodes that ideal gears tie turn as one coordinate (rigid_gears.hpp).
        if (rigid_.active())
            rigid_.accelerations(elements_of<elements::IdealGear>(), inertia_.data(), node_torque_.data(), omega, true,
                                 dxdt + node_count_);
        if (prescribes_motion_) impose_prescribed_motion(u, node_torque_.data(), dxdt + node_count_, last_torques_.data());
    }

    /// Whether ideal gears tie some nodes into one coordinate (rigid_gears.hpp): then a
    /// tied node's angle and speed follow its group's root's, θ_i = factor_i·θ_root.
    bool ties_nodes() const { return rigid_.active(); }
    /// Whether node i's coordinate is a tied group's root's (its state follows, not leads).
    bool tied_to_other(std::size_t i) const { return rigid_.plan().dependent(i); }
    /// Node i's group root and θ_i/θ_root at the ratios set (i and 1 for an untied node).
    std::size_t tie_root(std::size_t i) const { return rigid_.plan().root[i]; }
    const T& tie_factor(std::size_t i) const { return rigid_.factor(i); }
    /// θ_i − factor_i·θ_root: zero where node i's angle agrees with its group's.
    T tie_constraint(std::size_t i, const T* theta) const { return rigid_.constraint(i, theta); }
    /// The state x with each tied node's angle and speed set from its group's root's.
    void project_onto_ties(T* x) const {
        if (rigid_.active()) rigid_.project(x, node_count_);
    }

    /// Whether some element samples the line at instants and holds its output between them
    /// (a digital controller): then every simulation calls restart_sampling at its start
    /// and sample at each later sample of the recording.
    bool samples() const { return samples_; }

    /// The sampled elements' memory set for a simulation starting at state x, inputs u:
    /// each restarts its memory holding nothing, then settles on the torque that holds its
    /// node against the other elements' there (a controller that has held the start).
    void restart_sampling(const T* x, const double* u) {
        if (!samples_) return;
        const NodeMotion<T> motion{x, speeds_seen(x, u), u, angle_inputs_, true};
        for_each_element_kind([&](auto kind) {
            using Kind = decltype(kind);
            if constexpr (requires { Kind::restart(elements_of<Kind>()[0], motion); })
                for (auto& e : elements_of<Kind>()) Kind::restart(e, motion);
        });
        accumulate_torques(motion, other_torques_.data(), nullptr);
        for_each_element_kind([&](auto kind) {
            using Kind = decltype(kind);
            if constexpr (requires { Kind::settle(elements_of<Kind>()[0], motion, other_torques_[0]); })
                for (auto& e : elements_of<Kind>())
                    Kind::settle(e, motion, other_torques_[static_cast<std::size_t>(e.node)]);
        });
    }

    /// At sample time t of the recording (state x, inputs u), before the observer sees it:
    /// each sampled element whose clock ticks at t samples and updates the output it holds.
    void sample(double t, const T* x, const double* u) {
        if (!samples_) return;
        const NodeMotion<T> motion{x, speeds_seen(x, u), u, angle_inputs_, true};
        for_each_element_kind([&](auto kind) {
            using Kind = decltype(kind);
            if constexpr (requires { Kind::sample(elements_of<Kind>()[0], t, motion); })
                for (auto& e : elements_of<Kind>()) Kind::sample(e, t, motion);
        });
    }

    /// Net torque on each node with all speeds zero (for the static equilibrium).
    /// With ideal gears, a group's root carries the group's net torque through the ratios and
    /// each tied node's row is its tie_constraint (zero at a consistent angle).
    void static_torques(const T* theta, const double* u, T* torque) {
        accumulate_torques(NodeMotion<T>{theta, nullptr, u, angle_inputs_, false}, torque, nullptr);
        if (rigid_.active()) rigid_.static_rows(elements_of<elements::IdealGear>(), theta, torque);
    }

    /// The offset (amplitude shift) of output k.
    const T& output_offset(std::size_t k) const { return output_offsets_[k]; }

    /// Model output k (NetworkSpec::outputs order) including its gain and offset.
    T output(std::size_t k, const T* x, const double* u) const {
        return output_from(k, x, speeds_seen(x, u), [&](const ElementRef& ref, const T* theta, const T* omega) {
            return element_torque(ref, theta, omega, u);
        });
    }

    /// Model output k at the state x and inputs u of the last derivative() call: the value
    /// output(k, x, u) computes, with an element's torque taken from that call instead of
    /// evaluating the element again (a simulation that scores every sample needs the
    /// derivative there anyway, as the first stage of its next step).
    T output_after_derivative(std::size_t k, const T* x) const {
        const T* omega = prescribes_motion_ ? seen_speeds_.data() : x + node_count_;  // as that call saw them
        return output_from(k, x, omega, [&](const ElementRef& ref, const T*, const T*) { return last_torque(ref); });
    }

    /// The torque an element transmits (spring_damper, clearance, gear_mesh: the torque
    /// from a to b; friction: the friction torque c·ω; torque: the applied torque;
    /// cylinder: the gas torque; speed_source: the torque it applies to its node), with
    /// omega the speeds the elements see (speeds_seen).
    T element_torque(const ElementRef& ref, const T* theta, const T* omega, const double* u) const {
        const NodeMotion<T> motion{theta, omega, u, angle_inputs_, true};
        const auto i = static_cast<std::size_t>(ref.index);
        T t(0);
        for_each_element_kind([&](auto kind) {
            using Kind = decltype(kind);
            if (ref.kind != ElementRow<Kind>::kind) return;
            if constexpr (requires { Kind::prescribed_acceleration(elements_of<Kind>()[i], u); }) {
                // A reaction: the sum of every other torque on its node is needed.
                accumulate_torques(motion, other_torques_.data(), nullptr);
                const auto& e = elements_of<Kind>()[i];
                const auto node = static_cast<std::size_t>(e.node);
                t = inertia_[node] * Kind::prescribed_acceleration(e, u) - other_torques_[node];
            } else {
                t = Kind::torque(elements_of<Kind>()[i], motion);
            }
        });
        return t;
    }

    /// The node speeds the elements see at state x and inputs u: the state's, with the
    /// prescribed speeds of speed-source nodes.
    const T* speeds_seen(const T* x, const double* u) const {
        const T* omega = x + node_count_;
        if (!prescribes_motion_) return omega;
        std::copy_n(omega, node_count_, seen_speeds_.begin());
        for_each_element_kind([&](auto kind) {
            using Kind = decltype(kind);
            if constexpr (requires { Kind::prescribed_speed(elements_of<Kind>()[0], u); })
                for (const auto& e : elements_of<Kind>())
                    seen_speeds_[static_cast<std::size_t>(e.node)] = Kind::prescribed_speed(e, u);
        });
        return seen_speeds_.data();
    }

private:
    // A speed source's node turns at its prescribed speed (dθ/dt, set with the other
    // speeds) and its state speed follows the prescribed slope; the source's torque is
    // J·ω̇ minus the sum of the node's other torques, kept as that element's torque.
    void impose_prescribed_motion(const double* u, const T* node_torque, T* acceleration, T* kept) const {
        for_each_element_kind([&](auto kind) {
            using Kind = decltype(kind);
            if constexpr (requires { Kind::prescribed_acceleration(elements_of<Kind>()[0], u); }) {
                T* slot = kept + first_of_kind_[static_cast<std::size_t>(ElementRow<Kind>::kind)];
                for (const auto& e : elements_of<Kind>()) {
                    const auto node = static_cast<std::size_t>(e.node);
                    acceleration[node] = Kind::prescribed_acceleration(e, u);
                    *slot++ = inertia_[node] * acceleration[node] - node_torque[node];
                }
            }
        });
    }

    template <class ElementTorque>
    T output_from(std::size_t k, const T* x, const T* omega, ElementTorque&& torque_of) const {
        const OutputSpec& o = spec_->outputs[k];
        const T* theta = x;
        const auto element_torque = [&](const ElementRef& ref, TorqueSide side) {
            const T t = torque_of(ref, theta, omega);
            return side == TorqueSide::output
                       ? output_side_torque(ref, t, NodeMotion<T>{theta, omega, nullptr, angle_inputs_, true})
                       : t;
        };
        T y{};
        for_each_output_kind([&](auto kind) __attribute__((always_inline)) {
            using Kind = decltype(kind);
            if (o.kind == OutputRow<Kind>::kind) y = Kind::value(o, theta, omega, element_torque);
        });
        return output_gains_[k] * y + output_offsets_[k];  // a gain of 1 gives y + offset to the bit
    }

    // Element ref's torque t as its output side carries it in `motion` (elements/gear_mesh.hpp).
    T output_side_torque(const ElementRef& ref, const T& t, const NodeMotion<T>& motion) const {
        T y = t;
        for_each_element_kind([&](auto kind) {
            using Kind = decltype(kind);
            if constexpr (requires { Kind::output_side_torque(elements_of<Kind>()[0], t, motion); })
                if (ref.kind == ElementRow<Kind>::kind)
                    y = Kind::output_side_torque(elements_of<Kind>()[static_cast<std::size_t>(ref.index)], t, motion);
        });
        return y;
    }

    // The torque element `ref` transmitted in the last derivative() call.
    const T& last_torque(const ElementRef& ref) const {
        return last_torques_[first_of_kind_[static_cast<std::size_t>(ref.kind)] + static_cast<std::size_t>(ref.index)];
    }

    template <class Kind>
    BoundList<Kind>& elements_of() {
        return std::get<BoundList<Kind>>(elements_);
    }
    template <class Kind>
    const BoundList<Kind>& elements_of() const {
        return std::get<BoundList<Kind>>(elements_);
    }

    // Sums every element's torque on every node, kind by kind in the table's order. At
    // rest (no speeds) the kinds that act only in motion (friction) are left out.
    // Each element's transmitted torque is kept in `kept` (when not null, in motion; as
    // element_torque() computes it) for output_after_derivative().
    [[gnu::always_inline]] void accumulate_torques(const NodeMotion<T>& motion, T* torque, T* kept) const {
        for (std::size_t i = 0; i < node_count_; ++i) torque[i] = T(0);
        if (!motion.moving()) kept = nullptr;
        for_each_element_kind([&](auto kind) __attribute__((always_inline)) {
            using Kind = decltype(kind);
            if (!Kind::acts_at_rest && !motion.moving()) return;
            for (const auto& e : elements_of<Kind>()) {
                const T t = Kind::torque(e, motion);
                if (kept) *kept++ = t;
                Kind::load(e, t, motion, torque);
            }
        });
    }

    const NetworkSpec* spec_;
    std::size_t node_count_;
    std::vector<T> inverse_inertia_;
    std::vector<T> node_torque_;
    typename StorageOf<ElementTypes>::type elements_;  ///< the bound elements, one list per kind
    std::vector<T> inertia_;
    bool prescribes_motion_ = false;         ///< some node's speed is prescribed (a speed source)
    bool samples_ = false;                   ///< some element is sampled (has_sampled_elements)
    mutable std::vector<T> seen_speeds_;     ///< speeds_seen's result when prescribes_motion_
    mutable std::vector<T> other_torques_;   ///< element_torque's node sums for a reaction
    const CrankAngleChannels* angle_inputs_ = nullptr;
    std::vector<T> output_offsets_;
    std::vector<T> output_gains_;
    std::vector<T> parameters_;  ///< copy of the last set_parameters argument
    /// Where each element kind starts in last_torques_ (the table's order, as accumulate_torques keeps them).
    std::array<std::size_t, kElementKindCount> first_of_kind_{};
    mutable std::vector<T> last_torques_;  ///< every element's torque in the last derivative() call
    RigidGears<T> rigid_;                  ///< the ideal gears' reduction
};

}  // namespace tvid
