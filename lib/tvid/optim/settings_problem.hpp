#pragma once
// What the one check of an optimizer's settings finds wrong (after Ceres'
// Solver::Options::IsValid): the settings key at fault and what is wrong with it. Each
// optimizer's options header declares its `validate`, and its own file defines it; the
// experiment reader turns a problem into "FILE:LINE: estimation.<section>.<key>: <message>".

#include <optional>
#include <string>
#include <utility>

namespace tvid {

struct SettingsProblem {
    std::string key;       ///< the key in the optimizer's section, e.g. "particles"
    std::string message;   ///< what is wrong, e.g. "particles must be between 1 and 1000000"
    bool missing = false;  ///< the key is missing (reported at the section, not at the key)
};

inline std::optional<SettingsProblem> settings_problem(std::string key, std::string message) {
    return SettingsProblem{std::move(key), std::move(message)};
}

}  // namespace tvid
