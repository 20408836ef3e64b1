#include "tvid/util/text.hpp"

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

}  // namespace tvid
