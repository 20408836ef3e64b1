#include "tvid/analysis/torsional_modes.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "tvid/experiment/window_recording.hpp"
#include "tvid/model/steady_motion.hpp"
#include "tvid/util/kind_table.hpp"

namespace tvid {

namespace {

constexpr double kModesTwoPi = 6.283185307179586;

// v divided by its largest entry (that entry becomes 1 + 0i); the index of that entry.
std::size_t normalise_to_largest(std::vector<std::complex<double>>& v) {
    double largest = 0.0;
    for (const auto& c : v) largest = std::max(largest, std::abs(c));
    // The first node at the largest magnitude (to rounding: a rigid rotation is the first node's).
    std::size_t at = 0;
    while (at + 1 < v.size() && std::abs(v[at]) < (1.0 - 1e-6) * largest) ++at;
    if (v.empty() || std::abs(v[at]) == 0.0) return at;
    const std::complex<double> pivot = v[at];
    for (auto& c : v) c /= pivot;
    v[at] = 1.0;
    // A node the mode leaves still (one held by a speed source) reads 0, not rounding noise.
    for (auto& c : v)
        if (std::abs(c) < 1e-9) c = 0.0;
    return at;
}

// |⟨a, b⟩| / (|a| |b|): 1 when the complex vectors are parallel.
double alignment(const std::vector<std::complex<double>>& a, const std::vector<double>& b) {
    std::complex<double> dot = 0.0;
    double na = 0.0, nb = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        dot += a[i] * b[i];
        na += std::norm(a[i]);
        nb += b[i] * b[i];
    }
    return na > 0 && nb > 0 ? std::abs(dot) / std::sqrt(na * nb) : 0.0;
}

// |⟨a, b⟩| / (|a| |b|) of two complex shapes.
double shape_similarity(const std::vector<std::complex<double>>& a, const std::vector<std::complex<double>>& b) {
    std::complex<double> dot = 0.0;
    double na = 0.0, nb = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        dot += a[i] * std::conj(b[i]);
        na += std::norm(a[i]);
        nb += std::norm(b[i]);
    }
    return na > 0 && nb > 0 ? std::abs(dot) / std::sqrt(na * nb) : 0.0;
}

// An overdamped degree of freedom has two real eigenvalues λ1, λ2 < 0 with (nearly) the same
// shape: θ'' + 2ζω θ' + ω² θ = 0 has λ1·λ2 = ω² and λ1 + λ2 = −2ζω, so ζ = −(λ1 + λ2)/(2√(λ1λ2)) > 1.
// Each such pair becomes one mode with that ζ and ω/2π (its slower root as `eigenvalue`, the
// faster as `second_eigenvalue`); a real root with no partner (a first-order motion: a
// damper with no inertia behind it) keeps |λ|/2π, its corner frequency, and has no ζ.
void pair_overdamped_roots(std::vector<TorsionalMode>& modes) {
    constexpr double kSameShape = 0.9;
    std::vector<std::size_t> real;
    for (std::size_t k = 0; k < modes.size(); ++k)
        if (modes[k].kind == ModeKind::overdamped && modes[k].eigenvalue.real() < 0.0) real.push_back(k);
    std::vector<bool> merged(modes.size(), false);
    for (std::size_t a = 0; a < real.size(); ++a) {
        const std::size_t i = real[a];
        if (merged[i]) continue;
        std::size_t best = modes.size();
        double best_similarity = kSameShape;
        for (std::size_t b = a + 1; b < real.size(); ++b) {
            const std::size_t j = real[b];
            if (merged[j]) continue;
            const double similarity = shape_similarity(modes[i].shape, modes[j].shape);
            if (similarity > best_similarity) best_similarity = similarity, best = j;
        }
        TorsionalMode& m = modes[i];
        if (best == modes.size()) {
            m.damping_ratio = std::numeric_limits<double>::quiet_NaN();
            continue;
        }
        merged[best] = true;
        double slow = m.eigenvalue.real(), fast = modes[best].eigenvalue.real();
        if (std::abs(slow) > std::abs(fast)) {
            std::swap(slow, fast);
            m.shape = modes[best].shape;  // the slower root's shape
        }
        const double omega = std::sqrt(slow * fast);
        m.eigenvalue = slow;
        m.second_eigenvalue = fast;
        m.frequency_hz = omega / kModesTwoPi;
        m.damping_ratio = -(slow + fast) / (2.0 * omega);
    }
    std::size_t kept = 0;
    for (std::size_t k = 0; k < modes.size(); ++k) {
        if (merged[k]) continue;
        if (kept != k) modes[kept] = std::move(modes[k]);
        ++kept;
    }
    modes.resize(kept);
}

}  // namespace

