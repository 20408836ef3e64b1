#pragma once
// A multi-stage torsional spring between two nodes, or a node and ground: a clutch
// damper's spring sets, a dual-mass flywheel's arc springs. Piecewise linear torque against
// twist with smoothed corners, odd or with a negative side of its own.

#include <algorithm>
#include <array>
#include <string>

#include "tvid/model/element_source.hpp"
#include "tvid/model/element_traits.hpp"
#include "tvid/model/elements/node_motion.hpp"
#include "tvid/model/elements/two_node_load.hpp"
#include "tvid/model/field.hpp"
#include "tvid/model/field_bounds.hpp"
#include "tvid/model/smooth_clearance.hpp"

namespace tvid {

/// Stage i of a side begins at twist angle_i (counted from zero outwards) and has the
/// stiffness k_i until the next; with φ(x) = s·ln(1 + e^{x/s}) (s the smoothing angle) and
/// Δk_i = k_i − k_{i−1} (k_0 = 0), the torque from a to b at twist θ = θa − θb is
///   T = Σ_i Δk_i·φ(θ − angle_i) − Σ_j Δk⁻_j·φ(−θ − angle⁻_j) + c·θ',
/// with the negative side's stages equal to the positive side's unless `stages_negative`
/// is given (an odd law). A first stage at angle 0 on both sides gives k_1·θ exactly.
struct MultistageSpringSpec {
    static constexpr int kMaxStages = 6;  ///< per side
    std::string name;
    int a = 0, b = kGround;
    int stages = 0;           ///< the positive side's stages (the negative's too when odd)
    int stages_negative = 0;  ///< 0: the law is odd
    std::array<Field, kMaxStages> angle{}, k{}, angle_negative{}, k_negative{};
    Field c = Field::value(0.0), smoothing_angle = Field::value(0.001);
};

namespace elements {

struct MultistageSpring : TwoNodeLoad {  // its load: −t on a, +t on b
    using Spec = MultistageSpringSpec;
    static constexpr int kMaxStages = Spec::kMaxStages;
    template <class T>
    struct Bound : BetweenTwoNodes {
        int stages = 0, stages_negative = 0;
        std::array<T, kMaxStages> angle{}, k{}, angle_negative{}, k_negative{};
        T c, smoothing_angle;
        int pairs = 0;  ///< max(stages, negative side's stages)
        std::array<T, kMaxStages> rise{}, rise_negative{};  ///< Δk of each stage (0 past a side's last)
        std::array<T, kMaxStages> start{}, start_negative{};  ///< each stage's angle (0 past a side's last)
        T sigma = T(0.0);  ///< 1/s
    };

    /// The default smoothing angle [rad]: 0.06°, small beside a clutch damper's stages of a few degrees.
    static constexpr double kDefaultSmoothingAngle = 0.001;

    // ---- the experiment file: `{ type: multistage_spring, between: [a, b], stages: [{angle: A1, k: K1}, ...],
    // stages_negative: [...], c: C, smoothing_angle: S }`
    static constexpr const char* type_name = "multistage_spring";
    static constexpr const char* summary =
        "a multi-stage spring between two nodes: piecewise linear torque against twist (stages of angle and k), "
        "corners smoothed, odd or with a negative side of its own, and a damper";
    static constexpr const char* keys[] = {"between", "stages", "stages_negative", "c", "smoothing_angle"};

    static Spec read(ElementSource& src, const std::string& name) {
        Spec e = spec_at_ends<MultistageSpring>(src, name);
        e.stages = read_stages(src, "stages", e.angle, e.k);
        if (src.has("stages_negative")) e.stages_negative = read_stages(src, "stages_negative", e.angle_negative, e.k_negative);
        e.c = src.field_or("c", Field::value(0.0));
        e.smoothing_angle = src.field_or("smoothing_angle", Field::value(kDefaultSmoothingAngle));
        return e;
    }

