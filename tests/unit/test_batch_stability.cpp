// Unit tests of the batch's stability statistics: the median, the MAD, the robust
// z-score of Iglewicz & Hoaglin, mean/std/cv, the outlier jobs and the cross-cycle
// matrix's files, against values worked out by hand.

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "tvid/batch/batch_stability.hpp"
#include "tvid/batch/cross_matrix.hpp"
#include "tvid/batch/robust_statistics.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;
using Catch::Matchers::Contains;

namespace {
constexpr double kMissing = std::numeric_limits<double>::quiet_NaN();
}

TEST_CASE("median and MAD of odd, even and incomplete samples", "[batch-stability]") {
    CHECK(median({3, 1, 2}) == 2.0);
    CHECK(median({4, 1, 3, 2}) == 2.5);             // mean of the middle two
    CHECK(median({1, kMissing, 3}) == 2.0);          // a missing value is left out
    CHECK(std::isnan(median({})));
    // {4,1,3,2}: median 2.5, deviations {1.5,1.5,0.5,0.5} -> median 1.0
    CHECK(median_absolute_deviation({4, 1, 3, 2}) == 1.0);
    // {1,2,3,4,100}: median 3, deviations {2,1,0,1,97} -> sorted {0,1,1,2,97} -> 1
    CHECK(median_absolute_deviation({1, 2, 3, 4, 100}) == 1.0);
}

TEST_CASE("the robust z-score is 0.6745 (x - median) / MAD", "[batch-stability]") {
    const std::vector<double> z = robust_z_scores({1, 2, 3, 4, 100});
    REQUIRE(z.size() == 5);
    CHECK(z[0] == Approx(-2 * 0.6745));
    CHECK(z[2] == Approx(0.0));
    CHECK(z[3] == Approx(0.6745));
    CHECK(z[4] == Approx(97 * 0.6745));  // 65.43: the only |z| > 3.5
    // More than half the values equal: MAD = 0, no scale, nothing is judged.
    for (double v : robust_z_scores({5, 5, 5, 9})) CHECK(std::isnan(v));
    // A missing value has no score, the others keep theirs: {1,3,NaN,5} -> median 3, MAD 2.
    const std::vector<double> partial = robust_z_scores({1, 3, kMissing, 5});
    CHECK(partial[0] == Approx(-0.6745));
    CHECK(std::isnan(partial[2]));
}

TEST_CASE("stability: mean, sample standard deviation, coefficient of variation", "[batch-stability]") {
    // {2,4,4,4,5,5,7,9}: mean 5, Σ(x - 5)² = 32, s = √(32/7), median 4.5, MAD 0.5
    const Stability s = stability({2, 4, 4, 4, 5, 5, 7, 9});
    CHECK(s.count == 8);
    CHECK(s.mean == Approx(5.0));
    CHECK(s.std_dev == Approx(std::sqrt(32.0 / 7.0)));
    CHECK(s.cv == Approx(std::sqrt(32.0 / 7.0) / 5.0));
    CHECK(s.median == 4.5);
    CHECK(s.mad == 0.5);
    CHECK(s.min == 2.0);
    CHECK(s.max == 9.0);
    // A negative mean: the cv is relative to |mean|. {-1,-3}: s = √2, cv = √2/2
    CHECK(stability({-1, -3}).cv == Approx(std::sqrt(2.0) / 2.0));
    const Stability one = stability({7});
    CHECK(one.mean == 7.0);
    CHECK(std::isnan(one.std_dev));
    CHECK(std::isnan(one.cv));
}

TEST_CASE("outlier jobs: flagged per parameter over the ok rows, with the reason", "[batch-stability]") {
    const BatchColumns columns({"a", "b"}, {"y"});
    const std::vector<double> a{1, 1.1, 0.9, 1.0, 1.05, 5};
    const std::vector<double> b{2, 2, 2, 2, 2, 3};  // MAD 0: b judges no job
    std::vector<BatchRow> rows;
    for (std::size_t i = 0; i < a.size(); ++i) {
        BatchRow row = columns.row("job" + std::to_string(i + 1), kBatchOk, "");
        row[columns.index("a")] = batch_number(a[i]);
        row[columns.index("b")] = batch_number(b[i]);
        rows.push_back(row);
    }
    BatchRow failed = columns.row("job7", kBatchFailed, "start failed");
    failed[columns.index("a")] = "1000";  // not an estimate: left out
    rows.push_back(failed);

    const BatchStability s = batch_stability(columns, rows, {"kg m^2", "N m s/rad"}, nullptr);
    REQUIRE(s.parameters.size() == 2);
    CHECK(s.parameters[0].unit == "kg m^2");
    CHECK(s.parameters[0].stats.count == 6);
    CHECK(s.parameters[0].stats.mean == Approx(10.05 / 6));
    // a: median (1 + 1.05)/2 = 1.025, deviations {.025,.075,.125,.025,.025,3.975} -> MAD 0.05
    CHECK(s.parameters[0].stats.median == Approx(1.025));
    CHECK(s.parameters[0].stats.mad == Approx(0.05));
    REQUIRE(s.outliers.size() == 1);
    CHECK(s.outliers[0].id == "job6");
    CHECK(s.outliers[0].subject == "a");
    CHECK(s.outliers[0].z == Approx(0.6745 * 3.975 / 0.05));  // 53.6
    CHECK_THAT(s.outliers[0].reason, Contains("a = 5 kg m^2") && Contains("robust z +53.62") &&
                                         Contains("median 1.025 kg m^2"));
    const std::string csv = parameter_stability_csv(s);
    CHECK_THAT(csv, Contains("parameter,unit,count,mean,std,cv,median,mad,min,max,outliers\n"));
    CHECK_THAT(csv, Contains(",job6\n"));
    const nlohmann::json j = parameter_stability_json(s);
    CHECK(j["b"]["mad"].get<double>() == 0.0);
    CHECK(j["a"]["cv"].get<double>() == Approx(s.parameters[0].stats.std_dev / (10.05 / 6)));
    CHECK(outliers_json(s)[0]["robust_z"].get<double>() == Approx(53.62275));
}

