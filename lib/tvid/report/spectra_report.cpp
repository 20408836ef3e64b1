#include "tvid/io/csv_field.hpp"
#include "tvid/report/spectra_report.hpp"

#include "tvid/util/text.hpp"

#include <cstdio>
#include <sstream>

#include "tvid/experiment/window_recording.hpp"
#include "tvid/fit/fit_verdict.hpp"
#include "tvid/model/parameter_units.hpp"
#include "tvid/report/report_values.hpp"

namespace tvid {

namespace {

std::string output_unit_of(const Experiment& ex, std::size_t k) {
    return output_unit(ex.network, ex.network.outputs[static_cast<std::size_t>(ex.output_indices[k])]);
}

OrderSettings report_order_settings(const Experiment& ex) {
    OrderSettings s;
    s.max_order = kReportMaxOrder;
    s.cycle_deg = ex.cycle_deg;
    return s;
}

void spectra_rows(std::ostringstream& out, const SplitSpectra& s) {
    for (std::size_t f = 0; f < s.frequency_hz.size(); ++f) {
        out << csv_field(s.split) << ',' << csv_cell(s.frequency_hz[f], "%.9g");
        for (const OutputSpectra& o : s.outputs)
            out << ',' << csv_cell(o.measured[f]) << ',' << csv_cell(o.simulated[f]) << ',' << csv_cell(o.residual[f]);
        out << '\n';
    }
}

void order_rows(std::ostringstream& out, const Experiment& ex, const SplitOrders& orders) {
    for (const CycleOrders& c : orders.cycles) {
        const std::string unit = output_unit_of(ex, c.output);
        for (std::size_t i = 0; i < c.residual.order.size(); ++i)
            out << csv_field(orders.split) << ',' << csv_field(c.window) << ',' << c.residual.cycle << ','
                << csv_field(ex.outputs[c.output].model_name) << ',' << csv_field(unit) << ',' << csv_cell(c.residual.order[i], "%g") << ','
                << csv_cell(c.measured.amplitude[i]) << ',' << csv_cell(c.measured.phase_deg[i], "%.6g") << ','
                << csv_cell(c.simulated.amplitude[i]) << ',' << csv_cell(c.simulated.phase_deg[i], "%.6g") << ','
                << csv_cell(c.residual.amplitude[i]) << ',' << csv_cell(c.residual.phase_deg[i], "%.6g") << '\n';
    }
}

}  // namespace

std::string density_unit(const std::string& unit) {
    if (unit.empty() || unit == "1") return "1/Hz";
    if (unit.find_first_of(" /*") != std::string::npos) return "(" + unit + ")^2/Hz";
    return unit + "^2/Hz";
}

bool has_order_spectra(const Experiment& ex) { return !ex.crank_angle.empty(); }

std::string spectra_csv(const Experiment& ex, const Evaluation& ev) {
    std::ostringstream out;
    // Each column's unit in brackets after its name, as in estimation.csv.
    out << "split,frequency [Hz]";
    for (std::size_t k = 0; k < ex.outputs.size(); ++k) {
        const std::string& n = ex.outputs[k].model_name;
        const std::string u = " [" + density_unit(output_unit_of(ex, k)) + "]";
        out << ',' << csv_field(n + "_measured_psd" + u) << ',' << csv_field(n + "_simulated_psd" + u) << ','
            << csv_field(n + "_residual_psd" + u);
    }
    out << '\n';
    spectra_rows(out, split_spectra(ev.estimation, ex.outputs.size()));
    spectra_rows(out, split_spectra(ev.validation, ex.outputs.size()));
    return out.str();
}

std::string orders_csv(const Experiment& ex, const Evaluation& ev) {
    if (!has_order_spectra(ex)) return {};
    std::ostringstream out;
    // The amplitudes in the row's `unit` (the rows hold every output), the phases in degrees.
    out << "split,window,cycle,output,unit,order,measured_amplitude,measured_phase [deg],simulated_amplitude,"
           "simulated_phase [deg],residual_amplitude,residual_phase [deg]\n";
    const OrderSettings settings = report_order_settings(ex);
    const std::vector<RowSpan> recordings = recording_spans(ex);
    order_rows(out, ex, split_orders(ev.estimation, ex.outputs.size(), ex.crank_angle, settings, recordings));
    order_rows(out, ex, split_orders(ev.validation, ex.outputs.size(), ex.crank_angle, settings, recordings));
    return out.str();
}

std::vector<ResidualSpectrumSummary> residual_spectrum_summary(const Experiment& ex, const SplitEvaluation& split) {
    std::vector<ResidualSpectrumSummary> out;
    const SplitSpectra spectra = split_spectra(split, ex.outputs.size());
    bool engine = false;
    for (const ChannelBinding& input : ex.inputs) engine = engine || input.by_angle;
    SplitOrders orders;
    if (has_order_spectra(ex))
        orders = split_orders(split, ex.outputs.size(), ex.crank_angle, report_order_settings(ex), recording_spans(ex));
    for (std::size_t k = 0; k < ex.outputs.size(); ++k) {
        ResidualSpectrumSummary s;
        s.output = ex.outputs[k].model_name;
        s.unit = output_unit_of(ex, k);
        if (k < spectra.outputs.size()) s.band = dominant_band(spectra.frequency_hz, spectra.outputs[k].residual);
        s.segments = spectra.segments;
        s.segment_length = spectra.segment_length;
        s.gaps = spectra.gaps;
        s.resolution_hz = spectra.resolution_hz;
        s.other_rate_samples = spectra.other_rate_samples;
        s.other_rate_hz = spectra.other_rate_hz;
        s.order = dominant_order(orders, k);
        s.engine = engine;
        out.push_back(std::move(s));
    }
    return out;
}

namespace {

nlohmann::json split_residual_spectrum_json(const Experiment& ex, const SplitEvaluation& split) {
    nlohmann::json out = nlohmann::json::object();
    for (const ResidualSpectrumSummary& s : residual_spectrum_summary(ex, split)) {
        if (!s.band.available && !s.order.available) continue;
        nlohmann::json band = nullptr, order = nullptr;
        if (s.band.available)
            band = {{"peak_hz", json_number(s.band.peak_hz)},
                    {"band_hz", {json_number(s.band.band_low_hz), json_number(s.band.band_high_hz)}},
                    {"share", json_number(s.band.share)},
                    {"variance", json_number(s.band.variance)},
                    {"segments", s.segments},
                    {"segment_length", s.segment_length},
                    {"resolution_hz", json_number(s.resolution_hz)},
                    {"gaps", s.gaps},
                    {"sample_rate_hz", json_number(s.resolution_hz * static_cast<double>(s.segment_length))},
                    {"other_rate_samples", s.other_rate_samples}};
        if (s.order.available)
            order = {{"order", json_number(s.order.order)},
                     {"amplitude", json_number(s.order.amplitude)},
                     {"share", json_number(s.order.share)},
                     {"orders_share", json_number(s.order.orders_share)},
                     {"max_order", json_number(s.order.max_order)},
                     {"variance", json_number(s.order.variance)},
                     {"cycles", s.order.cycles}};
        out[s.output] = {{"unit", s.unit}, {"frequency", band}, {"order", order}};
    }
    return out;
}

}  // namespace

nlohmann::json residual_spectrum_json(const Experiment& ex, const Evaluation& ev) {
    return {{"estimation", split_residual_spectrum_json(ex, ev.estimation)},
            {"validation", split_residual_spectrum_json(ex, ev.validation)}};
}

std::string residual_spectrum_line(const ResidualSpectrumSummary& s, const ResidualWhiteness* whiteness) {
    if (whiteness && residual_is_white(*whiteness) && (s.band.available || s.order.available)) {
        char white[200];
        std::snprintf(white, sizeof white, "residual %s: white (Ljung-Box p %.2g over %d lags), no %s stands out",
                      s.output.c_str(), whiteness->p_value, whiteness->lags,
                      s.engine && s.order.available ? "order" : "band");
        return white;
    }
    const auto percent = readable_percent;  // "38 %", "0.39 %"
    char line[320];
    if (s.engine && s.order.available) {
        std::snprintf(line, sizeof line,
                      "residual %s: %s of its variance at order %g (amplitude %.3g %s, %zu cycle%s); orders up to %g: %s",
                      s.output.c_str(), percent(s.order.share).c_str(), s.order.order, s.order.amplitude, s.unit.c_str(),
                      s.order.cycles, s.order.cycles == 1 ? "" : "s", s.order.max_order,
                      percent(s.order.orders_share).c_str());
        return line;
    }
    if (!s.band.available) return {};
    // Beside the share white noise of the same variance would put in that band (its width
    // over the Nyquist frequency), so that a share is read against the noise, as the
    // verdict's systematic share is.
    const double nyquist = 0.5 * s.resolution_hz * static_cast<double>(s.segment_length);
    const double white = nyquist > 0 ? (s.band.band_high_hz - s.band.band_low_hz) / nyquist : 0.0;
    std::snprintf(line, sizeof line, "residual %s: %s of its variance at %.3g–%.3g Hz (peak %.3g Hz)", s.output.c_str(),
                  percent(s.band.share).c_str(), s.band.band_low_hz, s.band.band_high_hz, s.band.peak_hz);
    std::string text = line;
    if (white > 0 && white < 1) text += "; white noise would put " + percent(white) + " there";
    if (s.other_rate_samples > 0) {
        std::snprintf(line, sizeof line, " (at %.4g Hz; %zu samples at %.4g Hz left out)",
                      s.resolution_hz * static_cast<double>(s.segment_length), s.other_rate_samples, s.other_rate_hz);
        text += line;
    }
    return text;
}

}  // namespace tvid
