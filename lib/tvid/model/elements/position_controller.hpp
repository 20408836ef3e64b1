#pragma once
// A PID position controller on a node, as a drive's position loop: proportional on the
// angle error, derivative on the measured speed (not on the error, so a setpoint step
// gives no derivative kick). With `ki` the continuous controller integrates its angle
// error in a hidden node NAME.integral (J = 1, nothing else acting on it): the controller
// loads that node with its error, so the node's speed is ∫(θ_set − θa) dt.
//
// With `sample_period` it is digital, as a drive's firmware runs it: at every multiple of
// the period it samples its node's angle and its setpoint, takes the speed as the backward
// difference of its sampled angles (over `angle_average` periods: the difference of the
// averages of the last N angles), adds the error to its integral (`ki`), computes its
// command, saturates it at `limits`, and applies it `delay` later, held constant until
// the next one (zero-order hold). A sampled speed_controller (speed_controller.hpp) is the
// same element measuring its speed loop: kp on the speed error, ki on its integral.
// The memory of samples and commands lives in the bound element; a simulation restarts it
// (restart()) at its first sample as if the line had been turning there steadily, and
// each march calls sample() at every sample of the recording (NetworkModel::sample).

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "tvid/model/element_source.hpp"
#include "tvid/model/element_traits.hpp"
#include "tvid/model/elements/node_motion.hpp"
#include "tvid/model/field.hpp"
#include "tvid/model/field_bounds.hpp"
#include "tvid/simd/select.hpp"

namespace tvid {

/// What a controller's loop measures: its node's angle against an angle setpoint
/// (position_controller), or its speed against a speed setpoint (a sampled speed_controller).
enum class ControlledQuantity { angle, speed };

/// The longest delay and angle average a sampled controller keeps, in sample periods.
inline constexpr int kMaxControllerDelay = 16;
inline constexpr int kMaxAngleAverage = 16;

/// T = kp·(θ_set − θa) − kd·ωa on node a, θ_set a measured angle channel (input ≥ 0) or a
/// constant (a number or a parameter); with `limits: [min, max]` the command saturates there
/// (an actuator's torque limit). With sample_period > 0 it is sampled (see above).
struct PositionControllerSpec {
    std::string name;
    int node = 0;
    int input = -1;  ///< index into NetworkSpec::input_names; −1: the constant `setpoint`
    Field setpoint = Field::value(0.0), kp = Field::value(0.0), kd = Field::value(0.0);
    bool limited = false;
    Field lower = Field::value(0.0), upper = Field::value(0.0);  ///< the torque limits [N m], when limited
    Field ki = Field::value(0.0);  ///< the integral gain (sampled controllers)
    double sample_period = 0.0;    ///< [s]; 0: continuous
    /// [s] how far a recording's sample may lie from one of the controller's instants and
    /// still be that instant (a logger's clock jitters): 1e-3 of the recording's sample
    /// interval, set by the experiment reader; 0: 1e-6 of the period.
    double clock_tolerance = 0.0;
    int delay_periods = 0;         ///< the computation delay in sample periods
    int angle_average = 1;         ///< the speed: the difference of the averages of this many angles
    ControlledQuantity measures = ControlledQuantity::angle;
    int integral_node = -1;        ///< a continuous controller with ki: the node whose speed is its integral
    bool sampled() const { return sample_period > 0.0; }
    bool integrates() const { return ki.is_parameter() || ki.constant != 0.0; }
};

namespace elements {

struct PositionController {
    using Spec = PositionControllerSpec;
    template <class T>
    struct Bound : OnOneNode {
        int input = -1, integral_node = -1;
        T setpoint, kp, kd, lower, upper, ki;
        bool limited = false;
        // A sampled controller: its clock and its memory, restarted by each simulation.
        double period = 0.0, clock_tolerance = 0.0;
        int delay = 0, average = 1;
        bool speed_loop = false;
        bool holding = false;  ///< restarted: the torque is `held` (else the continuous law)
        int angle_at = 0, command_at = 0;  ///< the newest entries of the rings below
        std::array<T, kMaxAngleAverage + 1> angles{};     ///< the sampled angles, a ring
        std::array<T, kMaxControllerDelay + 1> commands{};  ///< the computed commands, a ring
        T integral{};  ///< ki·Σ Ts·error [N m], kept within the limits
        T held{};      ///< the command applied now
    };

