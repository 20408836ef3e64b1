#pragma once
// The files of `tvid profile` (docs/report-format.md, "Output of tvid profile"):
// profile.csv, one row per grid point, and profile.json with the optimum, the 95 % profile
// interval and the linearised one beside it.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "tvid/fit/profile_likelihood.hpp"

namespace tvid {

struct ProfileRunInfo {
    std::string version, command_line, experiment;
};

/// profile.csv: value, cost, delta_chi2, converged, termination, then each other free
/// parameter's refitted value.
std::string profile_csv(const ProfileResult& profile);

nlohmann::json profile_json(const ProfileResult& profile, const ProfileRunInfo& run);

/// Writes both files into `dir` (created if needed), each through a temporary name.
void write_profile_report(const std::filesystem::path& dir, const ProfileResult& profile, const ProfileRunInfo& run);

}  // namespace tvid