const char* mode_kind_name(ModeKind kind) {
    using enum ModeKind;
    static constexpr std::array<EnumName<ModeKind>, 3> names{{{rigid_body, "rigid_body"}, {overdamped, "overdamped"}, {oscillating, "oscillating"}}};
    static_assert(rows_in_enumerator_order(names, 3));
    return name_in(names, kind);
}

std::vector<double> node_ratios(const NetworkSpec& spec, const std::vector<double>& params, std::size_t reference) {
    const RigidMotion rigid = rigid_motion(spec, params, static_cast<int>(reference));
    std::vector<double> ratio(spec.nodes.size(), 1.0);
    if (!rigid.problem.empty()) return ratio;
    for (std::size_t i = 0; i < ratio.size(); ++i)
        if (rigid.tied[i] && rigid.ratio[i] != 0.0) ratio[i] = rigid.ratio[i];
    return ratio;
}

ModalAnalysis torsional_modes(const LinearNetwork& system, const std::vector<double>& ratio, std::size_t reference) {
    ModalAnalysis out;
    out.node_names = system.node_names;
    out.ratio = ratio;
    out.reference_node = reference;
    const std::size_t nodes = system.node_count();
    const auto ns = system.A.rows();
    if (ns == 0) return out;

    // A free rotation: the rigid motion (θ_i = ratio_i, ω = 0) meets no restoring torque.
    Eigen::VectorXd rigid = Eigen::VectorXd::Zero(ns);
    for (std::size_t i = 0; i < nodes; ++i)
        if (i >= system.angle_root.size() || system.angle_root[i] == i)  // a tied node's is its root's
            rigid[static_cast<Eigen::Index>(system.angle_state(i))] = ratio[i];
    const double scale = std::max(system.A.cwiseAbs().maxCoeff(), std::numeric_limits<double>::min());
    out.free_rotation = (system.A * rigid).norm() <= 1e-9 * scale * rigid.norm();

    const Eigen::EigenSolver<Eigen::MatrixXd> solver(system.A, true);
    if (solver.info() != Eigen::Success) throw std::runtime_error("the eigenvalues of the linearised network did not converge");
    const Eigen::VectorXcd lambda = solver.eigenvalues();
    const Eigen::MatrixXcd vectors = solver.eigenvectors();
    double largest = 0.0;
    for (Eigen::Index k = 0; k < ns; ++k) largest = std::max(largest, std::abs(lambda[k]));

    for (Eigen::Index k = 0; k < ns; ++k) {
        const std::complex<double> l = lambda[k];
        if (l.imag() < 0.0) continue;  // the pair's other half
        TorsionalMode m;
        m.eigenvalue = l;
        m.frequency_hz = std::abs(l) / kModesTwoPi;
        m.damped_frequency_hz = l.imag() / kModesTwoPi;
        m.damping_ratio = std::abs(l) > 0.0 ? -l.real() / std::abs(l) : std::numeric_limits<double>::quiet_NaN();
        // An undamped mode's real part is the eigensolver's rounding (about ε·‖A‖, of either
        // sign): reported as ζ = 0, not as ±1e-11.
        if (std::abs(l.real()) <= 1e-12 * scale && l.imag() > 0.0) m.damping_ratio = 0.0;
        m.shape.resize(nodes);
        for (std::size_t i = 0; i < nodes; ++i)
            m.shape[i] = (i < system.angle_factor.size() ? system.angle_factor[i] : 1.0) *
                         vectors(static_cast<Eigen::Index>(system.angle_state(i)), k);
        // Turning as one body: on a line free to rotate, the eigenvalue ~0 or real (the
        // speed's decay under friction) with the shape of the rigid motion.
        const bool tiny = std::abs(l) <= 1e-6 * largest;
        const bool real = l.imag() == 0.0;
        const bool rigid_shape = alignment(m.shape, ratio) > 0.99;
        m.kind = out.free_rotation && rigid_shape && (tiny || real) ? ModeKind::rigid_body
                 : real                                             ? ModeKind::overdamped
                                                                    : ModeKind::oscillating;
        if (m.kind == ModeKind::rigid_body && tiny) {
            // The free angle: λ = 0 to rounding.
            m.frequency_hz = m.damped_frequency_hz = 0.0;
            m.damping_ratio = std::numeric_limits<double>::quiet_NaN();
        }
        out.modes.push_back(std::move(m));
    }
    pair_overdamped_roots(out.modes);
    for (TorsionalMode& m : out.modes) {
        m.shape_common = m.shape;
        for (std::size_t i = 0; i < nodes; ++i) m.shape_common[i] /= ratio[i];
        normalise_to_largest(m.shape);
        m.dominant_node = normalise_to_largest(m.shape_common);
    }
    std::stable_sort(out.modes.begin(), out.modes.end(), [](const TorsionalMode& a, const TorsionalMode& b) {
        const bool ra = a.kind == ModeKind::rigid_body, rb = b.kind == ModeKind::rigid_body;
        if (ra != rb) return ra;
        return a.frequency_hz < b.frequency_hz;
    });
    return out;
}

