// The command line as a whole: `tvid help COMMAND`, the nearest command on a typo, the
// exit statuses in every --help, -o / --output-dir (and the older --output) in the
// commands that write a directory and in simulate and validate, and no file that tvid did
// not write replaced without --force (simulate's and validate's -o, --write-reference).
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

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
    CHECK_THAT(unknown.err, Catch::Contains("'fitt' is not a tvid command; did you mean 'fit'?"));
    // `help help` is help's own; a command's first letters or its name in capitals get it.
    const RunResult help = run_tvid({"help", "help"});
    CHECK(help.exit_code == 0);
    CHECK_THAT(help.out, Catch::Contains("tvid help COMMAND"));
    const RunResult sim = run_tvid({"help", "sim"});
    CHECK(sim.exit_code == 2);
    CHECK(sim.err == "tvid help: 'sim' is not a tvid command; did you mean 'simulate'? (tvid --help lists them)\n");
    const RunResult capitals = run_tvid({"help", "FIT"});
    CHECK(capitals.exit_code == 2);
    CHECK_THAT(capitals.err, Catch::Contains("did you mean 'fit'?"));
    // `tvid help` alone lists the commands, as `tvid --help` does.
    const RunResult all = run_tvid({"help"});
    CHECK(all.exit_code == 0);
    CHECK(all.out == run_tvid({"--help"}).out);
    CHECK_THAT(all.out, Catch::Contains("simulate") && Catch::Contains("batch"));
}

// The command table's completeness: every row a command's file defines
// (`CommandRow NAME_command_row()` in apps/tvid/*.cpp) is in command_table(), and
// `tvid help NAME` knows it.
TEST_CASE("every command row that a command's file defines is in the table and has help", "[e2e][cli]") {
    const auto read = [](const std::filesystem::path& file) {
        std::ifstream in(file);
        std::stringstream text;
        text << in.rdbuf();
        return text.str();
    };
    const std::filesystem::path apps = source_dir() / "apps/tvid";
    const std::regex defined(R"(\nCommandRow ([a-z_]+)_command_row\(\) \{)");
    std::set<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(apps)) {
        if (entry.path().extension() != ".cpp") continue;
        const std::string text = read(entry.path());
        for (auto m = std::sregex_iterator(text.begin(), text.end(), defined); m != std::sregex_iterator(); ++m)
            names.insert((*m)[1].str());
    }
    REQUIRE(names.size() >= 10);
    const std::string table = read(apps / "command_table.cpp");
    const RunResult all = run_tvid({"--help"});
    for (const std::string& name : names) {
        INFO(name);
        CHECK_THAT(table, Catch::Contains(name + "_command_row(),"));
        CHECK(run_tvid({"help", name}).exit_code == 0);
        CHECK_THAT(all.out, Catch::Contains(name));
    }
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

TEST_CASE("simulate and validate write to -o FILE or into --output-dir DIR", "[e2e][cli]") {
    TempDir dir;
    const std::string experiment = std::string(TVID_SOURCE_DIR) + "/configs/cvt_custom_network.yaml";
    const auto simulate = [&](const std::vector<std::string>& more) {
        std::vector<std::string> args{"simulate", experiment, "-q"};
        args.insert(args.end(), more.begin(), more.end());
        return run_tvid(args);
    };
    CHECK(simulate({"-o", (dir.path() / "mine.csv").string()}).exit_code == 0);
    CHECK(std::filesystem::is_regular_file(dir.path() / "mine.csv"));
    const std::filesystem::path sub = dir.path() / "sub";
    std::filesystem::create_directory(sub);
    CHECK(simulate({"--output-dir", sub.string()}).exit_code == 0);
    CHECK(std::filesystem::is_regular_file(sub / "simulation.csv"));
    dir.write("p.json", "{\"k_minus\": 3000}");
    CHECK(run_tvid({"validate", experiment, "--params", (dir.path() / "p.json").string(), "--output-dir", sub.string(),
                    "-q"}).exit_code == 0);
    CHECK_THAT(read_text(sub / "validation.json"), Catch::Contains("\"written_by\": \"tvid validate\""));
}

