// Nothing lost: a report directory that already holds a run is not overwritten without
// --force, an unusable report place is bad input before any work, and a fit or a batch
// killed with SIGKILL at any moment leaves every report and batch file either complete or
// absent (and --resume then completes the batch).
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <functional>
#include <map>
#include <random>
#include <thread>
#include <utility>
#include <vector>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"
#include "tvid/batch/batch_table.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
namespace fs = std::filesystem;

namespace {

// A quick fit: the CVT clearance model, three LM steps, one thread.
std::vector<std::string> quick_fit(const fs::path& out) {
    return {"fit", (source_dir() / "configs/cvt_tipin_clean.yaml").string(), "-o", out.string(), "--optimizer", "lm",
            "--set", "estimation.cost=l2", "--set", "estimation.lm.max_iterations=3", "--threads", "1", "--quiet",
            "--force"};
}

// Starts tvid and kills it with SIGKILL: after `delay` or, when `written` is given, `delay`
// after the moment `written()` first holds (polled every 0.1 ms; a run that ends first is
// not killed). The second form lands kills while the files are being written however fast
// or slow the machine is (a busy sanitizer run is many times slower than the timed run).
void run_and_kill(const std::vector<std::string>& args, std::chrono::microseconds delay,
                  const std::function<bool()>& written = {}) {
    const pid_t pid = ::fork();
    if (pid == 0) {
        std::vector<std::string> copy = args;
        std::string binary = tvid_binary();
        std::vector<char*> argv{binary.data()};
        for (auto& a : copy) argv.push_back(a.data());
        argv.push_back(nullptr);
        const int null = ::open("/dev/null", O_WRONLY);
        ::dup2(null, 1);
        ::dup2(null, 2);
        ::execv(binary.c_str(), argv.data());
        ::_exit(127);
    }
    int status = 0;
    if (written) {
        while (!written()) {
            if (::waitpid(pid, &status, WNOHANG) == pid) return;  // ended before writing
            std::this_thread::sleep_for(std::chrono::microseconds(100));
        }
    }
    std::this_thread::sleep_for(delay);
    ::kill(pid, SIGKILL);
    ::waitpid(pid, &status, 0);
}

// A small batch: the CVT clean experiment on four copies of its recording, a swarm of 64
// particles for two iterations per job, one thread (jobs finish one after the other, each
// adding a row).
std::vector<std::string> quick_batch(const fs::path& recordings, const fs::path& out, const std::string& mode) {
    return {"batch", (source_dir() / "configs/cvt_tipin_clean.yaml").string(), "--data", (recordings / "*.csv").string(),
            "-o", out.string(), "--set", "estimation.pso.start=latin_hypercube", "--set", "estimation.pso.particles=64",
            "--set", "estimation.pso.iterations=2", "--threads", "1", "--quiet", mode};
}

// The rows of batch.csv by job id, wall time blanked (the only cell that differs between runs).
std::map<std::string, tvid::BatchRow> rows_by_id(const tvid::BatchFile& table) {
    const auto wall = static_cast<std::size_t>(std::find(table.header.begin(), table.header.end(), "wall_seconds") -
                                               table.header.begin());
    std::map<std::string, tvid::BatchRow> out;
    for (tvid::BatchRow row : table.rows) {
        row.at(wall).clear();
        out[row[0]] = row;
    }
    return out;
}

const char* const kReportFiles[] = {"params.json", "params.csv", "estimation.csv", "validation.csv", "history.csv",
                                    "summary.json"};

}  // namespace