TEST_CASE("cross matrix: mean cross fit leaves out the diagonal, files name each cell", "[batch-stability]") {
    CrossMatrix m;
    m.jobs = {"cycle-2", "cycle-3", "cycle-4"};
    m.outputs = {"omega"};
    const double fits[3][3] = {{99, 90, 80}, {70, 98, 60}, {95, 85, 97}};
    m.cells.assign(3, std::vector<CrossCell>(3));
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) m.cells[i][j] = CrossCell{{fits[i][j]}, {0.5 * (i + 1) + 0.25 * j}, true, ""};
    m.cells[1][2] = CrossCell{{kMissing}, {kMissing}, false, "estimation window cycle 4: diverged"};
    const std::vector<double> mean = mean_cross_fit(m);
    CHECK(mean[0] == Approx(85.0));  // (90 + 80) / 2
    CHECK(mean[1] == Approx(70.0));  // the failed cell is left out
    CHECK(mean[2] == Approx(90.0));  // (95 + 85) / 2

    const std::string wide = cross_matrix_csv(m);
    CHECK_THAT(wide, Contains("fitted,fit_cycle-2,rmse_cycle-2,fit_cycle-3,rmse_cycle-3,fit_cycle-4,rmse_cycle-4\n"));
    CHECK_THAT(wide, Contains("\ncycle-3,70,1,98,1.25,,\n"));
    const std::string longform = cross_matrix_long_csv(m);
    CHECK_THAT(longform, Contains("cycle-3,cycle-4,omega,,,failed,estimation window cycle 4: diverged\n"));

    const nlohmann::json j = cross_matrix_json(m);
    CHECK(j["diagonal_mean_fit_percent"].get<double>() == Approx(98.0));
    CHECK(j["off_diagonal_mean_fit_percent"].get<double>() == Approx((90 + 80 + 70 + 95 + 85) / 5.0));
    CHECK(j["off_diagonal_min_fit_percent"].get<double>() == 70.0);
    CHECK(j["off_diagonal_median_fit_percent"].get<double>() == 85.0);  // {70,80,85,90,95}
    CHECK(j["off_diagonal_min_cell"] == "cycle-3 on cycle-2");
    CHECK(j["failed_cells"] == 1);

    // Several outputs: a fit and an RMSE column per output.
    m.outputs = {"omega", "torque"};
    for (auto& row : m.cells)
        for (auto& c : row) {
            c.fit_percent.push_back(50);
            c.rmse.push_back(1);
        }
    CHECK_THAT(cross_matrix_csv(m), Contains("fitted,fit_cycle-2_omega,rmse_cycle-2_omega,fit_cycle-2_torque,"));
}

TEST_CASE("outlier jobs: fewer than five jobs with a value judge no job", "[batch-stability]") {
    // {1, 1.001, 2, 1.0005}: median 1.00075, deviations {.00075,.00025,.99925,.00025} ->
    // MAD 0.0005, so 2 would score 0.6745 * 0.99925 / 0.0005 = 1348; but four jobs are too few.
    const BatchColumns columns({"a"}, {"y"});
    std::vector<BatchRow> rows;
    for (double v : {1.0, 1.001, 2.0, 1.0005}) {
        BatchRow row = columns.row("job" + std::to_string(rows.size() + 1), kBatchOk, "");
        row[columns.index("a")] = batch_number(v);
        rows.push_back(row);
    }
    CHECK(std::abs(robust_z_scores({1.0, 1.001, 2.0, 1.0005})[2]) > 1000);
    CHECK(batch_stability(columns, rows, {""}, nullptr).outliers.empty());
    BatchRow fifth = columns.row("job5", kBatchOk, "");
    fifth[columns.index("a")] = "1.0002";
    rows.push_back(fifth);
    const BatchStability five = batch_stability(columns, rows, {""}, nullptr);
    REQUIRE(five.outliers.size() == 1);
    CHECK(five.outliers[0].id == "job3");
}

}  // namespace TVID_UNITY_ID
