// The bounds every input is held to: regular files of a stated size, JSON of bounded
// depth without repeated keys, CSV headers checked in linear time, step counts that cannot
// overflow, an output directory one run holds at a time, and simulations that a stop
// request reaches.
#include <catch2/catch.hpp>
#include <sys/stat.h>

#include <chrono>
#include <functional>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "support/test_files.hpp"
#include "tvid/check/parameter_expression.hpp"
#include "tvid/io/atomic_file.hpp"
#include "tvid/io/csv_table.hpp"
#include "tvid/io/input_file.hpp"
#include "tvid/io/json_file.hpp"
#include "tvid/io/json_text.hpp"
#include "tvid/io/output_directory.hpp"
#include "tvid/sim/observation_loops.hpp"
#include "tvid/util/input_error.hpp"
#include "tvid/util/stop_request.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;
using tvid::test::TempDir;
namespace fs = std::filesystem;

namespace {

std::string problem_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.problem();
    }
    return "no error";
}

}  // namespace

TEST_CASE("read_input_file reads regular files whole and refuses everything else by name", "[io][limits]") {
    TempDir tmp;
    const fs::path file = tmp.write("a.txt", "hello\n");
    CHECK(read_input_file(file, "data file", 100) == "hello\n");
    CHECK(problem_of([&] { read_input_file(tmp.path() / "none", "data file", 100); }) == "no such data file");
    CHECK(problem_of([&] { read_input_file(tmp.path(), "data file", 100); }) == "the data file is a directory, not a file");
    CHECK(problem_of([&] { read_input_file("/dev/zero", "data file", 100); }) == "the data file is a device, not a file");
    const fs::path fifo = tmp.path() / "fifo";
    REQUIRE(::mkfifo(fifo.c_str(), 0644) == 0);
    CHECK(problem_of([&] { read_input_file(fifo, "data file", 100); }) == "the data file is a named pipe (FIFO), not a file");
    CHECK(not_a_file_reason(fifo) == "is a named pipe (FIFO)");
    CHECK(not_a_file_reason(file).empty());
    const fs::path loop = tmp.path() / "loop";
    fs::create_symlink(loop, loop);
    CHECK(problem_of([&] { read_input_file(loop, "data file", 100); }) == "the data file is a symbolic link loop");
    // Size: the limit is checked before reading; exactly the limit is fine.
    CHECK(read_input_file(file, "data file", 6).size() == 6);
    CHECK(problem_of([&] { read_input_file(file, "data file", 5); }) == "the data file is 6 bytes, more than the 5 bytes tvid reads");
    CHECK(byte_size_text(4.0 * (1 << 20)) == "4.19 MB");
}

TEST_CASE("JSON files are parsed with bounded depth and without repeated keys", "[io][limits]") {
    CHECK(parse_json_text<>(R"({"a": [1, {"b": 2}]})", "f.json")["a"][1]["b"] == 2);
    std::string deep(kMaxJsonDepth + 1, '[');
    deep += std::string(kMaxJsonDepth + 1, ']');
    CHECK(problem_of([&] { parse_json_text<>(deep, "f.json"); }) == "nested more than 64 levels deep");
    std::string shallow(kMaxJsonDepth, '[');
    shallow += std::string(kMaxJsonDepth, ']');
    CHECK_NOTHROW(parse_json_text<>(shallow, "f.json"));
    CHECK(problem_of([&] { parse_json_text<nlohmann::ordered_json>(R"({"a": 1, "b": {"a": 2, "a": 3}})", "f.json"); }) ==
          "the key \"a\" appears twice in one object");
    // The same key in sibling objects is not a repetition.
    CHECK_NOTHROW(parse_json_text<>(R"([{"a": 1}, {"a": 2}])", "f.json"));
    // A syntax error names its line.
    try {
        parse_json_text<>("{\n\"a\": 1,\n}", "f.json");
        FAIL("no exception");
    } catch (const InputError& e) {
        CHECK(e.line() == 3);
        CHECK(e.file() == "f.json");
    }
}

TEST_CASE("JSON text replaces bytes that are not UTF-8 instead of throwing", "[io][limits]") {
    const nlohmann::json j = {{"name", std::string("caf\xe9")}};
    CHECK(json_text(j, -1) == "{\"name\":\"caf\xef\xbf\xbd\"}");
}

TEST_CASE("a CSV header of 200 000 columns is checked in linear time, duplicates named", "[io][limits][csv]") {
    TempDir tmp;
    std::string header = "t";
    for (int i = 1; i < 200000; ++i) header += ",c" + std::to_string(i);
    std::string row = "0";
    for (int i = 1; i < 200000; ++i) row += ",1";
    const auto started = std::chrono::steady_clock::now();
    const CsvTable table = CsvTable::read(tmp.write("wide.csv", header + "\n" + row + "\n" + "1" + row.substr(1) + "\n"));
    CHECK(table.column_names().size() == 200000);
    CHECK(table.has_column("c199999"));
    CHECK(table.column("c123456").size() == 2);
    const std::string repeated = header + ",c7\n" + row + ",1\n";
    CHECK(problem_of([&] { CsvTable::read(tmp.write("dup.csv", repeated)); }) ==
          "column c7 appears twice (columns 8 and 200001)");
    // Printed, not asserted (a shared machine): a quadratic header took 24 s here.
    WARN("two 200 000-column files read in "
         << std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count() << " s");
}

TEST_CASE("the content hash is of the bytes read", "[io][limits]") {
    TempDir tmp;
    const fs::path f = tmp.write("d.csv", "t,y\n0,1\n1,2\n");
    const CsvTable table = CsvTable::read(f);
    fs::remove(f);  // gone after reading: the table still knows what it read
    // sha256sum of the same bytes
    CHECK(table.content_sha256() == "97d7e2cc1ac3e40d57582211c867e0cc585296dbb7aad908d5a86bc1aba3eb6c");
}