    // ---- the experiment file: `{ type: position_controller, node: NODE, setpoint: CHANNEL | RAD, kp: KP, kd: KD,
    //      limits: [MIN, MAX] }`
    static constexpr const char* type_name = "position_controller";
    static constexpr const char* summary =
        "a PID position controller on a node: T = kp*(theta_set - theta) + ki*integral(theta_set - theta) dt - kd*omega "
        "(derivative on the measured speed; ki optional), saturated at limits; sampled with sample_period";
    static constexpr const char* keys[] = {"node", "setpoint", "kp", "ki", "kd", "limits", "sample_period", "delay",
                                           "angle_average"};

    static Spec read(ElementSource& src, const std::string& name) {
        Spec e = spec_at_ends<PositionController>(src, name);
        read_setpoint(src, e, "an angle", "(an angle channel [rad], a constant angle or a parameter)");
        e.kp = src.field("kp");
        e.kd = src.field_or("kd", Field::value(0.0));
        read_sampling(src, e);
        // The integral of the angle error: a sampled controller keeps it with its samples, a
        // continuous one in its hidden node (add_parts).
        if (src.has("ki")) e.ki = src.field("ki");
        read_limits(src, e);
        return e;
    }

    /// `setpoint`: a constant or a parameter, else a channel of `quantity` (the controlled
    /// quantity: this one's angle or a sampled speed_controller's speed).
    static void read_setpoint(ElementSource& src, Spec& e, const char* quantity, const char* expected) {
        if (!src.has("setpoint")) src.fail_missing("setpoint", expected);
        if (src.names_constant("setpoint"))
            e.setpoint = src.field("setpoint");
        else
            e.input = src.time_input("setpoint", quantity);
    }

    /// `limits: [lower, upper]` on the controller's torque, when given.
    static void read_limits(ElementSource& src, Spec& e) {
        if (!src.has("limits")) return;
        const auto limits = src.field_pair("limits");
        e.limited = true;
        e.lower = limits.first;
        e.upper = limits.second;
    }

    /// A continuous controller with ki: its hidden node NAME.integral (J = 1), whose speed
    /// holds the integral of the angle error.
    /// (A template: NetworkSpec is complete only where the reader instantiates it.)
    template <class Network>
    static void add_parts(Spec& e, ElementSource& src, Network& net) {
        if (e.sampled() || !e.integrates()) return;
        typename decltype(net.nodes)::value_type integral;
        integral.name = e.name + ".integral";
        integral.inertia = Field::value(1.0);  // so that its acceleration is the error itself
        integral.holds_state = true;
        if (net.node_index(integral.name) >= 0)
            src.fail("name", "a node named '" + integral.name + "' already exists (the controller's integral)");
        e.integral_node = static_cast<int>(net.nodes.size());
        net.nodes.push_back(integral);
    }

