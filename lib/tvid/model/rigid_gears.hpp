#pragma once
// The nodes that ideal gears (elements/ideal_gear.hpp) tie together move as one coordinate:
// θ_i = factor_i · θ_root for every node of a group, factor the product of the ratios on
// the way from the group's root. The state keeps every node's angle and speed (outputs,
// starts and reports read nodes as before); the right-hand side gives the group one
// acceleration, from the group's reduced equation, and each node its share through the
// ratios, so a consistent start stays consistent (θ_i − factor_i·θ_root is linear in the
// state and its second derivative is zero in every stage of a step).
//
// The reduction eliminates the gears' torques from the leaves of each group's tree to its
// root. A child c behind gear g (ratio n, factor f on the torque it delivers to b) adds to
// its parent p what c's subtree needs to follow p:
//   c = b, p = a:  J_p += J_c / (n² f),  T_p += T_c / (n f)
//   c = a, p = b:  J_p += n² f J_c,      T_p += n f T_c
// (from J_c ω̇_c = T_c + n f τ on b, or T_c − τ on a, with ω̇_a = n ω̇_b). The root then has
// J ω̇ = T; the children follow through the ratios and each gear's torque τ is read back.
// A lossy gear's f = η^tanh(τ·ωa/P_s) and τ depend on each other: a lossless pass gives τ's
// sign, which is already exact for one gear (τ = (T_a J_b − n J_a T_b)/(J_b + n² f J_a) has
// the sign of its numerator whatever f is), and a few fixed-point updates of f settle τ
// within the smoothing band (kLossUpdates).

#include <cstddef>
#include <deque>
#include <string>
#include <type_traits>
#include <vector>

#include "tvid/model/elements/ideal_gear.hpp"
#include "tvid/model/smooth_sign.hpp"

namespace tvid {

struct NetworkSpec;

/// How the ideal gears of a network tie its nodes: each group's root and the order in
/// which its gears are eliminated. Depends on the network's structure alone.
struct RigidGearPlan {
    struct Step {
        std::size_t gear = 0;          ///< index among the network's ideal gears
        std::size_t child = 0, parent = 0;
        bool child_is_b = true;        ///< the child is the gear's b (output) side
    };
    std::vector<Step> steps;           ///< from each root outwards: parents before children
    std::vector<std::size_t> root;     ///< per node: its group's root (itself when no gear ties it)
    std::vector<std::size_t> roots;    ///< the roots of the groups that gears tie

    bool active() const { return !steps.empty(); }
    /// Whether node i's coordinate is its root's (a node tied to a lower-numbered one).
    bool dependent(std::size_t i) const { return root[i] != i; }
};

/// The plan of `spec`'s ideal gears: each group rooted at its lowest-numbered node. Expects
/// no loop (rigid_gear_problem).
RigidGearPlan plan_rigid_gears(const NetworkSpec& spec);

/// Why `spec`'s ideal gears cannot be reduced, or "": ideal gears around a loop (the
/// coordinate would be tied to itself), or a node of a group that a speed source prescribes
/// or a cylinder loads with its angle-dependent inertia. `element` gets the element named.
std::string rigid_gear_problem(const NetworkSpec& spec, std::string* element);

/// Whether a and b hold the same values (in every lane of a pack; a dual number's value alone).
template <class T>
bool same_values(const T& a, const T& b) {
    if constexpr (std::is_same_v<decltype(a == b), bool>)
        return a == b;
    else
        return (a == b).all();
}

/// The reduction for one scalar type: buffers sized once, nothing allocated per call.
template <class T>
class RigidGears {
public:
    using Gear = elements::IdealGear::Bound<T>;

    explicit RigidGears(RigidGearPlan plan)
        : plan_(std::move(plan)),
          inertia_(plan_.root.size()),
          torque_(plan_.root.size()),
          factor_(plan_.root.size(), T(1.0)),
          gear_torque_(plan_.steps.size()),
          loss_(plan_.steps.size(), T(1.0)) {}

    bool active() const { return plan_.active(); }
    const RigidGearPlan& plan() const { return plan_; }
    /// θ_i / θ_root of node i at the ratios last set (1 for a root or an untied node).
    const T& factor(std::size_t i) const { return factor_[i]; }

    /// The factors for the gears' ratios (after the gears are bound).
    void set_ratios(const std::vector<Gear>& gears) {
        for (const RigidGearPlan::Step& s : plan_.steps) {
            const T& n = gears[s.gear].ratio;
            factor_[s.child] = s.child_is_b ? factor_[s.parent] / n : factor_[s.parent] * n;  // θ_b = θ_a / n
        }
    }

