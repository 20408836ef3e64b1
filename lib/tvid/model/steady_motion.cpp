#include "tvid/model/steady_motion.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <deque>

namespace tvid {

namespace {

double value_of(const Field& f, const std::vector<double>& p) {
    return f.is_parameter() ? p[static_cast<std::size_t>(f.parameter)] : f.constant;
}

// ω_a = n · ω_b for an element joining a and b: n its gear ratio, 1 for a shaft.
struct Tie {
    int a, b;
    double ratio;
    const std::string* name;
};

std::vector<Tie> ties(const NetworkSpec& spec, const std::vector<double>& p) {
    std::vector<Tie> out;
    for_each_element(spec, [&](auto, const auto& e) {
        if constexpr (requires { e.a; e.b; }) {
            if (e.b == kGround) return;
            double n = 1.0;
            if constexpr (requires { e.ratio; }) n = value_of(e.ratio, p);
            out.push_back(Tie{e.a, e.b, n, &e.name});
        }
    });
    return out;
}

}  // namespace

RigidMotion rigid_motion(const NetworkSpec& spec, const std::vector<double>& p, int reference) {
    const std::size_t n = spec.nodes.size();
    RigidMotion m;
    m.ratio.assign(n, 0.0);
    m.tied.assign(n, 0);
    const std::vector<Tie> all = ties(spec, p);
    std::deque<int> queue{reference};
    m.ratio[static_cast<std::size_t>(reference)] = 1.0;
    m.tied[static_cast<std::size_t>(reference)] = 1;
    while (!queue.empty()) {
        const int at = queue.front();
        queue.pop_front();
        for (const Tie& t : all) {
            if (t.a != at && t.b != at) continue;
            const int other = t.a == at ? t.b : t.a;
            const double r = t.a == at ? m.ratio[static_cast<std::size_t>(at)] / t.ratio  // ω_b = ω_a / n
                                       : m.ratio[static_cast<std::size_t>(at)] * t.ratio;
            auto& known = m.ratio[static_cast<std::size_t>(other)];
            if (!m.tied[static_cast<std::size_t>(other)]) {
                known = r;
                m.tied[static_cast<std::size_t>(other)] = 1;
                queue.push_back(other);
            } else if (std::abs(known - r) > 1e-12 * std::abs(known)) {
                m.problem = "the gear ratios around a loop through " + *t.name + " disagree: node " +
                            spec.nodes[static_cast<std::size_t>(other)].name + " would turn at two speeds";
                return m;
            }
        }
    }
    return m;
}

SteadyMotion solve_steady_motion(NetworkModel<double>& model, const double* u, int reference, double speed,
                                 double angle) {
    SteadyMotion r;
    const NetworkSpec& spec = model.spec();
    const auto n = static_cast<Eigen::Index>(model.node_count());
    const auto ref = static_cast<Eigen::Index>(reference);
    RigidMotion rigid = rigid_motion(spec, model.parameters(), reference);
    if (!rigid.problem.empty()) {
        r.problem = rigid.problem;
        return r;
    }
    for (Eigen::Index i = 0; i < n; ++i)
        if (!rigid.tied[static_cast<std::size_t>(i)]) {
            r.problem = "node " + spec.nodes[static_cast<std::size_t>(i)].name + " is joined to " +
                        spec.nodes[static_cast<std::size_t>(reference)].name +
                        " by no element: it has no speed in the line's steady motion";
            return r;
        }
    r.ratio = rigid.ratio;
    std::vector<double> x(static_cast<std::size_t>(2 * n)), dxdt(x.size());
    const auto ratio = [&](Eigen::Index i) { return rigid.ratio[static_cast<std::size_t>(i)]; };
    for (Eigen::Index i = 0; i < n; ++i) x[static_cast<std::size_t>(n + i)] = ratio(i) * speed;
    // The unknowns z: each node's twist from the rigid position r_i·angle, except the
    // reference's slot, which holds α; the equations: θ_i'' − r_i·α = 0 for every node.
    auto set_angles = [&](const Eigen::VectorXd& z) {
        for (Eigen::Index i = 0; i < n; ++i) x[static_cast<std::size_t>(i)] = ratio(i) * angle + (i == ref ? 0.0 : z[i]);
    };
    auto eval = [&](const Eigen::VectorXd& z, Eigen::VectorXd& g) {
        set_angles(z);
        model.derivative(x.data(), u, dxdt.data());
        for (Eigen::Index i = 0; i < n; ++i) g[i] = dxdt[static_cast<std::size_t>(n + i)] - ratio(i) * z[ref];
    };
    Eigen::VectorXd z = Eigen::VectorXd::Zero(n), g(n), g_trial(n), trial(n);
    Eigen::MatrixXd jac(n, n);
    eval(z, g);
    bool polished = false;
    for (int iter = 0; iter < 100; ++iter) {
        const double norm = g.norm();
        if (!std::isfinite(norm)) break;
        for (Eigen::Index j = 0; j < n; ++j) {
            if (j == ref) {
                for (Eigen::Index i = 0; i < n; ++i) jac(i, j) = -ratio(i);  // ∂(θ_i'' − r_i·α)/∂α
                continue;
            }
            trial = z;
            const double h = 1e-7 + 1e-10 * std::abs(x[static_cast<std::size_t>(j)]);
            trial[j] += h;
            eval(trial, g_trial);
            jac.col(j) = (g_trial - g) / h;
        }
        const Eigen::FullPivLU<Eigen::MatrixXd> lu(jac);
        if (!lu.isInvertible()) {
            r.problem = "the line's stiffness matrix is singular in steady motion (a node without an elastic "
                        "joint to the rest of the line)";
            return r;
        }
        const Eigen::VectorXd step = lu.solve(-g);
        double alpha = 1.0;
        for (int ls = 0; ls < 40; ++ls, alpha *= 0.5) {
            trial = z + alpha * step;
            eval(trial, g_trial);
            if (std::isfinite(g_trial.norm()) && g_trial.norm() < norm) break;
        }
        z = trial;
        g = g_trial;
        double twist_step = 0.0, twist_scale = 1.0;
        for (Eigen::Index i = 0; i < n; ++i) {
            if (i == ref) continue;
            twist_step = std::max(twist_step, std::abs(alpha * step[i]));
            twist_scale = std::max(twist_scale, std::abs(x[static_cast<std::size_t>(i)]));
        }
        // Converged to the angles' precision (they may be thousands of radians on a
        // recording's cumulative encoder angle): one more step, to rounding.
        if (twist_step <= 1e-14 * twist_scale && !polished) {
            polished = true;
            continue;
        }
        if (polished || g.norm() == 0.0) {
            set_angles(z);
            r.found = true;
            r.acceleration = z[ref];
            r.x = x;
            return r;
        }
    }
    r.problem = "Newton's method did not converge to a steady motion";
    return r;
}

}  // namespace tvid