    /// `sample_period`, `delay` and `angle_average` of a controller (this one or a sampled
    /// speed_controller): a period in seconds (a number: the drive's clock), a delay of a
    /// whole number of periods, an average of 1 to kMaxAngleAverage angles.
    static void read_sampling(ElementSource& src, Spec& e) {
        if (!src.has("sample_period")) {
            for (const char* key : {"delay", "angle_average"})
                if (src.has(key)) src.fail(key, "belongs to a sampled controller: give its sample_period too");
            return;
        }
        e.sample_period = plain_number(src, "sample_period", "a number of seconds (a controller's clock is known, not "
                                                             "estimated)");
        if (!(e.sample_period > 0.0) || !std::isfinite(e.sample_period))
            src.fail("sample_period", "expected a positive number of seconds, got " + given_number(e.sample_period));
        if (src.has("delay")) {
            const double delay = plain_number(src, "delay", "a number of seconds, not a parameter");
            const double periods = delay / e.sample_period;
            if (!(delay >= 0.0) || std::abs(periods - std::round(periods)) > 1e-6 ||
                std::round(periods) > kMaxControllerDelay)
                src.fail("delay", "expected a whole number of sample periods (0 to " +
                                      std::to_string(kMaxControllerDelay) + " times " +
                                      given_number(e.sample_period) + " s), got " + given_number(delay) + " s");
            e.delay_periods = static_cast<int>(std::round(periods));
        }
        if (src.has("angle_average")) {
            const double n = plain_number(src, "angle_average", "a whole number of sampled angles, not a parameter");
            if (!(n >= 1 && n <= kMaxAngleAverage) || n != std::floor(n))
                src.fail("angle_average", "expected a whole number of sampled angles from 1 to " +
                                              std::to_string(kMaxAngleAverage) + ", got " + given_number(n));
            e.angle_average = static_cast<int>(n);
        }
    }

    /// After the sign rules: the limits hold zero between them (min <= 0 <= max for every
    /// value of their bounds), and some values of their bounds have min < max.
    static void check(const Spec& e, const FieldBounds& b) {
        if (!e.limited || !b.known(e.lower) || !b.known(e.upper)) return;
        const bool same = e.lower.is_parameter() && e.lower.parameter == e.upper.parameter;
        if (!(b.highest(e.lower) <= 0.0 && 0.0 <= b.lowest(e.upper) && b.lowest(e.lower) < b.highest(e.upper)) || same)
            b.fail("limits", {e.lower, e.upper},
                   "expected [min, max] with min <= 0 <= max and min < max, got [" + b.text(e.lower) + ", " +
                       b.text(e.upper) + "]");
    }

    /// f(info, field...) for each numeric field, of each of s, e... (a spec first, then bound elements) in step.
    template <class F, class Spec_, class... E>
    static void for_each_field(F&& f, Spec_& s, E&... e) {
        const bool speed = s.measures == ControlledQuantity::speed;
        f(FieldInfo{"setpoint", nullptr, SignRule::any, speed ? "rad/s" : "rad", s.input < 0}, s.setpoint,
          e.setpoint...);
        f(FieldInfo{"kp", "a controller gain", SignRule::non_negative, speed ? "N m s/rad" : "N m/rad"}, s.kp, e.kp...);
        f(FieldInfo{"kd", "a controller gain", SignRule::non_negative, "N m s/rad", !speed}, s.kd, e.kd...);
        f(FieldInfo{"limits.min", nullptr, SignRule::any, "N m", s.limited}, s.lower, e.lower...);
        f(FieldInfo{"limits.max", nullptr, SignRule::any, "N m", s.limited}, s.upper, e.upper...);
        f(FieldInfo{"ki", "a controller gain", SignRule::non_negative, speed ? "N m/rad" : "N m/(rad s)",
                    s.integrates()},
          s.ki, e.ki...);
    }

    static constexpr ChannelUse channel{"rad"};  ///< a measured angle setpoint, by time
    static int channel_of(const Spec& s) { return s.input; }
    static constexpr ElementOutputs outputs = ElementOutputs::torque;

