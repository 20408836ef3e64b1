// Several recordings in one experiment (data.recordings, docs/experiment-format.md): the
// loader lays them end to end, resolves each window on its own recording, reads every
// channel within its recording, and refuses bad lists and windows with one InputError
// "FILE:LINE: key.path: what is wrong".
#include <catch2/catch.hpp>

#include <cmath>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "support/test_files.hpp"
#include "tvid/estimation/problem_definition.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/io/sha256.hpp"
#include "tvid/util/input_error.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
using tvid::Experiment;
using tvid::InputError;

namespace {

// n samples from t0 at 1 ms: the preset's columns, a crank angle 36 deg a sample from 0,
// and the samples' index in column i (to see which recording a value came from).
std::string recording_csv(int n, double t0, double offset, bool with_tds = true) {
    std::ostringstream s;
    s << "t,Ttm" << (with_tds ? ",Tds" : "") << ",crank,i\n";
    for (int k = 0; k < n; ++k) {
        s << t0 + k * 0.001 << ',' << offset + 10 + std::sin(0.3 * k);
        if (with_tds) s << ',' << offset - 5 + 0.1 * k;
        s << ',' << 36 * k << ',' << k << '\n';
    }
    return s.str();
}

// run1: 101 samples, t = 0 … 0.1 s; run2: 51 samples, t = 0 … 0.05 s; late: 51 samples
// from t = 0.2 s; no_tds: run2 without the Tds column.
struct Scratch {
    TempDir dir;
    Scratch() {
        dir.write("run1.csv", recording_csv(101, 0.0, 0.0));
        dir.write("run2.csv", recording_csv(51, 0.0, 100.0));
        dir.write("late.csv", recording_csv(51, 0.2, 100.0));
        dir.write("no_tds.csv", recording_csv(51, 0.0, 100.0, false));
    }
    std::filesystem::path write(const std::vector<std::string>& lines) const {
        std::string text;
        for (const std::string& l : lines) text += l + "\n";
        return dir.write("exp.yaml", text);
    }
};

// The preset experiment over two recordings. Line numbers are index + 1.
const std::vector<std::string> kTwo = {
    "tvid: 1",                                                           // 1
    "name: two",                                                         // 2
    "data:",                                                             // 3
    "  recordings:",                                                     // 4
    "    - { name: run1, file: run1.csv, time: t }",                     // 5
    "    - { name: run2, file: run2.csv, time: t }",                     // 6
    "model: { preset: cvt_clearance }",                                  // 7
    "inputs: { Ttm: Ttm }",                                              // 8
    "outputs: { Tds: Tds }",                                             // 9
    "parameters:",                                                       // 10
    "  rho1:    { init: 1.5, min: 0.1, max: 10, range: [1, 2] }",        // 11
    "  k_minus: { init: 3000, min: 1, max: 1.0e6 }",                     // 12
    "  k_plus:  { init: 8000, min: 1, max: 1.0e6 }",                     // 13
    "  c_minus: { init: 4, min: 0, max: 100 }",                          // 14
    "  c_plus:  { init: 19, min: 0, max: 100 }",                         // 15
    "  mu:      { init: 0.0035, min: 0, max: 0.1 }",                     // 16
    "  sigma:   { value: 1132.81 }",                                     // 17
    "  d_ds:    { init: -7, min: -100, max: 100 }",                      // 18
    "  d_tm:    { init: 13, min: -100, max: 100 }",                      // 19
    "windows:",                                                          // 20
    "  estimation: [ { recording: run1, time: [0.010, 0.050] } ]",       // 21
    "  validation: [ { recording: run2, samples: [5, 20] }, { recording: run2 } ]",  // 22
    "estimation:",                                                       // 23
    "  pso: { start: latin_hypercube, particles: 4, iterations: 1 }",    // 24
};

std::vector<std::string> with(std::vector<std::string> lines, int line, const std::string& text) {
    lines.at(static_cast<std::size_t>(line - 1)) = text;
    return lines;
}

std::vector<std::string> inserted(std::vector<std::string> lines, int line, const std::string& text) {
    lines.insert(lines.begin() + line, text);
    return lines;
}

Experiment load(const Scratch& s, const std::vector<std::string>& lines) { return tvid::load_experiment(s.write(lines)); }

// Loads `lines` and checks the one-line error: that file, `line`, `key`, and `fragment` in it.
void expect_error(const std::vector<std::string>& lines, int line, const std::string& key, const std::string& fragment) {
    Scratch s;
    const auto file = s.write(lines);
    std::optional<InputError> e;
    try {
        (void)tvid::load_experiment(file);
    } catch (const InputError& error) {
        e = error;
    }
    REQUIRE(e.has_value());
    const std::string what = e->what();
    INFO(what);
    CHECK(e->file() == file.string());
    CHECK(e->line() == line);
    CHECK(e->key() == key);
    CHECK(what.rfind(file.string() + ":" + std::to_string(line) + ": " + key + ": ", 0) == 0);
    CHECK(what.find('\n') == std::string::npos);
    CHECK(what.find(fragment) != std::string::npos);
}

}  // namespace

