#include "tvid/io/csv_field.hpp"
#include "tvid/report/modes_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "tvid/io/atomic_file.hpp"
#include "tvid/io/json_text.hpp"
#include "tvid/report/report_values.hpp"

namespace tvid {

using nlohmann::json;

namespace {

constexpr double kDegreesPerRadian = 57.29577951308232;

double phase_deg(std::complex<double> v) { return std::abs(v) > 0 ? std::arg(v) * kDegreesPerRadian : 0.0; }

// {node: Re v_i} — the shape's signed amplitude (its phases are 0 or 180° for an undamped mode).
json real_shape_json(const std::vector<std::string>& nodes, const std::vector<std::complex<double>>& shape) {
    json j = json::object();
    for (std::size_t i = 0; i < nodes.size(); ++i) j[nodes[i]] = json_number(shape[i].real());
    return j;
}

json operating_point_json(const ModesStudy& s) {
    const OperatingPoint& op = s.operating_point;
    const std::size_t n = s.linear.node_count();
    json nodes = json::object();
    for (std::size_t i = 0; i < n; ++i)
        nodes[s.linear.node_names[i]] = {{"angle_rad", json_number(op.x[i])}, {"speed_rad_s", json_number(op.x[n + i])}};
    json inputs = json::object();
    for (std::size_t j = 0; j < op.u.size() && j < s.linear.input_names.size(); ++j)
        inputs[s.linear.input_names[j]] = json_number(op.u[j]);
    json out{{"window", op.label},
             {"window_index", op.window},
             {"initial_state", op.initial_state},
             {"sample", op.sample},
             {"time_s", json_number(op.time)},
             {"angle_dependence", angle_dependence_name(s.linear.angle_dependence)},
             {"nodes", nodes},
             {"inputs", inputs}};
    if (!op.recording.empty()) out["recording"] = op.recording;  // data.recordings
    return out;
}

// The operating point in a summary: its window (and recording), start and linearisation.
json operating_point_brief(const OperatingPoint& op, AngleDependence angle_dependence) {
    json out{{"window", op.label},
             {"initial_state", op.initial_state},
             {"time_s", json_number(op.time)},
             {"angle_dependence", angle_dependence_name(angle_dependence)}};
    if (!op.recording.empty()) out["recording"] = op.recording;
    return out;
}

std::string mode_cell(double v, const char* format = "%.6g") { return csv_cell(v, format); }

}  // namespace

json modes_json(const ModesStudy& s, const ModesRunInfo& run) {
    const ModalAnalysis& m = s.modal;
    json elements = json::array();
    for (const ElementLinearisation& e : s.linear.elements)
        elements.push_back({{"element", e.element}, {"kind", e.kind}, {"method", e.method}, {"note", e.note}});
    json held = json::array();
    for (std::size_t i = 0; i < m.node_names.size(); ++i)
        if (s.linear.prescribed[i]) held.push_back(m.node_names[i]);
    json ratios = json::object();
    for (std::size_t i = 0; i < m.node_names.size(); ++i) ratios[m.node_names[i]] = json_number(m.ratio[i]);
    json modes = json::array();
    for (std::size_t k = 0; k < m.modes.size(); ++k) {
        const TorsionalMode& mode = m.modes[k];
        json magnitude = json::object(), phase = json::object();
        for (std::size_t i = 0; i < m.node_names.size(); ++i) {
            magnitude[m.node_names[i]] = json_number(std::abs(mode.shape[i]));
            phase[m.node_names[i]] = json_number(phase_deg(mode.shape[i]));
        }
        modes.push_back({{"mode", k + 1},
                         {"kind", mode_kind_name(mode.kind)},
                         {"eigenvalue", {{"re", json_number(mode.eigenvalue.real())}, {"im", json_number(mode.eigenvalue.imag())}}},
                         {"second_eigenvalue", json_number(mode.second_eigenvalue)},
                         {"frequency_hz", json_number(mode.frequency_hz)},
                         {"damped_frequency_hz", json_number(mode.damped_frequency_hz)},
                         {"damping_ratio", json_number(mode.damping_ratio)},
                         {"dominant_node", m.node_names[mode.dominant_node]},
                         {"shape", real_shape_json(m.node_names, mode.shape)},
                         {"shape_magnitude", magnitude},
                         {"shape_phase_deg", phase},
                         {"shape_common_shaft", real_shape_json(m.node_names, mode.shape_common)}});
    }
    return {{"tool", "tvid"},
            {"version", run.version},
            {"command", run.command_line},
            {"experiment", run.experiment},
            {"model", run.model},
            {"operating_point", operating_point_json(s)},
            {"linearisation",
             {{"angle_dependence", angle_dependence_name(s.linear.angle_dependence)},
              {"nodes", m.node_names},
              {"held_nodes", held},
              {"states", s.linear.state_names},
              {"reference_node", m.node_names.empty() ? std::string() : m.node_names[m.reference_node]},
              {"ratios", ratios},
              {"free_rotation", m.free_rotation},
              {"elements", elements}}},
            {"modes", modes}};
}

json modes_summary_json(const ModesStudy& s) {
    const OperatingPoint& op = s.operating_point;
    json modes = json::array();
    for (const TorsionalMode& mode : s.modal.modes)
        modes.push_back({{"kind", mode_kind_name(mode.kind)},
                         {"frequency_hz", json_number(mode.frequency_hz)},
                         {"damped_frequency_hz", json_number(mode.damped_frequency_hz)},
                         {"damping_ratio", json_number(mode.damping_ratio)},
                         {"shape", real_shape_json(s.modal.node_names, mode.shape)}});
    return {{"operating_point",
             operating_point_brief(op, s.linear.angle_dependence)},
            {"modes", modes}};
}

json fit_modes_json(const IdentificationProblem& problem, const std::vector<double>& params, const SolvedStart* start) {
    try {
        return modes_summary_json(study_modes(problem, params, 0, AngleDependence::revolution_mean, start));
    } catch (const std::exception&) {
        return nullptr;  // no start at these parameters, or no eigenvalues: no block
    }
}

std::string modes_csv(const ModesStudy& s) {
    const ModalAnalysis& m = s.modal;
    std::ostringstream out;
    out << "mode,kind,frequency_hz,damped_frequency_hz,damping_ratio,eigenvalue_re,eigenvalue_im,dominant_node";
    for (const std::string& n : m.node_names)
        out << ',' << csv_field("shape_" + n) << ',' << csv_field("magnitude_" + n) << ',' << csv_field("phase_deg_" + n);
    for (const std::string& n : m.node_names) out << ',' << csv_field("common_" + n);
    out << '\n';
    for (std::size_t k = 0; k < m.modes.size(); ++k) {
        const TorsionalMode& mode = m.modes[k];
        out << k + 1 << ',' << mode_kind_name(mode.kind) << ',' << csv_cell(mode.frequency_hz) << ','
            << csv_cell(mode.damped_frequency_hz) << ',' << csv_cell(mode.damping_ratio) << ','
            << csv_cell(mode.eigenvalue.real()) << ',' << csv_cell(mode.eigenvalue.imag()) << ','
            << csv_field(m.node_names[mode.dominant_node]);
        for (std::size_t i = 0; i < m.node_names.size(); ++i)
            out << ',' << mode_cell(mode.shape[i].real()) << ',' << mode_cell(std::abs(mode.shape[i])) << ','
                << mode_cell(phase_deg(mode.shape[i]), "%.2f");
        for (std::size_t i = 0; i < m.node_names.size(); ++i) out << ',' << mode_cell(mode.shape_common[i].real());
        out << '\n';
    }
    return out.str();
}

std::string modes_table_text(const ModesStudy& s) {
    const OperatingPoint& op = s.operating_point;
    std::ostringstream out;
    out << "modes at the start of estimation window " << op.label << " (" << op.initial_state << " start, t = "
        << csv_cell(op.time, "%.6g") << " s); angle-dependent elements at their "
        << (s.linear.angle_dependence == AngleDependence::revolution_mean ? "mean over a revolution" : "operating point")
        << '\n';
    char line[160];
    std::snprintf(line, sizeof line, "%5s  %-12s %12s %12s %10s  %s\n", "mode", "kind", "f_n [Hz]", "f_d [Hz]", "zeta",
                  "dominant node");
    out << line;
    for (std::size_t k = 0; k < s.modal.modes.size(); ++k) {
        const TorsionalMode& m = s.modal.modes[k];
        const std::string zeta = std::isfinite(m.damping_ratio) ? csv_cell(m.damping_ratio, "%.4g") : "-";
        std::snprintf(line, sizeof line, "%5zu  %-12s %12.5g %12.5g %10s  %s\n", k + 1, mode_kind_name(m.kind),
                      m.frequency_hz, m.damped_frequency_hz, zeta.c_str(),
                      s.modal.node_names[m.dominant_node].c_str());
        out << line;
    }
    return out.str();
}

void write_modes_report(const std::filesystem::path& dir, const ModesStudy& study, const ModesRunInfo& run) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) throw std::runtime_error("cannot create directory " + dir.string() + ": " + ec.message());
    write_output_file(dir, "modes.csv", modes_csv(study));
    write_output_file(dir, "modes.json", json_text(modes_json(study, run)) + "\n");
}