    /// Linear: kp a spring and kd a damper from the node to ground, the setpoint an input (at
    /// the operating point's command, inside its limits or saturated there).
    static LinearNote linearise(const Spec& s, Spec&, const LinearisationPoint&) {
        if (s.sampled())
            return {"operating_point",
                    std::string(s.measures == ControlledQuantity::speed
                                    ? "a sampled speed controller, as its continuous law: kp a damper to ground; "
                                      "its integral (ki) is left out"
                                    : "a sampled PD(I), as its continuous law: kp a spring and kd a damper to ground; "
                                      "its integral (ki) is left out") +
                        "; the hold, the delay and the speed's backward difference (together a lag of about (" +
                        linear_number(0.5 + s.delay_periods + 0.5 * (s.angle_average - 1)) + " × " +
                        linear_number(s.sample_period) + ") s) are left out"};
        if (s.integral_node >= 0)
            return {"operating_point", "kp a spring and kd a damper to ground, and the integral of the angle error a "
                                       "state: node " + s.name + ".integral, whose speed it is (ki couples it back)" +
                                           std::string(s.limited ? "; saturated, a constant torque" : "")};
        if (s.limited) return {"operating_point", "kp a spring and kd a damper to ground while inside its limits; "
                                                  "saturated, a constant torque"};
        return {"exact", "linear: kp a spring and kd a damper to ground, the setpoint an input"};
    }

    // ---- the equations of motion

    template <class T>
    static void bind(const Spec& s, Bound<T>& e) {
        e.input = s.input;
        e.integral_node = s.integral_node;
        e.limited = s.limited;
        e.period = s.sample_period;
        e.clock_tolerance = s.clock_tolerance > 0.0 ? s.clock_tolerance : 1e-6 * s.sample_period;
        e.delay = s.delay_periods;
        e.average = s.angle_average;
        e.speed_loop = s.measures == ControlledQuantity::speed;
        e.holding = false;  // new parameters: a simulation restarts the memory
    }

    static bool sampled(const Spec& s) { return s.sampled(); }

    static constexpr bool acts_at_rest = true;  ///< it holds its node at the setpoint
    static constexpr ElementEnds ends = ElementEnds::one_node;

    /// The controller's torque on its node: a sampled one's held command once a simulation
    /// has restarted it; else (and at rest) the continuous law on the node's angle and speed.
    /// Out of line: inlined into the network's torque sum, its branches changed the registers
    /// of the other kinds' loops there (the paper swarm, which has no controller, took 2.5–3 %
    /// longer; docs/performance.md). One call per controller is nothing beside a simulation step.
    template <class T>
    [[gnu::noinline]] static T torque(const Bound<T>& e, const NodeMotion<T>& m) {
        if (e.holding && m.moving()) return e.held;
        const T c = law(e, m, m.theta[e.node], m.twist_rate(e.node, kGround));
        // A continuous integral: its node's speed (zero at rest).
        if (e.integral_node >= 0 && m.moving()) return saturate(e, c + e.ki * m.omega[e.integral_node]);
        return saturate(e, c);
    }

    /// A simulation's start, first step: the memory as if the node had turned at its present
    /// speed through every earlier sample (so the backward difference gives that speed),
    /// holding no torque while NetworkModel::restart_sampling sums the other elements'.
    template <class T>
    static void restart(Bound<T>& e, const NodeMotion<T>& m) {
        if (e.period <= 0.0) return;
        const T theta = m.theta[e.node], omega = m.omega[e.node];
        e.angle_at = 0;
        for (int j = 0; j <= e.average; ++j)  // angles[−j mod size] = θ(t − j·Ts)
            e.angles[static_cast<std::size_t>((kAngleRing - j) % kAngleRing)] = theta - T(j * e.period) * omega;
        e.integral = T(0);
        e.held = T(0);
        e.holding = true;
    }

    /// Second step, with `load` the other elements' torque on the node at the start: the
    /// controller has been holding the node steady, so its integral (with ki > 0) is what
    /// makes its command −load, within the limits; the delay line holds that command.
    template <class T>
    static void settle(Bound<T>& e, const NodeMotion<T>& m, const T& load) {
        if (e.period <= 0.0) return;
        using std::max;
        using std::min;
        const T theta = m.theta[e.node], omega = m.omega[e.node];
        const T proportional = law(e, m, theta, omega);
        T integral = select(e.ki > T(0), -load - proportional, T(0));
        if (e.limited) integral = min(max(integral, e.lower), e.upper);
        e.integral = integral;
        e.held = saturate(e, proportional + integral);
        e.command_at = 0;
        for (T& c : e.commands) c = e.held;
    }