TEST_CASE("two recordings are laid end to end, each window in its own recording's rows", "[experiment][recordings]") {
    Scratch s;
    const Experiment ex = load(s, kTwo);
    REQUIRE(ex.recordings.size() == 2);
    CHECK(ex.recordings[0].name == "run1");
    CHECK(ex.recordings[1].name == "run2");
    CHECK(ex.recordings[0].rows.begin == 0);
    CHECK(ex.recordings[0].rows.end == 101);
    CHECK(ex.recordings[1].rows.begin == 101);
    CHECK(ex.recordings[1].rows.end == 152);
    CHECK(ex.data.rows() == 152);
    CHECK(ex.recordings[1].sha256 == tvid::sha256_of_text(read_text(s.dir.path() / "run2.csv")));
    CHECK(ex.data_file == ex.recordings[0].file);
    // The second clock starts at 0 again: it moves to start one interval after the first.
    const std::vector<double>& t = ex.data.column("t");
    for (std::size_t i = 1; i < t.size(); ++i) REQUIRE(t[i] > t[i - 1]);
    CHECK(t[100] == 0.1);
    CHECK(t[101] == Approx(0.101).epsilon(1e-12));
    CHECK(ex.recordings[1].time_offset == Approx(0.101).epsilon(1e-12));
    CHECK(ex.data.column("i")[101] == 0.0);  // run2's first row

    REQUIRE(ex.estimation.size() == 1);
    CHECK(ex.estimation[0].recording == 0);
    CHECK(ex.estimation[0].first == 10);
    CHECK(ex.estimation[0].last == 50);
    CHECK(ex.estimation[0].label == "run1: time 0.01 to 0.05");
    REQUIRE(ex.validation.size() == 2);
    CHECK(ex.validation[0].recording == 1);
    CHECK(ex.validation[0].first == 106);
    CHECK(ex.validation[0].last == 121);
    CHECK(ex.validation[0].label == "run2: samples 5 to 20");
    // A window that names only its recording covers all of it.
    CHECK(ex.validation[1].start == 101);
    CHECK(ex.validation[1].first == 101);
    CHECK(ex.validation[1].last == 151);
    CHECK(ex.validation[1].label == "run2: whole recording");
}

TEST_CASE("a recording whose clock already starts later keeps its time stamps", "[experiment][recordings]") {
    Scratch s;
    const Experiment ex = load(s, with(kTwo, 6, "    - { name: run2, file: late.csv, time: t }"));
    CHECK(ex.recordings[1].time_offset == 0.0);
    CHECK(ex.data.column("t")[101] == 0.2);  // as written
}