    /// f(info, field...) for each numeric field, of each of s, e... (a spec first, then bound elements) in step:
    /// each side's stages (one unused slot when a side has none, so that its fields are listed), c and s.
    template <class F, class Spec_, class... E>
    static void for_each_field(F&& f, Spec_& s, E&... e) {
        for (int i = 0; i < std::max(s.stages, 1); ++i) {
            const auto j = static_cast<std::size_t>(i);
            f(FieldInfo{"stages.angle", "a stage angle", SignRule::non_negative, "rad", i < s.stages}, s.angle[j],
              e.angle[j]...);
            f(FieldInfo{"stages.k", "a stage stiffness", SignRule::non_negative, "N m/rad", i < s.stages}, s.k[j], e.k[j]...);
        }
        for (int i = 0; i < std::max(s.stages_negative, 1); ++i) {
            const auto j = static_cast<std::size_t>(i);
            f(FieldInfo{"stages_negative.angle", "a stage angle", SignRule::non_negative, "rad", i < s.stages_negative},
              s.angle_negative[j], e.angle_negative[j]...);
            f(FieldInfo{"stages_negative.k", "a stage stiffness", SignRule::non_negative, "N m/rad",
                        i < s.stages_negative},
              s.k_negative[j], e.k_negative[j]...);
        }
        f(FieldInfo{"c", "a damping coefficient", SignRule::non_negative, "N m s/rad"}, s.c, e.c...);
        f(FieldInfo{"smoothing_angle", "a smoothing angle", SignRule::positive, "rad"}, s.smoothing_angle,
          e.smoothing_angle...);
    }

    static constexpr ChannelUse channel{};  ///< reads no channel
    static int channel_of(const Spec&) { return -1; }
    static constexpr ElementOutputs outputs = ElementOutputs::torque;

    /// Enters with its slope dT/dθ at the operating point's twist (the stage it is in).
    static LinearNote linearise(const Spec& s, Spec&, const LinearisationPoint& at) {
        Bound<double> e;
        for_each_field([&](const FieldInfo&, const Field& field, double& value) { value = at.value(field); }, s, e);
        bind(s, e);
        const double twist = at.twist(s.a, s.b);
        const double h = 1e-3 * at.value(s.smoothing_angle);
        const double slope = (spring_torque(e, twist + h) - spring_torque(e, twist - h)) / (2 * h);
        return {"operating_point", "stage stiffness at the twist " + linear_number(twist) +
                                       " rad: dT/dtheta = " + linear_number(slope) + " N m/rad"};
    }

    // ---- the equations of motion

    template <class T>
    static void bind(const Spec& s, Bound<T>& e) {
        e.stages = s.stages;
        e.stages_negative = s.stages_negative;
        const bool odd = s.stages_negative == 0;
        const int negative = odd ? s.stages : s.stages_negative;
        e.pairs = std::max(s.stages, negative);
        T previous = T(0.0), previous_negative = T(0.0);
        for (std::size_t i = 0; i < static_cast<std::size_t>(kMaxStages); ++i) {
            const bool positive_stage = static_cast<int>(i) < s.stages, negative_stage = static_cast<int>(i) < negative;
            e.start[i] = positive_stage ? e.angle[i] : T(0.0);
            e.rise[i] = positive_stage ? e.k[i] - previous : T(0.0);
            if (positive_stage) previous = e.k[i];
            const T& angle_n = odd ? e.angle[i] : e.angle_negative[i];
            const T& k_n = odd ? e.k[i] : e.k_negative[i];
            e.start_negative[i] = negative_stage ? angle_n : T(0.0);
            e.rise_negative[i] = negative_stage ? k_n - previous_negative : T(0.0);
            if (negative_stage) previous_negative = k_n;
        }
        e.sigma = T(1.0) / e.smoothing_angle;
    }

    static constexpr bool acts_at_rest = true;
    static constexpr ElementEnds ends = ElementEnds::two_nodes;