json frf_json(const FrfComparison& f, const ModesRunInfo& run) {
    json rows = json::array();
    for (std::size_t k = 0; k < f.frequency_hz.size(); ++k) {
        json row{{"frequency_hz", json_number(f.frequency_hz[k])},
                 {"model_magnitude", json_number(std::abs(f.model[k]))},
                 {"model_phase_deg", json_number(phase_deg(f.model[k]))}};
        if (f.measured) {
            row["measured_magnitude"] = json_number(std::abs(f.measured_h1[k]));
            row["measured_phase_deg"] = json_number(phase_deg(f.measured_h1[k]));
            row["coherence"] = json_number(f.coherence[k]);
        }
        rows.push_back(row);
    }
    json curve{{"frequency_hz", json::array()}, {"magnitude", json::array()}, {"phase_deg", json::array()}};
    for (std::size_t k = 0; k < f.curve.size(); ++k) {
        curve["frequency_hz"].push_back(json_number(f.curve_frequency_hz[k]));
        curve["magnitude"].push_back(json_number(std::abs(f.curve[k])));
        curve["phase_deg"].push_back(json_number(phase_deg(f.curve[k])));
    }
    const OperatingPoint& op = f.operating_point;
    return {{"tool", "tvid"},
            {"version", run.version},
            {"command", run.command_line},
            {"experiment", run.experiment},
            {"model", run.model},
            {"input", f.input},
            {"output", f.output},
            {"input_unit", f.input_unit},
            {"output_unit", f.output_unit},
            {"magnitude_unit", f.output_unit + " per " + f.input_unit},
            {"operating_point",
             operating_point_brief(op, f.angle_dependence)},
            {"measured",
             {{"available", f.measured},
              {"estimator", "H1 = S_xy / S_xx, Welch, Hann, 50 % overlap"},
              {"windows", f.windows},
              {"sample_rate_hz", json_number(f.sample_rate_hz)},
              {"segment_length", f.segment_length},
              {"segments", f.segments},
              {"resolution_hz", json_number(f.resolution_hz)},
              {"gaps", f.gaps},
              {"left_out_windows", f.left_out},
              {"coherence_defined", f.segments >= 2}}},
            {"undamped_resonances_hz", f.undamped_hz},
            {"rows", rows},
            {"model_curve", curve}};
}

