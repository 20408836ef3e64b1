#include "tvid/optim/nlopt_algorithms.hpp"

#include <nlopt.h>

#include <algorithm>
#include <cctype>

namespace tvid {

namespace {

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

std::string upper_case(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
    return s;
}

NloptAlgorithm describe(int code) {
    const auto a = static_cast<nlopt_algorithm>(code);
    NloptAlgorithm info;
    info.code = code;
    info.name = nlopt_algorithm_to_string(a);
    info.description = nlopt_algorithm_name(a);
    info.global = info.name[0] == 'G';
    info.gradient = info.name.size() > 1 && info.name[1] == 'D';
    info.needs_local = info.name == "G_MLSL" || info.name == "G_MLSL_LDS" || info.name == "AUGLAG" ||
                       info.name == "AUGLAG_EQ";
    info.takes_local = info.name.find("MLSL") != std::string::npos || info.name.find("AUGLAG") != std::string::npos;
    return info;
}

bool compiled(int code) {
    const std::string description = nlopt_algorithm_name(static_cast<nlopt_algorithm>(code));
    return description.find("NOT COMPILED") == std::string::npos;
}

}  // namespace

std::vector<NloptAlgorithm> nlopt_algorithms() {
    std::vector<NloptAlgorithm> out;
    for (int code = 0; code < NLOPT_NUM_ALGORITHMS; ++code)
        if (compiled(code)) out.push_back(describe(code));
    return out;
}

std::optional<NloptAlgorithm> find_nlopt_algorithm(const std::string& name) {
    std::string key = upper_case(name);
    if (starts_with(key, "NLOPT_")) key = key.substr(6);
    for (int code = 0; code < NLOPT_NUM_ALGORITHMS; ++code)
        if (key == nlopt_algorithm_to_string(static_cast<nlopt_algorithm>(code)))
            return compiled(code) ? std::optional<NloptAlgorithm>(describe(code)) : std::nullopt;
    return std::nullopt;
}

std::string nlopt_algorithm_list() {
    std::string out;
    for (const NloptAlgorithm& a : nlopt_algorithms()) out += (out.empty() ? "" : ", ") + a.name;
    return out;
}

}  // namespace tvid
