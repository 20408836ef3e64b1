// The command line as a whole: `tvid help COMMAND`, the nearest command on a typo, the
// exit statuses in every --help, and -o / --output-dir (and the older --output) in the
// commands that write a directory.
#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"

using namespace tvid::test;

TEST_CASE("tvid help COMMAND prints that command's options", "[e2e][cli]") {
    const RunResult fit = run_tvid({"help", "fit"});
    CHECK(fit.exit_code == 0);
    CHECK_THAT(fit.out, Catch::Contains("--optimizer"));
    CHECK_THAT(fit.out, Catch::Contains("--output-dir"));
    const RunResult frf = run_tvid({"help", "frf"});
    CHECK(frf.exit_code == 0);
    CHECK_THAT(frf.out, Catch::Contains("--input"));
    CHECK_THAT(frf.out, !Catch::Contains("--optimizer"));
    const RunResult unknown = run_tvid({"help", "fitt"});
    CHECK(unknown.exit_code == 2);
    CHECK_THAT(unknown.err, Catch::Contains("'fitt' is not a tvid command"));
}

TEST_CASE("a mistyped command gets the nearest one, in one line with exit 2", "[e2e][cli]") {
    const RunResult r = run_tvid({"fitt", "exp.yaml"});
    CHECK(r.exit_code == 2);
    CHECK(r.err == "tvid: 'fitt' is not a tvid command; did you mean 'fit'? (tvid --help lists them)\n");
    CHECK(r.out.empty());
    const RunResult far = run_tvid({"plot"});
    CHECK(far.exit_code == 2);
    CHECK_THAT(far.err, Catch::Contains("'plot' is not a tvid command"));
    CHECK_THAT(far.err, !Catch::Contains("did you mean"));
}

TEST_CASE("every --help lists the exit statuses", "[e2e][cli]") {
    for (const std::string command : {"", "fit", "batch", "check", "modes", "simulate"}) {
        INFO(command);
        const RunResult r = command.empty() ? run_tvid({"--help"}) : run_tvid({command, "--help"});
        CHECK(r.exit_code == 0);
        CHECK_THAT(r.out, Catch::Contains("Exit status:"));
        CHECK_THAT(r.out, Catch::Contains("130"));
        CHECK_THAT(r.out, Catch::Contains("bad input"));
    }
}

TEST_CASE("fit takes its report directory as -o, --output-dir or --output", "[e2e][cli]") {
    TempDir dir;
    const std::string experiment = std::string(TVID_SOURCE_DIR) + "/configs/cvt_custom_network.yaml";
    for (const std::string flag : {"-o", "--output-dir", "--output"}) {
        INFO(flag);
        const std::string out = (dir.path() / ("report" + flag)).string();
        const RunResult r = run_tvid({"fit", experiment, flag, out, "--optimizer", "lm", "--set", "estimation.cost=l2",
                                      "--set", "estimation.lm.max_iterations=2", "--quiet"});
        CHECK(r.exit_code == 0);
        CHECK(std::filesystem::is_regular_file(std::filesystem::path(out) / "params.json"));
    }
}