std::string frf_csv(const FrfComparison& f) {
    std::ostringstream out;
    out << "frequency_hz,model_magnitude,model_phase_deg,measured_magnitude,measured_phase_deg,coherence\n";
    for (std::size_t k = 0; k < f.frequency_hz.size(); ++k) {
        out << csv_cell(f.frequency_hz[k]) << ',' << csv_cell(std::abs(f.model[k])) << ','
            << csv_cell(phase_deg(f.model[k]), "%.4f");
        if (f.measured)
            out << ',' << csv_cell(std::abs(f.measured_h1[k])) << ',' << csv_cell(phase_deg(f.measured_h1[k]), "%.4f")
                << ',' << csv_cell(f.coherence[k], "%.5f");
        else
            out << ",,,";
        out << '\n';
    }
    return out.str();
}

void write_frf_report(const std::filesystem::path& dir, const FrfComparison& frf, const ModesRunInfo& run) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) throw std::runtime_error("cannot create directory " + dir.string() + ": " + ec.message());
    write_output_file(dir, "frf.csv", frf_csv(frf));
    write_output_file(dir, "frf.json", json_text(frf_json(frf, run)) + "\n");
}

// The windows the measured H1 left out, at another sample rate than its own.
static std::string left_out_text(const FrfComparison& f) {
    if (f.left_out.empty()) return "";
    std::string text = "; left out at another sample rate than its " + csv_cell(f.sample_rate_hz, "%.4g") + " Hz: ";
    for (std::size_t i = 0; i < f.left_out.size(); ++i) text += (i ? ", " : "") + f.left_out[i];
    return text;
}