TEST_CASE("the same fit again replaces its own report, anything else is refused without --force", "[e2e][report]") {
    TempDir tmp;
    const fs::path out = tmp.path() / "run";
    std::vector<std::string> args = quick_fit(out);
    args.pop_back();  // without --force
    REQUIRE(run_tvid(args).exit_code == 0);
    // Running the same command again replaces tvid's own report, and leaves the user's files.
    tmp.write("run/notes.txt", "my notes");
    const RunResult same = run_tvid(args);
    INFO(same.err);
    CHECK(same.exit_code == 0);
    CHECK(read_text(out / "notes.txt") == "my notes");
    const std::string before = read_text(out / "params.json");

    // A summary.json tvid did not write, or another experiment's report: refused, one line.
    nlohmann::json other = nlohmann::json::parse(read_text(out / "summary.json"));
    other["experiment"] = "engine-idle";
    for (const auto& [summary, why] : std::vector<std::pair<std::string, std::string>>{
             {"{ \"tool\": \"other\" }", "a summary.json that tvid did not write"},
             {"not json", "a summary.json that tvid did not write"},
             {other.dump(), "the fit report of experiment 'engine-idle'"}}) {
        tmp.write("run/summary.json", summary);
        const RunResult again = run_tvid(args);
        INFO(again.err);
        CHECK(again.exit_code == 2);
        CHECK(again.err.find(out.string()) != std::string::npos);
        CHECK(again.err.find(why) != std::string::npos);
        CHECK(again.err.find("--force") != std::string::npos);
        CHECK(std::count(again.err.begin(), again.err.end(), '\n') == 1);  // one line
        CHECK(read_text(out / "params.json") == before);
        CHECK(read_text(out / "summary.json") == summary);
    }
    // With --force it is replaced, and temporary files a killed run left are swept away;
    // a user's own file that merely looks temporary is kept.
    const fs::path leftover = out / "params.json.tvid-tmp.99999";
    tmp.write("run/params.json.tvid-tmp.99999", "{ torn");
    tmp.write("run/notes.tmp.2024", "my notes");
    REQUIRE(run_tvid(quick_fit(out)).exit_code == 0);
    CHECK_FALSE(fs::exists(leftover));
    CHECK(read_text(out / "notes.tmp.2024") == "my notes");
    CHECK(nlohmann::json::parse(read_text(out / "summary.json"))["tool"] == "tvid");
}

TEST_CASE("a report's file that tvid did not write is never replaced without --force", "[e2e][report]") {
    TempDir tmp;
    // A folder holding only the user's own params.csv (no summary.json of tvid's): refused.
    const fs::path out = tmp.path() / "mine";
    tmp.write("mine/params.csv", "my,own\n1,2\n");
    std::vector<std::string> args = quick_fit(out);
    args.pop_back();  // without --force
    const RunResult refused = run_tvid(args);
    INFO(refused.err);
    CHECK(refused.exit_code == 2);
    CHECK(refused.err.find("params.csv") != std::string::npos);
    CHECK(refused.err.find("--force") != std::string::npos);
    CHECK(read_text(out / "params.csv") == "my,own\n1,2\n");
    CHECK_FALSE(fs::exists(out / "summary.json"));
    REQUIRE(run_tvid(quick_fit(out)).exit_code == 0);  // --force: replaced
    CHECK(read_text(out / "params.csv") != "my,own\n1,2\n");

    // The same rule for the analyses' directories: modes.csv of the user's is kept.
    const fs::path modes = tmp.path() / "modes";
    tmp.write("modes/modes.csv", "mine\n");
    const std::vector<std::string> modes_args{"modes", (source_dir() / "configs/cvt_tipin_clean.yaml").string(), "-o",
                                              modes.string()};
    const RunResult modes_refused = run_tvid(modes_args);
    CHECK(modes_refused.exit_code == 2);
    CHECK(modes_refused.err.find("modes.csv") != std::string::npos);
    CHECK(read_text(modes / "modes.csv") == "mine\n");
    std::vector<std::string> forced = modes_args;
    forced.push_back("--force");
    REQUIRE(run_tvid(forced).exit_code == 0);
    CHECK(run_tvid(modes_args).exit_code == 0);  // now tvid's own: replaced without --force
}

