#pragma once
// How numbers are written in report files (docs/report-format.md, conventions): JSON has
// no NaN or infinity, so such values are null; a CSV cell writes NaN as empty and the
// infinities as inf / -inf.

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

namespace tvid {

inline nlohmann::json json_number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

inline std::string csv_cell(double v, const char* format = "%.10g") {
    if (!std::isfinite(v)) return std::isnan(v) ? "" : (v > 0 ? "inf" : "-inf");
    char buf[40];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

}  // namespace tvid
