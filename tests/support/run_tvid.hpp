#pragma once
// Runs the tvid binary as a user would and captures what it prints.

#include <string>
#include <vector>

namespace tvid::test {

struct RunResult {
    int exit_code = -1;
    std::string out;  ///< stdout
    std::string err;  ///< stderr
};

/// Runs `tvid args...` in folder `cwd` (empty: the current one), no shell involved.
RunResult run_tvid(const std::vector<std::string>& args, const std::string& cwd = "");

}  // namespace tvid::test