    /// The accelerations of the tied nodes, given each node's inertia and net torque from
    /// every other element (moving: with the speeds omega; at rest no loss acts).
    void accelerations(const std::vector<Gear>& gears, const T* inertia, const T* node_torque, const T* omega,
                       bool moving, T* acceleration) {
        bool lossy = false;
        for (const Gear& g : gears) lossy = lossy || g.lossy;
        for (T& f : loss_) f = T(1.0);
        eliminate(gears, inertia, node_torque, acceleration);
        if (!lossy || !moving) return;
        for (int update = 0; update < kLossUpdates; ++update) {
            bool settled = true;
            for (std::size_t k = 0; k < gears.size(); ++k) {
                const Gear& g = gears[k];
                if (!g.lossy) continue;
                // f = η^tanh(P/P_s), P = τ·ωa the power a gives the gear (the last pass's τ)
                const T power = gear_torque_[k] * omega[g.a];
                const T f = math::exp(smooth_sign(power * g.inverse_smoothing_power) * g.log_efficiency);
                settled = settled && same_values(f, loss_[k]);
                loss_[k] = f;
            }
            // Every f as the last pass had it: that pass's τ is the fixed point, and every
            // further update would repeat it bit for bit (outside the smoothing band, where
            // f = η exactly, the second pass already is).
            if (settled) return;
            eliminate(gears, inertia, node_torque, acceleration);
        }
    }

    /// The loss factors' fixed-point updates after the lossless pass: f and τ depend on each
    /// other only within the smoothing band, where one update shrinks f's error by at most
    /// (n²fJ_a/J)·|ln η|·max(x sech²x) ≤ 0.45·|ln η| (0.03 for η = 0.93, 0.31 for η = 0.5).
    static constexpr int kLossUpdates = 4;

    /// At rest (the static equilibrium's torques): each root's row the group's net torque
    /// reduced through the ratios (lossless), each tied node's row its constraint
    /// θ_i − factor_i·θ_root, zero where the angles agree.
    void static_rows(const std::vector<Gear>& gears, const T* theta, T* torque) {
        for (std::size_t i = 0; i < torque_.size(); ++i) torque_[i] = torque[i];
        for (auto s = plan_.steps.rbegin(); s != plan_.steps.rend(); ++s) {
            const T& n = gears[s->gear].ratio;
            torque_[s->parent] += s->child_is_b ? torque_[s->child] / n : n * torque_[s->child];
        }
        for (std::size_t r : plan_.roots) torque[r] = torque_[r];
        for (const RigidGearPlan::Step& s : plan_.steps) torque[s.child] = constraint(s.child, theta);
    }

    /// θ_i − factor_i·θ_root: how far node i's angle is from its group's.
    T constraint(std::size_t i, const T* theta) const { return theta[i] - factor_[i] * theta[plan_.root[i]]; }

    /// The state x (n nodes) with each tied node's angle and speed set from its root's.
    void project(T* x, std::size_t n) const {
        for (const RigidGearPlan::Step& s : plan_.steps) {
            x[s.child] = factor_[s.child] * x[plan_.root[s.child]];
            x[n + s.child] = factor_[s.child] * x[n + plan_.root[s.child]];
        }
    }

private:
    // One pass of the reduction with the loss factors in loss_.
    void eliminate(const std::vector<Gear>& gears, const T* inertia, const T* node_torque, T* acceleration) {
        for (std::size_t i = 0; i < inertia_.size(); ++i) {
            inertia_[i] = inertia[i];
            torque_[i] = node_torque[i];
        }
        for (auto s = plan_.steps.rbegin(); s != plan_.steps.rend(); ++s) {  // leaves first
            const T& n = gears[s->gear].ratio;
            const T& f = loss_[s->gear];
            if (s->child_is_b) {
                inertia_[s->parent] += inertia_[s->child] / (n * n * f);
                torque_[s->parent] += torque_[s->child] / (n * f);
            } else {
                inertia_[s->parent] += n * n * f * inertia_[s->child];
                torque_[s->parent] += n * f * torque_[s->child];
            }
        }
        for (std::size_t r : plan_.roots) acceleration[r] = torque_[r] / inertia_[r];
        for (const RigidGearPlan::Step& s : plan_.steps) {  // roots first
            const T& n = gears[s.gear].ratio;
            const std::size_t c = s.child;
            if (s.child_is_b) {
                acceleration[c] = acceleration[s.parent] / n;
                gear_torque_[s.gear] = (inertia_[c] * acceleration[c] - torque_[c]) / (n * loss_[s.gear]);
            } else {
                acceleration[c] = n * acceleration[s.parent];
                gear_torque_[s.gear] = torque_[c] - inertia_[c] * acceleration[c];
            }
        }
    }

    RigidGearPlan plan_;
    std::vector<T> inertia_, torque_;  ///< each subtree's reduced inertia and torque
    std::vector<T> factor_;
    std::vector<T> gear_torque_;       ///< per gear: τ, the torque it takes from a
    std::vector<T> loss_;              ///< per gear: f
};

}  // namespace tvid
