// The sensitivity report (the methodology paper Figs. 4–5): the ranking of the free parameters by the
// RMS of the scaled sensitivity p·∂y/∂p, and the CSV/JSON files, on hand-made numbers.
#include <catch2/catch.hpp>
#include <cmath>
#include <sstream>

#include "support/test_files.hpp"
#include "tvid/report/sensitivity_report.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

WindowSensitivity window(const Window& w, std::vector<double> time, std::vector<std::vector<double>> output,
                         std::vector<std::vector<std::vector<double>>> dydp) {
    WindowSensitivity s;
    s.window = &w;
    s.time = std::move(time);
    s.output = std::move(output);
    s.dydp = std::move(dydp);
    return s;
}

// Model parameters a (free, 2), c (fixed, 7), b (free, −0.5); outputs y1, y2; an
// estimation and a validation window of two samples each.
struct Example {
    Window est{"time 0 to 1", 0, 0, 2, {}};
    Window val{"time 1 to 2", 2, 2, 4, {}};
    SensitivityStudy study;

    Example() {
        study.experiment = "hand-made";
        study.model = "custom";
        study.parameters = {"a", "c", "b"};
        study.values = {2.0, 7.0, -0.5};
        study.free = {0, 2};
        study.outputs = {"y1", "y2"};
        //                          ∂y1/∂a        ∂y1/∂b          ∂y2/∂a      ∂y2/∂b
        study.estimation.push_back(window(est, {0.5, 1.0}, {{10, 11}, {20, 21}},
                                          {{{1, -1}, {3, 0}}, {{0, 0}, {2, 2}}}));
        study.validation.push_back(window(val, {1.5, 2.0}, {{12, 13}, {22, 23}},
                                          {{{1, 1}, {-4, 0}}, {{0, 0}, {2, 2}}}));
    }
};

}  // namespace

TEST_CASE("parameters are ranked by the RMS of p·dy/dp over every scored sample", "[sensitivity-report]") {
    const Example ex;
    REQUIRE(ex.study.samples() == 4);
    const std::vector<OutputRanking> r = rank_parameters(ex.study);
    REQUIRE(r.size() == 2);

    // y1: a: Σd² = 1+1+1+1 = 4, rms_raw = 1, scaled 2·1 = 2;
    //     b: Σd² = 9+0+16+0 = 25, rms_raw = 2.5, scaled |−0.5|·2.5 = 1.25.
    CHECK(r[0].output == "y1");
    CHECK(r[0].samples == 4);
    REQUIRE(r[0].ranks.size() == 2);
    CHECK(r[0].ranks[0].parameter == "a");
    CHECK(r[0].ranks[0].rank == 1);
    CHECK(r[0].ranks[0].free_index == 0);
    CHECK(r[0].ranks[0].value == 2.0);
    CHECK(r[0].ranks[0].rms_raw == Approx(1.0));
    CHECK(r[0].ranks[0].rms_scaled == Approx(2.0));
    CHECK(r[0].ranks[0].relative == Approx(1.0));
    CHECK(r[0].ranks[1].parameter == "b");
    CHECK(r[0].ranks[1].rank == 2);
    CHECK(r[0].ranks[1].value == -0.5);
    CHECK(r[0].ranks[1].rms_raw == Approx(2.5));
    CHECK(r[0].ranks[1].rms_scaled == Approx(1.25));
    CHECK(r[0].ranks[1].relative == Approx(0.625));

    // y2: b: rms_raw 2, scaled 1; a does not move y2 at all.
    CHECK(r[1].output == "y2");
    CHECK(r[1].ranks[0].parameter == "b");
    CHECK(r[1].ranks[0].rms_scaled == Approx(1.0));
    CHECK(r[1].ranks[0].relative == Approx(1.0));
    CHECK(r[1].ranks[1].parameter == "a");
    CHECK(r[1].ranks[1].rms_scaled == 0.0);
    CHECK(r[1].ranks[1].relative == 0.0);
}

TEST_CASE("an output no parameter moves has no relative ranking, ties keep the parameter order",
          "[sensitivity-report]") {
    Example ex;
    for (auto& w : ex.study.estimation) w.dydp[1] = {{0, 0}, {0, 0}};
    for (auto& w : ex.study.validation) w.dydp[1] = {{0, 0}, {0, 0}};
    const std::vector<OutputRanking> r = rank_parameters(ex.study);
    CHECK(r[1].ranks[0].parameter == "a");
    CHECK(r[1].ranks[1].parameter == "b");
    CHECK(r[1].ranks[0].rms_scaled == 0.0);
    CHECK(std::isnan(r[1].ranks[0].relative));
    CHECK(ranking_csv(r).find("y2,1,a,2,0,,0\n") != std::string::npos);  // NaN is an empty cell
}

