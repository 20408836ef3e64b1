#pragma once
// `tvid fit configs/NAME.yaml -o TMP/NAME --threads 2 --json` on a shipped experiment, as a
// user runs it: the summary it prints, the run required to succeed; and a shipped
// experiment's text, to write a variant of it.

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

/// `text` with its first `from` replaced by `to`; the test fails when `from` is not there.
inline void replace_once(std::string& text, const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    REQUIRE(at != std::string::npos);
    text.replace(at, from.size(), to);
}

/// configs/NAME.yaml with its first "../data/" made absolute: a variant of it written
/// elsewhere reads the same recording.
inline std::string shipped_config_text(const std::string& config) {
    std::string text = read_text(source_dir() / "configs" / (config + ".yaml"));
    replace_once(text, "../data/", (source_dir() / "data").string() + "/");
    return text;
}

}  // namespace tvid::test
