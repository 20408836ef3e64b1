#include "tvid/io/csv_field.hpp"
#include "tvid/report/profile_report.hpp"

#include <cmath>
#include <sstream>

#include "tvid/io/atomic_file.hpp"
#include "tvid/io/json_text.hpp"
#include "tvid/report/report_values.hpp"

namespace tvid {

std::string profile_csv(const ProfileResult& profile) {
    std::ostringstream out;
    out << csv_field(profile.parameter) << ",cost,delta_chi2,converged,termination";
    for (const std::string& name : profile.others) out << ',' << csv_field(name);
    out << '\n';
    for (const ProfilePoint& p : profile.points) {
        out << csv_cell(p.value, "%.17g") << ',' << csv_cell(p.cost, "%.17g") << ',' << csv_cell(p.delta_chi2) << ','
            << (p.converged ? "true" : "false") << ',' << csv_field(p.termination);
        for (std::size_t j = 0; j < p.others.size(); ++j) out << ',' << csv_cell(p.others[j], "%.17g");
        out << '\n';
    }
    return out.str();
}

nlohmann::json profile_json(const ProfileResult& profile, const ProfileRunInfo& run) {
    const double t975 = 1.959963984540054;  // the normal quantile: the profile's threshold is χ²₁
    nlohmann::json wald = nullptr;
    if (std::isfinite(profile.std_error))
        wald = nlohmann::json::array({profile.best_value - t975 * profile.std_error, profile.best_value + t975 * profile.std_error});
    return {{"tool", "tvid"},
            {"version", run.version},
            {"command", run.command_line},
            {"experiment", run.experiment},
            {"parameter", profile.parameter},
            {"unit", profile.unit},
            {"optimum", {{"value", profile.best_value},
                         {"cost", profile.best_cost},
                         {"termination", profile.optimum_termination},
                         {"residuals", profile.residuals},
                         {"s2", json_number(profile.s2)},
                         {"std_error", json_number(profile.std_error)}}},
            {"threshold", kProfileThreshold95},
            {"interval95", {{"low", profile.low ? json_number(*profile.low) : nlohmann::json(nullptr)},
                            {"high", profile.high ? json_number(*profile.high) : nlohmann::json(nullptr)},
                            {"open_below", !profile.low},
                            {"open_above", !profile.high},
                            {"disconnected", profile.disconnected}}},
            {"grid", {profile.points.empty() ? 0.0 : profile.points.front().value,
                      profile.points.empty() ? 0.0 : profile.points.back().value}},
            {"linearised_interval95", wald},
            {"better_point_found", profile.better_point_found},
            {"points", profile.points.size()},
            {"threads", profile.threads},
            {"wall_time_s", profile.seconds}};
}

void write_profile_report(const std::filesystem::path& dir, const ProfileResult& profile, const ProfileRunInfo& run) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) throw std::runtime_error("cannot create profile directory " + dir.string() + ": " + ec.message());
    write_output_file(dir, "profile.csv", profile_csv(profile));
    write_output_file(dir, "profile.json", json_text(profile_json(profile, run)) + "\n");
}

}  // namespace tvid