TEST_CASE("the time column is shared beside the list, and one recording needs no recording: key",
          "[experiment][recordings]") {
    Scratch s;
    SECTION("data.time for the entries without their own") {
        std::vector<std::string> lines = with(kTwo, 5, "    - { name: run1, file: run1.csv }");
        lines = with(lines, 6, "    - { name: run2, file: run2.csv }");
        lines = inserted(lines, 6, "  time: t");
        CHECK(load(s, lines).data.rows() == 152);
    }
    SECTION("a list of one: windows may leave out their recording") {
        std::vector<std::string> lines = with(kTwo, 6, "");
        lines = with(lines, 21, "  estimation: [ { time: [0.010, 0.050] } ]");
        lines = with(lines, 22, "  validation: [ { recording: run1 } ]");
        const Experiment ex = load(s, lines);
        CHECK(ex.estimation[0].label == "run1: time 0.01 to 0.05");
        CHECK(ex.validation[0].first == 0);
        CHECK(ex.validation[0].last == 100);
        CHECK(ex.validation[0].label == "run1: whole recording");
    }
}

TEST_CASE("data.recordings errors name the line and the key", "[experiment][recordings]") {
    SECTION("a window that names an unknown recording") {
        expect_error(with(kTwo, 22, "  validation: [ { recording: run3 } ]"), 22, "windows.validation[0].recording",
                     "no recording named 'run3' (data.recordings: run1, run2)");
    }
    SECTION("a window without its recording when there are several") {
        expect_error(with(kTwo, 21, "  estimation: [ { time: [0.010, 0.050] } ]"), 21, "windows.estimation[0].recording",
                     "missing (the experiment reads several recordings: name this window's, one of run1, run2)");
    }
    SECTION("a recording that lacks a column the experiment reads") {
        expect_error(with(kTwo, 6, "    - { name: run2, file: no_tds.csv, time: t }"), 9, "outputs.Tds",
                     "no column 'Tds' in ");
        expect_error(with(kTwo, 6, "    - { name: run2, file: no_tds.csv, time: t }"), 9, "outputs.Tds", "no_tds.csv");
    }
    SECTION("a recording's time column that is not there") {
        expect_error(with(kTwo, 6, "    - { name: run2, file: run2.csv, time: time }"), 6, "data.recordings[1].time",
                     "no column 'time' in ");
    }
    SECTION("two recordings of one name") {
        expect_error(with(kTwo, 6, "    - { name: run1, file: run2.csv, time: t }"), 6, "data.recordings[1].name",
                     "a second recording named 'run1'");
    }
    SECTION("an empty list") {
        std::vector<std::string> lines = with(kTwo, 4, "  recordings: []");
        lines = with(lines, 5, "");
        lines = with(lines, 6, "");
        expect_error(lines, 4, "data.recordings", "at least one recording is needed");
    }
    SECTION("a list and data.file together") {
        expect_error(inserted(kTwo, 3, "  file: run1.csv"), 4, "data.file", "not both");
    }
    SECTION("a name that cannot label a window") {
        expect_error(with(kTwo, 5, "    - { name: 'run 1', file: run1.csv, time: t }"), 5, "data.recordings[0].name",
                     "not a recording name");
    }
    SECTION("an entry without a time column, and none shared") {
        expect_error(with(kTwo, 5, "    - { name: run1, file: run1.csv }"), 5, "data.recordings[0].time", "missing");
    }
    SECTION("an unknown key in an entry") {
        expect_error(with(kTwo, 5, "    - { name: run1, file: run1.csv, tim: t }"), 5, "data.recordings[0].tim",
                     "did you mean 'time'");
    }
    SECTION("a window outside its recording, on that recording's own clock") {
        expect_error(with(kTwo, 22, "  validation: [ { recording: run2, time: [0, 0.09] } ]"), 22,
                     "windows.validation[0].time", "outside the data: recording run2 spans t = 0 … 0.05 s (51 samples)");
        expect_error(with(kTwo, 22, "  validation: [ { recording: run2, samples: [0, 60] } ]"), 22,
                     "windows.validation[0].samples", "outside the data of recording run2: rows 0 … 50");
    }
    SECTION("a warm-up that would reach into the previous recording") {
        expect_error(inserted(kTwo, 20, "  warmup: 0.005"), 23, "windows.validation[1]", "before recording run2 (t = 0 s)");
    }
    SECTION("a delay longer than the shortest recording") {
        expect_error(with(kTwo, 8, "inputs: { Ttm: { column: Ttm, delay: 0.07 } }"), 8, "inputs.Ttm.delay",
                     "shifts the channel past recording run2 (0.05 s long)");
    }
    SECTION("recording: with a single data.file") {
        std::vector<std::string> lines = with(kTwo, 4, "  file: run1.csv");
        lines = with(lines, 5, "  time: t");
        lines = with(lines, 6, "");
        expect_error(lines, 21, "windows.estimation[0].recording", "this experiment reads one data.file");
    }
}