std::string frf_summary_text(const FrfComparison& f) {
    std::ostringstream out;
    out << "FRF " << f.input << " -> " << f.output << " [" << f.output_unit << " per " << f.input_unit
        << "], model linearised at the start of window " << f.operating_point.label << "; ";
    if (f.measured)
        out << "measured H1 over " << f.windows.size() << " estimation window(s): " << f.segments << " segments of "
            << f.segment_length << " samples, " << csv_cell(f.sample_rate_hz / static_cast<double>(f.segment_length), "%.4g")
            << " Hz resolution" << (f.gaps > 0 ? ", cut at " + std::to_string(f.gaps) + " gap(s) in the recording" : "")
            << (f.segments < 2 ? "; one segment: no coherence" : "") << left_out_text(f) << "\n";
    else
        out << "no measured H1\n";
    // The model's resonance peaks (local maxima of |H| on the fine curve), the largest
    // first, each beside the measured H1 in the nearest bin of the measurement's grid.
    const auto& c = f.curve;
    char line[200];
    // An undamped mode's resonance: |H| is infinite there (the curve only approaches it).
    const auto near_undamped = [&](double fk) {
        for (const double fn : f.undamped_hz)
            if (std::abs(fk - fn) <= 0.02 * fn) return true;
        return false;
    };
    for (const double fn : f.undamped_hz) {
        std::snprintf(line, sizeof line, "  model resonance %10.4g Hz  |H| infinite (an undamped mode)\n", fn);
        out << line;
    }
    std::vector<std::size_t> peaks;
    for (std::size_t k = 1; k + 1 < c.size(); ++k)
        if (std::abs(c[k]) > std::abs(c[k - 1]) && std::abs(c[k]) >= std::abs(c[k + 1]) &&
            !near_undamped(f.curve_frequency_hz[k]))
            peaks.push_back(k);
    std::sort(peaks.begin(), peaks.end(), [&](std::size_t a, std::size_t b) { return std::abs(c[a]) > std::abs(c[b]); });
    if (peaks.size() > 5) peaks.resize(5);
    for (std::size_t k : peaks) {
        const double fk = f.curve_frequency_hz[k];
        std::size_t bin = 0;
        for (std::size_t i = 1; i < f.frequency_hz.size(); ++i)
            if (std::abs(f.frequency_hz[i] - fk) < std::abs(f.frequency_hz[bin] - fk)) bin = i;
        if (f.measured && std::isfinite(f.coherence[bin]))
            std::snprintf(line, sizeof line,
                          "  model peak %10.4g Hz  |H| %10.4g   measured at %8.4g Hz: |H1| %10.4g  coherence %.3f\n", fk,
                          std::abs(c[k]), f.frequency_hz[bin], std::abs(f.measured_h1[bin]), f.coherence[bin]);
        else if (f.measured)
            std::snprintf(line, sizeof line, "  model peak %10.4g Hz  |H| %10.4g   measured at %8.4g Hz: |H1| %10.4g\n",
                          fk, std::abs(c[k]), f.frequency_hz[bin], std::abs(f.measured_h1[bin]));
        else
            std::snprintf(line, sizeof line, "  model peak %10.4g Hz  |H| %10.4g\n", fk, std::abs(c[k]));
        out << line;
    }
    return out.str();
}

}  // namespace tvid