    /// The spring's torque at twist θ: each stage's ramp on either side, a pair of
    /// stages sharing their logistic divisions (smooth_clearance.hpp).
    template <class T>
    [[gnu::always_inline]] static T spring_torque(const Bound<T>& e, const T& twist) {
        const T a = e.sigma * twist;
        T t = T(0.0);
        for (std::size_t i = 0; i < static_cast<std::size_t>(e.pairs); ++i) {
            const T z_fore = a - e.sigma * e.start[i], z_back = -a - e.sigma * e.start_negative[i];
            const ContactRampSteps<T> r =
                contact_ramp_steps(z_back, z_fore, two_exponentials(z_back, z_fore), e.smoothing_angle);
            t = t + e.rise[i] * r.fore.ramp - e.rise_negative[i] * r.back.ramp;
        }
        return t;
    }

    /// The torque transmitted from a to b.
    template <class T>
    [[gnu::always_inline]] static T torque(const Bound<T>& e, const NodeMotion<T>& m) {
        return spring_torque(e, m.twist(e.a, e.b)) + e.c * m.twist_rate(e.a, e.b);
    }


    /// Each side's stage angles can rise from zero outwards: bounds that put a stage wholly
    /// before the one it follows are refused (a pair of constants is checked where the stages
    /// are read, at the stage's own key).
    static void check(const Spec& e, const FieldBounds& b) {
        const auto side = [&](const char* key, const std::array<Field, kMaxStages>& angle, int stages) {
            for (int i = 1; i < stages; ++i) {
                const Field& before = angle[static_cast<std::size_t>(i - 1)];
                const Field& at = angle[static_cast<std::size_t>(i)];
                if (!before.is_parameter() && !at.is_parameter()) continue;
                if (!b.known(before) || !b.known(at)) continue;
                const bool same = before.is_parameter() && before.parameter == at.parameter;
                if (!(b.highest(at) > b.lowest(before)) || same)
                    b.fail(key, {at, before},
                           "the stage angles must rise from zero outwards: stage " + std::to_string(i + 1) + "'s " +
                               b.text(at) + " rad cannot lie beyond stage " + std::to_string(i) + "'s " +
                               b.text(before) + " rad");
            }
        };
        side("stages", e.angle, e.stages);
        side("stages_negative", e.angle_negative, e.stages_negative);
    }

private:
    // One side's list of {angle, k}, in order from zero outwards; returns its length.
    static int read_stages(ElementSource& src, const char* key, std::array<Field, kMaxStages>& angle,
                           std::array<Field, kMaxStages>& k) {
        const auto list = src.entries(key, {"angle", "k"});
        if (list.size() > static_cast<std::size_t>(kMaxStages))
            src.fail(key, "at most " + std::to_string(kMaxStages) + " stages a side, got " + std::to_string(list.size()));
        double last = -1.0;
        for (std::size_t i = 0; i < list.size(); ++i) {
            ElementSource& stage = *list[i];
            angle[i] = stage.field("angle");
            k[i] = stage.field("k");
            if (!k[i].is_parameter() && k[i].constant < 0)
                stage.fail("k", "cannot be negative: a stage stiffness (got " + given_number(k[i].constant) + ")");
            if (angle[i].is_parameter()) {
                last = -1.0;
                continue;
            }
            if (angle[i].constant < 0)
                stage.fail("angle", "is the twist where the stage begins, counted from zero outwards, and cannot be "
                                    "negative (got " + given_number(angle[i].constant) +
                                    "); give the negative side under stages_negative");
            if (angle[i].constant <= last)
                stage.fail("angle", "must lie beyond the previous stage's " + given_number(last) + " rad (got " +
                                        given_number(angle[i].constant) + ")");
            last = angle[i].constant;
        }
        return static_cast<int>(list.size());
    }
};

}  // namespace elements
}  // namespace tvid