namespace {

/// The hooks of a march that only looks: nothing to read, nothing sampled.
struct OnlyGoOn {
    void begin(std::size_t) {}
    SimulationStatus arrive(std::size_t) { return SimulationStatus::ok; }
};

/// The sample loop over `time` from sample 0 to `last` in fixed substeps of at most max_step.
template <class Step>
SimulationStatus march_fixed(const std::vector<double>& time, std::size_t last, double max_step, Step step) {
    return march_over_samples(0, last, FixedSubsteps(time, max_step, step, [] { return SimulationStatus::ok; }),
                              OnlyGoOn{});
}

}  // namespace

TEST_CASE("fixed-step counts are doubles, and a march past the cap stops instead of wrapping", "[sim][limits]") {
    CHECK(substeps_over(1.0, 0.0) == 1.0);
    CHECK(substeps_over(1e-3, 1e-3) == 1.0);
    CHECK(substeps_over(1e-3, 1e-4) == 10.0);
    CHECK(substeps_over(1e7, 1e-3) == 1e10);  // an int would have wrapped
    const std::vector<double> time{0.0, 1e-3, 2e-3, 2e-3 + 1e7};
    const FixedStepCount c = fixed_steps_over(time, 1e-3);
    CHECK(c.longest == 1e10);
    CHECK(c.longest_at == 2);
    CHECK(c.total == 2 + 1e10);
    int steps = 0;
    const SimulationStatus status = march_fixed(time, 3, 1e-3, [&](const FixedStep&) { ++steps; });
    CHECK(status == SimulationStatus::step_budget_exceeded);
    CHECK(steps == 2);  // the two ordinary intervals, then the refusal
}

TEST_CASE("a stop request ends a march only while simulations are interruptible", "[sim][limits]") {
    const std::vector<double> time{0.0, 1.0};
    long long steps = 0;
    auto march = [&] {
        steps = 0;
        return march_fixed(time, 1, 1e-6, [&](const FixedStep&) { ++steps; });
    };
    stop_request() = true;
    CHECK(march() == SimulationStatus::ok);  // not armed: the evaluation of a report runs whole
    CHECK(steps == 1000000);
    {
        const InterruptibleSimulations armed(true);
        CHECK(march() == SimulationStatus::stopped_by_request);  // at the first sample
        CHECK(steps == 0);
        // A request during a long interval is seen within kStopCheckInterval substeps.
        stop_request() = false;
        steps = 0;
        const SimulationStatus status = march_fixed(time, 1, 1e-6, [&](const FixedStep&) {
            if (++steps == 10) stop_request() = true;
        });
        CHECK(status == SimulationStatus::stopped_by_request);
        CHECK(steps == static_cast<long long>(kStopCheckInterval));
        stop_request() = true;
    }
    {
        const SimulationGracePeriod grace(60.0);  // within the grace period it runs
        CHECK(march() == SimulationStatus::ok);
    }
    {
        const SimulationGracePeriod grace(-1.0);  // past it, it is cut
        CHECK(march() == SimulationStatus::stopped_by_request);
    }
    stop_request() = false;
    const InterruptibleSimulations armed(true);
    CHECK(march() == SimulationStatus::ok);  // no request, nothing stops
}

TEST_CASE("an output directory is held by one run at a time", "[io][limits]") {
    TempDir tmp;
    const fs::path dir = tmp.path() / "out";
    {
        const OutputDirectoryLock first = prepare_output_directory(dir, "report directory");
        CHECK(first.held());
        const std::string problem = problem_of([&] { (void)prepare_output_directory(dir, "report directory"); });
        CHECK(problem.rfind("the report directory is in use by another tvid run (process ", 0) == 0);
    }
    // Released with its holder.
    CHECK(prepare_output_directory(dir, "report directory").held());
}

TEST_CASE("only tvid's own temporary files are swept from an output directory", "[io][limits]") {
    CHECK(is_leftover_temporary("params.json.tvid-tmp.4242"));
    CHECK_FALSE(is_leftover_temporary("notes.tmp.2024"));
    CHECK_FALSE(is_leftover_temporary("params.json.tvid-tmp.42x"));
    CHECK_FALSE(is_leftover_temporary(".tvid-tmp.42"));
    TempDir tmp;
    const fs::path dir = tmp.path() / "out";
    fs::create_directories(dir);
    tmp.write("out/notes.tmp.2024", "mine");
    tmp.write("out/summary.json.tvid-tmp.99999", "{ torn");
    (void)prepare_output_directory(dir, "report directory");
    CHECK(fs::exists(dir / "notes.tmp.2024"));
    CHECK_FALSE(fs::exists(dir / "summary.json.tvid-tmp.99999"));
    write_output_file(dir, "x.txt", "x");
    CHECK(tvid::test::read_text(dir / "x.txt") == "x");
}

TEST_CASE("a combination expression nested deeper than 100 levels is refused, not recursed into", "[check][limits]") {
    std::string ok = std::string(99, '(') + "a" + std::string(99, ')');
    CHECK(ParameterExpression(ok).evaluate([](const std::string&) { return 2.0; }) == 2.0);
    const std::string deep = std::string(100000, '(') + "a" + std::string(100000, ')');
    CHECK_THROWS_WITH(ParameterExpression(deep), Catch::Contains("nested more than 100 levels deep"));
    CHECK_THROWS_WITH(ParameterExpression(std::string(100000, '-') + "a"), Catch::Contains("nested more than"));
}

}  // namespace TVID_UNITY_ID