TEST_CASE("sensitivity.csv has a row per scored sample and output, raw then scaled columns", "[sensitivity-report]") {
    const Example ex;
    const std::vector<std::string> lines = lines_of(sensitivity_csv(ex.study));
    REQUIRE(lines.size() == 1 + 4 * 2);
    CHECK(lines[0] == "window,time,output,y,d_a,d_b,s_a,s_b");
    // s = p·∂y/∂p: a = 2, b = −0.5.
    CHECK(lines[1] == "time 0 to 1,0.5,y1,10,1,3,2,-1.5");
    CHECK(lines[2] == "time 0 to 1,0.5,y2,20,0,2,0,-1");
    CHECK(lines[3] == "time 0 to 1,1,y1,11,-1,0,-2,0");
    CHECK(lines[5] == "time 1 to 2,1.5,y1,12,1,-4,2,2");
    CHECK(lines[8] == "time 1 to 2,2,y2,23,0,2,0,-1");
}

TEST_CASE("ranking.csv and sensitivity.json carry the ranking, values and windows", "[sensitivity-report]") {
    const Example ex;
    const std::vector<OutputRanking> r = rank_parameters(ex.study);
    const std::vector<std::string> lines = lines_of(ranking_csv(r));
    REQUIRE(lines.size() == 1 + 2 * 2);
    CHECK(lines[0] == "output,rank,parameter,value,rms_scaled,relative,rms_raw");
    CHECK(lines[1] == "y1,1,a,2,2,1,1");
    CHECK(lines[2] == "y1,2,b,-0.5,1.25,0.625,2.5");
    CHECK(lines[3] == "y2,1,b,-0.5,1,1,2");

    const nlohmann::json j = sensitivity_json(ex.study, r, SensitivityRunInfo{"9.9", "tvid sensitivity x", 2, 0.5});
    CHECK(j["experiment"] == "hand-made");
    CHECK(j["model"] == "custom");
    CHECK(j["samples"] == 4);
    CHECK(j["free_parameters"] == nlohmann::json({"a", "b"}));
    REQUIRE(j["parameters"].size() == 3);
    CHECK(j["parameters"][1]["name"] == "c");
    CHECK(j["parameters"][1]["value"] == 7.0);
    CHECK(j["parameters"][1]["fixed"] == true);
    CHECK(j["parameters"][2]["fixed"] == false);
    REQUIRE(j["windows"].size() == 2);
    CHECK(j["windows"][0]["window"] == "time 0 to 1");
    CHECK(j["windows"][0]["split"] == "estimation");
    CHECK(j["windows"][0]["samples"] == 2);
    CHECK(j["windows"][1]["split"] == "validation");
    CHECK(j["windows"][1]["status"] == "ok");
    CHECK(j["ranking"]["y1"][0]["parameter"] == "a");
    CHECK(j["ranking"]["y1"][1]["relative"].get<double>() == Approx(0.625));
    CHECK(j["ranking"]["y2"][0]["rms_scaled"].get<double>() == Approx(1.0));
    CHECK(j["threads"] == 2);
}

TEST_CASE("the sensitivity files are written into a new folder, or a clear error is thrown", "[sensitivity-report]") {
    const Example ex;
    const std::vector<OutputRanking> r = rank_parameters(ex.study);
    tvid::test::TempDir tmp;
    const auto dir = tmp.path() / "a" / "sensitivity";
    write_sensitivity_report(dir, ex.study, r, SensitivityRunInfo{});
    CHECK(tvid::test::read_text(dir / "sensitivity.csv") == sensitivity_csv(ex.study));
    CHECK(tvid::test::read_text(dir / "ranking.csv") == ranking_csv(r));
    CHECK(nlohmann::json::parse(tvid::test::read_text(dir / "sensitivity.json"))["experiment"] == "hand-made");

    const auto blocker = tmp.write("blocker", "a file, not a folder");
    try {
        write_sensitivity_report(blocker / "sensitivity", ex.study, r, SensitivityRunInfo{});
        FAIL("no error");
    } catch (const std::runtime_error& e) {
        CHECK(std::string(e.what()).find((blocker / "sensitivity").string()) != std::string::npos);
    }
}

}  // namespace TVID_UNITY_ID