    /// At time t (a sample of the recording, the state there in m): if t is on the
    /// controller's clock, it samples, computes its command and applies the one `delay` old.
    template <class T>
    static void sample(Bound<T>& e, double t, const NodeMotion<T>& m) {
        if (e.period <= 0.0 || !on_clock(t, e.period, e.clock_tolerance)) return;
        using std::max;
        using std::min;
        e.angle_at = (e.angle_at + 1) % kAngleRing;
        const T theta = m.theta[e.node];
        e.angles[static_cast<std::size_t>(e.angle_at)] = theta;
        // The difference of the averages of the last N angles: (θ_k − θ_{k−N}) / (N·Ts).
        const T oldest = e.angles[static_cast<std::size_t>((e.angle_at - e.average + kAngleRing) % kAngleRing)];
        const T rate = (theta - oldest) / T(e.average * e.period);
        const T target = e.input < 0 ? e.setpoint : T(m.u[e.input]);
        const T error = e.speed_loop ? target - rate : target - theta;
        e.integral = e.integral + e.ki * T(e.period) * error;
        if (e.limited) e.integral = min(max(e.integral, e.lower), e.upper);  // anti-windup: clamped to the limits
        e.command_at = (e.command_at + 1) % kCommandRing;
        e.commands[static_cast<std::size_t>(e.command_at)] = saturate(e, law(e, m, theta, rate) + e.integral);
        e.held = e.commands[static_cast<std::size_t>((e.command_at - e.delay + kCommandRing) % kCommandRing)];
    }

    /// A key that must hold a number (not a parameter or a channel).
    static double plain_number(ElementSource& src, const char* key, const char* expected) {
        if (!src.names_constant(key) || src.field(key).is_parameter()) src.fail(key, std::string("expected ") + expected);
        return src.field(key).constant;
    }

    /// Whether t is a multiple of the period (to a millionth of it).
    /// Whether the sample at time t is one of the instants k·period, within `tolerance` [s].
    static bool on_clock(double t, double period, double tolerance) {
        const double k = std::round(t / period);
        return std::abs(t - k * period) <= tolerance;
    }

    template <class T>
    [[gnu::always_inline]] static void load(const Bound<T>& e, const T& t, const NodeMotion<T>& m, T* node_torque) {
        node_torque[e.node] += t;
        if (e.integral_node >= 0) {  // d/dt of the integral node's speed (J = 1) is the angle error
            const T target = e.input < 0 ? e.setpoint : T(m.u[e.input]);
            node_torque[e.integral_node] += target - m.theta[e.node];
        }
    }

private:
    static constexpr int kAngleRing = kMaxAngleAverage + 1, kCommandRing = kMaxControllerDelay + 1;

    /// The command before the integral and the limits, for the angle `theta` and speed
    /// `rate` the controller sees: position kp·(θ_set − θ) − kd·ω; speed kp·(ω_set − ω).
    template <class T>
    [[gnu::always_inline]] static T law(const Bound<T>& e, const NodeMotion<T>& m, const T& theta, const T& rate) {
        const T target = e.input < 0 ? e.setpoint : T(m.u[e.input]);
        return e.speed_loop ? e.kp * (target - rate) : e.kp * (target - theta) - e.kd * rate;
    }

    template <class T>
    [[gnu::always_inline]] static T saturate(const Bound<T>& e, const T& command) {
        using std::max;
        using std::min;
        return e.limited ? min(max(command, e.lower), e.upper) : command;
    }
};

}  // namespace elements
}  // namespace tvid