TEST_CASE("an unusable report place is bad input before the fit", "[e2e][report]") {
    TempDir tmp;
    const fs::path file = tmp.write("not-a-dir", "x");
    const RunResult is_file = run_tvid(quick_fit(file));
    CHECK(is_file.exit_code == 2);
    CHECK(is_file.err.find("is a file") != std::string::npos);
    const RunResult below_file = run_tvid(quick_fit(file / "report"));  // root or not, this cannot be created
    CHECK(below_file.exit_code == 2);
    CHECK(below_file.err.find("cannot create the report directory") != std::string::npos);
    // A directory nobody may write in, not even root: /proc.
    const RunResult unwritable = run_tvid(quick_fit("/proc"));
    CHECK(unwritable.exit_code == 2);
    CHECK(unwritable.err.rfind("/proc: the report directory is not writable: ", 0) == 0);
    CHECK(std::count(unwritable.err.begin(), unwritable.err.end(), '\n') == 1);
    // The same for a batch directory.
    const RunResult batch_below_file =
        run_tvid({"batch", (source_dir() / "configs/cvt_tipin_clean.yaml").string(), "--data",
                  (source_dir() / "data/cvt/tipin_clean.csv").string(), "-o", (file / "batch").string()});
    CHECK(batch_below_file.exit_code == 2);
    CHECK(batch_below_file.err.rfind((file / "batch").string() + ": cannot create the batch directory: ", 0) == 0);
    const RunResult batch_unwritable = run_tvid({"batch", (source_dir() / "configs/cvt_tipin_clean.yaml").string(),
                                                 "--data", (source_dir() / "data/cvt/tipin_clean.csv").string(), "-o",
                                                 "/proc"});
    CHECK(batch_unwritable.exit_code == 2);
    CHECK(batch_unwritable.err.rfind("/proc: the batch directory is not writable: ", 0) == 0);
}

TEST_CASE("a fit killed with SIGKILL leaves each report file complete or absent", "[e2e][report]") {
    TempDir tmp;
    // The complete report, and how long a run takes.
    const fs::path reference = tmp.path() / "reference";
    const auto t0 = std::chrono::steady_clock::now();
    REQUIRE(run_tvid(quick_fit(reference)).exit_code == 0);
    const auto run_time = std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - t0);
    std::map<std::string, std::string> complete;
    for (const char* name : kReportFiles) complete[name] = read_text(reference / name);

    std::mt19937 random(20261123);
    std::uniform_int_distribution<long long> moment(0, run_time.count() * 12 / 10);
    int killed_with_files = 0;
    for (int k = 0; k < 40; ++k) {
        // Even runs write over a complete report, odd ones into an empty directory.
        const fs::path out = tmp.path() / (k % 2 == 0 ? "over" : "fresh-" + std::to_string(k));
        if (k % 2 == 0 && !fs::exists(out / "summary.json")) fs::copy(reference, out, fs::copy_options::overwrite_existing);
        if (k % 4 == 3) {
            // Every fourth run is killed 0-2 ms after its first report file appears.
            const auto written = [&] {
                return std::any_of(std::begin(kReportFiles), std::end(kReportFiles),
                                   [&](const char* name) { return fs::exists(out / name); });
            };
            run_and_kill(quick_fit(out), std::chrono::microseconds(moment(random) % 2000), written);
        } else {
            run_and_kill(quick_fit(out), std::chrono::microseconds(moment(random)));
        }
        INFO("run " << k);
        bool any = false;
        for (const char* name : kReportFiles) {
            if (!fs::exists(out / name)) continue;
            any = true;
            INFO(name);
            const std::string text = read_text(out / name);
            if (std::string(name) == "summary.json") {
                // Written last: its presence vouches for every other file.
                const nlohmann::json s = nlohmann::json::parse(text);  // throws on a torn file
                CHECK(s.contains("cost"));
                for (const char* other : kReportFiles) CHECK(fs::exists(out / other));
            } else {
                CHECK(text == complete[name]);  // the same experiment gives the same bytes
            }
        }
        killed_with_files += any ? 1 : 0;
    }
    CHECK(killed_with_files > 0);  // some kills did land while or after files were written
}