TEST_CASE("simulate and validate create --output-dir NEWDIR, and refuse -o into a missing folder before the work",
          "[e2e][cli]") {
    TempDir dir;
    const std::string experiment = std::string(TVID_SOURCE_DIR) + "/configs/cvt_custom_network.yaml";
    const std::filesystem::path params = dir.write("p.json", "{\"k_minus\": 3000}");
    const std::filesystem::path fresh = dir.path() / "new" / "deeper";
    CHECK(run_tvid({"simulate", experiment, "--output-dir", fresh.string(), "-q"}).exit_code == 0);
    CHECK(std::filesystem::is_regular_file(fresh / "simulation.csv"));
    CHECK(run_tvid({"validate", experiment, "--params", params.string(), "--output-dir", (dir.path() / "v").string(),
                    "-q"}).exit_code == 0);
    CHECK(std::filesystem::is_regular_file(dir.path() / "v" / "validation.json"));

    // -o FILE in a folder that is not there: one line, exit 2, and nothing computed (no
    // summary on stdout, which --quiet would hide, so without it).
    const std::filesystem::path missing = dir.path() / "missing" / "x.csv";
    const RunResult simulate = run_tvid({"simulate", experiment, "-o", missing.string()});
    CHECK(simulate.exit_code == 2);
    CHECK(simulate.err == missing.string() + ": its folder " + (dir.path() / "missing").string() +
                              " does not exist: create it first, or give another name\n");
    CHECK(simulate.out.empty());
    const RunResult validate =
        run_tvid({"validate", experiment, "--params", params.string(), "-o", (dir.path() / "missing" / "v.json").string()});
    CHECK(validate.exit_code == 2);
    CHECK(validate.out.empty());
    CHECK_FALSE(std::filesystem::exists(dir.path() / "missing"));
}

TEST_CASE("a file tvid did not write is replaced only with --force", "[e2e][cli]") {
    TempDir dir;
    const std::string experiment = std::string(TVID_SOURCE_DIR) + "/configs/cvt_custom_network.yaml";
    const std::filesystem::path csv = dir.path() / "mine.csv", json = dir.path() / "mine.json",
                                params = dir.path() / "p.json";
    dir.write("mine.csv", "my own notes\n");
    dir.write("mine.json", "{\"mine\": true}\n");
    dir.write("p.json", "{\"k_minus\": 3000}");
    // simulate -o over a user's CSV: refused in one line, the file untouched; --force replaces it.
    RunResult r = run_tvid({"simulate", experiment, "-o", csv.string(), "-q"});
    CHECK(r.exit_code == 2);
    CHECK(r.err == csv.string() + ": exists and is not a simulation CSV that tvid wrote: give --force to replace it, or "
                                  "another name\n");
    CHECK(read_text(csv) == "my own notes\n");
    CHECK(run_tvid({"simulate", experiment, "-o", csv.string(), "-q", "--force"}).exit_code == 0);
    CHECK(read_text(csv).rfind("t [s],window,", 0) == 0);
    CHECK(run_tvid({"simulate", experiment, "-o", csv.string(), "-q"}).exit_code == 0);  // its own file: replaced
    // validate -o likewise.
    r = run_tvid({"validate", experiment, "--params", params.string(), "-o", json.string(), "-q"});
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Catch::Contains("is not a validation JSON that tvid wrote"));
    CHECK(read_text(json) == "{\"mine\": true}\n");
    CHECK(run_tvid({"validate", experiment, "--params", params.string(), "-o", json.string(), "-q", "--force"})
              .exit_code == 0);
    CHECK(run_tvid({"validate", experiment, "--params", params.string(), "-o", json.string(), "-q"}).exit_code == 0);
    // --write-reference over a hand-kept reference.
    const std::filesystem::path report = dir.path() / "report", reference = dir.path() / "ref.json";
    REQUIRE(run_tvid({"fit", experiment, "-o", report.string(), "--optimizer", "lm", "--set", "estimation.cost=l2",
                      "-q"}).exit_code == 0);
    dir.write("ref.json", "{\"parameters\": {\"k_minus\": {\"expected\": 3000, \"rel\": 0.5}}}\n");
    r = run_tvid({"check", report.string(), "--write-reference", reference.string(), "-q"});
    CHECK(r.exit_code == 2);
    CHECK_THAT(r.err, Catch::Contains("is not a reference that tvid wrote"));
    CHECK_THAT(read_text(reference), Catch::Contains("\"rel\": 0.5"));
    CHECK(run_tvid({"check", report.string(), "--write-reference", reference.string(), "-q", "--force"}).exit_code == 0);
    CHECK(run_tvid({"check", report.string(), "--write-reference", reference.string(), "-q"}).exit_code == 0);
}

}  // namespace TVID_UNITY_ID
