#include "tvid/util/text.hpp"

#include <algorithm>
#include <cstdio>

namespace tvid {

std::string join_words(const std::vector<std::string>& words) {
    std::string out;
    for (const std::string& w : words) out.append(out.empty() ? "" : ", ").append(w);
    return out;
}

std::string number_text(double value) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.10g", value);
    return buf;
}

namespace {
std::string percent_as(const char* format, double fraction) {
    char buf[32];
    std::snprintf(buf, sizeof buf, format, 100.0 * fraction);
    return buf;
}
}  // namespace

std::string whole_percent(double fraction) { return percent_as("%.0f %%", fraction); }

std::string readable_percent(double fraction) { return percent_as(fraction >= 0.1 ? "%.0f %%" : "%.2g %%", fraction); }

std::size_t edit_distance(const std::string& a, const std::string& b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diagonal = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t up = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
            diagonal = up;
        }
    }
    return row[b.size()];
}

}  // namespace tvid