TEST_CASE("a delayed channel of the second recording reads that recording as it alone would", "[experiment][recordings]") {
    // Whole and half samples, late and early: each recording's own samples, held at its own
    // ends. A second recording whose clock starts after the first's keeps its time stamps
    // and reads bit for bit as alone; one whose clock starts again at 0 is moved, and its
    // interpolation weights round differently.
    for (const char* file : {"late.csv", "run2.csv"}) {
        const double tolerance = std::string(file) == "late.csv" ? 0.0 : 1e-12;
        for (const char* delay : {"0.0025", "-0.0025", "0.003", "-0.003"}) {
            INFO(file << ", delay " << delay);
            Scratch s;
            const std::string input = std::string("inputs: { Ttm: { column: Ttm, delay: ") + delay + " } }";
            const std::string output = std::string("outputs: { Tds: { column: Tds, delay: ") + delay + " } }";
            std::vector<std::string> two = with(with(kTwo, 8, input), 9, output);
            two = with(two, 6, std::string("    - { name: run2, file: ") + file + ", time: t }");
            const Experiment ex = load(s, two);
            const tvid::ProblemDefinition joined = tvid::problem_definition(ex);
            std::vector<std::string> alone = with(two, 4, std::string("  file: ") + file);
            alone = with(alone, 5, "  time: t");
            alone = with(alone, 6, "");
            alone = with(alone, 21, "  estimation: [ { samples: [0, 50] } ]");
            alone = with(alone, 22, "");
            const tvid::ProblemDefinition single = tvid::problem_definition(load(s, alone));
            REQUIRE(single.inputs.samples() == 51);
            for (std::size_t i = 0; i < 51; ++i) {
                INFO("sample " << i);
                CHECK(joined.inputs.value(0, 101 + i) == Approx(single.inputs.value(0, i)).epsilon(tolerance).margin(0));
                CHECK(joined.measured[0][101 + i] == Approx(single.measured[0][i]).epsilon(tolerance).margin(0));
            }
            // Read late, the first recording's last sample holds its own value, not the next's.
            if (std::stod(delay) > 0) CHECK(joined.inputs.value(0, 100) == ex.data.column("Ttm")[100]);
        }
    }
}

TEST_CASE("engine cycles count on each recording's own crank angle, moved by whole cycles", "[experiment][recordings]") {
    Scratch s;
    std::vector<std::string> lines = inserted(kTwo, 6, "  angle: crank");
    lines = inserted(lines, 7, "  cycle_deg: 360");
    // Lines 21 and 22 of kTwo are now 23 and 24.
    lines = with(lines, 23, "  estimation: [ { recording: run1, cycle: 2 } ]");
    lines = with(lines, 24, "  validation: [ { recording: run2, cycle: 1 } ]");
    const Experiment ex = load(s, lines);
    // 36 deg a sample: cycle k spans rows 10k … 10k + 10 of its recording.
    CHECK(ex.estimation[0].first == 20);
    CHECK(ex.estimation[0].last == 30);
    CHECK(ex.validation[0].first == 111);
    CHECK(ex.validation[0].last == 121);
    CHECK(ex.validation[0].label == "run2: cycle 1");
    // run1 ends at 3600 deg; run2 starts at 0 again and moves to 3960, a cycle after it.
    CHECK(ex.recordings[1].angle_offset == 3960.0);
    for (std::size_t i = 1; i < ex.crank_angle.size(); ++i) REQUIRE(ex.crank_angle[i] > ex.crank_angle[i - 1]);
    CHECK(ex.crank_angle[101] * 180.0 / 3.14159265358979323846 == Approx(3960.0));
}

}  // namespace TVID_UNITY_ID