TEST_CASE("a batch killed with SIGKILL leaves batch files complete or absent, and --resume finishes it",
          "[e2e][report][batch][fits]") {
    TempDir tmp;
    const fs::path recordings = tmp.path() / "recordings";
    fs::create_directories(recordings);
    for (const char* name : {"run1.csv", "run2.csv", "run3.csv", "run4.csv"})
        fs::copy_file(source_dir() / "data/cvt/tipin_clean.csv", recordings / name);

    // The complete batch, and how long it takes.
    const fs::path reference = tmp.path() / "reference";
    const auto t0 = std::chrono::steady_clock::now();
    const RunResult whole = run_tvid(quick_batch(recordings, reference, "--force"));
    INFO(whole.err);
    REQUIRE(whole.exit_code == 0);
    const auto run_time = std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - t0);
    const auto complete_table = tvid::read_batch_file(reference / "batch.csv");
    REQUIRE(complete_table);
    REQUIRE(complete_table->rows.size() == 4);
    const std::map<std::string, tvid::BatchRow> complete = rows_by_id(*complete_table);

    std::mt19937 random(20261124);
    std::uniform_int_distribution<long long> moment(0, run_time.count() * 12 / 10);
    int partial = 0, resumed = 0;
    for (int k = 0; k < 24; ++k) {
        // Even runs start over a complete batch (--force), odd ones in an empty directory.
        const fs::path out = tmp.path() / (k % 2 == 0 ? "over" : "fresh-" + std::to_string(k));
        if (k % 2 == 0 && !fs::exists(out / "batch_summary.json"))
            fs::copy(reference, out, fs::copy_options::overwrite_existing);
        if (k % 4 == 3) {
            // Every fourth run is killed 0-5 ms after its batch.csv appears (its first row).
            const auto written = [&] { return fs::exists(out / "batch.csv"); };
            run_and_kill(quick_batch(recordings, out, "--force"), std::chrono::microseconds(moment(random) % 5000),
                         written);
        } else {
            run_and_kill(quick_batch(recordings, out, "--force"), std::chrono::microseconds(moment(random)));
        }
        INFO("run " << k);
        std::size_t rows = 0;
        if (fs::exists(out / "batch.csv")) {
            const auto table = tvid::read_batch_file(out / "batch.csv");
            REQUIRE(table);
            CHECK(table->header == complete_table->header);
            CHECK(table->incomplete_rows == 0);  // never a torn line
            for (const auto& [id, row] : rows_by_id(*table)) {
                REQUIRE(complete.count(id) == 1);
                CHECK(row == complete.at(id));  // each row whole and as in the uninterrupted batch
            }
            rows = table->rows.size();
        }
        if (fs::exists(out / "batch_summary.json")) {
            // Written last: its presence vouches for a complete batch.csv.
            const nlohmann::json s = nlohmann::json::parse(read_text(out / "batch_summary.json"));  // throws if torn
            CHECK(s["jobs"] == 4);
            CHECK(s["ok"] == 4);
            CHECK(rows == 4);
        } else if (fs::exists(out / "batch.csv")) {
            ++partial;
            // An interrupted batch: --resume runs the missing jobs and gives the uninterrupted table.
            if (resumed < 3) {
                ++resumed;
                const RunResult r = run_tvid(quick_batch(recordings, out, "--resume"));
                INFO(r.err);
                CHECK(r.exit_code == 0);
                const auto table = tvid::read_batch_file(out / "batch.csv");
                REQUIRE(table);
                CHECK(rows_by_id(*table) == complete);
                CHECK(fs::exists(out / "batch_summary.json"));
                for (const fs::directory_entry& e : fs::directory_iterator(out))
                    CHECK(e.path().filename().string().find(".tvid-tmp.") == std::string::npos);  // swept away
            }
        }
    }
    CHECK(partial > 0);  // some kills did land while the batch was writing its rows
    CHECK(resumed > 0);
}

}  // namespace TVID_UNITY_ID