OperatingPoint window_operating_point(const IdentificationProblem& problem, const std::vector<double>& params,
                                      std::size_t window, const SolvedStart* given) {
    const ProblemDefinition& d = problem.definition();
    if (window >= d.estimation.size()) throw std::runtime_error("there is no estimation window " + std::to_string(window));
    const Window& w = d.estimation[window];
    auto ws = problem.make_workspace();
    problem.use_parameters(params, *ws);
    std::string why;
    const WindowStart start = given && given->x_start.size() == ws->x.size()
                                  ? IdentificationProblem::restore_start(*given, *ws)
                                  : problem.start_window(w, *ws, &why);
    if (start.status != SimulationStatus::ok || !why.empty())
        throw std::runtime_error("the start of estimation window " + w.label + " cannot be prepared" +
                                 (why.empty() ? std::string(": ") + to_string(start.status) : ": " + why));
    OperatingPoint op;
    op.window = window;
    op.label = w.label;
    op.initial_state = initial_state_row(d.initial_state).name;
    const Experiment& ex = problem.experiment();
    op.recording = recording_name(ex, w);
    op.sample = w.start - (w.recording < d.recordings.size() ? d.recordings[w.recording].begin : 0);
    op.time = recording_time(ex, w, d.inputs.time()[w.start]);
    // The state at the window's start (after a warm-up ws->x is at its first scored sample).
    op.x = ws->x_start;
    op.u = ws->u0;
    for (double v : op.x)
        if (!std::isfinite(v)) throw std::runtime_error("the start of estimation window " + w.label + " is not finite");
    return op;
}

ModesStudy study_modes(const IdentificationProblem& problem, const std::vector<double>& params, std::size_t window,
                       AngleDependence angle_dependence, const SolvedStart* given) {
    ModesStudy s;
    s.operating_point = window_operating_point(problem, params, window, given);
    const ProblemDefinition& d = problem.definition();
    s.linear = linearise_network(d.network, params, &d.angle_inputs, s.operating_point.x, s.operating_point.u,
                                 angle_dependence);
    s.modal = torsional_modes(s.linear, node_ratios(d.network, params, 0), 0);
    return s;
}

}  // namespace tvid
