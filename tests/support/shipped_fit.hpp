#pragma once
// `tvid fit configs/NAME.yaml -o TMP/NAME --threads 2 --json` on a shipped experiment, as a
// user runs it: the summary it prints, the run required to succeed.

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"

namespace tvid::test {

inline nlohmann::json fit_shipped(const TempDir& tmp, const std::string& config) {
    const RunResult r = run_tvid({"fit", (source_dir() / "configs" / (config + ".yaml")).string(), "-o",
                                  (tmp.path() / config).string(), "--threads", "2", "--json"});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    return nlohmann::json::parse(r.out);
}

}  // namespace tvid::test
